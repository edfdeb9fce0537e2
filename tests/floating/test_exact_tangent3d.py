"""The analytic tangent of the 3-D exact beam element.

Independent references: central differences of the element force under the same
multiplicative perturbations (a second, numerical derivative of the same force); the
Lie-bracket identity of a gradient on the rotation group (the tangent of a potential's
spatial-spin gradient differs from its transpose by ``-m~`` on each node's rotation block, ``m``
the node's moment: ``exp(a~) exp(b~)`` and ``exp(b~) exp(a~)`` differ by ``exp((a x b)~)`` to
second order), hence symmetry where the moments balance; Newton's quadratic rate on a 3-D
elastica (observed order of the residuals).
"""

from __future__ import annotations

import numpy as np
import pytest

from rotaflex.core.threads import limit_blas_threads
from rotaflex.floating import exact_kernels3d as ek3
from rotaflex.floating.exact_beam3d import PointLoads3D, arc3d, assemble3d, cantilever3d, solve_static, straight3d
from rotaflex.rotation import rotation_matrix


@pytest.fixture(autouse=True, scope="module")
def _one_blas_thread():
    with limit_blas_threads():
        yield


def two_beams():
    """A curved and a straight beam, unequal section stiffnesses, arbitrary section frames."""
    arc = arc3d(
        2.0, 1.0, 4, ea=30.0, ga=(20.0, 10.0), gj=2.0, ei2=3.0, ei3=4.0, frame=rotation_matrix("123", (1, 2, 3))
    )
    bar = straight3d(1.5, 3, ea=80.0, ga=(15.0, 25.0), gj=1.0, ei2=6.0, ei3=2.5, start=(0.0, 1.0, 0.0))
    return assemble3d([arc, bar], [True, False])


def moved(b, rng, size):
    """The reference state moved by random increments of ``size`` (m and rad)."""
    q = b.reference_state()
    dx = size * rng.standard_normal(b.n_dof)
    dx[b.frame_dof :] = 0.0
    ek3.advance(q, dx)
    return q


def forces(b, q, mode):
    """Internal force and tangent (``mode`` 1 analytic, 2 central differences)."""
    n = b.n_dof
    f, K = np.zeros(n), np.zeros((n, n))
    gam0, kap0 = b._ref
    ek3.internal(q, b.conn, b.reference_lengths(), gam0, kap0, b.stiffness, f, K, mode)
    return f, K


@pytest.mark.parametrize("size", [1e-6, 1e-3, 0.05, 0.4, 1.2])
def test_analytic_tangent_equals_central_differences(size):
    # from nearly undeformed (the series branches of the coefficients, relative rotations of
    # 1e-6 rad) to large rotations (random spins of 1.2 rad per node: relative rotations up
    # to about 2.5 rad, the closed forms)
    rng = np.random.default_rng(int(1e6 * size))
    b = two_beams()
    for _ in range(3):
        q = moved(b, rng, size)
        f, K = forces(b, q, 1)
        f2, Kfd = forces(b, q, 2)
        assert np.array_equal(f, f2)
        # central differences: truncation ~(1e-6)^2 and round-off ~1e-16 / 1e-6 of K
        assert K == pytest.approx(Kfd, abs=1e-6 * np.abs(Kfd).max())
        # the geometric part is checked too: it is not small against that tolerance here
        if size >= 0.4:
            Kref = forces(b, b.reference_state(), 1)[1]
            assert np.abs(K - Kref).max() > 0.1 * np.abs(Kref).max()


def spin_skew(m):
    return np.array([[0.0, -m[2], m[1]], [m[2], 0.0, -m[0]], [-m[1], m[0], 0.0]])


def test_skew_part_is_the_bracket_of_the_nodal_moments():
    rng = np.random.default_rng(5)
    b = two_beams()
    q = moved(b, rng, 0.8)
    f, K = forces(b, q, 1)
    S = K - K.T
    expect = np.zeros_like(S)
    for i in range(b.n_nodes):
        r = slice(6 * i + 3, 6 * i + 6)
        expect[r, r] = -spin_skew(f[r])
    assert S == pytest.approx(expect, abs=1e-12 * np.abs(K).max())
    # and it is not zero away from equilibrium
    assert np.abs(S).max() > 1e-2 * np.abs(K).max()


