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

Boundary: the reference frame is fixed, or turns about a fixed axis through its origin by a
prescribed angle ``phi(t)`` (:meth:`~rotaflex.floating.model.Prescribed.packed` profiles:
spin-up, bang-bang and versine slews). Clamped nodes (and the frame block) are eliminated: their
state is imposed at every step end from the frame's motion (:func:`rigid_motion`: position
``R_F x0``, rotation ``R_F R0``, inertial velocity ``w x x``, material angular velocity
``R0^T w`` and the accelerations), so the consistent mass couples their prescribed acceleration
into the free rows. The clamp's reaction is the residual of the eliminated rows; its work (the
drive work: trapezoidal rule on the eliminated increments) closes the energy balance.
"""

from __future__ import annotations

import time

import numpy as np

from rotaflex.core.errors import ConvergenceError
from rotaflex.floating import exact_kernels as ek
from rotaflex.floating import exact_kernels3d as ek3
from rotaflex.floating.exact_beam3d import ExactBeam3D, PointLoads3D
from rotaflex.floating.exact_solve import ExactSolution, alpha_coefficients, time_grid
from rotaflex.floating.kernels import motion_profile
from rotaflex.rotation import quaternion_to_matrix
from rotaflex.rotation.quaternion import quaternion_product


def rigid_motion(beam: ExactBeam3D, pres, t: float):
    """The reference body carried rigidly by the prescribed frame at time ``t`` [s].

    ``pres``: packed :class:`~rotaflex.floating.model.Prescribed` (unit axis, profile) or
    ``None`` (fixed frame). Returns the state ``q`` (7 per block), velocities and accelerations
    (6 per block: inertial translation [m/s, m/s^2], material angular velocity [rad/s] and its
    rate [rad/s^2]) of every node and the frame block, and the frame angle ``phi`` [rad]. The
    frame turns about the fixed unit axis ``a``: ``R_F = exp(phi a~)``, ``w = phi' a``; since
    ``R_F a = a`` the material angular velocity of a section is ``R0^T w``."""
    nn = beam.n_nodes
    q, v, a = beam.reference_state(), np.zeros(beam.n_dof), np.zeros(beam.n_dof)
    if pres is None:
        return q, v, a, 0.0
    ax = np.asarray(pres[:3], dtype=float)
    phi, rate, acc = motion_profile(np.asarray(pres, dtype=float), float(t))
    qf = np.array([np.cos(0.5 * phi), *(np.sin(0.5 * phi) * ax)])
    x = beam.nodes @ quaternion_to_matrix(qf).T
    w, wd = rate * ax, acc * ax
    R0t = quaternion_to_matrix(beam.quats).transpose(0, 2, 1)
    blocks, vb, ab = q.reshape(-1, 7), v.reshape(-1, 6), a.reshape(-1, 6)
    blocks[:nn, :3] = x
    blocks[:nn, 3:] = quaternion_product(qf, beam.quats)
    blocks[nn, 3:] = qf
    vb[:nn, :3] = np.cross(w, x)
    vb[:nn, 3:] = R0t @ w
    vb[nn, 3:] = w
    ab[:nn, :3] = np.cross(wd, x) + np.cross(w, np.cross(w, x))
    ab[:nn, 3:] = R0t @ wd
    ab[nn, 3:] = wd
    return q, v, a, float(phi)


def _rigid_increment(beam: ExactBeam3D, pres, q0, t0: float, t1: float) -> np.ndarray:
    """Increments (6 per block, rotations material) from the imposed state ``q0`` at ``t0`` to the
    frame's rigid motion at ``t1``: translations ``x(t1) - x(t0)``, rotations ``R0^T a dphi``."""
    d = np.zeros(beam.n_dof)
    if pres is None:
        return d
    q1, _, _, phi1 = rigid_motion(beam, pres, t1)
    phi0 = motion_profile(np.asarray(pres, dtype=float), float(t0))[0]
    ax = np.asarray(pres[:3], dtype=float) * (phi1 - phi0)
    db = d.reshape(-1, 6)
    nn = beam.n_nodes
    db[:, :3] = q1.reshape(-1, 7)[:, :3] - np.asarray(q0).reshape(-1, 7)[:, :3]
    db[:nn, 3:] = quaternion_to_matrix(beam.quats).transpose(0, 2, 1) @ ax
    db[nn, 3:] = ax
    return d


