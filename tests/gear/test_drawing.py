"""Gears as on a drawing: ISO 21771 pair geometry (independent formulas, a published example),
swap symmetry, one-line InputErrors naming the dotted field, relief in the flank geometry."""

import copy
import math

import numpy as np
import pytest
from scipy.optimize import brentq

from rotaflex.core.config import from_mapping
from rotaflex.core.errors import InputError
from rotaflex.gear.pair.drawing import GearSpec, pair_from_mapping
from rotaflex.gear.pair.geometry import GearGeometry
from rotaflex.gear.pair.tooth_mesh import COARSE, DEFAULT, build_tooth_mesh

PAIR = {
    "pinion": {"teeth": 19, "module": 2.5e-3, "face_width": 0.02, "profile_shift": 0.3},
    "wheel": {"teeth": 47, "module": 2.5e-3, "face_width": 0.02, "profile_shift": -0.2},
}


def _with(path, value, base=PAIR):
    d = copy.deepcopy(base)
    node = d
    keys = path.split(".")
    for k in keys[:-1]:
        node = node.setdefault(k, {})
    node[keys[-1]] = value
    return d


def _inv(a):
    return math.tan(a) - a


def test_pair_geometry_matches_iso21771_formulas_computed_here():
    p = pair_from_mapping(PAIR)
    m, a0 = 2.5e-3, math.radians(20.0)
    z1, z2, x1, x2 = 19, 47, 0.3, -0.2
    # operating pressure angle: root of inv(aw) = inv(a) + 2 tan(a) (x1+x2)/(z1+z2) (bracketed)
    target = _inv(a0) + 2 * math.tan(a0) * (x1 + x2) / (z1 + z2)
    aw = brentq(lambda a: _inv(a) - target, 0.1, 0.8, xtol=1e-15)
    assert p.operating_pressure_angle == pytest.approx(aw, abs=1e-12)
    aw_dist = 0.5 * m * (z1 + z2) * math.cos(a0) / math.cos(aw)
    assert p.working_center_distance == pytest.approx(aw_dist, rel=1e-12)
    # tip / base radii and contact ratio
    ra1, ra2 = 0.5 * m * z1 + (1 + x1) * m, 0.5 * m * z2 + (1 + x2) * m
    rb1, rb2 = 0.5 * m * z1 * math.cos(a0), 0.5 * m * z2 * math.cos(a0)
    eps = (math.sqrt(ra1**2 - rb1**2) + math.sqrt(ra2**2 - rb2**2) - aw_dist * math.sin(aw)) / (
        math.pi * m * math.cos(a0)
    )
    assert p.contact_ratio == pytest.approx(eps, rel=1e-12)
    # tip thickness s_a = d_a (s/d + inv(a) - inv(a_a))
    g1, g2 = p.gears
    for g, z, x, ra in ((g1, z1, x1, ra1), (g2, z2, x2, ra2)):
        s = m * (math.pi / 2 + 2 * x * math.tan(a0))
        aa = math.acos(0.5 * m * z * math.cos(a0) / ra)
        assert g.tip_thickness == pytest.approx(2 * ra * (s / (m * z) + _inv(a0) - _inv(aa)), rel=1e-12)
    # backlash at a larger centre distance: thickness sum on the operating pitch circles
    a1 = aw_dist + 0.1e-3
    aw1 = math.acos((rb1 + rb2) / a1)
    rw1, rw2 = rb1 / math.cos(aw1), rb2 / math.cos(aw1)

    def s_at(z, x, r):
        return 2 * r * ((math.pi / 2 + 2 * x * math.tan(a0)) / z + _inv(a0) - _inv(aw1))

    jbn = (2 * math.pi * rw1 / z1 - s_at(z1, x1, rw1) - s_at(z2, x2, rw2)) * math.cos(aw1)
    p1 = pair_from_mapping(_with("center_distance", a1))
    assert p1.normal_backlash_at(a1) == pytest.approx(jbn, rel=1e-10)
    # first-order check of that number: j_bn ~ 2 (a' - a_w) sin(a_w)
    assert jbn == pytest.approx(2 * 0.1e-3 * math.sin(aw), rel=0.01)
    # a backlash given instead of the centre distance gives that centre distance back
    assert pair_from_mapping(_with("backlash", jbn)).working_center_distance == pytest.approx(a1, rel=1e-12)