def test_tangent_is_symmetric_at_an_equilibrium_under_forces_fixed_in_space():
    # a 3-D elastica: EI2 != EI3, tip force oblique to both principal planes
    b = cantilever3d(1.0, 6, ea=1e4, ga=1e4, gj=0.7, ei2=2.0, ei3=1.0)
    loads = PointLoads3D.build(b, [(1.0, 0.0, 0.0)], ["force"], ["inertial"], [(0.0, -3.0, 2.0)])
    q = solve_static(b, loads, tol=1e-12).q
    r, K, _ = b.residual(loads, q, 1.0)
    free = slice(6, b.frame_dof)  # the clamped node 0 carries the clamp's reaction moment
    assert np.abs(r[free]).max() < 1e-9
    Kf = K[free, free]
    assert Kf == pytest.approx(Kf.T, abs=1e-9 * np.abs(Kf).max())
    # the clamped node's rotation block is skew by minus its moment: the reaction of the clamp
    S = K - K.T
    assert S[3:6, 3:6] == pytest.approx(-spin_skew(r[3:6]), abs=1e-9 * np.abs(K).max())
    assert np.abs(r[3:6]).max() > 1.0  # the root moment is not small (|M| ~ 3.6 N m)


def newton(b, loads, q, mult, spoil=0.0, n_iter=9):
    """Newton iterations of the bordered clamp system at the full load from ``q`` (multipliers
    ``mult``) with the tangent times ``1 + spoil`` (a deliberately inconsistent tangent when
    ``spoil`` > 0). Returns the residuals [N] and the largest
    position/rotation corrections [m, rad] of each iteration."""
    clamp = b.clamp_table()
    free = np.arange(b.frame_dof)
    nf = len(free)
    g, G = np.zeros(6), np.zeros((6, b.n_dof))
    res, steps = [], []
    for _ in range(n_iter):
        r, K, _ = b.residual(loads, q, 1.0)
        K = K * (1.0 + spoil)
        b.constrain(q, clamp, g, G)
        r = r + G.T @ mult
        A = np.zeros((nf + 6, nf + 6))
        A[:nf, :nf], A[:nf, nf:], A[nf:, :nf] = K[np.ix_(free, free)], G[:, free].T, G[:, free]
        dx = np.linalg.solve(A, -np.concatenate([r[free], g]))
        b.advance(q, free, dx[:nf])
        mult = mult + dx[nf:]
        res.append(np.abs(r[free]).max())
        steps.append(np.abs(dx[:nf]).max())
    return np.array(res), np.array(steps)


def observed_orders(e, floor):
    """``log(e_k+1 / e_k) / log(e_k / e_k-1)`` over the values above ``floor``."""
    e = e[e > floor]
    return np.log(e[2:] / e[1:-1]) / np.log(e[1:-1] / e[:-2])


def test_newton_on_the_elastica_converges_quadratically():
    # from the equilibrium at 90 % of an oblique tip load straight to the full load: Newton
    # with the bordered clamp system (multipliers started at the clamp's reaction; G = I on
    # the clamped node 0). Round-off floor: ~3e-13 N of the residual (EA = 300 N), so ~1e-13
    # of the corrections; orders are taken above 1e-11
    b = cantilever3d(1.0, 8, ea=300.0, ga=200.0, gj=0.7, ei2=2.0, ei3=1.0)
    loads = PointLoads3D.build(b, [(1.0, 0.0, 0.0)], ["force"], ["inertial"], [(0.0, -4.0, 2.0)])
    q0 = solve_static(b, loads, target=0.9, tol=1e-13).q
    mult0 = -b.residual(loads, q0, 0.9, want_k=False)[0][:6]
    res, steps = newton(b, loads, q0.copy(), mult0)
    print("\nNewton residuals [N]:", " ".join(f"{x:.2e}" for x in res))
    print("corrections [m, rad]:", " ".join(f"{x:.2e}" for x in steps))
    order = observed_orders(steps, 1e-11)
    print("observed orders of the corrections:", np.round(order, 2))
    assert res[4] < 1e-11  # at the round-off floor after 4 corrections
    assert order[-1] > 1.8, order
    e = steps[steps > 1e-11]
    assert e[-1] < 5.0 * e[-2] ** 2  # the quadratic contraction constant (1.1 here)
    # the same test tells a tangent 1 % off: linear convergence (rate 0.01, order 1)
    res_b, steps_b = newton(b, loads, q0.copy(), mult0, spoil=0.01)
    print("tangent 1 % off, residuals:", " ".join(f"{x:.2e}" for x in res_b))
    order_b = observed_orders(steps_b, 1e-14)
    print("tangent 1 % off, corrections:", " ".join(f"{x:.2e}" for x in steps_b))
    assert res_b[4] > 1e-9 and np.all(np.abs(order_b[-2:] - 1.0) < 0.2), order_b