def _motion_scale(beam: ExactBeam3D, pres, t_end: float) -> float:
    """Inertia force scale [N] of the prescribed motion: mass times the largest rigid-body
    acceleration at the beam's length over the run (sampled)."""
    if pres is None:
        return 0.0
    m = float(np.sum(beam.rho_a * beam.reference_lengths()))
    ts = np.linspace(0.0, t_end, 401)
    prof = np.array([motion_profile(np.asarray(pres, dtype=float), float(t))[1:] for t in ts])
    return m * beam.length * float(np.max(np.abs(prof[:, 1]) + prof[:, 0] ** 2))


def _skew_all(v: np.ndarray) -> np.ndarray:
    """(k, 3, 3) skew matrices ``v~`` of the rows of ``v`` (k, 3)."""
    S = np.zeros((len(v), 3, 3))
    S[:, 0, 1], S[:, 0, 2], S[:, 1, 2] = -v[:, 2], v[:, 1], -v[:, 0]
    S[:, 1, 0], S[:, 2, 0], S[:, 2, 1] = v[:, 2], -v[:, 1], v[:, 0]
    return S


def _exp_jacobians(dq: np.ndarray) -> np.ndarray:
    """(nb, 3, 3) right Jacobians of the exponential map ``Jr(dTheta)`` of each block's rotation
    increment (``R exp(dTheta + d) = R exp(dTheta) exp(Jr d)``): the rotation blocks of the
    tangent operator ``T`` (identity on the translations)."""
    v = dq.reshape(-1, 6)[:, 3:]
    th = np.linalg.norm(v, axis=1)
    small = th < 1e-4
    ts = np.where(small, 1.0, th)
    c1 = np.where(small, 0.5 - th * th / 24.0, (1.0 - np.cos(ts)) / ts**2)
    c2 = np.where(small, 1.0 / 6.0 - th * th / 120.0, (ts - np.sin(ts)) / ts**3)
    S = _skew_all(v)
    return np.eye(3) - c1[:, None, None] * S + c2[:, None, None] * S @ S


def _times_tangent(K: np.ndarray, dq: np.ndarray) -> np.ndarray:
    """``K T`` (n, n) for the block-diagonal tangent operator ``T`` of :func:`_exp_jacobians`
    (only the rotation columns change: each 3-column block times its ``Jr``)."""
    nb = len(dq) // 6
    out = K.copy()
    o4 = out.reshape(len(K), nb, 6)
    o4[:, :, 3:] = np.einsum("rbk,bkl->rbl", o4[:, :, 3:], _exp_jacobians(dq))
    return out


