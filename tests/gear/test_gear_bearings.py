"""Bearing (lateral) compliance of the gear centres along the line of action: closed-form
natural frequencies, a frequency-domain solution of the linear 3-DOF system, statics, energy,
the rigid-bearing limit and the elastic-tooth model against the lumped one."""

import math

import numpy as np
import pytest

from rotaflex.core.errors import InputError
from rotaflex.gear.models.chain import (
    OperatingPoint,
    TorsionalSystem,
    energy_balance,
    natural_frequencies,
    simulate,
    steady_state,
)
from rotaflex.gear.models.mesh_stiffness import harmonic_mesh

RB = 0.04177  # base radius [m]
J = 2.965e-4  # gear inertia [kg m^2]
K = 1.9e8  # mesh stiffness [N/m]
KB = (3.0e8, 5.0e8)  # bearing stiffness along the line of action [N/m]
CB = (400.0, 700.0)  # bearing damping [N s/m]
MASS = (0.35, 0.5)  # gear masses [kg]
E = (1.0e-6, 0.4e-6, 0.2e-6)  # unloaded TE harmonics 1x, 2x, 3x [m]


def _free_pair(**kw):
    """Both gears free (motor drive, rigid shafts), constant mesh stiffness."""
    return TorsionalSystem(
        mesh=harmonic_mesh(K), base_radius=(RB, RB), inertia=(J, J), drive="motor", motor_slope=0.5, **kw
    )


def test_symmetric_pair_natural_frequencies_closed_form():
    """Equal gears and bearings, both gears free: the symmetric mode pair solves
    M m w^4 - (M (k_b + 2k) + 2 k m) w^2 + 2 k k_b = 0 (M = J / r_b^2); the antisymmetric lateral
    mode does not strain the mesh, w^2 = k_b / m."""
    kb, m = 4.0e8, 0.4
    sys = _free_pair(bearing_stiffness=(kb, kb), gear_mass=(m, m))
    big_m = J / RB**2
    a, b, c = big_m * m, -(big_m * (kb + 2 * K) + 2 * K * m), 2 * K * kb
    w2 = np.sort(np.roots([a, b, c]).real)
    expected = np.sort(np.sqrt(np.append(w2, kb / m)) / (2 * math.pi))
    nf = natural_frequencies(sys)
    np.testing.assert_allclose(nf["frequency"], expected, rtol=1e-10)
    lateral = np.argmin(np.abs(nf["frequency"] - math.sqrt(kb / m) / (2 * math.pi)))
    assert nf["mesh_energy"][lateral] < 1e-10


def test_stiff_bearings_approach_the_rigid_pair():
    f0 = natural_frequencies(_free_pair())["frequency"][0]
    errs = []
    for kb in (1e11, 1e12, 1e13):
        nf = natural_frequencies(_free_pair(bearing_stiffness=(kb, kb), gear_mass=MASS))
        errs.append(abs(nf["frequency"][nf["mesh_mode"]] / f0 - 1))
    # series springs: the mesh mode softens by about k / (2 k_b) per bearing pair -> 1/k_b
    assert errs[0] > 5e-4
    np.testing.assert_allclose(np.array(errs[:-1]) / np.array(errs[1:]), 10.0, rtol=0.02)


def _held_pinion(**kw):
    """Pinion turned at constant speed, wheel (+ load) free, both centres on bearings."""
    return TorsionalSystem(
        mesh=harmonic_mesh(K, (), E),
        base_radius=(RB, RB),
        inertia=(J, J),
        bearing_stiffness=KB,
        bearing_damping=CB,
        gear_mass=MASS,
        **kw,
    )


