"""Finite-length Reynolds equation of a plain 360 deg journal bearing, by finite differences.

Dimensionless form (isoviscous, incompressible, aligned journal), on the unwrapped film
theta in [0, 2 pi) (periodic, measured from +x towards +y, the spin sense) and zb = z / L in
[-1/2, 1/2]::

    d/dtheta(H^3 dP/dtheta) + (R/L)^2 d/dzb(H^3 dP/dzb) = dH/dtheta - 2 (ex' cos theta + ey' sin theta)

with H = h / c = 1 - ex cos theta - ey sin theta, P = p c^2 / (6 mu omega R^2), the journal
centre at (ex, ey) c and moving at (ex', ey') c omega. P = 0 (ambient) at both ends.

Cavitation: the Reynolds (Swift-Stieber) condition P >= P_cav with the equation holding where
P > P_cav and d(flux) >= 0 where P = P_cav, i.e. the linear complementarity problem
M P + f >= 0, P - P_cav >= 0, (M P + f)(P - P_cav) = 0 (M = minus the discrete operator, an
M-matrix). It is solved by a primal-dual active-set iteration (exact for M-matrices after a
finite number of sparse solves, warm-started from the previous cavitated set), not by SOR.

Film force on the journal Fb = -int int P (cos theta, sin theta) dtheta dzb, in units of
6 mu omega R^3 L / c^2. The stiffness kb = -dFb/de and damping bb = -dFb/de' come from the
exact derivative of the discrete solution with the cavitated set frozen (the perturbed Reynolds
equations on the full-film region, Lund's method), reusing the factorisation of the last solve.

:func:`solve_general` takes any film H = 1 - sum_k q_k cos(theta - phase_k) (the journal's x and
y are phases 0 and pi/2; a tilting pad adds its tilt and preload) on the full circle or on a
pad arc (P = 0 at the pad edges), and returns the generalised forces -int int P cos(theta -
phase_k) with their derivatives; :func:`solve_film` is the plain-bearing case.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg.lapack import dgbtrf, dgbtrs

MAX_ACTIVE_SET_ITERATIONS = 60


@dataclass(frozen=True)
class FilmSolution:
    """Dimensionless film state at one journal position (rest frame of the bearing).

    Attributes
    ----------
    force : ndarray (2,)
        Film force on the journal in units of 6 mu omega R^3 L / c^2.
    k : ndarray (2, 2)
        -dForce/de (e: eccentricity vector / c).
    b : ndarray (2, 2)
        -dForce/de' (e' = journal velocity / (c omega)).
    pressure : ndarray (n_theta, n_z + 1)
        P on the grid (ends included).
    active : ndarray of bool
        Cavitated nodes (warm start for the next solve).
    iterations : int
        Active-set iterations.
    """

    force: np.ndarray
    k: np.ndarray
    b: np.ndarray
    pressure: np.ndarray
    active: np.ndarray
    iterations: int


class ReynoldsGrid:
    """Grid, sparsity pattern and quadrature of the unwrapped film (built once per bearing).

    The film is symmetric about the mid-plane for an aligned journal, so only the half
    zb in [-1/2, 0] is solved (mirror condition at zb = 0).

    Parameters
    ----------
    length_over_diameter : float
        L / D.
    n_theta : int
        Nodes around the circumference (>= 8).
    n_z : int
        Intervals across the whole length (even, >= 4; the ends are Dirichlet nodes).
    arc : (float, float) or None
        None: the full periodic film. (theta0, theta1) [rad]: a pad from theta0 to theta1 with
        P = 0 at both edges, ``n_theta`` intervals along it.
    """

    def __init__(self, length_over_diameter: float, n_theta: int = 72, n_z: int = 12, arc=None):
        self.n_theta, self.n_z = int(n_theta), int(n_z)
        if self.n_theta < 8 or self.n_z < 4 or self.n_z % 2:
            raise ValueError("n_theta >= 8 and an even n_z >= 4 are required")
        self.alpha = (0.5 / length_over_diameter) ** 2  # (R/L)^2
        nzi = self.n_z // 2  # unknown rows j = 1 .. n_z/2 (the last is the mid-plane)
        self.nzi = nzi
        self.dz = 1.0 / self.n_z
        if arc is None:
            nt = self.n_theta
            self.dt = 2 * np.pi / nt
            self.theta = np.arange(nt) * self.dt
            self.theta_face = self.theta + 0.5 * self.dt  # face i + 1/2 (east of node i)
            east_face, west_face = np.arange(nt), (np.arange(nt) - 1) % nt
            # positions interleaved (0, nt-1, 1, nt-2, ...) so that the periodic neighbours are at
            # most 2 positions apart: a band matrix of half-width 2 nzi (LAPACK gbtrf)
            interleave = np.empty(nt, int)
            interleave[0::2] = np.arange((nt + 1) // 2)
            interleave[1::2] = nt - 1 - np.arange(nt // 2)
        else:
            nt = self.n_theta - 1  # interior nodes; the pad edges carry P = 0
            self.dt = (arc[1] - arc[0]) / self.n_theta
            self.theta = arc[0] + (np.arange(nt) + 1) * self.dt
            self.theta_face = arc[0] + (np.arange(nt + 1) + 0.5) * self.dt  # face f sits west of node f
            east_face, west_face = np.arange(nt) + 1, np.arange(nt)
            interleave = np.arange(nt)
        self.nt = nt
        self.theta_half = self.theta_face[east_face]
        self.n = nt * nzi
        pos = np.empty(nt, int)
        pos[interleave] = np.arange(nt)
        i, j = np.meshgrid(interleave, np.arange(nzi), indexing="ij")
        i, j = i.ravel(), j.ravel()
        k = pos[i] * nzi + j
        self.i_of = i
        if arc is None:
            has_e = has_w = np.ones(i.size, bool)
            east, west = pos[(i + 1) % nt] * nzi + j, pos[(i - 1) % nt] * nzi + j
        else:
            has_e, has_w = i + 1 < nt, i > 0
            east, west = pos[np.minimum(i + 1, nt - 1)] * nzi + j, pos[np.maximum(i - 1, 0)] * nzi + j
        mid = j == nzi - 1
        # entries: (row, col, kind) with kind 0 diag, 1 east, 2 west, 3 axial
        rows = [k, k[has_e], k[has_w], k[j > 0], k[~mid]]
        cols = [k, east[has_e], west[has_w], k[j > 0] - 1, k[~mid] + 1]
        n_s, n_n = int((j > 0).sum()), int((~mid).sum())
        kind = [np.full(k.size, 0), np.full(has_e.sum(), 1), np.full(has_w.sum(), 2), np.full(n_s, 3), np.full(n_n, 3)]
        # axial weight: 1 per neighbour, 2 for the mid-plane's south neighbour (its mirror image)
        zmul = [np.zeros(k.size), np.zeros(has_e.sum()), np.zeros(has_w.sum()), np.where(mid[j > 0], 2.0, 1.0)]
        zmul.append(np.ones(n_n))
        rows, cols = np.concatenate(rows), np.concatenate(cols)
        kind, zmul = np.concatenate(kind), np.concatenate(zmul)
        order = np.lexsort((cols, rows))
        self._rows, self._cols, self._kind, self._zmul = rows[order], cols[order], kind[order], zmul[order]
        self._i = self.i_of[self._rows]
        self._diag = np.flatnonzero(self._kind == 0)
        # entry = mult * G[src], G = [g at faces, scaled g at nodes]; the diagonal sums its faces
        nf = self.theta_face.size
        self._nf, self._east_face, self._west_face = nf, east_face, west_face
        src = np.where(self._kind == 1, east_face[self._i], np.where(self._kind == 2, west_face[self._i], nf + self._i))
        self._src, self._mult = src, np.where(self._kind == 3, -self._zmul, -1.0)
        self.band = 2 * nzi
        kb = self.band
        self._ab_shape = (3 * kb + 1, self.n)  # gbtrf storage: kl extra rows for the pivoting fill-in
        self._ab_index = (2 * kb + self._rows - self._cols) * self.n + self._cols
        # quadrature over the whole length: the half counted twice, the mid-plane once
        wz = np.where(mid, 1.0, 2.0)
        self.w = self.dt * self.dz * wz
        self._s = 2 * np.sin(self.dt / 2) / self.dt

    def values(self, g_face: np.ndarray, g_node: np.ndarray) -> np.ndarray:
        """CSR data of M (minus the discrete operator) for coefficients g (H^3 or a derivative).

        g_face : values at ``theta_face``; g_node : values at the nodes ``theta``.
        """
        G = np.concatenate([g_face, self.alpha * (self.dt / self.dz) ** 2 * g_node]) / self.dt**2
        v = self._mult * G[self._src]
        i = self._i[self._diag]
        v[self._diag] = G[self._east_face[i]] + G[self._west_face[i]] + 2 * G[self._nf + i]
        return v

    def matvec(self, data: np.ndarray, P: np.ndarray) -> np.ndarray:
        """M P for the matrix with entries ``data`` on the fixed pattern."""
        return np.bincount(self._rows, data * P[self._cols], minlength=self.n)

    def factor(self, data: np.ndarray):
        """Band LU factors of the matrix with entries ``data``."""
        ab = np.zeros(self._ab_shape)
        ab.flat[self._ab_index] = data
        lu, piv, info = dgbtrf(ab, self.band, self.band, overwrite_ab=1)
        if info != 0:
            raise RuntimeError(f"singular film matrix (LAPACK gbtrf info {info})")
        return lu, piv

    def solve(self, factors, b: np.ndarray) -> np.ndarray:
        """Solve with factors from :meth:`factor` (b: (n,) or (n, m))."""
        x, info = dgbtrs(factors[0], self.band, self.band, b, factors[1])
        return x

    def film(self, q, phase):
        """H = 1 - sum_k q_k cos(theta - phase_k) at faces and nodes."""
        c_f = np.cos(self.theta_face[:, None] - phase[None, :])
        c_n = np.cos(self.theta[:, None] - phase[None, :])
        return 1 - c_f @ q, 1 - c_n @ q, c_f, c_n

    def rhs(self, q, phase, qdot=None) -> np.ndarray:
        """f = dH/dtheta - 2 dH/dt / omega at the unknowns. dH/dtheta is taken conservatively,
        (H_{i+1/2} - H_{i-1/2}) / dtheta = 2 sin(dtheta/2)/dtheta sum_k q_k sin(theta_i - phase_k)."""
        th = self.theta[self.i_of][:, None] - phase[None, :]
        f = self._s * (np.sin(th) @ q)
        if qdot is not None:
            f = f - 2 * (np.cos(th) @ qdot)
        return f

    def generalised_force(self, P: np.ndarray, phase) -> np.ndarray:
        """Q_k = -int int P cos(theta - phase_k) dtheta dzb (trapezoid rule), (n_k,) or (n_k, n_rhs)."""
        g = np.cos(self.theta[self.i_of][None, :] - phase[:, None]) * self.w
        return -(g @ P)

    def force(self, P: np.ndarray) -> np.ndarray:
        """Film force on the journal (2,) or (2, n_rhs) from nodal pressures (trapezoid rule)."""
        return self.generalised_force(P, XY)


XY = np.array([0.0, np.pi / 2])  #: phases of cos(theta) and sin(theta): the journal's x and y


@dataclass(frozen=True)
class GeneralSolution:
    """Film state for H = 1 - sum_k q_k cos(theta - phase_k) (dimensionless, as FilmSolution).

    Attributes
    ----------
    Q : (n_k,) generalised forces -int int P cos(theta - phase_k)
    k : (n_k, n_d) -dQ/dq_j;  b : (n_k, n_d) -dQ/dqdot_j (j < n_d, the perturbed coordinates)
    P : nodal pressures (unknown ordering); active : cavitated nodes; iterations : active-set steps
    """

    Q: np.ndarray
    k: np.ndarray
    b: np.ndarray
    P: np.ndarray
    active: np.ndarray
    iterations: int


def solve_general(grid, q, phase, n_d: int, p_cav: float = 0.0, active=None, derivatives: bool = True):
    """Reynolds LCP for the film H = 1 - sum_k q_k cos(theta - phase_k); derivatives with respect
    to the first ``n_d`` coordinates (displacements and velocities) by the perturbed equations."""
    q, phase = np.asarray(q, float), np.asarray(phase, float)
    hf, hn, c_f, c_n = grid.film(q, phase)
    if min(hf.min(), hn.min()) <= 0:
        raise ValueError("film thickness <= 0: the journal touches the bearing")
    data = grid.values(hf**3, hn**3)
    f = grid.rhs(q, phase)
    # cold start: cavitated where the film diverges (the half-Sommerfeld guess)
    A = f > 0 if active is None else active.copy()
    it = 0
    while True:
        it += 1
        if it > MAX_ACTIVE_SET_ITERATIONS:
            raise RuntimeError(f"cavitation active set did not settle in {MAX_ACTIVE_SET_ITERATIONS} iterations")
        # active rows become P = p_cav (identity rows): same pattern, no slicing
        d = data.copy()
        d[A[grid._rows]] = 0.0
        d[grid._diag[A]] = 1.0
        lu = grid.factor(d)
        P = grid.solve(lu, np.where(A, p_cav, -f))
        lam = grid.matvec(data, P) + f
        A_new = np.where(A, lam > 0, P < p_cav)
        if np.array_equal(A_new, A):
            break
        A = A_new
    Q = grid.generalised_force(P, phase)
    k = b = np.full((phase.size, n_d), np.nan)
    if derivatives:
        # d/dq_j of (M P + f) at fixed P, and d f / d qdot_j; then M_FF dP_F = -that, dP = 0 where cavitated
        cols = []
        for j in range(n_d):
            dM = grid.values(-3 * hf**2 * c_f[:, j], -3 * hn**2 * c_n[:, j])  # dH/dq_j = -cos
            unit = np.zeros(phase.size)
            unit[j] = 1.0
            cols.append(grid.matvec(dM, P) + grid.rhs(unit, phase))  # the rhs is linear in q
        th = grid.theta[grid.i_of][:, None] - phase[None, :n_d]
        R = -np.concatenate([np.stack(cols, 1), -2 * np.cos(th)], 1)
        R[A] = 0.0
        dQ = grid.generalised_force(grid.solve(lu, R), phase)  # (n_k, 2 n_d)
        k, b = -dQ[:, :n_d], -dQ[:, n_d:]
    return GeneralSolution(Q, k, b, P, A, it)


def solve_film(
    grid: ReynoldsGrid,
    ex: float,
    ey: float = 0.0,
    p_cav: float = 0.0,
    active: np.ndarray | None = None,
    derivatives: bool = True,
) -> FilmSolution:
    """Pressure, force and (optionally) force derivatives at journal position (ex, ey).

    Parameters
    ----------
    grid : ReynoldsGrid
    ex, ey : float
        Eccentricity vector / c (|e| < 1).
    p_cav : float
        Dimensionless cavitation pressure (<= 0 relative to the ambient pressure at the ends).
    active : bool array or None
        Initial cavitated set (warm start).
    derivatives : bool
        Also compute k = -dF/de and b = -dF/de'.

    Raises
    ------
    RuntimeError
        The active-set iteration did not settle (should not happen for an M-matrix).
    """
    s = solve_general(grid, [ex, ey], XY, 2, p_cav, active, derivatives)
    half = np.empty((grid.nt, grid.nzi))
    half[grid.i_of.reshape(grid.nt, grid.nzi)[:, 0]] = s.P.reshape(grid.nt, grid.nzi)
    pressure = np.zeros((grid.nt, grid.n_z + 1))
    pressure[:, 1 : grid.nzi + 1] = half
    pressure[:, grid.nzi + 1 : -1] = half[:, -2::-1]
    return FilmSolution(s.Q, s.k, s.b, pressure, s.active, s.iterations)
