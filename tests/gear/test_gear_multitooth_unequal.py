"""Several elastic teeth per gear on drawing pairs ([pinion]/[wheel], rotaflex.gear.models.multitooth):
two copies of the paper's gear reproduce the [gear] path bit for bit; the 20/40 pair of
examples/gear/unequal_shifted_relief.toml (no reliefs, coarse mesh) with three teeth per gear
meshes at the driver's pitch, carries tau_0 / r_b,driver on average with the disks in the tooth
ratio, with either gear driving, and shares the load between its pairs as the quasi-static
analyses do."""

import copy
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from rotaflex.gear.cases.simulate import run_case
from rotaflex.gear.cases.simulate_config import build, elastic_constants, load_config, to_run
from rotaflex.gear.cases.static import run_static
from rotaflex.gear.models import multitooth

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "gear"
PAPER_SPEC = {
    "teeth": 28,
    "module": 3.175e-3,
    "face_width": 6.35e-3,
    "pressure_angle_deg": 20.0,
    "tip_radius": 0.047625,
    "root_radius": 0.04048,
    "material": {"youngs_modulus": 210e9, "poisson_ratio": 0.3, "density": 7800.0},
    "blank": {"inertia": 2.965e-4},
}
SHORT = {"mesh": {"preset": "coarse"}, "output": {"every": 10, "root_stress": False}}
#: the pinion-driven and the wheel-driven run: same pinion speed (4000 rpm, mesh frequency
#: 1.33 kHz) and the same mesh force (4257 N = 80 N m / r_b,pinion), pair 1 starting 2 pinion
#: degrees before its start of contact and the span up to just past the entry of pair 2
RUNS = {
    "pinion": dict(rpm=4000.0, torque=80.0, start=-2.0, window=2.5, span=20.5),
    "wheel": dict(rpm=2000.0, torque=160.0, start=-1.0, window=1.5, span=10.25),
}


@pytest.mark.parametrize("driver", ["A", "B"])
def test_identical_drawing_pair_with_three_teeth_is_the_gear_path_bit_for_bit(driver):
    base = {"model": {"teeth_per_gear": 3}, **copy.deepcopy(SHORT)}
    paper = run_case({**base, "operation": {"span_deg": 0.5, "driver": driver}}).dataset
    drawing = run_case(
        {
            **copy.deepcopy(base),
            "pinion": PAPER_SPEC,
            "wheel": PAPER_SPEC,
            "driver": "pinion" if driver == "A" else "wheel",
            "mesh": {"preset": "coarse", "contact_smoothing": 0},  # the paper's surfaces, as the [gear] path
            "operation": {"span_deg": 0.5, "driver_speed_rpm": 4000.0},
        }
    ).dataset
    assert drawing.attrs["status"] == "success"
    for name in ("contact_force", "rotation_angle", "angular_velocity", "contact_point", "gap", "preload_force"):
        np.testing.assert_array_equal(paper[name].values, drawing[name].values, err_msg=name)
    assert float(paper["energy_balance_error"]) == float(drawing["energy_balance_error"])


def _unequal(driver: str, **model) -> dict:
    """The 20/40 example without reliefs, coarse mesh, paper's surfaces, three teeth."""
    run = RUNS[driver]
    cfg = tomllib.loads((EXAMPLES / "unequal_shifted_relief.toml").read_text())
    for g in ("pinion", "wheel"):
        cfg[g].pop("tip_relief")
    cfg["driver"] = driver
    # the coarse mesh has no flank kinks: the paper's surfaces (energy balance 0.6 % vs 3 %)
    cfg["mesh"] = {"preset": "coarse", "contact_smoothing": 0}
    cfg["solver"]["dt"] = 2.5e-8  # RK4 limit of this coarse mesh: 2.53e-8 s
    cfg["output"] = {"every": 10, "root_stress": False}
    cfg["operation"].update(driver_speed_rpm=run["rpm"], torque=run["torque"], span_deg=run["span"])
    cfg["model"] = {"teeth_per_gear": 3, "start_angle_deg": run["start"], "mesh_window_deg": run["window"]}
    cfg["model"].update(model)
    return cfg


