"""Tooth mesh: topology, geometry fidelity, quality and the RK4 time-step contract."""

import math

import numpy as np
import pytest

from rotaflex.core.errors import InputError
from rotaflex.gear.pair.geometry import GearGeometry
from rotaflex.gear.pair.plane_stress import jacobian_determinants, stable_time_step
from rotaflex.gear.pair.tooth_mesh import COARSE, DEFAULT, build_tooth_mesh, mesh_quality

G = GearGeometry(module=3.175e-3, teeth=28, face_width=6.35e-3, tip_radius=0.047625, root_radius=0.04048)


def _distance_to_profile(g, pts):
    """Distance of points to the analytic profile (both flanks), as a fine polyline."""
    d = np.inf
    for sign in (1.0, -1.0):
        prof = g.profile(n_fillet=3000, n_involute=3000) * [sign, 1.0]
        a, b = prof[:-1], prof[1:]
        ab = b - a
        t = np.einsum("pnk,nk->pn", pts[:, None, :] - a[None], ab) / np.einsum("nk,nk->n", ab, ab)
        q = a[None] + np.clip(t, 0, 1)[..., None] * ab[None]
        d = np.minimum(d, np.linalg.norm(pts[:, None, :] - q, axis=2).min(axis=1))
    return d


@pytest.mark.parametrize("kw", [COARSE, DEFAULT])
def test_topology_and_quality(kw):
    m = build_tooth_mesh(G, **kw)
    assert m.elements.shape[1] == 8 and m.nodes.shape[1] == 2
    assert np.array_equal(np.unique(m.elements), np.arange(m.n_nodes))  # no orphan nodes
    assert np.all(jacobian_determinants(m) > 0)  # counter-clockwise, not distorted
    # mid-side node 4 + i lies between corners i and i + 1 (within the curvature of the edge)
    c = m.nodes[m.elements[:, :4]]
    chord = np.roll(c, -1, axis=1) - c
    rel = m.nodes[m.elements[:, 4:]] - c
    t = np.einsum("eik,eik->ei", rel, chord) / np.einsum("eik,eik->ei", chord, chord)
    assert np.all(np.abs(t - 0.5) < 0.05)  # well-centred mid-side nodes
    perp = np.abs(rel[..., 0] * chord[..., 1] - rel[..., 1] * chord[..., 0]) / np.einsum("eik,eik->ei", chord, chord)
    assert perp.max() < 0.15  # curved edges only as curved as the boundary
    # every element edge is shared by at most two elements, boundary edges form one closed loop
    e = m.elements
    edges = np.sort(np.stack([e[:, [0, 1, 2, 3]], e[:, [1, 2, 3, 0]]], axis=-1).reshape(-1, 2), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    assert counts.max() == 2
    n_boundary = int((counts == 1).sum())
    n_expected = 2 * (kw["n_flank"] + 2 * kw["n_fillet"] + kw["n_rim"] + kw["n_through"])
    assert n_boundary == n_expected
    q = mesh_quality(m)
    assert q["min_jacobian_ratio"] > 0.5 and q["max_aspect_ratio"] < 6


def test_area_matches_sector_area():
    # area of the modelled sector from the analytic profile (shoelace), independent of the mesh
    from rotaflex.gear.pair.plane_stress import GAUSS_WEIGHTS

    m = build_tooth_mesh(G, **DEFAULT)
    fine = build_tooth_mesh(G, n_flank=40, n_through=20, n_fillet=8, n_rim=12)
    area_fe = float((jacobian_determinants(m) * GAUSS_WEIGHTS).sum())
    area_fine = float((jacobian_determinants(fine) * GAUSS_WEIGHTS).sum())
    half = math.pi / G.teeth
    right = G.profile(2000, 2000)[::-1]  # tip corner -> root
    th = np.linspace(G.root_half_angle, half, 200)
    land = np.column_stack([G.root_radius_ * np.sin(th), G.root_radius_ * np.cos(th)])
    th2 = np.linspace(half, -half, 2000)
    rim = np.column_stack([m.rim_radius * np.sin(th2), m.rim_radius * np.cos(th2)])
    left = G.profile(2000, 2000) * [-1, 1]
    left_land = land[::-1] * [-1, 1]
    psi = G.flank_half_angle(np.array([G.tip_radius_]))[0]
    th3 = np.linspace(-psi, psi, 500)[1:-1]
    tip = np.column_stack([G.tip_radius_ * np.sin(th3), G.tip_radius_ * np.cos(th3)])
    poly = np.vstack([right, land, rim, left_land, left, tip])  # clockwise
    x, y = poly[:, 0], poly[:, 1]
    area = 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))
    # quadratic edges on the sharp fillet: 2e-5 on the default mesh, converging under refinement
    assert area_fe == pytest.approx(area, rel=5e-5)
    assert area_fine == pytest.approx(area, rel=1e-6)


