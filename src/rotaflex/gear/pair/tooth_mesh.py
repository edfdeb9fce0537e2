"""Structured 8-node serendipity mesh of one gear tooth and the rim sector beneath it.

Layout (gear frame: centre at the origin, tooth centreline along +y)
-------------------------------------------------------------------
The modelled region is one pitch sector: the tooth and a rim ring segment of depth
``rim_depth_coef * m`` below the root circle, bounded by the radial cuts at +-pi/z (the
symmetry lines halfway between teeth). It is split into two mapped (transfinite) blocks:

* tooth block: between the two profiles from the split points F (where the fillet tangent
  makes ``split_angle`` with the tooth centreline) up to the tip, closed by the tip arc and
  the straight chord F_left - F_right; ``n_through`` elements across, ``n_flank`` along the
  profile, graded geometrically (element length at the tip / at F = ``flank_grading``);
* rim block: below the curve side cut - root land - lower fillet - chord - lower fillet - root
  land - side cut, down to the arc of radius ``r_f - rim_depth``; ``n_fillet`` elements along
  each lower fillet + root land, ``n_through`` along the chord, ``n_rim`` layers radially
  (graded, the layer at the root ``rim_grading`` times thinner than the deepest).

Boundary nodes (mid-side nodes included) lie exactly on the involute, the rack-generated
fillet, the root and tip circles (placed by arc length), so curved edges are quadratic.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Literal

import numpy as np

from rotaflex.core.errors import InputError
from rotaflex.core.units import deg_to_rad
from rotaflex.gear.pair.geometry import GearGeometry

__all__ = ["ToothMesh", "build_tooth_mesh", "mesh_quality", "COARSE", "DEFAULT"]

#: keyword sets of :func:`build_tooth_mesh` for fast tests and for the default dynamic mesh
COARSE = dict(n_flank=4, n_through=2, n_fillet=2, n_rim=3)
DEFAULT = dict(n_flank=10, n_through=5, n_fillet=2, n_rim=4)
#: fillet tangent angle at the split point between the tooth and rim blocks, 50 deg [rad]
SPLIT_ANGLE = deg_to_rad(50.0)
#: allowed split angles, 20 to 75 deg [rad]
SPLIT_ANGLE_RANGE = (deg_to_rad(20.0), deg_to_rad(75.0))


@dataclasses.dataclass(frozen=True, eq=False)
class ToothMesh:
    """Finite-element mesh of one tooth (+ rim sector) in the gear frame.

    Attributes
    ----------
    nodes : ndarray, shape (n, 2), float
        Node coordinates [m]; gear centre at the origin, tooth centreline along +y.
    elements : ndarray, shape (ne, 8), int
        8-node serendipity connectivity: corners 0-3 counter-clockwise, then mid-side nodes
        4-7, mid-side ``4 + i`` on the edge from corner ``i`` to corner ``(i + 1) % 4``.
    root_nodes : ndarray, int
        Nodes tied to the rigid disk: the rim's inner arc (radius ``r_f - rim_depth``) and,
        when ``support == "bottom_and_sides"``, the radial side cuts at +-pi/z (sorted).
    flank_nodes : dict[str, ndarray]
        ``"left"`` (x < 0) and ``"right"`` (x > 0) free-surface nodes of each side, corner and
        mid-side nodes, ordered from the root to the tip corner: root land (from the side cut),
        fillet, involute. Consecutive triples ``[2k, 2k+1, 2k+2]`` are the nodes of one element
        edge. The tip corner is the last entry.
    tip_nodes : ndarray, int
        Tip-arc nodes ordered left tip corner -> right tip corner.
    thickness : float
        Plane-stress thickness = face width [m].
    geometry : GearGeometry
        The gear this mesh models.
    rim_radius : float
        Radius of the inner arc [m].
    """

    nodes: np.ndarray
    elements: np.ndarray
    root_nodes: np.ndarray
    flank_nodes: dict
    tip_nodes: np.ndarray
    thickness: float
    geometry: GearGeometry
    rim_radius: float

    @property
    def n_nodes(self) -> int:
        """Number of nodes."""
        return int(self.nodes.shape[0])

    @property
    def n_dofs(self) -> int:
        """Number of DOFs (2 per node, interleaved x, y)."""
        return 2 * self.n_nodes

    @property
    def n_elements(self) -> int:
        """Number of elements."""
        return int(self.elements.shape[0])


# ----------------------------------------------------------------------------- curves
class _Curve:
    """A curve evaluated exactly from a parameter, re-parameterised by arc length."""

    def __init__(self, pieces: list, n_dense: int = 1500):
        # pieces: list of (func(t)->(n,2), t0, t1)
        self.pieces = pieces
        gs, pts = [], []
        for k, (f, t0, t1) in enumerate(pieces):
            t = np.linspace(0.0, 1.0, n_dense)
            if k > 0:
                t = t[1:]
            gs.append(k + t)
            pts.append(f(t0 + (t1 - t0) * t))
        self.g = np.concatenate(gs)
        p = np.vstack(pts)
        self.s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(p, axis=0).T))])
        self.length = float(self.s[-1])

    def at(self, frac: np.ndarray) -> np.ndarray:
        """Points at normalised arc-length positions ``frac`` in [0, 1]."""
        g = np.interp(np.asarray(frac) * self.length, self.s, self.g)
        k = np.minimum(np.floor(g).astype(int), len(self.pieces) - 1)
        out = np.empty((g.size, 2))
        for i, (f, t0, t1) in enumerate(self.pieces):
            sel = k == i
            if np.any(sel):
                out[sel] = f(t0 + (t1 - t0) * (g[sel] - i))
        return out


def _graded(n: int, ratio: float) -> np.ndarray:
    """2n+1 positions in [0, 1]: n elements with geometric sizes (last/first = ratio), mid-nodes."""
    q = ratio ** (1.0 / (n - 1)) if n > 1 else 1.0
    h = q ** np.arange(n)
    c = np.concatenate([[0.0], np.cumsum(h)]) / h.sum()
    out = np.empty(2 * n + 1)
    out[0::2] = c
    out[1::2] = 0.5 * (c[:-1] + c[1:])
    return out


def _tfi(bottom, top, left, right):
    """Transfinite (Coons) interpolation.

    bottom/top (ni, 2) run left -> right, left/right (nj, 2) bottom -> top.
    """

    def frac(p):
        s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(p, axis=0).T))])
        return s / s[-1]

    ub, ut, vl, vr = frac(bottom), frac(top), frac(left), frac(right)
    vbar = 0.5 * (vl + vr)
    ubar = 0.5 * (ub + ut)
    u = (1.0 - vbar)[None, :] * ub[:, None] + vbar[None, :] * ut[:, None]  # (ni, nj)
    v = (1.0 - ubar)[:, None] * vl[None, :] + ubar[:, None] * vr[None, :]
    u, v = u[..., None], v[..., None]
    p = (
        (1 - v) * bottom[:, None, :]
        + v * top[:, None, :]
        + (1 - u) * left[None, :, :]
        + u * right[None, :, :]
        - ((1 - u) * (1 - v) * bottom[0] + u * (1 - v) * bottom[-1] + (1 - u) * v * top[0] + u * v * top[-1])
    )
    p[:, 0], p[:, -1], p[0, :], p[-1, :] = bottom, top, left, right
    return p  # (ni, nj, 2)


def _block_elements(ids: np.ndarray) -> np.ndarray:
    """Connectivity of the quad8 elements of a (2N+1, 2M+1) node-id grid (i right, j up)."""
    n, m = (ids.shape[0] - 1) // 2, (ids.shape[1] - 1) // 2
    a, b = np.meshgrid(2 * np.arange(n), 2 * np.arange(m), indexing="ij")
    a, b = a.ravel(), b.ravel()
    return np.column_stack(
        [
            ids[a, b],
            ids[a + 2, b],
            ids[a + 2, b + 2],
            ids[a, b + 2],
            ids[a + 1, b],
            ids[a + 2, b + 1],
            ids[a + 1, b + 2],
            ids[a, b + 1],
        ]
    )


def _fillet_split_phi(g: GearGeometry, angle: float) -> float:
    """Generating roll angle where the right fillet's tangent makes ``angle`` with +y [rad]."""
    pa, pb = g.fillet_phi
    phi = np.linspace(pa, pb, 4001)
    p = g.fillet_points(phi)
    d = np.gradient(p, axis=0)
    ang = np.arctan2(np.abs(d[:, 0]), np.abs(d[:, 1]))  # angle of tangent from the y axis
    # ang decreases from ~90 deg (root) to ~0 (form point)
    k = int(np.argmin(np.abs(ang - angle)))
    return float(phi[k])