#: both runs (34,000 steps of three pairs, about 35 s each on the idle 2-core machine) run with
#: ``-m slow``. Their cheaper twins in the suite: the first 2.5 deg of the pinion-driven run
#: (test_short_pinion_run_keeps_the_ratio_and_enters_with_premature_contact), the wheel-driven
#: three-tooth model of the same pair (tie multipliers relabelled, test below), the same-model
#: statics against gear static (test below) and the bit-for-bit mirror of a swapped driver
#: (test_gear_unequal.py::test_swapping_the_tables_and_the_driver_mirrors_the_results)
DRIVERS = [pytest.param("pinion", marks=pytest.mark.slow), pytest.param("wheel", marks=pytest.mark.slow)]


def test_short_pinion_run_keeps_the_ratio_and_enters_with_premature_contact():
    """The first 2.5 deg of the pinion-driven run (one eighth of its steps): static start,
    torques and speeds in the tooth ratio, pair 1's premature contact ahead of its flank
    contact, energy balance."""
    cfg = _unequal("pinion")
    cfg["operation"]["span_deg"] = 2.5
    ds = run_case(cfg).dataset
    assert ds.attrs["status"] == "success"
    rb = ds["gear_base_radius"].values
    assert rb[1] / rb[0] == pytest.approx(2.0, rel=1e-14)
    nominal = 80.0 / rb[0]
    assert float(ds["nominal_force"]) == pytest.approx(nominal, rel=1e-12)
    th, on1, _ = _cycle_start(ds, "pinion")
    # the static preload of pair 0 balances the torque at t = 0; its lever arm is r_b up to the
    # FE profile deviation and the deflection (um against 18.8 mm): within 1 % of T / r_b
    assert float(ds["total_contact_force"][0]) == pytest.approx(nominal, rel=1e-2)
    tq = ds["torque"].values
    assert np.allclose(tq[:, 0], 80.0) and np.allclose(tq[:, 1], 160.0)
    # pair 1 takes load before its tip-corner contact (case 1) gives way to the flank (case 0),
    # by less than 0.1 pitch, as in the whole runs (measured 1.3 deg here)
    case = ds["contact_case"].values
    flank1 = np.flatnonzero((case[:-1, 1] == 1) & (case[1:, 1] == 0))[0]
    assert 0.0 < th[flank1] - th[on1] < 0.1 * 18.0
    # rotation increments in the ratio 2: the approach along the line of action changes by at
    # most the ~15 um approach under load, 1.8 % of the 0.82 mm rolled on the pinion's base circle
    rot = ds["rotation_angle"].values
    assert (rot[-1, 0] - rot[0, 0]) / (rot[-1, 1] - rot[0, 1]) == pytest.approx(2.0, rel=2e-2)
    assert float(ds["energy_balance_error"]) < 1e-2  # the bound of the whole runs


@pytest.fixture(scope="module", params=DRIVERS)
def unequal(request):
    """(driver, dataset) of the 20/40 pair with three teeth per gear (about 35 s each)."""
    return request.param, run_case(_unequal(request.param)).dataset


def _cycle_start(ds, driver):
    """Driver angle [deg], the first load on pair 1 and the records of the loads on pair 2."""
    th = np.degrees(ds["rotation_angle"].sel(gear="A" if driver == "pinion" else "B").values)
    f = ds["contact_force"].values
    nominal = float(ds["nominal_force"])
    assert f[0, 1] == 0.0 and f[0, 2] == 0.0  # pair 0 alone at t = 0
    on1 = np.flatnonzero(f[:, 1] > 0.01 * nominal)[0]
    return th, on1, np.flatnonzero(f[:, 2] > 0.01 * nominal)


