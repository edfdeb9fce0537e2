"""Equations: kernels vs an independent numpy Kane residual; eq. 32/42 reduction."""

import numpy as np
import pytest

from rotaflex.floating import kernels
from rotaflex.floating.beam import uniform_beam
from rotaflex.floating.body import phi_hat, skew
from rotaflex.floating.reduction import first_order_matrices, paper_matrices, planar_eq42
from rotaflex.floating.solve import pack_body, pack_loads


def kane_residual(body, V, w, q, p, Vd, wd, pd):
    """sum m L^T a + K q for a force-free body, written directly from the point kinematics."""
    c = body.points + body.shapes @ q
    a = (
        Vd
        + np.cross(wd, c)
        + body.shapes @ pd
        + np.cross(w, V)
        + np.cross(w, np.cross(w, c))
        + 2 * np.cross(w, body.shapes @ p)
    )
    m = body.masses
    Je = body.extra_inertia
    return np.concatenate(
        [
            m @ a,
            m @ np.cross(c, a) + Je @ wd + np.cross(w, Je @ w),
            np.einsum("k,kaj,ka->j", m, body.shapes, a) + body.stiffness @ q,
        ]
    )


@pytest.fixture(scope="module")
def body3d():
    # cantilever modes in a floating frame: not mean axes, all coupling terms present
    return uniform_beam(2.0, 1.5, 30.0, 3, support="cantilever", spatial=True, ei_z=45.0, section_radius=0.02)


def test_full_kernel_satisfies_kane_equations(body3d):
    n = body3d.n_modes
    rng = np.random.default_rng(1)
    y = np.concatenate([rng.normal(size=3), [1, 0, 0, 0], rng.normal(size=6 + 2 * n)])
    dy = kernels.rhs_full_py(0.0, y, pack_body(body3d), pack_loads(body3d, []), False)
    res = kane_residual(body3d, y[7:10], y[10:13], y[13 : 13 + n], y[13 + n :], dy[7:10], dy[10:13], dy[13 + n :])
    assert np.abs(res).max() < 1e-10


def test_perturbation_kernel_is_the_linearisation(body3d):
    n = body3d.n_modes
    rng = np.random.default_rng(2)
    V0, w0 = rng.normal(size=3), rng.normal(size=3)
    x1 = rng.normal(size=6 + n)
    q1 = rng.normal(size=n)
    y = np.zeros(25 + 2 * n)
    y[3] = 1.0
    y[7:10], y[10:13], y[19:25], y[25 : 25 + n], y[25 + n :] = V0, w0, x1[:6], q1, x1[6:]
    dy = kernels.rhs_perturbation_py(0.0, y, pack_body(body3d), pack_loads(body3d, []), False)
    acc0, xd1 = dy[7:13], np.concatenate([dy[19:25], dy[25 + n :]])

    def F(eps):
        return kane_residual(
            body3d,
            V0 + eps * x1[:3],
            w0 + eps * x1[3:6],
            eps * q1,
            eps * x1[6:],
            acc0[:3] + eps * xd1[:3],
            acc0[3:] + eps * xd1[3:6],
            eps * xd1[6:],
        )

    F0 = F(0.0)
    assert np.abs(F0[:6]).max() < 1e-12  # zero-order rigid equations hold
    errs = [np.abs(F(e) - (1 - e) * F0).max() for e in (1e-2, 1e-3)]
    assert errs[1] < 2e-2 * errs[0]  # remainder is O(eps^2): first order is exact


