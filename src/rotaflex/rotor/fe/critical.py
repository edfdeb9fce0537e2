"""Direct solve of synchronous (or h-times synchronous) critical speeds.

A critical speed is a spin speed Omega at which a mode's damped natural frequency equals the
excitation: omega_d(Omega) = h Omega. A coarse Campbell scan (MAC-tracked modes) brackets each
crossing; the crossing is then solved by Brent's method on g(Omega) = omega_d(Omega) - h Omega,
where omega_d(Omega) is the mode at Omega with the largest MAC to the bracket's mode shape. The
root is found to a relative tolerance of 1e-12 in Omega (no interpolation between speeds), so a
backward critical needs a handful of eigen-solves instead of a fine Campbell diagram.
"""

from __future__ import annotations

import math

import numpy as np

from rotaflex.rotor.fe.modal import CampbellData, campbell, critical_whirl, line_crossings, mac, modal
from rotaflex.rotor.fe.model import Rotor


def brent_root(f, a: float, b: float, xtol: float, rtol: float, maxiter: int = 100) -> float:
    """A root of ``f`` between ``a`` and ``b`` (``f(a)``, ``f(b)`` of opposite signs) by Brent's method.

    Brent (1973), *Algorithms for Minimization without Derivatives*, ch. 4: the bracket
    [x, c] always holds a sign change, x being the end with the smaller |f|; each step is a
    secant or inverse quadratic interpolation step when it falls well inside the bracket and
    shrinks fast enough, a bisection otherwise, and never shorter than the tolerance
    ``(xtol + rtol |x|) / 2``, reached when half the bracket is below it. The steps and their
    floating-point operations are those of SciPy's ``brentq`` (its C implementation), so the
    root is the same to the bit (tested) without importing ``scipy.optimize`` (~0.17 s).

    Raises
    ------
    ValueError
        If ``f(a)`` and ``f(b)`` have the same sign or ``f`` returns NaN (as ``brentq``).
    RuntimeError
        If the tolerance is not reached in ``maxiter`` steps (as ``brentq``).
    """

    def value(x):
        fx = f(x)
        if math.isnan(fx):
            raise ValueError(f"the function is NaN at {x!r}")
        return fx

    x_old, f_old = a, value(a)  # the previous iterate
    x, fx = b, value(b)  # the current one
    if f_old == 0:
        return a
    if fx == 0:
        return b
    if math.copysign(1.0, f_old) == math.copysign(1.0, fx):
        raise ValueError("f(a) and f(b) must have different signs")
    c = fc = 0.0  # the other end of the bracket
    step = step_old = 0.0
    for _ in range(maxiter):
        if f_old != 0 and fx != 0 and math.copysign(1.0, f_old) != math.copysign(1.0, fx):
            c, fc = x_old, f_old  # the sign change is now between x_old and x
            step = step_old = x - x_old
        if abs(fc) < abs(fx):  # the better end becomes x
            x_old, x, c = x, c, x
            f_old, fx, fc = fx, fc, fx
        tol = (xtol + rtol * abs(x)) / 2
        half = (c - x) / 2
        if fx == 0 or abs(half) < tol:
            return x
        if abs(step_old) > tol and abs(fx) < abs(f_old):
            if x_old == c:  # two points: secant
                trial = -fx * (x - x_old) / (fx - f_old)
            else:  # three points: inverse quadratic interpolation
                s_old = (f_old - fx) / (x_old - x)
                s_c = (fc - fx) / (c - x)
                trial = -fx * (fc * s_c - f_old * s_old) / (s_c * s_old * (fc - f_old))
            if 2 * abs(trial) < min(abs(step_old), 3 * abs(half) - tol):
                step_old, step = step, trial
            else:
                step = step_old = half
        else:
            step = step_old = half
        x_old, f_old = x, fx
        x += step if abs(step) > tol else (tol if half > 0 else -tol)
        fx = value(x)
    raise RuntimeError(f"no convergence to {xtol:g} + {rtol:g} |x| in {maxiter} steps")


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
        ``whirl`` at the root by the rule of the Campbell diagram
        (:func:`~rotaflex.rotor.fe.modal.critical_whirl`: forward or backward; planar counts as
        forward), ``shape_whirl`` (forward/backward/mixed by the nodes' orbits), ``forward_fraction``,
        ``log_dec`` at the root, ``evaluations``.
    """
    scan = np.asarray(scan, float)
    c = campbell(rotor, scan, n_modes, harmonics) if data is None else data
    wd = c.modes.wd
    n_cand = min(n_modes + 6, rotor.n_dof)
    out = []

    # the Campbell diagram's crossings (every track, also those of modes oscillating from inside
    # the scan) bracket the roots; each is also the interpolated fallback
    brackets = {h: line_crossings(scan, wd, h) for h in harmonics}
    total = sum(len(b) for b in brackets.values())
    for h in harmonics:
        for k, s, _, interpolated in brackets[h]:
            ref = c.modes.shape[s, k]
            count = [0]

            def g(w, ref=ref, count=count, h=h):
                count[0] += 1
                m = modal(rotor, w, n_cand)
                j = int(np.argmax(mac(ref[None], m.shape[0])[0]))
                return m.wd[0, j] - h * w

            try:
                root = brent_root(g, scan[s], scan[s + 1], xtol=xtol * scan[s + 1], rtol=4 * np.finfo(float).eps)
                how = "direct"
            except ValueError:  # the MAC-matched mode has no sign change (a near-degenerate pair): interpolate
                root = interpolated
                how = "interpolated"
            m = modal(rotor, root, n_cand)
            j = int(np.argmax(mac(ref[None], m.shape[0])[0]))
            out.append(
                {
                    "mode": k,
                    "harmonic": float(h),
                    "speed": float(root),
                    "frequency": float(h * root),
                    "whirl": critical_whirl(float(m.forward_fraction[0, j])),
                    "shape_whirl": str(m.whirl[0, j]),
                    "forward_fraction": float(m.forward_fraction[0, j]),
                    "log_dec": float(m.log_dec[0, j]),
                    "evaluations": count[0],
                    "solve": how,
                }
            )
            if progress is not None:
                progress(len(out), total)
    out.sort(key=lambda x: x["speed"])
    return out
