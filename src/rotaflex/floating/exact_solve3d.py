"""Dynamics of the 3-D geometrically exact beam: Lie-group generalized-alpha.

Equations per node (translations inertial, rotations in section axes with the material angular
velocity ``W``, ``R' = R W~``)::

    M_t x'' + f_int - f_ext = 0,       J W' + W x J W + R^T (m_int - m_ext) = 0,

``M_t`` the consistent translational mass, ``J`` the lumped rotary inertia in section axes
(:meth:`~rotaflex.floating.exact_beam3d.ExactBeam3D.mass_matrix`). Integrator: the Lie-group
generalized-alpha method of Brüls & Cardona (2010, J. Comput. Nonlinear Dyn. 5, 031002) in the
form of Brüls, Cardona & Arnold (2012, Mech. Mach. Theory 48, 121-137): the step's increment
``dq = h v_n + h^2 (1/2 - beta) a_n + h^2 beta a_{n+1}`` moves the positions additively and the
rotations by ``R_{n+1} = R_n exp(h dTheta~)`` (material), ``v`` and the acceleration-like ``a``
follow the Chung-Hulbert recursions of :func:`rotaflex.floating.exact_solve.alpha_coefficients`
(second order; ``rho_inf = 1`` keeps the energy to O(h^2) without drift, smaller values damp the
unresolved frequencies). Newton's iteration matrix is ``M + gamma' C_gyro + beta' K T``: the
static tangent turned into section axes (plus the turn of the rows ``(R^T m)~``), ``T`` the
tangent operator of the exponential map of the step's rotation increment.

Boundary: a fixed reference frame; clamped nodes keep their reference state (their 6 DOFs are
held). No prescribed frame motion or hub yet.
"""

from __future__ import annotations

import time

import numpy as np

from rotaflex.core.errors import ConvergenceError
from rotaflex.floating import exact_kernels as ek
from rotaflex.floating import exact_kernels3d as ek3
from rotaflex.floating.exact_beam3d import ExactBeam3D, PointLoads3D
from rotaflex.floating.exact_solve import ExactSolution, alpha_coefficients, time_grid
from rotaflex.rotation import quaternion_to_matrix


