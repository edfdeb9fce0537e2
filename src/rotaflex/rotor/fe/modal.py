"""Eigen-analyses: modes at a speed, Campbell diagram with MAC tracking, undamped critical speed map.

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

from rotaflex.core.errors import InputError
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

    @property
    def forward_fraction(self) -> np.ndarray:
        """sum |X + iY|^2 / (sum |X + iY|^2 + sum |X - iY|^2): 1 pure forward, 0 pure backward."""
        X, Y = self.shape[..., 0::NDOF_NODE], self.shape[..., 1::NDOF_NODE]
        f = np.sum(np.abs(X + 1j * Y) ** 2, -1)
        b = np.sum(np.abs(X - 1j * Y) ** 2, -1)
        return f / (f + b)

    @property
    def whirl(self) -> np.ndarray:
        """``"forward"``, ``"backward"`` or ``"mixed"`` per mode, from the nodes' orbit senses."""
        X, Y = self.shape[..., 0::NDOF_NODE], self.shape[..., 1::NDOF_NODE]
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


def _state_matrices(rotor: Rotor, speeds: np.ndarray) -> np.ndarray:
    n = rotor.n_dof
    K, C = rotor.KC(speeds)
    Minv = _minv(rotor)
    A = np.zeros((speeds.size, 2 * n, 2 * n))
    A[:, :n, n:] = np.eye(n)
    A[:, n:, :n] = -Minv @ K
    A[:, n:, n:] = -Minv @ (C + speeds[:, None, None] * rotor.G[None])
    return A


def _minv(rotor: Rotor) -> np.ndarray:
    try:
        return sla.inv(rotor.M)
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


def _select(lam: np.ndarray, vec: np.ndarray, n: int, n_keep: int) -> tuple[np.ndarray, np.ndarray]:
    """Oscillatory eigenpairs (omega_d > 0) sorted by omega_d; displacement part normalised."""
    scale = np.max(np.abs(lam)) + 1.0
    keep = np.flatnonzero(lam.imag > 1e-9 * scale)
    keep = keep[np.argsort(lam.imag[keep], kind="stable")][:n_keep]
    lam, v = lam[keep], vec[:n, keep].T  # (m, n)
    trans = np.abs(v.copy())
    trans[:, 2::NDOF_NODE] = 0
    trans[:, 3::NDOF_NODE] = 0
    j = np.argmax(trans, axis=1)
    v = v / v[np.arange(v.shape[0]), j][:, None]
    return lam, v


