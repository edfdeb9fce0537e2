"""Time response: constant speed or run-up, unbalance, and a plug-in nonlinear force.

Equation of motion with a spin speed Omega(t) = Omega_0 + alpha t and spin angle
phi(t) = Omega_0 t + alpha t^2 / 2:

    M q'' + (C(Omega) + Omega G) q' + (K(Omega) + alpha Kst) q = f_u(t) + f_nl(t, q, q')

with the unbalance force f_x = u (Omega^2 cos(phi + b) + alpha sin(phi + b)),
f_y = u (Omega^2 sin(phi + b) - alpha cos(phi + b)) and ``Kst`` the spin-acceleration
coupling of the disks and shaft (from the Ip (Omega + theta_x' theta_y) kinetic energy).

``method="direct"`` integrates all DOFs with the Newmark average-acceleration rule (implicit,
unconditionally stable: the shaft's high modes make the full system stiff), ``steps_per_output``
steps per output interval; a nonlinear force is converged by fixed-point iteration in each step.
Elements with added mass (liquid seals) enter M at the mid speed Omega_mid of the run.
``method="modal"`` projects on the lowest undamped modes of (K(Omega_mid), M), which removes the
stiff modes, and integrates with the adaptive DOP853 scheme.

Large-rotation disks (``large_rotation``): ``large_rotation_model="euler_123"`` adds the exact
1-2-3 tilt terms of :class:`~rotaflex.rotor.fe.elements.large_disk.LargeRotationDisk` to the
node's DOFs (singular at theta_y = +-90 deg: the integration stops with a SingularityError at
|theta_y| > 89 deg); ``"quaternion"`` carries each disk as a rigid body with quaternion attitude
and body rates (:class:`~rotaflex.rotor.fe.elements.quaternion_disk.QuaternionDisk`), joined
to the node by a bending hub spring, integrated together with the modal coordinates (the
quaternion is not renormalised in the state; it is normalised where the attitude is used and
its norm drift is returned). The quaternion disk needs a constant speed (its spin is free,
the joint transmits no torque about the disk axis) and the modal method.

The linear part is written once for rotors and machines: :class:`Pencil` (the matrices over a
speed grid, unbalance groups each at its own signed speed ratio), :class:`Linear` (basis,
reduced matrices, right-hand side, integration) and :func:`linear_transient`; :func:`transient`
builds the rotor's pencil and adds the large-rotation disks to the right-hand side, and
:func:`rotaflex.system.transient.machine_transient` builds a machine's.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np
import scipy.linalg as sla

from rotaflex.core.errors import ConvergenceError, InputError, SingularityError
from rotaflex.core.limits import require
from rotaflex.rotor.fe.elements.large_disk import LargeRotationDisk
from rotaflex.rotor.fe.elements.quaternion_disk import QuaternionDisk
from rotaflex.rotor.fe.model import NDOF_NODE, Rotor
from rotaflex.rotor.fe.response import unbalance_force

log = logging.getLogger(__name__)

Force = Callable[[float, np.ndarray, np.ndarray], np.ndarray]


@dataclass(frozen=True)
class TransientData:
    """Time history of all DOFs.

    Attributes
    ----------
    time : ndarray (t,) [s]
    q, v : ndarray (t, n_dof) [m, rad], [m/s, rad/s]
    speed : ndarray (t,) [rad/s]
    nfev : int
    wall_time : float [s]
    message : str
    quaternion : ndarray (t, n_disk, 4) or None
        Attitudes of the quaternion disks (as integrated, not renormalised).
    omega : ndarray (t, n_disk, 3) or None
        Their body angular velocities [rad/s].
    disks : tuple of QuaternionDisk
        The quaternion disks, in the order of the second axis above.
    """

    time: np.ndarray
    q: np.ndarray
    v: np.ndarray
    speed: np.ndarray
    nfev: int
    wall_time: float
    message: str
    quaternion: np.ndarray | None = None
    omega: np.ndarray | None = None
    disks: tuple = ()

    @property
    def quaternion_norm_drift(self) -> float:
        """max | |e| - 1 | over the history and the quaternion disks (0 without any)."""
        if self.quaternion is None or self.quaternion.size == 0:
            return 0.0
        return float(np.max(np.abs(np.linalg.norm(self.quaternion, axis=-1) - 1.0)))


def speed_grid(rotor: Rotor, lo: float, hi: float, scale: float = 1.0) -> np.ndarray:
    """Speeds in [lo, hi] [rad/s] at which the pencil is evaluated: the ends and every breakpoint
    of the bearings' speed tables (a table's speed divided by ``scale``: a machine's rotor turns
    at ``scale`` times the drive speed), so that linear interpolation reproduces linear tables."""
    pts = [lo, hi]
    for _, _, el in rotor.bearings:
        if el.speeds is not None:
            pts += [s / scale for s in el.speeds if lo < s / scale < hi]
    return np.unique(pts)


@dataclass(frozen=True)
class Pencil:
    """Linear equations of motion on n coordinates at the drive speed W(t) = W0 + alpha t and
    drive angle phi(t) = W0 t + alpha t^2 / 2:

        M q'' + (C(W) + W G) q' + (K(W) + alpha Kst) q = sum_g Re[F_g (f_g^2 W^2 - i f_g alpha) e^{i f_g phi}]

    where the g-th unbalance group turns at ``f_g`` times the drive speed (a rotor, or several at
    one signed speed ratio). K(W), C(W) are linear between the ``speeds`` of their table (the
    run's speeds lie within them): bearings at the instantaneous speed, exact for linear speed
    tables.

    Attributes
    ----------
    M : ndarray (n, n) [kg]
        Constant mass (elements with added mass at the mid speed of the run).
    speeds : ndarray (s,) [rad/s]
        Drive speeds of the K, C table (one: speed-independent).
    K, C : ndarray (s, n, n) [N/m, N s/m]
    G : ndarray (n, n) [N s/m per rad/s]
        Gyroscopic matrix per unit drive speed.
    Kst : ndarray (n, n) [N/m per rad/s^2]
        Spin-acceleration coupling per unit drive acceleration.
    F : ndarray (n, g) complex [kg m]
        Unbalance phasors (x row ``u e^{i b}``, y row ``-i u e^{i b}``) per group.
    factor : ndarray (g,)
        Signed speed of each group per unit drive speed.
    K_basis, M_basis : callable () -> ndarray (n, n), ndarray (n, n)
        Stiffness (evaluated only by the modal method) and mass of the undamped modal basis.
    """

    M: np.ndarray
    speeds: np.ndarray
    K: np.ndarray
    C: np.ndarray
    G: np.ndarray
    Kst: np.ndarray
    F: np.ndarray
    factor: np.ndarray
    K_basis: Callable[[], np.ndarray]
    M_basis: np.ndarray


#: right-hand sides DOP853 spends per radian of the highest mode it integrates (measured: 9.4)
RHS_PER_RADIAN = 9.0
#: most right-hand sides a modal run may need (~10 min at 60 us each)
MAX_RHS = 1e7


class Linear:
    """A :class:`Pencil` on the basis T (``"modal"``: the lowest ``n_modes`` undamped modes of
    (K_basis, M_basis); ``"direct"``: all coordinates): the reduced matrices, the interpolated
    pencil ``mats(t)``, the load ``load(t, W, x, v)`` (unbalance groups plus the optional
    ``force(t, q, v)`` on the full coordinates), the right-hand side ``rhs(t, z)``, the initial
    state ``start(q0, v0)`` and :meth:`integrate`."""

    def __init__(self, p: Pencil, method: str, n_modes: int, speed_start: float, alpha: float, force=None):
        n = p.M.shape[0]
        if method == "modal":
            Kmid = p.K_basis()
            k = min(n_modes, n)
            w2, Phi = sla.eigh(0.5 * (Kmid + Kmid.T), p.M_basis, subset_by_index=(0, k - 1))
            T = Phi
            self.w_max = float(np.sqrt(max(w2.max(), 0.0)))  # [rad/s], sets DOP853's step
        elif method == "direct":
            T = np.eye(n)
        else:
            raise InputError("transient.method", method, "'modal' or 'direct'")
        self.p, self.T, self.m, self.method, self.n_modes = p, T, T.shape[1], method, n_modes
        self.speed_start, self.alpha, self.force = speed_start, alpha, force
        self.Mr = T.T @ p.M @ T
        self.Mi = sla.inv(self.Mr)
        self.Gr, self.Kstr = T.T @ p.G @ T, T.T @ p.Kst @ T
        self.Kr = np.einsum("ia,sij,jb->sab", T, p.K, T)
        self.Cr = np.einsum("ia,sij,jb->sab", T, p.C, T)
        self.Fr = [T.T @ p.F[:, g] for g in range(p.F.shape[1])]
        self.mats, self.load, self.rhs = self._closures()

    def _closures(self):
        """``mats(t)``: (W [rad/s], K + alpha Kst, C + W G) on the basis at time t [s];
        ``load(t, W, x, v)``: unbalance plus the extra force on the basis; ``rhs(t, z)``: the
        first-order right-hand side of the linear equations (state [x, v] on the basis).
        Closures over local names: the integrator calls them ~1e4-1e5 times a run."""
        speed_start, alpha, m, grid = self.speed_start, self.alpha, self.m, self.p.speeds
        Kr, Cr, Kstr, Gr, Mi, T, force = self.Kr, self.Cr, self.Kstr, self.Gr, self.Mi, self.T, self.force
        groups = [(float(fac), Fr) for fac, Fr in zip(self.p.factor, self.Fr, strict=True)]
        last = grid.size - 2

        def mats(t):
            w = speed_start + alpha * t
            if last < 0:
                K, C = Kr[0], Cr[0]
            else:
                j = min(max(int(grid.searchsorted(w)) - 1, 0), last)  # np.clip of a scalar: 18 us a call
                s = (w - grid[j]) / (grid[j + 1] - grid[j])
                K, C = Kr[j] + s * (Kr[j + 1] - Kr[j]), Cr[j] + s * (Cr[j + 1] - Cr[j])
            return w, K + alpha * Kstr, C + w * Gr

        def load(t, w, x, v):
            phi = speed_start * t + 0.5 * alpha * t * t
            f = None
            for fac, Fr in groups:  # each group at its own signed speed and angle
                wr, ar = fac * w, fac * alpha
                fg = (Fr * (wr * wr - 1j * ar) * np.exp(1j * (fac * phi))).real
                f = fg if f is None else f + fg
            if f is None:
                f = np.zeros(m)
            if force is not None:
                f = f + T.T @ force(t, T @ x, T @ v)
            return f

        if len(groups) == 1 and force is None:  # one rotor's unbalance: the same force inline
            (fac, Fr), half = groups[0], 0.5 * alpha

            def rhs(t, z):
                w, K, D = mats(t)
                x, v = z[:m], z[m : 2 * m]
                wr = fac * w
                f = (Fr * (wr * wr - 1j * (fac * alpha)) * np.exp(1j * (fac * (speed_start * t + half * t * t)))).real
                return np.concatenate([v, Mi @ (f - D @ v - K @ x)])

        else:

            def rhs(t, z):
                w, K, D = mats(t)
                x, v = z[:m], z[m : 2 * m]
                f = load(t, w, x, v)
                return np.concatenate([v, Mi @ (f - D @ v - K @ x)])

        return mats, load, rhs

    def start(self, q0, v0):
        """Basis coordinates of the initial state (n,) in the basis' own mass metric."""
        T, Mb = self.T, self.p.M_basis
        Pb = sla.solve(T.T @ Mb @ T, T.T @ Mb)
        return Pb @ q0, Pb @ v0

    def integrate(self, rhs, z0, t_end, *, n_output, rtol, atol, steps_per_output, nonlinear, t0, progress):
        """Integrate ``rhs`` from ``z0`` (basis coordinates first, then any extra state):
        Newmark (direct) or DOP853 (modal). Returns (TransientData on the n coordinates, the
        extra state (t, k) or None)."""
        m, T, method = self.m, self.T, self.method
        t_eval = np.linspace(0.0, t_end, n_output)
        if method == "direct":
            return _newmark(
                self.mats, rhs, self.p.M, self.Mi, z0, t_eval, steps_per_output, nonlinear, rtol, t0, progress
            ), None
        # an explicit step must resolve the basis' highest mode: DOP853 took 9.4 right-hand
        # sides per radian of it (a 4-element shaft of negligible mass: 6.0e6 rad/s)
        evals = RHS_PER_RADIAN * self.w_max * t_end
        require(
            "transient.n_modes",
            self.n_modes,
            evals,
            MAX_RHS,
            "right-hand sides of the explicit integrator",
            f"its basis keeps a mode at {self.w_max / (2 * np.pi):.4g} Hz: fewer modes, or method = 'direct' "
            "(implicit, any step)",
        )
        from scipy.integrate import solve_ivp  # here: importing it costs every rotor verb ~0.15 s

        f = rhs if progress is None else _reporting(rhs, t_end, progress)
        sol = solve_ivp(f, (0.0, t_end), z0, method="DOP853", t_eval=t_eval, rtol=rtol, atol=atol)
        if not sol.success:
            tt = float(sol.t[-1]) if sol.t.size else 0.0
            raise ConvergenceError(f"time integration ({method}): {sol.message}", tt, float("nan"), rtol)
        q = (T @ sol.y[:m]).T
        v = (T @ sol.y[m : 2 * m]).T
        log.info("transient %s: %d rhs evaluations", method, sol.nfev)
        data = TransientData(
            sol.t,
            q,
            v,
            self.speed_start + self.alpha * sol.t,
            int(sol.nfev),
            time.perf_counter() - t0,
            f"{method}: {sol.message}",
        )
        return data, sol.y[2 * m :].T


def linear_transient(
    p: Pencil,
    t_end: float,
    *,
    speed_start: float,
    speed_end: float,
    method: str = "modal",
    n_modes: int = 20,
    q0=None,
    v0=None,
    force: Force | None = None,
    n_output: int = 2001,
    rtol: float = 1e-7,
    atol: float = 1e-12,
    steps_per_output: int = 4,
    progress: Callable[[float, float], None] | None = None,
) -> TransientData:
    """Integrate the linear equations of ``p`` (:class:`Pencil`) from 0 to ``t_end`` [s]; the
    drive speed goes linearly from ``speed_start`` to ``speed_end`` [rad/s]. ``method``,
    ``n_modes``, ``force``, ``progress`` and the tolerances as :func:`transient` takes them;
    ``q0``, ``v0`` (n,) on the pencil's coordinates. This is the integration of
    ``rotaflex rotor transient`` (without large-rotation disks) and of ``rotaflex system transient``.
    """
    t0 = time.perf_counter()
    alpha = (speed_end - speed_start) / t_end
    n = p.M.shape[0]
    lin = Linear(p, method, n_modes, speed_start, alpha, force)
    q0 = np.zeros(n) if q0 is None else np.asarray(q0, float)
    v0 = np.zeros(n) if v0 is None else np.asarray(v0, float)
    z0 = np.concatenate(lin.start(q0, v0))
    data, _ = lin.integrate(
        lin.rhs,
        z0,
        t_end,
        n_output=n_output,
        rtol=rtol,
        atol=atol,
        steps_per_output=steps_per_output,
        nonlinear=force is not None,
        t0=t0,
        progress=progress,
    )
    return data


def transient(
    rotor: Rotor,
    t_end: float,
    *,
    speed_start: float,
    speed_end: float | None = None,
    unbalance=(),
    force: Force | None = None,
    q0=None,
    v0=None,
    n_output: int = 2001,
    method: str = "modal",
    n_modes: int = 20,
    rtol: float = 1e-7,
    atol: float = 1e-12,
    steps_per_output: int = 4,
    large_rotation=(),
    large_rotation_model: str = "euler_123",
    hub_stiffness: float | None = None,
    disk_state0=None,
    progress: Callable[[float, float], None] | None = None,
) -> TransientData:
    """Integrate the rotor's motion from 0 to ``t_end`` [s].

    The linear part is :func:`linear_transient`'s (:class:`Pencil` of the rotor: ``Rotor.KC``
    on the speed grid of its bearing tables, M at the mid speed, ``G``, ``Kst``); the
    large-rotation disks add their terms to its right-hand side here.

    Parameters
    ----------
    speed_start, speed_end : float
        Spin speed at t = 0 and t = t_end [rad/s] (linear ramp; equal for constant speed).
    unbalance : sequence of (node, magnitude [kg m], phase [rad])
    force : callable ``force(t, q, v) -> ndarray (n_dof,)`` [N, N m], optional
        Extra (e.g. nonlinear) force on all DOFs, evaluated at every right-hand-side call.
    method : ``"modal"`` or ``"direct"``
    n_modes : int
        Undamped modes kept by ``"modal"``.
    large_rotation : sequence of int
        Disk nodes whose tilt is integrated with exact (large-rotation) kinematics
        (:class:`~rotaflex.rotor.fe.elements.large_disk.LargeRotationDisk`).
    large_rotation_model : ``"euler_123"`` or ``"quaternion"``
    hub_stiffness : float, optional
        Bending stiffness of the quaternion disks' hub joint [N m/rad]; default 1000 times the
        node's largest tilt stiffness diagonal (close to rigid; 0 gives a free disk).
    disk_state0 : dict node -> (quaternion (4,), body rates (3,) [rad/s]), optional
        Initial state of quaternion disks; default from the node's initial tilt and tilt rate
        and ``speed_start`` (:meth:`QuaternionDisk.initial_state`).
    progress : callable ``progress(t, t_end)``, optional
        Called with the simulated time reached [s]: from the right-hand side at most every
        ``t_end / 200`` of simulated time (adaptive integrator), after each output (Newmark).
    """
    t0 = time.perf_counter()
    speed_end = speed_start if speed_end is None else speed_end
    alpha = (speed_end - speed_start) / t_end
    n = rotor.n_dof
    grid = speed_grid(rotor, min(speed_start, speed_end), max(speed_start, speed_end))
    Kg, Cg = rotor.KC(grid)
    # a seal's added mass enters at the mid speed of the run (constant M in the integrators)
    mid = 0.5 * (speed_start + speed_end)
    M = rotor.MKC(mid)[0][0]
    G, Kst = rotor.G, rotor.Kst
    disks = dict(rotor.disks)
    if large_rotation_model not in ("euler_123", "quaternion"):
        raise InputError("transient.large_rotation_model", large_rotation_model, "'euler_123' or 'quaternion'")
    for node in large_rotation:
        if node not in disks:
            raise InputError("transient.large_rotation", node, "nodes that carry a disk: " + str(sorted(disks)))
    quat = large_rotation_model == "quaternion" and bool(large_rotation)
    Mbasis = M
    if quat:
        if method != "modal":
            raise InputError("transient.method", method, "'modal' with large_rotation_model = 'quaternion'")
        if speed_end != speed_start:
            raise InputError(
                "transient.speed_rpm", (speed_start, speed_end), "equal speeds with large_rotation_model = 'quaternion'"
            )
        M, G, Kst = M.copy(), G.copy(), Kst.copy()
        for node in large_rotation:  # the disk's rotary inertia moves to the rigid body
            sl = slice(NDOF_NODE * node, NDOF_NODE * node + 4)
            M[sl, sl] -= np.diag([0.0, 0.0, disks[node].Id, disks[node].Id])
            G[sl, sl] -= disks[node].G()
            Kst[sl, sl] -= disks[node].Kst()
    F = np.zeros((n, 2), complex)  # unbalance: x and y rows, phasor of the spin angle
    for node, u, phase in unbalance:
        if not 0 <= node < rotor.n_nodes:
            raise InputError("transient.mass.node", node, f"an existing node 0..{rotor.n_nodes - 1}")
        F[NDOF_NODE * node : NDOF_NODE * node + 2, 0] += unbalance_force(1.0, u, phase)  # per unit spin^2
    # basis of the rotor with its disks' rotary inertia (also for quaternion disks: their stiff
    # hub keeps the node near the disk's attitude, so the same low modes span it)
    pencil = Pencil(
        M,
        grid,
        Kg,
        Cg,
        G,
        Kst,
        F[:, :1] if unbalance else F[:, :0],
        np.ones(1 if unbalance else 0),
        lambda: rotor.KC(mid)[0][0],
        Mbasis,
    )
    if not large_rotation:
        return linear_transient(
            pencil,
            t_end,
            speed_start=speed_start,
            speed_end=speed_end,
            method=method,
            n_modes=n_modes,
            q0=q0,
            v0=v0,
            force=force,
            n_output=n_output,
            rtol=rtol,
            atol=atol,
            steps_per_output=steps_per_output,
            progress=progress,
        )
    lin = Linear(pencil, method, n_modes, speed_start, alpha, force)
    T, m = lin.T, lin.m
    large, qdisks = [], []
    q0 = np.zeros(n) if q0 is None else np.asarray(q0, float)
    v0 = np.zeros(n) if v0 is None else np.asarray(v0, float)
    # modal coordinates of q0, v0 in the basis' own mass metric; a quaternion disk starts at the
    # node's tilt as the basis represents it (an unstrained hub)
    x0, xv0 = lin.start(q0, v0)
    q0b, v0b = T @ x0, T @ xv0
    z_disk = []
    for node in large_rotation:
        Tn = T[NDOF_NODE * node : NDOF_NODE * node + 4]
        if not quat:
            large.append((LargeRotationDisk(node, disks[node].Id, disks[node].Ip), Tn))
            continue
        sl = slice(NDOF_NODE * node + 2, NDOF_NODE * node + 4)
        kb = hub_stiffness if hub_stiffness is not None else 1e3 * float(np.max(np.diag(Kg[0])[sl]))
        if not (np.isfinite(kb) and kb >= 0):
            raise InputError("transient.hub_stiffness", hub_stiffness, "a finite number >= 0 [N m/rad]")
        el = QuaternionDisk(node, disks[node].Id, disks[node].Ip, kb)
        if disk_state0 is not None and node in disk_state0:
            e0, w0 = (np.asarray(a, float) for a in disk_state0[node])
        else:
            e0, w0 = QuaternionDisk.initial_state(q0b[sl], v0b[sl], speed_start)
        qdisks.append((el, Tn[2:4]))
        z_disk += [e0, w0]
    nq = len(qdisks)
    Mr, Mi = lin.Mr, lin.Mi

    def rhs(t, z):
        w, K, D = lin.mats(t)
        x, v = z[:m], z[m : 2 * m]
        f = lin.load(t, w, x, v)
        if qdisks:
            dz = []
            for i, (el, Tt) in enumerate(qdisks):
                zi = z[2 * m + 7 * i : 2 * m + 7 * i + 7]
                de, dw, mom = el.rates(zi[:4], zi[4:], Tt @ x)
                f = f + Tt.T @ mom
                dz += [de, dw]
            return np.concatenate([v, Mi @ (f - D @ v - K @ x), *dz])
        Mq = Mr.copy()
        for el, Tn in large:
            qn, vn = Tn @ x, Tn @ v
            if abs(qn[3]) > np.radians(89.0):
                raise SingularityError(
                    f"Euler 1-2-3 large-rotation disk at node {el.node}",
                    t,
                    f"theta_y = {np.degrees(qn[3]):.2f} deg, singular at 90 deg; "
                    "use large_rotation_model = 'quaternion'",
                )
            Mq += el.mass_increment(qn) * np.outer(Tn[2], Tn[2])
            f = f - Tn.T @ el.force(qn, vn, w, alpha)
        return np.concatenate([v, np.linalg.solve(Mq, f - D @ v - K @ x)])

    z0 = np.concatenate([x0, xv0, *z_disk])
    data, extra = lin.integrate(
        rhs,
        z0,
        t_end,
        n_output=n_output,
        rtol=rtol,
        atol=atol,
        steps_per_output=steps_per_output,
        nonlinear=force is not None or bool(large),
        t0=t0,
        progress=progress,
    )
    if not nq:
        return data
    zd = extra.reshape(data.time.size, nq, 7)
    return replace(
        data,
        wall_time=time.perf_counter() - t0,
        quaternion=zd[..., :4],
        omega=zd[..., 4:],
        disks=tuple(el for el, _ in qdisks),
    )


def _reporting(rhs, t_end: float, progress: Callable[[float, float], None]):
    """``rhs`` that also reports the time it is evaluated at, at most 200 times over the run
    (the integrator's trial stages run slightly ahead of the accepted time; that is enough for
    a progress line)."""
    shown = [-t_end]

    def f(t, z):
        if t - shown[0] >= t_end / 200:
            shown[0] = t
            progress(min(t, t_end), t_end)
        return rhs(t, z)

    return f


def _newmark(mats, rhs, M, Mi, z0, t_eval, sub, nonlinear, tol, t_start, progress=None) -> TransientData:
    """Newmark average acceleration (beta = 1/4, gamma = 1/2) on the full system."""
    n = M.shape[0]
    h = (t_eval[1] - t_eval[0]) / sub
    q, v = z0[:n].copy(), z0[n:].copy()
    a = rhs(0.0, z0)[n:]
    Q, V, S = np.empty((t_eval.size, n)), np.empty((t_eval.size, n)), np.empty(t_eval.size)
    Q[0], V[0], S[0] = q, v, mats(0.0)[0]
    nfev, t = 1, 0.0
    for k in range(1, t_eval.size):
        for _ in range(sub):
            t1 = t + h
            w, K, D = mats(t1)
            lu = sla.lu_factor(M + h / 2 * D + h * h / 4 * K)
            qp = q + h * v + h * h / 4 * a  # predictor parts of the Newmark update
            vp = v + h / 2 * a
            # external force at t1: f = M a + D v + K q evaluated through rhs at any state
            z_guess = np.concatenate([qp, vp])
            for _ in range(50):
                f = M @ rhs(t1, z_guess)[n:] + D @ z_guess[n:] + K @ z_guess[:n]
                nfev += 1
                a1 = sla.lu_solve(lu, f - D @ vp - K @ qp, check_finite=False)
                q1, v1 = qp + h * h / 4 * a1, vp + h / 2 * a1
                if not nonlinear:
                    break
                change = np.linalg.norm(q1 - z_guess[:n]) / max(np.linalg.norm(q1), 1e-300)
                z_guess = np.concatenate([q1, v1])
                if change < tol:
                    break
            else:
                raise ConvergenceError("Newmark step (nonlinear force)", t1, float(change), tol)
            q, v, a, t = q1, v1, a1, t1
        Q[k], V[k], S[k] = q, v, mats(t)[0]
        if progress is not None:
            progress(t, t_eval[-1])
    return TransientData(
        t_eval,
        Q,
        V,
        S,
        nfev,
        time.perf_counter() - t_start,
        f"direct: Newmark, {sub * (t_eval.size - 1)} steps of {h:.3g} s",
    )