def _frequency_response(sys, speed_rpm, torque):
    """Steady response of the linear system z = (v, y1, y2), v = r2 theta2 - r1 theta1:
    M z'' + C z' + K z + g F = f0, F = k (g.z - e) + c (g.z' - e'), g = (-1, 1, -1), solved per
    TE harmonic in the frequency domain. Returns DTE (= -v) amplitudes and F_max / F0."""
    k, c, f0 = K, sys.mesh_damping, torque / RB
    mass = np.diag([J / RB**2, *MASS])
    damp = np.diag([0.0, *CB]) + c * np.outer(G, G)
    stiff = np.diag([0.0, *KB]) + k * np.outer(G, G)
    w_mesh = speed_rpm * math.pi / 30 * 28
    t = np.linspace(0, 2 * math.pi / w_mesh, 20001)
    force = np.full_like(t, f0)
    amps = []
    for h, e_h in enumerate(E, start=1):
        w = h * w_mesh
        e_c = -1j * e_h  # e = e_h sin(w t) = Re(-i e_h exp(i w t))
        z = np.linalg.solve(stiff - w**2 * mass + 1j * w * damp, G * (k + 1j * w * c) * e_c)
        amps.append(abs(z[0]))
        f_c = (k + 1j * w * c) * (G @ z - e_c)
        force += np.real(f_c * np.exp(1j * w * t))
    return np.array(amps), force.max() / f0


G = np.array([-1.0, 1.0, -1.0])


@pytest.mark.parametrize("speed", [4000.0, 9000.0, 12500.0])
def test_linear_limit_matches_frequency_domain_solution(speed):
    """Measured: harmonics within 1e-5, K_v within 7e-6 (RK4 at 200 steps per cycle)."""
    sys = _held_pinion()
    torque = 300.0  # no contact loss
    res, _ = steady_state(sys, OperatingPoint(speed, torque), tol=1e-7, max_cycles=2000, steps_per_cycle=200)
    ds = res.dataset
    assert res.status == "success"
    amps, kv = _frequency_response(sys, speed, torque)
    got = np.array([float(ds[f"dte_h{h}"]) for h in (1, 2, 3)])
    np.testing.assert_allclose(got, amps, rtol=2e-3, atol=1e-4 * amps.max())
    assert float(ds["dynamic_factor"]) == pytest.approx(kv, rel=1e-3)
    assert float(ds["contact_loss_fraction"]) == 0.0


def test_static_deflection_adds_the_bearing_compliances():
    """Slow roll, constant stiffness, no TE: DTE = F (1/k + 1/k_b1 + 1/k_b2) and the centres
    sit at -F/k_b1, +F/k_b2."""
    sys = TorsionalSystem(
        mesh=harmonic_mesh(K), base_radius=(RB, RB), inertia=(J, J), bearing_stiffness=KB, gear_mass=MASS
    )
    torque = 50.0
    f0 = torque / RB
    h = simulate(sys, OperatingPoint(200.0, torque), 5)
    names = h["names"]
    expected = f0 * (1 / K + 1 / KB[0] + 1 / KB[1])
    assert np.max(np.abs(h["dte"] - expected)) < 1e-9 * expected
    np.testing.assert_allclose(h["theta"][-1, names.index("pinion_lateral")], -f0 / KB[0], rtol=1e-9)
    np.testing.assert_allclose(h["theta"][-1, names.index("wheel_lateral")], f0 / KB[1], rtol=1e-9)
    np.testing.assert_allclose(h["force"], f0, rtol=1e-9)


@pytest.mark.parametrize("drive", ["constant_speed", "motor"])
def test_energy_balance_with_bearing_damping(drive):
    kw = {"drive": drive, "motor_slope": 0.5} if drive == "motor" else {}
    sys = _held_pinion(input_shaft_stiffness=2e4, motor_inertia=1e-3, **kw)
    op = OperatingPoint(9000.0, 40.0)  # from statics, no contact loss: smooth, RK4 order
    # measured residual / dissipation: 5.9e-6, 5.0e-7 (constant speed), 7.2e-6, 5.7e-7 (motor)
    res = []
    for spc in (100, 200):
        h = simulate(sys, op, 30, steps_per_cycle=spc)
        eb = energy_balance(sys, op, h)
        assert eb["dissipated"] > 0
        res.append(abs(eb["residual"]) / eb["dissipated"])
    assert res[0] < 1e-4
    assert res[1] < res[0] / 4


def test_bad_bearing_input_names_the_field():
    with pytest.raises(InputError, match=r"gear_mass\[1\]"):
        TorsionalSystem(mesh=harmonic_mesh(K), bearing_stiffness=(math.inf, 1e8))
    with pytest.raises(InputError, match=r"bearing_stiffness\[0\]"):
        TorsionalSystem(mesh=harmonic_mesh(K), bearing_stiffness=(-1.0, math.inf))
    with pytest.raises(InputError, match=r"bearing_damping\[1\]"):
        TorsionalSystem(mesh=harmonic_mesh(K), bearing_damping=(0.0, -2.0))