def _skew(v):
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def _tangent_operator(dq: np.ndarray) -> np.ndarray:
    """Block-diagonal ``T`` (n, n): identity on translations, the right Jacobian of the
    exponential map ``Jr(dTheta)`` on each rotation (``R exp(dTheta + d) = R exp(dTheta) exp(Jr d)``)."""
    T = np.eye(len(dq))
    for b in range(len(dq) // 6):
        v = dq[6 * b + 3 : 6 * b + 6]
        th = float(np.linalg.norm(v))
        if th < 1e-4:
            c1, c2 = 0.5 - th * th / 24.0, 1.0 / 6.0 - th * th / 120.0
        else:
            c1, c2 = (1.0 - np.cos(th)) / th**2, (th - np.sin(th)) / th**3
        S = _skew(v)
        T[6 * b + 3 : 6 * b + 6, 6 * b + 3 : 6 * b + 6] = np.eye(3) - c1 * S + c2 * S @ S
    return T


class _Equations:
    """Residual and iteration matrix of the 3-D beam's equations of motion."""

    def __init__(self, beam: ExactBeam3D, loads: PointLoads3D):
        self.beam, self.loads = beam, loads
        self.M = beam.mass_matrix()
        n = beam.n_dof
        self.rot = np.zeros(n, dtype=bool)
        self.rot.reshape(-1, 6)[:, 3:] = True
        self.fixed = np.zeros(n, dtype=bool)
        self.fixed[beam.frame_dof :] = True
        for c in beam.clamps[:, 0].astype(int):
            self.fixed[6 * c : 6 * c + 6] = True
        self.free = np.flatnonzero(~self.fixed)

    def load_factors(self, t: float) -> np.ndarray:
        ld = self.loads
        lam = np.zeros(len(ld.node) + 1)
        ek.load_factors(float(t), ld.profile, ld.par, lam)
        return lam

    def forces(self, q, t, want_k=True):
        """``f_int - f_ext`` (spatial, increment layout), its tangent and the strain energy."""
        return self.beam.residual(self.loads, q, self.load_factors(t), want_k)

    def residual(self, q, v, vd, t, want_k=True):
        """Equations of motion (n,) at state ``q``, velocities ``v`` (translations inertial,
        rotations material) and their rates ``vd``; with ``want_k`` the iteration blocks
        ``(K in section axes, C_gyro)``."""
        r, K, _ = self.forces(q, t, want_k)
        nb = self.beam.n_dof // 6
        R = quaternion_to_matrix(q.reshape(nb, 7)[:, 3:])
        out = self.M @ vd
        Jd = np.diag(self.M)
        C = np.zeros_like(self.M) if want_k else None
        G = np.zeros_like(self.M) if want_k else None
        for b in range(nb):
            w = v[6 * b + 3 : 6 * b + 6]
            J = Jd[6 * b + 3 : 6 * b + 6]
            rows = slice(6 * b + 3, 6 * b + 6)
            out[6 * b : 6 * b + 3] += r[6 * b : 6 * b + 3]
            m = R[b].T @ r[rows]
            out[rows] += np.cross(w, J * w) + m
            if want_k:
                C[rows, rows] = _skew(w) @ np.diag(J) - _skew(J * w)
                G[rows, rows] = _skew(m)  # d(R^T m) / dTheta at fixed m: the row's own turn
        if not want_k:
            return out, None, None
        # spatial rows/columns -> section axes on the rotations (rows R^T, columns R)
        S = np.eye(self.beam.n_dof)
        for b in range(nb):
            S[6 * b + 3 : 6 * b + 6, 6 * b + 3 : 6 * b + 6] = R[b]
        return out, S.T @ K @ S + G, C

    def energy(self, q, v):
        """Kinetic and strain energy [J]."""
        _, _, u = self.forces(q, 0.0, want_k=False)
        return 0.5 * v @ self.M @ v, u


def simulate_exact3d(
    beam: ExactBeam3D,
    loads: PointLoads3D,
    *,
    t_end: float,
    dt_out: float,
    time_step: float,
    rho_inf: float = 1.0,
    q0=None,
    v0=None,
    tol: float = 1e-10,
    max_iter: int = 30,
    progress=None,
) -> ExactSolution:
    """Time history of a 3-D exact beam from ``q0`` (state, default the reference) and ``v0``
    (6 per block: inertial translational velocity [m/s], material angular velocity [rad/s]).

    Returns an :class:`~rotaflex.floating.exact_solve.ExactSolution` with ``v`` in that layout
    and the energy columns kinetic, strain, work of the loads (trapezoidal rule on the
    spatial increments), 0 (fixed frame: no drive work).

    Raises
    ------
    ConvergenceError
        Newton's iteration of a step did not converge in ``max_iter`` iterations.
    """
    t_wall = time.perf_counter()
    eq = _Equations(beam, loads)
    am, af, beta, gamma = alpha_coefficients(rho_inf)
    n = beam.n_dof
    q = beam.reference_state() if q0 is None else np.array(q0, dtype=float)
    v = np.zeros(n) if v0 is None else np.array(v0, dtype=float)
    v[eq.fixed] = 0.0
    free = eq.free
    # start: M vd = -(gyroscopic + internal - external)
    r0, _, _ = eq.residual(q, v, np.zeros(n), 0.0, want_k=False)
    vd = np.zeros(n)
    vd[free] = np.linalg.solve(eq.M[np.ix_(free, free)], -r0[free])
    a = vd.copy()
    times, is_out = time_grid(t_end, dt_out, time_step)
    Q, V, E = [], [], []
    work, iters = 0.0, 0
    fe_prev = _external(eq, q, 0.0)
    # force scale of the tolerance: the larger of the start's forces and momentum / step
    # (and the loads at full value, for a start from rest)
    mom = float(np.abs(eq.M @ v).max()) / time_step
    f_full = np.zeros(n)
    ld = loads
    ek3.external(
        q,
        np.ones(len(ld.node) + 1),
        ld.node,
        ld.kind,
        ld.frame,
        ld.amp,
        beam.n_nodes,
        ld.dist,
        f_full,
        np.zeros((1, 1)),
        False,
    )
    scale = max(float(np.abs(eq.M @ vd).max()), float(np.abs(r0).max()), mom, float(np.abs(f_full).max()), 1e-300)

    def record(q, v, w):
        ek, u = eq.energy(q, v)
        Q.append(q.copy())
        V.append(v.copy())
        E.append((ek, u, w, 0.0))

    record(q, v, work)
    for k in range(1, len(times)):
        t1, h = times[k], times[k] - times[k - 1]
        bp = (1.0 - af) / (1.0 - am) * h * h * beta
        gp = (1.0 - af) / (1.0 - am) * h * gamma
        vd1 = np.zeros(n)
        a1 = (af * vd - am * a) / (1.0 - am)
        v1 = v + h * (1.0 - gamma) * a + h * gamma * a1
        dq = h * v + h * h * (0.5 - beta) * a + h * h * beta * a1
        dq[eq.fixed] = v1[eq.fixed] = 0.0
        q1 = q.copy()
        step = np.inf
        for it in range(1, max_iter + 1):
            ek3.advance_material(q1, q, dq)
            r, K, C = eq.residual(q1, v1, vd1, t1)
            res = float(np.abs(r[free]).max())
            # converged: the residual at its tolerance, or the last correction of the positions
            # at round-off level (the stiff axial forces' floor)
            if it > 1 and (res <= tol * scale or step <= 1e-13 * beam.length):
                break
            A = eq.M + gp * C + bp * K @ _tangent_operator(dq)
            d = np.linalg.solve(A[np.ix_(free, free)], -r[free])
            vd1[free] += d
            a1[free] += (1.0 - af) / (1.0 - am) * d
            v1[free] += gp * d
            dq[free] += bp * d
            step = bp * float(np.abs(d).max())
        else:
            raise ConvergenceError("generalized-alpha step", float(t1), res, tol * scale)
        iters += it
        # work of the loads: trapezoidal rule on the spatial increments (rotations R_n dTheta)
        fe = _external(eq, q1, t1)
        R = quaternion_to_matrix(q.reshape(-1, 7)[:, 3:])
        ds = dq.reshape(-1, 6).copy()
        ds[:, 3:] = np.einsum("bij,bj->bi", R, ds[:, 3:])
        work += 0.5 * (fe_prev + fe) @ ds.ravel()
        fe_prev = fe
        q, v, vd, a = q1, v1, vd1, a1
        if is_out[k]:
            record(q, v, work)
        if progress is not None and is_out[k]:
            progress(float(t1))
    return ExactSolution(
        time=times[is_out],
        q=np.array(Q),
        v=np.array(V),
        energy=np.array(E),
        message=f"Lie-group generalized-alpha: {len(times) - 1} steps, {iters} Newton iterations",
        nstep=len(times) - 1,
        niter=iters,
        wall_time=time.perf_counter() - t_wall,
        method="exact",
    )


def _external(eq: _Equations, q, t) -> np.ndarray:
    ld = eq.loads
    f, K = np.zeros(eq.beam.n_dof), np.zeros((1, 1))
    ek3.external(q, eq.load_factors(t), ld.node, ld.kind, ld.frame, ld.amp, eq.beam.n_nodes, ld.dist, f, K, False)
    return f
