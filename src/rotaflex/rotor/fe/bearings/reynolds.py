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
    """

    def __init__(self, length_over_diameter: float, n_theta: int = 72, n_z: int = 12):
        self.n_theta, self.n_z = int(n_theta), int(n_z)
        if self.n_theta < 8 or self.n_z < 4 or self.n_z % 2:
            raise ValueError("n_theta >= 8 and an even n_z >= 4 are required")
        self.alpha = (0.5 / length_over_diameter) ** 2  # (R/L)^2
        nt, nzi = self.n_theta, self.n_z // 2  # unknown rows j = 1 .. n_z/2 (the last is the mid-plane)
        self.nzi = nzi
        self.dt, self.dz = 2 * np.pi / nt, 1.0 / self.n_z
        self.theta = np.arange(nt) * self.dt
        self.theta_half = self.theta + 0.5 * self.dt  # face i + 1/2
        self.n = nt * nzi
        # circumferential positions interleaved (0, nt-1, 1, nt-2, ...) so that the periodic
        # neighbours are at most 2 positions apart: a band matrix of half-width 2 nzi (LAPACK gbtrf)
        interleave = np.empty(nt, int)
        interleave[0::2] = np.arange((nt + 1) // 2)
        interleave[1::2] = nt - 1 - np.arange(nt // 2)
        pos = np.empty(nt, int)
        pos[interleave] = np.arange(nt)
        i, j = np.meshgrid(interleave, np.arange(nzi), indexing="ij")
        i, j = i.ravel(), j.ravel()
        k = pos[i] * nzi + j
        self.i_of = i
        east, west = pos[(i + 1) % nt] * nzi + j, pos[(i - 1) % nt] * nzi + j
        mid = j == nzi - 1
        # entries: (row, col, kind) with kind 0 diag, 1 east (face i+1/2), 2 west (face i-1/2), 3 axial
        rows = [k, k, k, k[j > 0], k[~mid]]
        cols = [k, east, west, k[j > 0] - 1, k[~mid] + 1]
        n_s, n_n = int((j > 0).sum()), int((~mid).sum())
        kind = [np.full(k.size, 0), np.full(k.size, 1), np.full(k.size, 2), np.full(n_s, 3), np.full(n_n, 3)]
        # axial weight: 1 per neighbour, 2 for the mid-plane's south neighbour (its mirror image)
        zero = np.zeros(k.size)
        zmul = [zero, zero, zero, np.where(mid[j > 0], 2.0, 1.0), np.ones(n_n)]
        rows, cols = np.concatenate(rows), np.concatenate(cols)
        kind, zmul = np.concatenate(kind), np.concatenate(zmul)
        order = np.lexsort((cols, rows))
        self._rows, self._cols, self._kind, self._zmul = rows[order], cols[order], kind[order], zmul[order]
        self._i = self.i_of[self._rows]
        self._diag = np.flatnonzero(self._kind == 0)
        # off-diagonal entry = mult * G[src], G = [g at faces, scaled g at nodes]
        src = np.where(self._kind == 1, self._i, np.where(self._kind == 2, (self._i - 1) % nt, nt + self._i))
        self._src, self._mult = src, np.where(self._kind == 3, -self._zmul, -1.0)
        self.band = 2 * nzi
        kb = self.band
        self._ab_shape = (3 * kb + 1, self.n)  # gbtrf storage: kl extra rows for the pivoting fill-in
        self._ab_index = (2 * kb + self._rows - self._cols) * self.n + self._cols
        # quadrature over the whole length: the half counted twice, the mid-plane once
        wz = np.where(mid, 1.0, 2.0)
        self.w = self.dt * self.dz * wz
        self.cos, self.sin = np.cos(self.theta[i]), np.sin(self.theta[i])
        self._s = 2 * np.sin(self.dt / 2) / self.dt

    def values(self, g_face: np.ndarray, g_node: np.ndarray) -> np.ndarray:
        """CSR data of M (minus the discrete operator) for coefficients g (H^3 or a derivative).

        g_face : (n_theta,) values at faces i + 1/2; g_node : (n_theta,) values at nodes.
        """
        G = np.concatenate([g_face, self.alpha * (self.dt / self.dz) ** 2 * g_node]) / self.dt**2
        v = self._mult * G[self._src]
        i = self._i[self._diag]
        v[self._diag] = G[i] + G[(i - 1) % self.n_theta] + 2 * G[self.n_theta + i]
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

    def film(self, ex: float, ey: float):
        """H at faces and nodes."""
        hf = 1 - ex * np.cos(self.theta_half) - ey * np.sin(self.theta_half)
        hn = 1 - ex * np.cos(self.theta) - ey * np.sin(self.theta)
        return hf, hn

    def rhs(self, ex: float, ey: float, vx: float = 0.0, vy: float = 0.0) -> np.ndarray:
        """f = dH/dtheta - 2 (vx cos + vy sin) at the unknowns, dH/dtheta taken conservatively as
        (H_{i+1/2} - H_{i-1/2}) / dtheta = 2 sin(dtheta/2)/dtheta (ex sin theta_i - ey cos theta_i)."""
        return self._s * (ex * self.sin - ey * self.cos) - 2 * (vx * self.cos + vy * self.sin)

    def force(self, P: np.ndarray) -> np.ndarray:
        """Film force on the journal (2,) or (2, n_rhs) from nodal pressures (trapezoid rule)."""
        return -np.stack([(self.w * self.cos) @ P, (self.w * self.sin) @ P])


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
    hf, hn = grid.film(ex, ey)
    data = grid.values(hf**3, hn**3)
    f = grid.rhs(ex, ey)
    # cold start: cavitated where the film diverges (the half-Sommerfeld guess)
    A = f > 0 if active is None else active.copy()
    it = 0
    while True:
        it += 1
        if it > MAX_ACTIVE_SET_ITERATIONS:
            raise RuntimeError(f"cavitation active set did not settle in {MAX_ACTIVE_SET_ITERATIONS} iterations")
        # active rows become P = p_cav (identity rows): same pattern, no slicing
        d = data.copy()
        on = A[grid._rows]
        d[on] = 0.0
        d[grid._diag[A]] = 1.0
        lu = grid.factor(d)
        P = grid.solve(lu, np.where(A, p_cav, -f))
        lam = grid.matvec(data, P) + f
        A_new = np.where(A, lam > 0, P < p_cav)
        if np.array_equal(A_new, A):
            break
        A = A_new
    force = grid.force(P)
    k = b = np.full((2, 2), np.nan)
    if derivatives:
        # d/de_x, d/de_y of (M P + f) at fixed P; then M_FF dP_F = -that, dP = 0 on the cavitated set
        cols = []
        for c_f, c_n, unit in (
            (np.cos(grid.theta_half), np.cos(grid.theta), (1.0, 0.0)),
            (np.sin(grid.theta_half), np.sin(grid.theta), (0.0, 1.0)),
        ):
            dM = grid.values(-3 * hf**2 * c_f, -3 * hn**2 * c_n)
            cols.append(grid.matvec(dM, P) + grid.rhs(*unit))  # the rhs is linear in e
        cols.append(-2 * grid.cos)  # d f / d ex'
        cols.append(-2 * grid.sin)  # d f / d ey'
        R = -np.stack(cols, 1)
        R[A] = 0.0
        dP = grid.solve(lu, R)
        dF = grid.force(dP)  # (2, 4)
        k, b = -dF[:, :2], -dF[:, 2:]
    half = np.empty((grid.n_theta, grid.nzi))
    half[grid.i_of.reshape(grid.n_theta, grid.nzi)[:, 0]] = P.reshape(grid.n_theta, grid.nzi)
    pressure = np.zeros((grid.n_theta, grid.n_z + 1))
    pressure[:, 1 : grid.nzi + 1] = half
    pressure[:, grid.nzi + 1 : -1] = half[:, -2::-1]
    return FilmSolution(force, k, b, pressure, A, it)