def _cycle(ds, driver):
    """Driver angle [deg] and the records of one mesh cycle: from the first load on pair 1 to
    the first load on pair 2 (both enter by geometry, premature contact included)."""
    th, on1, on2 = _cycle_start(ds, driver)
    return th, on1, on2[0]


def test_unequal_pairs_enter_one_driver_pitch_apart(unequal):
    driver, ds = unequal
    assert ds.attrs["status"] == "success"
    z = 20 if driver == "pinion" else 40
    pitch = 360.0 / z
    th, on1, on2 = _cycle(ds, driver)
    # contact-case history: the tip-corner projection (case 1) of a pair gives way to the flank
    # search (case 0) at its geometric start of contact, one driver pitch after the previous
    # pair (measured: 1.3 and 0.6 records off; a pitch of the driven gear would be 2x or 0.5x)
    case = ds["contact_case"].values
    flank1 = np.flatnonzero((case[:-1, 1] == 1) & (case[1:, 1] == 0))[0]
    flank2 = np.flatnonzero((case[:-1, 2] == 1) & (case[1:, 2] == 0))[0]
    step = th[1] - th[0]
    assert th[flank2] - th[flank1] == pytest.approx(pitch, abs=3 * step)
    # first load: premature contact of the deflected teeth, 1.1-1.3 pinion degrees early; its
    # advance follows the mesh vibration (dynamic factor 1.28), so the entries are one pitch
    # apart within 1.5 % (measured 1.03 % pinion driving, 0.74 % wheel driving)
    assert th[on2] - th[on1] == pytest.approx(pitch, rel=0.015)
    assert 0.0 < th[flank1] - th[on1] < 0.1 * pitch


def test_unequal_mean_force_speed_ratio_and_energy_over_a_mesh_cycle(unequal):
    driver, ds = unequal
    th, on1, on2 = _cycle(ds, driver)
    cyc = slice(on1, on2)
    rb = ds["gear_base_radius"].values  # (pinion, wheel)
    torque = RUNS[driver]["torque"]
    nominal = torque / (rb[0] if driver == "pinion" else rb[1])
    assert float(ds["nominal_force"]) == pytest.approx(nominal, rel=1e-12)
    total = ds["total_contact_force"].values[cyc]
    # mean over one whole mesh cycle: within 1 % of T / r_b,driver (measured -0.18 %, -0.25 %)
    assert np.mean(total) == pytest.approx(nominal, rel=1e-2)
    # the load torque is the drive torque times the ratio, constant
    tq = ds["torque"].values[cyc]
    drive, load = (0, 1) if driver == "pinion" else (1, 0)
    assert np.allclose(tq[:, drive], torque) and np.allclose(tq[:, load], torque * (2.0 if drive == 0 else 0.5))
    # speed ratio z_wheel / z_pinion = 2 over the cycle (rotation increments; measured -2.9e-4,
    # +2.4e-4: the change of the tooth deflections over the cycle)
    rot = ds["rotation_angle"].values
    ratio = (rot[on2, 0] - rot[on1, 0]) / (rot[on2, 1] - rot[on1, 1])
    assert ratio == pytest.approx(2.0, rel=1e-3)
    om = ds["angular_velocity"].values[cyc]
    assert np.mean(om[:, 0]) / np.mean(om[:, 1]) == pytest.approx(2.0, rel=1e-3)
    # energy balance over the run (measured 0.62 % pinion driving, 0.73 % wheel driving)
    assert float(ds["energy_balance_error"]) < 1e-2


