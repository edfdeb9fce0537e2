"""Two or three elastic teeth per gear: the two-pair zones modelled directly (issue 3, part 3).

Model
-----
Each gear is a rigid disk carrying ``n`` (2 or 3) adjacent elastic teeth at the angular pitch
``2 pi / z``; every tooth is its own pitch-sector mesh (:func:`rotaflex.gear.mesh.build_tooth_mesh`)
whose root nodes (inner arc and side cuts) are tied to the disk, exactly as the single tooth of
:mod:`rotaflex.gear.dynamics`. Tooth ``j`` of A can touch tooth ``j`` of B only: ``n`` contact
pairs, each unilateral with its own contact search (minimum normal distance between the spline
surfaces), sliding terms and multiplier row in the paper's three-pass iteration
(:func:`rotaflex.gear.kernels_multi.run_steps_m`). Both disks carry the constant torque
``tau_0`` (drive on A, load on B): no Fig. 7 ramps.

Pair ``j`` has the contact angle ``psi_j + phi_A`` (rotation of A since that pair's geometric
start of contact), ``psi_j = (1 - j) * 2 pi / z``: pair 0 is the previous pair (it starts at
the beginning of its final two-pair zone), pair 1 is just entering contact, pair 2 (three
teeth) is the next one. Gear frames: the disk frame of each gear is the tooth frame of its
pair-1 tooth (placed as in the single-tooth model); tooth ``j`` of A is turned by ``+psi_j``,
of B by ``-psi_j`` (B turns clockwise).

Start: quasi-static preload. The loaded pairs' tooth deflections and B's rigid rotation are
found from the static balance of tau_0 (linear FE compliances of each pair at its contact
point, unilateral), so the run starts close to equilibrium instead of with a sudden torque.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from rotaflex.core.errors import ConvergenceError, InputError
from rotaflex.gear.dynamics import (
    GearPairModel,
    rigid_velocities,
    tie_eigen_bounds,
    torque_ramp,
)

#: default mesh window: pairs are searched from 1 deg before to 1 deg after their contact [rad]
WINDOW = math.radians(1.0)


@dataclass
class MultiToothModel(GearPairModel):
    """:class:`GearPairModel` with ``n_teeth`` teeth per gear and one contact pair per tooth."""

    n_teeth: int = 1
    pair_flank: np.ndarray | None = None  # (npair, 2, nfl) flank node ids, root -> tip
    pair_nedge: np.ndarray | None = None  # (npair, 2)
    pair_psi: np.ndarray | None = None  # (npair,) contact angle of each pair at t = 0 [rad]
    tooth_offset: np.ndarray | None = None  # (2, n) turn of each tooth in its disk frame [rad]
    tooth_node0: np.ndarray | None = None  # (2, n) first global node of each tooth
    initial_positions: np.ndarray | None = None  # (2N,) preloaded start state
    preload: dict | None = None


def _rot(t):
    c, s = math.cos(t), math.sin(t)
    return np.array([[c, -s], [s, c]])


def build_multi_model(
    geometry, mesh, n_teeth, *, youngs_modulus, poisson_ratio, density, inertia, n_points=61, start_angle=0.0
):
    """Two identical gears with ``n_teeth`` elastic teeth each.

    Placed (rigidly, unloaded) so that pair 1 is at the contact angle ``start_angle`` [rad]
    (0 = geometric start of contact, < 0 = before it; see module docstring).
    """
    from rotaflex.gear import dynamics, fe

    if n_teeth not in (1, 2, 3):
        raise InputError("model.teeth_per_gear", n_teeth, "1, 2 or 3")
    base = dynamics.build_model(
        geometry,
        geometry,
        mesh,
        mesh,
        youngs_modulus=youngs_modulus,
        poisson_ratio=poisson_ratio,
        density=density,
        inertia=inertia,
        n_points=n_points,
    )
    pitch = 2 * math.pi / geometry.teeth
    m_enter = min(1, n_teeth - 1)
    tooth_turn = np.array([(m_enter - j) * pitch for j in range(n_teeth)])
    psi = tooth_turn + start_angle
    base.theta0 = base.theta0 + np.array([start_angle, -start_angle])
    k0 = fe.stiffness_matrix(mesh, youngs_modulus, poisson_ratio).tocsr()
    m0 = fe.lumped_mass(mesh, density)[::2]
    nn = mesh.n_nodes
    roots = np.asarray(mesh.root_nodes, dtype=np.int64)
    fl0 = np.asarray(mesh.flank_nodes["left"], dtype=np.int64)
    xl, gid, minv, ks, tie_node, tie_gear = [], [], [], [], [], []
    tb_i, tb_j, tb_b = [], [], []
    offsets = np.zeros((2, n_teeth))
    node0 = np.zeros((2, n_teeth), dtype=np.int64)
    off = 0
    ntie = 0
    for g in range(2):
        for j in range(n_teeth):
            ang = tooth_turn[j] if g == 0 else -tooth_turn[j]
            offsets[g, j] = ang
            node0[g, j] = off
            r = _rot(ang)
            if ang == 0.0:
                k = k0.copy()
            else:
                t = sp.block_diag([r] * nn, format="csr")
                k = (t @ k0 @ t.T).tocsr()
            xl.append(mesh.nodes @ r.T)
            gid.append(np.full(nn, g))
            minv.append(1.0 / m0)
            ks.append(k)
            tie_node.append(roots + off)
            tie_gear.append(np.full(len(roots), g))
            bi, bj, bb = dynamics._tie_blocks(k, roots, ntie)
            tb_i += bi
            tb_j += bj
            tb_b += bb
            off += nn
            ntie += len(roots)
    pair_flank = np.zeros((n_teeth, 2, len(fl0)), dtype=np.int64)
    for j in range(n_teeth):
        for g in range(2):
            pair_flank[j, g] = fl0 + node0[g, j]
    nedge = (len(fl0) - 1) // 2
    model = MultiToothModel(
        geometry=base.geometry,
        meshes=base.meshes,
        centre_distance=base.centre_distance,
        theta0=base.theta0.copy(),
        centres=base.centres,
        xloc=np.ascontiguousarray(np.vstack(xl)),
        gid=np.concatenate(gid).astype(np.int64),
        minv=np.concatenate(minv),
        stiffness=sp.block_diag(ks, format="csr"),
        tie_node=np.concatenate(tie_node).astype(np.int64),
        tie_gear=np.concatenate(tie_gear).astype(np.int64),
        tb_i=np.array(tb_i, dtype=np.int64),
        tb_j=np.array(tb_j, dtype=np.int64),
        tb_b=np.ascontiguousarray(np.array(tb_b, dtype=float).reshape(-1, 2, 2)),
        flank=pair_flank[min(1, n_teeth - 1)].copy(),
        nedge=np.array([nedge, nedge]),
        sig=base.sig,
        inertia=base.inertia,
        rsgn=base.rsgn,
        n_points=base.n_points,
        dt_limit=base.dt_limit,
        n_teeth=n_teeth,
        pair_flank=pair_flank,
        pair_nedge=np.full((n_teeth, 2), nedge, dtype=np.int64),
        pair_psi=psi,
        tooth_offset=offsets,
        tooth_node0=node0,
    )
    model.initial_positions = model.reference_positions()
    return model


def involute_start(model: MultiToothModel, psi: float) -> tuple[float, float]:
    """Flank parameters (a, b) of the rigid involute contact point at contact angle ``psi``.

    Used as the warm start of each pair's contact search; ``psi`` is clamped to the path of
    contact (a pair out of mesh starts from its nearest end of contact).
    """
    from rotaflex.gear.kernels import sample_flank

    g = model.geometry[0]
    rb = g.base_radius
    a = model.centre_distance
    length = math.sqrt(a * a - (2 * rb) ** 2)
    ra = g.tip_radius_
    s_end = math.sqrt(ra**2 - rb**2)
    s_start = length - s_end
    s = min(max(s_start + rb * psi, s_start), s_end)
    r_a = math.hypot(rb, s)
    r_b = math.hypot(rb, length - s)
    mesh = model.meshes[0]
    pts = np.empty((model.n_points, 2))
    fl = np.asarray(mesh.flank_nodes["left"], dtype=np.int64)
    sample_flank(mesh.nodes.ravel().copy(), fl, (len(fl) - 1) // 2, pts)
    rad = np.maximum.accumulate(np.hypot(pts[:, 0], pts[:, 1]))
    rad = rad + 1e-12 * np.arange(len(rad))
    par = np.linspace(0.0, 1.0, model.n_points)
    return float(np.interp(r_a, rad, par)), float(np.interp(r_b, rad, par))


def pair_geometry(model: MultiToothModel, x: np.ndarray, start=None, phi_a: float = 0.0, theta_s: float | None = None):
    """Contact search of every pair at positions ``x``: (cres (npair, 8), cnod, cw).

    ``start`` (npair, 2) warm starts; default: the involute contact point of each pair at
    gear A's rotation ``phi_a`` (:func:`involute_start`). With ``theta_s`` given, pairs before
    the start / after the end of contact use the tip-corner projection, as in the solver.
    """
    from rotaflex.gear.kernels_multi import pair_contact

    npair = model.n_teeth
    m = model.n_points
    cres = np.zeros((npair, 8))
    cnod = np.zeros((npair, 2, 3), dtype=np.int64)
    cw = np.zeros((npair, 2, 3))
    for j in range(npair):
        if start is None:
            cres[j, 0], cres[j, 1] = involute_start(model, model.pair_psi[j] + phi_a)
        else:
            cres[j, 0], cres[j, 1] = start[j]
        buf = [np.empty((m, 2)) for _ in range(4)]
        psi = model.pair_psi[j] + phi_a
        mode = 0 if theta_s is None else (1 if psi < 0 else (2 if psi > theta_s else 0))
        if not pair_contact(
            x, model.pair_flank[j], model.pair_nedge[j], model.sig, m, *buf, cres[j], cnod[j], cw[j], mode
        ):
            raise ConvergenceError("contact search", 0.0, float("nan"), 0.0)
    return cres, cnod, cw


def _positions(model, theta0, u_local):
    """Global positions for disk orientations ``theta0`` and tooth-frame displacements."""
    x = np.empty((model.n_nodes, 2))
    nn = model.meshes[0].n_nodes
    for g in range(2):
        for j in range(model.n_teeth):
            a = model.tooth_node0[g, j]
            r = _rot(theta0[g] + model.tooth_offset[g, j])
            x[a : a + nn] = model.centres[g] + (model.meshes[0].nodes + u_local[g, j]) @ r.T
    return x.ravel()


def static_preload(
    model: MultiToothModel,
    torque: float,
    youngs_modulus: float,
    poisson_ratio: float,
    theta_s: float,
    window: float = WINDOW,
    n_iter: int = 4,
    start=None,
) -> dict:
    """Quasi-static start: deflect the loaded pairs and turn B so the pairs carry ``torque``.

    Linear statics per tooth (root nodes fixed to the disk) with a unit normal point force
    distributed as in the dynamics (quadratic edge shape functions); the pair forces
    ``P_j = max(0, (beta d_j - h_j) / c_j)`` (h_j rigid gap, d_j moment arm about B's centre,
    c_j pair compliance) balance ``torque`` on B; pairs outside the mesh window
    ``[-window, theta_s + window]`` of contact angles are ignored. Repeated ``n_iter`` times with the gaps of the
    deformed state. Sets ``model.theta0`` (B) and ``model.initial_positions``; returns the pair
    forces, compliances and the final gaps.
    """
    from rotaflex.gear.static import solve_static

    mesh = model.meshes[0]
    nn = mesh.n_nodes
    npair = model.n_teeth
    theta_ref = model.theta0.copy()
    u = np.zeros((2, npair, nn, 2))
    x = _positions(model, theta_ref, u)
    inmesh = (model.pair_psi >= -window) & (model.pair_psi <= theta_s + window)
    cres, cnod, cw = pair_geometry(model, x, start=start, theta_s=theta_s)
    cres[~inmesh, 2] = 1.0
    comp = np.ones(npair)
    unit = np.zeros((2, npair, nn, 2))
    arm = np.zeros(npair)
    for j in np.where(inmesh)[0]:
        n = cres[j, 3:5]
        disp = []
        for g in range(2):
            r = _rot(theta_ref[g] + model.tooth_offset[g, j])
            nl = r.T @ n
            f = np.zeros(2 * nn)
            sgn = -1.0 if g == 0 else 1.0
            for q in range(3):
                i = cnod[j, g, q] - model.tooth_node0[g, j]
                f[2 * i : 2 * i + 2] += sgn * cw[j, g, q] * nl
            ul = solve_static(mesh, f, youngs_modulus, poisson_ratio).reshape(-1, 2)
            unit[g, j] = ul
            ug = ul @ r.T
            disp.append(sum(cw[j, g, q] * (n @ ug[cnod[j, g, q] - model.tooth_node0[g, j]]) for q in range(3)))
        comp[j] = disp[1] - disp[0]
        xb = np.array([sum(cw[j, 1, q] * x[2 * cnod[j, 1, q] + d] for q in range(3)) for d in range(2)])
        rb_vec = xb - model.centres[1]
        arm[j] = -(rb_vec[0] * n[1] - rb_vec[1] * n[0])
    arm[~inmesh] = np.max(arm[inmesh])
    h_eff = cres[:, 2].copy()
    beta = 0.0
    pj = np.zeros(npair)
    for _ in range(n_iter):

        def bal(b, h=h_eff):
            return np.sum(np.maximum(0.0, (b * arm - h) / comp) * arm) - torque

        lo = float(np.min(h_eff / arm))
        hi = lo + max(torque * np.max(comp) / np.min(arm) ** 2, 1e-12)
        while bal(hi) < 0.0:
            hi = lo + 2 * (hi - lo)
        from scipy.optimize import brentq

        beta = brentq(bal, lo, hi, xtol=1e-16, rtol=1e-15) if torque > 0 else 0.0
        pj = np.maximum(0.0, (beta * arm - h_eff) / comp)
        for j in range(npair):
            for g in range(2):
                u[g, j] = pj[j] * unit[g, j]
        th = theta_ref.copy()
        th[1] += beta
        x = _positions(model, th, u)
        c2, _, _ = pair_geometry(model, x, start=cres[:, :2], theta_s=theta_s)
        c2[~inmesh, 2] = 1.0
        pred = np.where(pj > 0, 0.0, h_eff - beta * arm)
        h_eff = h_eff + (c2[:, 2] - pred)
    model.theta0 = th
    model.initial_positions = x
    model.preload = {"force": pj, "compliance": comp, "arm": arm, "gap": c2[:, 2], "beta": beta}
    return model.preload


def strain_energy(model: GearPairModel, x: np.ndarray) -> float:
    """Strain energy 1/2 w^T K w of the co-rotational displacements at positions ``x`` [J]."""
    xr = x.reshape(-1, 2)
    w = np.empty_like(xr)
    for g in range(2):
        sel = model.gid == g
        r = _rot(model.theta0[g])
        w[sel] = (xr[sel] - model.centres[g]) @ r - model.xloc[sel]
    w = w.ravel()
    return float(0.5 * w @ (model.stiffness @ w))


@dataclass
class MultiOutput:
    """Raw histories returned by :func:`simulate_multi`."""

    records: dict  # global name -> (n_rec,)
    pair_records: dict  # per-pair name -> (n_rec, npair)
    tie_multipliers: np.ndarray
    steps: int
    wall_time: float
    initial_energy: float
    dt: float


def warm_start_table(model: MultiToothModel, theta_s: float, n: int = 61) -> np.ndarray:
    """(n, 3): involute contact parameters (a, b) on a uniform grid of the contact angle."""
    ang = np.linspace(0.0, theta_s, n)
    return np.array([[*involute_start(model, t), t] for t in ang])


def simulate_multi(
    model: MultiToothModel,
    *,
    speeds_rpm,
    torque,
    theta_2,
    theta_s,
    span,
    dt,
    torque_mode=1,
    window=WINDOW,
    tol=1e-12,
    n_accel=4,
    max_iter=500,
    record_every=10,
    progress=None,
    progress_every=2000,
) -> MultiOutput:
    """Integrate the multi-tooth pair over a rotation ``span`` of gear A [rad].

    Same scheme and parameters as :func:`rotaflex.gear.dynamics.simulate`; ``torque_mode`` 1
    applies the constant ``torque`` to both disks, 0 the Fig. 7 ramps (for the comparison with
    the single-tooth kernel). A pair is searched only while its nominal contact angle is within
    ``[-window, theta_s + window]`` (``window=None``: always, as the single-tooth model).
    Starts from ``model.initial_positions`` rotating rigidly.
    """
    from rotaflex.gear.kernels import kinetic_energy
    from rotaflex.gear.kernels_multi import GLOBAL_COLUMNS, PAIR_COLUMNS, run_steps_m

    if dt > model.dt_limit:
        raise InputError(
            "solver.dt",
            dt,
            f"a step <= the RK4 stability limit of the mesh, {model.dt_limit:.4g} s"
            " (refine dt or coarsen the smallest elements)",
        )
    omega = np.array(speeds_rpm, dtype=float) * 2 * math.pi / 60
    n_steps = max(1, int(round(span / (omega[0] * dt))))
    eps = tie_eigen_bounds(model, dt)
    k = model.stiffness
    x = model.initial_positions.copy()
    nn = model.n_nodes
    npair = model.n_teeth
    om = np.array([omega[0], -omega[1]])
    v = rigid_velocities(model, x, om)
    a = np.zeros(2 * nn)
    alp = np.zeros(2)
    phi = np.zeros(2)
    nc = 2 * len(model.tie_node) + npair
    mu = np.zeros(nc)
    cres = np.zeros((npair, 8))
    for j in range(npair):
        cres[j, 0], cres[j, 1] = involute_start(model, model.pair_psi[j])
    cnod = np.zeros((npair, 2, 3), dtype=np.int64)
    cw = np.zeros((npair, 2, 3))
    sc = np.zeros(24)
    spair = np.zeros((npair, 6))
    n_rec = n_steps // record_every + 1
    out = np.zeros((n_rec, len(GLOBAL_COLUMNS)))
    outp = np.zeros((n_rec, npair, len(PAIR_COLUMNS)))
    out_mu = np.zeros((n_rec, nc - npair))
    info = np.zeros(4)
    lo, hi = (-1e9, 1e9) if window is None else (-window, theta_s + window)
    par = np.array(
        [dt, torque, theta_2, theta_s, tol, tol / dt, tol / dt**2, *eps, lo, hi, 0.0 if window is None else 1.0]
    )
    wtab = warm_start_table(model, theta_s)
    args_model = (
        model.gid,
        k.indptr.astype(np.int64),
        k.indices.astype(np.int64),
        model.tie_node,
        model.tie_gear,
        model.pair_flank,
        model.pair_nedge,
        model.tb_i,
        model.tb_j,
        model.xloc,
        model.minv,
        k.data.astype(float),
        model.centres,
        model.theta0,
        model.inertia,
        model.sig,
        model.tb_b,
        model.rsgn,
        model.pair_psi,
        wtab,
    )
    e0 = kinetic_energy(v, om, model.minv, model.inertia) + strain_energy(model, x)
    chunk = max(record_every, (progress_every // record_every) * record_every)
    rates = np.zeros((len(model.pair_psi), 4))  # contact-parameter rates, carried across calls
    names = {1: "displacement pass (eq. 19)", 2: "velocity pass (eq. 20)", 3: "acceleration pass (eq. 21)"}
    t0 = time.perf_counter()
    done = 0
    row = 0
    first = True
    while done < n_steps:
        n = min(chunk, n_steps - done)
        ipar = np.array([n_accel, max_iter, model.n_points, row, 1 if first else 0, torque_mode], dtype=np.int64)
        status, row = run_steps_m(
            n,
            record_every,
            *args_model,
            par,
            ipar,
            x,
            v,
            a,
            phi,
            om,
            alp,
            mu,
            cres,
            cnod,
            cw,
            sc,
            spair,
            rates,
            out,
            outp,
            out_mu,
            info,
        )
        first = False
        if status in names:
            raise ConvergenceError(names[status], info[0], info[1], info[2])
        if status == 4:
            raise ConvergenceError("contact search", info[0], float("nan"), 0.0)
        done += n
        if progress is not None:
            progress(done, n_steps)
    wall = time.perf_counter() - t0
    return MultiOutput(
        records={name: out[:row, i].copy() for i, name in enumerate(GLOBAL_COLUMNS)},
        pair_records={name: outp[:row, :, i].copy() for i, name in enumerate(PAIR_COLUMNS)},
        tie_multipliers=out_mu[:row].copy(),
        steps=n_steps,
        wall_time=wall,
        initial_energy=float(e0),
        dt=dt,
    )


# ----------------------------------------------------------------------------- case / output
def default_span(n_teeth: int, pitch: float, theta_s: float, start_angle: float) -> float:
    """Rotation of A simulated by default: pair 1 from its start angle up to the entry of the
    next pair (two teeth) or over its whole contact theta_s (three teeth) [rad]."""
    return (pitch if n_teeth == 2 else theta_s) - start_angle


def run_multi_case(cfg, *, progress: bool = False):
    """``run_case`` for ``[model] teeth_per_gear`` = 2 or 3 (validated ``GearCaseConfig``)."""
    import json
    from dataclasses import asdict

    from rotaflex.gear.case import DEFAULT_DT, GearResult, build, run_message
    from rotaflex.gear.geometry import contact_angles

    t_wall = time.perf_counter()
    sol = cfg.solver
    # the multi-pair kernel implements the paper's scheme only (one pass type per pair row)
    for key, value, allowed in (
        ("solver.method", sol.method, "paper_rk4"),
        ("solver.multipliers", sol.multipliers, "iterative"),
        ("solver.restitution", sol.restitution, 0.0),
        ("operation.driver", cfg.operation.driver, "A"),
    ):
        if value != allowed:
            raise InputError(key, value, f"{allowed!r} with [model] teeth_per_gear > 1")
    geo, mesh, _ = build(cfg)
    n = cfg.model.teeth_per_gear
    start = math.radians(cfg.model.start_angle_deg)
    window = math.radians(cfg.model.mesh_window_deg)
    if start < -window:
        raise InputError(
            "model.start_angle_deg", cfg.model.start_angle_deg, f">= -mesh_window_deg = {-cfg.model.mesh_window_deg:g}"
        )
    ths, th2 = contact_angles(geo, geo)
    op = cfg.operation
    if op.theta_s_deg is not None:
        ths = math.radians(op.theta_s_deg)
    if op.theta_2_deg is not None:
        th2 = math.radians(op.theta_2_deg)
    pitch = 2 * math.pi / geo.teeth
    limit = (n - 1) * pitch - start
    span = math.radians(op.span_deg) if op.span_deg is not None else default_span(n, pitch, ths, start)
    if span > limit * (1 + 1e-9):
        raise InputError(
            "operation.span_deg",
            math.degrees(span),
            f"<= {math.degrees(limit):.4g} deg with {n} teeth per gear (beyond it "
            "a pair of teeth that is not modelled would be in contact)",
        )
    mat = cfg.material
    model = build_multi_model(
        geo,
        mesh,
        n,
        youngs_modulus=mat.youngs_modulus,
        poisson_ratio=mat.poisson_ratio,
        density=mat.density,
        inertia=(cfg.disk_inertia, cfg.disk_inertia),
        n_points=cfg.mesh.n_points,
        start_angle=start,
    )
    static_preload(model, op.torque, mat.youngs_modulus, mat.poisson_ratio, ths, window)
    bar = None
    cb = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=1, unit="step", desc=f"gear {n} teeth")

        def cb(done, total):
            bar.total = total
            bar.n = done
            bar.refresh()

    try:
        out = simulate_multi(
            model,
            speeds_rpm=op.speed_rpm,
            torque=op.torque,
            theta_2=th2,
            theta_s=ths,
            span=span,
            dt=sol.dt or DEFAULT_DT["paper_rk4"],
            window=window,
            tol=cfg.solver.tolerance,
            n_accel=cfg.solver.accel_n,
            max_iter=cfg.solver.max_iter,
            record_every=cfg.output.every or 10,
            progress=cb,
        )
    finally:
        if bar is not None:
            bar.close()
    ds = to_dataset_multi(out, model, geo, op.torque, th2, ths)
    ds.attrs.update(
        status="success",
        message=run_message(ds),
        wall_time=time.perf_counter() - t_wall,
        config=json.dumps(asdict(cfg)),
    )
    return GearResult(ds)


def zone_pairs(pair_angle: np.ndarray, theta_s: float) -> np.ndarray:
    """Number of pairs nominally in contact (contact angle in [0, theta_s]) per record."""
    return np.sum((pair_angle >= 0.0) & (pair_angle <= theta_s), axis=1)


def to_dataset_multi(out: MultiOutput, model: MultiToothModel, geo, tau0, th2, ths):
    """Histories of :func:`simulate_multi` as an xarray Dataset with a ``pair`` dimension."""
    import xarray as xr

    from rotaflex.gear.case import add_constraint_histories, run_scalars

    r = out.records
    pr = out.pair_records
    rb = geo.base_radius
    nominal = tau0 / rb
    npair = model.n_teeth
    rot = np.column_stack([r["phi_A"], -r["phi_B"]])
    pair_angle = model.pair_psi[None, :] + rot[:, :1]
    force = pr["force"]
    total = force.sum(axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        share = np.where(total[:, None] > 0, force / total[:, None], np.nan)
    insearch = pr["contact_case"] >= 0
    gap = np.where(insearch, pr["gap"], np.nan)
    balance = (
        r["kinetic_energy"] + r["strain_energy"] - r["external_work"] + r["velocity_pass_loss"] - out.initial_energy
    )
    ds = xr.Dataset(
        coords={
            "time": ("time", r["time"], {"units": "s"}),
            "gear": ["A", "B"],
            "xy": ["x", "y"],
            "pair": np.arange(npair),
        }
    )

    def add(name, dims, val, units, long):
        ds[name] = (dims, np.asarray(val), {"units": units, "long_name": long})

    add("contact_force", ("time", "pair"), force, "N", "contact force of each pair (acceleration pass)")
    add(
        "contact_force_displacement_pass",
        ("time", "pair"),
        pr["force_disp"],
        "N",
        "contact force of the displacement pass",
    )
    add(
        "contact_force_velocity_pass",
        ("time", "pair"),
        pr["force_vel"],
        "N",
        "contact force of the velocity pass (impulse / dt at impacts)",
    )
    add(
        "peak_force_interval",
        ("time", "pair"),
        pr["force_peak"],
        "N",
        "largest contact force since the previous record",
    )
    add("total_contact_force", ("time",), total, "N", "sum of the pair forces")
    add("load_share", ("time", "pair"), share, "1", "pair force / sum of pair forces")
    add(
        "pair_angle",
        ("time", "pair"),
        pair_angle,
        "rad",
        "contact angle of each pair (rotation of A since its geometric start of contact)",
    )
    add(
        "fig7_ramp_force",
        ("time", "pair"),
        torque_ramp(pair_angle, tau0, th2, ths) / rb,
        "N",
        "force of the pair implied by the Fig. 7 torque ramps, tau(angle)/r_b",
    )
    add("nominal_force_ramp", ("time",), np.full(len(total), nominal), "N", "tau_0 / r_b (constant torques)")
    add("rotation_angle", ("time", "gear"), rot, "rad", "rotation angle (running direction)")
    add(
        "angular_velocity",
        ("time", "gear"),
        np.column_stack([r["omega_A"], -r["omega_B"]]),
        "rad/s",
        "angular velocity",
    )
    add(
        "torque",
        ("time", "gear"),
        np.column_stack([r["torque_A"], r["torque_B"]]),
        "N m",
        "external torque (drive on A, load on B)",
    )
    add("gap", ("time", "pair"), gap, "m", "normal gap (> 0 open; NaN: pair out of mesh)")
    add("normal_velocity", ("time", "pair"), pr["normal_velocity"], "m/s", "relative normal velocity (> 0 approaching)")
    cp = np.stack(
        [np.stack([pr["cpA_x"], pr["cpA_y"]], axis=-1), np.stack([pr["cpB_x"], pr["cpB_y"]], axis=-1)], axis=2
    )
    add("contact_point", ("time", "pair", "gear", "xy"), cp, "m", "contact point")
    add(
        "contact_case",
        ("time", "pair"),
        pr["contact_case"],
        "1",
        "0 flank-flank, 1 tip of B on A, 2 tip of A on B, -1 out of mesh (not searched)",
    )
    add_constraint_histories(add, r, out.tie_multipliers, balance)
    nz = zone_pairs(pair_angle, ths)
    single = nz == 1
    mean_single = float(np.mean(total[single])) if np.any(single) else float("nan")
    peak = float(np.max(pr["force_peak"])) if len(total) else 0.0
    scalars = run_scalars(out, r, balance, peak=peak, mean_single=mean_single, nominal=nominal, rb=rb, th2=th2, ths=ths)
    scalars.update(
        {
            "mean_total_force": (float(np.mean(total)) if len(total) else float("nan"), "N"),
            "teeth_per_gear": (npair, "1"),
            "preload_beta": (float(model.preload["beta"]) if model.preload else 0.0, "rad"),
        }
    )
    for name, (val, unit) in scalars.items():
        ds[name] = ((), val, {"units": unit})
    if model.preload:
        ds["preload_force"] = (("pair",), model.preload["force"], {"units": "N"})
    return ds


def plot_multi(ds) -> dict:
    """Figures of a multi-tooth result: pair forces vs the Fig. 7 ramps, load share, energy."""
    from rotaflex.core.plotting import new_figure
    from rotaflex.gear.case import ANGLE_LABEL, history_figures, line_figure

    figs = {}
    ang = np.degrees(ds["rotation_angle"].sel(gear="A").values)
    fig, ax = new_figure()
    for j in ds["pair"].values:
        (line,) = ax.plot(ang, ds["contact_force"].sel(pair=j).values, lw=0.8, label=f"pair {j}")
        ax.plot(ang, ds["fig7_ramp_force"].sel(pair=j).values, "--", lw=0.7, color=line.get_color())
    ax.plot(ang, ds["total_contact_force"].values, "k", lw=0.6, label="sum")
    ax.axhline(float(ds["nominal_force"]), color="grey", lw=0.5)
    ax.set_xlabel("rotation angle of gear A [deg]")
    ax.set_ylabel("contact force [N] (dashed: Fig. 7 ramps)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    figs["contact_force"] = fig
    figs["load_share"] = line_figure(ang, ds["load_share"].values, ANGLE_LABEL, "load share of each pair [-]")
    figs.update(history_figures(ds, "normal gap of each pair [um]"))
    return figs
