"""Eigen-analyses: modes at a speed, Campbell diagram with MAC tracking (the UCS map: :mod:`.ucs`).

Equation of motion (SI, node DOFs [x, y, theta_x, theta_y]):

    M q'' + (C(Omega) + Omega G) q' + K(Omega) q = f

solved as the first-order eigenproblem of A = [[0, I], [-M^-1 K, -M^-1 (C + Omega G)]].
A mode with eigenvalue lambda = sigma + i omega_d (omega_d > 0) has natural frequency
omega_n = |lambda|, damping ratio zeta = -sigma / |lambda| and logarithmic decrement
delta = -2 pi sigma / omega_d (negative: unstable). Its whirl sense comes from its orbit:
each node's x + i y = 1/2 [(X + iY) e^{i omega t} + conj(X - iY) e^{-i omega t}] (times the
decay), so the forward (with the spin, +z) radius is |X + iY|/2 and the backward one |X - iY|/2;
the mode is forward when every node that moves (orbit radius >= 1 % of the largest) whirls
forward (|X + iY| > |X - iY|), backward when every such node whirls backward, and mixed when
both senses occur; a mode whose orbits are all straight lines (planar) is called by the sum
rule sum |X + iY|^2 >= sum |X - iY|^2.

Stability: a mode is unstable when its damping ratio is below -STABILITY_TOL (Re(lambda) >
1e-8 |lambda|, a log decrement below about -6.3e-8): round-off leaves the eigenvalues of an
undamped rotor with real parts of order 1e-12 |lambda| of either sign, which are not instability.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla

from rotaflex.core.errors import ConvergenceError, InputError
from rotaflex.core.units import rad_s_to_rpm
from rotaflex.rotor.fe.model import NDOF_NODE, Rotor

#: a mode is unstable when its damping ratio is below -STABILITY_TOL (relative to |lambda|)
STABILITY_TOL = 1e-8
#: nodes whose orbit radius is below this fraction of the largest do not vote on the whirl sense
WHIRL_NODE_FRACTION = 0.01
#: an orbit with | |X + iY| - |X - iY| | below this fraction of their sum is a straight line
WHIRL_LINE_FRACTION = 1e-3
#: a tracked mode's best MAC must beat its second best by more than this for the row-wise best
#: to be taken as the tracking assignment without solving the assignment problem
ASSIGN_MARGIN = 1e-9


class EigenvalueView:
    """Frequencies and damping of an ``eigenvalue`` array (complex [1/s], any shape) of
    eigenvalues with omega_d > 0; the modes of a rotor and of a gearbox share them."""

    eigenvalue: np.ndarray

    @property
    def wd(self) -> np.ndarray:
        """Damped natural frequency [rad/s]."""
        return self.eigenvalue.imag

    @property
    def wn(self) -> np.ndarray:
        """Undamped natural frequency |lambda| [rad/s]."""
        return np.abs(self.eigenvalue)

    @property
    def damping_ratio(self) -> np.ndarray:
        return -self.eigenvalue.real / np.abs(self.eigenvalue)

    @property
    def log_dec(self) -> np.ndarray:
        """Logarithmic decrement -2 pi sigma / omega_d [-]."""
        return -2 * np.pi * self.eigenvalue.real / self.eigenvalue.imag


@dataclass(frozen=True)
class Modes(EigenvalueView):
    """Modes at one or more speeds (leading dimension: speed).

    Attributes
    ----------
    speed : ndarray (s,)  [rad/s]
    eigenvalue : ndarray (s, m) complex  [1/s]
    shape : ndarray (s, m, n_dof) complex; displacement part, largest translation = 1
    """

    speed: np.ndarray
    eigenvalue: np.ndarray
    shape: np.ndarray
    n_rotor: int | None = None  #: DOFs of the shaft's nodes in ``shape`` (pedestal DOFs follow); None: all

    @property
    def _rotor_shape(self) -> np.ndarray:
        return self.shape if self.n_rotor is None else self.shape[..., : self.n_rotor]

    @property
    def forward_fraction(self) -> np.ndarray:
        """sum |X + iY|^2 / (sum |X + iY|^2 + sum |X - iY|^2) over the shaft's nodes: 1 forward, 0 backward."""
        X, Y = self._rotor_shape[..., 0::NDOF_NODE], self._rotor_shape[..., 1::NDOF_NODE]
        f = np.sum(np.abs(X + 1j * Y) ** 2, -1)
        b = np.sum(np.abs(X - 1j * Y) ** 2, -1)
        with np.errstate(invalid="ignore"):  # NaN where a track has no mode (before it starts)
            return f / (f + b)

    @property
    def whirl(self) -> np.ndarray:
        """``"forward"``, ``"backward"`` or ``"mixed"`` per mode, from the nodes' orbit senses."""
        X, Y = self._rotor_shape[..., 0::NDOF_NODE], self._rotor_shape[..., 1::NDOF_NODE]
        rf, rb = np.abs(X + 1j * Y), np.abs(X - 1j * Y)
        size = rf + rb
        moving = size >= WHIRL_NODE_FRACTION * np.max(size, -1, keepdims=True)
        clear = np.abs(rf - rb) > WHIRL_LINE_FRACTION * size
        fw = np.any(moving & clear & (rf > rb), -1)
        bw = np.any(moving & clear & (rf < rb), -1)
        by_sum = np.where(self.forward_fraction >= 0.5, "forward", "backward")
        return np.where(fw & bw, "mixed", np.where(fw, "forward", np.where(bw, "backward", by_sum)))

    @property
    def unstable(self) -> np.ndarray:
        """True where the damping ratio is below -:data:`STABILITY_TOL`."""
        return self.damping_ratio < -STABILITY_TOL