# ------------------------------------------------------------------ elastic-tooth window model
@pytest.fixture(scope="module")
def paper_pair():
    from rotaflex.gear.pair.geometry import GearGeometry, center_distance_no_backlash
    from rotaflex.gear.pair.tooth_mesh import build_tooth_mesh
    from rotaflex.gear.static.loaded_te import pair_line

    g = GearGeometry(module=3.175e-3, teeth=28, face_width=6.35e-3)
    mesh = build_tooth_mesh(g)
    torque = 5.0
    line = pair_line(g, g, mesh, mesh, center_distance_no_backlash(g, g), torque / g.base_radius, (210e9, 0.3) * 2)
    return g, mesh, line, torque


def _pair_system(g, table, **kw):
    return TorsionalSystem(
        mesh=table,
        base_radius=(g.base_radius,) * 2,
        inertia=(J, J),
        drive="motor",
        motor_slope=0.5,
        mesh_damping_ratio=0.2,
        bearing_stiffness=KB,
        bearing_damping=CB,
        gear_mass=MASS,
        **kw,
    )


def test_window_model_with_bearings_is_the_lumped_model_with_bearings(paper_pair):
    """Massless FE teeth without corner contact = the lumped model driven by gear static's
    k(phi): the bearing nodes enter both kernels the same way."""
    from rotaflex.gear.models.mesh_stiffness import loaded_mesh_table, mesh_table_from_static
    from rotaflex.gear.models.window import build_window_model
    from rotaflex.gear.solvers import window_run as wr
    from rotaflex.gear.static.tooth_analysis import mesh_stiffness

    g, mesh, line, torque = paper_pair
    lumped = _pair_system(g, mesh_table_from_static(mesh_stiffness(g, g, 210e9, 0.3, torque=torque), 28))
    table = loaded_mesh_table(line, torque / g.base_radius)
    model = build_window_model(_pair_system(g, table), line, (mesh, mesh), (7800.0,) * 2, corner_contact=False)
    st_l = st_w = None
    for rpm in (12000.0, 16000.0, 19000.0):
        op = OperatingPoint(rpm, torque)
        rl, st_l = steady_state(lumped, op, state=st_l)
        rw, st_w = wr.steady_state(model, op, state=st_w)
        dl, dw = rl.dataset, rw.dataset
        assert float(dl.contact_loss_fraction) == 0 and float(dw.contact_loss_fraction) == 0
        assert float(dw.dynamic_factor) == pytest.approx(float(dl.dynamic_factor), rel=5e-3)
        assert float(dw.dte_h1) == pytest.approx(float(dl.dte_h1), rel=5e-3)
    assert len(st_w.theta) == 4  # pinion, wheel (rigid shafts merged) and the two centres


def test_window_model_energy_with_bearings_and_tooth_modes(paper_pair):
    from rotaflex.gear.models.mesh_stiffness import loaded_mesh_table
    from rotaflex.gear.models.window import build_window_model
    from rotaflex.gear.solvers import window_run as wr

    g, mesh, line, torque = paper_pair
    model = build_window_model(
        _pair_system(g, loaded_mesh_table(line, line.force)), line, (mesh, mesh), (7800.0,) * 2, n_modes=2
    )
    op = OperatingPoint(10000.0, torque)
    _, st = wr.steady_state(model, op, fixed_cycles=20)
    res = []
    for spc in (400, 1600):
        eb = wr.energy_balance(model, op, wr.simulate(model, op, 10, steps_per_cycle=spc, state=st))
        res.append(abs(eb["residual"]) / eb["dissipated"])
    assert res[1] < 0.01 and res[1] < res[0] / 2, res


# ------------------------------------------------------------------------- config and CLI
def _fast_case(speed=9000.0, **extra):
    """The paper's pair with the analytic mesh (no FE statics) at one speed."""
    return {"mesh": {"source": "contact_pattern", "pair_stiffness": 1.2e8}, "operation": {"speed_rpm": speed}, **extra}


