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
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np


class ModelArrays(NamedTuple):
    """Assembled two-gear model with ``npair`` contact pairs (SI units)."""

    gid: np.ndarray  # (N,) int64, gear of each node
    indptr: np.ndarray  # CSR of the block-diagonal stiffness in the tooth frames
    indices: np.ndarray
    data: np.ndarray  # [N/m]
    xloc: np.ndarray  # (N, 2) node coordinates in the disk frames [m]
    minv: np.ndarray  # (N,) inverse lumped nodal mass [1/kg]
    centres: np.ndarray  # (2, 2) disk centres [m]
    theta0: np.ndarray  # (2,) initial orientation of each disk frame [rad]
    inertia: np.ndarray  # (2,) disk polar inertia [kg m^2]
    rsgn: np.ndarray  # (2,) running sense: rotation from the start = rsgn[g] * phi[g]
    sig: np.ndarray  # (2,) side of the flank normal
    tie_node: np.ndarray  # (nt,) tied (root) nodes
    tie_gear: np.ndarray  # (nt,)
    tb_i: np.ndarray  # tie-block coupling of the stiffness (q-th 2x2 block (tb_i, tb_j))
    tb_j: np.ndarray
    tb_b: np.ndarray  # (nq, 2, 2) [N/m]
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
    direct: bool  # direct multiplier solve
    dfac: np.ndarray  # (3, n + 1, bw + 3) tie-block factors (direct); else (3, 1, 1)
    dperm: np.ndarray  # (n,) row order of the factors
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
