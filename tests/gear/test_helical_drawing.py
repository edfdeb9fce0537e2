"""Helical pairs on a drawing: ISO 21771 quantities computed here from the standard's formulas
(normal module, normal profile shift), a published example, beta = 0 as the spur pair, and the
one-line refusals naming the key."""

import copy
import math

import pytest
from scipy.optimize import brentq

from rotaflex.core.errors import InputError
from rotaflex.gear.pair.drawing import pair_from_mapping


def _inv(a):
    return math.tan(a) - a


def _pair(z1, z2, mn, beta, b, x1=0.0, x2=0.0, **root):
    common = {"module": mn, "face_width": b, "helix_angle_deg": beta}
    return {
        "pinion": {"teeth": z1, "profile_shift": x1, "hand": "right", **common},
        "wheel": {"teeth": z2, "profile_shift": x2, "hand": "left", **common},
        **root,
    }


def _iso21771(z1, z2, mn, beta_deg, b, x1, x2, a_given=None, alpha_n_deg=20.0, ha=1.0):
    """The standard's formulas, written out here (ISO 21771:2007, sections 4-5)."""
    beta, an = math.radians(beta_deg), math.radians(alpha_n_deg)
    mt = mn / math.cos(beta)
    at = math.atan(math.tan(an) / math.cos(beta))
    d1, d2 = z1 * mt, z2 * mt
    db1, db2 = d1 * math.cos(at), d2 * math.cos(at)
    bb = math.asin(math.sin(beta) * math.cos(an))  # sin(beta_b) = sin(beta) cos(alpha_n)
    da1, da2 = d1 + 2 * (ha + x1) * mn, d2 + 2 * (ha + x2) * mn
    target = _inv(at) + 2 * math.tan(an) * (x1 + x2) / (z1 + z2)
    awt0 = brentq(lambda a: _inv(a) - target, 1e-3, 1.2, xtol=1e-15)
    a0 = 0.5 * (d1 + d2) * math.cos(at) / math.cos(awt0)
    a = a0 if a_given is None else a_given
    awt = math.acos(0.5 * (db1 + db2) / a)
    pbt = math.pi * mt * math.cos(at)
    g_alpha = 0.5 * (math.sqrt(da1**2 - db1**2) + math.sqrt(da2**2 - db2**2)) - a * math.sin(awt)
    eps_a = g_alpha / pbt
    eps_b = b * math.sin(beta) / (math.pi * mn)
    return {
        "transverse_module": mt,
        "transverse_pressure_angle_deg": math.degrees(at),
        "base_helix_angle_deg": math.degrees(bb),
        "pinion_lead": math.pi * d1 / math.tan(beta),
        "wheel_lead": math.pi * d2 / math.tan(beta),
        "axial_pitch": math.pi * mn / math.sin(beta),
        "transverse_base_pitch": pbt,
        "overlap_ratio": eps_b,
        "total_contact_ratio": eps_a + eps_b,
        "contact_ratio": eps_a,
        "center_distance_no_backlash": a0,
        "center_distance": a,
        "operating_pressure_angle_deg": math.degrees(awt),
        # tan(beta_w) = tan(beta) d_w / d with d_w = d_b / cos(alpha_wt)
        "working_helix_angle_deg": math.degrees(math.atan(math.tan(beta) * math.cos(at) / math.cos(awt))),
        "pinion_tip_radius": 0.5 * da1,
        "wheel_tip_radius": 0.5 * da2,
    }


@pytest.mark.parametrize(
    "case",
    [
        dict(z1=20, z2=40, mn=2e-3, beta_deg=15.0, b=0.02, x1=0.0, x2=0.0),
        # profile-shifted pair at a given (larger) centre distance
        dict(z1=17, z2=53, mn=3e-3, beta_deg=22.0, b=0.035, x1=0.35, x2=-0.1, a_given=0.1142),
    ],
)
def test_helical_geometry_matches_iso21771_formulas(case):
    ref = _iso21771(**case)
    root = {} if case.get("a_given") is None else {"center_distance": case["a_given"]}
    p = pair_from_mapping(
        _pair(case["z1"], case["z2"], case["mn"], case["beta_deg"], case["b"], case["x1"], case["x2"], **root)
    )
    s = p.summary()
    for key, val in ref.items():
        assert s[key] == pytest.approx(val, rel=1e-11, abs=1e-14), key
    # the transverse geometry is the spur gear of module m_t and pressure angle alpha_t
    g1, _ = p.gears
    assert g1.pitch_radius == pytest.approx(0.5 * case["z1"] * ref["transverse_module"], rel=1e-14)


def test_backlash_of_helical_pair_at_larger_centre_distance():
    # j_bn = j_wt cos(alpha_wt) cos(beta_b), to first order 2 (a' - a_w) sin(alpha_wt) cos(beta_b)
    d = _pair(17, 53, 3e-3, 22.0, 0.035, 0.35, -0.1)
    a0 = pair_from_mapping(d).center_distance_no_backlash
    p = pair_from_mapping({**d, "center_distance": a0 + 20e-6})
    ref = _iso21771(17, 53, 3e-3, 22.0, 0.035, 0.35, -0.1)
    first = 2 * 20e-6 * math.sin(math.radians(ref["operating_pressure_angle_deg"]))
    first *= math.cos(math.radians(ref["base_helix_angle_deg"]))
    assert p.normal_backlash_at(a0) == pytest.approx(0.0, abs=1e-15)
    assert p.summary()["normal_backlash"] == pytest.approx(first, rel=2e-3)


