"""Two or three elastic teeth per gear: several contact pairs (rotaflex.gear.multitooth)."""

import math

import numpy as np
import pytest

from rotaflex.core.errors import InputError
from rotaflex.gear import dynamics, multitooth
from rotaflex.gear.case import run_case
from rotaflex.gear.geometry import GearGeometry, contact_angles
from rotaflex.gear.mesh import COARSE, build_tooth_mesh

TAU0 = 22.25
KW = dict(youngs_modulus=210e9, poisson_ratio=0.3, density=7800.0, inertia=(2.965e-4, 2.965e-4))


@pytest.fixture(scope="module")
def gear():
    g = GearGeometry(module=3.175e-3, teeth=28, face_width=6.35e-3, tip_radius=0.047625, root_radius=0.04048)
    return g, build_tooth_mesh(g, **COARSE)


def test_one_pair_kernel_reproduces_single_tooth_solver_bitwise(gear):
    """The multi-pair kernel with one pair and the Fig. 7 ramps is the single-pair solver."""
    g, m = gear
    ths, th2 = contact_angles(g, g)
    kw = dict(
        speeds_rpm=(4000, 4000),
        torque=TAU0,
        theta_2=th2,
        theta_s=ths,
        span=math.radians(1.0),
        dt=3e-8,
        record_every=10,
        n_accel=3,
    )
    o1 = dynamics.simulate(dynamics.build_model(g, g, m, m, **KW), **kw)
    mm = multitooth.build_multi_model(g, m, 1, **KW)
    o2 = multitooth.simulate_multi(mm, torque_mode=0, window=None, **kw)
    assert np.max(o1.records["force"]) > 10.0
    assert np.array_equal(o1.records["force"], o2.pair_records["force"][:, 0])
    assert np.array_equal(o1.records["gap"], o2.pair_records["gap"][:, 0])
    for k in ("phi_A", "phi_B", "kinetic_energy", "strain_energy", "external_work"):
        assert np.array_equal(o1.records[k], o2.records[k])
    # the kernel split into calls of 10 steps carries its state (incl. contact rates) exactly
    o3 = multitooth.simulate_multi(mm, torque_mode=0, window=None, progress_every=10, **kw)
    assert np.array_equal(o2.pair_records["force"], o3.pair_records["force"])
    assert np.array_equal(o2.records["strain_energy"], o3.records["strain_energy"])


def test_placement_and_static_preload(gear):
    """Pairs at pitch spacing touch along the involute; the preload balances tau_0."""
    g, m = gear
    ths, _ = contact_angles(g, g)
    mm = multitooth.build_multi_model(g, m, 2, start_angle=0.0, **KW)
    pitch = 2 * math.pi / 28
    assert np.allclose(mm.pair_psi, [pitch, 0.0])
    cres, _, _ = multitooth.pair_geometry(mm, mm.reference_positions(), theta_s=ths)
    # rigid gaps: the entering pair closed exactly, the previous pair within the FE profile
    # deviation from the involute (well below the ~4 um load deflection)
    assert abs(cres[1, 2]) < 1e-12 and cres[1, 5] == 1  # tip of B on A
    assert abs(cres[0, 2]) < 1.5e-6 and cres[0, 5] == 0
    pre = multitooth.static_preload(mm, TAU0, 210e9, 0.3, ths)
    f = pre["force"]
    assert np.all(f > 0)  # both pairs share the load
    assert abs(np.sum(f * pre["arm"]) - TAU0) < 1e-9 * TAU0
    assert abs(f.sum() / (TAU0 / g.base_radius) - 1) < 0.01
    assert np.all(np.abs(pre["gap"]) < 1e-11)
    # pair compliance of the order of the static single-pair mesh stiffness (~1.2e8 N/m)
    assert np.all((pre["compliance"] > 3e-9) & (pre["compliance"] < 3e-8))


def test_two_teeth_entry_forces_energy_and_constraints(gear):
    """Entering pair picks up load; sum of forces ~ tau_0/r_b; energy; tolerances."""
    g, m = gear
    ths, th2 = contact_angles(g, g)
    mm = multitooth.build_multi_model(g, m, 2, start_angle=math.radians(-0.5), **KW)
    multitooth.static_preload(mm, TAU0, 210e9, 0.3, ths)
    out = multitooth.simulate_multi(
        mm,
        speeds_rpm=(4000, 4000),
        torque=TAU0,
        theta_2=th2,
        theta_s=ths,
        span=math.radians(2.3),
        dt=3e-8,
        record_every=10,
    )
    r, pr = out.records, out.pair_records
    nominal = TAU0 / g.base_radius
    f = pr["force"]
    assert abs(f[0].sum() / nominal - 1) < 0.1 and f[0, 0] > 0.5 * nominal
    assert np.max(f[:, 1]) > 0.2 * nominal  # the entering pair takes its share
    assert f[-1, 1] > 0.1 * nominal and f[-1, 0] > 0.1 * nominal  # two-pair zone
    assert abs(np.mean(f.sum(axis=1)) / nominal - 1) < 0.1
    bal = r["kinetic_energy"] + r["strain_energy"] - r["external_work"] + r["velocity_pass_loss"] - out.initial_energy
    assert np.max(np.abs(bal)) < 0.02 * np.max(r["strain_energy"])
    dt = 3e-8
    assert np.max(r["tie_residual"]) <= 1e-12 * (1 + 1e-9)
    assert np.max(r["res_vel"]) <= 1e-12 / dt * (1 + 1e-9)
    assert np.max(r["res_acc"]) <= 1e-12 / dt**2 * (1 + 1e-9)
    loaded = f > 1.0
    assert np.max(np.abs(pr["gap"][loaded])) < 2e-12


def test_run_case_three_teeth_and_bad_inputs(tmp_path):
    cfg = {
        "model": {"teeth_per_gear": 3},
        "mesh": {"preset": "coarse"},
        "operation": {"span_deg": 0.3},
        "output": {"every": 10},
    }
    res = run_case(cfg)
    ds = res.dataset
    assert ds["contact_force"].dims == ("time", "pair") and ds.sizes["pair"] == 3
    assert ds["gap"].dims == ("time", "pair")
    assert np.all(np.isnan(ds["gap"].sel(pair=2).values))  # next pair out of mesh
    assert abs(float(ds["total_contact_force"][0]) / 532.7 - 1) < 0.05
    assert res.summary()["teeth_per_gear"]["value"] == 3
    res.save(tmp_path)
    assert (tmp_path / "load_share.png").exists()
    with pytest.raises(InputError, match="teeth_per_gear"):
        run_case({"model": {"teeth_per_gear": 4}})
    with pytest.raises(InputError, match="span_deg"):
        run_case({"model": {"teeth_per_gear": 2}, "operation": {"span_deg": 20.0}})


@pytest.mark.slow
def test_comparison_three_teeth_vs_ramps(tmp_path):
    from rotaflex.gear.compare_teeth import comparison

    fe = comparison(tmp_path, fast=True)
    assert all(c.passed for c in fe.checks), [(c.name, c.measured) for c in fe.checks]
