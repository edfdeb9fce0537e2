"""Stiffness kernels of the paper's step (2 x 2 node blocks) against scipy's sparse products and
the energy they derive from; the step pieces against one call of ``run_steps``."""

import math

import numpy as np
import pytest

from rotaflex.core.units import rpm_to_rad_s
from rotaflex.gear.kernels import forces, rk4
from rotaflex.gear.kernels.passes import k_local_product
from rotaflex.gear.models import fe_pair as dynamics
from rotaflex.gear.pair.geometry import GearGeometry, contact_angles
from rotaflex.gear.pair.tooth_mesh import COARSE, build_tooth_mesh


@pytest.fixture(scope="module")
def setup():
    g = GearGeometry(module=3.175e-3, teeth=28, face_width=6.35e-3, tip_radius=0.047625, root_radius=0.04048)
    m = build_tooth_mesh(g, **COARSE)
    mod = dynamics.build_model(
        g, g, m, m, youngs_modulus=210e9, poisson_ratio=0.3, density=7800.0, inertia=(2.965e-4, 2.965e-4)
    )
    ths, th2 = contact_angles(g, g)
    ki = dynamics.kernel_inputs(
        mod, speeds=rpm_to_rad_s((4000, 4000)), torque=22.25, theta_2=th2, theta_s=ths, span=1.0, dt=3e-8
    )
    return mod, ki


def _deformed(mod, seed=1):
    """Node positions with a random deformation of 10 um around the reference."""
    rng = np.random.default_rng(seed)
    return mod.reference_positions() + 1e-5 * rng.standard_normal(2 * mod.n_nodes)


def _local_displacement(mod, x, phi):
    """w = R^T (x - c) - X per node, written out with numpy (independent of the kernel)."""
    xy = x.reshape(-1, 2)
    w = np.empty_like(xy)
    for g in range(2):
        sel = mod.gid == g
        ang = mod.theta0[g] + phi[g]
        c, s = math.cos(ang), math.sin(ang)
        d = xy[sel] - mod.centres[g]
        w[sel, 0] = c * d[:, 0] + s * d[:, 1] - mod.xloc[sel, 0]
        w[sel, 1] = -s * d[:, 0] + c * d[:, 1] - mod.xloc[sel, 1]
    return w.ravel()


def _energy(mod, ma, x, phi):
    rot = np.empty((2, 2))
    forces.set_rotation(phi, ma.theta0, rot)
    n = 2 * mod.n_nodes
    return forces.elastic_force(x, rot, ma, np.empty(n), np.empty(n), np.empty(2))


def test_node_blocks_hold_the_stiffness_exactly(setup):
    mod, ki = setup
    k = mod.stiffness.tocsr()
    rows = np.repeat(np.arange(mod.n_nodes), np.diff(ki.arrays.kptr.astype(np.int64)))
    dense = np.zeros(k.shape)
    for b, (i, j) in enumerate(zip(rows, ki.arrays.kcol, strict=True)):
        dense[2 * i : 2 * i + 2, 2 * j : 2 * j + 2] = ki.arrays.kblk[b].reshape(2, 2)
    assert np.array_equal(dense, k.toarray())


def test_elastic_force_is_minus_r_k_w_and_its_torque_minus_de_dphi(setup):
    mod, ki = setup
    ma = ki.arrays
    x = _deformed(mod)
    phi = np.array([0.003, -0.002])
    n = 2 * mod.n_nodes
    rot = np.empty((2, 2))
    forces.set_rotation(phi, ma.theta0, rot)
    fglob, tel = np.empty(n), np.empty(2)
    energy = forces.elastic_force(x, rot, ma, np.empty(n), fglob, tel)
    w = _local_displacement(mod, x, phi)
    kw = mod.stiffness @ w
    assert energy == pytest.approx(0.5 * w @ kw, rel=1e-12)
    # f = -R K w, node by node in the frame of its gear
    floc = kw.reshape(-1, 2)
    ref = np.empty_like(floc)
    for g in range(2):
        sel = mod.gid == g
        c, s = rot[g]
        ref[sel, 0] = -(c * floc[sel, 0] - s * floc[sel, 1])
        ref[sel, 1] = -(s * floc[sel, 0] + c * floc[sel, 1])
    scale = np.abs(ref).max()
    assert np.abs(fglob - ref.ravel()).max() <= 1e-12 * scale
    # the disk torque is -dE/dphi (central difference of the energy: h^2 truncation ~1e-9
    # relative; round-off of w = R^T (x - c) - X, ~1e-17 m, gives ~1e-6 relative at this h)
    for g in range(2):
        h = 1e-5
        dp = np.zeros(2)
        dp[g] = h
        de = (_energy(mod, ma, x, phi + dp) - _energy(mod, ma, x, phi - dp)) / (2 * h)
        assert tel[g] == pytest.approx(-de, rel=1e-5)


