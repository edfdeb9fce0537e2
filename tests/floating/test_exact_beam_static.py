"""Statics of the planar geometrically exact beam against closed-form large-deflection solutions.

References: the elastica of a cantilever under a tip load fixed in direction (Bisshopp &
Drucker 1945, Quart. Appl. Math. 3, 272-275), computed here from Legendre's incomplete elliptic
integrals and cross-checked by quadrature of the same first integral; the pure-bending circle
(curvature M / EI); Timoshenko's small-deflection cantilever ``P L^3 / 3 EI + P L / k G A``.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq
from scipy.special import ellipeinc, ellipkinc

from rotaflex.core.errors import InputError
from rotaflex.floating.exact_beam import LoadSteppingError, PointLoads, cantilever, solve_static

STIFF = 1e8  # EA, GA [N] for EI = 1 N m^2, L = 1 m: the inextensible, shear-rigid limit


def elastica_tip(alpha: float) -> tuple[float, float, float]:
    """Tip ``(x / L, deflection / L, tip angle)`` of the elastica for ``alpha = P L^2 / EI``.

    ``EI theta' ^2 / 2 = P (sin theta0 - sin theta)``; with ``1 + sin theta = 2 k^2 sin^2 phi``:
    ``sqrt(alpha) = F(k) - F(k, phi1)``, ``sin phi1 = 1 / (k sqrt 2)``,
    ``y / L = 1 - 2 (E(k) - E(k, phi1)) / sqrt(alpha)``, ``x / L = sqrt(2 sin theta0 / alpha)``.
    """
    lam = np.sqrt(alpha)

    def length_gap(k):
        m = k * k
        phi1 = np.arcsin(1.0 / (k * np.sqrt(2.0)))
        return ellipkinc(np.pi / 2, m) - ellipkinc(phi1, m) - lam

    k = brentq(length_gap, 1.0 / np.sqrt(2.0) + 1e-15, 1.0 - 1e-15, xtol=1e-15)
    m = k * k
    phi1 = np.arcsin(1.0 / (k * np.sqrt(2.0)))
    th0 = np.arcsin(2.0 * m - 1.0)
    y = 1.0 - 2.0 * (ellipeinc(np.pi / 2, m) - ellipeinc(phi1, m)) / lam
    x = np.sqrt(2.0 * np.sin(th0) / alpha)
    return x, y, th0


def elastica_by_quadrature(alpha: float) -> tuple[float, float]:
    """The same tip from the first integral by quadrature (tip angle from the length condition)."""

    def integral(f, th0):
        # the substitution sin th = sin th0 (1 - u^2) removes the 1/sqrt singularity at th0
        def g(u):
            s = np.sin(th0) * (1.0 - u * u)
            th = np.arcsin(s)
            return f(th) * 2.0 * u * np.sin(th0) / (np.cos(th) * np.sqrt(np.sin(th0)) * u)

        return quad(g, 0.0, 1.0, epsabs=1e-13, epsrel=1e-13, limit=200)[0]

    th0 = brentq(lambda t: integral(lambda th: 1.0, t) - np.sqrt(2.0 * alpha), 1e-6, np.pi / 2 - 1e-12, xtol=1e-15)
    x = integral(np.cos, th0) / np.sqrt(2.0 * alpha)
    y = integral(np.sin, th0) / np.sqrt(2.0 * alpha)
    return x, y


def tip_under_load(alpha, n_el, ea=STIFF, ga=STIFF, frame="inertial"):
    b = cantilever(1.0, n_el, ea=ea, ga=ga, ei=1.0, rho_a=1.0)
    loads = PointLoads.build(b, [(1.0, 0.0, 0.0)], ["force"], [frame], [(0.0, -alpha)])
    q = solve_static(b, loads).q
    return q[3 * n_el], -q[3 * n_el + 1], -q[3 * n_el + 2]


def test_elliptic_reference_matches_bisshopp_drucker_and_quadrature():
    # Bisshopp & Drucker (1945), Table 1 at P L^2 / EI = 1: vertical 0.30172 L, horizontal
    # shortening 0.05643 L
    x, y, _ = elastica_tip(1.0)
    assert y == pytest.approx(0.30172, abs=1e-5)
    assert 1.0 - x == pytest.approx(0.05643, abs=1e-5)
    for alpha in (1.0, 2.0, 5.0, 10.0):
        xq, yq = elastica_by_quadrature(alpha)
        xe, ye, _ = elastica_tip(alpha)
        assert (xq, yq) == pytest.approx((xe, ye), abs=1e-9)


@pytest.mark.parametrize("alpha", [1.0, 2.0, 5.0, 10.0])
def test_elastica_tip_load(alpha):
    x, y, th = elastica_tip(alpha)
    xt, yt, tht = tip_under_load(alpha, 64)
    # 64 elements: the O(h^2) discretisation error is below 2e-4 L here (see the order test)
    assert xt == pytest.approx(x, abs=2e-4)
    assert yt == pytest.approx(y, abs=2e-4)
    assert tht == pytest.approx(th, abs=2e-4)


def test_mesh_convergence_is_second_order():
    _, y, _ = elastica_tip(5.0)
    n = np.array([4, 8, 16, 32])
    err = np.array([abs(tip_under_load(5.0, k)[1] - y) for k in n])
    order = np.log(err[:-1] / err[1:]) / np.log(2.0)
    assert np.all(order > 1.85) and np.all(order < 2.15), order


def test_end_moment_rolls_a_full_circle():
    n = 40
    b = cantilever(2.0, n, ea=1e6, ga=1e6, ei=3.0, rho_a=1.0)
    loads = PointLoads.build(b, [(2.0, 0.0, 0.0)], ["torque"], ["inertial"], [(2 * np.pi * 3.0 / 2.0, 0.0)])
    q = solve_static(b, loads).q
    tip = q[3 * n : 3 * n + 3]
    assert np.hypot(tip[0], tip[1]) < 1e-9 * 2.0
    assert tip[2] == pytest.approx(2 * np.pi, rel=1e-12)
    # zero axial and shear strain, constant curvature M / EI: the nodes are the corners of a
    # regular n-gon of side L / n, on a circle of radius (L / n) / (2 sin(pi / n)), which tends
    # to EI / M = L / (2 pi)
    xy = q[: 3 * (n + 1)].reshape(-1, 3)[:, :2]
    side = np.hypot(*np.diff(xy, axis=0).T)
    assert np.allclose(side, 2.0 / n, rtol=1e-12)
    centre = xy.mean(axis=0) * (n + 1) / n - xy[0] / n  # the n distinct corners' mean
    radius = np.hypot(*(xy - centre).T)
    assert np.allclose(radius, (2.0 / n) / (2 * np.sin(np.pi / n)), rtol=1e-12)


def test_small_load_timoshenko_shear_and_extension():
    # shear: P L^3 / (3 EI) + P L / GA; extension: P L / EA (linear limit, load 1e-6 of critical)
    ei, ga, ea, L, P = 2.0, 50.0, 80.0, 1.5, 1e-6
    b = cantilever(L, 64, ea=ea, ga=ga, ei=ei, rho_a=1.0)
    q = solve_static(b, PointLoads.build(b, [(L, 0.0)], ["force"], ["inertial"], [(0.0, -P)])).q
    expected = P * L**3 / (3 * ei) + P * L / ga
    # discretisation: the one-point element's bending part is P L^3 / 3 EI (1 + 1 / (4 n^2)) off
    assert -q[3 * 64 + 1] == pytest.approx(expected, rel=1e-4)
    q = solve_static(b, PointLoads.build(b, [(L, 0.0)], ["force"], ["inertial"], [(P, 0.0)])).q
    assert q[3 * 64] - L == pytest.approx(P * L / ea, rel=1e-9)


def test_extensible_shear_beam_leaves_the_elastica():
    # with EA = GA = 20 EI / L^2 the tip of alpha = 2 is visibly off the inextensible elastica,
    # and the rigid limit returns to it
    _, y, _ = elastica_tip(2.0)
    soft = tip_under_load(2.0, 32, ea=20.0, ga=20.0)[1]
    rigid = tip_under_load(2.0, 32)[1]
    assert abs(soft - y) > 1e-2
    assert abs(rigid - y) < 5e-4


def test_follower_force_stays_normal_to_the_tip():
    # a follower force normal to the tip section: the equilibrium tip force is perpendicular to
    # the tip tangent, and at small load it equals the fixed-direction result
    n = 32
    b = cantilever(1.0, n, ea=STIFF, ga=STIFF, ei=1.0, rho_a=1.0)
    q = solve_static(b, PointLoads.build(b, [(1.0, 0.0)], ["force"], ["material"], [(0.0, -3.0)])).q
    th = q[3 * n + 2]
    # moment balance about the root: M_root = F x r with F = 3 (sin th, -cos th)
    F = 3.0 * np.array([np.sin(th), -np.cos(th)])
    r = q[3 * n : 3 * n + 2]
    m_root = r[0] * F[1] - r[1] * F[0]
    # EI theta'(0): curvature of the first element; the tip rotates more than under a fixed load
    assert abs(th) > abs(tip_under_load(3.0, n)[2])
    kappa0 = (q[5] - q[2]) / (1.0 / n)
    assert -m_root == pytest.approx(-kappa0, rel=0.05)
    small = solve_static(b, PointLoads.build(b, [(1.0, 0.0)], ["force"], ["material"], [(0.0, -1e-6)])).q
    assert -small[3 * n + 1] == pytest.approx(1e-6 / 3.0, rel=1e-3)


def test_load_beyond_reach_reports_the_fraction():
    # a tip load of 1e4 EI / L^2 with at most 3 Newton iterations per step and steps of at
    # least 5 % of the load cannot be followed: the error names the fraction reached
    b = cantilever(1.0, 8, ea=STIFF, ga=STIFF, ei=1.0, rho_a=1.0)
    loads = PointLoads.build(b, [(1.0, 0.0)], ["force"], ["inertial"], [(0.0, -1e4)])
    with pytest.raises(LoadSteppingError, match="load fraction"):
        solve_static(b, loads, max_iter=3, min_step=0.05)


@pytest.mark.parametrize(
    ("key", "kw"),
    [
        ("ei", {"ei": 0.0}),
        ("ea", {"ea": -1.0}),
        ("ga", {"ga": 0.0}),
        ("elements", {"n": 0}),
        ("elements", {"n": 10_000}),
    ],
)
def test_bad_section_data_names_the_key(key, kw):
    args = {"ea": 1.0, "ga": 1.0, "ei": 1.0, "rho_a": 1.0}
    n = kw.pop("n", 4)
    args.update(kw)
    with pytest.raises(InputError, match=rf"body\.exact\.{key} ="):
        cantilever(1.0, n, **args)
