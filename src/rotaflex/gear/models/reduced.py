"""Large-time-step method: Craig-Bampton reduced teeth + implicit HHT-alpha with unilateral contact.

Why this combination
--------------------
The paper's explicit RK4 is limited by the highest frequency of the FE tooth (dt < 3.8e-8 s for
the default mesh), while the contact force varies on the time scale of the mesh-contact mode
(period ~ 0.2 ms) and the lowest tooth modes (~ 20 us). Two things are done:

1. Model (exact reformulation + one approximation). In the disk frame the tie constraints of
   eq. 2 say ``w_k = 0`` for every tie node, so they are eliminated: the unknowns of gear g are
   the disk angle ``phi`` and the elastic displacements ``w`` of the free nodes in the disk
   frame, ``x_i = c + R(phi) (X_i + w_i)``. Lagrange's equations of this floating-frame form are
   exact (same kinetic and strain energy as the absolute formulation, gyroscopic and
   centrifugal terms kept). The free nodes are then reduced by Craig-Bampton with a fixed
   interface: boundary = all nodes of the working flank (every contact load acts there through
   the quadratic edge shape functions, so static responses to any contact point are exact),
   plus ``n_modes`` fixed-interface modes of the interior. This is the only approximation of
   the model: interior dynamics above the retained modes are dropped.
2. Integration: HHT-alpha (Hilber-Hughes-Taylor) in the index-3 form of Negrut et al. (2007),
   unconditionally stable for the linear part, second order, with mild high-frequency damping
   for alpha < 0. Contact is a complementarity condition ``s <= 0, p <= 0, p s = 0`` at the
   end of each step (position level), solved together with the Newton iteration by an active
   set ``p = min(0, p - c s)`` with ``c = 1/(beta h^2 A_kk)``. The Newton matrix
   ``M_0/(1+alpha) + beta h^2 K`` is constant in the disk frame (factored once per gear); the
   neglected Jacobian terms (Coriolis, contact geometric stiffness) only slow the iteration.

Several contact pairs are supported by the kernel (``pairs`` lists flank ids; the Schur system
of the pairs is solved densely); :func:`build_reduced` currently sets up the single pair of
:class:`rotaflex.gear.models.fe_pair.GearPairModel`.

Time-step check (:func:`time_step_limit`): the scheme is stable for any dt, so the check is on
accuracy and on the frozen iteration matrix: dt must resolve the mesh-contact mode
(``dt <= T_c / 20``, T_c from the pair's contact stiffness and the disks' reduced inertia) and
the rotation per step must stay small (``omega dt <= 0.01 rad``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
import scipy.linalg as sla

from rotaflex.core.errors import ConvergenceError, InputError

#: points per mesh-contact period required by :func:`time_step_limit`
STEPS_PER_CONTACT_PERIOD = 20
#: largest rotation per step [rad]
MAX_ROTATION_PER_STEP = 0.01


@dataclass(frozen=True)
class ReducedPairModel:
    """Craig-Bampton data of both gears, padded to a common size ``n``."""

    base: object  # GearPairModel
    nr: np.ndarray  # (2,) reduced coordinates per gear
    mr: np.ndarray  # (2, n, n) reduced mass
    kr: np.ndarray  # (2, n, n) reduced stiffness
    gr: np.ndarray  # (2, n, n) T^T M J T (skew)
    hx: np.ndarray  # (2, n) T^T M J X
    cx: np.ndarray  # (2, n) T^T M X
    ix: np.ndarray  # (2,) sum m |X|^2 (all tooth nodes)
    transform: list  # per gear (2 N_g, nr) map reduced -> nodal disk-frame displacement
    fl_gear: np.ndarray
    fl_start: np.ndarray
    fl_len: np.ndarray
    fl_xref: np.ndarray  # (nf, 2) flank node reference coordinates (disk frame)
    fl_map: np.ndarray  # (nf,) index in z of the flank node's x displacement, -1 if tied
    pairs: np.ndarray  # (npair, 2) flank ids
    modes: np.ndarray  # (2, n_modes) fixed-interface angular frequencies [rad/s]
    contact_period: float  # T_c [s]


def _craig_bampton(k, m_nodal, tie, flank, n_modes):
    """Fixed-interface Craig-Bampton basis of one tooth (ties clamped, untied flank nodes =
    boundary, in the given order)."""
    nn = len(m_nodal)
    flank = np.array([f for f in flank if f not in set(tie.tolist())], dtype=np.int64)
    free = np.setdiff1d(np.arange(nn), tie)
    inner = np.setdiff1d(free, flank)
    bd = np.column_stack([2 * flank, 2 * flank + 1]).ravel()
    idof = np.column_stack([2 * inner, 2 * inner + 1]).ravel()
    kd = k.toarray()
    kii = kd[np.ix_(idof, idof)]
    kib = kd[np.ix_(idof, bd)]
    mi = np.repeat(m_nodal[inner], 2)
    psi = -sla.solve(kii, kib, assume_a="pos")
    sq = 1.0 / np.sqrt(mi)
    lam, vec = sla.eigh(sq[:, None] * kii * sq[None, :], subset_by_index=[0, n_modes - 1])
    phi_i = sq[:, None] * vec  # mass-normalised
    nb = len(bd)
    t = np.zeros((2 * nn, nb + n_modes))
    t[bd, :nb] = np.eye(nb)
    t[idof, :nb] = psi
    t[idof, nb:] = phi_i
    return t, np.sqrt(np.maximum(lam, 0.0))


def build_reduced(model, n_modes: int = 20) -> ReducedPairModel:
    """Craig-Bampton reduction of both teeth of a :class:`GearPairModel`."""
    if n_modes < 0:
        raise InputError("solver.modes", n_modes, ">= 0")
    offs = np.concatenate([[0], np.cumsum([mm.n_nodes for mm in model.meshes])])
    ts, mrs, krs, grs, hxs, cxs, ixs, oms = [], [], [], [], [], [], [], []
    fl_start, fl_len, fl_x, fl_map = [], [], [], []
    start = 0
    for g in range(2):
        sel = slice(offs[g], offs[g + 1])
        kg = model.stiffness[2 * offs[g] : 2 * offs[g + 1], 2 * offs[g] : 2 * offs[g + 1]]
        mg = 1.0 / model.minv[sel]
        tie = model.tie_node[model.tie_gear == g] - offs[g]
        nfl = 2 * int(model.nedge[g]) + 1
        flank = model.flank[g, :nfl] - offs[g]
        tied = set(tie.tolist())
        q = 0
        for node in flank:
            if node in tied:
                fl_map.append(-1)
            else:
                fl_map.append(q)
                q += 2
        t, om = _craig_bampton(kg, mg, tie, flank, n_modes)
        xl = model.xloc[sel]
        mvec = np.repeat(mg, 2)
        xv = xl.ravel()
        jx = np.column_stack([-xl[:, 1], xl[:, 0]]).ravel()
        mt = mvec[:, None] * t
        jt = np.empty_like(t)
        jt[0::2] = -t[1::2]
        jt[1::2] = t[0::2]
        ts.append(t)
        mrs.append(t.T @ mt)
        krs.append(t.T @ (kg @ t))
        grs.append(t.T @ (mvec[:, None] * jt))
        hxs.append(t.T @ (mvec * jx))
        cxs.append(t.T @ (mvec * xv))
        ixs.append(float(np.sum(mg * (xl[:, 0] ** 2 + xl[:, 1] ** 2))))
        oms.append(om)
        fl_start.append(start)
        fl_len.append(nfl)
        fl_x.append(xl[flank])
        start += nfl
    nr = np.array([t.shape[1] for t in ts], dtype=np.int64)
    n = int(nr.max())

    def pad(mats):
        out = np.zeros((2, n, n))
        for g, a in enumerate(mats):
            out[g, : a.shape[0], : a.shape[1]] = a
        return out

    def padv(vecs):
        out = np.zeros((2, n))
        for g, a in enumerate(vecs):
            out[g, : len(a)] = a
        return out

    red = ReducedPairModel(
        base=model,
        nr=nr,
        mr=pad(mrs),
        kr=pad(krs),
        gr=pad(grs),
        hx=padv(hxs),
        cx=padv(cxs),
        ix=np.array(ixs),
        transform=ts,
        fl_gear=np.array([0, 1], dtype=np.int64),
        fl_start=np.array(fl_start, dtype=np.int64),
        fl_len=np.array(fl_len, dtype=np.int64),
        fl_xref=np.ascontiguousarray(np.vstack(fl_x)),
        fl_map=np.array(fl_map, dtype=np.int64),
        pairs=np.array([[0, 1]], dtype=np.int64),
        modes=np.array(oms) if n_modes else np.zeros((2, 0)),
        contact_period=0.0,
    )
    return replace(red, contact_period=_contact_period(red))


def _contact_period(red: ReducedPairModel) -> float:
    """Period of the mesh-contact mode: static contact stiffness at the pitch point of the
    reduced teeth in series, against the disks' reduced inertia J_A J_B / (J_A + J_B) / r_b^2
    (1 / (r_bA^2 / J_A + r_bB^2 / J_B) for unequal gears)."""
    base = red.base
    comp = 0.0
    for g in range(2):
        m = int(red.nr[g])
        k = red.kr[g, :m, :m]
        # unit normal load at mid-flank node along the line of action (in the tooth frame the
        # involute normal makes roughly the pressure angle with the tangent; use the local
        # flank normal from the neighbouring nodes)
        j = int(red.fl_len[g]) // 2
        xs = red.fl_xref[red.fl_start[g] : red.fl_start[g] + red.fl_len[g]]
        tan = xs[j + 1] - xs[j - 1]
        nrm = np.array([-tan[1], tan[0]]) / np.hypot(*tan)
        f = np.zeros(m)
        q = int(red.fl_map[red.fl_start[g] + j])
        f[q : q + 2] = nrm
        comp += float(f @ np.linalg.solve(k, f))
    ja, jb = base.inertia
    rb, rb_b = base.geometry[0].base_radius, base.geometry[1].base_radius
    if rb == rb_b:
        meq = ja * jb / (ja + jb) / rb**2
    else:  # equivalent mass of the two disks along the line of action
        meq = 1.0 / (rb**2 / ja + rb_b**2 / jb)
    return 2 * math.pi * math.sqrt(meq * comp)


def time_step_limit(red: ReducedPairModel, speeds) -> float:
    """Largest dt accepted by the large-step method [s] (see module docstring)."""
    om = max(abs(float(s)) for s in speeds)
    return min(red.contact_period / STEPS_PER_CONTACT_PERIOD, MAX_ROTATION_PER_STEP / om)


def simulate_reduced(
    red: ReducedPairModel,
    *,
    speeds,
    torque,
    theta_2,
    theta_s,
    span,
    dt,
    alpha=-0.05,
    tol=1e-12,
    max_iter=50,
    record_every=1,
    snapshots=0,
    progress=None,
    progress_every=2000,
    gain=(1.0, 1.0),
):
    """Integrate the reduced pair with HHT-alpha over a rotation ``span`` of gear A [rad].

    Parameters as :func:`rotaflex.gear.models.fe_pair.simulate` (``gain``: gear-ratio factor of each
    disk), plus ``alpha`` (HHT parameter in
    [-1/3, 0]; 0 = trapezoidal rule). ``tol`` [m] bounds the Newton displacement increment and
    the penetration of active contacts.
    """
    from rotaflex.gear.kernels.arrays import HHTParams, HHTRecords
    from rotaflex.gear.kernels.hht import RECORD_COLUMNS, run_hht
    from rotaflex.gear.solvers.drive_loop import SolverOutput, drive

    if not -1.0 / 3.0 <= alpha <= 0.0:
        raise InputError("solver.hht_alpha", alpha, "[-1/3, 0]")
    lim = time_step_limit(red, speeds)
    if dt > lim:
        raise InputError(
            "solver.dt",
            dt,
            f"<= {lim:.4g} s for the reduced implicit method "
            f"({STEPS_PER_CONTACT_PERIOD} steps per contact period "
            f"{red.contact_period:.3g} s and <= {MAX_ROTATION_PER_STEP} rad per step)",
        )
    base = red.base
    omega = np.asarray(speeds, dtype=float)
    n_steps = max(1, int(round(span / (omega[0] * dt))))
    tpar = np.array([torque, theta_2, theta_s, gain[0], gain[1]], dtype=float)
    m = _hht_model(red, alpha, dt)
    state = _initial_state(red, omega)
    z, phi, sc = state.z, state.phi, state.sc
    n_rec = n_steps // record_every + 1
    npair = red.pairs.shape[0]
    prm = HHTParams(
        dt=float(dt),
        alpha=float(alpha),
        tau0=float(tpar[0]),
        theta_2=float(tpar[1]),
        theta_s=float(tpar[2]),
        tol=float(tol),
        r_ref=float(max(g.tip_radius_ for g in base.geometry)),
        max_iter=int(max_iter),
        n_points=int(base.n_points),
        gain=np.asarray(gain, dtype=float),
    )
    info = np.zeros(4)
    rec = HHTRecords(out=np.zeros((n_rec, len(RECORD_COLUMNS))), outp=np.zeros((n_rec, npair)), info=info)
    if run_hht(0, record_every, 0, True, m, prm, state, rec)[0] != 0:
        raise ConvergenceError("contact search", 0.0, float("nan"), 0.0)
    e0 = float(info[3])
    row = [0]

    def step(nstep, first):
        status, row[0] = run_hht(nstep, record_every, row[0], False, m, prm, state, rec)
        return (5 if status == 1 else status), row[0]

    row, snaps, wall = drive(
        step,
        n_steps=n_steps,
        record_every=record_every,
        time_of=lambda: sc[0],
        positions=lambda: positions(red, z, phi),
        info=info,
        snapshots=snapshots,
        progress=progress,
        progress_every=progress_every,
    )
    out = rec.out[:row]
    records = {name: out[:, i].copy() for i, name in enumerate(RECORD_COLUMNS)}
    from rotaflex.gear.kernels.rk4 import PAIR_COLUMNS

    # one contact pair: its columns of the record are the per-pair histories
    pair_records = {name: records[name][:, None].copy() for name in PAIR_COLUMNS}
    return SolverOutput(
        records=records,
        pair_records=pair_records,
        tie_multipliers=np.zeros((row, 0)),
        steps=n_steps,
        wall_time=wall,
        initial_energy=e0,
        dt=dt,
        snapshots=snaps,
    )


def _hht_model(red: ReducedPairModel, alpha: float, dt: float):
    """Kernel arrays of the reduced pair with the Cholesky factors of the HHT iteration matrix
    ``M / (1 + alpha) + beta dt^2 K`` and of the mass matrix, per gear (padded to n + 1)."""
    from rotaflex.gear.kernels.arrays import HHTModel

    base = red.base
    n = red.mr.shape[1]
    beta = 0.25 * (1 - alpha) ** 2
    sfac = np.zeros((2, n + 1, n + 1))
    m0fac = np.zeros_like(sfac)
    for g in range(2):
        m = int(red.nr[g])
        mm = np.zeros((m + 1, m + 1))
        mm[:m, :m] = red.mr[g, :m, :m]
        mm[:m, m] = mm[m, :m] = red.hx[g, :m]
        mm[m, m] = base.inertia[g] + red.ix[g]
        kk = np.zeros_like(mm)
        kk[:m, :m] = red.kr[g, :m, :m]
        sfac[g, : m + 1, : m + 1] = np.linalg.cholesky(mm / (1 + alpha) + beta * dt * dt * kk)
        m0fac[g, : m + 1, : m + 1] = np.linalg.cholesky(mm)
    return HHTModel(
        nr=red.nr,
        fl_map=red.fl_map,
        mr=red.mr,
        kr=red.kr,
        gr=red.gr,
        hx=red.hx,
        cx=red.cx,
        ix=red.ix,
        inertia=np.asarray(base.inertia, float),
        sfac=sfac,
        m0fac=m0fac,
        fl_gear=red.fl_gear,
        fl_start=red.fl_start,
        fl_len=red.fl_len,
        fl_xref=red.fl_xref,
        centres=base.centres,
        theta0=np.asarray(base.theta0, float),
        sig=base.sig,
        pairs=red.pairs,
        rsgn=base.rsgn,
    )


def _initial_state(red: ReducedPairModel, omega: np.ndarray):
    """Undeformed start at the speeds ``omega`` [rad/s]; :func:`run_hht`'s first call (``init``)
    makes its accelerations consistent."""
    from rotaflex.gear.kernels.arrays import HHTState

    n = red.mr.shape[1]
    npair = red.pairs.shape[0]
    cres = np.zeros((npair, 8))
    cres[:, 0], cres[:, 1] = 0.3, 0.99
    return HHTState(
        z=np.zeros((2, n)),
        zd=np.zeros((2, n)),
        za=np.zeros((2, n)),
        phi=np.zeros(2),
        phid=np.array([omega[0], -omega[1]]),
        phia=np.zeros(2),
        p=np.zeros(npair),
        cres=cres,
        cnod=np.zeros((npair, 2, 3), dtype=np.int64),
        cw=np.zeros((npair, 2, 3)),
        fz=np.zeros((2, n)),
        fphi=np.zeros(2),
        sc=np.zeros(8),
    )


def positions(red: ReducedPairModel, z: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """Absolute node positions (N, 2) of both teeth from the reduced state."""
    base = red.base
    out = []
    for g in range(2):
        sel = base.gid == g
        w = (red.transform[g] @ z[g, : red.nr[g]]).reshape(-1, 2)
        u = base.xloc[sel] + w
        c, s = math.cos(base.theta0[g] + phi[g]), math.sin(base.theta0[g] + phi[g])
        out.append(
            np.column_stack(
                [base.centres[g, 0] + c * u[:, 0] - s * u[:, 1], base.centres[g, 1] + s * u[:, 0] + c * u[:, 1]]
            )
        )
    return np.vstack(out)