def _zone_shares(ds, driver):
    """Zone means of the entering pair's load share over its first two-pair zone (interior:
    0.1 to 0.9 theta_2 in four zones) from the run, the same-model statics and gear static."""
    th2, ths = float(ds["theta_2"]), float(ds["theta_s"])
    edges = th2 * np.array([0.1, 0.3, 0.5, 0.7, 0.9])
    pa = ds["pair_angle"].values[:, 1]
    f = ds["contact_force"].values
    share = f[:, 1] / (f[:, 0] + f[:, 1])
    dyn = np.array([np.mean(share[(pa >= a) & (pa < b)]) for a, b in zip(edges[:-1], edges[1:], strict=True)])

    def zones(x, y):
        return np.array(
            [np.mean(np.interp(np.linspace(a, b, 41), x, y)) for a, b in zip(edges[:-1], edges[1:], strict=True)]
        )

    # linear FE statics of the same model (same teeth, point-force contact, surfaces)
    cfg = load_config(_unequal(driver, start_angle_deg=0.0))
    geo, _, model = build(cfg)
    run = to_run(cfg, geo, model)
    assert run.theta_2 == pytest.approx(th2, rel=1e-12) and run.theta_s == pytest.approx(ths, rel=1e-12)
    ang = np.linspace(edges[0], edges[-1], 9)
    fs = multitooth.static_pair_forces(model, run.torque, *elastic_constants(cfg), ths, ang)
    same = zones(ang, fs[:, 1] / fs.sum(axis=1))
    # gear static: structural FE compliances + Weber contact along the line of action
    scfg = tomllib.loads((EXAMPLES / "unequal_shifted_relief.toml").read_text())
    for g in ("pinion", "wheel"):
        scfg[g].pop("tip_relief")
    scfg.update(driver=driver, load={"torque": 80.0})
    scfg["mesh"]["preset"] = "coarse"
    scfg["analysis"] = {"n_angles": 240, "refinement": [1]}
    st = run_static(scfg).dataset
    static = zones(st["engagement"].values, st["load_share"].values)
    return dyn, same, static


def test_unequal_load_sharing_follows_the_quasi_static_shares(unequal):
    """The run at 4000 rpm (pinion) against the quasi-static load sharing.

    The mesh vibration moves the pair forces together (both pairs deflect by the same approach
    along the line of action), so the shares stay quasi-static: against the statics of the same
    FE model the zone means agree within 0.02 (measured 0.0066 pinion / 0.0049 wheel driving).
    Against ``gear static`` (FE compliances + Weber contact) they differ by up to 0.15 on this
    coarse mesh (measured 0.111 / 0.110, as the same-model statics: 0.111 / 0.111). That is a
    mesh effect of the FE contact model (the coarse FE edges deviate from the involute by ~2 um
    and the point force indents them, against a ~15 um approach under load), not of the
    dynamics: the same-model statics approach gear static as the mesh is refined (next test);
    on the default mesh the run is within 0.017 of gear static (slow test below).
    """
    driver, ds = unequal
    dyn, same, static = _zone_shares(ds, driver)
    assert np.all(np.diff(dyn) > 0) and np.all(np.diff(static) > 0)  # the entering pair picks up load
    assert np.max(np.abs(dyn - same)) < 0.02
    assert np.max(np.abs(dyn - static)) < 0.15
    # the run's two-pair zone: both pairs loaded over theta_2 plus the premature and prolonged
    # contact of the deflected teeth (measured +2.05 pinion degrees = 0.11 pitch either way)
    f = ds["contact_force"].values
    thr = 0.01 * float(ds["nominal_force"])
    both = (f[:, 0] > thr) & (f[:, 1] > thr)
    extra = np.ptp(ds["pair_angle"].values[both, 1]) - float(ds["theta_2"])
    pitch = 2 * math.pi / (20 if driver == "pinion" else 40)
    assert 0.0 < extra < 0.15 * pitch


def _static_shares(preset: str, edges: np.ndarray):
    """Zone means of the entering pair's share from the same-model statics and gear static on
    one mesh preset (pinion driving)."""
    cfg = _unequal("pinion", start_angle_deg=0.0)
    cfg["mesh"]["preset"] = preset
    cfg = load_config(cfg)
    geo, _, model = build(cfg)
    run = to_run(cfg, geo, model)
    ang = np.linspace(edges[0], edges[-1], 9)
    fs = multitooth.static_pair_forces(model, run.torque, *elastic_constants(cfg), run.theta_s, ang)
    scfg = tomllib.loads((EXAMPLES / "unequal_shifted_relief.toml").read_text())
    for g in ("pinion", "wheel"):
        scfg[g].pop("tip_relief")
    scfg["mesh"]["preset"] = preset
    scfg["analysis"] = {"n_angles": 240, "refinement": [1]}
    st = run_static(scfg).dataset
    out = []
    for x, y in ((ang, fs[:, 1] / fs.sum(axis=1)), (st["engagement"].values, st["load_share"].values)):
        out.append(
            [np.mean(np.interp(np.linspace(a, b, 41), x, y)) for a, b in zip(edges[:-1], edges[1:], strict=True)]
        )
    return np.array(out)


