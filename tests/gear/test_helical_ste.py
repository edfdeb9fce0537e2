"""Sliced helical STE: the spur pair as the one-slice limit, slice convergence (observed order),
the overlap-ratio law of mesh-stiffness fluctuation, force balance, the slice coupling against an
independent Winkler solution, lead modifications, ISO 6336-1 helical terms, bad input."""

import dataclasses
import math

import numpy as np
import pytest
from scipy.optimize import brentq

from rotaflex.core.errors import InputError
from rotaflex.gear.cases.static import gear_meshes
from rotaflex.gear.pair.drawing import pair_from_mapping
from rotaflex.gear.static.helical import FaceModel, face_model, slice_positions, sliced_te
from rotaflex.gear.static.loaded_te import loaded_te, pair_line
from rotaflex.gear.static.tooth_analysis import iso6336_stiffness

MN, BETA = 2e-3, 15.0


def _pair(beta=BETA, b=0.02, **lead):
    c = {"module": MN, "face_width": b, "helix_angle_deg": beta}
    hands = ({"hand": "right"}, {"hand": "left"}) if beta else ({}, {})
    pin = {"teeth": 20, **c, **hands[0], **({"lead": lead} if lead else {})}
    return pair_from_mapping({"pinion": pin, "wheel": {"teeth": 40, **c, **hands[1]}})


def _line(pair):
    g1, g2 = pair.gears
    m1, m2 = gear_meshes(pair, "coarse")
    force = 100.0 / g1.base_radius
    return pair_line(g1, g2, m1, m2, pair.working_center_distance, force, (210e9, 0.3, 210e9, 0.3), 9)


@pytest.fixture(scope="module")
def helical():
    p = _pair()
    return p, _line(p)


@pytest.fixture(scope="module")
def spur():
    p = _pair(0.0)
    return p, _line(p)


def _cycle(line, n=200):
    return line.s_start + line.base_pitch * np.arange(n) / n


def _face(pair, n=20, lam=0.0, b=None, gap=None):
    b = pair.face_width if b is None else b
    return FaceModel(b, pair.base_helix_angle, 1, n, lam, np.zeros(n) if gap is None else gap)


def test_zero_helix_slices_add_up_to_the_spur_pair(spur):
    pair, line = spur
    s = _cycle(line)
    ref = loaded_te(line, s)
    for n in (1, 7, 20):
        res = sliced_te(line, _face(pair, n, lam=MN), s)
        np.testing.assert_allclose(res["stiffness"], ref["stiffness"], rtol=1e-12)
        np.testing.assert_allclose(res["te"], ref["te"], rtol=1e-12)


def test_slice_convergence_observed_order(helical):
    pair, line = helical
    s = _cycle(line, 120)
    out = {n: sliced_te(line, _face(pair, n), s) for n in (10, 20, 40, 80, 640)}
    ref = out[640]
    err = [np.max(np.abs(out[n]["stiffness"] - ref["stiffness"])) / ref["stiffness"].mean() for n in (10, 20, 40, 80)]
    mean_err = [
        abs(out[n]["stiffness"].mean() - ref["stiffness"].mean()) / ref["stiffness"].mean() for n in (10, 20, 40)
    ]
    order = -np.polyfit(np.log([10, 20, 40, 80]), np.log(err), 1)[0]
    # a slice enters contact as a whole: the pointwise error is first order in 1/N (fitted
    # over 10..80 slices), the cycle mean (midpoint rule over the contact lines) converges faster
    assert 0.8 < order < 1.5, (err, order)
    assert err[1] < 0.02  # 20 slices: within 2 % of the 640-slice curve, pointwise
    assert max(mean_err) < 2e-3


def _fluct(line, pair, eps_beta, n=200):
    b = eps_beta * math.pi * MN / math.sin(math.radians(BETA))
    res = sliced_te(line, _face(pair, n, b=b), _cycle(line, 150))
    k = res["stiffness"] / b  # per unit face width
    return (k.max() - k.min()) / k.mean()


