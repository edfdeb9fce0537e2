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
from dataclasses import dataclass, field

import numpy as np

from rotaflex.core.errors import ConvergenceError, InputError
from rotaflex.floating import exact_kernels as ek
from rotaflex.floating import exact_kernels3d as ek3
from rotaflex.floating import exact_step3d
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
    rate [rad/s^2]) of every node and the frame block, and the frame angle ``phi`` [rad]
    (:func:`frame_state`)."""
    if pres is None:
        return beam.reference_state(), np.zeros(beam.n_dof), np.zeros(beam.n_dof), 0.0
    phi, rate, acc = motion_profile(np.asarray(pres, dtype=float), float(t))
    q, v, a = frame_state(beam, np.asarray(pres[:3], dtype=float), phi, rate, acc)
    return q, v, a, float(phi)


def frame_state(beam: ExactBeam3D, ax, phi: float, rate: float, acc: float):
    """The reference body turned rigidly by ``phi`` [rad] about the fixed unit axis ``ax``
    through the origin, turning at ``rate`` [rad/s] with ``acc`` [rad/s^2]: state ``q``,
    velocities and accelerations (layout of :func:`rigid_motion`). ``R_F = exp(phi a~)``,
    ``w = phi' a``; since ``R_F a = a`` the material angular velocity of a section is ``R0^T w``."""
    nn = beam.n_nodes
    q, v, a = beam.reference_state(), np.zeros(beam.n_dof), np.zeros(beam.n_dof)
    qf = np.array([np.cos(0.5 * phi), *(np.sin(0.5 * phi) * ax)])
    # a x r = r A^T with A = a~ (matrix products: np.cross costs more than the rest here)
    A = _skew_all(np.asarray(ax, dtype=float)[None])[0]
    x = beam.nodes @ quaternion_to_matrix(qf).T
    ax_x = x @ A.T
    R0t_a = np.einsum("bji,j->bi", _section_matrices(beam), ax)
    blocks, vb, ab = q.reshape(-1, 7), v.reshape(-1, 6), a.reshape(-1, 6)
    blocks[:nn, :3] = x
    blocks[:nn, 3:] = quaternion_product(qf, beam.quats)
    blocks[nn, 3:] = qf
    vb[:nn, :3] = rate * ax_x
    vb[:nn, 3:] = rate * R0t_a
    vb[nn, 3:] = rate * ax
    ab[:nn, :3] = acc * ax_x + rate * rate * (ax_x @ A.T)
    ab[:nn, 3:] = acc * R0t_a
    ab[nn, 3:] = acc * ax
    return q, v, a


def _turn_increment(beam: ExactBeam3D, ax, q0, phi0: float, phi1: float, q1=None) -> np.ndarray:
    """Increments (6 per block, rotations material) from the rigid state ``q0`` at frame angle
    ``phi0`` to the one at ``phi1`` [rad] about the unit axis ``ax`` (``q1``, if given, its
    state): translations ``x(phi1) - x(phi0)``, rotations ``R0^T a dphi``."""
    d = np.zeros(beam.n_dof)
    if q1 is None:
        q1 = frame_state(beam, ax, phi1, 0.0, 0.0)[0]
    db = d.reshape(-1, 6)
    nn = beam.n_nodes
    turn = np.asarray(ax, dtype=float) * (phi1 - phi0)
    db[:, :3] = q1.reshape(-1, 7)[:, :3] - np.asarray(q0).reshape(-1, 7)[:, :3]
    db[:nn, 3:] = np.einsum("bji,j->bi", _section_matrices(beam), turn)
    db[nn, 3:] = turn
    return d


