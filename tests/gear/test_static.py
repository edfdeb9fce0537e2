"""Static tooth analysis: load consistency, compliance convergence, mesh stiffness, root stress."""

import math

import numpy as np
import pytest

from rotaflex.gear.pair.geometry import GearGeometry, contact_angles
from rotaflex.gear.pair.tooth_mesh import COARSE, DEFAULT, build_tooth_mesh
from rotaflex.gear.static.tooth_analysis import (
    flank_contact_point,
    iso6336_stiffness,
    mesh_stiffness,
    root_stress,
    root_stress_points,
    solve_static,
    stiffness_matrix,
    surface_load,
    tooth_compliance,
)

E, NU = 210e9, 0.3
G = GearGeometry(module=3.175e-3, teeth=28, face_width=6.35e-3, tip_radius=0.047625, root_radius=0.04048)
F = 22.25 / G.base_radius  # paper's nominal normal load, 532.7 N


def refined(k):
    return build_tooth_mesh(G, **{key: k * v for key, v in DEFAULT.items()})


def test_surface_load_resultant_acts_on_line_of_action():
    m = build_tooth_mesh(G, **DEFAULT)
    for side in ("right", "left"):
        f = surface_load(m, 0.0455, F, 1e-4, side=side)
        fx, fy = f[0::2].sum(), f[1::2].sum()
        assert math.hypot(fx, fy) == pytest.approx(F, rel=1e-12)
        # the line of action is tangent to the base circle: moment about the centre = F r_b
        moment = (m.nodes[:, 0] * f[1::2] - m.nodes[:, 1] * f[0::2]).sum()
        assert abs(moment) == pytest.approx(F * G.base_radius, rel=2e-4)
        p, d = flank_contact_point(G, 0.0455, side)
        assert np.allclose([fx, fy], F * d, rtol=1e-12)


def test_static_equilibrium_reactions():
    m = build_tooth_mesh(G, **COARSE)
    f = surface_load(m, 0.046, F, 1e-4)
    u = solve_static(m, f, E, NU)
    r = stiffness_matrix(m, E, NU) @ u - f  # reactions, non-zero only at the root nodes
    free = np.setdiff1d(np.arange(m.n_nodes), m.root_nodes)
    assert np.abs(r[2 * free]).max() < 1e-8 * F and np.abs(r[2 * free + 1]).max() < 1e-8 * F
    assert r[0::2].sum() == pytest.approx(-f[0::2].sum(), rel=1e-9)
    assert r[1::2].sum() == pytest.approx(-f[1::2].sum(), rel=1e-9)


def test_structural_compliance_converges_load_point_does_not():
    radii = np.array([0.0425, 0.04445, 0.0470])
    c = [tooth_compliance(refined(k), radii, E, NU, force=F) for k in (1, 2, 3)]
    s = np.array([ci.structural for ci in c])
    lp = np.array([ci.load_point for ci in c])
    d1, d2 = np.abs(s[1] - s[0]), np.abs(s[2] - s[1])
    assert np.all(d2 < d1 / 3)  # converging (observed order > 2.7 for a 2 -> 3 refinement)
    assert np.all(np.abs(s[0] / s[2] - 1) < 0.01)  # default mesh within 1 % of the refined one
    assert np.all(np.diff(s[2]) > 0)  # higher load point -> more compliant
    # the trap: the load-patch displacement keeps growing as elements approach the patch size
    assert np.all(lp[2] > lp[1]) and np.all(lp[1] > lp[0]) and np.all(lp[0] > s[0])


def test_mesh_stiffness_zones_and_iso_comparison():
    m = build_tooth_mesh(G, **DEFAULT)
    ms = mesh_stiffness(G, G, E, NU, torque=22.25, n_angles=401, mesh1=m, mesh2=m)
    theta_s, theta_2 = contact_angles(G, G)
    assert ms.theta_s == pytest.approx(theta_s) and ms.theta_2 == pytest.approx(theta_2)
    two = ms.mesh_stiffness > ms.pair_stiffness * (1 + 1e-9)
    expected_two = (ms.angle < theta_2 - 1e-9) | (ms.angle > theta_s - theta_2 + 1e-9)
    inner = (np.abs(ms.angle - theta_2) > 1e-3) & (np.abs(ms.angle - (theta_s - theta_2)) > 1e-3)
    assert np.array_equal(two[inner], expected_two[inner])
    assert np.all((ms.load_share > 0) & (ms.load_share <= 1))
    # symmetry of identical gears: the pair stiffness is symmetric about the middle of contact
    assert np.allclose(ms.pair_stiffness, ms.pair_stiffness[::-1], rtol=1e-3)
    # static TE = F / k; single-pair TE is larger than two-pair TE
    assert np.allclose(ms.transmission_error * ms.mesh_stiffness, ms.force)
    assert ms.transmission_error[~two].min() > ms.transmission_error[two].max()
    iso = iso6336_stiffness(G, G)
    assert iso["c_th"] == pytest.approx(1 / (0.04723 + 0.15551 / 28 + 0.25791 / 28))
    # FE single-pair stiffness vs ISO theoretical c'_th: same magnitude (difference discussed
    # in docs/gear-fe.md: plane stress, tied rim cuts, Weber contact term)
    ratio = ms.pair_stiffness.max() / iso["k_th"]
    assert 0.8 < ratio < 1.35


def test_root_stress_converges_and_matches_beam_estimate():
    r_load = 0.0472  # near the tip, patch fully on the flank
    vals = []
    for k in (1, 2, 3):
        m = refined(k)
        u = solve_static(m, surface_load(m, r_load, F, 8e-5), E, NU)
        vals.append(root_stress(m, u, E, NU))
    vals = np.array(vals)
    assert vals[2, 1] > 0 > vals[2, 0]  # loaded-side fillet in tension, other in compression
    assert np.all(np.abs(vals[1] / vals[2] - 1) < 0.01)
    assert np.all(np.abs(vals[0] / vals[2] - 1) < 0.08)
    # nominal bending + compression at the 30-degree section (ISO 6336-3 style, Y_S excluded)
    pts = root_stress_points(G)
    y30 = pts["right"][0][1]
    s_fn = 2 * pts["right"][0][0]
    pc, d = flank_contact_point(G, r_load)
    y_load = pc[1] + (-pc[0] / d[0]) * d[1]  # load line meets the centreline
    alpha_fen = math.atan2(-d[1], -d[0])
    h_fe = y_load - y30
    b = G.face_width
    sig_b = 6 * F * math.cos(alpha_fen) * h_fe / (b * s_fn**2)
    sig_c = F * math.sin(alpha_fen) / (b * s_fn)
    concentration = vals[2, 1] / (sig_b - sig_c)
    assert 1.2 < concentration < 2.5  # ISO stress correction factors Y_S lie in this range
    # history input: (nt, 2n) -> (nt, 2)
    m = refined(1)
    u = solve_static(m, surface_load(m, r_load, F, 8e-5), E, NU)
    hist = root_stress(m, np.stack([u, 2 * u]), E, NU)
    assert hist.shape == (2, 2) and np.allclose(hist[1], 2 * hist[0])