def test_eq42_planar_reduction_matrix_by_matrix():
    b = uniform_beam(2.0, 1.5, 30.0, 4, support="cantilever")
    Vx0, Vy0, thd, Vyd, thdd = 0.7, -0.3, 1.3, 0.4, -0.9
    k = first_order_matrices(b, [Vx0, Vy0, 0], [0, 0, thd], [0.2, Vyd, 0], [0, 0, thdd])
    e = planar_eq42(b, Vx0, Vy0, thd, Vyd, thdd)
    M0, G, K, d = k["M0"], k["G"], k["K"], k["d"]
    scale = np.abs(K).max()
    assert np.abs(M0[6:, 1] - e["Vy1_dot"]).max() < 1e-12
    assert np.abs(M0[6:, 5] - e["theta1_ddot"]).max() < 1e-12
    assert np.abs(G[6:, 0] - e["Vx1"]).max() < 1e-10
    assert np.abs(G[6:, 5] - e["theta1_dot"]).max() < 1e-10
    assert np.abs(G[6:, 6:]).max() < 1e-12
    assert np.abs(K[6:] - e["q1"]).max() < 1e-12 * scale
    assert np.abs(d[6:] - e["d3"]).max() < 1e-12 and np.abs(e["d3"]).max() > 0.1


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_eq44_inertial_form_matches_the_kernel_row(seed):
    from rotaflex.floating.reduction import planar_eq44_residual, planar_inertial_to_body

    b = uniform_beam(2.0, 1.5, 30.0, 4, support="cantilever")
    rng = np.random.default_rng(seed)
    n = b.n_modes
    zero = dict(
        th=rng.uniform(-3, 3), thd=rng.normal(), thdd=rng.normal(), Rd=rng.normal(size=2), Rdd=rng.normal(size=2)
    )
    first = dict(
        th=rng.normal(),
        thd=rng.normal(),
        thdd=rng.normal(),
        Rd=rng.normal(size=2),
        Rdd=rng.normal(size=2),
        q=1e-2 * rng.normal(size=n),
        qd=1e-2 * rng.normal(size=n),
        qdd=1e-2 * rng.normal(size=n),
    )
    bf = planar_inertial_to_body(zero, first)
    k = first_order_matrices(b, bf["V0"], [0, 0, zero["thd"]], bf["Vd0"], [0, 0, zero["thdd"]])
    row = k["M0"][6:] @ bf["x1d"] + k["G"][6:] @ bf["x1"] + k["K"][6:] @ first["q"] - k["d"][6:]
    ref = planar_eq44_residual(b, zero, first)
    assert np.abs(row - ref).max() < 1e-10 * np.abs(ref).max()
    # the theta_1 term is far above the tolerance, so a wrong sign of it would fail above
    pb = b.masses @ b.shapes[:, 1, :]
    c, s = np.cos(zero["th"]), np.sin(zero["th"])
    term = pb * (c * zero["Rdd"][0] + s * zero["Rdd"][1]) * first["th"]
    assert np.abs(term).max() > 1e-3 * np.abs(ref).max()


def test_eq32_3d_matches_except_phihat_sign(body3d):
    st = ([0.3, -0.2, 0.5], [0.4, -0.7, 1.1], [0.1, 0.2, -0.3], [0.5, 0.3, -0.2])
    k, p = first_order_matrices(body3d, *st), paper_matrices(body3d, *st)
    n = body3d.n_modes
    assert np.abs(k["K"] - p["K"]).max() < 1e-10 * np.abs(k["K"]).max()  # eq. 32c, 32g
    assert np.abs(k["d"][6:] - p["d3"]).max() < 1e-12  # eq. 28b
    D = k["G"] - p["G"]
    mask = np.ones_like(D, dtype=bool)
    mask[6:, 3:6] = False
    assert np.abs(D[mask]).max() < 1e-10  # every block of eq. 31-32b but one
    ph = phi_hat(body3d, st[1])
    Pb = p["Phibar"]
    # elastic row, w1 column: the derivation gives  Phibar^T V0~^T - Phi^T(w0)  (eq. 32b prints +)
    assert np.abs(k["G"][6:, 3:6] - (Pb.T @ skew(st[0]).T - ph.T)).max() < 1e-11
    assert np.abs(ph).max() > 0.1
    assert n == 6
