"""Several elastic teeth per gear: the two-pair zones and continuous meshing modelled directly.

Model
-----
Each gear is a rigid disk carrying ``n`` (2 to 12) adjacent elastic teeth at the angular pitch
``2 pi / z``; every tooth is its own pitch-sector mesh (:func:`rotaflex.gear.mesh.build_tooth_mesh`)
whose root nodes (inner arc and side cuts) are tied to the disk, exactly as the single tooth of
:mod:`rotaflex.gear.dynamics`. Tooth ``j`` of A can touch tooth ``j`` of B only: ``n`` contact
pairs, each unilateral with its own contact search (minimum normal distance between the spline
surfaces), sliding terms and multiplier row in the paper's three-pass iteration
(:func:`rotaflex.gear.kernels.rk4.run_steps`). Both disks carry the constant torque
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
from dataclasses import dataclass, replace

import numpy as np
import scipy.sparse as sp

from rotaflex.core.errors import ConvergenceError, InputError
from rotaflex.gear.dynamics import (
    GearPairModel,
)

#: default mesh window: pairs are searched from 1 deg before to 1 deg after their contact [rad]
WINDOW = math.radians(1.0)


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


def build_multi_model(
    geometry, mesh, n_teeth, *, youngs_modulus, poisson_ratio, density, inertia, n_points=61, start_angle=0.0
):
    """Two identical gears with ``n_teeth`` elastic teeth each.

    Placed (rigidly, unloaded) so that pair 1 is at the contact angle ``start_angle`` [rad]
    (0 = geometric start of contact, < 0 = before it; see module docstring).
    """
    from rotaflex.gear import dynamics, fe

    if not 1 <= n_teeth <= 12:
        raise InputError("model.teeth_per_gear", n_teeth, "1..12")
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
        theta0=base.theta0 + np.array([start_angle, -start_angle]),
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
    return replace(model, initial_positions=model.reference_positions())


def involute_start(model: MultiToothModel, psi: float) -> tuple[float, float]:
    """Flank parameters (a, b) of the rigid involute contact point at contact angle ``psi``.

    Used as the warm start of each pair's contact search; ``psi`` is clamped to the path of
    contact (a pair out of mesh starts from its nearest end of contact).
    """
    from rotaflex.gear.kernels.contact import sample_flank

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
    from rotaflex.gear.kernels.contact import pair_contact

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
            np.zeros((2, 2, 1)),
            np.zeros((2, 1, 2)),
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
    deformed state. Returns the preloaded model (a new one: ``theta0`` of B turned,
    ``initial_positions`` deflected, ``preload`` = pair forces, compliances, arms, final gaps).
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
    return replace(
        model,
        theta0=th,
        initial_positions=x,
        preload={"force": pj, "compliance": comp, "arm": arm, "gap": c2[:, 2], "beta": beta},
    )


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


def simulate_multi(
    model: MultiToothModel, *, speeds, torque, theta_2, theta_s, span, dt, torque_mode=1, window=WINDOW, n_accel=4, **kw
):
    """Integrate the multi-tooth pair over a rotation ``span`` of gear A [rad].

    :func:`rotaflex.gear.dynamics.integrate` with ``torque_mode`` 1 (the constant ``torque`` on
    both disks; 0: the Fig. 7 ramps, for the comparison with the single-tooth model), the mesh
    ``window`` and the warm-start table of this model; starts from ``model.initial_positions``
    rotating rigidly. Other keywords as :func:`~rotaflex.gear.dynamics.integrate`.
    """
    from rotaflex.gear.dynamics import integrate

    return integrate(
        model,
        speeds=speeds,
        torque=torque,
        theta_2=theta_2,
        theta_s=theta_s,
        span=span,
        dt=dt,
        torque_mode=torque_mode,
        window=window,
        n_accel=n_accel,
        **kw,
    )
