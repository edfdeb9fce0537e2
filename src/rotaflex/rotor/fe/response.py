"""Steady unbalance response, Bode data, orbits, API 684-style amplification factor and margin.

An unbalance ``u = m_u e`` [kg m] at angle ``phi`` on a rotor spinning at Omega exerts
f_x = u Omega^2 cos(Omega t + phi), f_y = u Omega^2 sin(Omega t + phi), i.e. the complex
amplitudes F_x = u Omega^2 e^{i phi}, F_y = -i F_x. The response q = Re(Q e^{i Omega t}) solves

    [K(Omega) - Omega^2 M + i Omega (C(Omega) + Omega G)] Q = F

for all speeds at once (one batched LAPACK solve). Amplitude |Q_x| and phase arg(Q_x) are
reported (x(t) = |Q_x| cos(Omega t + phase), so a lag is a negative phase).

Definitions used (API 684 style): on the amplitude-vs-speed curve at a probe, each peak at
N_c has half-power speeds N_1 < N_c < N_2 where the amplitude is peak / sqrt(2); the
amplification factor is AF = N_c / (N_2 - N_1) and the separation margin from the operating
speed N_op is SM = ``|N_op - N_c| / N_op * 100`` %.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from rotaflex.core.errors import InputError
from rotaflex.rotor.fe.model import NDOF_NODE, Rotor


@dataclass(frozen=True)
class UnbalanceData:
    """Complex response amplitudes at every DOF and speed.

    Attributes
    ----------
    speed : ndarray (s,)  [rad/s]
    Q : ndarray (s, n_dof) complex  [m, rad]
    """

    speed: np.ndarray
    Q: np.ndarray

    def at(self, node: int) -> tuple[np.ndarray, np.ndarray]:
        """Complex x and y amplitudes at ``node`` [m], shape (s,) each."""
        return self.Q[:, NDOF_NODE * node], self.Q[:, NDOF_NODE * node + 1]

    def major_axis(self, node: int) -> np.ndarray:
        """Semi-major axis of the elliptical orbit at ``node`` [m]."""
        X, Y = self.at(node)
        return 0.5 * (np.abs(X + 1j * Y) + np.abs(X - 1j * Y))

    def minor_axis(self, node: int) -> np.ndarray:
        X, Y = self.at(node)
        return 0.5 * np.abs(np.abs(X + 1j * Y) - np.abs(X - 1j * Y))

    def orbit(self, node: int, speed_index: int, n: int = 181) -> tuple[np.ndarray, np.ndarray]:
        """Orbit x(t), y(t) [m] over one revolution at ``speed[speed_index]``."""
        X, Y = self.at(node)
        th = np.linspace(0, 2 * np.pi, n)
        e = np.exp(1j * th)
        return (X[speed_index] * e).real, (Y[speed_index] * e).real


def unbalance_response(
    rotor: Rotor, speeds, unbalance, progress: Callable[[float, float], None] | None = None
) -> UnbalanceData:
    """Steady response to unbalances at spin ``speeds`` [rad/s].

    Parameters
    ----------
    unbalance : sequence of (node, magnitude [kg m], phase [rad])
    progress : callable ``progress(done, total)``, optional
        Called with the speeds solved; the speeds are then solved in 10 chunks (each speed's
        solve is the same LAPACK call as without it).

    Examples
    --------
    >>> from rotaflex.rotor.fe.model import Rotor, Shaft, Bearing
    >>> r = Rotor(shaft=(Shaft(outer_diameter=0.05, length=1.0, elements=4),),
    ...           bearing=(Bearing(node=0, kxx=1e7, kyy=1e7), Bearing(node=4, kxx=1e7, kyy=1e7)))
    >>> unbalance_response(r, [100.0, 200.0], [(2, 1e-4, 0.0)]).Q.shape
    (2, 20)
    """
    speeds = np.atleast_1d(np.asarray(speeds, float))
    n = rotor.n_dof
    F = np.zeros((speeds.size, n), complex)
    for node, u, phase in unbalance:
        if not 0 <= node < rotor.n_nodes:
            raise InputError("unbalance.mass.node", node, f"an existing node 0..{rotor.n_nodes - 1}")
        F[:, NDOF_NODE * node : NDOF_NODE * node + 2] += unbalance_force(speeds, u, phase)

    def pencil(sp):
        M, K, C = rotor.MKC(sp)
        return M, C + sp[:, None, None] * rotor.G[None], K

    return UnbalanceData(speeds, harmonic_solve(pencil, speeds, F, progress=progress))


def unbalance_force(spin: np.ndarray, magnitude: float, phase: float) -> np.ndarray:
    """Complex amplitudes (F_x, F_y) [N], shape (s, 2), of an unbalance ``magnitude`` [kg m] at
    angle ``phase`` [rad] on a rotor turning at the signed ``spin`` [rad/s] (s,), relative to
    ``e^{i spin t}``: ``F_x = u spin^2 e^{i phase}``, ``F_y = -i F_x`` (for either sense of
    rotation: the mass is at angle ``spin t + phase``)."""
    fx = magnitude * spin**2 * np.exp(1j * phase)
    return np.stack([fx, -1j * fx], -1)


def dynamic_stiffness(M: np.ndarray, D: np.ndarray, K: np.ndarray, w: np.ndarray) -> np.ndarray:
    """``K - w^2 M + i w D`` (f, n, n) at each excitation frequency ``w`` (f,) [rad/s].

    The one dynamic stiffness of the harmonic solves: :func:`harmonic_solve` (matrices that
    change with the speed, ``(f, n, n)``) and :func:`rotaflex.rotor.fe.frf.dynamic_solve` (one
    set of matrices ``(n, n)`` at many frequencies) both solve it.
    """
    w = np.asarray(w, float)[:, None, None]
    return K - w**2 * M + 1j * w * D


def harmonic_solve(
    pencil: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray]],
    speeds: np.ndarray,
    F: np.ndarray,
    frequency: np.ndarray | None = None,
    progress: Callable[[float, float], None] | None = None,
) -> np.ndarray:
    """Steady harmonic response ``Q`` of ``M q'' + D q' + K q = Re(F e^{i w t})`` at each speed.

    Solves ``[K - w^2 M + i w D] Q = F`` with ``(M, D, K) = pencil(speeds[idx])``; for a rotor
    ``D = C(Omega) + Omega G`` and ``w = Omega`` give the unbalance equation of this module,
    for a machine :mod:`rotaflex.system.unbalance` passes its assembled matrices.

    Parameters
    ----------
    pencil : callable
        ``pencil(speeds)`` with speeds (k,) [rad/s] -> (M, D, K), each (k, n, n) or (n, n)
        [kg, N s/m, N/m] (D includes the gyroscopic term at those speeds).
    speeds : ndarray (s,) [rad/s]
    F : ndarray (s, n) complex [N]
    frequency : ndarray (s,), optional
        Excitation frequency w [rad/s] at each speed (signed; default: ``speeds``).
    progress : callable ``progress(done, total)``, optional
        Called with the speeds solved; the speeds are then solved in 10 chunks (each speed's
        solve is the same LAPACK call as without it).

    Returns
    -------
    ndarray (s, n) complex [m, rad]
    """
    w_all = speeds if frequency is None else np.asarray(frequency, float)
    Q = np.empty_like(F)
    chunks = [np.arange(speeds.size)] if progress is None else np.array_split(np.arange(speeds.size), 10)
    for idx in (c for c in chunks if c.size):
        M, D, K = pencil(speeds[idx])
        Q[idx] = np.linalg.solve(dynamic_stiffness(M, D, K, w_all[idx]), F[idx, :, None])[..., 0]
        if progress is not None:
            progress(idx[-1] + 1, speeds.size)
    return Q


def peaks(
    speed: np.ndarray, amplitude: np.ndarray, operating_speed: float | None = None, range_end: bool = False
) -> list[dict]:
    """Resonance peaks of an amplitude curve with their half-power AF and separation margin.

    Parameters
    ----------
    speed : ndarray (s,) [rad/s], increasing
    amplitude : ndarray (s,) [m]
    operating_speed : float, optional [rad/s]
    range_end : bool
        Also return the maxima that cannot be rated from the curve alone, with ``kind``
        saying which: ``"half-power band beyond the range"`` (a local maximum whose amplitude
        does not fall to 1/sqrt(2) of it before an end of the range; ``af`` nan and the side
        not reached nan) and ``"rising at the range end"`` (the curve still rises at the
        last speed: ``speed`` and ``amplitude`` are the last sample's). A rated peak has
        ``kind = "resonance"``. Without it (default) only rated peaks are returned.

    Returns
    -------
    list of dict
        ``speed`` (N_c, refined by a parabola through the three highest samples), ``amplitude``,
        ``n1``, ``n2`` (half-power speeds, nan if outside the range), ``af`` (N_c / (N_2 - N_1)),
        ``sm_percent`` (``|N_op - N_c| / N_op * 100``, nan without an operating speed),
        ``sm_required_percent`` (:func:`api684_required_margin`, nan without an operating speed)
        and ``sm_ok`` (1.0 if the margin meets the requirement, 0.0 if not, nan without one).
    """
    a = np.asarray(amplitude, float)
    out = []
    idx = np.flatnonzero((a[1:-1] > a[:-2]) & (a[1:-1] >= a[2:])) + 1
    for i in idx:
        y0, y1, y2 = a[i - 1], a[i], a[i + 1]
        den = y0 - 2 * y1 + y2
        t = 0.5 * (y0 - y2) / den if den != 0 else 0.0
        nc = speed[i] + t * (speed[i + 1] - speed[i - 1]) / 2
        peak = y1 - 0.25 * (y0 - y2) * t
        half = peak / np.sqrt(2)
        left = np.flatnonzero(a[:i] < half)
        right = np.flatnonzero(a[i:] < half)
        n1 = n2 = np.nan
        if left.size:
            j = left[-1]
            n1 = speed[j] + (half - a[j]) / (a[j + 1] - a[j]) * (speed[j + 1] - speed[j])
        if right.size:
            j = i + right[0]
            n2 = speed[j - 1] + (a[j - 1] - half) / (a[j - 1] - a[j]) * (speed[j] - speed[j - 1])
        if np.isnan(n1) or np.isnan(n2):
            if range_end:  # a maximum the user sees: reported, with the band that is not resolved
                out.append(_unrated(nc, peak, n1, n2, "half-power band beyond the range"))
            continue
        sm = abs(operating_speed - nc) / operating_speed * 100 if operating_speed else np.nan
        af = nc / (n2 - n1)
        req = api684_required_margin(af, nc < operating_speed) if operating_speed else np.nan
        ok = float(sm >= req) if operating_speed else np.nan
        out.append(
            {
                "speed": float(nc),
                "amplitude": float(peak),
                "n1": float(n1),
                "n2": float(n2),
                "af": float(af),
                "sm_percent": float(sm),
                "sm_required_percent": float(req),
                "sm_ok": ok,
                "kind": "resonance",
            }
        )
    if range_end and a.size > 1 and a[-1] > a[-2]:
        left = np.flatnonzero(a < a[-1] / np.sqrt(2))
        n1 = np.nan
        if left.size:
            j = left[-1]
            n1 = speed[j] + (a[-1] / np.sqrt(2) - a[j]) / (a[j + 1] - a[j]) * (speed[j + 1] - speed[j])
        out.append(_unrated(float(speed[-1]), float(a[-1]), n1, np.nan, "rising at the range end"))
    return out


def _unrated(nc: float, amplitude: float, n1: float, n2: float, kind: str) -> dict:
    """A maximum whose half-power band (hence AF) the speed range does not resolve."""
    nan = float("nan")
    return {
        "speed": float(nc),
        "amplitude": float(amplitude),
        "n1": float(n1),
        "n2": float(n2),
        "af": nan,
        "sm_percent": nan,
        "sm_required_percent": nan,
        "sm_ok": nan,
        "kind": kind,
    }


def api684_required_margin(af: float, below: bool) -> float:
    """Separation margin [%] required of a critical speed with amplification factor ``af``.

    The API 684 / API 617 rule: a critical with AF < 2.5 needs no margin (0 %); otherwise a
    critical below the operating speed needs min(16, 17 (1 - 1/(AF - 1.5))) % and one above it
    min(26, 10 + 17 (1 - 1/(AF - 1.5))) %.

    Examples
    --------
    >>> round(api684_required_margin(5.5, below=True), 4)
    12.75
    """
    if af < 2.5:
        return 0.0
    base = 17.0 * (1.0 - 1.0 / (af - 1.5))
    return min(16.0, base) if below else min(26.0, 10.0 + base)