def state_matrix(MinvK: np.ndarray, MinvD: np.ndarray) -> np.ndarray:
    """First-order state matrices ``A = [[0, I], [-M^-1 K, -M^-1 D]]`` from ``M^-1 K`` and
    ``M^-1 D`` (..., n, n) [1/s^2, 1/s]: the one layout of every modal analysis (FE rotor, full
    and reduced; machine's ``rotaflex.system.modal._solve``). Each caller forms the two
    products its own way (one inverse of a speed-independent M for the rotor's stack of speeds,
    ``scipy.linalg.solve`` for the machine), so their eigenvalues are those they always were."""
    n = MinvK.shape[-1]
    A = np.zeros((*MinvK.shape[:-2], 2 * n, 2 * n))
    A[..., :n, n:] = np.eye(n)
    A[..., n:, :n] = -MinvK
    A[..., n:, n:] = -MinvD
    return A


def _state_matrices(rotor: Rotor, speeds: np.ndarray, whirl: np.ndarray | None = None) -> np.ndarray:
    M, K, C = rotor.MKC(speeds, whirl)
    Minv = _minv(M)
    return state_matrix(Minv @ K, Minv @ (C + speeds[:, None, None] * rotor.G[None]))


def _minv(M: np.ndarray) -> np.ndarray:
    """Inverse of the mass matrices (n_speed, n_dof, n_dof): one inverse when they are all equal
    (no speed-dependent added mass), as before elements had mass."""
    try:
        if np.array_equal(M, np.broadcast_to(M[0], M.shape)):
            return sla.inv(M[0])[None]
        return np.linalg.inv(M)
    except np.linalg.LinAlgError:
        raise InputError("disk", "<rotary inertia>", "a non-singular mass matrix (every node needs inertia)") from None


