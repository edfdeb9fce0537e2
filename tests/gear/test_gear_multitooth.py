"""Several elastic teeth per gear: several contact pairs (rotaflex.gear.models.multitooth)."""

import math

import numpy as np
import pytest

from rotaflex.core.errors import InputError
from rotaflex.core.units import rpm_to_rad_s
from rotaflex.gear.cases.simulate import run_case
from rotaflex.gear.models import fe_pair as dynamics
from rotaflex.gear.models import multitooth
from rotaflex.gear.pair.geometry import GearGeometry, contact_angles
from rotaflex.gear.pair.tooth_mesh import COARSE, build_tooth_mesh

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
        speeds=rpm_to_rad_s((4000, 4000)),
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
    # bit for bit on the machine it was written on; on this AMD EPYC host numba's LLVM contracts other
    # multiply-adds into FMAs in the two kernels, and the contact dynamics carry that rounding
    # to ~1e-8 relative over the 1 deg run: the same solver, compared at 1e-6 of each record's range
    for got, ref in [(o2.pair_records[k][:, 0], o1.records[k]) for k in ("force", "gap")] + [
        (o2.records[k], o1.records[k]) for k in ("phi_A", "phi_B", "kinetic_energy", "strain_energy", "external_work")
    ]:
        assert np.allclose(got, ref, rtol=0.0, atol=1e-6 * np.ptp(ref))
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
    pre = multitooth.static_preload(mm, TAU0, 210e9, 0.3, ths).preload
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
    mm = multitooth.static_preload(mm, TAU0, 210e9, 0.3, ths)
    out = multitooth.simulate_multi(
        mm,
        speeds=rpm_to_rad_s((4000, 4000)),
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
        run_case({"model": {"teeth_per_gear": 13}})
    with pytest.raises(InputError, match="span_deg"):
        run_case({"model": {"teeth_per_gear": 2}, "operation": {"span_deg": 20.0}})


@pytest.mark.slow
def test_comparison_three_teeth_vs_ramps(tmp_path):
    from rotaflex.reproduce.gear_teeth import comparison

    fe = comparison(tmp_path, fast=True)
    assert all(c.passed for c in fe.checks), [(c.name, c.measured) for c in fe.checks]


def test_every_option_runs_with_several_pairs(gear):
    """Direct solve, restitution and smoothed surfaces with two pairs (one kernel for any pairs).

    The direct solve meets the same constraints exactly, so the pair forces agree with the
    iteration to its tolerance (as for one pair, test_gear_direct); with e = 0.5 the entering
    pair rebounds (more impacts than the plastic law's one) and the energy balance, which books
    the impact loss, still closes; smoothing only removes the local indentation from the surfaces,
    so the load sum follows the paper-surface run.
    """
    g, m = gear
    ths, th2 = contact_angles(g, g)
    mm = multitooth.build_multi_model(g, m, 2, start_angle=math.radians(-0.5), **KW)
    mm = multitooth.static_preload(mm, TAU0, 210e9, 0.3, ths)
    kw = dict(
        speeds=rpm_to_rad_s((4000, 4000)),
        torque=TAU0,
        theta_2=th2,
        theta_s=ths,
        span=math.radians(1.0),
        dt=3e-8,
        record_every=10,
    )
    it = multitooth.simulate_multi(mm, **kw)
    di = multitooth.simulate_multi(mm, multipliers="direct", **kw)
    f_it, f_di = it.pair_records["force"], di.pair_records["force"]
    assert f_it.shape[1] == 2 and np.max(f_it[:, 1]) > 10.0  # the entering pair takes load
    assert np.max(np.abs(f_it - f_di)) < 0.1
    assert np.max(di.records["res_disp"]) < 1e-15
    sm = multitooth.simulate_multi(mm, smoothing=12, **kw)
    total = sm.pair_records["force"].sum(axis=1)
    assert abs(np.mean(total) / np.mean(f_it.sum(axis=1)) - 1) < 0.05
    assert abs(total[0] / (TAU0 / g.base_radius) - 1) < 0.01  # starts from the static preload
    rs = multitooth.simulate_multi(mm, restitution=0.5, **kw)
    assert rs.records["impacts"][-1] > it.records["impacts"][-1] >= 1
    r = rs.records
    bal = r["kinetic_energy"] + r["strain_energy"] - r["external_work"] + r["velocity_pass_loss"] - rs.initial_energy
    assert np.max(np.abs(bal)) < 0.02 * np.max(r["strain_energy"])


def test_driver_b_with_several_teeth_is_the_mirror_image():
    """Identical gears at equal speeds: driver B is driver A with the gear axes swapped."""
    base = {"model": {"teeth_per_gear": 2}, "mesh": {"preset": "coarse"}, "operation": {"span_deg": 0.3}}
    a = run_case(base).dataset
    b = run_case({**base, "operation": {"span_deg": 0.3, "driver": "B"}}).dataset
    np.testing.assert_array_equal(a["contact_force"].values, b["contact_force"].values)
    np.testing.assert_array_equal(a["rotation_angle"].sel(gear="A").values, b["rotation_angle"].sel(gear="B").values)
    assert b.attrs["driver"] == "B"


@pytest.mark.slow
def test_four_teeth_mesh_continuously_at_the_base_pitch():
    """Full-FE continuous meshing over two mesh cycles: with four teeth per gear the pairs come
    into and leave the mesh by geometry, one pitch apart, and carry tau_0 / r_b on average.

    About 36 s (25,000 steps of four pairs): runs with ``-m slow``. Its cheaper twins in the
    suite: the entering pair's load pick-up and the load sum of two pairs
    (test_two_teeth_entry_forces_energy_and_constraints), three pairs through the case
    (test_run_case_three_teeth_and_bad_inputs) and a pair's flank contact starting at its
    geometric start of contact (test_gear_multitooth_unequal.py, the short pinion-driven run).
    """
    cfg = {
        "model": {"teeth_per_gear": 4},
        "mesh": {"preset": "coarse"},
        "operation": {"span_deg": 26.7},
        "solver": {"dt": 4.4e-8},
        "output": {"every": 20, "root_stress": False},
    }
    ds = run_case(cfg).dataset
    assert ds.attrs["status"] == "success"
    assert float(ds["energy_balance_error"]) < 0.02  # measured 0.76 %
    f = ds["contact_force"].values
    th = np.degrees(ds["rotation_angle"].sel(gear="A").values)
    nominal = TAU0 / float(ds["base_radius"])
    on = [np.flatnonzero(f[:, j] > 0.01 * nominal) for j in range(4)]
    pitch = 360.0 / 28
    # entries of pairs 2 and 3 and exits of pairs 0 and 1 are one pitch apart (0.03 deg measured)
    assert th[on[3][0]] - th[on[2][0]] == pytest.approx(pitch, abs=0.15)
    assert th[on[1][-1]] - th[on[0][-1]] == pytest.approx(pitch, abs=0.15)
    # each pair carries load over about theta_s (1.64 pitches), plus premature/prolonged contact
    ths, _ = contact_angles(
        *[GearGeometry(module=3.175e-3, teeth=28, face_width=6.35e-3, tip_radius=0.047625, root_radius=0.04048)] * 2
    )
    assert th[on[1][-1]] - th[on[1][0]] == pytest.approx(math.degrees(ths), abs=1.5)
    assert np.mean(f.sum(axis=1)) == pytest.approx(nominal, rel=0.02)  # measured +0.73 %