def test_case_with_bearings_runs_and_reports_the_nodes():
    from rotaflex.gear.cases.steady import run_torsional

    bearings = {"stiffness": [3e8, 5e8], "damping": [400.0, 700.0], "mass": [0.35, 0.5]}
    soft = run_torsional(_fast_case(bearings=bearings))
    ds = soft.dataset
    assert soft.status == "success"
    assert list(ds["chain_node"].values) == ["pinion", "wheel", "pinion_lateral", "wheel_lateral"]
    assert ds.sizes["mode"] == run_torsional(_fast_case()).dataset.sizes["mode"] + 2
    # quasi-static (500 rpm): the mean DTE grows by F (1/k_b1 + 1/k_b2)
    slow = run_torsional(_fast_case(500.0, bearings=bearings)).dataset
    shift = float(slow["dte_mean"]) - float(run_torsional(_fast_case(500.0)).dataset["dte_mean"])
    assert shift == pytest.approx(float(slow["static_mesh_force"]) * (1 / 3e8 + 1 / 5e8), rel=1e-3)


def test_bearing_masses_default_to_the_drawing_blanks():
    from pathlib import Path

    from rotaflex.core.config import load_toml
    from rotaflex.gear.cases.steady import _bearing_keys, _checked

    path = Path(__file__).parents[2] / "examples" / "gear" / "steady" / "bearings.toml"
    cfg = load_toml(path)
    cfg.pop("domain")
    cfg.pop("verb")
    keys = _bearing_keys(_checked(cfg))
    pin = cfg["pinion"]
    # solid steel pinion: disk to the root circle minus the bore, teeth annulus at half density
    from rotaflex.core.config import from_mapping
    from rotaflex.gear.pair.drawing import GearSpec

    g = from_mapping(GearSpec, pin)._plain("pinion")
    rho, b = 7800.0, pin["face_width"]
    rf, ra, rbore = g.root_radius_, g.tip_radius_, 0.5 * pin["blank"]["bore_diameter"]
    expected = math.pi * rho * b * (rf**2 - rbore**2) + 0.5 * math.pi * rho * b * (ra**2 - rf**2)
    assert keys["gear_mass"][0] == pytest.approx(expected, rel=1e-12)
    assert keys["bearing_stiffness"] == (2.0e8, 3.0e8)


def test_bad_bearing_config():
    from rotaflex.gear.cases.steady import run_torsional

    with pytest.raises(InputError, match="bearings.mass"):
        run_torsional(_fast_case(bearings={"stiffness": [3e8, 5e8]}))
    with pytest.raises(InputError, match="bearings.stiffness"):
        run_torsional(_fast_case(bearings={"stiffness": [-3e8, 5e8], "mass": [1.0, 1.0]}))
    with pytest.raises(InputError, match="bearings.stiffness"):
        run_torsional(_fast_case(bearings={"mass": [1.0, 1.0]}))
    rigid = run_torsional(_fast_case())
    with pytest.raises(InputError, match="initial_state"):
        run_torsional(
            _fast_case(bearings={"stiffness": [3e8, 5e8], "mass": [0.35, 0.5]}), initial_state=rigid.final_state()
        )


def test_bearings_example_runs_from_the_command_line(tmp_path, capsys):
    import json
    from pathlib import Path

    from rotaflex.cli import main

    example = Path(__file__).parents[2] / "examples" / "gear" / "steady" / "bearings.toml"
    with pytest.raises(SystemExit) as exc:
        main(["gear", "steady", str(example), "--out", str(tmp_path / "out")])
    assert exc.value.code == 0, capsys.readouterr().err
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["status"]["value"] == "success"
    # the supports' static deflection is in the DTE: 9.96 um on rigid supports
    assert summary["dte_mean"]["value"] > 3 * 9.96e-6


def test_an_unstable_step_is_reported_with_its_time():
    """RK4 far beyond its stability limit (2 steps per mesh cycle at 4,000 rpm: w h = 13 for the
    8 kHz mesh mode, limit 2.8):
    the run stops with the time of the first non-finite state instead of returning NaNs."""
    from rotaflex.core.errors import DivergenceError
    from rotaflex.gear.models.chain import build_chain, initial_state, run_cycles

    sys = _held_pinion()
    op = OperatingPoint(4000.0, 50.0)
    ch = build_chain(sys, op)
    with pytest.raises(DivergenceError, match=r"torsional mesh model \(RK4\) diverged at t = [0-9.e-]+ s"):
        run_cycles(sys, op, ch, initial_state(sys, op, ch), 200, 2)
