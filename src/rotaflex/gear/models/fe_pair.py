"""Dynamic contact of two spur gears: rigid disks + one elastic FE tooth each (Lee & Jang).

Model (section 2 of the paper)
------------------------------
* Each gear is a rigid disk (polar inertia J, pinned centre, rotation ``phi``) and one elastic
  tooth (8-node plane-stress elements, HRZ-lumped mass) whose *absolute* nodal positions are
  unknowns. The tooth's ``root_nodes`` are tied to the disk, ``x_i = c + R(phi) X_i``
  (eq. 2), with Lagrange multipliers.
* Elastic force in the disk-fixed frame (eq. 4-5), exact co-rotational form
  ``w = R^T (x - c) - X``, ``f = -R K w``; the disk receives ``-dE/dphi`` so the elastic
  force is conservative (the paper's eq. 5 has no such term; it is second order in w).
* Contact between gear A's and gear B's working flanks (see :mod:`rotaflex.gear.pair.contact_geometry`).
* External torques ramp as in Fig. 7 (:func:`torque_ramp`).

Placement: gear A (driver, counter-clockwise) at the origin, gear B (driven, clockwise) at
``(0, a)`` with ``a`` the standard centre distance; at t = 0 the teeth touch at the start of
the path of contact (B's tip corner on A's flank) with zero gap, found by the contact search.

Time integration (section 3): :func:`integrate`, kernel :func:`rotaflex.gear.kernels.rk4.run_steps`.
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass, field, replace
from typing import NamedTuple

import numpy as np
import scipy.sparse as sp

from rotaflex.core.errors import InputError


def torque_ramp(theta: np.ndarray | float, tau0: float, theta_2: float, theta_s: float):
    """External torque of Fig. 7 on a single-tooth gear [N m].

    Rises linearly from 0 to ``tau0`` over the first two-pair zone ``[0, theta_2]``, stays at
    ``tau0`` in the single-pair zone and falls to 0 over ``[theta_s - theta_2, theta_s]``;
    zero outside ``[0, theta_s]``. Angles in rad, measured from the start of contact.
    """
    th = np.asarray(theta, dtype=float)
    f = np.clip(np.minimum(th / theta_2, (theta_s - th) / theta_2), 0.0, 1.0)
    return tau0 * f


@dataclass(frozen=True)
class GearPairModel:
    """Assembled arrays of the two-gear model (gear A nodes first, then gear B).

    Frozen: a changed model is a new one (``dataclasses.replace``); the arrays are not
    written after construction.
    """

    geometry: tuple
    meshes: tuple
    centre_distance: float
    theta0: np.ndarray  # (2,) initial orientation of each tooth frame [rad]
    centres: np.ndarray  # (2, 2)
    xloc: np.ndarray  # (N, 2) node coordinates in the tooth frames
    gid: np.ndarray  # (N,) gear of each node
    minv: np.ndarray  # (N,) inverse lumped nodal mass
    stiffness: sp.csr_matrix  # block-diagonal, local frames
    tie_node: np.ndarray
    tie_gear: np.ndarray
    tb_i: np.ndarray
    tb_j: np.ndarray
    tb_b: np.ndarray
    flank: np.ndarray  # (2, n) working-flank node ids (global numbering), root -> tip
    nedge: np.ndarray
    sig: np.ndarray
    inertia: np.ndarray  # (2,)
    rsgn: np.ndarray  # rotation sense: theta_g = rsgn[g] * phi[g]
    n_points: int
    dt_limit: float
    offsets: tuple = field(default=(0, 0))

    @property
    def n_nodes(self) -> int:
        return int(self.xloc.shape[0])

    #: torque of the disks: the Fig. 7 ramps (one tooth per gear) or the constant tau_0
    constant_torque = False

    def pair_layout(self):
        """Contact pairs: flank ids (npair, 2, nfl), edges (npair, 2), nominal contact angles at
        t = 0 (npair,), initial contact parameters (npair, 2) and start positions (2N,).
        One tooth per gear is one pair starting at the start of contact, unloaded."""
        return (self.flank[None], self.nedge[None], np.zeros(1), np.array([[0.3, 0.99]]), self.reference_positions())

    def warm_start_table(self, theta_s: float):
        """Involute contact parameters for pairs entering the mesh window (none for one pair)."""
        return None

    def start_strain_energy(self, x: np.ndarray) -> float:
        """Strain energy of the start state [J] (0: the single pair starts unloaded)."""
        return 0.0

    def reference_positions(self) -> np.ndarray:
        """Global node positions at t = 0, flattened (2N,)."""
        out = np.empty((self.n_nodes, 2))
        for g in range(2):
            sel = self.gid == g
            c, s = math.cos(self.theta0[g]), math.sin(self.theta0[g])
            xl = self.xloc[sel]
            out[sel, 0] = self.centres[g, 0] + c * xl[:, 0] - s * xl[:, 1]
            out[sel, 1] = self.centres[g, 1] + s * xl[:, 0] + c * xl[:, 1]
        return out.ravel()


def _tie_blocks(k_local: sp.csr_matrix, nodes: np.ndarray, offset_tie: int):
    """2x2 stiffness blocks between tie nodes (local frame)."""
    dofs = np.column_stack([2 * nodes, 2 * nodes + 1]).ravel()
    sub = k_local[dofs][:, dofs].toarray()
    nt = len(nodes)
    bi, bj, bb = [], [], []
    for i in range(nt):
        for j in range(nt):
            blk = sub[2 * i : 2 * i + 2, 2 * j : 2 * j + 2]
            if np.any(blk != 0.0):
                bi.append(i + offset_tie)
                bj.append(j + offset_tie)
                bb.append(blk)
    return bi, bj, bb


def _per_gear(value) -> tuple[float, float]:
    """(A, B) of a material value given once for both gears or per gear."""
    v = np.broadcast_to(np.asarray(value, dtype=float), (2,))
    return float(v[0]), float(v[1])


def build_model(
    geometry_a,
    geometry_b,
    mesh_a,
    mesh_b,
    *,
    youngs_modulus,
    poisson_ratio,
    density,
    inertia,
    n_points=61,
    flank="left",
    centre_distance=None,
):
    """Place the two single-tooth gears at the start of contact and assemble the arrays.

    Gear A is the driver (counter-clockwise about the origin), gear B the driven gear (clockwise
    about ``(0, a)``); the gears may differ (teeth, profile shift, reliefs, mesh, material).

    Parameters
    ----------
    geometry_a, geometry_b : GearGeometry
    mesh_a, mesh_b : ToothMesh
    youngs_modulus, poisson_ratio, density : float or (float, float)
        E [Pa], nu [-], rho [kg/m^3]; one value for both gears or one per gear (A, B).
    inertia : (float, float)
        Disk polar inertia of A and B [kg m^2].
    n_points : int
        Spline data points per flank (61 in the paper).
    flank : str
        Working flank of both teeth; with A turning counter-clockwise and B clockwise the
        working flanks are the ``"left"`` ones (x < 0 in the tooth frame).
    centre_distance : float or None
        Working centre distance a [m] (default: the no-backlash one of the two geometries);
        the operating pressure angle is ``acos((r_bA + r_bB) / a)``.
    """
    from rotaflex.gear.pair import plane_stress as fe
    from rotaflex.gear.pair.contact_geometry import search
    from rotaflex.gear.pair.geometry import center_distance_no_backlash

    geoms = (geometry_a, geometry_b)
    meshes = (mesh_a, mesh_b)
    a = center_distance_no_backlash(geometry_a, geometry_b) if centre_distance is None else float(centre_distance)
    mats = [_per_gear(v) for v in (youngs_modulus, poisson_ratio, density)]
    alpha_w = math.acos((geometry_a.base_radius + geometry_b.base_radius) / a)
    rb = (geometry_a.base_radius, geometry_b.base_radius)
    # start of the path of contact, measured from A's tangency point T_A
    l_start = a * math.sin(alpha_w) - math.sqrt(geometry_b.tip_radius_**2 - rb[1] ** 2)
    psi_b = [float(g.flank_half_angle(np.array(g.base_radius))) for g in geoms]
    theta_a0 = l_start / rb[0] - alpha_w - psi_b[0]
    theta_b0 = math.pi + (a * math.sin(alpha_w) - l_start) / rb[1] - alpha_w - psi_b[1]
    centres = np.array([[0.0, 0.0], [0.0, a]])

    xl, gid, minv, ks, tie_node, tie_gear, fl = [], [], [], [], [], [], []
    tb_i, tb_j, tb_b = [], [], []
    off = 0
    ntie = 0
    dt_lim = []
    for g, mesh in enumerate(meshes):
        e_g, nu_g, rho_g = (v[g] for v in mats)
        k = fe.stiffness_matrix(mesh, e_g, nu_g).tocsr()
        m = fe.lumped_mass(mesh, rho_g)[::2]
        if np.any(m <= 0):
            raise InputError("mesh", "HRZ masses", "positive lumped masses")
        dt_lim.append(fe.stable_time_step(mesh, e_g, nu_g, rho_g))
        xl.append(mesh.nodes)
        gid.append(np.full(mesh.n_nodes, g))
        minv.append(1.0 / m)
        ks.append(k)
        roots = np.asarray(mesh.root_nodes, dtype=np.int64)
        tie_node.append(roots + off)
        tie_gear.append(np.full(len(roots), g))
        bi, bj, bb = _tie_blocks(k, roots, ntie)
        tb_i += bi
        tb_j += bj
        tb_b += bb
        fl.append(np.asarray(mesh.flank_nodes[flank], dtype=np.int64) + off)
        off += mesh.n_nodes
        ntie += len(roots)
    nfl = max(len(f) for f in fl)
    flank_arr = np.zeros((2, nfl), dtype=np.int64)
    for g in range(2):
        flank_arr[g, : len(fl[g])] = fl[g]
    nedge = np.array([(len(f) - 1) // 2 for f in fl], dtype=np.int64)
    sig = np.array([1.0 if flank == "left" else -1.0] * 2)
    model = GearPairModel(
        geometry=geoms,
        meshes=meshes,
        centre_distance=a,
        theta0=np.array([theta_a0, theta_b0]),
        centres=centres,
        xloc=np.ascontiguousarray(np.vstack(xl)),
        gid=np.concatenate(gid).astype(np.int64),
        minv=np.concatenate(minv),
        stiffness=sp.block_diag(ks, format="csr"),
        tie_node=np.concatenate(tie_node).astype(np.int64),
        tie_gear=np.concatenate(tie_gear).astype(np.int64),
        tb_i=np.array(tb_i, dtype=np.int64),
        tb_j=np.array(tb_j, dtype=np.int64),
        tb_b=np.ascontiguousarray(np.array(tb_b, dtype=float).reshape(-1, 2, 2)),
        flank=flank_arr,
        nedge=nedge,
        sig=sig,
        inertia=np.asarray(inertia, dtype=float),
        rsgn=np.array([1.0, -1.0]),
        n_points=int(n_points),
        dt_limit=float(min(dt_lim)),
    )
    # close the initial gap exactly: rotate B about its centre until the surfaces touch
    for _ in range(8):
        pts = _flank_points(model, model.reference_positions())
        pair = search(pts[0], pts[1], model.sig[0], model.sig[1], start=(0.3, 0.99))
        if abs(pair.gap) < 1e-14:
            break
        # a counter-clockwise turn of B by d moves its flank towards A by about r_b * d
        theta0 = model.theta0.copy()
        theta0[1] += pair.gap / rb[1]
        model = replace(model, theta0=theta0)
    if abs(pair.gap) > 1e-10 or pair.case == "tip_A":
        raise InputError("geometry", "gear pair", "teeth that meet at the start of contact")
    return model


def smoothing_tables(model: GearPairModel, n_intervals: int, flank=None, nedge=None, per_interval: int = 40):
    """Tables of the smoothed contact surfaces (:func:`rotaflex.gear.kernels.contact.sample_smooth`).

    The flank displacement is replaced by its least-squares fit with a clamped cubic B-spline of
    ``n_intervals`` uniform intervals of the flank parameter (L2 projection on a fine grid of
    ``(n_points - 1) * per_interval + 1`` parameters). ``flank`` (npair, 2, nfl) and ``nedge``
    (npair, 2) are the flanks of the contact pairs (default: the model's one pair). Returns
    ``tab`` (npair, 2, NT, nfl): the weights T_n(s) of the flank nodes on that grid, and ``mloc``
    (npair, 2, n_points, 2): the misfit ``X(s) - sum_n T_n(s) X_n`` of the undeformed flank (disk
    frame) at the spline points, so that the undeformed surface is the FE edge exactly.
    ``n_intervals = 0``: dummy arrays (the paper's surfaces and 3-node contact force).
    """
    if flank is None:
        flank, nedge = model.flank[None], model.nedge[None]
    npair = flank.shape[0]
    if n_intervals <= 0:
        return np.zeros((npair, 2, 2, 1)), np.zeros((npair, 2, 1, 2))
    mpts = model.n_points
    if n_intervals + 3 > mpts:
        raise InputError("mesh.contact_smoothing", n_intervals, f"0 or 1..{mpts - 3} (n_points - 3)")
    from scipy.interpolate import BSpline

    from rotaflex.gear.kernels.contact import flank_weights

    nt = (mpts - 1) * per_interval + 1
    grid = np.linspace(0.0, 1.0, nt)
    knots = np.concatenate([[0.0] * 3, np.linspace(0.0, 1.0, n_intervals + 1), [1.0] * 3])
    b = BSpline.design_matrix(grid, knots, 3).toarray()
    nf = flank.shape[2]
    tab = np.zeros((npair, 2, nt, nf))
    mloc = np.empty((npair, 2, mpts, 2))
    nodes = np.empty(3, dtype=np.int64)
    w = np.empty(3)
    for jp in range(npair):
        for g in range(2):
            fl = flank[jp, g]
            col = {int(i): j for j, i in enumerate(fl)}
            q = np.zeros((nt, nf))
            for r, s in enumerate(grid):
                flank_weights(fl, int(nedge[jp, g]), s, nodes, w)
                for j in range(3):
                    q[r, col[int(nodes[j])]] += w[j]
            tab[jp, g] = b @ np.linalg.solve(b.T @ b, b.T @ q)
            xl = model.xloc[fl]
            rows = np.arange(mpts) * per_interval
            mloc[jp, g] = q[rows] @ xl - tab[jp, g][rows] @ xl
    return np.ascontiguousarray(tab), mloc


def _flank_points(model: GearPairModel, x: np.ndarray) -> list[np.ndarray]:
    from rotaflex.gear.kernels.contact import sample_flank

    out = []
    for g in range(2):
        p = np.empty((model.n_points, 2))
        sample_flank(x, model.flank[g], int(model.nedge[g]), p)
        out.append(p)
    return out


#: tie_eigen_bounds by content of what it reads (a run validates and then builds with the same
#: model; runs of one pair at several speeds share it): key -> bounds
_TIE_BOUNDS: dict[bytes, np.ndarray] = {}


def tie_eigen_bounds(model: GearPairModel, dt: float) -> np.ndarray:
    """Smallest eigenvalue of the tie block of C for the three passes (rotation invariant).

    C_tie = c1 M^-1 - c2 M^-1 K_tt M^-1 + (c1/J) b b^T in the tooth frame, with
    (c1, c2) = (dt^2/2, dt^4/24), (dt, dt^3/6), (1, 0). Dense eigenvalues of a block of twice
    the tied nodes: remembered per process by the content of its inputs.
    """
    digest = hashlib.blake2b(np.float64(dt).tobytes(), digest_size=20)
    m = model
    for a in (m.tie_node, m.tie_gear, m.minv, m.xloc, m.inertia, m.tb_i, m.tb_j, m.tb_b):
        a = np.ascontiguousarray(a)
        digest.update(str((a.dtype, a.shape)).encode())
        digest.update(a.tobytes())
    key = digest.digest()
    if key not in _TIE_BOUNDS:
        if len(_TIE_BOUNDS) >= 32:
            _TIE_BOUNDS.clear()
        _TIE_BOUNDS[key] = _tie_eigen_bounds(model, dt)
    return _TIE_BOUNDS[key].copy()


def _tie_eigen_bounds(model: GearPairModel, dt: float) -> np.ndarray:
    nt = len(model.tie_node)
    mt = np.repeat(model.minv[model.tie_node], 2)
    ktt = np.zeros((2 * nt, 2 * nt))
    for i, j, b in zip(model.tb_i, model.tb_j, model.tb_b, strict=True):
        ktt[2 * i : 2 * i + 2, 2 * j : 2 * j + 2] = b
    out = []
    for c1, c2 in ((dt * dt / 2, dt**4 / 24), (dt, dt**3 / 6), (1.0, 0.0)):
        c = c1 * np.diag(mt) - c2 * (mt[:, None] * ktt * mt[None, :])
        for g in range(2):
            sel = np.where(model.tie_gear == g)[0]
            xl = model.xloc[model.tie_node[sel]]
            b = np.zeros(2 * nt)
            b[2 * sel] = -xl[:, 1]
            b[2 * sel + 1] = xl[:, 0]
            c += c1 / model.inertia[g] * np.outer(b, b)
        lam = np.linalg.eigvalsh(c)
        if lam[0] <= 0:
            raise InputError(
                "solver.dt",
                dt,
                f"a step for which the constraint matrix is positive definite (dt < {model.dt_limit:.4g} s)",
            )
        out.append(lam[0])
    return np.array(out)


def rigid_velocities(model, x: np.ndarray, om: np.ndarray) -> np.ndarray:
    """Nodal velocities [m/s] (flat, 2 per node) of both gears turning rigidly at ``om``
    [rad/s] (counter-clockwise positive) about their centres, at positions ``x``."""
    v = np.empty(2 * model.n_nodes)
    for g in range(2):
        sel = np.where(model.gid == g)[0]
        rel = x.reshape(-1, 2)[sel] - model.centres[g]
        v[2 * sel] = -om[g] * rel[:, 1]
        v[2 * sel + 1] = om[g] * rel[:, 0]
    return v


def node_blocks(k: sp.csr_matrix):
    """The stiffness (2N x 2N, DOFs ``[x0, y0, x1, ...]``) as 2 x 2 node blocks: block-row
    pointers (N + 1,), node columns (nb,) and blocks (nb, 4) = (K_xx, K_xy, K_yx, K_yy) [N/m]
    (blocks in ascending column order; a block absent from the pattern of K is absent here,
    an entry missing inside a present block is stored as 0)."""
    bsr = sp.bsr_matrix(k, blocksize=(2, 2))
    bsr.sort_indices()
    kblk = np.ascontiguousarray(bsr.data.reshape(-1, 4), dtype=float)
    return bsr.indptr.astype(np.uint64), bsr.indices.astype(np.uint64), kblk


def tie_blocks(model):
    """The stiffness among the tied nodes as block rows: pointers (nt + 1,), tie index of each
    block's column (nq,) and blocks (nq, 4) = (K_xx, K_xy, K_yx, K_yy) [N/m]; the blocks of a row
    keep their order in ``model.tb_*`` (a stable sort), so each row sums its terms as before."""
    order = np.argsort(model.tb_i, kind="stable")
    counts = np.bincount(model.tb_i, minlength=len(model.tie_node))
    ptr = np.concatenate(([0], np.cumsum(counts))).astype(np.uint64)
    blocks = np.ascontiguousarray(np.asarray(model.tb_b, dtype=float)[order].reshape(-1, 4))
    return ptr, np.asarray(model.tb_j)[order].astype(np.uint64), blocks


def _kernel_arrays(model, flank, nedge, psi, warm_start, tab, mloc):
    """:class:`~rotaflex.gear.kernels.arrays.ModelArrays` of ``model`` with its contact-pair
    layout (``flank, nedge, psi``), warm-start table and smoothed-surface tables."""
    from rotaflex.gear.kernels.arrays import ModelArrays

    kptr, kcol, kblk = node_blocks(model.stiffness)
    tb_ptr, tb_j, tb_b = tie_blocks(model)
    return ModelArrays(
        gid=model.gid,
        kptr=kptr,
        kcol=kcol,
        kblk=kblk,
        xloc=model.xloc,
        minv=model.minv,
        centres=model.centres,
        theta0=np.asarray(model.theta0, dtype=float),
        inertia=np.asarray(model.inertia, float),
        rsgn=model.rsgn,
        sig=model.sig,
        tie_node=model.tie_node,
        tie_gear=model.tie_gear,
        tb_ptr=tb_ptr,
        tb_j=tb_j,
        tb_b=tb_b,
        flank=np.ascontiguousarray(flank),
        nedge=np.ascontiguousarray(nedge),
        psi=psi,
        wtab=np.zeros((1, 3)) if warm_start is None else np.asarray(warm_start, float),
        tab=tab,
        mloc=mloc,
    )


class KernelInputs(NamedTuple):
    """Arguments of :func:`rotaflex.gear.kernels.rk4.run_steps` for one run, its step count and
    the start energy [J] (made by :func:`kernel_inputs`)."""

    arrays: object  # ModelArrays
    params: object  # StepParams
    state: object  # State
    rec: object  # Records
    n_steps: int
    initial_energy: float


def kernel_inputs(
    model,
    *,
    speeds,
    torque,
    theta_2,
    theta_s,
    span,
    dt,
    tol=1e-12,
    n_accel=3,
    max_iter=500,
    record_every=10,
    restitution=0.0,
    multipliers="iterative",
    smoothing=0,
    torque_mode=None,
    window=None,
    warm_start=None,
    gain=(1.0, 1.0),
):
    """Kernel arguments of a run of :func:`integrate` (same parameters; checked here)."""
    from rotaflex.gear.kernels.arrays import Records, State, StepParams
    from rotaflex.gear.kernels.forces import kinetic_energy
    from rotaflex.gear.kernels.rk4 import GLOBAL_COLUMNS, PAIR_COLUMNS

    if dt > model.dt_limit:
        raise InputError(
            "solver.dt",
            dt,
            f"a step <= the RK4 stability limit of the mesh, "
            f"{model.dt_limit:.4g} s (refine dt or coarsen the smallest elements)",
        )
    if multipliers not in ("iterative", "direct"):
        raise InputError("solver.multipliers", multipliers, "'iterative' or 'direct'")
    if not 0.0 <= restitution <= 1.0:
        raise InputError("solver.restitution", restitution, "in [0, 1]")
    flank, nedge, psi, start, x = model.pair_layout()
    if torque_mode is None:
        torque_mode = 1 if model.constant_torque else 0
    if warm_start is None:
        warm_start = model.warm_start_table(theta_s)
    npair = flank.shape[0]
    tab, mloc = smoothing_tables(model, smoothing, flank, nedge)
    omega = np.asarray(speeds, dtype=float)
    n_steps = max(1, int(round(span / (omega[0] * dt))))
    eps = tie_eigen_bounds(model, dt)
    nn = model.n_nodes
    om = np.array([omega[0], -omega[1]])
    v = rigid_velocities(model, x, om)
    nc = 2 * len(model.tie_node) + npair
    cres = np.zeros((npair, 8))
    cres[:, :2] = start
    nw = 3 if smoothing <= 0 else flank.shape[2]
    n_rec = n_steps // record_every + 1
    lo, hi = (-1e9, 1e9) if window is None else (-window, theta_s + window)
    arrays = _kernel_arrays(model, flank, nedge, psi, warm_start, tab, mloc)
    if multipliers == "direct":
        from rotaflex.gear.kernels.passes import factor_tie_blocks

        dfac, dperm, _ = factor_tie_blocks(model, dt)
    else:
        dfac, dperm = np.zeros((3, 0, 0)), np.zeros(0, dtype=np.int64)  # empty: the iteration
    params = StepParams(
        dt=float(dt),
        tau0=float(torque),
        theta_2=float(theta_2),
        theta_s=float(theta_s),
        tol_disp=float(tol),
        tol_vel=tol / dt,
        tol_acc=tol / dt**2,
        eps_disp=float(eps[0]),
        eps_vel=float(eps[1]),
        eps_acc=float(eps[2]),
        restitution=float(restitution),
        window_lo=float(lo),
        window_hi=float(hi),
        corners=window is not None,
        n_accel=int(n_accel),
        max_iter=int(max_iter),
        n_points=int(model.n_points),
        torque_mode=int(torque_mode),
        dfac=dfac,
        dperm=dperm,
        gain=np.asarray(gain, dtype=float),
    )
    state = State(
        x=x,
        v=v,
        a=np.zeros(2 * nn),
        phi=np.zeros(2),
        om=om,
        alp=np.zeros(2),
        mu=np.zeros(nc),
        cres=cres,
        cnod=np.zeros((npair, 2, nw), dtype=np.int64),
        cw=np.zeros((npair, 2, nw)),
        sc=np.zeros(24),
        spair=np.zeros((npair, 6)),
        rates=np.zeros((npair, 4)),
    )
    rec = Records(
        out=np.zeros((n_rec, len(GLOBAL_COLUMNS))),
        outp=np.zeros((n_rec, npair, len(PAIR_COLUMNS))),
        out_mu=np.zeros((n_rec, nc - npair)),
        info=np.zeros(4),
    )
    e0 = kinetic_energy(v, om, model.minv, model.inertia) + model.start_strain_energy(x)
    return KernelInputs(arrays, params, state, rec, n_steps, float(e0))


def integrate(
    model: GearPairModel,
    *,
    record_every=10,
    snapshots=0,
    progress=None,
    progress_every=2000,
    record_nodes=None,
    **run,
):
    """Integrate the pair over a rotation ``span`` of gear A [rad] with the paper's scheme.

    The keywords of the run (``speeds`` ... ``gain`` below, except those of the output:
    ``record_every``, ``snapshots``, ``progress``, ``progress_every``, ``record_nodes``) go to
    :func:`kernel_inputs` unchanged, which holds their defaults and checks them.

    Parameters
    ----------
    model : GearPairModel or MultiToothModel
        One contact pair per tooth (see :meth:`GearPairModel.pair_layout`).
    speeds : (float, float)
        Initial speeds of A (counter-clockwise) and B (clockwise) [rad/s]
        (:func:`rotaflex.core.units.rpm_to_rad_s`).
    torque : float
        tau_0 [N m]; drive torque on A and (times ``gain[1]``) load torque on B.
    theta_2, theta_s : float
        Two-pair zone and single-tooth contact angles of Fig. 7 [rad].
    span : float
        Rotation of gear A to simulate [rad]; the number of steps is span / (omega_A dt).
    dt : float
        Time step [s]; must not exceed the RK4 stability limit of the mesh.
    tol : float
        Displacement tolerance [m]; velocity and acceleration tolerances are tol/dt, tol/dt^2.
    n_accel : int
        Acceleration level n of appendix B (polynomial degree 2^(n-1) - 1).
    record_every : int
        Output decimation (1 = every step).
    snapshots : int
        Number of nodal-position snapshots to keep (for VTU output).
    progress : callable(done_steps, total_steps) or None
    restitution : float
        Newton coefficient of restitution e in [0, 1]: at an impact (a contact that closes
        while approaching) the velocity pass targets a relative normal velocity of
        -e x the approach velocity instead of 0 (e = 0: the paper's plastic impact).
    record_nodes : array of int or None
        Global node ids whose positions are stored at every record (``node_positions``), e.g.
        the support of the root-stress operator. The kernel is then called once per record.
    multipliers : {"iterative", "direct"}
        ``"iterative"``: the accelerated iteration of eq. 19-24 (the paper's scheme);
        ``"direct"``: exact solve of each pass (:func:`rotaflex.gear.kernels.passes.direct_solve`).
    smoothing : int
        Intervals of the smoothed contact surfaces (0 = the paper's surfaces).
    torque_mode : int or None
        0: the Fig. 7 ramps on both disks; 1: constant ``torque``. Default: 0 for one tooth per
        gear, 1 for several.
    window : float or None
        A pair is searched only while its nominal contact angle is within
        ``[-window, theta_s + window]`` [rad], with tip-corner contact outside [0, theta_s]
        (None: always searched, as the single-tooth model).
    warm_start : (nw, 3) array or None
        Involute contact parameters (a, b, contact angle) for pairs entering the window
        (default: none for one tooth per gear, the involute table of the model for several).
    gain : (float, float)
        Gear-ratio factor u_g of each disk (1 for the driver A, z_B / z_A for the driven B):
        disk g gets ``u_g tau(u_g theta_g)``, so the load torque is the drive torque times the
        ratio and its ramp follows the driver's rotation.

    Returns
    -------
    rotaflex.gear.solvers.registry.SolverOutput
        For one pair, ``records`` also holds the pair columns of that pair (shorthand).
    """
    from rotaflex.gear.kernels.rk4 import GLOBAL_COLUMNS, PAIR_COLUMNS, run_steps
    from rotaflex.gear.solvers.drive_loop import SolverOutput, drive

    arrays, params, state, rec, n_steps, e0 = kernel_inputs(model, record_every=record_every, **run)
    x = state.x
    n_rec = rec.out.shape[0]
    npair = state.cres.shape[0]
    rec_nodes = None if record_nodes is None else np.asarray(record_nodes, dtype=np.int64)
    rec_x = None if rec_nodes is None else np.zeros((n_rec, len(rec_nodes), 2))
    row = [0]

    def step(n, first):
        status, row[0] = run_steps(n, record_every, row[0], first, arrays, params, state, rec)
        return status, row[0]

    nrow, snaps, wall = drive(
        step,
        n_steps=n_steps,
        record_every=record_every,
        time_of=lambda: state.sc[0],
        positions=lambda: x.reshape(-1, 2),
        info=rec.info,
        snapshots=snapshots,
        record_nodes=rec_nodes,
        rec_x=rec_x,
        progress=progress,
        progress_every=progress_every,
    )
    records = {name: rec.out[:nrow, i].copy() for i, name in enumerate(GLOBAL_COLUMNS)}
    pair_records = {name: rec.outp[:nrow, :, i].copy() for i, name in enumerate(PAIR_COLUMNS)}
    if npair == 1:
        records.update({name: val[:, 0].copy() for name, val in pair_records.items()})
    return SolverOutput(
        records=records,
        pair_records=pair_records,
        tie_multipliers=rec.out_mu[:nrow].copy(),
        steps=n_steps,
        wall_time=wall,
        initial_energy=e0,
        dt=params.dt,
        snapshots=snaps,
        node_positions=None if rec_x is None else rec_x[:nrow].copy(),
        record_nodes=rec_nodes,
    )


#: the single-tooth entry point (same parameters as :func:`integrate`)
simulate = integrate