def test_published_example_khk_helical_profile_shifted():
    # KHK Gear Technical Reference, helical gear, normal system, profile shifted: m_n = 3 mm,
    # alpha_n = 20 deg, beta = 30 deg, z = 12 / 60, x_n = 0.09809 / 0, a = 125 mm ->
    # alpha_t = 22.79588 deg, inv(alpha_wt) = 0.023405, alpha_wt = 23.1126 deg, d = 41.569 mm
    p = pair_from_mapping(_pair(12, 60, 3e-3, 30.0, 0.03, 0.09809, 0.0))
    s = p.summary()
    assert s["transverse_pressure_angle_deg"] == pytest.approx(22.79588, abs=1e-5)
    assert s["operating_pressure_angle_deg"] == pytest.approx(23.1126, abs=1e-4)
    assert _inv(math.radians(s["operating_pressure_angle_deg"])) == pytest.approx(0.023405, abs=1e-6)
    assert s["center_distance"] == pytest.approx(0.125, abs=2e-6)
    assert 2 * p.gears[0].pitch_radius == pytest.approx(41.569e-3, abs=1e-6)


def test_zero_helix_is_the_spur_pair():
    spur = {
        "pinion": {"teeth": 19, "module": 2.5e-3, "face_width": 0.02, "profile_shift": 0.3},
        "wheel": {"teeth": 47, "module": 2.5e-3, "face_width": 0.02, "profile_shift": -0.2},
    }
    zero = copy.deepcopy(spur)
    zero["pinion"]["helix_angle_deg"] = 0.0
    zero["wheel"]["helix_angle_deg"] = 0.0
    p0, p1 = pair_from_mapping(spur), pair_from_mapping(zero)
    assert p0.gears == p1.gears and p0.summary() == p1.summary()
    assert "overlap_ratio" not in p0.summary()
    # a tiny helix angle tends to the spur numbers (continuity of the transverse section)
    tiny = copy.deepcopy(spur)
    for g, hand in (("pinion", "right"), ("wheel", "left")):
        tiny[g].update(helix_angle_deg=1e-6, hand=hand)
    s0, st = p0.summary(), pair_from_mapping(tiny).summary()
    for key in ("center_distance", "contact_ratio", "operating_pressure_angle_deg", "pinion_tip_radius"):
        assert st[key] == pytest.approx(s0[key], rel=1e-12), key


@pytest.mark.parametrize(
    "path, value, key",
    [
        ("pinion.helix_angle_deg", 45.0, "pinion.helix_angle_deg"),
        ("pinion.helix_angle_deg", -1.0, "pinion.helix_angle_deg"),
        ("wheel.hand", "right", "wheel.hand"),
        ("wheel.helix_angle_deg", 14.0, "wheel.helix_angle_deg"),
        ("pinion.hand", None, "pinion.hand"),
        ("pinion.profile_shift", -0.5, "pinion.profile_shift"),
    ],
)
def test_bad_helical_input_names_the_key(path, value, key):
    d = _pair(20, 40, 2e-3, 15.0, 0.02)
    gear, k = path.split(".")
    if value is None:
        d[gear].pop(k)
    else:
        d[gear][k] = value
    with pytest.raises(InputError) as err:
        pair_from_mapping(d)
    assert err.value.field == key
    assert "\n" not in str(err.value)


def test_undercut_bound_is_given_in_normal_terms():
    # ISO 21771 undercut limit of a helical gear cut by a rack with a tip round rho_fP: the
    # straight flank ends h_fP - rho_fP (1 - sin(alpha_n)) below the reference line (normal
    # section, same height in the transverse one), so
    # x_n,min = h_fP* - rho_fP* (1 - sin(alpha_n)) - z sin^2(alpha_t) / (2 cos(beta))
    d = _pair(12, 40, 2e-3, 15.0, 0.02)
    with pytest.raises(InputError) as err:
        pair_from_mapping(d)
    bound = float(str(err.value).split(">= ")[1].split()[0])
    an, beta = math.radians(20), math.radians(15)
    at = math.atan(math.tan(an) / math.cos(beta))
    x_min = 1.25 - 0.38 * (1 - math.sin(an)) - 12 * math.sin(at) ** 2 / (2 * math.cos(beta))
    assert err.value.field == "pinion.profile_shift"
    assert bound == pytest.approx(x_min, abs=1e-4)
    # and just above the bound the gear is accepted
    d["pinion"]["profile_shift"] = x_min + 1e-3
    pair_from_mapping(d)


def test_spur_only_verbs_refuse_a_helical_pair_naming_the_key():
    p = pair_from_mapping(_pair(20, 40, 2e-3, 15.0, 0.02))
    with pytest.raises(InputError) as err:
        p.spur_only("gear simulate")
    assert err.value.field == "pinion.helix_angle_deg"
    with pytest.raises(InputError) as err:
        p.spur_only("system", "gear_mesh[0]")
    assert err.value.field == "gear_mesh[0].pinion.helix_angle_deg"
    # a lead-modified spur pair too (its lead would be ignored)
    lead = _pair(20, 40, 2e-3, 0.0, 0.02)
    for g in ("pinion", "wheel"):
        lead[g].pop("hand")
    lead["wheel"]["lead"] = {"crowning": 5e-6}
    with pytest.raises(InputError) as err:
        pair_from_mapping(lead).spur_only("gear simulate")
    assert err.value.field == "wheel.lead"
    # a hand on a spur gear is refused too (it would say nothing)
    with pytest.raises(InputError) as err:
        pair_from_mapping(_pair(20, 40, 2e-3, 0.0, 0.02))
    assert err.value.field == "pinion.hand"