def test_integer_overlap_ratio_gives_small_fluctuation_falling_with_eps_beta(helical):
    pair, line = helical
    non = {e: _fluct(line, pair, e) for e in (0.5, 1.5, 2.5)}
    whole = {e: _fluct(line, pair, e) for e in (1.0, 2.0)}
    # classic result: the total contact line length is constant for an integer overlap ratio
    assert whole[1.0] < 0.25 * non[0.5] and whole[1.0] < 0.5 * non[1.5]
    assert whole[2.0] < 0.5 * non[2.5]
    # and the fluctuation at non-integer eps_beta falls as eps_beta grows (~ 1 / eps_beta)
    assert non[0.5] > non[1.5] > non[2.5]
    assert non[0.5] / non[2.5] == pytest.approx(5.0, rel=0.35)


def _winkler(k, gap, force):
    """Independent slices: f_j = k_j max(delta - e_j, 0), sum f = F (bracketed root)."""
    delta = brentq(
        lambda d: np.sum(k * np.maximum(d - gap, 0.0)) - force, gap.min(), gap.min() + force / k.min(), xtol=1e-18
    )
    return k * np.maximum(delta - gap, 0.0), delta


def test_crowned_independent_slices_match_a_winkler_solution_and_coupling_limits(helical):
    pair, line = helical
    crowned = _pair(crowning=8e-6)
    n = 24
    face0 = face_model(crowned, n, 0.0, 0.0)
    s = _cycle(line, 40)
    res = sliced_te(line, face0, s)
    for i in (0, 17, 33):
        inside = res["load"][i] > 0.0
        sl = res["s"][i]
        m = (sl >= line.s_start) & (sl <= line.s_end)
        k = (1.0 / n) / line.compliance(sl[m])
        gap = line.gap(sl[m]) + np.broadcast_to(face0.lead_gap, sl.shape)[m]
        f, delta = _winkler(k, gap, line.force)
        np.testing.assert_allclose(res["load"][i][m], f, rtol=1e-9, atol=1e-9 * line.force)
        assert res["te"][i] == pytest.approx(delta, rel=1e-10)
        assert inside.sum() == (f > 0).sum()
    # force balance with coupling: sum of slice loads = F; normal force F / cos(beta_b)
    coupled = sliced_te(line, dataclasses.replace(face0, coupling_length=2 * MN), s)
    np.testing.assert_allclose(coupled["load"].sum(axis=(1, 2)), line.force, rtol=1e-7)
    # a vanishing coupling length tends to the independent slices
    weak = sliced_te(line, dataclasses.replace(face0, coupling_length=1e-3 * MN), s)
    np.testing.assert_allclose(weak["load"], res["load"], rtol=0, atol=1e-4 * res["load"].max())
    # uniform gap: the coupling shears nothing (same loads as independent slices)
    flat = sliced_te(line, _face(pair, n, lam=2 * MN, gap=np.full(n, 3e-6)), s)
    base = sliced_te(line, _face(pair, n, lam=0.0, gap=np.full(n, 3e-6)), s)
    np.testing.assert_allclose(flat["load"], base["load"], rtol=1e-8, atol=1e-9 * line.force)


def test_misalignment_moves_the_load_to_the_closed_end(helical):
    pair, line = helical
    n = 20
    z = slice_positions(pair.face_width, n)
    face = face_model(pair, n, 1.0, 4e-4)  # gap = 4e-4 z: open at +z
    res = sliced_te(line, face, _cycle(line, 30))
    per_slice = res["load"].sum(axis=(0, 1))
    assert np.sum(per_slice * z) / np.sum(per_slice) < -0.05 * pair.face_width
    assert per_slice[0] > 2 * per_slice[-1]
    np.testing.assert_allclose(face.lead_gap, 4e-4 * z, rtol=1e-12)