def build_tooth_mesh(
    geometry: GearGeometry,
    n_flank: int = DEFAULT["n_flank"],
    n_through: int = DEFAULT["n_through"],
    n_fillet: int = DEFAULT["n_fillet"],
    n_rim: int = DEFAULT["n_rim"],
    *,
    rim_depth_coef: float = 2.0,
    flank_grading: float = 1.5,
    rim_grading: float = 3.0,
    split_angle: float = SPLIT_ANGLE,
    support: Literal["bottom", "bottom_and_sides", "root_circle"] = "bottom_and_sides",
    check: bool = True,
) -> ToothMesh:
    """Mesh one tooth of ``geometry`` and the rim sector beneath it with 8-node quadrilaterals.

    Parameters
    ----------
    geometry : GearGeometry
        The gear.
    n_flank : int
        Elements along each profile in the tooth block (split point F to tip).
    n_through : int
        Elements across the tooth.
    n_fillet : int
        Elements along each lower fillet + root land (rim block top).
    n_rim : int
        Element layers through the rim depth.
    rim_depth_coef : float
        Rim depth below the root circle, in modules. With the side cuts tied, the tooth
        compliance changes by < 0.4 % from 2 to 3 modules (1 module: 4 % too stiff), hence 2.
    flank_grading : float
        Element length at the tip / at the split point F along the profile (> 1: finer at root).
    rim_grading : float
        Deepest rim layer thickness / thickness of the layer at the root.
    split_angle : float
        Fillet tangent angle from the tooth centreline [rad] at the split point F between blocks
        (:data:`SPLIT_ANGLE_RANGE`).
    support : {"bottom", "bottom_and_sides", "root_circle"}
        Which nodes are tied to the rigid disk (``root_nodes``): the rim's inner arc, the arc and
        the radial side cuts, or (``"root_circle"``, the paper's root clamp) every node on or
        inside the root circle, which leaves only the tooth above the root circle elastic.
    check : bool
        Check Jacobians at all Gauss points (raises InputError if any is not positive).

    Returns
    -------
    ToothMesh

    Notes
    -----
    ``DEFAULT`` (10/5/2/4: 86 elements, 305 nodes for the paper's gear) has an RK4 limit of
    3.78e-8 s for steel, so the paper's dt = 3e-8 s is stable (see
    :func:`rotaflex.gear.pair.plane_stress.stable_time_step`); ``COARSE`` (4/2/2/3, 26 elements) is for fast
    tests. The limit is set by the rim elements under the fillet (``n_fillet``) and the
    elements across the tip (``n_through``).

    Examples
    --------
    >>> from rotaflex.gear.pair.geometry import GearGeometry
    >>> g = GearGeometry(module=3.175e-3, teeth=28, face_width=6.35e-3)
    >>> m = build_tooth_mesh(g, **COARSE)
    >>> m.elements.shape[1]
    8
    """
    for name, val in (
        ("n_flank", n_flank),
        ("n_through", n_through),
        ("n_fillet", n_fillet),
        ("n_rim", n_rim),
    ):
        if not isinstance(val, (int, np.integer)) or val < 1:
            raise InputError(f"mesh.{name}", val, "an integer >= 1")
    if not rim_depth_coef > 0.0:
        raise InputError("mesh.rim_depth_coef", rim_depth_coef, "> 0")
    if not SPLIT_ANGLE_RANGE[0] <= split_angle <= SPLIT_ANGLE_RANGE[1]:
        lo, hi = SPLIT_ANGLE_RANGE
        raise InputError("mesh.split_angle", split_angle, f"between {lo:.4f} and {hi:.4f} rad (20 and 75 deg)")
    if support not in ("bottom", "bottom_and_sides", "root_circle"):
        raise InputError("mesh.support", support, "'bottom', 'bottom_and_sides' or 'root_circle'")
    g = geometry
    rf, ra, z = g.root_radius_, g.tip_radius_, g.teeth
    r_rim = rf - rim_depth_coef * g.module
    if r_rim <= 0.2 * rf:
        raise InputError(
            "mesh.rim_depth_coef",
            rim_depth_coef,
            f"< {0.8 * rf / g.module:.3g} (rim inside the bore)",
        )
    half = math.pi / z
    pa, pb = g.fillet_phi
    ps = _fillet_split_phi(g, split_angle)

    def mirror(p):
        q = p.copy()
        q[:, 0] *= -1.0
        return q

    def polar(r, th):  # th measured from +y towards +x
        return np.column_stack([r * np.sin(th), r * np.cos(th)])

    r_form = g.form_radius
    # right profile: fillet (ps -> pb) then involute (r_form -> ra)
    upper = _Curve([(g.fillet_points, ps, pb), (lambda r: g.involute_points(r), r_form, ra)])
    # right lower curve from the side cut corner: root land (arc) then fillet (pa -> ps)
    land = (lambda th: polar(np.full_like(th, rf), th), half, pa)
    lower = (
        _Curve([land, (g.fillet_points, pa, ps)]) if half - pa > 1e-12 * half else _Curve([(g.fillet_points, pa, ps)])
    )

    # --- tooth block (i across left->right, j along root->tip)
    s_fl = _graded(n_flank, flank_grading)
    right_T = upper.at(s_fl)
    left_T = mirror(right_T)
    u_t = np.linspace(0.0, 1.0, 2 * n_through + 1)
    fL, fR = left_T[0], right_T[0]
    bottom_T = fL[None, :] + u_t[:, None] * (fR - fL)[None, :]
    if g.tip_relief is None:
        psi_tip = float(g.flank_half_angle(np.array([ra]))[0])
        top_T = polar(np.full_like(u_t, ra), -psi_tip + 2 * psi_tip * u_t)
    else:  # the relieved tip corner lies off the tip circle: the arc joins the two corners
        r_c = float(np.hypot(*right_T[-1]))
        psi_tip = math.atan2(right_T[-1][0], right_T[-1][1])
        top_T = polar(np.full_like(u_t, r_c), -psi_tip + 2 * psi_tip * u_t)
    grid_T = _tfi(bottom_T, top_T, left_T, right_T)

    # --- rim block (i across left side cut -> right side cut, j from rim arc up)
    s_lo = np.linspace(0.0, 1.0, 2 * n_fillet + 1)
    right_lo = lower.at(s_lo)[::-1]  # from F down to the side corner
    top_R = np.vstack([mirror(lower.at(s_lo)), bottom_T[1:-1], right_lo])
    seg = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(top_R, axis=0).T))])
    seg /= seg[-1]
    # blend of arc-length and equal-width spacing: wider columns under the short fillet curves
    seg = 0.5 * seg + 0.5 * np.linspace(0.0, 1.0, seg.size)
    bottom_R = polar(np.full(seg.size, r_rim), -half + 2 * half * seg)
    t_rim = 1.0 - _graded(n_rim, rim_grading)[::-1]  # fine near the root circle
    left_R = polar(r_rim + (rf - r_rim) * t_rim, np.full(t_rim.size, -half))
    right_R = polar(r_rim + (rf - r_rim) * t_rim, np.full(t_rim.size, half))
    grid_R = _tfi(bottom_R, top_R, left_R, right_R)

    # --- number nodes, merge the shared chord, drop element centre nodes
    nT, nR = grid_T.shape[0] * grid_T.shape[1], grid_R.shape[0] * grid_R.shape[1]
    ids_T = np.arange(nT).reshape(grid_T.shape[:2])
    ids_R = nT + np.arange(nR).reshape(grid_R.shape[:2])
    # chord nodes of the rim top row are the tooth block's bottom row
    i0 = 2 * n_fillet
    ids_R[i0 : i0 + 2 * n_through + 1, -1] = ids_T[:, 0]
    pts = np.vstack([grid_T.reshape(-1, 2), grid_R.reshape(-1, 2)])
    elements = np.vstack([_block_elements(ids_T), _block_elements(ids_R)])
    used = np.unique(elements)
    remap = -np.ones(pts.shape[0], dtype=np.int64)
    remap[used] = np.arange(used.size)
    nodes = pts[used]
    elements = remap[elements]

    def r(ids):
        return remap[np.asarray(ids)]

    root = [ids_R[:, 0]]
    if support == "bottom_and_sides":
        root += [ids_R[0, :], ids_R[-1, :]]
    root_nodes = np.unique(r(np.concatenate(root)))
    if support == "root_circle":
        inside = np.hypot(nodes[:, 0], nodes[:, 1]) <= rf * (1.0 + 1e-9)
        root_nodes = np.flatnonzero(inside)
    flank_right = np.concatenate([ids_R[::-1, -1][: 2 * n_fillet], ids_T[-1, :]])
    flank_left = np.concatenate([ids_R[:, -1][: 2 * n_fillet], ids_T[0, :]])
    mesh = ToothMesh(
        nodes=nodes,
        elements=elements.astype(np.int64),
        root_nodes=root_nodes,
        flank_nodes={"left": r(flank_left), "right": r(flank_right)},
        tip_nodes=r(ids_T[:, -1]),
        thickness=float(g.face_width),
        geometry=g,
        rim_radius=float(r_rim),
    )
    if check:
        q = mesh_quality(mesh)
        if q["min_jacobian_ratio"] <= 0.0:
            raise InputError("mesh", "parameters", "a mesh with positive Jacobians (refine or change grading)")
    return mesh


def mesh_quality(mesh: ToothMesh) -> dict:
    """Mesh quality numbers.

    Returns
    -------
    dict
        ``min_jacobian_ratio``: min over elements of (min det J at the 3x3 Gauss points /
        mean det J) (must be > 0); ``max_aspect_ratio``: max over elements of longest / shortest
        corner-to-corner edge; ``min_edge``, ``max_edge`` [m]; ``n_nodes``, ``n_elements``.
    """
    from rotaflex.gear.pair.plane_stress import jacobian_determinants

    det = jacobian_determinants(mesh)  # (ne, 9)
    ratio = det.min(axis=1) / det.mean(axis=1)
    ratio = np.where(det.mean(axis=1) > 0, ratio, -1.0)
    c = mesh.nodes[mesh.elements[:, :4]]
    edges = np.linalg.norm(np.roll(c, -1, axis=1) - c, axis=2)
    return {
        "min_jacobian_ratio": float(ratio.min()),
        "max_aspect_ratio": float((edges.max(axis=1) / edges.min(axis=1)).max()),
        "min_edge": float(edges.min()),
        "max_edge": float(edges.max()),
        "n_nodes": mesh.n_nodes,
        "n_elements": mesh.n_elements,
    }
