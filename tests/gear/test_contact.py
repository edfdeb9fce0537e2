"""Contact search and sliding kinematics against analytic cases (two circles, a line)."""

import numpy as np
import pytest

from rotaflex.gear.pair.contact_geometry import normal_rates, search, spline_point


def arc(centre, radius, a0, a1, n=61):
    t = np.linspace(a0, a1, n)
    return np.column_stack([centre[0] + radius * np.cos(t), centre[1] + radius * np.sin(t)])


def test_spline_reproduces_cubic_data_interior():
    s = np.linspace(0, 1, 61)
    pts = np.column_stack([s, np.sin(2 * s)])
    e = spline_point(pts, 0.437)
    assert abs(e[0, 1] - np.sin(0.874)) < 1e-6
    assert abs(e[1, 1] - 2 * np.cos(0.874)) < 1e-3


def test_two_circles_distance_and_normal():
    # A: circle radius 1 centred at origin, arc around +x; B: radius 0.5 centred at (1.6, 0.1)
    ca, ra = np.array([0.0, 0.0]), 1.0
    cb, rb = np.array([1.6, 0.1]), 0.5
    pa = arc(ca, ra, -0.6, 0.6)  # counter-clockwise: outward normal = tangent turned -90
    pb = arc(cb, rb, np.pi + 0.7, np.pi - 0.7)  # clockwise around B: outward = tangent turned +90
    pair = search(pa, pb, sig_a=-1.0, sig_b=1.0)
    d = np.linalg.norm(cb - ca)
    assert pair.case == "interior"
    assert abs(pair.gap - (d - ra - rb)) < 1e-6
    assert np.allclose(pair.normal, (cb - ca) / d, atol=1e-6)


def test_penetration_is_negative_gap():
    pa = arc((0.0, 0.0), 1.0, -0.6, 0.6)
    pb = arc((1.4, 0.0), 0.5, np.pi + 0.7, np.pi - 0.7)
    pair = search(pa, pb, sig_a=-1.0, sig_b=1.0)
    assert abs(pair.gap - (1.4 - 1.5)) < 1e-6


def test_tip_corner_on_flank():
    # B ends (tip) short of the common normal: corner of B projected on A's straight flank
    pa = np.column_stack([np.zeros(61), np.linspace(-1, 1, 61)])  # line x = 0, up
    pb = arc((0.8, 0.9), 0.7, np.pi + 0.2, np.pi + 0.9)  # ends at angle pi+0.9 (lower end)
    pair = search(pa, pb, sig_a=-1.0, sig_b=1.0)
    corner = pb[-1]
    assert pair.case == "tip_B"
    assert abs(abs(pair.gap) - abs(corner[0])) < 1e-6


@pytest.mark.parametrize("case", ["interior"])
def test_sliding_terms_against_finite_differences(case):
    """Two rigidly rotating circles: s(t) from repeated searches, s_dot and s_ddot by FD."""
    ca, cb = np.array([0.0, 0.0]), np.array([1.55, 0.2])
    ra, rb = 1.0, 0.5
    wa, wb = 3.0, -5.0
    # surfaces are off-centre arcs (material points) so that rotation moves the contact point
    ea, eb = np.array([0.05, -0.02]), np.array([-0.03, 0.04])
    la = arc(ea, ra, -0.8, 0.8)
    lb = arc(eb, rb, np.pi + 0.9, np.pi - 0.9)

    def state(t):
        qa = np.array([[np.cos(wa * t), -np.sin(wa * t)], [np.sin(wa * t), np.cos(wa * t)]])
        qb = np.array([[np.cos(wb * t), -np.sin(wb * t)], [np.sin(wb * t), np.cos(wb * t)]])
        pa = la @ qa.T + ca
        pb = lb @ qb.T + cb
        va = wa * np.column_stack([-(pa - ca)[:, 1], (pa - ca)[:, 0]])
        vb = wb * np.column_stack([-(pb - cb)[:, 1], (pb - cb)[:, 0]])
        aa = -(wa**2) * (pa - ca)
        ab = -(wb**2) * (pb - cb)
        return pa, pb, va, vb, aa, ab

    def s_of(t):
        pa, pb, *_ = state(t)
        return -search(pa, pb, -1.0, 1.0).gap

    pa, pb, va, vb, aa, ab = state(0.0)
    r = normal_rates(pa, va, pb, vb, -1.0, 1.0)
    pair = r["pair"]
    n = pair.normal
    acc_a = spline_point(aa, pair.a)[0]
    acc_b = spline_point(ab, pair.b)[0]
    s_ddot = n @ (acc_a - acc_b) + r["sliding"]
    h = 1e-4
    fd1 = (s_of(h) - s_of(-h)) / (2 * h)
    fd2 = (s_of(h) - 2 * s_of(0.0) + s_of(-h)) / h**2
    assert abs(r["s_dot"] - fd1) < 1e-6 * max(1.0, abs(fd1))
    assert abs(s_ddot - fd2) < 1e-3 * max(1.0, abs(fd2))
    # the sliding part matters here (not a trivially zero check)
    assert abs(r["sliding"]) > 0.01 * abs(s_ddot)
