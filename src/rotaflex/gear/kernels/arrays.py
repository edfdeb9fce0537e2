"""Named argument groups of the compiled gear solver (numba-compatible ``NamedTuple`` s).

:class:`ModelArrays` is the assembled pair (constant during a run), :class:`StepParams` the
scalars and factors of one run, :class:`State` everything a call of
:func:`rotaflex.gear.kernels.rk4.run_steps` advances (a run split into calls is bit-identical to
one call), :class:`Records` the output buffers. The ``HHT*`` groups are those of
:func:`rotaflex.gear.kernels.hht.run_hht` (reduced teeth).

Per-gear quantities are indexed by gear (0 = A, 1 = B): ``centres[g]``, ``theta0[g]``,
``inertia[g]``, ``rsgn[g]``, ``sig[g]``; node arrays cover both gears (A's nodes first) with
``gid`` the gear of each node, and the flanks of a pair are ``flank[j, g]`` padded to a common
length (used part ``nedge[j, g]`` quadratic edges), so the two gears may have different tooth
meshes and geometry.

Sparse index arrays are unsigned (``uint64``): numba then indexes without the wrap-around test
of negative indices, 10-15 % of a stiffness product.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np


class ModelArrays(NamedTuple):
    """Assembled two-gear model with ``npair`` contact pairs (SI units)."""

    gid: np.ndarray  # (N,) int64, gear of each node
    kptr: np.ndarray  # (N + 1,) uint64 block-row pointers of the stiffness in the tooth frames
    kcol: np.ndarray  # (nb,) uint64 node column of each 2 x 2 block
    kblk: np.ndarray  # (nb, 4) blocks (K_xx, K_xy, K_yx, K_yy) [N/m]
    xloc: np.ndarray  # (N, 2) node coordinates in the disk frames [m]
    minv: np.ndarray  # (N,) inverse lumped nodal mass [1/kg]
    centres: np.ndarray  # (2, 2) disk centres [m]
    theta0: np.ndarray  # (2,) initial orientation of each disk frame [rad]
    inertia: np.ndarray  # (2,) disk polar inertia [kg m^2]
    rsgn: np.ndarray  # (2,) running sense: rotation from the start = rsgn[g] * phi[g]
    sig: np.ndarray  # (2,) side of the flank normal
    tie_node: np.ndarray  # (nt,) tied (root) nodes
    tie_gear: np.ndarray  # (nt,)
    tb_ptr: np.ndarray  # (nt + 1,) uint64 block-row pointers of the stiffness among the tied nodes
    tb_j: np.ndarray  # (nq,) uint64 tie index of each block's column
    tb_b: np.ndarray  # (nq, 4) blocks (K_xx, K_xy, K_yx, K_yy) [N/m]
    flank: np.ndarray  # (npair, 2, nfl) working-flank node ids, root -> tip
    nedge: np.ndarray  # (npair, 2) quadratic edges of each flank
    psi: np.ndarray  # (npair,) nominal contact angle of each pair at t = 0 [rad]
    wtab: np.ndarray  # (nw, 3) warm start (a, b, contact angle); one row: none
    tab: np.ndarray  # (npair, 2, NT, nfl) smoothed-surface weights; (npair, 2, 2, 1): none
    mloc: np.ndarray  # (npair, 2, M, 2) smoothed-surface misfit in the disk frame [m]


class StepParams(NamedTuple):
    """Scalars of a run and the factors of the direct solve."""

    dt: float  # [s]
    tau0: float  # [N m]
    theta_2: float  # [rad] two-pair zone of the Fig. 7 ramps
    theta_s: float  # [rad]
    tol_disp: float  # [m]
    tol_vel: float  # [m/s]
    tol_acc: float  # [m/s^2]
    eps_disp: float  # smallest eigenvalue bound of the tie block, per pass
    eps_vel: float
    eps_acc: float
    restitution: float  # Newton coefficient e
    window_lo: float  # mesh window of the nominal contact angle [rad]
    window_hi: float
    corners: bool  # tip-corner contact outside [0, theta_s]
    n_accel: int
    max_iter: int
    n_points: int  # spline points per flank
    torque_mode: int  # 0: Fig. 7 ramps; 1: constant tau0
    dfac: np.ndarray  # (3, n + 1, bw + 3) tie-block factors of the direct solve; (3, 0, 0): iteration
    dperm: np.ndarray  # (n,) row order of the factors; (0,): iteration
    gain: np.ndarray  # (2,) gear-ratio factor u_g of each disk: torque u_g tau(u_g theta_g) (1 for the driver)


class State(NamedTuple):
    """State carried across calls (advanced in place)."""

    x: np.ndarray  # (2N,) absolute nodal positions [m]
    v: np.ndarray  # (2N,)
    a: np.ndarray  # (2N,) consistent accelerations of the step start
    phi: np.ndarray  # (2,) disk rotations since t = 0 (counter-clockwise) [rad]
    om: np.ndarray  # (2,)
    alp: np.ndarray  # (2,)
    mu: np.ndarray  # (2 nt + npair,) tie multipliers, then contact forces (p <= 0)
    cres: np.ndarray  # (npair, 8) contact search result per pair
    cnod: np.ndarray  # (npair, 2, nw) nodes of the contact rows
    cw: np.ndarray  # (npair, 2, nw) weights of the contact rows
    sc: np.ndarray  # (24,) running scalars, see run_steps
    spair: np.ndarray  # (npair, 6) per-pair running scalars, see run_steps
    rates: np.ndarray  # (npair, 4) contact-parameter rates da/dt, db/dt, dn/dt


class Records(NamedTuple):
    """Output buffers: global columns, per-pair columns, tie multipliers; ``info`` = (time,
    residual, tolerance) of a failure."""

    out: np.ndarray  # (n_rec, len(GLOBAL_COLUMNS))
    outp: np.ndarray  # (n_rec, npair, len(PAIR_COLUMNS))
    out_mu: np.ndarray  # (n_rec, 2 nt)
    info: np.ndarray  # (4,)


class HHTModel(NamedTuple):
    """Craig-Bampton pair of :func:`rotaflex.gear.kernels.hht.run_hht` (padded to ``n``)."""

    nr: np.ndarray  # (2,) used size per gear
    fl_map: np.ndarray
    mr: np.ndarray  # (2, n, n) reduced mass [kg]
    kr: np.ndarray  # (2, n, n) reduced stiffness [N/m]
    gr: np.ndarray
    hx: np.ndarray
    cx: np.ndarray
    ix: np.ndarray
    inertia: np.ndarray  # (2,) disk polar inertia [kg m^2]
    sfac: np.ndarray  # Cholesky factors of the HHT iteration matrix per gear
    m0fac: np.ndarray  # Cholesky factors of the mass matrix per gear
    fl_gear: np.ndarray
    fl_start: np.ndarray
    fl_len: np.ndarray
    fl_xref: np.ndarray  # flank reference positions [m]
    centres: np.ndarray  # (2, 2) [m]
    theta0: np.ndarray  # (2,) [rad]
    sig: np.ndarray  # (2,)
    pairs: np.ndarray  # (npair, 2) flank ids of each contact pair
    rsgn: np.ndarray  # (2,)


class HHTParams(NamedTuple):
    dt: float  # [s]
    alpha: float  # HHT alpha in [-1/3, 0]
    tau0: float  # [N m]
    theta_2: float  # [rad]
    theta_s: float  # [rad]
    tol: float  # [m]
    r_ref: float  # reference radius of the angle residual [m]
    max_iter: int
    n_points: int
    gain: np.ndarray  # (2,) gear-ratio factor u_g of each disk (as StepParams.gain)


class HHTState(NamedTuple):
    z: np.ndarray  # (2, n) reduced coordinates
    zd: np.ndarray
    za: np.ndarray
    phi: np.ndarray  # (2,) [rad]
    phid: np.ndarray
    phia: np.ndarray
    p: np.ndarray  # (npair,) contact forces
    cres: np.ndarray
    cnod: np.ndarray
    cw: np.ndarray
    fz: np.ndarray  # F at the current state
    fphi: np.ndarray
    sc: np.ndarray  # (8,) running scalars


class HHTRecords(NamedTuple):
    out: np.ndarray  # (n_rec, len(RECORD_COLUMNS of kernels.hht))
    outp: np.ndarray  # (n_rec, npair)
    info: np.ndarray  # (4,)


class StepScratch(NamedTuple):
    """Work arrays of one call of :func:`rotaflex.gear.kernels.rk4.run_steps` (made by
    :func:`rotaflex.gear.kernels.rk4.new_scratch`; nothing in them is carried between calls)."""

    rot: np.ndarray  # (2, 2) cos, sin of each disk frame
    bvec: np.ndarray  # (nt, 2) disk-angle derivative of the tie constraints
    rx: np.ndarray  # (nt, 2) tie-node positions in the disk frame [m]
    wbuf: np.ndarray  # (2N,) co-rotational displacement [m]
    fglob: np.ndarray  # (2N,) elastic force, global frame [N]
    fc: np.ndarray  # (2N,) constraint force on the nodes [N]
    tel: np.ndarray  # (2,) elastic torque on the disks [N m]
    fth: np.ndarray  # (2,) constraint torque on the disks [N m]
    gsc: np.ndarray  # (2N,) G^T dmu (kept zero between uses)
    gth: np.ndarray  # (2,)
    zk: np.ndarray  # (2N,) K R^T M^-1 g (kept zero between uses)
    xs: np.ndarray  # (2N,) RK4 stage positions
    vs: np.ndarray  # (2N,) RK4 stage velocities
    ak: np.ndarray  # (2N,) RK4 stage accelerations
    xsum: np.ndarray  # (2N,) RK4 velocity sum; then the predicted positions
    asum: np.ndarray  # (2N,) RK4 acceleration sum
    ps: np.ndarray  # (2,) stage disk angles
    os_: np.ndarray  # (2,) stage disk speeds
    alk: np.ndarray  # (2,) stage disk accelerations
    psum: np.ndarray  # (2,) RK4 speed sum; then the predicted angles
    osum: np.ndarray  # (2,) RK4 acceleration sum
    phi_t: np.ndarray  # (2,) disk angles of the step start
    pa: np.ndarray  # (npair, mpts, 2) spline points of flank A
    ma: np.ndarray  # (npair, mpts, 2) spline second derivatives of flank A
    pb: np.ndarray
    mb: np.ndarray
    va: np.ndarray  # (mpts, 2) flank velocities of A
    mva: np.ndarray
    vb: np.ndarray
    mvb: np.ndarray
    cn: np.ndarray  # (npair, 2) contact normals of the current state
    cn_s: np.ndarray  # (npair, 2) contact normals of a stage
    cnod_t: np.ndarray  # (npair, 2, nw) int64 contact-row nodes of a stage
    cw_t: np.ndarray  # (npair, 2, nw) contact-row weights of a stage
    ct: np.ndarray  # (npair, 4) contact parameters and normal of the step start
    zero4: np.ndarray  # (npair, 4) zero rates
    rate1: np.ndarray  # (4,) rates of one pair
    ccol: np.ndarray  # (npair, nc) contact columns of C
    e0: np.ndarray  # (nc,) error vector of a pass
    mu0: np.ndarray  # (nc,) multipliers before a pass
    dmu: np.ndarray  # (nc,) multiplier change of a pass
    pbar: np.ndarray  # (npair,) contact force after the displacement pass [N]
    sh_pred: np.ndarray  # (npair,) approach velocity of the predicted state [m/s]
    vtgt: np.ndarray  # (npair,) target normal velocity of the velocity pass [m/s]
    work: np.ndarray  # (13, nc) scratch of the passes
    stats: np.ndarray  # (2,) residual, iterations of the last pass
    poly: np.ndarray  # (4, 33) acceleration polynomial: coefficients and three work rows
    actm: np.ndarray  # (2, npair) bool: active contact rows, all rows
    fl_nodes: np.ndarray  # (3,) int64 nodes of a quadratic flank edge
    fl_w: np.ndarray  # (3,) their weights
    sm_w: np.ndarray  # (nw,) weights of a smoothed surface ((0,) with quadratic edges)


class HHTScratch(NamedTuple):
    """Work arrays of one call of :func:`rotaflex.gear.kernels.hht.run_hht` (made by
    :func:`rotaflex.gear.kernels.hht.new_hht_scratch`)."""

    xf: np.ndarray  # (2 nf,) flank-node positions [m]
    flid: np.ndarray  # (2, max flank length) int64 flank node ids of a pair
    nedge2: np.ndarray  # (2,) int64 quadratic edges of the two flanks
    pa: np.ndarray  # (mpts, 2) spline points of flank A
    ma: np.ndarray
    pb: np.ndarray
    mb: np.ndarray
    grow: np.ndarray  # (npair, 2, n + 1) gradients of the penetrations
    sgap: np.ndarray  # (npair,) penetrations [m]
    fz: np.ndarray  # (2, n) F at the iterate
    fphi: np.ndarray  # (2,)
    tau: np.ndarray  # (2,) external torques at the iterate [N m]
    taun: np.ndarray  # (2,) external torques of the step start [N m]
    ok: np.ndarray  # (1,) int64 contact search flag
    zn: np.ndarray  # (2, n) state of the step start
    zdn: np.ndarray
    zan: np.ndarray
    phin: np.ndarray  # (2,)
    phidn: np.ndarray
    phian: np.ndarray
    mz: np.ndarray  # (2, n) M a
    mphi: np.ndarray  # (2,)
    rhs: np.ndarray  # (n + 1,)
    y: np.ndarray  # (2, n + 1) S^-1 rhs per gear
    wcol: np.ndarray  # (npair, 2, n + 1) S^-1 gradients
    amat: np.ndarray  # (npair, npair) Schur matrix of the contact rows
    bvec: np.ndarray  # (npair,)
    dp: np.ndarray  # (npair,) contact-force change [N]
    act: np.ndarray  # (npair,) bool active pairs
    act_old: np.ndarray  # (npair,) bool