def test_k_local_product_is_k_r_t_minv_g(setup):
    mod, ki = setup
    ma = ki.arrays
    n = 2 * mod.n_nodes
    rng = np.random.default_rng(3)
    g = np.zeros(n)
    nodes = rng.choice(mod.n_nodes, 6, replace=False)
    g[2 * nodes] = rng.standard_normal(6)
    g[2 * nodes + 1] = rng.standard_normal(6)
    rot = np.empty((2, 2))
    forces.set_rotation(np.array([0.01, -0.02]), ma.theta0, rot)
    zk = np.zeros(n)
    k_local_product(g, ma, rot, zk)
    gl = np.empty(n)
    for i in range(mod.n_nodes):
        c, s = rot[mod.gid[i]]
        gl[2 * i] = (c * g[2 * i] + s * g[2 * i + 1]) * mod.minv[i]
        gl[2 * i + 1] = (-s * g[2 * i] + c * g[2 * i + 1]) * mod.minv[i]
    ref = mod.stiffness.T @ gl
    assert np.abs(zk - ref).max() <= 1e-12 * np.abs(ref).max()


def test_run_in_calls_equals_one_call_bit_for_bit(setup):
    """The state carried between calls (contact rates, multipliers, running scalars) is complete:
    300 steps as one call and as calls of 7 steps give the same records, bit for bit."""
    mod, _ = setup
    g = GearGeometry(module=3.175e-3, teeth=28, face_width=6.35e-3, tip_radius=0.047625, root_radius=0.04048)
    ths, th2 = contact_angles(g, g)
    kw = dict(speeds=rpm_to_rad_s((4000, 4000)), torque=22.25, theta_2=th2, theta_s=ths, span=1.0, dt=3e-8)
    runs = []
    for chunk in (300, 7):
        m, p, s, r, _, _ = dynamics.kernel_inputs(mod, record_every=1, **kw)
        row, done, first = 0, 0, True
        while done < 300:
            n = min(chunk, 300 - done)
            status, row = rk4.run_steps(n, 1, row, first, m, p, s, r)
            assert status == 0
            done, first = done + n, False
        runs.append((r.out[:row].copy(), r.outp[:row].copy(), s.x.copy()))
    for a, b in zip(*runs, strict=True):
        assert np.array_equal(a, b)


@pytest.mark.parametrize("n_nodes", [1, 2, 3, 8])
def test_block_product_is_k_u_for_any_number_of_rows(n_nodes):
    """Two block rows are summed side by side (rows i and i + n//2 + 1): every row count, odd
    and even, and rows of different lengths give scipy's product; each row adds its terms in
    column order, so a row equals the row summed on its own, bit for bit."""
    import scipy.sparse as sp

    rng = np.random.default_rng(n_nodes)
    dense = rng.standard_normal((2 * n_nodes, 2 * n_nodes))
    mask = np.kron(rng.random((n_nodes, n_nodes)) < 0.6, np.ones((2, 2))) + np.eye(2 * n_nodes)
    k = sp.csr_matrix(dense * (mask > 0))
    kptr, kcol, kblk = dynamics.node_blocks(k)
    u = rng.standard_normal(2 * n_nodes)
    f = np.empty(2 * n_nodes)
    forces.block_product(kptr, kcol, kblk, u.reshape(-1, 2), f.reshape(-1, 2))
    assert np.abs(f - k @ u).max() <= 1e-14 * np.abs(k @ u).max()
    for i in range(n_nodes):
        row = np.empty((1, 2))
        b0, b1 = int(kptr[i]), int(kptr[i + 1])
        sub_ptr = np.array([0, b1 - b0], dtype=np.uint64)
        forces.block_product(sub_ptr, kcol[b0:b1], kblk[b0:b1], u.reshape(-1, 2), row)
        assert np.array_equal(row[0], f[2 * i : 2 * i + 2])


def test_tie_block_rows_hold_the_tie_stiffness(setup):
    """The tie block as rows (pointer, column, 2 x 2 block) is the model's list of tie-block
    couplings, each row's blocks in their original order."""
    mod, ki = setup
    ma = ki.arrays
    nt = len(mod.tie_node)
    from_rows = np.zeros((2 * nt, 2 * nt))
    for k in range(nt):
        for q in range(int(ma.tb_ptr[k]), int(ma.tb_ptr[k + 1])):
            j = int(ma.tb_j[q])
            from_rows[2 * k : 2 * k + 2, 2 * j : 2 * j + 2] += ma.tb_b[q].reshape(2, 2)
    ref = np.zeros((2 * nt, 2 * nt))
    for i, j, b in zip(mod.tb_i, mod.tb_j, mod.tb_b, strict=True):
        ref[2 * i : 2 * i + 2, 2 * j : 2 * j + 2] += b
    assert np.array_equal(from_rows, ref)
    # and it is the stiffness among the tied nodes
    dofs = np.ravel(np.column_stack([2 * mod.tie_node, 2 * mod.tie_node + 1]))
    assert np.array_equal(ref, mod.stiffness.toarray()[np.ix_(dofs, dofs)])