def batched_eig(
    A: np.ndarray, workers: int | None = None, progress: Callable[[float, float], None] | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """``np.linalg.eig`` of a stack (s, m, m), the stack split over threads.

    LAPACK's dgeev is ~98 % of a Campbell diagram's time and runs one matrix per call on one
    core; numpy releases the GIL around it, so chunks of the stack run in parallel. Each matrix
    still goes through the same dgeev call (BLAS pinned to one thread meanwhile), so the result is bitwise that of one
    ``np.linalg.eig(A)`` (tested). ``workers``: threads (default: the usable CPUs, at most 8).
    ``progress(done, total)``: called with the matrices done after each chunk; with it the stack
    is cut into at least 10 chunks (whole 10 % steps of progress; the same dgeev per matrix).
    """
    import os
    from concurrent.futures import ThreadPoolExecutor

    cpus = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    workers = min(cpus, 8) if workers is None else workers
    s = A.shape[0]
    if progress is None and (workers <= 1 or s < 2 * workers):
        return np.linalg.eig(A)
    chunks = np.array_split(np.arange(s), max(workers, 10) if progress is not None else workers)
    chunks = [c for c in chunks if c.size]
    parts, done = [], 0
    if workers <= 1 or s < 2 * workers:
        for idx in chunks:
            parts.append(np.linalg.eig(A[idx]))
            done += idx.size
            progress(done, s)
    else:
        from threadpoolctl import threadpool_limits

        with threadpool_limits(limits=1), ThreadPoolExecutor(workers) as pool:  # no BLAS threads on top
            for idx, part in zip(chunks, pool.map(lambda idx: np.linalg.eig(A[idx]), chunks), strict=True):
                parts.append(part)
                done += idx.size
                if progress is not None:
                    progress(done, s)
    return np.concatenate([p[0] for p in parts]), np.concatenate([p[1] for p in parts])


#: an eigenvalue is oscillatory when omega_d > OSCILLATORY_TOL (max |lambda| + 1 [1/s]): beyond
#: the round-off of the largest eigenvalue (the machine's modes use 1e-7, :mod:`rotaflex.system.modal`)
OSCILLATORY_TOL = 1e-9


def _oscillatory(lam: np.ndarray, tol: float = OSCILLATORY_TOL) -> np.ndarray:
    """True for the eigenvalues with omega_d > 0 (beyond round-off of the largest |lambda|)."""
    return lam.imag > tol * (np.max(np.abs(lam), axis=-1, keepdims=True) + 1.0)


def oscillatory_pairs(
    lam: np.ndarray, vec: np.ndarray, n: int, n_keep: int, tol: float = OSCILLATORY_TOL
) -> tuple[np.ndarray, np.ndarray]:
    """The ``n_keep`` lowest oscillatory eigenpairs of a first-order eigenproblem of one speed
    (eigenvalues ``lam`` (2n,), right vectors ``vec`` (2n, 2n)), sorted by damped frequency:
    eigenvalues (m,) [1/s] and the displacement parts (m, n) of the vectors, unnormalised.
    The one selection of the FE rotor's and the machine's modes (each normalises its own way)."""
    keep = np.flatnonzero(_oscillatory(lam, tol))
    keep = keep[np.argsort(lam.imag[keep], kind="stable")][:n_keep]
    return lam[keep], vec[:n, keep].T


def _select(
    lam: np.ndarray, vec: np.ndarray, n: int, n_keep: int, n_rotor: int | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Oscillatory eigenpairs (omega_d > 0) sorted by omega_d; displacement part normalised by
    its largest translation of a shaft node (the first ``n_rotor`` DOFs)."""
    lam, v = oscillatory_pairs(lam, vec, n, n_keep)  # (m,), (m, n)
    trans = np.abs(v.copy())
    trans[:, n_rotor:] = 0
    trans[:, 2::NDOF_NODE] = 0
    trans[:, 3::NDOF_NODE] = 0
    j = np.argmax(trans, axis=1)
    v = v / v[np.arange(v.shape[0]), j][:, None]
    return lam, v


def modal(rotor: Rotor, speed: float = 0.0, n_modes: int | None = None) -> Modes:
    """Damped modes at spin ``speed`` [rad/s]: the ``n_modes`` lowest in damped frequency.

    With ``speed`` an array (s,), modes at each speed (leading dimension). A rotor with a
    frequency-dependent bearing is solved mode by mode on its own damped frequency
    (:func:`modes_at`).

    Examples
    --------
    >>> from rotaflex.rotor.fe.model import Rotor, Shaft, Bearing
    >>> r = Rotor(shaft=(Shaft(outer_diameter=0.05, length=1.0, elements=4),),
    ...           bearing=(Bearing(node=0, kxx=1e7, kyy=1e7), Bearing(node=4, kxx=1e7, kyy=1e7)))
    >>> modal(r, 0.0, 2).wn.shape
    (1, 2)
    """
    speeds = np.atleast_1d(np.asarray(speed, float))
    m = rotor.n_dof if n_modes is None else n_modes
    lam = np.full((speeds.size, m), complex(np.nan, np.nan))
    v = np.zeros((speeds.size, m, rotor.n_dof), complex)
    for s, w in enumerate(speeds):
        ls, vs = modes_at(rotor, w, m)
        lam[s, : ls.size], v[s, : ls.size] = ls, vs
    if speeds.size == 1 or np.all(np.isfinite(lam)):
        k = min(int(np.sum(np.isfinite(lam), 1).min()), m)
        lam, v = lam[:, :k], v[:, :k]
    return Modes(speeds, lam, v, rotor.n_rotor_dof)


#: the whirl-frequency iteration of a frequency-dependent rotor stops when a mode's damped
#: frequency changes by less than this fraction (of itself, or of 1 rad/s below it)
WHIRL_TOL = 1e-10
#: after WHIRL_STALL_STEPS steps a relative change below WHIRL_ACCEPT ends the iteration (the
#: eigenvalues of a degenerate pair are only that accurate; see modes_at)
WHIRL_STALL_STEPS = 8
WHIRL_ACCEPT = 1e-7
WHIRL_MAXITER = 50


class WhirlIterationError(ConvergenceError):
    """The whirl-frequency iteration of a mode did not converge."""

    def __init__(self, what: str, residual: float, tolerance: float):
        self.what, self.time, self.residual, self.tolerance = what, float("nan"), residual, tolerance
        RuntimeError.__init__(self, f"{what} did not converge: change {residual:.3e} > tolerance {tolerance:.3e}")


def _eig_at(rotor: Rotor, speed: float, whirl: float | None, n_keep: int) -> tuple[np.ndarray, np.ndarray]:
    w = None if whirl is None else np.array([whirl])
    A = _state_matrices(rotor, np.array([speed]), w)[0]
    lam, vec = sla.eig(A, check_finite=False, overwrite_a=True)
    return _select(lam, vec, rotor.n_dof, n_keep, rotor.n_rotor_dof)


def _follow(ref: np.ndarray, lam: np.ndarray, v: np.ndarray) -> int:
    """Index of the mode among ``lam``, ``v`` (m, n) that continues the shape ``ref`` (n,).

    Eigenvalues equal to 1e-8 relative form one cluster (the x and y modes of an axisymmetric
    rotor: any combination of them is a mode), scored by the share of ``ref`` in their span;
    a single MAC would split between the two and could lose to another mode of similar shape
    (unweighted MACs of different bending modes reach 0.6).
    """
    score = np.zeros(lam.size)
    r = ref / np.linalg.norm(ref)
    for j in range(lam.size):
        near = np.flatnonzero(np.abs(lam - lam[j]) <= 1e-8 * np.abs(lam[j]))
        q, _ = np.linalg.qr(v[near].T)
        score[j] = np.sum(np.abs(q.conj().T @ r) ** 2)
    best = np.flatnonzero(score >= score.max() - 1e-9)
    return int(best[np.argmax(mac(ref[None], v[best])[0])])


def _whirl_guess(rotor: Rotor, speed: float) -> float:
    """Starting whirl frequency [rad/s]: the speed (synchronous), moved inside the whirl tables."""
    ends = [(el.whirls[0], el.whirls[-1]) for _, _, el in rotor.bearings if el.whirls is not None]
    if not ends:  # computed kinds (magnetic bearings) take any whirl frequency
        return float(speed)
    lo, hi = max(e[0] for e in ends), min(e[1] for e in ends)
    return float(np.clip(speed, lo, max(lo, hi)))


def modes_at(rotor: Rotor, speed: float, n_keep: int) -> tuple[np.ndarray, np.ndarray]:
    """The ``n_keep`` lowest oscillatory eigenpairs at ``speed`` [rad/s]: eigenvalues (m,) and
    displacement shapes (m, n_dof), sorted by damped frequency.

    Frequency-dependent bearings are evaluated at each mode's own damped frequency omega_d:
    every mode of a first solve (at the synchronous frequency, moved inside the whirl tables)
    is followed by MAC through solves at whirl = omega_d until omega_d changes by less than
    :data:`WHIRL_TOL` relative (secant steps on omega_d(w) - w after a first fixed-point step;
    at most :data:`WHIRL_MAXITER` solves per mode, then :class:`WhirlIterationError`).
    """
    if not rotor.frequency_dependent:
        return _eig_at(rotor, speed, None, n_keep)
    n_cand = min(n_keep + 4, rotor.n_dof)
    lam0, v0 = _eig_at(rotor, speed, _whirl_guess(rotor, speed), n_cand)
    lams, vecs = [], []
    for k in range(min(n_keep, lam0.size)):
        ref, w = v0[k], float(lam0[k].imag)
        w_old = g_old = None
        for it in range(WHIRL_MAXITER):
            lam, v = _eig_at(rotor, speed, w, n_cand)
            j = _follow(ref, lam, v)
            ref, g = v[j], float(lam[j].imag) - w
            scale = max(abs(w), 1.0)
            # past a few steps, a change at the eigenvalues' own accuracy is the answer: a
            # degenerate pair (isotropic supports at rest) jitters by ~1e-8 relative from solve to solve
            if abs(g) <= WHIRL_TOL * scale or (it >= WHIRL_STALL_STEPS and abs(g) <= WHIRL_ACCEPT * scale):
                break
            step = g if g_old is None or g == g_old else -g * (w - w_old) / (g - g_old)
            w_old, g_old, w = w, g, w + step
        else:
            raise WhirlIterationError(
                f"whirl-frequency iteration of mode {k} at {rad_s_to_rpm(speed):.6g} rpm", abs(g), WHIRL_TOL * abs(w)
            )
        lams.append(lam[j])
        vecs.append(v[j])
    order = np.argsort(np.imag(lams), kind="stable")
    return np.asarray(lams)[order], np.asarray(vecs).reshape(-1, rotor.n_dof)[order]


def mac(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Modal assurance criterion |a^H b|^2 / (|a|^2 |b|^2) between rows of ``a`` and ``b``."""
    num = np.abs(np.conj(a) @ b.T) ** 2
    return num / np.outer(np.sum(np.abs(a) ** 2, 1), np.sum(np.abs(b) ** 2, 1))


def assign_modes(mm: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Rows and columns of ``mm`` (r, c) that maximise the sum of ``mm[rows, cols]``, one column per row.

    When every row's largest entry sits in a different column and beats the row's second
    largest by more than :data:`ASSIGN_MARGIN`, those columns are the assignment: any other
    one loses more than the margin in some row and gains nothing in the others, so they are
    the unique optimum, the one ``scipy.optimize.linear_sum_assignment(-mm)`` returns (same
    rows and columns; tested). Otherwise (ties, crossing modes whose MACs are close, fewer
    columns than rows, NaN) the assignment problem is solved by SciPy. The check saves a
    start-up the import of scipy.optimize (~0.17 s) on a well-tracked Campbell diagram.
    """
    n, m = mm.shape
    if 0 < n <= m and np.all(np.isfinite(mm)):
        rows = np.arange(n)
        cols = np.argmax(mm, axis=1)
        if np.unique(cols).size == n:
            others = mm.copy()
            others[rows, cols] = -np.inf
            if np.all(mm[rows, cols] - others.max(axis=1) > ASSIGN_MARGIN):
                return rows, cols
    from scipy.optimize import linear_sum_assignment

    return linear_sum_assignment(-mm)


@dataclass(frozen=True)
class CampbellData:
    """Tracked modes over a speed range, their critical speeds and instability onsets."""

    modes: Modes
    mac_min: np.ndarray  # (s,) smallest MAC of a tracked assignment at each speed step
    critical: list[dict]  # {"mode", "harmonic", "speed", "frequency", "whirl"}
    unstable: list[dict]  # {"mode", "speed"}: first speed with log dec < 0


def _reduced_state_matrices(rotor: Rotor, speeds: np.ndarray, n_basis: int) -> tuple[np.ndarray, np.ndarray]:
    """State matrices projected on the lowest ``n_basis`` undamped modes of (K_sym(mid speed), M)."""
    M, K, C = rotor.MKC(speeds)
    mid = speeds.size // 2
    Km = K[mid]
    _, T = sla.eigh(0.5 * (Km + Km.T), M[mid], subset_by_index=(0, n_basis - 1))  # T^T M T = I at mid speed
    Kr = T.T @ K @ T
    Dr = T.T @ (C + speeds[:, None, None] * rotor.G[None]) @ T
    if not np.array_equal(M, np.broadcast_to(M[mid], M.shape)):  # added mass varying with speed
        Mri = np.linalg.inv(T.T @ M @ T)
        Kr, Dr = Mri @ Kr, Mri @ Dr
    return state_matrix(Kr, Dr), T  # T^T M T = I: Kr, Dr are already M^-1 K, M^-1 D


#: a critical speed whose mode's forward fraction is at least 0.5 - PLANAR_BAND is called
#: forward: straight-line (planar) orbits have a forward fraction of 0.5 up to round-off and,
#: half forward, are excited by unbalance; the band is half the straight-line tolerance
PLANAR_BAND = WHIRL_LINE_FRACTION / 2


def critical_whirl(forward_fraction) -> str:
    """Whirl label of a critical speed, the same for the Campbell and the direct solve:
    ``"forward"`` when the mode's forward fraction is >= 0.5 - :data:`PLANAR_BAND` (forward,
    mixed with forward dominant, or planar), ``"backward"`` otherwise."""
    return "forward" if forward_fraction >= 0.5 - PLANAR_BAND else "backward"


#: a mode becoming oscillatory is tracked from the first speed where its damping ratio is below
#: this: at 0.9 a mode decays by e^13 per cycle (log dec 13), too damped to be a resonance;
#: overdamped x and y pairs coupled by the gyroscopic moments turn complex with damping ratios
#: of 0.9999 and damped frequencies rising through the 1X line, which are not critical speeds
TRACK_ZETA = 0.9


def _trackable(lam) -> np.ndarray:
    """True for eigenvalues whose damping ratio is below :data:`TRACK_ZETA`."""
    lam = np.asarray(lam)
    with np.errstate(invalid="ignore", divide="ignore"):
        return -lam.real / np.abs(lam) < TRACK_ZETA


def track_modes(cands, n_osc, n_modes: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Tracked modes (s, t) from the candidates ``(lam (m,), v (m, n))`` of each speed.

    The one mode tracking of every Campbell diagram (FE rotor and machine,
    :func:`rotaflex.system.modal.campbell`). The ``n_modes`` lowest modes of the first speed
    start the tracks; at each later speed the tracks are matched to the candidates by the
    largest total MAC (:func:`assign_modes`). When more eigenvalues are oscillatory with a
    damping ratio below :data:`TRACK_ZETA` than at the speed before (``n_osc`` rises: a real
    pair became a complex one), as many unmatched candidates, lowest in frequency and below the
    highest tracked mode (or any, while fewer than ``n_modes`` are tracked), start new tracks
    there (NaN before); a constant ``n_osc`` keeps the tracks the first speed started.

    Parameters
    ----------
    cands : iterable of (ndarray, ndarray)
        Per speed, in speed order: eigenvalues (m,) [1/s] and shapes (m, n); read once (a
        generator keeps one speed's candidates in memory at a time).
    n_osc : array_like of int (s,)
        Oscillatory, trackable eigenvalues per speed (its length is the number of speeds).
    n_modes : int
        Tracks to start at the first speed.

    Returns
    -------
    lam (s, t) complex [1/s], shapes (s, t, n) complex, smallest MAC of each step (s,) [-]
    """
    ns = len(n_osc)
    cands = iter(cands)
    lam0, v0 = next(cands)
    n = v0.shape[-1]
    k = min(n_modes, lam0.size)
    # filled in place (the tracks' shapes are the largest array of a Campbell diagram); widened
    # only when a track starts late
    lam_t = np.full((ns, max(k, n_modes)), complex(np.nan, np.nan))
    v_t = np.zeros((ns, max(k, n_modes), n), complex)
    lam_t[0, :k], v_t[0, :k] = lam0[:k], v0[:k]
    tracks = k
    mac_min = np.ones(ns)
    before = v0  # the candidates of the speed before
    for s, (lam, v) in enumerate(cands, start=1):
        prev = v_t[s - 1, :tracks]
        live = np.flatnonzero(np.any(prev != 0, axis=1))
        taken = set()
        if live.size and lam.size:
            mm = mac(prev[live], v)
            rows, cols = assign_modes(mm)
            lam_t[s, live[rows]], v_t[s, live[rows]] = lam[cols], v[cols]
            taken = {int(c) for c in cols}
            mac_min[s] = float(mm[rows, cols].min()) if rows.size else np.nan
        new = int(n_osc[s] - n_osc[s - 1]) if tracks >= n_modes else max(n_modes - tracks, 0)
        if new > 0:
            top = max((x.imag for x in lam_t[s, :tracks] if np.isfinite(x)), default=np.inf)
            free = [
                c
                for c in range(lam.size)
                if c not in taken and _trackable(lam[c]) and (tracks < n_modes or lam[c].imag <= top)
            ]
            if free and before.size:  # the newly oscillatory: least like any mode of the speed before
                kin = mac(v[free], before).max(axis=1)
                free = [free[i] for i in np.argsort(kin, kind="stable")]
            add = free[:new]
            if tracks + len(add) > lam_t.shape[1]:
                grow = tracks + len(add) - lam_t.shape[1]
                lam_t = np.concatenate([lam_t, np.full((ns, grow), complex(np.nan, np.nan))], 1)
                v_t = np.concatenate([v_t, np.zeros((ns, grow, n), complex)], 1)
            lam_t[s, tracks : tracks + len(add)], v_t[s, tracks : tracks + len(add)] = lam[add], v[add]
            tracks += len(add)
        before = v
    return lam_t, v_t, mac_min


def line_crossings(speeds: np.ndarray, wd: np.ndarray, factor: float) -> list[tuple[int, int, float, float]]:
    """Where tracked damped frequencies cross an excitation line ``omega = factor * Omega``.

    The one crossing interpolation of every Campbell diagram (critical speeds of the FE rotor,
    line crossings of the machine): a sign change of ``wd - factor * Omega`` between two
    speeds, interpolated linearly.

    Parameters
    ----------
    speeds : ndarray (s,)
        Speeds [rad/s], increasing.
    wd : ndarray (s, t)
        Damped natural frequencies of the tracked modes [rad/s] (NaN: no crossing there).
    factor : float
        Excitation frequency per unit speed [-] (harmonic, order x ratio).

    Returns
    -------
    list of (mode, step, fraction, speed)
        Track ``mode``, the step ``s`` it crosses between speeds ``s`` and ``s + 1``, the
        interpolation fraction ``t`` in [0, 1] (for quantities interpolated the same way) and
        the crossing speed [rad/s]; modes in order, speeds ascending within a mode.
    """
    out = []
    for k in range(wd.shape[1]):
        d = wd[:, k] - factor * speeds
        for s in np.flatnonzero(np.sign(d[:-1]) * np.sign(d[1:]) < 0):
            t = d[s] / (d[s] - d[s + 1])
            out.append((k, int(s), t, speeds[s] + t * (speeds[s + 1] - speeds[s])))
    return out


def campbell(
    rotor: Rotor,
    speeds,
    n_modes: int = 8,
    harmonics=(1,),
    extra: int = 6,
    reduce: int | None = None,
    progress: Callable[[float, float], None] | None = None,
) -> CampbellData:
    """Campbell diagram: modes at each speed [rad/s], tracked by MAC through crossings.

    Unstable: damping ratio below -:data:`STABILITY_TOL`; the onset speed is interpolated to log dec = 0.
    At each speed the ``n_modes + extra`` lowest modes are candidates; the tracked modes of
    the previous speed are matched to them by maximising the total MAC (assignment problem,
    :func:`assign_modes`), so a mode keeps its label when its frequency crosses another's.
    Critical speeds are where a tracked damped frequency crosses ``h * Omega`` for each
    harmonic ``h`` (linear interpolation between speeds). ``reduce = m`` solves in the basis of
    the lowest ``m`` undamped modes (symmetric stiffness at the middle speed) instead of all DOFs:
    faster, approximate (the benchmark prints the frequency difference). ``progress(done, total)``
    is called with the speeds whose eigenproblem is solved (see :func:`batched_eig`).
    """
    speeds = np.asarray(speeds, float)
    if speeds.ndim != 1 or speeds.size < 2 or np.any(np.diff(speeds) <= 0):
        raise InputError("campbell.speed_rpm", list(np.round(rad_s_to_rpm(speeds), 6)), "increasing speeds (>= 2)")
    n = rotor.n_dof
    n_cand = min(n_modes + extra, n)
    if rotor.frequency_dependent:  # each mode on its own whirl frequency: one speed at a time
        cands = []
        for s, w in enumerate(speeds):
            cands.append(modes_at(rotor, w, min(n_modes + 2, n)))  # each candidate costs an iteration
            if progress is not None:
                progress(s + 1, speeds.size)
        n_osc = np.array([np.sum(_trackable(c[0])) for c in cands])
    else:
        if reduce is not None and reduce < n:
            A, T = _reduced_state_matrices(rotor, speeds, reduce)
            lams, vecs = batched_eig(A, progress=progress)
            vecs = np.concatenate([T @ vecs[:, :reduce], T @ vecs[:, reduce:]], 1)
        else:
            A = _state_matrices(rotor, speeds)
            lams, vecs = batched_eig(A, progress=progress)
        cands = [_select(lams[s], vecs[s], n, n_cand, rotor.n_rotor_dof) for s in range(speeds.size)]
        n_osc = np.sum(_oscillatory(lams) & _trackable(lams), axis=-1)
    lam_t, v_t, mac_min = track_modes(cands, n_osc, n_modes)
    modes = Modes(speeds, lam_t, v_t, rotor.n_rotor_dof)
    wd, fw = modes.wd, modes.forward_fraction
    critical = []
    for h in harmonics:
        for k, s, t, sp in line_crossings(speeds, wd, h):
            frac = fw[s, k] + t * (fw[s + 1, k] - fw[s, k])
            critical.append(
                {
                    "mode": k,
                    "harmonic": float(h),  # 0.5X is 0.5, not int(0.5) = 0
                    "speed": float(sp),
                    "frequency": float(h * sp),
                    "whirl": critical_whirl(frac),
                }
            )
    critical.sort(key=lambda c: c["speed"])
    ld, bad_all = modes.log_dec, modes.unstable
    unstable = []
    for k in range(wd.shape[1]):
        bad = np.flatnonzero(bad_all[:, k])
        if bad.size:
            s = bad[0]
            sp = (
                speeds[s]
                if s == 0
                else speeds[s - 1] + ld[s - 1, k] / (ld[s - 1, k] - ld[s, k]) * (speeds[s] - speeds[s - 1])
            )
            unstable.append({"mode": k, "speed": float(sp)})
    return CampbellData(modes, mac_min, critical, unstable)
