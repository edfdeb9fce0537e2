"""Direct multiplier solve: exact against a dense numpy solve, and equal to the iteration."""

import math

import numpy as np
import pytest

from rotaflex.core.units import rpm_to_rad_s
from rotaflex.gear.kernels.passes import direct_pass, factor_tie_blocks
from rotaflex.gear.models import fe_pair as dynamics
from rotaflex.gear.pair.geometry import GearGeometry, contact_angles
from rotaflex.gear.pair.tooth_mesh import COARSE, build_tooth_mesh

DT = 3e-8


@pytest.fixture(scope="module")
def model():
    g = GearGeometry(module=3.175e-3, teeth=28, face_width=6.35e-3, tip_radius=0.047625, root_radius=0.04048)
    m = build_tooth_mesh(g, **COARSE)
    mod = dynamics.build_model(
        g, g, m, m, youngs_modulus=210e9, poisson_ratio=0.3, density=7800.0, inertia=(2.965e-4, 2.965e-4)
    )
    return g, mod


def dense_c(mod, c1, c2, bvec, ccol):
    """C = G W G^T of the tie rows written out densely (independent of the kernels)."""
    nt = len(mod.tie_node)
    mt = np.repeat(mod.minv[mod.tie_node], 2)
    ktt = np.zeros((2 * nt, 2 * nt))
    for i, j, b in zip(mod.tb_i, mod.tb_j, mod.tb_b, strict=True):
        ktt[2 * i : 2 * i + 2, 2 * j : 2 * j + 2] = b
    ct = c1 * np.diag(mt) - c2 * (mt[:, None] * ktt * mt[None, :])
    for g in range(2):
        b = np.zeros(2 * nt)
        sel = np.where(mod.tie_gear == g)[0]
        b[2 * sel] = bvec[sel, 0]
        b[2 * sel + 1] = bvec[sel, 1]
        ct += c1 / mod.inertia[g] * np.outer(b, b)
    c = np.zeros((2 * nt + 1, 2 * nt + 1))
    c[:-1, :-1] = ct
    c[:-1, -1] = c[-1, :-1] = ccol[:-1]
    c[-1, -1] = ccol[-1]
    return c


@pytest.mark.parametrize("pas", [0, 1, 2])
def test_direct_pass_solves_the_complementarity_problem(model, pas):
    _, mod = model
    packed, perm, bw = factor_tie_blocks(mod, DT)
    assert bw < 2 * len(mod.tie_node) // 2  # the reordering found a band
    c1, c2 = [(DT * DT / 2, DT**4 / 24), (DT, DT**3 / 6), (1.0, 0.0)][pas]
    nt = len(mod.tie_node)
    rng = np.random.default_rng(3)
    xl = mod.xloc[mod.tie_node]
    bvec = np.column_stack([-xl[:, 1], xl[:, 0]])  # reference disk vectors
    ccol = np.zeros(2 * nt + 1)
    ccol[rng.choice(2 * nt, 4, replace=False)] = 1e-3 * c1 * rng.standard_normal(4)
    ccol[-1] = 3.0 * c1 * mod.minv.max()
    c = dense_c(mod, c1, c2, bvec, ccol)
    for s_sign in (+1.0, -1.0):
        e0 = 1e-9 * rng.standard_normal(2 * nt + 1)
        e0[-1] = s_sign * 1e-8
        mu = np.zeros(2 * nt + 1)
        dmu = np.zeros_like(mu)
        direct_pass(
            pas + 1, e0, mu, -1.0, packed[pas], perm, mod.tie_gear, bvec, ccol, 1e-14, dmu, np.zeros((6, 2 * nt + 1))
        )
        e = e0 + c @ dmu
        # ties exact; contact either closed with p < 0 or open with p = 0 and s <= 0
        assert np.max(np.abs(e[:-1])) < 1e-12 * np.max(np.abs(e0))
        if dmu[-1] < 0:
            assert abs(e[-1]) < 1e-12 * abs(e0[-1])
        else:
            assert dmu[-1] == 0.0 and e[-1] <= 0.0
        # reference: dense solve with the contact row active / dropped
        full = np.linalg.solve(c, -e0)
        if full[-1] < 0:
            np.testing.assert_allclose(dmu, full, rtol=1e-9, atol=1e-12 * np.abs(full).max())
        else:
            red = np.linalg.solve(c[:-1, :-1], -e0[:-1])
            np.testing.assert_allclose(dmu[:-1], red, rtol=1e-9, atol=1e-12 * np.abs(red).max())


def test_direct_equals_iterative_on_a_short_span(model):
    """Same contact force as the paper's iteration to the tolerance level (coarse, 1.5 deg)."""
    g, mod = model
    ths, th2 = contact_angles(g, g)
    outs = {}
    for mode in ("iterative", "direct"):
        outs[mode] = dynamics.simulate(
            mod,
            speeds=rpm_to_rad_s((4000, 4000)),
            torque=22.25,
            theta_2=th2,
            theta_s=ths,
            span=math.radians(1.5),
            dt=DT,
            record_every=5,
            multipliers=mode,
        )
    a, b = outs["iterative"].records, outs["direct"].records
    assert np.max(a["force"]) > 50.0  # contact is loaded
    # 1e-12 m of constraint tolerance x contact stiffness ~1e8 N/m x amplification: 0.1 N bound
    assert np.max(np.abs(a["force"] - b["force"])) < 0.1
    assert np.max(np.abs(a["phi_A"] - b["phi_A"])) < 1e-10
    # the direct solve meets the constraints far below the paper's tolerances, in one solve
    assert np.max(b["res_disp"]) < 1e-15 and np.max(b["tie_residual"]) < 1e-15
    assert np.max(b["iter_disp"]) <= 2 and np.max(b["iter_acc"]) <= 2