def modal(rotor: Rotor, speed: float = 0.0, n_modes: int | None = None) -> Modes:
    """Damped modes at spin ``speed`` [rad/s]: the ``n_modes`` lowest in damped frequency.

    Examples
    --------
    >>> from rotaflex.rotor.fe.model import Rotor, Shaft, Bearing
    >>> r = Rotor(shaft=(Shaft(outer_diameter=0.05, length=1.0, elements=4),),
    ...           bearing=(Bearing(node=0, kxx=1e7, kyy=1e7), Bearing(node=4, kxx=1e7, kyy=1e7)))
    >>> modal(r, 0.0, 2).wn.shape
    (1, 2)
    """
    speeds = np.atleast_1d(np.asarray(speed, float))
    A = _state_matrices(rotor, speeds)[0]
    lam, vec = sla.eig(A, check_finite=False, overwrite_a=True)
    m = rotor.n_dof if n_modes is None else n_modes
    lam, v = _select(lam, vec, rotor.n_dof, m)
    return Modes(speeds, lam[None], v[None])


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
    K, C = rotor.KC(speeds)
    Km = K[speeds.size // 2]
    _, T = sla.eigh(0.5 * (Km + Km.T), rotor.M, subset_by_index=(0, n_basis - 1))  # T^T M T = I
    Kr = T.T @ K @ T
    Dr = T.T @ (C + speeds[:, None, None] * rotor.G[None]) @ T
    A = np.zeros((speeds.size, 2 * n_basis, 2 * n_basis))
    A[:, :n_basis, n_basis:] = np.eye(n_basis)
    A[:, n_basis:, :n_basis] = -Kr
    A[:, n_basis:, n_basis:] = -Dr
    return A, T


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
        raise InputError("campbell.speed_rpm", list(np.round(speeds * 30 / np.pi, 6)), "increasing speeds (>= 2)")
    n = rotor.n_dof
    if reduce is not None and reduce < n:
        A, T = _reduced_state_matrices(rotor, speeds, reduce)
        lams, vecs = batched_eig(A, progress=progress)
        vecs = np.concatenate([T @ vecs[:, :reduce], T @ vecs[:, reduce:]], 1)
    else:
        A = _state_matrices(rotor, speeds)
        lams, vecs = batched_eig(A, progress=progress)
    n_cand = min(n_modes + extra, n)
    lam_t = np.full((speeds.size, n_modes), np.nan + 0j)
    v_t = np.zeros((speeds.size, n_modes, n), complex)
    mac_min = np.ones(speeds.size)
    prev = None
    for s in range(speeds.size):
        lam, v = _select(lams[s], vecs[s], n, n_cand)
        if prev is None:
            k = min(n_modes, lam.size)
            lam_t[s, :k], v_t[s, :k] = lam[:k], v[:k]
            prev = v_t[s]
            continue
        mm = mac(prev, v)
        rows, cols = assign_modes(mm)
        lam_t[s, rows], v_t[s, rows] = lam[cols], v[cols]
        mac_min[s] = float(mm[rows, cols].min()) if rows.size else np.nan
        prev = v_t[s]
    modes = Modes(speeds, lam_t, v_t)
    wd, fw = modes.wd, modes.forward_fraction
    critical = []
    for h in harmonics:
        for k in range(n_modes):
            d = wd[:, k] - h * speeds
            for s in np.flatnonzero(np.sign(d[:-1]) * np.sign(d[1:]) < 0):
                t = d[s] / (d[s] - d[s + 1])
                sp = speeds[s] + t * (speeds[s + 1] - speeds[s])
                frac = fw[s, k] + t * (fw[s + 1, k] - fw[s, k])
                critical.append(
                    {
                        "mode": k,
                        "harmonic": float(h),  # 0.5X is 0.5, not int(0.5) = 0
                        "speed": float(sp),
                        "frequency": float(h * sp),
                        "whirl": "forward" if frac >= 0.5 else "backward",
                    }
                )
    critical.sort(key=lambda c: c["speed"])
    ld, bad_all = modes.log_dec, modes.unstable
    unstable = []
    for k in range(n_modes):
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


def plane_dofs(n_nodes: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """x-z plane DOFs (x, theta_y), y-z plane DOFs (y, theta_x) and the y-z slope signs (1, -1)."""
    base = NDOF_NODE * np.arange(n_nodes)[:, None]
    ia = (base + np.array([0, 3])).ravel()
    ib = (base + np.array([1, 2])).ravel()
    sb = np.tile([1.0, -1.0], n_nodes)
    return ia, ib, sb


def ucs_map(
    rotor: Rotor, stiffness, n_modes: int = 4, progress: Callable[[float, float], None] | None = None
) -> np.ndarray:
    """Undamped synchronous forward critical speeds [rad/s] vs isotropic bearing stiffness [N/m].

    Every bearing's coefficients are replaced by kxx = kyy = ``stiffness`` (no damping, no
    cross-coupling). For an axisymmetric rotor on isotropic supports, forward circular whirl
    at omega = Omega reduces to the symmetric one-plane problem
    (K_p - omega^2 (M_p - G_p)) u = 0, with G_p the gyroscopic coupling block of the x-z and
    y-z slope coordinates; this is solved as M_eff u = mu K_p u, omega = mu^-1/2 for mu > 0.

    Returns
    -------
    ndarray (n_stiffness, n_modes)
        Critical speeds [rad/s] (nan where fewer than ``n_modes`` exist).

    ``progress(done, total)`` is called with the stiffness values done.
    """
    stiffness = np.atleast_1d(np.asarray(stiffness, float))
    ia, ib, sb = plane_dofs(rotor.n_nodes)
    M, G = rotor.M, rotor.G
    Kshaft = rotor.K_shaft
    Mp = M[np.ix_(ia, ia)]
    Gp = G[np.ix_(ia, ib)] * sb[None, :]
    Meff = Mp - 0.5 * (Gp + Gp.T)
    out = np.full((stiffness.size, n_modes), np.nan)
    pos = {int(i): p for p, i in enumerate(ia)}
    for s, k in enumerate(stiffness):
        Kp = Kshaft[np.ix_(ia, ia)].copy()
        for node, other, _ in rotor.bearings:
            i = pos[NDOF_NODE * node]
            Kp[i, i] += k
            if other is not None:
                j = pos[NDOF_NODE * other]
                Kp[j, j] += k
                Kp[i, j] -= k
                Kp[j, i] -= k
        mu = sla.eigh(Meff, Kp, eigvals_only=True)
        mu = np.sort(mu[mu > 0])[::-1]
        w = 1.0 / np.sqrt(mu[:n_modes])
        out[s, : w.size] = w
        if progress is not None:
            progress(s + 1, stiffness.size)
    return out