def _section_matrices(beam: ExactBeam3D) -> np.ndarray:
    """(nn, 3, 3) rotation matrices of the reference sections, computed once per body (the
    frozen dataclass's ``__dict__`` holds them; they were computed twice per step)."""
    cache = beam.__dict__
    if "_r0_cache" not in cache:
        cache["_r0_cache"] = quaternion_to_matrix(beam.quats)
    return cache["_r0_cache"]


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
        gam0, kap0 = beam._ref
        self.beam_args = (beam.conn, beam._lengths, gam0, kap0, beam.stiffness)
        # the compiled path's tangent (filled and turned in place at every iteration)
        self.work_k, self.no_k = np.zeros((n, n)), np.zeros((1, 1))

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

    def step_equations(self, q1, v1, vd1, dq, t, gp, bp, want_k, kernel=True, rows=None):
        """Residual (n,), its largest value on the free DOFs and, with ``want_k``, the
        iteration matrix ``M + gp C + bp K T`` of a step with the increments ``dq`` on the DOFs
        ``rows`` (default all): the element and load kernels, then
        :func:`rotaflex.floating.exact_step3d.dynamic_residual` and ``iteration_matrix``
        (``kernel``), or :meth:`residual` and :func:`_times_tangent` in numpy."""
        rows = np.arange(len(dq)) if rows is None else rows
        if not kernel:
            r, K, C = self.residual(q1, v1, vd1, t, want_k)
            res = float(np.abs(r[self.free]).max(initial=0.0))
            if not want_k:
                return r, res, None
            return r, res, (self.M + gp * C + bp * _times_tangent(K, dq))[np.ix_(rows, rows)]
        n = len(dq)
        ld, (conn, L0, gam0, kap0, stiff) = self.loads, self.beam_args
        f, fe, K = np.zeros(n), np.zeros(n), self.work_k if want_k else self.no_k
        ek3.internal(q1, v1, conn, L0, gam0, kap0, stiff, self.eta, self.kv, f, K, int(want_k))
        lam = self.load_factors(t)
        ek3.external(q1, lam, ld.node, ld.kind, ld.frame, ld.amp, self.beam.n_nodes, ld.dist, fe, K, bool(want_k))
        r, m = np.zeros(n), np.zeros((n // 6, 3))
        res = exact_step3d.dynamic_residual(q1, v1, vd1, self.M, self.Jd, f, fe, self.free, r, m)
        if not want_k:
            return r, res, None
        A = np.empty((len(rows), len(rows)))
        exact_step3d.iteration_matrix(q1, v1, dq, self.M, self.Jd, K, m, float(gp), float(bp), rows, A)
        return r, res, A

    def energy(self, q, v):
        """Kinetic and strain energy [J]."""
        _, _, u = self.forces(q, 0.0, want_k=False)
        return 0.5 * v @ self.M @ v, u


def _force_scale(eq: _Equations, q, v, vd, r0, time_step: float, extra: float) -> float:
    """Force scale [N] of Newton's tolerance: the larger of the start's forces (``r0``, the
    residual at zero acceleration, and ``M vd``), momentum / step, the loads at full value (for
    a start from rest) and ``extra`` (the drive's inertia forces)."""
    ld = eq.loads
    f_full = np.zeros(eq.beam.n_dof)
    lam = np.ones(len(ld.node) + 1)
    ek3.external(q, lam, ld.node, ld.kind, ld.frame, ld.amp, eq.beam.n_nodes, ld.dist, f_full, np.zeros((1, 1)), False)
    mom = float(np.abs(eq.M @ v).max()) / time_step
    return max(float(np.abs(eq.M @ vd).max()), float(np.abs(r0).max()), mom, float(np.abs(f_full).max()), extra, 1e-300)


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
    kernel: bool = True,
) -> ExactSolution:
    """Time history of a 3-D exact beam from ``q0`` (state, default the reference carried by the
    frame) and ``v0`` (6 per block: inertial translational velocity [m/s], material angular
    velocity [rad/s]; default the frame's rigid motion).

    ``prescribed``: packed :meth:`~rotaflex.floating.model.Prescribed.packed` rotation of the
    reference frame about its origin (``None``: fixed); the clamped nodes follow it exactly.
    ``breakpoints``: times [s] the steps land on (profile kinks). ``eta``: Kelvin-Voigt material
    damping time constant [s] (``2 zeta / omega`` damps the mode of frequency ``omega`` with
    ratio ``zeta``, higher modes more; its dissipation is not in the energy columns).
    ``kernel``: the residual and iteration matrix of Newton's iteration (:func:`_newton`)
    compiled (:mod:`rotaflex.floating.exact_step3d`); ``False`` computes them in numpy
    (:meth:`_Equations.residual`: the reference the tests compare with; about three times
    slower).

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
    qr, vr, vdr, phi0 = rigid_motion(beam, pres, 0.0)
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
    scale = _force_scale(eq, q, v, vd, r0, time_step, _motion_scale(beam, pres, t_end))

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
        qr1, vr1, vdr1, phi1 = rigid_motion(beam, pres, t1)
        vd1 = np.where(fixed, vdr1, 0.0)
        a1 = (af * vd - am * a) / (1.0 - am)
        v1 = v + h * (1.0 - gamma) * a + h * gamma * a1
        dq = h * v + h * h * (0.5 - beta) * a + h * h * beta * a1
        # the eliminated DOFs: imposed from the frame's motion
        dq[fixed] = 0.0 if pres is None else _turn_increment(beam, pres[:3], q, phi0, phi1, qr1)[fixed]
        phi0 = phi1
        v1[fixed] = vr1[fixed]
        q1 = q.copy()
        tols = (tol * scale, 1e-13 * beam.length)
        ok, it, res, r = _newton(eq, q, q1, dq, v1, vd1, a1, t1, (gp, bp, am, af), tols, max_iter, kernel)
        if not ok:
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


def _newton(eq: _Equations, q, q1, dq, v1, vd1, a1, t1, alpha, tols, max_iter, kernel):
    """Newton's iteration of one step from the predictor ``dq, v1, vd1, a1`` (the eliminated
    DOFs imposed), all updated in place, ``q1 = q (+) dq``; ``alpha``: ``(gamma', beta',
    alpha_m, alpha_f)``, ``tols``: force [N] and position step [m] tolerances, ``kernel``: the
    equations compiled or in numpy (:meth:`_Equations.step_equations`). Returns ``(converged,
    iterations, residual, r)``, ``r`` the last residual (its eliminated rows: the clamps'
    reaction)."""
    gp, bp, am, af = alpha
    free = eq.free
    step = np.inf
    for it in range(1, max_iter + 1):
        ek3.advance_material(q1, q, dq)
        # the residual alone first: the tangent only when another iteration follows
        r, res, _ = eq.step_equations(q1, v1, vd1, dq, t1, gp, bp, False, kernel)
        # converged: the residual at its tolerance, or the last correction of the positions
        # at round-off level (the stiff axial forces' floor)
        if it > 1 and (res <= tols[0] or step <= tols[1]):
            return True, it, res, r
        A = eq.step_equations(q1, v1, vd1, dq, t1, gp, bp, True, kernel, free)[2]
        d = np.linalg.solve(A, -r[free])
        vd1[free] += d
        a1[free] += (1.0 - af) / (1.0 - am) * d
        v1[free] += gp * d
        dq[free] += bp * d
        step = bp * float(np.abs(d).max())
    return False, max_iter, res, r


def _external(eq: _Equations, q, t) -> np.ndarray:
    ld = eq.loads
    f, K = np.zeros(eq.beam.n_dof), np.zeros((1, 1))
    ek3.external(q, eq.load_factors(t), ld.node, ld.kind, ld.frame, ld.amp, eq.beam.n_nodes, ld.dist, f, K, False)
    return f


@dataclass(frozen=True)
class HubDrive:
    """A rigid hub on a bearing: it turns about the fixed unit ``axis`` through the origin (one
    DOF, the angle ``phi``), with ``inertia`` [kg m^2] about that axis, driven by the torques
    ``torque`` [N m] (about the axis) times their time profiles (``profile``, ``par``: the
    layout of :func:`rotaflex.floating.exact_kernels.load_factors`). The bearing carries every
    other force and moment (no work: the axis and the origin are fixed)."""

    axis: np.ndarray
    inertia: float
    torque: np.ndarray = field(default_factory=lambda: np.zeros(0))
    profile: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    par: np.ndarray = field(default_factory=lambda: np.zeros((0, 4)))

    def __post_init__(self):
        if not (np.isfinite(self.inertia) and self.inertia > 0):
            raise InputError("body.hub.inertia", self.inertia, "a moment of inertia > 0 about the slew axis [kg m^2]")

    def torque_at(self, t: float) -> float:
        """Torque about the axis [N m] at ``t`` [s]."""
        lam = np.zeros(len(self.torque) + 1)
        ek.load_factors(float(t), np.asarray(self.profile, dtype=np.int64), np.asarray(self.par, dtype=float), lam)
        return float(np.asarray(self.torque, dtype=float) @ lam[:-1])


@dataclass
class HubSolution(ExactSolution):
    """:class:`~rotaflex.floating.exact_solve.ExactSolution` of a free hub, plus ``hub`` (T, 3):
    hub angle [rad] (unwrapped), rate [rad/s] and the applied torque about the axis [N m]."""

    hub: np.ndarray | None = None


def _reduced(A: np.ndarray, free: np.ndarray, B: np.ndarray) -> np.ndarray:
    """``P^T A P`` (nf + 1, nf + 1) for the map ``P`` from the unknowns (free increments, hub
    angle) to all increments: the identity on the free DOFs, ``B`` (the clamped blocks'
    increments per unit hub angle, zero on the free DOFs) last."""
    nf = len(free)
    out = np.empty((nf + 1, nf + 1))
    AB = A @ B
    out[:nf, :nf] = A[np.ix_(free, free)]
    out[:nf, nf] = AB[free]
    out[nf, :nf] = B @ A[:, free]
    out[nf, nf] = B @ AB
    return out


def simulate_hub3d(
    beam: ExactBeam3D,
    loads: PointLoads3D,
    hub: HubDrive,
    *,
    t_end: float,
    dt_out: float,
    time_step: float,
    rho_inf: float = 1.0,
    breakpoints=(),
    tol: float = 1e-10,
    max_iter: int = 30,
    progress=None,
    kernel: bool = True,
) -> HubSolution:
    """Time history of a 3-D exact beam clamped to a free hub turning about a fixed axis
    (:class:`HubDrive`), from rest in the reference state.

    The unknowns of each Lie-group generalized-alpha step (:func:`simulate_exact3d`) are the
    free nodes' accelerations and the hub's angular acceleration ``phi''`` (its angle and rate
    follow the same recursions); the clamped blocks are the frame's rigid motion at the
    current ``phi, phi', phi''`` (:func:`frame_state`). The hub's equation is the virtual work
    of a hub rotation ``d phi``::

        J phi'' + B^T r_c - tau(t) = 0,

    ``B`` the clamped blocks' increments per unit ``d phi`` (``a x x`` on the translations,
    ``R0^T a`` on the material rotations) and ``r_c`` the clamped rows' residual (the force the
    hub applies to the beam). Newton's matrix is ``P^T (M + gamma' C + beta' K T) P + J`` with
    ``P`` the map of :func:`_reduced` (a quasi-Newton matrix: the turn of ``B`` and of the
    centripetal accelerations with ``phi`` and ``phi'`` left out; adding them changed the
    iteration count by < 0.1 % in a 720 deg slew at 25 rad/s).

    At a breakpoint the step ending there sees the loads' left limit and the next starts from
    accelerations re-solved with their right limit (so a piecewise-constant torque's impulse
    and work are integrated exactly). Energy columns: kinetic (hub included), strain, work of
    the loads and the hub torque (trapezoidal rule on the increments), 0 (the bearing does
    no work). ``kernel``: as :func:`simulate_exact3d`.

    Raises
    ------
    ConvergenceError
        Newton's iteration of a step did not converge in ``max_iter`` iterations.
    """
    t_wall = time.perf_counter()
    eq = _Equations(beam, loads)
    am, af, beta, gamma = alpha_coefficients(rho_inf)
    n, ax, J = beam.n_dof, np.asarray(hub.axis, dtype=float), float(hub.inertia)
    fixed, free = eq.fixed, eq.free
    nf = len(free)

    def clamped(phi, rate, acc):
        """Clamped blocks' state, velocity, acceleration and ``B`` at the hub's motion (the
        rigid motion is linear in the rate's square and the acceleration)."""
        qs, B, cen = frame_state(beam, ax, phi, 1.0, 0.0)
        B, cen = np.where(fixed, B, 0.0), np.where(fixed, cen, 0.0)
        return qs, rate * B, acc * B + rate * rate * cen, B

    def accelerations(q, v, phi, rate, t):
        """Free accelerations and ``phi''`` from the equations at ``(q, v)`` (linear in them)."""
        _, _, acs, B = clamped(phi, rate, 0.0)
        vd = np.where(fixed, acs, 0.0)  # the centripetal part of the clamped accelerations
        r0 = eq.residual(q, v, vd, t, want_k=False)[0]
        A = _reduced(eq.M, free, B)
        A[-1, -1] += J
        z = np.linalg.solve(A, -np.concatenate([r0[free], [B @ r0 - hub.torque_at(t)]]))
        vd[free] += z[:-1]
        return vd + B * z[-1], float(z[-1]), r0

    q, v, _ = frame_state(beam, ax, 0.0, 0.0, 0.0)
    ph, pw = 0.0, 0.0
    vd, pd, r0 = accelerations(q, v, ph, pw, 0.0)
    a, pa = vd.copy(), pd
    times, is_out = time_grid(t_end, dt_out, time_step, breakpoints)
    breaks = np.asarray(breakpoints, dtype=float)
    tau_max = float(np.max(np.abs(np.asarray(hub.torque, dtype=float)), initial=0.0))
    lscale = max(beam.length, 1.0)
    scale = _force_scale(eq, q, v, vd, r0, time_step, tau_max / lscale)
    Q, V, E, H = [], [], [], []
    work, iters = 0.0, 0
    fe_prev, tau_prev = _external(eq, q, 0.0), hub.torque_at(0.0)

    def record(q, v, w, t):
        k_beam, u = eq.energy(q, v)
        Q.append(q.copy())
        V.append(v.copy())
        E.append((k_beam + 0.5 * J * pw * pw, u, w, 0.0))
        H.append((ph, pw, hub.torque_at(t)))

    record(q, v, work, 0.0)
    c = (1.0 - af) / (1.0 - am)
    for k in range(1, len(times)):
        t1, h = times[k], times[k] - times[k - 1]
        at_break = bool(np.any(np.abs(breaks - t1) <= 1e-12 * max(t1, 1.0)))
        te = t1 - 1e-9 * h if at_break else t1  # a breakpoint's left limit
        bp, gp = c * h * h * beta, c * h * gamma
        a1 = (af * vd - am * a) / (1.0 - am)
        v1 = v + h * (1.0 - gamma) * a + h * gamma * a1
        dq = h * v + h * h * (0.5 - beta) * a + h * h * beta * a1
        vd1 = np.zeros(n)
        pa1 = (af * pd - am * pa) / (1.0 - am)
        pw1 = pw + h * (1.0 - gamma) * pa + h * gamma * pa1
        dphi = h * pw + h * h * (0.5 - beta) * pa + h * h * beta * pa1
        pd1 = 0.0
        q1 = q.copy()
        step = np.inf
        for it in range(1, max_iter + 1):
            qc, vc, acs, B = clamped(ph + dphi, pw1, pd1)
            dq[fixed] = _turn_increment(beam, ax, q, ph, ph + dphi, qc)[fixed]
            v1[fixed], vd1[fixed] = vc[fixed], acs[fixed]
            ek3.advance_material(q1, q, dq)
            r, res, _ = eq.step_equations(q1, v1, vd1, dq, te, gp, bp, False, kernel)
            rh = J * pd1 + B @ r - hub.torque_at(te)
            res = max(res, abs(rh) / lscale)
            if it > 1 and (res <= tol * scale or step <= 1e-13 * beam.length):
                break
            A = _reduced(eq.step_equations(q1, v1, vd1, dq, te, gp, bp, True, kernel)[2], free, B)
            A[-1, -1] += J
            d = np.linalg.solve(A, -np.concatenate([r[free], [rh]]))
            vd1[free] += d[:nf]
            a1[free] += c * d[:nf]
            v1[free] += gp * d[:nf]
            dq[free] += bp * d[:nf]
            pd1 += d[-1]
            pa1 += c * d[-1]
            pw1 += gp * d[-1]
            dphi += bp * d[-1]
            step = bp * max(float(np.abs(d[:nf]).max(initial=0.0)), abs(d[-1]) * beam.length)
        else:
            raise ConvergenceError("generalized-alpha step (free hub)", float(t1), res, tol * scale)
        iters += it
        # work of the loads (spatial increments, as simulate_exact3d) and of the hub torque
        fe = _external(eq, q1, te)
        R = quaternion_to_matrix(q.reshape(-1, 7)[:, 3:])
        ds = dq.reshape(-1, 6).copy()
        ds[:, 3:] = np.einsum("bij,bj->bi", R, ds[:, 3:])
        tau = hub.torque_at(te)
        work += 0.5 * (fe_prev + fe) @ ds.ravel() + 0.5 * (tau_prev + tau) * dphi
        q, v, vd, a = q1, v1, vd1, a1
        ph, pw, pd, pa = ph + dphi, pw1, pd1, pa1
        fe_prev, tau_prev = fe, tau
        if at_break:  # restart from the right limit: the loads' jump enters the accelerations
            tr = t1 + 1e-9 * h
            vd, pd, _ = accelerations(q, v, ph, pw, tr)
            a, pa = vd.copy(), pd
            fe_prev, tau_prev = _external(eq, q, tr), hub.torque_at(tr)
        if is_out[k]:
            record(q, v, work, t1)
            if progress is not None:
                progress(float(t1))
    return HubSolution(
        time=times[is_out],
        q=np.array(Q),
        v=np.array(V),
        energy=np.array(E),
        message=f"Lie-group generalized-alpha, free hub: {len(times) - 1} steps, {iters} Newton iterations",
        nstep=len(times) - 1,
        niter=iters,
        wall_time=time.perf_counter() - t_wall,
        method="exact",
        hub=np.array(H),
    )
