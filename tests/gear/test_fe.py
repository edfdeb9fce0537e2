"""Plane-stress quad8 element: patch test, cantilever vs beam theory, rigid modes, HRZ mass."""

from types import SimpleNamespace

import numpy as np
import pytest
import scipy.sparse.linalg as spla
import sympy as sym

from rotaflex.gear.pair.geometry import GearGeometry
from rotaflex.gear.pair.plane_stress import (
    consistent_mass,
    elasticity_matrix,
    lumped_mass,
    shape_derivatives,
    shape_functions,
    stable_time_step,
    stiffness_matrix,
    stress_operator,
)
from rotaflex.gear.pair.tooth_mesh import COARSE, build_tooth_mesh

E, NU, RHO = 210e9, 0.3, 7800.0


def grid_mesh(corners_x, corners_y, thickness=1.0, distort=None):
    """Quad8 mesh from a tensor grid of corner nodes (optionally distorted interior corners)."""
    nx, ny = len(corners_x) - 1, len(corners_y) - 1
    X, Y = np.meshgrid(corners_x, corners_y, indexing="ij")
    if distort is not None:
        X, Y = distort(X, Y)
    # 9-node grid: corners at even indices, mid-sides at mid-points of straight edges
    gx = np.zeros((2 * nx + 1, 2 * ny + 1))
    gy = np.zeros_like(gx)
    gx[::2, ::2], gy[::2, ::2] = X, Y
    gx[1::2, ::2], gy[1::2, ::2] = 0.5 * (X[:-1] + X[1:]), 0.5 * (Y[:-1] + Y[1:])
    gx[::2, 1::2], gy[::2, 1::2] = 0.5 * (X[:, :-1] + X[:, 1:]), 0.5 * (Y[:, :-1] + Y[:, 1:])
    ids = -np.ones(gx.shape, dtype=int)
    keep = np.ones(gx.shape, bool)
    keep[1::2, 1::2] = False
    ids[keep] = np.arange(keep.sum())
    nodes = np.column_stack([gx[keep], gy[keep]])
    el = []
    for a in range(nx):
        for b in range(ny):
            i, j = 2 * a, 2 * b
            el.append(
                [
                    ids[i, j],
                    ids[i + 2, j],
                    ids[i + 2, j + 2],
                    ids[i, j + 2],
                    ids[i + 1, j],
                    ids[i + 2, j + 1],
                    ids[i + 1, j + 2],
                    ids[i, j + 1],
                ]
            )
    return SimpleNamespace(nodes=nodes, elements=np.array(el), thickness=thickness), gx, gy, ids


def test_shape_functions_partition_of_unity_and_kronecker():
    xi = np.array([-1, 1, 1, -1, 0, 1, 0, -1.0])
    eta = np.array([-1, -1, 1, 1, -1, 0, 1, 0.0])
    assert np.allclose(shape_functions(xi, eta), np.eye(8), atol=1e-14)
    rng = np.random.default_rng(0)
    p = rng.uniform(-1, 1, (20, 2))
    assert np.allclose(shape_functions(p[:, 0], p[:, 1]).sum(-1), 1.0)
    # derivatives against finite differences
    h = 1e-6
    d = shape_derivatives(p[:, 0], p[:, 1])
    fd_xi = (shape_functions(p[:, 0] + h, p[:, 1]) - shape_functions(p[:, 0] - h, p[:, 1])) / (2 * h)
    fd_eta = (shape_functions(p[:, 0], p[:, 1] + h) - shape_functions(p[:, 0], p[:, 1] - h)) / (2 * h)
    assert np.allclose(d[..., 0], fd_xi, atol=1e-8) and np.allclose(d[..., 1], fd_eta, atol=1e-8)