class _Equations:
    """Residual and iteration matrix of the 3-D beam's equations of motion."""

    def __init__(self, beam: ExactBeam3D, loads: PointLoads3D, eta: float = 0.0):
        self.beam, self.loads = beam, loads
        # Kelvin-Voigt time constant [s] and the step's d velocity / d increment (set per step)
        self.eta, self.kv = float(eta), 0.0
        self.M = beam.mass_matrix()
        n = beam.n_dof
        self.rot = np.zeros(n, dtype=bool)
        self.rot.reshape(-1, 6)[:, 3:] = True
        self.fixed = np.zeros(n, dtype=bool)
        self.fixed[beam.frame_dof :] = True
        for c in beam.clamps[:, 0].astype(int):
            self.fixed[6 * c : 6 * c + 6] = True
        self.free = np.flatnonzero(~self.fixed)
        self.Jd = np.diag(self.M).copy()
        # row and column indices (nb, 3, 3) of the diagonal rotation blocks
        base = 6 * np.arange(n // 6)[:, None, None] + 3
        self.rot_r = base + np.arange(3)[None, :, None]
        self.rot_c = base + np.arange(3)[None, None, :]

    def load_factors(self, t: float) -> np.ndarray:
        ld = self.loads
        lam = np.zeros(len(ld.node) + 1)
        ek.load_factors(float(t), ld.profile, ld.par, lam)
        return lam

    def forces(self, q, t, want_k=True, v=None):
        """``f_int - f_ext`` (spatial, increment layout), its tangent and the strain energy."""
        return self.beam.residual(self.loads, q, self.load_factors(t), want_k, v, self.eta, self.kv)

    def residual(self, q, v, vd, t, want_k=True):
        """Equations of motion (n,) at state ``q``, velocities ``v`` (translations inertial,
        rotations material) and their rates ``vd``; with ``want_k`` the iteration blocks
        ``(K in section axes, C_gyro)``. Vectorised over the nodes (block views, no Python loop
        per node)."""
        r, K, _ = self.forces(q, t, want_k, v)
        n = self.beam.n_dof
        nb = n // 6
        R = quaternion_to_matrix(q.reshape(nb, 7)[:, 3:])
        W = v.reshape(nb, 6)[:, 3:]
        J = self.Jd.reshape(nb, 6)[:, 3:]
        rb = r.reshape(nb, 6)
        m = np.einsum("bji,bj->bi", R, rb[:, 3:])  # R^T m: the moments in section axes
        out = self.M @ vd
        ob = out.reshape(nb, 6)
        ob[:, :3] += rb[:, :3]
        ob[:, 3:] += np.cross(W, J * W) + m
        if not want_k:
            return out, None, None
        # gyroscopic C = W~ J - (J W)~ and G = (R^T m)~ (d(R^T m) / dTheta at fixed m: the
        # row's own turn) on the rotation blocks of the diagonal
        C = np.zeros((n, n))
        C[self.rot_r, self.rot_c] = _skew_all(W) * J[:, None, :] - _skew_all(J * W)
        # spatial rows/columns -> section axes on the rotations (rows R^T, columns R)
        A = K.copy()
        a4 = A.reshape(nb, 6, nb, 6)
        a4[:, :, :, 3:] = np.einsum("aibk,bkl->aibl", a4[:, :, :, 3:], R)
        a4[:, 3:] = np.einsum("aki,akbl->aibl", R, a4[:, 3:])
        A[self.rot_r, self.rot_c] += _skew_all(m)
        return out, A, C

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
    eta: float = 0.0,
    q0=None,
    v0=None,
    prescribed=None,
    breakpoints=(),
    tol: float = 1e-10,
    max_iter: int = 30,
    progress=None,
) -> ExactSolution:
    """Time history of a 3-D exact beam from ``q0`` (state, default the reference carried by the
    frame) and ``v0`` (6 per block: inertial translational velocity [m/s], material angular
    velocity [rad/s]; default the frame's rigid motion).

    ``prescribed``: packed :meth:`~rotaflex.floating.model.Prescribed.packed` rotation of the
    reference frame about its origin (``None``: fixed); the clamped nodes follow it exactly.
    ``breakpoints``: times [s] the steps land on (profile kinks). ``eta``: Kelvin-Voigt material
    damping time constant [s] (``2 zeta / omega`` damps the mode of frequency ``omega`` with
    ratio ``zeta``, higher modes more; its dissipation is not in the energy columns).

    Returns an :class:`~rotaflex.floating.exact_solve.ExactSolution` with ``v`` in that layout
    and the energy columns kinetic, strain, work of the loads (trapezoidal rule on the
    spatial increments), work of the clamps (reaction times the imposed increments; 0 for a
    fixed frame).

    Raises
    ------
    ConvergenceError
        Newton's iteration of a step did not converge in ``max_iter`` iterations.
    """
    t_wall = time.perf_counter()
    eq = _Equations(beam, loads, eta)
    am, af, beta, gamma = alpha_coefficients(rho_inf)
    n = beam.n_dof
    pres = None if prescribed is None else np.asarray(prescribed, dtype=float)
    fixed, free = eq.fixed, eq.free
    qr, vr, vdr, _ = rigid_motion(beam, pres, 0.0)
    q = qr if q0 is None else np.array(q0, dtype=float)
    q[np.repeat(fixed.reshape(-1, 6)[:, 0], 7)] = qr[np.repeat(fixed.reshape(-1, 6)[:, 0], 7)]
    v = vr.copy() if v0 is None else np.array(v0, dtype=float)
    v[fixed] = vr[fixed]
    # start: M vd = -(gyroscopic + internal - external), the clamps' accelerations imposed
    vd = np.zeros(n)
    vd[fixed] = vdr[fixed]
    r0, _, _ = eq.residual(q, v, vd, 0.0, want_k=False)
    vd[free] = np.linalg.solve(eq.M[np.ix_(free, free)], -r0[free])
    react0, _, _ = eq.residual(q, v, vd, 0.0, want_k=False)  # the clamps' start reaction
    a = vd.copy()
    times, is_out = time_grid(t_end, dt_out, time_step, breakpoints)
    Q, V, E = [], [], []
    work, drive, iters = 0.0, 0.0, 0
    react_prev = np.where(fixed, react0, 0.0)
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
    scale = max(
        float(np.abs(eq.M @ vd).max()),
        float(np.abs(r0).max()),
        mom,
        float(np.abs(f_full).max()),
        _motion_scale(beam, pres, t_end),
        1e-300,
    )

    def record(q, v, w, d):
        ek, u = eq.energy(q, v)
        Q.append(q.copy())
        V.append(v.copy())
        E.append((ek, u, w, d))

    record(q, v, work, drive)
    for k in range(1, len(times)):
        t1, h = times[k], times[k] - times[k - 1]
        bp = (1.0 - af) / (1.0 - am) * h * h * beta
        gp = (1.0 - af) / (1.0 - am) * h * gamma
        eq.kv = gp / bp
        _, vr1, vdr1, _ = rigid_motion(beam, pres, t1)
        vd1 = np.where(fixed, vdr1, 0.0)
        a1 = (af * vd - am * a) / (1.0 - am)
        v1 = v + h * (1.0 - gamma) * a + h * gamma * a1
        dq = h * v + h * h * (0.5 - beta) * a + h * h * beta * a1
        # the eliminated DOFs: imposed from the frame's motion
        dq[fixed] = _rigid_increment(beam, pres, q, times[k - 1], t1)[fixed]
        v1[fixed] = vr1[fixed]
        q1 = q.copy()
        step = np.inf
        for it in range(1, max_iter + 1):
            ek3.advance_material(q1, q, dq)
            # the residual alone first: the tangent (central differences, most of the cost) only
            # when another iteration follows
            r, _, _ = eq.residual(q1, v1, vd1, t1, want_k=False)
            res = float(np.abs(r[free]).max())
            # converged: the residual at its tolerance, or the last correction of the positions
            # at round-off level (the stiff axial forces' floor)
            if it > 1 and (res <= tol * scale or step <= 1e-13 * beam.length):
                break
            _, K, C = eq.residual(q1, v1, vd1, t1)
            A = eq.M + gp * C + bp * _times_tangent(K, dq)
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
        # work of the clamps: their reaction (the eliminated rows' residual; rotations in
        # section axes, as the material increments) on the imposed increments
        react = np.where(fixed, r, 0.0)
        drive += 0.5 * (react_prev + react) @ dq
        react_prev = react
        q, v, vd, a = q1, v1, vd1, a1
        if is_out[k]:
            record(q, v, work, drive)
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