def test_published_example_khk_profile_shifted_pair():
    # KHK Gear Technical Reference, profile-shifted spur gear example (reproduced at
    # bolsover.com "Profile Shifted External Spur Gears"): m = 3 mm, alpha = 20 deg,
    # z = 12 / 24, x = 0.6 / 0.36, outside diameters 44.84 / 79.40 mm ->
    # inv(alpha_w) = 0.034317, alpha_w = 26.0888 deg (KHK: 26.0886), a = 56.4999 mm,
    # root diameters 32.10 / 66.66 mm, contact ratio 1.202.
    d = {
        "pinion": {"teeth": 12, "module": 3e-3, "face_width": 0.02, "profile_shift": 0.6, "tip_radius": 44.84e-3 / 2},
        "wheel": {"teeth": 24, "module": 3e-3, "face_width": 0.02, "profile_shift": 0.36, "tip_radius": 79.40e-3 / 2},
    }
    p = pair_from_mapping(d)
    assert _inv(p.operating_pressure_angle) == pytest.approx(0.034317, abs=1e-6)
    assert math.degrees(p.operating_pressure_angle) == pytest.approx(26.0887, abs=3e-4)
    assert p.working_center_distance == pytest.approx(56.4999e-3, abs=1e-7)
    g1, g2 = p.gears
    assert 2 * g1.root_radius_ == pytest.approx(32.10e-3, abs=1e-8)
    assert 2 * g2.root_radius_ == pytest.approx(66.66e-3, abs=1e-8)
    assert p.contact_ratio == pytest.approx(1.202, abs=6e-4)


def test_swapping_pinion_and_wheel_swaps_the_geometry():
    p = pair_from_mapping(PAIR)
    q = pair_from_mapping({"pinion": PAIR["wheel"], "wheel": PAIR["pinion"]})
    a, b = p.summary(), q.summary()
    for key in ("center_distance", "operating_pressure_angle_deg", "contact_ratio", "path_of_contact"):
        assert a[key] == pytest.approx(b[key], rel=1e-12)
    assert a["pinion_tip_thickness"] == b["wheel_tip_thickness"]
    assert a["wheel_inertia"] == b["pinion_inertia"]
    assert q.ratio == pytest.approx(1 / p.ratio)


@pytest.mark.parametrize(
    "path, value, field",
    [
        ("pinion.teeth", 10, "pinion.profile_shift"),  # undercut (x >= 0.4151 needed)
        ("pinion.profile_shift", 1.0, "pinion.profile_shift"),  # tip thickness < 0.2 m
        ("pinion.profile_shift", 1.2, "pinion.tip_radius"),  # pointed (thickness < 0)
        ("wheel.module", 3e-3, "wheel.module"),
        ("wheel.pressure_angle_deg", 25.0, "wheel.pressure_angle_deg"),
        ("center_distance", 0.08, "center_distance"),  # contact ratio < 1
        ("center_distance", 0.0824, "center_distance"),  # negative backlash
        ("wheel.tip_radius", 0.0615, "wheel.tip_radius"),  # below the pinion's form circle
        ("pinion.tip_relief", {"amount": 6e-4, "start_diameter": 0.0525}, "pinion.tip_relief.amount"),
        ("wheel.root_relief", {"amount": 5e-4, "start_diameter": 0.1155}, "wheel.root_relief.amount"),
        ("pinion.tip_relief", {"amount": 1e-5, "start_diameter": 0.06}, "pinion.tip_relief.start_diameter"),
        ("pinion.teeth", 19.5, "pinion.teeth"),
        ("pinion.module", 3.0, "pinion.module"),  # millimetres typed as metres
    ],
)
def test_bad_pairs_raise_one_line_naming_the_field(path, value, field):
    with pytest.raises(InputError) as exc:
        pair_from_mapping(_with(path, value))
    assert exc.value.field == field
    assert "\n" not in str(exc.value)


def test_limits_stated_in_the_messages():
    with pytest.raises(InputError, match=r"tip thickness is >= 0.0005 m \(0.2 x module\); this profile shift leaves"):
        pair_from_mapping(_with("pinion.profile_shift", 1.0))
    with pytest.raises(InputError, match="to avoid undercut with 10 teeth"):
        pair_from_mapping(_with("pinion.teeth", 10))
    with pytest.raises(InputError, match="negative backlash"):
        pair_from_mapping(_with("center_distance", 0.0824))
    with pytest.raises(InputError, match="fillet interference"):
        pair_from_mapping(_with("wheel.tip_radius", 0.0615))
    # 13/80 teeth: a wheel tip reaching beyond the pinion's base-circle tangency point T1
    d = _with("wheel.teeth", 80, _with("pinion.teeth", 13, _with("pinion.profile_shift", 0.5)))
    d = _with("wheel.profile_shift", 0.0, d)
    pair_from_mapping(_with("wheel.tip_radius", 0.1025, d))  # still fine
    with pytest.raises(InputError, match="tip interference") as exc:
        pair_from_mapping(_with("wheel.tip_radius", 0.104, d))
    assert exc.value.field == "wheel.tip_radius"