def test_patch_test_linear_field_exact():
    def distort(X, Y):
        X, Y = X.copy(), Y.copy()
        X[1, 1] += 0.13
        Y[1, 1] -= 0.08
        X[2, 1] -= 0.1
        Y[1, 2] += 0.11
        return X, Y

    mesh, gx, gy, ids = grid_mesh(np.linspace(0, 2, 4), np.linspace(0, 1.5, 4), 0.01, distort)
    k = stiffness_matrix(mesh, E, NU)
    a = np.array([1e-4, 2e-4, -3e-4, 1.5e-4, 0.5e-4, -1e-4])  # u = a0 + a1 x + a2 y, v = ...
    x, y = mesh.nodes[:, 0], mesh.nodes[:, 1]
    exact = np.column_stack([a[0] + a[1] * x + a[2] * y, a[3] + a[4] * x + a[5] * y]).ravel()
    on_bnd = np.isclose(x, 0) | np.isclose(x, 2) | np.isclose(y, 0) | np.isclose(y, 1.5)
    fixed = np.column_stack([2 * np.flatnonzero(on_bnd), 2 * np.flatnonzero(on_bnd) + 1]).ravel()
    free = np.setdiff1d(np.arange(k.shape[0]), fixed)
    u = np.zeros(k.shape[0])
    u[fixed] = exact[fixed]
    u[free] = spla.spsolve(k[free][:, free].tocsc(), -k[free][:, fixed] @ u[fixed])
    assert np.allclose(u, exact, rtol=0, atol=1e-15)
    # constant stress everywhere, equal to D eps
    eps = np.array([a[1], a[5], a[2] + a[4]])
    sig = elasticity_matrix(E, NU) @ eps
    ne = mesh.elements.shape[0]
    pts = np.random.default_rng(1).uniform(-1, 1, (ne, 2))
    s = stress_operator(mesh, E, NU, np.arange(ne), pts[:, 0], pts[:, 1]) @ u
    assert np.allclose(s, sig[None, :], rtol=1e-9)
    # interior nodal forces vanish (internal equilibrium)
    assert np.abs((k @ exact)[free]).max() < 1e-9 * np.abs(k @ exact).max()


def cantilever_tip_deflection(n):
    length, h, t, load = 1.0, 0.1, 0.01, 1000.0
    mesh, gx, gy, ids = grid_mesh(np.linspace(0, length, 10 * n + 1), np.linspace(-h / 2, h / 2, n + 1), t)
    k = stiffness_matrix(mesh, E, NU).tocsc()
    x, y = mesh.nodes[:, 0], mesh.nodes[:, 1]
    clamp = np.flatnonzero(np.isclose(x, 0))
    # parabolic shear on the free end, consistent nodal loads by 3-point Gauss per edge
    f = np.zeros(2 * len(x))
    end = ids[-1, :]
    gp, gw = np.array([-np.sqrt(0.6), 0, np.sqrt(0.6)]), np.array([5, 8, 5]) / 9
    for b in range(n):
        nodes3 = end[2 * b : 2 * b + 3]
        y0, y2 = y[nodes3[0]], y[nodes3[2]]
        for s_, w_ in zip(gp, gw, strict=True):
            yy = 0.5 * (y0 + y2) + 0.5 * s_ * (y2 - y0)
            tau = 1.5 * load / (h * t) * (1 - (2 * yy / h) ** 2)
            nn = np.array([0.5 * s_ * (s_ - 1), 1 - s_**2, 0.5 * s_ * (s_ + 1)])
            f[2 * nodes3 + 1] -= w_ * 0.5 * (y2 - y0) * t * tau * nn
    fixed = np.concatenate([2 * clamp, 2 * clamp + 1])
    free = np.setdiff1d(np.arange(2 * len(x)), fixed)
    u = np.zeros_like(f)
    u[free] = spla.spsolve(k[free][:, free], f[free])
    tip = end[n]  # centre-line node at the free end
    return -u[2 * tip + 1]


def test_cantilever_matches_timoshenko_beam_and_converges():
    length, h, t, load = 1.0, 0.1, 0.01, 1000.0
    inertia = t * h**3 / 12
    g = E / (2 * (1 + NU))
    timoshenko = load * length**3 / (3 * E * inertia) + load * length / (5 / 6 * g * h * t)
    d = [cantilever_tip_deflection(n) for n in (1, 2, 4)]
    # beam theory ignores the clamp's local warping restraint: agreement to 0.5 %
    assert d[-1] == pytest.approx(timoshenko, rel=5e-3)
    # observed convergence: successive differences shrink (order >= 1.5)
    e1, e2 = abs(d[1] - d[0]), abs(d[2] - d[1])
    assert e2 < e1 / 2**1.5