def test_normal_and_axial_force_from_iso_formulas():
    # F_n = T / (r_b cos(beta_b)), F_a = T tan(beta_w) / r_w (written out from ISO 21771 here)
    p = _pair()
    torque = 100.0
    an, beta = math.radians(20.0), math.radians(BETA)
    at = math.atan(math.tan(an) / math.cos(beta))
    rb1 = 0.5 * 20 * MN / math.cos(beta) * math.cos(at)
    bb = math.asin(math.sin(beta) * math.cos(an))
    a = p.working_center_distance
    rw1 = a * 20 / 60
    bw = math.atan(math.tan(beta) * rw1 / (0.5 * 20 * MN / math.cos(beta)))
    line_force = torque / p.gears[0].base_radius
    assert line_force / math.cos(p.base_helix_angle) == pytest.approx(torque / (rb1 * math.cos(bb)), rel=1e-12)
    assert line_force * math.tan(p.base_helix_angle) == pytest.approx(torque * math.tan(bw) / rw1, rel=1e-12)


def test_iso6336_helical_stiffness_terms():
    p = _pair(b=0.03)
    g1, g2 = p.gears
    iso = iso6336_stiffness(
        g1,
        g2,
        load_per_width=200.0,
        eps_alpha=p.contact_ratio,
        helix_angle=math.radians(BETA),
        base_helix_angle=p.base_helix_angle,
    )
    beta = math.radians(BETA)
    bb = math.asin(math.sin(beta) * math.cos(math.radians(20.0)))
    zn1, zn2 = 20 / (math.cos(bb) ** 2 * math.cos(beta)), 40 / (math.cos(bb) ** 2 * math.cos(beta))
    q = 0.04723 + 0.15551 / zn1 + 0.25791 / zn2
    c_prime = 1 / q * 0.8 * 1.0 * 0.975 * math.cos(beta)  # C_M, C_R, C_B (h_fP = 1.25 m_n), cos(beta)
    assert iso["q"] == pytest.approx(q, rel=1e-12)
    assert iso["c_single"] == pytest.approx(c_prime, rel=1e-12)
    assert iso["c_gamma"] == pytest.approx(c_prime * (0.75 * p.contact_ratio + 0.25), rel=1e-12)
    assert iso["c_gamma_beta"] == pytest.approx(0.85 * iso["c_gamma"], rel=1e-12)


def test_bad_face_input_names_the_key():
    with pytest.raises(InputError) as err:
        face_model(_pair(b=0.002), 40, 1.0, 0.0)
    assert err.value.field == "pinion.face_width"
    with pytest.raises(InputError) as err:
        _pair(end_relief=5e-6)
    assert err.value.field == "pinion.lead.end_relief_length"
    d = {"module": MN, "helix_angle_deg": BETA}
    with pytest.raises(InputError) as err:
        pair_from_mapping(
            {
                "pinion": {"teeth": 20, "face_width": 0.02, "hand": "right", **d},
                "wheel": {"teeth": 40, "face_width": 0.025, "hand": "left", **d},
            }
        )
    assert err.value.field == "wheel.face_width"


def test_lead_modification_depths_by_hand():
    from rotaflex.gear.pair.lead import LeadSpec

    b = 0.04
    z = np.array([-0.02, -0.015, 0.0, 0.01, 0.02])
    crown = LeadSpec(crowning=6e-6).depth(z, b)
    np.testing.assert_allclose(crown, 6e-6 * (2 * z / b) ** 2, rtol=1e-14)
    assert crown[0] == pytest.approx(6e-6) and crown[2] == 0.0
    # linear end relief of 10 um over 10 mm from each end: 5 um at 5 mm from the end
    rel = LeadSpec(end_relief=10e-6, end_relief_length=0.01).depth(z, b)
    np.testing.assert_allclose(rel, [10e-6, 5e-6, 0.0, 0.0, 10e-6], rtol=1e-12, atol=1e-20)
    par = LeadSpec(end_relief=10e-6, end_relief_length=0.01, end_relief_shape="parabolic").depth(z, b)
    assert par[1] == pytest.approx(2.5e-6)
    slope = LeadSpec(slope_deviation=-4e-6).depth(z, b)
    np.testing.assert_allclose(slope, -4e-6 * z / b, rtol=1e-14)