def test_relief_is_in_the_mesh_flank_nodes():
    spec = GearSpec(teeth=20, module=2e-3, face_width=0.02, profile_shift=0.25)
    plain = spec.geometry()
    rel = pair_from_mapping(
        {
            "pinion": {
                "teeth": 20,
                "module": 2e-3,
                "face_width": 0.02,
                "profile_shift": 0.25,
                "tip_relief": {"amount": 12e-6, "start_diameter": 0.0418},
                "root_relief": {"amount": 6e-6, "start_diameter": 0.0392, "shape": "parabolic"},
            },
            "wheel": {"teeth": 40, "module": 2e-3, "face_width": 0.02},
        }
    ).gears[0]
    m0 = build_tooth_mesh(plain, **DEFAULT)
    m1 = build_tooth_mesh(rel, **DEFAULT)
    assert m0.nodes.shape == m1.nodes.shape
    p1 = m1.nodes[m1.flank_nodes["right"]]
    big_r = np.hypot(*p1.T)
    inv = big_r >= plain.form_radius * (1 + 1e-6)
    p1, big_r = p1[inv], big_r[inv]
    rb = plain.base_radius
    # a point at angle d_theta inside the true involute at the same radius lies on that
    # involute rotated by d_theta, whose normal distance from it is rb d_theta (involute
    # property); along that normal the roll length of the true involute point is u + depth
    d_theta = plain.flank_half_angle(big_r) - np.arctan2(p1[:, 0], p1[:, 1])
    depth = rb * d_theta
    r_nom = np.sqrt(rb**2 + (np.sqrt(big_r**2 - rb**2) + depth) ** 2)
    # expected depth from the relief definition, written here: linear / parabolic in roll length
    u = np.sqrt(r_nom**2 - rb**2)
    ua = math.sqrt(plain.tip_radius_**2 - rb**2)
    us = math.sqrt(0.0209**2 - rb**2)
    uf = math.sqrt(plain.form_radius**2 - rb**2)
    ur = math.sqrt(0.0196**2 - rb**2)
    tip = 12e-6 * np.clip((u - us) / (ua - us), 0, 1)
    root = 6e-6 * np.clip((ur - u) / (ur - uf), 0, 1) ** 2
    assert np.abs(depth - (tip + root)).max() < 1e-10
    assert depth.max() == pytest.approx(12e-6, rel=1e-6)
    assert (tip > 0).sum() >= 5 and (root > 0).sum() >= 2
    # the rim is untouched
    assert np.array_equal(m0.nodes[m0.root_nodes], m1.nodes[m1.root_nodes])


def test_paper_gear_through_the_drawing_spec_is_bit_identical():
    from rotaflex.gear.cases.simulate_config import GearConfig  # defaults: the paper data of gear/paper.py

    paper = GearConfig()
    spec = GearSpec(
        teeth=paper.teeth,
        module=paper.module,
        face_width=paper.face_width,
        pressure_angle_deg=paper.pressure_angle_deg,  # the config key: degrees
        tip_radius=paper.tip_radius,
        root_radius=paper.root_radius,
    )
    g = spec.geometry()
    assert g == paper.geometry()
    a = build_tooth_mesh(g, **COARSE, **spec.mesh_options())
    b = build_tooth_mesh(paper.geometry(), **COARSE)
    assert np.array_equal(a.nodes, b.nodes) and np.array_equal(a.root_nodes, b.root_nodes)


def test_root_clamp_is_stiffer_than_the_default_rim():
    from rotaflex.gear.static.tooth_analysis import tooth_compliance

    g = GearGeometry(module=3.175e-3, teeth=28, face_width=6.35e-3, tip_radius=0.047625, root_radius=0.04048)
    r = np.array([0.04445, 0.0470])
    rim = tooth_compliance(build_tooth_mesh(g, **DEFAULT), r, 210e9, 0.3).structural
    clamp = tooth_compliance(build_tooth_mesh(g, **DEFAULT, support="root_circle"), r, 210e9, 0.3).structural
    # measured (docs/gear-static.md): rim / clamp = 1.47 at the pitch, 1.32 near the tip
    assert rim / clamp == pytest.approx([1.467, 1.317], abs=0.01)


def test_blank_inertia_solid_and_rimmed():
    rho, b = 7800.0, 0.02
    spec = GearSpec(teeth=40, module=2e-3, face_width=b)
    rf, ra = spec.geometry().root_radius_, spec.geometry().tip_radius_
    teeth = 0.5 * 0.5 * math.pi * rho * b * (ra**4 - rf**4)
    assert spec.inertia() == pytest.approx(0.5 * math.pi * rho * b * rf**4 + teeth, rel=1e-12)
    base = {"teeth": 40, "module": 2e-3, "face_width": b}
    rimmed = from_mapping(
        GearSpec,
        {
            **base,
            "blank": {
                "kind": "rimmed",
                "rim_thickness": 5e-3,
                "web_thickness": 6e-3,
                "hub_diameter": 0.03,
                "bore_diameter": 0.02,
            },
        },
    )
    assert rimmed.inertia() < spec.inertia()
    with pytest.raises(InputError, match="gear.blank.hub_diameter"):
        from_mapping(
            GearSpec,
            {**base, "blank": {"kind": "rimmed", "rim_thickness": 5e-3, "web_thickness": 6e-3, "hub_diameter": 0.09}},
        ).inertia()