def test_rigid_body_modes_of_tooth_stiffness():
    g = GearGeometry(module=3.175e-3, teeth=28, face_width=6.35e-3)
    m = build_tooth_mesh(g, **COARSE)
    k = stiffness_matrix(m, E, NU).toarray()
    assert np.allclose(k, k.T, rtol=0, atol=1e-6 * np.abs(k).max())
    w = np.linalg.eigvalsh(k)
    assert np.all(np.abs(w[:3]) < 1e-10 * w[-1])
    assert w[3] > 1e-6 * w[-1]
    # the three zero modes are translations and the in-plane rotation
    n = m.n_nodes
    r = np.zeros((2 * n, 3))
    r[0::2, 0] = 1
    r[1::2, 1] = 1
    r[0::2, 2], r[1::2, 2] = -m.nodes[:, 1], m.nodes[:, 0]
    assert np.abs(k @ r).max() < 1e-10 * np.abs(k).max()


def test_hrz_mass_positive_total_and_corner_ratio():
    g = GearGeometry(module=3.175e-3, teeth=28, face_width=6.35e-3)
    m = build_tooth_mesh(g, **COARSE)
    ml = lumped_mass(m, RHO)
    mc = consistent_mass(m, RHO)
    assert np.all(ml > 0)
    assert ml.sum() == pytest.approx(mc.sum(), rel=1e-12)  # total (x and y) preserved
    # rectangle: HRZ corner/mid-side ratio from exact integrals (sympy), vs plain row sum (< 0)
    mesh, *_ = grid_mesh(np.array([0.0, 2.0]), np.array([0.0, 1.0]), 0.5)
    ml = lumped_mass(mesh, RHO)[0::2]
    xi, eta = sym.symbols("xi eta")
    n_c = sym.Rational(1, 4) * (1 - xi) * (1 - eta) * (-xi - eta - 1)
    n_m = sym.Rational(1, 2) * (1 - xi**2) * (1 - eta)
    ic = sym.integrate(n_c**2, (xi, -1, 1), (eta, -1, 1))
    im = sym.integrate(n_m**2, (xi, -1, 1), (eta, -1, 1))
    total = RHO * 0.5 * 2.0
    expected_corner = total * float(ic / (4 * ic + 4 * im))
    corners = ml[mesh.elements[0, :4]]
    assert np.allclose(corners, expected_corner, rtol=1e-12)
    assert ml.sum() == pytest.approx(total, rel=1e-12)
    assert (consistent_mass(mesh, RHO).sum(axis=1).A1[0::2][mesh.elements[0, :4]] < 0).all()


def test_stable_time_step_against_dense_eigenvalues():
    g = GearGeometry(module=3.175e-3, teeth=28, face_width=6.35e-3)
    m = build_tooth_mesh(g, **COARSE)
    k = stiffness_matrix(m, E, NU).toarray()
    ml = lumped_mass(m, RHO)
    w2 = np.linalg.eigvalsh(k / np.sqrt(np.outer(ml, ml)))[-1]
    dt = stable_time_step(m, E, NU, RHO)
    assert dt == pytest.approx(2.785 / np.sqrt(w2), rel=1e-5)
    assert stable_time_step(m, E, NU, RHO, method="element") <= dt * (1 + 1e-12)  # upper bound on w
    # an RK4 march of the free tooth just below the limit stays bounded, just above it blows up
    rng = np.random.default_rng(0)
    u0 = rng.standard_normal(k.shape[0]) * 1e-9
    a_mat = -k / ml[:, None]

    def march(dt_, steps=2000):
        y = np.concatenate([u0, np.zeros_like(u0)])
        n = u0.size
        f = lambda s: np.concatenate([s[n:], a_mat @ s[:n]])  # noqa: E731
        for _ in range(steps):
            k1 = f(y)
            k2 = f(y + 0.5 * dt_ * k1)
            k3 = f(y + 0.5 * dt_ * k2)
            k4 = f(y + dt_ * k3)
            y = y + dt_ / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
            if not np.isfinite(y).all():
                return np.inf
        return np.abs(y[:n]).max()

    assert march(0.98 * dt) < 1e-7
    blown = march(1.1 * 2 * np.sqrt(2) / np.sqrt(w2), steps=600)
    assert not np.isfinite(blown) or blown > 1e-3