def test_same_model_statics_approach_gear_static_with_the_mesh():
    """Max zone difference of the entering pair's share, FE model statics vs gear static:
    coarse 0.111, default 0.010 (fine: 0.011; the rest is point force vs Weber contact)."""
    th2 = math.radians(9.872936265455593)
    edges = th2 * np.array([0.1, 0.3, 0.5, 0.7, 0.9])
    dev = {p: float(np.max(np.abs(np.subtract(*_static_shares(p, edges))))) for p in ("coarse", "default")}
    assert dev["coarse"] > 0.08
    assert dev["default"] < 0.02 and dev["default"] < 0.2 * dev["coarse"]


@pytest.mark.slow
def test_default_mesh_run_follows_gear_static():
    """The pinion-driven run on the default mesh (smoothed surfaces, the drawing-pair default;
    about 25 s): zone means of the entering pair's share within 0.03 of gear static (measured
    0.017; 0.0066 from the same-model statics), energy balance < 2 % (measured 1.19 %), mean
    total force within 1 % over the run (measured -0.49 %)."""
    cfg = _unequal("pinion")
    cfg["mesh"] = {"preset": "default"}
    cfg["solver"]["dt"] = 1.8e-8
    cfg["operation"]["span_deg"] = 12.5
    ds = run_case(cfg).dataset
    assert ds.attrs["status"] == "success"
    assert float(ds["energy_balance_error"]) < 0.02
    th2 = float(ds["theta_2"])
    edges = th2 * np.array([0.1, 0.3, 0.5, 0.7, 0.9])
    pa = ds["pair_angle"].values[:, 1]
    f = ds["contact_force"].values
    share = f[:, 1] / (f[:, 0] + f[:, 1])
    dyn = np.array([np.mean(share[(pa >= a) & (pa < b)]) for a, b in zip(edges[:-1], edges[1:], strict=True)])
    _, static = _static_shares("default", edges)
    assert np.max(np.abs(dyn - static)) < 0.03
    assert np.mean(ds["total_contact_force"].values) == pytest.approx(float(ds["nominal_force"]), rel=1e-2)


def test_driver_wheel_relabels_the_tie_multipliers_of_unequal_supports():
    """A root-clamped wheel (62 tie nodes per tooth on the coarse mesh) driving a rim-supported
    pinion (25): after the mirror relabelling each gear's tie block is its own, so the tie forces
    of tooth 0 of either gear add up to the force of pair 0 (quasi-static start)."""
    cfg = _unequal("wheel")
    cfg["wheel"]["support"] = "root_clamp"
    cfg["operation"]["span_deg"] = 0.1
    _, _, model = build(load_config(cfg))
    n_wheel, n_pinion = (int(np.count_nonzero(model.tie_gear == g)) // 3 for g in (0, 1))
    assert (n_pinion, n_wheel) == (25, 62)
    ds = run_case(cfg).dataset
    mu = ds["tie_multiplier"].values[0]
    force = float(ds["contact_force"].values[0, 0])

    def resultant(block):
        return math.hypot(block[0::2].sum(), block[1::2].sum())

    assert resultant(mu[: 2 * n_pinion]) == pytest.approx(force, rel=0.02)
    assert resultant(mu[6 * n_pinion : 6 * n_pinion + 2 * n_wheel]) == pytest.approx(force, rel=0.02)
