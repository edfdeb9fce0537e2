"""Direct solve of synchronous (or h-times synchronous) critical speeds.

A critical speed is a spin speed Omega at which a mode's damped natural frequency equals the
excitation: omega_d(Omega) = h Omega. A coarse Campbell scan (MAC-tracked modes) brackets each
crossing; the crossing is then solved by Brent's method on g(Omega) = omega_d(Omega) - h Omega,
where omega_d(Omega) is the mode at Omega with the largest MAC to the bracket's mode shape. The
root is found to a relative tolerance of 1e-12 in Omega (no interpolation between speeds), so a
backward critical needs a handful of eigen-solves instead of a fine Campbell diagram.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq

from rotaflex.rotor.fe.modal import CampbellData, campbell, mac, modal
from rotaflex.rotor.fe.model import Rotor


def critical_speeds(
    rotor: Rotor,
    scan,
    n_modes: int = 6,
    harmonics=(1,),
    xtol: float = 1e-12,
    data: CampbellData | None = None,
    progress=None,
) -> list[dict]:
    """Critical speeds [rad/s] within the scan speeds ``scan`` [rad/s] (increasing), solved directly.

    Parameters
    ----------
    scan : array (s,) [rad/s]
        Speeds of the bracketing Campbell scan (a crossing between two of them is found; a
        mode crossing h Omega twice between neighbours is missed, so keep the scan moderate).
    data : CampbellData, optional
        The Campbell result at ``scan`` if already computed (with the same n_modes, harmonics).
    progress : callable ``progress(done, total)``, optional
        Called with the crossings solved so far (each a root search of ~10-20 eigenproblems).

    Returns
    -------
    list of dict
        ``mode`` (tracked index), ``harmonic``, ``speed`` [rad/s], ``frequency`` (h Omega) [rad/s],
        ``whirl`` (forward/backward/mixed at the root), ``log_dec`` at the root, ``evaluations``.
    """
    scan = np.asarray(scan, float)
    c = campbell(rotor, scan, n_modes, harmonics) if data is None else data
    wd = c.modes.wd
    n_cand = min(n_modes + 6, rotor.n_dof)
    out = []

    def crossings(h, k):  # speed steps where mode k's damped frequency crosses h Omega
        d = wd[:, k] - h * scan
        return np.flatnonzero(np.sign(d[:-1]) * np.sign(d[1:]) < 0)

    total = sum(crossings(h, k).size for h in harmonics for k in range(n_modes))
    for h in harmonics:
        for k in range(n_modes):
            d = wd[:, k] - h * scan
            for s in crossings(h, k):
                ref = c.modes.shape[s, k]
                count = [0]

                def g(w, ref=ref, count=count, h=h):
                    count[0] += 1
                    m = modal(rotor, w, n_cand)
                    j = int(np.argmax(mac(ref[None], m.shape[0])[0]))
                    return m.wd[0, j] - h * w

                try:
                    root = brentq(g, scan[s], scan[s + 1], xtol=xtol * scan[s + 1], rtol=4 * np.finfo(float).eps)
                    how = "direct"
                except ValueError:  # the MAC-matched mode has no sign change (a near-degenerate pair): interpolate
                    root = scan[s] + d[s] / (d[s] - d[s + 1]) * (scan[s + 1] - scan[s])
                    how = "interpolated"
                m = modal(rotor, root, n_cand)
                j = int(np.argmax(mac(ref[None], m.shape[0])[0]))
                out.append(
                    {
                        "mode": k,
                        "harmonic": float(h),
                        "speed": float(root),
                        "frequency": float(h * root),
                        "whirl": str(m.whirl[0, j]),
                        "log_dec": float(m.log_dec[0, j]),
                        "evaluations": count[0],
                        "solve": how,
                    }
                )
                if progress is not None:
                    progress(len(out), total)
    out.sort(key=lambda x: x["speed"])
    return out
