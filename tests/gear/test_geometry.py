"""Involute geometry, rack-generated fillet and contact-ratio quantities (seed C, section 4)."""

import math

import numpy as np
import pytest

from rotaflex.core.errors import InputError
from rotaflex.gear.pair.geometry import (
    GearGeometry,
    center_distance_no_backlash,
    contact_angles,
    contact_ratio,
    path_of_contact,
)


def paper_gear(**kw):
    base = dict(module=3.175e-3, teeth=28, face_width=6.35e-3, tip_radius=0.047625, root_radius=0.04048)
    base.update(kw)
    return GearGeometry(**base)


def test_paper_numbers():
    # published in Lee & Jang, section 4 (rounded to the digits given there)
    g = paper_gear()
    assert g.pitch_radius == pytest.approx(0.04445, abs=1e-9)
    assert g.base_radius == pytest.approx(0.041770, abs=1e-6)
    assert path_of_contact(g, g) == pytest.approx(0.01535, abs=1e-5)
    assert g.base_pitch == pytest.approx(0.009373, abs=1e-6)
    assert contact_ratio(g, g) == pytest.approx(1.638, abs=1e-3)
    theta_s, theta_2 = contact_angles(g, g)
    assert math.degrees(theta_s) == pytest.approx(21.06, abs=0.01)
    assert math.degrees(theta_2) == pytest.approx(8.20, abs=0.01)
    # nominal normal load tau0 / r_b = 532.7 N
    assert 22.25 / g.base_radius == pytest.approx(532.7, abs=0.1)


def test_default_radii_match_explicit_ones():
    g = GearGeometry(module=3.175e-3, teeth=28, face_width=6.35e-3)
    assert g.tip_radius_ == pytest.approx(0.047625, rel=1e-12)
    assert g.root_radius_ == pytest.approx(0.04048, abs=2e-6)  # 1.25 m dedendum
    assert center_distance_no_backlash(g, g) == pytest.approx(2 * g.pitch_radius, rel=1e-12)


def test_profile_shift_center_distance():
    # x1 + x2 > 0 widens the centre distance: a = (r1 + r2) cos(a0) / cos(aw), aw from inv()
    g1 = GearGeometry(module=2e-3, teeth=20, face_width=0.01, profile_shift=0.3)
    g2 = GearGeometry(module=2e-3, teeth=40, face_width=0.01, profile_shift=0.2)
    a = center_distance_no_backlash(g1, g2)
    aw = math.acos((g1.base_radius + g2.base_radius) / a)
    lhs = math.tan(aw) - aw
    rhs = math.tan(math.radians(20)) - math.radians(20) + 2 * 0.5 * math.tan(math.radians(20)) / 60
    assert lhs == pytest.approx(rhs, rel=1e-10)
    assert a > g1.pitch_radius + g2.pitch_radius


def _cutter_distance(g, p, phi):
    """Signed distance of gear-frame points p (n,2) from the right cutter tooth at roll angles phi.

    Built directly from the rack description (not from the library's fillet formula): rack frame
    q = R(phi) p + (r phi, 0); the cutter tooth is right of the flank line above the round's tangent
    point and outside the round below it. Positive = outside the cutter.
    """
    a, rp = g.pressure_angle, g.pitch_radius
    rho = g.rack_tip_radius_coef * g.module
    s = g.pitch_thickness
    c, sn = np.cos(phi)[None, :], np.sin(phi)[None, :]
    x = c * p[:, :1] - sn * p[:, 1:] + rp * phi[None, :]
    y = sn * p[:, :1] + c * p[:, 1:]
    k = 0.5 * s * math.cos(a) + rp * math.sin(a)
    yc = g.root_radius_ + rho
    xc = (k + rho - yc * math.sin(a)) / math.cos(a)
    y_t = yc - rho * math.sin(a)
    d_line = k - (x * math.cos(a) + y * math.sin(a))
    # below the tangency: distance to the round (valid near the round, where the fillet is)
    d_round = np.where(x < xc, np.hypot(x - xc, y - yc) - rho, yc - rho - y)
    return np.where(y >= y_t, d_line, d_round)


@pytest.mark.parametrize("kw", [{}, {"profile_shift": 0.4, "tip_radius": None, "root_radius": None}])
def test_profile_is_envelope_of_generating_rack(kw):
    g = paper_gear(**kw)
    p = g.profile(n_fillet=25, n_involute=25)
    pa, pb = g.fillet_phi
    phi = np.linspace(pa - 0.5, pb + 0.5, 40001)
    d = _cutter_distance(g, p, phi)
    # every profile point is touched by the cutter but never cut into (within sampling error)
    assert np.all(d.min(axis=1) > -1e-8)
    assert np.all(d.min(axis=1) < 1e-8)


def test_fillet_joins_involute_and_root_circle():
    g = paper_gear()
    pa, pb = g.fillet_phi
    f = g.fillet_points(np.array([pa, pb]))
    assert np.hypot(*f[0]) == pytest.approx(g.root_radius_, rel=1e-12)
    r_form = np.hypot(*f[1])
    assert g.base_radius < r_form < 0.0425
    inv = g.involute_points(np.array([r_form]))[0]
    assert np.allclose(inv, f[1], atol=1e-12)
    # tangent continuity at the form point
    eps = 1e-7
    t_f = g.fillet_points(np.array([pb - eps]))[0] - f[1]
    t_i = g.involute_points(np.array([r_form + 1e-9]))[0] - inv
    cosang = abs(t_f @ t_i) / np.linalg.norm(t_f) / np.linalg.norm(t_i)
    assert cosang > 1 - 1e-6


def test_involute_normal_is_tangent_to_base_circle():
    g = paper_gear()
    r = np.linspace(g.base_radius * 1.01, g.tip_radius_, 7)
    p = g.involute_points(r)
    dp = g.involute_points(r + 1e-9) - p
    n = np.column_stack([dp[:, 1], -dp[:, 0]])
    n /= np.linalg.norm(n, axis=1)[:, None]
    # distance from the centre to the normal line equals r_b
    dist = np.abs(p[:, 0] * n[:, 1] - p[:, 1] * n[:, 0])
    assert np.allclose(dist, g.base_radius, rtol=1e-5)
    # tooth thickness on the pitch circle = pi m / 2 for x = 0
    psi = g.flank_half_angle(np.array([g.pitch_radius]))[0]
    assert 2 * g.pitch_radius * psi == pytest.approx(math.pi * g.module / 2, rel=1e-12)


def test_bad_inputs_raise_inputerror():
    with pytest.raises(InputError, match="profile_shift"):  # undercut: 10 teeth, x = 0
        GearGeometry(module=2e-3, teeth=10, face_width=0.01)
    GearGeometry(module=2e-3, teeth=10, face_width=0.01, profile_shift=0.45)  # shift cures it
    with pytest.raises(InputError, match="pointed"):
        GearGeometry(module=2e-3, teeth=10, face_width=0.01, profile_shift=1.2)
    with pytest.raises(InputError, match="contact ratio"):
        g = GearGeometry(module=2e-3, teeth=20, face_width=0.01, addendum_coef=0.4)
        contact_ratio(g, g)
    with pytest.raises(InputError, match="rack_tip_radius_coef"):
        GearGeometry(module=2e-3, teeth=20, face_width=0.01, rack_tip_radius_coef=0.55)
    with pytest.raises(InputError, match="module"):
        contact_ratio(paper_gear(), GearGeometry(module=2e-3, teeth=20, face_width=0.01))
