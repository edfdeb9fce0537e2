"""Several elastic teeth per gear: the two-pair zones and continuous meshing modelled directly.

Model
-----
Each gear ``g`` is a rigid disk carrying ``n`` (2 to 12) adjacent elastic teeth at its angular
pitch ``2 pi / z_g``; every tooth is its own pitch-sector mesh of that gear
(:func:`rotaflex.gear.pair.tooth_mesh.build_tooth_mesh`, per-gear material) whose root nodes (inner arc
and side cuts) are tied to the disk, exactly as the single tooth of
:mod:`rotaflex.gear.models.fe_pair`. The gears may differ (a ``[pinion]``/``[wheel]`` pair: teeth,
profile shift, reliefs, blanks, working centre distance); gear A is the driver. Tooth ``j`` of
A can touch tooth ``j`` of B only: ``n`` contact pairs, each unilateral with its own contact
search (minimum normal distance between the spline surfaces), sliding terms and multiplier row
in the paper's three-pass iteration (:func:`rotaflex.gear.kernels.rk4.run_steps`). The disks
carry constant torques (drive ``tau_0`` on A, load ``tau_0 z_B / z_A`` on B): no Fig. 7 ramps.

Pair ``j`` has the contact angle ``psi_j + phi_A`` (rotation of the driver A since that pair's
geometric start of contact), ``psi_j = (1 - j) * 2 pi / z_A``: pair 0 is the previous pair (it
starts at the beginning of its final two-pair zone), pair 1 is just entering contact, pair 2
(three teeth) is the next one. Gear frames: the disk frame of each gear is the tooth frame of
its pair-1 tooth (placed as in the single-tooth model); tooth ``j`` of A is turned by
``+(1 - j) 2 pi / z_A``, of B by ``-(1 - j) 2 pi / z_B`` (B turns clockwise).

Start: quasi-static preload. The loaded pairs' tooth deflections and B's rigid rotation are
found from the static balance of B's load torque (linear FE compliances of each pair at its
contact point, unilateral), so the run starts close to equilibrium instead of with a sudden
torque.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
import scipy.sparse as sp

from rotaflex.core.errors import ConvergenceError, InputError
from rotaflex.gear.models.fe_pair import (
    GearPairModel,
)

#: default mesh window: pairs are searched from 1 deg before to 1 deg after their contact [rad]
WINDOW = 0.017453292519943295  # 1 deg


@dataclass(frozen=True)
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

    #: constant tau_0 on both disks (no Fig. 7 ramps)
    constant_torque = True

    def pair_layout(self):
        """Pairs of adjacent teeth, warm-started at the involute point, preloaded start."""
        start = np.array([involute_start(self, p) for p in self.pair_psi])
        return (
            self.pair_flank,
            self.pair_nedge,
            np.asarray(self.pair_psi, float),
            start,
            self.initial_positions.copy(),
        )

    def warm_start_table(self, theta_s: float, n: int = 61) -> np.ndarray:
        """(n, 3): involute contact parameters (a, b) on a uniform grid of the contact angle."""
        ang = np.linspace(0.0, theta_s, n)
        return np.array([[*involute_start(self, t), t] for t in ang])

    def start_strain_energy(self, x: np.ndarray) -> float:
        return strain_energy(self, x)


def _rot(t):
    c, s = math.cos(t), math.sin(t)
    return np.array([[c, -s], [s, c]])


def _pair_of(value) -> tuple:
    """(A, B) of a geometry or mesh given once for both gears or as a pair."""
    return tuple(value) if isinstance(value, (tuple, list)) else (value, value)


def build_multi_model(
    geometry,
    mesh,
    n_teeth,
    *,
    youngs_modulus,
    poisson_ratio,
    density,
    inertia,
    n_points=61,
    start_angle=0.0,
    centre_distance=None,
):
    """Two gears with ``n_teeth`` elastic teeth each.

    Placed (rigidly, unloaded) so that pair 1 is at the contact angle ``start_angle`` [rad]
    (0 = geometric start of contact, < 0 = before it; see module docstring).

    Parameters
    ----------
    geometry, mesh : GearGeometry, ToothMesh or (A, B) pairs of them
        One value: identical gears; a pair: gear A (driver) and gear B, which may differ (teeth,
        profile shift, reliefs, mesh). Tooth ``j`` of gear ``g`` is turned by its own angular
        pitch ``2 pi / z_g``.
    youngs_modulus, poisson_ratio, density : float or (float, float)
        E [Pa], nu [-], rho [kg/m^3]; one value for both gears or one per gear (A, B).
    inertia : (float, float)
        Disk polar inertia of A and B [kg m^2].
    n_points : int
        Spline data points per flank.
    start_angle : float
        Contact angle of pair 1 at t = 0 [rad] (rotation of A); B is turned by
        ``start_angle r_bA / r_bB`` (conjugate rigid motion).
    centre_distance : float or None
        Working centre distance [m] (default: the no-backlash one, as
        :func:`rotaflex.gear.models.fe_pair.build_model`).

    Examples
    --------
    >>> from rotaflex.gear.pair.geometry import GearGeometry
    >>> from rotaflex.gear.pair.tooth_mesh import COARSE, build_tooth_mesh
    >>> g = GearGeometry(module=3.175e-3, teeth=28, face_width=6.35e-3, tip_radius=0.047625, root_radius=0.04048)
    >>> m = build_tooth_mesh(g, **COARSE)
    >>> mm = build_multi_model(g, m, 2, youngs_modulus=210e9, poisson_ratio=0.3, density=7800.0,
    ...                        inertia=(3e-4, 3e-4))
    >>> mm.pair_psi.round(4).tolist()
    [0.2244, 0.0]
    """
    from rotaflex.gear.models import fe_pair as dynamics
    from rotaflex.gear.pair import plane_stress as fe

    if not 1 <= n_teeth <= 12:
        raise InputError("model.teeth_per_gear", n_teeth, "1..12")
    geos, meshes = _pair_of(geometry), _pair_of(mesh)
    mats = [dynamics._per_gear(v) for v in (youngs_modulus, poisson_ratio, density)]
    base = dynamics.build_model(
        *geos,
        *meshes,
        youngs_modulus=youngs_modulus,
        poisson_ratio=poisson_ratio,
        density=density,
        inertia=inertia,
        n_points=n_points,
        centre_distance=centre_distance,
    )
    m_enter = min(1, n_teeth - 1)
    # turn of tooth j in its disk frame: A counter-clockwise, B clockwise, each by its own pitch
    tooth_turn = [np.array([(m_enter - j) * 2 * math.pi / g.teeth for j in range(n_teeth)]) for g in geos]
    psi = tooth_turn[0] + start_angle
    fl0 = [np.asarray(m.flank_nodes["left"], dtype=np.int64) for m in meshes]
    nfl = max(len(f) for f in fl0)
    xl, gid, minv, ks, tie_node, tie_gear = [], [], [], [], [], []
    tb_i, tb_j, tb_b = [], [], []
    offsets = np.zeros((2, n_teeth))
    node0 = np.zeros((2, n_teeth), dtype=np.int64)
    pair_flank = np.zeros((n_teeth, 2, nfl), dtype=np.int64)
    off = 0
    ntie = 0
    for g in range(2):
        msh = meshes[g]
        k0 = fe.stiffness_matrix(msh, mats[0][g], mats[1][g]).tocsr()
        m0 = fe.lumped_mass(msh, mats[2][g])[::2]
        nn = msh.n_nodes
        roots = np.asarray(msh.root_nodes, dtype=np.int64)
        for j in range(n_teeth):
            ang = tooth_turn[g][j] if g == 0 else -tooth_turn[g][j]
            offsets[g, j] = ang
            node0[g, j] = off
            pair_flank[j, g, : len(fl0[g])] = fl0[g] + off
            r = _rot(ang)
            if ang == 0.0:
                k = k0.copy()
            else:
                t = sp.block_diag([r] * nn, format="csr")
                k = (t @ k0 @ t.T).tocsr()
            xl.append(msh.nodes @ r.T)
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
    nedge = np.array([(len(f) - 1) // 2 for f in fl0], dtype=np.int64)
    # B turns by the conjugate angle (exactly -start_angle for identical gears)
    ratio = geos[0].base_radius / geos[1].base_radius
    model = MultiToothModel(
        geometry=base.geometry,
        meshes=base.meshes,
        centre_distance=base.centre_distance,
        theta0=base.theta0 + np.array([start_angle, -start_angle * ratio]),
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
        flank=pair_flank[m_enter].copy(),
        nedge=nedge,
        sig=base.sig,
        inertia=base.inertia,
        rsgn=base.rsgn,
        n_points=base.n_points,
        dt_limit=base.dt_limit,
        n_teeth=n_teeth,
        pair_flank=pair_flank,
        pair_nedge=np.tile(nedge, (n_teeth, 1)),
        pair_psi=psi,
        tooth_offset=offsets,
        tooth_node0=node0,
    )
    return replace(model, initial_positions=model.reference_positions())


def involute_start(model: MultiToothModel, psi: float) -> tuple[float, float]:
    """Flank parameters (a, b) of the rigid involute contact point at contact angle ``psi``.

    Used as the warm start of each pair's contact search; ``psi`` [rad] is the rotation of A
    since the pair's start of contact, clamped to the path of contact (a pair out of mesh
    starts from its nearest end of contact). Along the line of action from A's tangency point
    (length ``sqrt(a^2 - (r_bA + r_bB)^2)`` at the working centre distance ``a``) the contact
    point is at ``s = s_start + r_bA psi``, at radius ``hypot(r_bA, s)`` on A and
    ``hypot(r_bB, length - s)`` on B; each radius is looked up on its gear's FE flank.
    """
    from rotaflex.gear.kernels.contact import sample_flank

    rb = [g.base_radius for g in model.geometry]
    a = model.centre_distance
    length = math.sqrt(a * a - (rb[0] + rb[1]) ** 2)
    s_end = math.sqrt(model.geometry[0].tip_radius_ ** 2 - rb[0] ** 2)
    s_start = length - math.sqrt(model.geometry[1].tip_radius_ ** 2 - rb[1] ** 2)
    s = min(max(s_start + rb[0] * psi, s_start), s_end)
    radius = (math.hypot(rb[0], s), math.hypot(rb[1], length - s))
    par = np.linspace(0.0, 1.0, model.n_points)
    out = []
    for mesh, r in zip(model.meshes, radius, strict=True):
        pts = np.empty((model.n_points, 2))
        fl = np.asarray(mesh.flank_nodes["left"], dtype=np.int64)
        sample_flank(mesh.nodes.ravel().copy(), fl, (len(fl) - 1) // 2, pts)
        rad = np.maximum.accumulate(np.hypot(pts[:, 0], pts[:, 1]))
        rad = rad + 1e-12 * np.arange(len(rad))
        out.append(float(np.interp(r, rad, par)))
    return out[0], out[1]


def pair_geometry(
    model: MultiToothModel,
    x: np.ndarray,
    start=None,
    phi_a: float = 0.0,
    theta_s: float | None = None,
    surfaces=None,
):
    """Contact search of every pair at positions ``x``: (cres (npair, 8), cnod, cw).

    ``start`` (npair, 2) warm starts; default: the involute contact point of each pair at
    gear A's rotation ``phi_a`` (:func:`involute_start`). With ``theta_s`` given, pairs before
    the start / after the end of contact use the tip-corner projection, as in the solver.
    ``surfaces``: the smoothed contact surfaces ``(tab, mloc)`` of the pairs
    (:func:`rotaflex.gear.models.fe_pair.smoothing_tables`; ``cnod``, ``cw`` then hold the weights of
    every flank node) or None for the paper's surfaces and 3-node force; with smoothed surfaces
    the disks are at ``model.theta0``.
    """
    from rotaflex.gear.kernels.contact import pair_contact

    npair = model.n_teeth
    m = model.n_points
    nw = 3 if surfaces is None else model.pair_flank.shape[2]
    cres = np.zeros((npair, 8))
    cnod = np.zeros((npair, 2, nw), dtype=np.int64)
    cw = np.zeros((npair, 2, nw))
    for j in range(npair):
        if start is None:
            cres[j, 0], cres[j, 1] = involute_start(model, model.pair_psi[j] + phi_a)
        else:
            cres[j, 0], cres[j, 1] = start[j]
        buf = [np.empty((m, 2)) for _ in range(4)]
        psi = model.pair_psi[j] + phi_a
        mode = 0 if theta_s is None else (1 if psi < 0 else (2 if psi > theta_s else 0))
        if not pair_contact(
            x,
            np.zeros(2),
            model.pair_flank[j],
            model.pair_nedge[j],
            model.sig,
            m,
            *buf,
            cres[j],
            cnod[j],
            cw[j],
            mode,
            model.theta0,
            np.zeros((2, 2, 1)) if surfaces is None else surfaces[0][j],
            np.zeros((2, 1, 2)) if surfaces is None else surfaces[1][j],
        ):
            raise ConvergenceError("contact search", 0.0, float("nan"), 0.0)
    return cres, cnod, cw


def _positions(model, theta0, u_local):
    """Global positions for disk orientations ``theta0`` and tooth-frame displacements."""
    x = np.empty((model.n_nodes, 2))
    for g in range(2):
        nodes = model.meshes[g].nodes
        nn = len(nodes)
        for j in range(model.n_teeth):
            a = model.tooth_node0[g, j]
            r = _rot(theta0[g] + model.tooth_offset[g, j])
            x[a : a + nn] = model.centres[g] + (nodes + u_local[g][j]) @ r.T
    return x.ravel()


def static_preload(
    model: MultiToothModel,
    torque: float,
    youngs_modulus,
    poisson_ratio,
    theta_s: float,
    window: float = WINDOW,
    n_iter: int = 4,
    start=None,
    smoothing: int = 0,
) -> MultiToothModel:
    """Quasi-static start: deflect the loaded pairs and turn B so the pairs carry the torques.

    Linear statics per tooth (root nodes fixed to the disk; each gear's own mesh, E and nu)
    with a unit normal point force distributed as in the dynamics (quadratic edge shape
    functions); the pair forces ``P_j = max(0, (beta d_j - h_j) / c_j)`` (h_j rigid gap, d_j
    moment arm about B's centre, c_j pair compliance) balance B's load torque
    ``torque z_B / z_A`` (``torque`` = tau_0 [N m], the drive torque on A; the kernel's torque
    on B, :class:`rotaflex.gear.cases.simulate_config.Run` ``gain``); pairs outside the mesh window
    ``[-window, theta_s + window]`` of contact angles are ignored. Repeated ``n_iter`` times
    with the gaps of the deformed state. ``youngs_modulus`` [Pa] and ``poisson_ratio``: one
    value or one per gear (A, B). ``smoothing``: the contact-surface intervals of the run
    (:func:`rotaflex.gear.models.fe_pair.smoothing_tables`; 0 = the paper's surfaces), so that the
    start state closes the gaps the solver sees. Returns the preloaded model (a new one: ``theta0`` of B
    turned, ``initial_positions`` deflected, ``preload`` = pair forces, compliances, arms,
    final gaps, B's turn ``beta``).
    """
    from scipy.optimize import brentq

    from rotaflex.gear.models.fe_pair import _per_gear, smoothing_tables
    from rotaflex.gear.static.tooth_analysis import solve_static

    e_g, nu_g = _per_gear(youngs_modulus), _per_gear(poisson_ratio)
    # load torque on B (exactly tau_0 for identical gears)
    torque_b = torque * (model.geometry[1].teeth / model.geometry[0].teeth)
    npair = model.n_teeth
    theta_ref = model.theta0.copy()
    u = [np.zeros((npair, m.n_nodes, 2)) for m in model.meshes]
    x = _positions(model, theta_ref, u)
    inmesh = (model.pair_psi >= -window) & (model.pair_psi <= theta_s + window)
    surfaces = smoothing_tables(model, smoothing, model.pair_flank, model.pair_nedge) if smoothing > 0 else None
    cres, cnod, cw = pair_geometry(model, x, start=start, theta_s=theta_s, surfaces=surfaces)
    cres[~inmesh, 2] = 1.0
    comp = np.ones(npair)
    unit = [np.zeros((npair, m.n_nodes, 2)) for m in model.meshes]
    arm = np.zeros(npair)
    for j in np.where(inmesh)[0]:
        n = cres[j, 3:5]
        disp = []
        # nodes of the contact force (3 or, on smoothed surfaces, the flank nodes with weight)
        loaded = [range(3)] * 2 if surfaces is None else [np.flatnonzero(cw[j, g]) for g in range(2)]
        for g in range(2):
            mesh = model.meshes[g]
            r = _rot(theta_ref[g] + model.tooth_offset[g, j])
            nl = r.T @ n
            f = np.zeros(2 * mesh.n_nodes)
            sgn = -1.0 if g == 0 else 1.0
            for q in loaded[g]:
                i = cnod[j, g, q] - model.tooth_node0[g, j]
                f[2 * i : 2 * i + 2] += sgn * cw[j, g, q] * nl
            ul = solve_static(mesh, f, e_g[g], nu_g[g]).reshape(-1, 2)
            unit[g][j] = ul
            ug = ul @ r.T
            disp.append(sum(cw[j, g, q] * (n @ ug[cnod[j, g, q] - model.tooth_node0[g, j]]) for q in loaded[g]))
        comp[j] = disp[1] - disp[0]
        xb = np.array([sum(cw[j, 1, q] * x[2 * cnod[j, 1, q] + d] for q in loaded[1]) for d in range(2)])
        rb_vec = xb - model.centres[1]
        arm[j] = -(rb_vec[0] * n[1] - rb_vec[1] * n[0])
    arm[~inmesh] = np.max(arm[inmesh])
    h_eff = cres[:, 2].copy()
    beta = 0.0
    pj = np.zeros(npair)
    for _ in range(n_iter):

        def bal(b, h=h_eff):
            return np.sum(np.maximum(0.0, (b * arm - h) / comp) * arm) - torque_b

        lo = float(np.min(h_eff / arm))
        hi = lo + max(torque_b * np.max(comp) / np.min(arm) ** 2, 1e-12)
        while bal(hi) < 0.0:
            hi = lo + 2 * (hi - lo)
        beta = brentq(bal, lo, hi, xtol=1e-16, rtol=1e-15) if torque_b > 0 else 0.0
        pj = np.maximum(0.0, (beta * arm - h_eff) / comp)
        for g in range(2):
            for j in range(npair):
                u[g][j] = pj[j] * unit[g][j]
        th = theta_ref.copy()
        th[1] += beta
        x = _positions(model, th, u)
        c2, _, _ = pair_geometry(replace(model, theta0=th), x, start=cres[:, :2], theta_s=theta_s, surfaces=surfaces)
        c2[~inmesh, 2] = 1.0
        pred = np.where(pj > 0, 0.0, h_eff - beta * arm)
        h_eff = h_eff + (c2[:, 2] - pred)
    return replace(
        model,
        theta0=th,
        initial_positions=x,
        preload={"force": pj, "compliance": comp, "arm": arm, "gap": c2[:, 2], "beta": beta},
    )


def turned(model: MultiToothModel, angle: float) -> MultiToothModel:
    """The unloaded model turned rigidly by ``angle`` [rad] of A (B by the conjugate angle
    ``angle r_bA / r_bB``): the placement of :func:`build_multi_model` with ``start_angle``
    increased by ``angle``, without re-assembling the FE arrays."""
    ratio = model.geometry[0].base_radius / model.geometry[1].base_radius
    out = replace(model, theta0=model.theta0 + np.array([angle, -angle * ratio]), pair_psi=model.pair_psi + angle)
    return replace(out, initial_positions=out.reference_positions(), preload=None)


def static_pair_forces(
    model: MultiToothModel,
    torque: float,
    youngs_modulus,
    poisson_ratio,
    theta_s: float,
    angles,
    step: float = 2e-3,
    smoothing: int = 0,
) -> np.ndarray:
    """Quasi-static pair forces [N], shape (len(angles), npair), of the model turned rigidly by
    each of ``angles`` [rad of A, increasing from 0] (:func:`turned`, :func:`static_preload`).

    The same FE teeth, point-force contact and spline surfaces as the dynamics: the load share
    that a run at low speed should follow. The contact-search warm starts are tracked along the
    rigid rotation in steps of at most ``step`` [rad] (a fresh minimum-distance search near a
    tip corner can converge to a distant point). ``smoothing`` as :func:`static_preload`.
    """
    start, _, _ = pair_geometry(model, model.reference_positions(), theta_s=theta_s)
    done = 0.0
    out = []
    for ang in np.asarray(angles, dtype=float):
        for d in np.linspace(done, ang, max(2, int(abs(ang - done) / step) + 1))[1:]:
            mod = turned(model, float(d))
            start, _, _ = pair_geometry(mod, mod.reference_positions(), start=start[:, :2], theta_s=theta_s)
        done = float(ang)
        mod = turned(model, float(ang))
        pre = static_preload(
            mod, torque, youngs_modulus, poisson_ratio, theta_s, start=start[:, :2], smoothing=smoothing
        ).preload
        out.append(pre["force"])
    return np.array(out)


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


def simulate_multi(model: MultiToothModel, *, torque_mode=1, window=WINDOW, n_accel=4, **kw):
    """Integrate the multi-tooth pair over a rotation ``span`` of gear A [rad].

    :func:`rotaflex.gear.models.fe_pair.integrate` with ``torque_mode`` 1 (the constant ``torque`` on
    both disks; 0: the Fig. 7 ramps, for the comparison with the single-tooth model), the mesh
    ``window`` and the warm-start table of this model; starts from ``model.initial_positions``
    rotating rigidly. Other keywords as :func:`~rotaflex.gear.models.fe_pair.integrate`.
    """
    from rotaflex.gear.models.fe_pair import integrate

    return integrate(model, torque_mode=torque_mode, window=window, n_accel=n_accel, **kw)