def test_boundary_node_sets_follow_contract():
    m = build_tooth_mesh(G, **DEFAULT)
    r = np.hypot(*m.nodes.T)
    for side, sign in (("left", -1), ("right", 1)):
        f = m.flank_nodes[side]
        assert f.size % 2 == 1 and f.size == 2 * (DEFAULT["n_flank"] + DEFAULT["n_fillet"]) + 1
        p = m.nodes[f]
        assert np.all(np.sign(p[:, 0]) == sign)
        assert np.all(np.diff(r[f]) >= -1e-12)  # root -> tip
        assert r[f[-1]] == pytest.approx(G.tip_radius_, rel=1e-12)
        assert r[f[0]] == pytest.approx(G.root_radius_, rel=1e-12)
        # every flank node (corner and mid-side) lies on the analytic tooth profile or root circle
        on_land = np.abs(r[f] - G.root_radius_) < 1e-12
        assert _distance_to_profile(G, p[~on_land]).max() < 1e-8
    # left/right mirror symmetry of the whole mesh
    mirrored = m.nodes * [-1, 1]
    d = np.hypot(mirrored[:, None, 0] - m.nodes[None, :, 0], mirrored[:, None, 1] - m.nodes[None, :, 1])
    assert d.min(axis=1).max() < 1e-12
    # tip nodes on the tip circle, root nodes on the rim arc or the side cuts
    assert np.allclose(r[m.tip_nodes], G.tip_radius_, rtol=1e-12)
    rn = m.nodes[m.root_nodes]
    ang = np.abs(np.arctan2(rn[:, 0], rn[:, 1]))
    on_cut = np.isclose(ang, math.pi / G.teeth, rtol=1e-9) | np.isclose(r[m.root_nodes], m.rim_radius)
    assert on_cut.all()
    n_bottom = 2 * (DEFAULT["n_through"] + 2 * DEFAULT["n_fillet"]) + 1
    assert m.root_nodes.size == n_bottom + 2 * (2 * DEFAULT["n_rim"] + 1) - 2
    only_bottom = build_tooth_mesh(G, **DEFAULT, support="bottom")
    assert only_bottom.root_nodes.size == n_bottom


def test_default_mesh_is_stable_for_paper_time_step():
    m = build_tooth_mesh(G, **DEFAULT)
    assert stable_time_step(m, 210e9, 0.3, 7800.0) > 3e-8
    # a fine mesh is not: the check the dynamics relies on has teeth
    fine = build_tooth_mesh(G, n_flank=16, n_through=6, n_fillet=5, n_rim=5)
    assert stable_time_step(fine, 210e9, 0.3, 7800.0) < 3e-8


def test_bad_mesh_parameters():
    with pytest.raises(InputError, match="n_flank"):
        build_tooth_mesh(G, n_flank=0)
    with pytest.raises(InputError, match="rim_depth_coef"):
        build_tooth_mesh(G, rim_depth_coef=-1.0)


def test_write_vtu_round_trip(tmp_path):
    import meshio

    from rotaflex.gear.results.export import write_vtu

    m = build_tooth_mesh(G, **COARSE)
    u = np.arange(2 * m.n_nodes, dtype=float) * 1e-9
    path = write_vtu(tmp_path / "tooth.vtu", m, displacement=u, cell_data={"id": np.arange(m.n_elements)})
    back = meshio.read(path)
    assert back.cells[0].type == "quad8"
    assert np.array_equal(back.cells[0].data, m.elements)
    assert np.allclose(back.points[:, :2], m.nodes)
    assert np.allclose(back.point_data["displacement"][:, :2], u.reshape(-1, 2))
    with pytest.raises(InputError, match="displacement"):
        write_vtu(tmp_path / "bad.vtu", m, displacement=np.zeros(5))
    assert not (tmp_path / "bad.vtu").exists()
