"""Static tooth analysis: tooth compliance, pair mesh stiffness, transmission error, root stress.

Load model
----------
A normal load ``F`` [N] on a flank at contact radius ``r`` acts along the line of action (the
involute normal, tangent to the base circle), pressing into the tooth. It is spread over the
surface as a Hertzian (semi-elliptical) line pressure of half-width ``a`` (default: the
Hertzian half-width of the pair at that point under ``F``, plane-stress elastic constants) and
converted to consistent nodal forces ``f_i = int N_i p(s) ds`` on the quadratic boundary edges
(3-point Gauss on 200 sub-intervals per edge, so the patch is resolved even when it is much
smaller than an element).

Compliance measures
-------------------
A concentrated (or sub-element) load gives a local displacement that grows without bound under
mesh refinement (2-D Flamant singularity), so the displacement *at* the load point is not a mesh
converged quantity unless elements are much smaller than ``a``. We therefore report

* ``structural`` compliance: displacement along the line of action of the point where the line
  of action crosses the tooth centreline, per unit load. It contains bending, shear, rim/foundation
  and the far part of the local deformation and converges under refinement;
* ``load_point`` compliance ``f . u / F^2`` (work-conjugate): shown only to demonstrate the trap;
* the remaining local contact compliance of the pair is Weber's 2-D contact formula between the
  two centreline points (plane-stress constants, consistent with the FE):
  ``q_H = 2/(pi E b) [ln(2 h1 / a) + ln(2 h2 / a) - nu]`` with ``h_i`` the distance from the
  contact point to tooth i's centreline along the line of action.

Pair mesh stiffness: ``k_pair = 1 / (q1 + q2 + q_H)``; with two pairs in contact the pairs act in
parallel (``k = k_a + k_b``), the load shares ``k_a / k``; the static transmission error along
the line of action for a normal load ``F = T / r_b1`` is ``F / k`` (no profile errors).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from rotaflex.core.errors import InputError
from rotaflex.core.units import deg_to_rad
from rotaflex.gear.pair.geometry import (
    STANDARD_PRESSURE_ANGLE,
    GearGeometry,
    center_distance_no_backlash,
    contact_ratio,
    path_of_contact,
)
from rotaflex.gear.pair.plane_stress import (
    shape_derivatives,
    shape_functions,
    stiffness_matrix,
    stress_operator,
)
from rotaflex.gear.pair.tooth_mesh import ToothMesh, _fillet_split_phi, build_tooth_mesh

__all__ = [
    "flank_contact_point",
    "hertz_half_width",
    "surface_load",
    "solve_static",
    "ToothCompliance",
    "tooth_compliance",
    "weber_contact_compliance",
    "MeshStiffness",
    "mesh_stiffness",
    "iso6336_stiffness",
    "root_stress_points",
    "root_stress_operator",
    "root_stress",
    "ROOT_STRESS_ANGLE",
]

#: tangent angle of the fillet point of the root stress, 30 deg: the ISO 6336-3 critical section [rad]
ROOT_STRESS_ANGLE = deg_to_rad(30.0)
#: ISO 6336-1 basic-rack factor C_B = (1 + 0.5 (1.2 - h_fP/m)) (1 - 0.02 (20 deg - alpha_n)):
#: the standard's slope, 0.02 per degree, per radian of (20 deg - alpha_n) [1/rad]
C_B_SLOPE = 0.02 / deg_to_rad(1.0)


# ----------------------------------------------------------------------------- loads
def flank_contact_point(g: GearGeometry, radius: float, side: str = "right"):
    """Point on the involute at ``radius`` and the inward unit load direction [m], [-].

    The direction is the involute normal pointing into the tooth (the line of action).
    """
    if not g.form_radius <= radius <= g.tip_radius_ * (1 + 1e-12):
        raise InputError("radius", radius, f"in [{g.form_radius:.6g}, {g.tip_radius_:.6g}] m")
    p = g.involute_points(np.array([radius]))[0]
    psi = float(g.flank_half_angle(np.array([radius]))[0])
    a_r = math.acos(g.base_radius / radius)
    # right flank: outward normal makes angle (psi - a_r) ... direction tangent to base circle
    # the normal line is tangent to the base circle: n_out = (cos(a_r - psi), sin(a_r - psi))
    n_out = np.array([math.cos(a_r - psi), math.sin(a_r - psi)])
    if side == "left":
        p = p * [-1.0, 1.0]
        n_out = n_out * [-1.0, 1.0]
    return p, -n_out


def hertz_half_width(force: float, b: float, e: float, nu: float, rho1: float, rho2: float) -> float:
    """Hertzian half-width of two parallel cylinders, plane-stress constants [m].

    ``a = sqrt(4 F R / (pi b E'))``, ``1/R = 1/rho1 + 1/rho2``, ``E' = E / 2`` (identical
    materials, plane stress).
    """
    r = rho1 * rho2 / (rho1 + rho2)
    return math.sqrt(4.0 * force * r / (math.pi * b * 0.5 * e))


def _edge_triples(mesh: ToothMesh, side: str) -> np.ndarray:
    f = mesh.flank_nodes[side]
    k = np.arange(0, f.size - 2, 2)
    return np.stack([f[k], f[k + 1], f[k + 2]], axis=1)


def surface_load(
    mesh: ToothMesh,
    radius: float,
    force: float,
    half_width: float,
    side: str = "right",
) -> np.ndarray:
    """Consistent nodal load vector (2n,) [N] of a Hertzian line load on a flank.

    Parameters
    ----------
    mesh : ToothMesh
    radius : float
        Contact radius on the involute [m].
    force : float
        Total normal load [N] (over the face width).
    half_width : float
        Half-width ``a`` of the semi-elliptical pressure [m].
    side : {"right", "left"}
    """
    if not half_width > 0:
        raise InputError("half_width", half_width, "> 0 [m]")
    pc, d = flank_contact_point(mesh.geometry, radius, side)
    t = np.array([-d[1], d[0]])  # tangent (sign irrelevant)
    tri = _edge_triples(mesh, side)
    x = mesh.nodes[tri]  # (ne, 3, 2)
    nsub = 200
    gp = np.array([-math.sqrt(0.6), 0.0, math.sqrt(0.6)])
    gw = np.array([5.0, 8.0, 5.0]) / 9.0
    edges = np.linspace(-1.0, 1.0, nsub + 1)
    xi = (0.5 * (edges[:-1] + edges[1:])[:, None] + 0.5 * (edges[1] - edges[0]) * gp[None, :]).ravel()
    w = np.tile(gw, nsub) * 0.5 * (edges[1] - edges[0])
    n3 = np.stack([0.5 * xi * (xi - 1.0), 1.0 - xi**2, 0.5 * xi * (xi + 1.0)], axis=1)  # (q, 3)
    dn3 = np.stack([xi - 0.5, -2.0 * xi, xi + 0.5], axis=1)
    pos = np.einsum("qa,eak->eqk", n3, x)
    jac = np.linalg.norm(np.einsum("qa,eak->eqk", dn3, x), axis=2)
    s = (pos - pc) @ t
    p = np.where(np.abs(s) < half_width, np.sqrt(np.clip(1.0 - (s / half_width) ** 2, 0, None)), 0.0)
    p *= 2.0 * force / (math.pi * half_width)  # int p ds = force
    fn = np.einsum("eq,q,qa->ea", p * jac, w, n3)  # (ne, 3) nodal magnitudes
    if fn.sum() <= 0.45 * force:  # a tip-corner patch carries ~half the load on the flank
        raise InputError("radius", radius, "a contact point on the meshed flank")
    fn *= force / fn.sum()  # remove the (tiny) quadrature error of the total
    out = np.zeros(2 * mesh.n_nodes)
    np.add.at(out, 2 * tri.ravel(), (fn * d[0]).ravel())
    np.add.at(out, 2 * tri.ravel() + 1, (fn * d[1]).ravel())
    return out


def solve_static(mesh: ToothMesh, loads: np.ndarray, e: float, nu: float) -> np.ndarray:
    """Displacements (2n,) or (2n, m) [m] for loads with the root nodes fixed (rigid disk)."""
    k = stiffness_matrix(mesh, e, nu)
    fixed = np.concatenate([2 * mesh.root_nodes, 2 * mesh.root_nodes + 1])
    free = np.setdiff1d(np.arange(k.shape[0]), fixed)
    lu = spla.splu(sp.csc_matrix(k[free][:, free]))
    f = np.asarray(loads, dtype=float)
    u = np.zeros_like(f)
    u[free] = lu.solve(f[free])
    return u


def _locate(mesh: ToothMesh, pts: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Element and natural coordinates of points (inverse isoparametric map, clamped)."""
    xe = mesh.nodes[mesh.elements]
    cen = xe.mean(axis=1)
    out_e = np.zeros(len(pts), dtype=int)
    out_x = np.zeros((len(pts), 2))
    for i, p in enumerate(pts):  # few points; not in a time loop
        best = (np.inf, 0, np.zeros(2))
        for e in np.argsort(np.linalg.norm(cen - p, axis=1))[:8]:
            z = np.zeros(2)
            for _ in range(30):
                n = shape_functions(z[0], z[1])
                dn = shape_derivatives(z[0], z[1])
                r = n @ xe[e] - p
                jac = dn.T @ xe[e]  # (2, 2): d x_l / d xi_k
                z = np.clip(z - np.linalg.solve(jac.T, r), -1.0, 1.0)
            err = np.linalg.norm(shape_functions(z[0], z[1]) @ xe[e] - p)
            if err < best[0]:
                best = (err, e, z)
        out_e[i], out_x[i] = best[1], best[2]
    return out_e, out_x


def _interp_operator(mesh: ToothMesh, pts: np.ndarray) -> sp.csr_matrix:
    """Sparse (2 npts, 2n) operator giving displacements at points."""
    el, z = _locate(mesh, pts)
    n = shape_functions(z[:, 0], z[:, 1])  # (npts, 8)
    nodes = mesh.elements[el]
    rows = np.concatenate([np.repeat(2 * np.arange(len(pts)), 8), np.repeat(2 * np.arange(len(pts)) + 1, 8)])
    cols = np.concatenate([2 * nodes.ravel(), 2 * nodes.ravel() + 1])
    return sp.csr_matrix(
        (np.concatenate([n.ravel(), n.ravel()]), (rows, cols)),
        shape=(2 * len(pts), 2 * mesh.n_nodes),
    )


# ------------------------------------------------------------------------ compliance
@dataclasses.dataclass(frozen=True)
class ToothCompliance:
    """Tooth compliance along the line of action at several contact radii.

    Attributes
    ----------
    radius : ndarray
        Contact radii [m].
    structural : ndarray
        Centreline-point compliance [m/N] (mesh converged quantity).
    load_point : ndarray
        Work-conjugate load-patch compliance [m/N] (mesh dependent, for illustration).
    arm : ndarray
        Distance h from the contact point to the tooth centreline along the line of action [m].
    half_width : ndarray
        Load-patch half-width used [m].
    """

    radius: np.ndarray
    structural: np.ndarray
    load_point: np.ndarray
    arm: np.ndarray
    half_width: np.ndarray


def _mate_curvatures(g: GearGeometry, radius: np.ndarray, mate: GearGeometry | None):
    mate = g if mate is None else mate
    a = center_distance_no_backlash(g, mate)
    aw = math.acos((g.base_radius + mate.base_radius) / a)
    rho1 = np.sqrt(radius**2 - g.base_radius**2)
    rho2 = a * math.sin(aw) - rho1
    return rho1, rho2


def tooth_compliance(
    mesh: ToothMesh,
    radii: np.ndarray,
    e: float,
    nu: float,
    force: float = 532.7,
    side: str = "right",
    half_width: float | None = None,
    mate: GearGeometry | None = None,
) -> ToothCompliance:
    """Compliance of one tooth (+ rim sector) under a normal flank load at each radius.

    Parameters
    ----------
    mesh : ToothMesh
    radii : ndarray
        Contact radii on the involute [m].
    e, nu : float
        Young's modulus [Pa], Poisson ratio.
    force : float
        Normal load [N] (sets the Hertzian patch; the model is linear otherwise).
    side : {"right", "left"}
    half_width : float, optional
        Patch half-width [m]; default the Hertzian half-width against ``mate`` (default: an
        identical gear at the no-backlash centre distance).
    """
    g = mesh.geometry
    radii = np.atleast_1d(np.asarray(radii, dtype=float))
    rho1, rho2 = _mate_curvatures(g, radii, mate)
    if half_width is None:
        hw = np.array([hertz_half_width(force, g.face_width, e, nu, a, b) for a, b in zip(rho1, rho2, strict=True)])
    else:
        hw = np.full(radii.size, float(half_width))
    loads, ref, dirs, arms = [], [], [], []
    for r, a in zip(radii, hw, strict=True):
        pc, d = flank_contact_point(g, r, side)
        loads.append(surface_load(mesh, r, force, a, side))
        t = -pc[0] / d[0]
        ref.append(pc + t * d)
        dirs.append(d)
        arms.append(t)
    f = np.stack(loads, axis=1)
    u = solve_static(mesh, f, e, nu)
    op = _interp_operator(mesh, np.array(ref))
    uref = (op @ u).reshape(len(radii), 2, len(radii))  # (point, xy, load case)
    dirs = np.array(dirs)
    struct = np.array([uref[i, :, i] @ dirs[i] for i in range(len(radii))]) / force
    lp = np.einsum("ij,ij->j", f, u) / force**2
    return ToothCompliance(radii, struct, lp, np.array(arms), hw)


def weber_contact_compliance(force: float, b: float, e: float, nu: float, h1, h2, half_width):
    """Weber's 2-D contact compliance between two points at depths h1, h2 [m/N] (plane stress)."""
    h1, h2, a = np.asarray(h1), np.asarray(h2), np.asarray(half_width)
    return 2.0 / (math.pi * e * b) * (np.log(2.0 * h1 / a) + np.log(2.0 * h2 / a) - nu)


# -------------------------------------------------------------------- mesh stiffness
@dataclasses.dataclass(frozen=True)
class MeshStiffness:
    """Static mesh stiffness and transmission error of a gear pair vs rotation of gear 1.

    Attributes
    ----------
    angle : ndarray
        Rotation of gear 1 from the start of contact of the reference pair [rad].
    pair_stiffness : ndarray
        Stiffness of the reference tooth pair along the line of action [N/m].
    mesh_stiffness : ndarray
        Stiffness of all pairs in contact [N/m].
    load_share : ndarray
        Fraction of the load carried by the reference pair.
    transmission_error : ndarray
        Static TE along the line of action [m] under ``force``.
    force : float
        Total normal load [N].
    theta_s, theta_2 : float
        Single-pair contact span and two-pair zone length [rad].
    """

    angle: np.ndarray
    pair_stiffness: np.ndarray
    mesh_stiffness: np.ndarray
    load_share: np.ndarray
    transmission_error: np.ndarray
    force: float
    theta_s: float
    theta_2: float


def mesh_stiffness(
    g1: GearGeometry,
    g2: GearGeometry,
    e: float,
    nu: float,
    torque: float = 22.25,
    n_angles: int = 200,
    n_radii: int = 9,
    mesh1: ToothMesh | None = None,
    mesh2: ToothMesh | None = None,
) -> MeshStiffness:
    """Static mesh stiffness and transmission error over one tooth pair's contact.

    Tooth compliances are computed with the FE tooth at ``n_radii`` contact radii and
    interpolated (cubic) along the path of contact; the contact compliance is Weber's formula.
    """
    from scipy.interpolate import CubicSpline

    mesh1 = build_tooth_mesh(g1) if mesh1 is None else mesh1
    mesh2 = build_tooth_mesh(g2) if mesh2 is None else mesh2
    a = center_distance_no_backlash(g1, g2)
    eps = contact_ratio(g1, g2, a)
    if eps >= 2.0:
        raise InputError("tip_radius", g1.tip_radius_, "a contact ratio < 2 (at most two pairs)")
    aw = math.acos((g1.base_radius + g2.base_radius) / a)
    length = a * math.sin(aw)
    g = path_of_contact(g1, g2, a)
    s_end = math.sqrt(g1.tip_radius_**2 - g1.base_radius**2)
    s_start = s_end - g
    force = torque / g1.base_radius
    pb = g1.base_pitch

    def comp(mesh, gg, mate, s_lo, s_hi):
        rr = np.sqrt(gg.base_radius**2 + np.linspace(s_lo, s_hi, n_radii) ** 2)
        c = tooth_compliance(mesh, rr, e, nu, force=force, mate=mate)
        return (CubicSpline(rr, c.structural), CubicSpline(rr, c.arm))

    q1, h1 = comp(mesh1, g1, g2, s_start, s_end)
    q2, h2 = comp(mesh2, g2, g1, length - s_end, length - s_start)

    def pair_k(s):
        r1 = np.sqrt(g1.base_radius**2 + s**2)
        r2 = np.sqrt(g2.base_radius**2 + (length - s) ** 2)
        rho1, rho2 = s, length - s
        hw = np.array([hertz_half_width(force, g1.face_width, e, nu, x, y) for x, y in zip(rho1, rho2, strict=True)])
        qh = weber_contact_compliance(force, g1.face_width, e, nu, h1(r1), h2(r2), hw)
        return 1.0 / (q1(r1) + q2(r2) + qh)

    ang = np.linspace(0.0, g / g1.base_radius, n_angles)
    s = s_start + g1.base_radius * ang
    k_ref = pair_k(s)
    k_tot = k_ref.copy()
    for shift in (-pb, pb):
        s_o = s + shift
        inside = (s_o >= s_start - 1e-15) & (s_o <= s_end + 1e-15)
        if np.any(inside):
            k_tot[inside] += pair_k(s_o[inside])
    return MeshStiffness(
        angle=ang,
        pair_stiffness=k_ref,
        mesh_stiffness=k_tot,
        load_share=k_ref / k_tot,
        transmission_error=force / k_tot,
        force=force,
        theta_s=g / g1.base_radius,
        theta_2=(g - pb) / g1.base_radius,
    )


def iso6336_stiffness(
    g1: GearGeometry,
    g2: GearGeometry,
    load_per_width: float | None = None,
    *,
    eps_alpha: float | None = None,
    c_r: float = 1.0,
    helix_angle: float = 0.0,
    base_helix_angle: float = 0.0,
) -> dict:
    """ISO 6336-1 (method B) single stiffness c' and mesh stiffness c_gamma_alpha.

    ``q' = C1 + C2/zn1 + C3/zn2 + C4 x1 + C5 x1/zn1 + C6 x2 + C7 x2/zn2 + C8 x1^2 + C9 x2^2``
    [mm um / N] with C1..C9 = 0.04723, 0.15551, 0.25791, -0.00635, -0.11654, -0.00193,
    -0.24188, 0.00529, 0.00182; ``c'_th = 1/q'``; ``c' = c'_th C_M C_R C_B cos(beta)`` with
    C_M = 0.8, C_R = ``c_r`` (1 for solid blanks), ``C_B = [1 + 0.5 (1.2 - h_fP/m)]
    [1 - 0.02 (20 - alpha)]`` (the mean of the two gears' values when their basic-rack dedendums
    differ), cos(beta) = 1 (spur); for ``F_t K_A / b < 100 N/mm`` c' is multiplied by
    ``(F_t K_A / b / 100)^0.25``; ``c_gamma_alpha = c' (0.75 eps_alpha + 0.25)``. The caller
    passes ``load_per_width = F_t K_A / b`` [N/mm] with ``F_t = T_1 / r_1`` the nominal tangential
    load at the *reference* circle (not the base circle) and ``b`` the face width;
    ``eps_alpha`` defaults to the contact ratio at the no-backlash centre distance.

    Helical pairs (``helix_angle`` beta > 0 [rad], ``base_helix_angle`` beta_b [rad], ``g1``,
    ``g2`` the transverse sections): q' takes the virtual numbers of teeth ``z_n = z /
    (cos^2(beta_b) cos(beta))`` and the normal profile shifts ``x_n = x_t / cos(beta)``, c'
    the factor cos(beta), and ``c_gamma_beta = 0.85 c_gamma_alpha`` (ISO 6336-1:2006, 9.3);
    h_fP/m and alpha in C_B are the normal-section values.

    Returns
    -------
    dict
        ``c_th``, ``c_single``, ``c_gamma`` in N/(mm um) and ``k_th``, ``k_single``, ``k_gamma``
        in N/m for the face width, plus the factors used.
    """
    c = (0.04723, 0.15551, 0.25791, -0.00635, -0.11654, -0.00193, -0.24188, 0.00529, 0.00182)
    z1, z2, x1, x2 = g1.teeth, g2.teeth, g1.profile_shift, g2.profile_shift
    cos_b = 1.0
    if helix_angle > 0.0:
        cos_b = math.cos(helix_angle)
        zn = 1.0 / (math.cos(base_helix_angle) ** 2 * cos_b)
        z1, z2, x1, x2 = z1 * zn, z2 * zn, x1 / cos_b, x2 / cos_b
    q = (
        c[0]
        + c[1] / z1
        + c[2] / z2
        + c[3] * x1
        + c[4] * x1 / z1
        + c[5] * x2
        + c[6] * x2 / z2
        + c[7] * x1**2
        + c[8] * x2**2
    )
    c_th = 1.0 / q

    def cb(g):
        if helix_angle > 0.0:  # normal section: h_fP / m_n and alpha_n
            h_fp = g.cutter_addendum / (g.module * cos_b)
            alpha = math.atan(math.tan(g.pressure_angle) * cos_b)
            return (1.0 + 0.5 * (1.2 - h_fp)) * (1.0 - C_B_SLOPE * (STANDARD_PRESSURE_ANGLE - alpha))
        h_fp = g.cutter_addendum / g.module
        return (1.0 + 0.5 * (1.2 - h_fp)) * (1.0 - C_B_SLOPE * (STANDARD_PRESSURE_ANGLE - g.pressure_angle))

    c_b = 0.5 * (cb(g1) + cb(g2))
    c_m = 0.8
    f_load = 1.0
    if load_per_width is not None and load_per_width < 100.0:
        f_load = (load_per_width / 100.0) ** 0.25
    c_single = c_th * c_m * c_r * c_b * f_load
    if helix_angle > 0.0:
        c_single = c_single * cos_b
    eps = contact_ratio(g1, g2) if eps_alpha is None else float(eps_alpha)
    c_gamma = c_single * (0.75 * eps + 0.25)
    bw = min(g1.face_width, g2.face_width) * 1e3  # mm
    to_n_per_m = bw * 1e6  # N/(mm um) * mm -> N/um -> N/m
    return {
        "q": q,
        "c_th": c_th,
        "c_single": c_single,
        "c_gamma": c_gamma,
        "k_th": c_th * to_n_per_m,
        "k_single": c_single * to_n_per_m,
        "k_gamma": c_gamma * to_n_per_m,
        "C_M": c_m,
        "C_R": c_r,
        "C_B": c_b,
        "load_factor": f_load,
        "eps_alpha": eps,
        "k_th_gamma": c_th * (0.75 * eps + 0.25) * to_n_per_m,
        "c_gamma_beta": 0.85 * c_gamma,
        "k_gamma_beta": 0.85 * c_gamma * to_n_per_m,
    }


# ---------------------------------------------------------------------------- root stress
def root_stress_points(g: GearGeometry, angle: float = ROOT_STRESS_ANGLE) -> dict:
    """Fillet points where the tangent makes ``angle`` [rad] with the tooth centreline.

    Returns
    -------
    dict
        ``{"left": (point, tangent), "right": (point, tangent)}`` [m], unit tangents.
    """
    phi = _fillet_split_phi(g, angle)
    p = g.fillet_points(np.array([phi - 1e-7, phi, phi + 1e-7]))
    t = p[2] - p[0]
    t /= np.linalg.norm(t)
    return {"right": (p[1], t), "left": (p[1] * [-1.0, 1.0], t * [-1.0, 1.0])}


def root_stress_operator(mesh: ToothMesh, e: float, nu: float, angle: float = ROOT_STRESS_ANGLE) -> np.ndarray:
    """Matrix S (2, 2n): ``S @ u`` = surface tangential stress [Pa] at the (left, right) fillet
    points of ``angle`` [rad] tangent (ISO 6336-3 critical section for 30 deg).

    The stress is evaluated directly from the FE field (derivatives of the quadratic element at
    the point's natural coordinates); positive = tension.
    """
    pts = root_stress_points(mesh.geometry, angle)
    rows = []
    for side in ("left", "right"):
        p, t = pts[side]
        el, z = _locate(mesh, p[None, :])
        s = stress_operator(mesh, e, nu, el, z[:, 0], z[:, 1])[0]  # (3, 2n): sxx, syy, sxy
        rows.append(t[0] ** 2 * s[0] + t[1] ** 2 * s[1] + 2.0 * t[0] * t[1] * s[2])
    return np.array(rows)


def root_stress(mesh: ToothMesh, u: np.ndarray, e: float, nu: float, angle: float = ROOT_STRESS_ANGLE) -> np.ndarray:
    """Tangential fillet stress [Pa] at the 30-degree tangent points, shape (..., 2) (left, right).

    ``u`` holds elastic nodal displacements in the gear frame, shape (2n,) or (nt, 2n) (a
    history); for co-rotational dynamics pass the elastic part ``w`` (eq. 4 of the paper).
    For repeated use build :func:`root_stress_operator` once and apply it.
    """
    s = root_stress_operator(mesh, e, nu, angle)
    return np.asarray(u) @ s.T
