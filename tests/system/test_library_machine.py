"""Machines built in Python (rotaflex.system.study): the same model, numbers, messages and
figures as the TOML path of ``rotaflex system`` (issue 37, "The library")."""

from __future__ import annotations

import dataclasses
import math
import runpy
import sys
from pathlib import Path

import numpy as np
import pytest

from rotaflex.core.config import load_toml
from rotaflex.core.errors import InputError
from rotaflex.rotor.fe import Bearing, Disk, Rotor, Shaft
from rotaflex.rotor.fe.materials import MATERIALS
from rotaflex.system import Gearbox
from rotaflex.system.case import (
    run_campbell,
    run_frf,
    run_modal,
    run_response,
    run_stability,
    run_startup,
    run_static,
    run_steady,
    run_torsional,
    run_transient,
    run_ucs,
    run_unbalance,
)
from rotaflex.system.study import (
    DriveSpec,
    LoadSpec,
    Machine,
    MachineDOF,
    MachineRotor,
    MachineStaticLoad,
    MachineUnbalanceMass,
    MeshSpec,
    Probe,
    campbell_diagram,
    critical_speed_map,
    frf,
    mesh_response,
    modes,
    stability,
    startup,
    static_state,
    steady_state_study,
    torsional_analysis,
    transient_response,
    unbalance_response_study,
)

ROOT = Path(__file__).resolve().parents[2]
TOML = ROOT / "examples" / "system" / "motor_coupling_pump.toml"
SCRIPT = ROOT / "examples" / "python" / "coupled_train.py"


@pytest.fixture(scope="module")
def example(tmp_path_factory):
    """examples/python/coupled_train.py run in this process (its figures written to a tmp dir)."""
    out = tmp_path_factory.mktemp("coupled_train")
    argv, sys.argv = sys.argv, ["coupled_train.py", str(out)]
    try:
        ns = runpy.run_path(str(SCRIPT), run_name="__main__")
    finally:
        sys.argv = argv
    return ns, out


def test_python_train_gives_the_toml_numbers(example):
    """The Python-built train and examples/system/motor_coupling_pump.toml through the runners
    the CLI calls: the same model (equal specs) and the same frequencies to 1e-12."""
    ns, out = example
    assert (out / "interference.png").exists() and (out / "campbell.png").exists()
    cfg = load_toml(TOML)
    assert ns["machine"].gearbox.spec == Gearbox.from_mapping(cfg).spec
    pairs = (
        (ns["torsion"], run_torsional(cfg), "natural_frequency"),
        (ns["coupled"], run_modal(cfg), "damped_frequency"),
        (ns["camp"], run_campbell(cfg), "damped_frequency"),
        (ns["static"], run_static(cfg), "reaction"),  # the file's [static] is the defaults
    )
    for lib, cli, var in pairs:
        a, b = lib.dataset[var].values, cli.dataset[var].values
        assert a.shape == b.shape and a.size
        np.testing.assert_allclose(a, b, rtol=1e-12, atol=0)
    assert ns["torsion"].summary()["api684_verdict"] == run_torsional(cfg).summary()["api684_verdict"]


def test_example_critical_and_runup_agree_with_the_unbalance_peak(example):
    """The example's undamped critical at the pump's 1e8 N/m (critical_speed_map) against a second
    formulation, the peak of its damped unbalance response (85 speeds, bearings damped
    lightly: within 1 %); its 2000 rpm/s run-up peaks later and lower than the steady response
    (the run-up lag of F. M. Lewis, "Vibration during acceleration through a critical speed",
    Trans. ASME 54, 1932)."""
    ns, _ = example
    ucs, unb, run = ns["ucs"], ns["unbalance"].summary(), ns["runup"].summary()
    assert float(ucs.dataset["stiffness"][2]) == pytest.approx(1e8, rel=1e-12)
    critical = float(ucs.dataset["critical_speed"][2, 0]) * 30 / math.pi
    assert critical == pytest.approx(unb["peak_0_speed_rpm"]["value"], rel=1e-2)
    assert run["speed_at_max_rpm"]["value"] > critical
    assert run["max_radial_displacement"]["value"] < unb["peak_0_amplitude"]["value"]


def test_lowest_torsional_mode_is_the_two_inertia_mode(example):
    """Independent check: the motor and pump inertias on the coupling spring in series with the
    two shaft lengths between them (a two-inertia system). The shafts' own inertia, lumped
    here at the ends, is 2 % of the total, so the closed form is good to about that."""
    ns, _ = example
    steel = MATERIALS["steel"]
    jp = {d: math.pi * d**4 / 32 for d in (0.075, 0.06)}
    j_motor = 1.2 + steel.rho * jp[0.075] * 0.9 + 0.05 / 2  # core + shaft + half the coupling
    j_pump = 0.35 + steel.rho * jp[0.06] * 0.8 + 0.05 / 2
    flex = 1 / 1.2e4 + 0.45 / (steel.G * jp[0.075]) + 0.8 / (steel.G * jp[0.06])  # core to impeller
    f = math.sqrt((j_motor + j_pump) / (j_motor * j_pump) / flex) / (2 * math.pi)
    got = float(ns["torsion"].dataset["natural_frequency"][0]) / (2 * math.pi)
    assert got == pytest.approx(f, rel=0.02)


def _gear_rotor(d, k, disk=None):
    b = dict(kxx=k, kyy=k, cxx=500.0, cyy=500.0)
    return Rotor(
        shaft=(Shaft(outer_diameter=d, length=0.24, elements=6),),
        bearing=(Bearing(node=1, **b), Bearing(node=5, **b)),
        disk=() if disk is None else (disk,),
    )


def geared_machine(out_center=(0.0901, 0.0), **mesh) -> Machine:
    """tests/system/conftest.py's two-shaft 20/40 gearbox (``config()``), written in Python."""
    gears = {
        "pinion": {"teeth": 20, "module": 3e-3, "face_width": 0.025, "blank": {"kind": "solid", "bore_diameter": 0.03}},
        "wheel": {"teeth": 40, "module": 3e-3, "face_width": 0.025, "blank": {"kind": "solid", "bore_diameter": 0.04}},
    }
    keys = dict(pinion_rotor="in", pinion_node=3, wheel_rotor="out", wheel_node=3, source="harmonic", k_mean=4e8)
    keys.update(damping_ratio=0.07, center_distance=0.0901)
    return Machine(
        rotors={
            "in": _gear_rotor(0.035, 2e8, Disk(node=0, mass=1.0, Id=1e-3, Ip=1.5e-3)),
            "out": MachineRotor(_gear_rotor(0.045, 3e8), center=out_center),
        },
        meshes=(MeshSpec(**{**keys, **gears, **mesh}),),
        drive=DriveSpec(rotor="in", node=0, kind="torque"),
        load=LoadSpec(rotor="out", node=6, torque=100.0, inertia=0.02),
    )


def test_geared_machine_gives_the_toml_numbers(make):
    box = geared_machine()
    cfg = make()
    assert box.gearbox.spec == Gearbox.from_mapping(cfg).spec
    lib = modes(box, speed_rpm=3000.0, n_modes=8)
    cli = run_modal({**cfg, "modal": {"speed_rpm": 3000.0, "n_modes": 8}})
    np.testing.assert_allclose(lib.dataset["damped_frequency"], cli.dataset["damped_frequency"], rtol=1e-12)
    rad = modes(box, speed=3000.0 * math.pi / 30, n_modes=8)  # the same speed in rad/s
    np.testing.assert_allclose(rad.dataset["damped_frequency"], lib.dataset["damped_frequency"], rtol=1e-12)
    assert set(lib.plot()) == {"system", "energy_split"}


def test_response_steady_and_startup_give_the_toml_numbers(make, example):
    """The time-domain and frequency-response analyses on short runs: the Python machines and
    their TOML twins through the CLI runners, equal to 1e-12."""
    te = (1e-6,)
    lib = mesh_response(geared_machine(te_harmonics=te), speed_rpm=(500.0, 6000.0), n_speeds=20)
    cli = run_response({**make(te=te), "response": {"speed_rpm": [500.0, 6000.0], "n_speeds": 20}})
    assert float(lib.dataset["mesh_force"].max()) > 0
    np.testing.assert_allclose(lib.dataset["mesh_force"], cli.dataset["mesh_force"], rtol=1e-12)
    one, two = lib.plot_response(), lib.plot()["response"]
    la, lb = one.axes[1].get_lines(), two.axes[1].get_lines()
    assert la and all(np.array_equal(a.get_xydata(), b.get_xydata()) for a, b in zip(la, lb, strict=True))
    settings = {"min_cycles": 2, "max_cycles": 4, "eval_cycles": 2}
    lib = steady_state_study(geared_machine(), speed_rpm=3000.0, **settings)
    cli = run_steady({**make(), "steady": {"speed_rpm": 3000.0, **settings}})
    np.testing.assert_allclose(lib.dataset["mesh_force"], cli.dataset["mesh_force"], rtol=1e-12)
    run = {"duration": 0.05, "n_out": 11, "max_frequency_hz": 400.0}
    lib = startup(example[0]["machine"], **run)
    cli = run_startup({**load_toml(TOML), "startup": run})
    assert float(lib.dataset["rotor_speed"][-1, 0]) > 0
    np.testing.assert_allclose(lib.dataset["rotor_speed"], cli.dataset["rotor_speed"], rtol=1e-12)


def _message(fn) -> str:
    with pytest.raises(InputError) as err:
        fn()
    return str(err.value)


def test_bad_machines_get_the_toml_messages(make, example):
    """The same mistake in Python and in the file gives the same message, naming the file's key."""
    for key, value, kwargs in (
        ("pinion_node", 9, {"pinion_node": 9}),
        ("damping_ratio", 2.0, {"damping_ratio": 2.0}),
    ):
        cfg = make()
        cfg["gear_mesh"][0][key] = value
        py = _message(lambda kw=kwargs: geared_machine(**kw))
        assert py == _message(lambda c=cfg: Gearbox.from_mapping(c)) and "gear_mesh[0]" in py
    cfg = make()
    cfg["rotor"][1]["center"] = [0.1, 0.0]
    py = _message(lambda: geared_machine(out_center=(0.1, 0.0)))
    assert py == _message(lambda: Gearbox.from_mapping(cfg)) and py.startswith("rotor[1].center")
    cfg = make()  # a response needs an excitation: refused naming the key that gives one
    py = _message(lambda: mesh_response(geared_machine(), speed_rpm=(500.0, 6000.0), n_speeds=20))
    cli = _message(lambda: run_response({**cfg, "response": {"speed_rpm": [500.0, 6000.0], "n_speeds": 20}}))
    assert py == cli and py.startswith("gear_mesh[0].te_harmonics")
    machine = example[0]["machine"]
    toml = load_toml(TOML)
    del toml["coupling"][0]["torsional_stiffness"]
    soft = dataclasses.replace(machine.couplings[0], torsional_stiffness=None)
    py = _message(lambda: dataclasses.replace(machine, couplings=(soft,)))
    assert py == _message(lambda: Gearbox.from_mapping(toml)) and py.startswith("coupling[0].torsional_stiffness")


def test_speeds_are_explicit_in_their_names():
    box = geared_machine()
    with pytest.raises(InputError, match="one of speed_rpm"):
        campbell_diagram(box, speed_rpm=(0, 3000), speed=(0, 314))
    with pytest.raises(InputError, match="one of speed_rpm"):
        campbell_diagram(box)
    with pytest.raises(TypeError):
        modes(box, 3000.0)  # a bare number has no unit: refused
    with pytest.raises(InputError, match="torsional.operating_speed_rpm"):
        torsional_analysis(box, operating_speed_rpm=(1, 2), operating_speed=(0.1, 0.2))


def test_plot_methods_are_the_cli_figures(example):
    """Each plot method draws what the CLI's file of that name shows (one implementation)."""
    ns, _ = example
    for res, method, key in (
        (ns["torsion"], "plot_interference", "interference"),
        (ns["torsion"], "plot_modes", "torsional_modes"),
        (ns["camp"], "plot_campbell", "campbell"),
        (ns["coupled"], "plot_energy", "energy_split"),
    ):
        one, cli = getattr(res, method)(), res.plot()[key]
        la, lb = one.axes[0].get_lines(), cli.axes[0].get_lines()
        assert len(la) == len(lb) and la
        for x, y in zip(la, lb, strict=True):
            assert np.array_equal(x.get_xydata(), y.get_xydata(), equal_nan=True)
    assert set(ns["torsion"].plot()) == {"system", "interference", "torsional_modes"}
    assert ns["camp"].plot_model() is not None


_MASS = {"rotor": "pump", "node": 5, "magnitude": 1e-4, "phase_deg": 30.0}
_UNB = {"speed_rpm": [300.0, 3000.0], "n_speeds": 30, "operating_range_rpm": [1440.0, 1500.0]}
_DOFS = [{"rotor": "pump", "node": 5, "direction": "x"}, {"rotor": "motor", "node": 3, "direction": "x"}]
_FRF = {"frequency_hz": [5.0, 100.0], "n_frequencies": 20, "kind": "mobility"}


def _same(lib, cli):
    """Every data variable of the two datasets identical (same code path, same numbers)."""
    a, b = lib.dataset, cli.dataset
    assert list(a.data_vars) == list(b.data_vars) and a.data_vars
    for v in a.data_vars:
        np.testing.assert_array_equal(a[v].values, b[v].values)


def test_unbalance_response_is_the_cli_runner(example):
    """The machine's unbalance response from Python equals ``rotaflex system unbalance`` on the
    TOML twin; independent check: the response is linear in the unbalance (twice m e, twice the
    orbit) and the phase key turns the orbit's complex amplitude by that angle."""
    machine = example[0]["machine"]
    mass = MachineUnbalanceMass(**_MASS)
    lib = unbalance_response_study(
        machine,
        [mass],
        speed_rpm=(300.0, 3000.0),
        n_speeds=30,
        probes=[Probe(rotor="pump", node=5)],
        operating_range_rpm=(1440.0, 1500.0),
    )
    probes = [{"rotor": "pump", "node": 5}]
    cli = run_unbalance({**load_toml(TOML), "unbalance": {**_UNB, "probes": probes, "mass": [_MASS]}})
    _same(lib, cli)
    assert lib.summary().keys() == cli.summary().keys()
    double = unbalance_response_study(
        machine,
        [{**_MASS, "magnitude": 2e-4, "phase_deg": 0.0}],
        speed=(300.0 * math.pi / 30, 3000.0 * math.pi / 30),
        n_speeds=30,
    )
    a, b = lib.dataset, double.dataset
    za = (a["x_real"] + 1j * a["x_imag"]).values.ravel()
    zb = (b["x_real"] + 1j * b["x_imag"]).values.ravel()
    assert np.abs(za).max() > 1e-7
    np.testing.assert_allclose(zb, 2 * za * np.exp(-1j * math.radians(30.0)), rtol=1e-6, atol=1e-12)


def test_frf_is_the_cli_runner_and_reciprocal(example):
    """FRFs from Python equal ``rotaflex system frf``; independent check (Maxwell-Betti): at
    rest the matrices are symmetric, so the cross FRFs H_ij and H_ji are equal."""
    machine = example[0]["machine"]
    lib = frf(machine, inputs=[MachineDOF(**d) for d in _DOFS], outputs=_DOFS, speed_rpm=1480.0, **_FRF)
    cli = run_frf({**load_toml(TOML), "frf": {**_FRF, "speed_rpm": 1480.0, "inputs": _DOFS, "outputs": _DOFS}})
    _same(lib, cli)
    rest = frf(machine, inputs=_DOFS, **_FRF).dataset  # outputs default to the inputs; at rest
    H = rest["H_real"].values + 1j * rest["H_imag"].values
    names = list(rest["pair"].values)
    ij, ji = names.index("motor:3 x / pump:5 Fx"), names.index("pump:5 x / motor:3 Fx")
    assert np.abs(H[:, ij]).max() > 0
    np.testing.assert_allclose(H[:, ij], H[:, ji], rtol=1e-8)


def test_stability_is_the_cli_runner(example):
    """API 617 stability from Python equals ``rotaflex system stability``; the MCS in rad/s is
    the same run as in rpm."""
    machine = example[0]["machine"]
    lib = stability(machine, rotor="pump", kind="pump", speed_rpm=1480.0)
    cli = run_stability({**load_toml(TOML), "stability": {"rotor": "pump", "machine": "pump", "speed_rpm": 1480.0}})
    _same(lib, cli)
    rad = stability(machine, rotor="pump", kind="pump", speed=1480.0 * math.pi / 30)
    np.testing.assert_allclose(rad.dataset["log_dec_level2"], lib.dataset["log_dec_level2"], rtol=1e-9)
    assert lib.summary()["level2_verdict"]["value"] == cli.summary()["level2_verdict"]["value"]


def test_bad_machine_analyses_name_the_toml_keys(example):
    """A wrong rotor name, direction or speed in Python gets the message of the same mistake in
    the file, naming its key (``unbalance.mass[0].rotor``)."""
    machine, toml = example[0]["machine"], load_toml(TOML)
    bad = {**_MASS, "rotor": "fan"}
    py = _message(lambda: unbalance_response_study(machine, [bad], speed_rpm=(300.0, 3000.0), n_speeds=5))
    cli = _message(
        lambda: run_unbalance({**toml, "unbalance": {"speed_rpm": [300.0, 3000.0], "n_speeds": 5, "mass": [bad]}})
    )
    assert py == cli and py.startswith("unbalance.mass[0].rotor")
    dof = {"rotor": "pump", "node": 5, "direction": "z"}
    py = _message(lambda: frf(machine, inputs=[_DOFS[0], dof], n_frequencies=5))
    cli = _message(lambda: run_frf({**toml, "frf": {"inputs": [_DOFS[0], dof], "n_frequencies": 5}}))
    assert py == cli and py.startswith("frf.inputs[1].direction")
    py = _message(lambda: stability(machine, rotor="fan", kind="pump", speed_rpm=1480.0))
    cli = _message(
        lambda: run_stability({**toml, "stability": {"rotor": "fan", "machine": "pump", "speed_rpm": 1480.0}})
    )
    assert py == cli and py.startswith("stability.rotor")
    with pytest.raises(InputError, match="frf.speed_rpm"):
        frf(machine, inputs=_DOFS, speed_rpm=1480.0, speed=155.0)
    with pytest.raises(InputError, match="unbalance.mass"):
        unbalance_response_study(machine, _MASS, speed_rpm=(300.0, 3000.0))  # one table, not a list


_LOAD = {"rotor": "pump", "node": 5, "fy": -500.0}


def test_static_state_is_the_cli_runner_and_carries_the_weight(example):
    """The static state from Python equals ``rotaflex system static`` on the TOML twin (every
    array identical); independent check (equilibrium of the whole train): the bearing reactions
    carry the weight of both shafts, the motor core, the impeller and the coupling, computed here
    from the geometry (steel, 7810 kg/m^3), plus a point load, to 1e-9."""
    machine = example[0]["machine"]
    lib = static_state(machine, loads=[MachineStaticLoad(**_LOAD)], speed_rpm=1480.0)
    cli = run_static({**load_toml(TOML), "static": {"load": [_LOAD], "speed_rpm": 1480.0}})
    _same(lib, cli)
    rho = MATERIALS["steel"].rho
    mass = rho * math.pi / 4 * (0.075**2 * 0.9 + 0.06**2 * 0.8) + 120.0 + 25.0 + 8.0
    g = 9.80665
    plain = static_state(machine, speed=1480.0 * math.pi / 30)  # gravity alone, the speed in rad/s
    assert float(plain.dataset["reaction"][:, 1].sum()) == pytest.approx(mass * g, rel=1e-9)
    assert float(lib.dataset["reaction"][:, 1].sum()) == pytest.approx(mass * g + 500.0, rel=1e-9)
    side = static_state(machine, gravity=2.0, gravity_direction=(1.0, 0.0))  # along +x: reactions in -x
    assert float(side.dataset["reaction"][:, 0].sum()) == pytest.approx(-mass * 2.0, rel=1e-9)


def _bare_rotor(k: float) -> Rotor:
    return Rotor(
        shaft=(Shaft(outer_diameter=0.05, length=0.8, elements=8),),
        bearing=(Bearing(node=0, kxx=k, kyy=k), Bearing(node=8, kxx=k, kyy=k)),
    )


def test_critical_speed_map_is_the_cli_runner_and_has_the_beam_limits(example):
    """The UCS map from Python equals ``rotaflex system ucs`` (arrays identical); independent
    checks on a bare uniform shaft (d 50 mm, 0.8 m, steel) as a machine of one rotor: soft
    bearings give the rigid-body bounce sqrt(2 k / m) (to 0.2 %: the shaft's own bending), stiff
    bearings the pinned-pinned Euler-Bernoulli beam pi^2 sqrt(E I / (rho A L^4)) (to 1 %:
    Timoshenko shear and rotary inertia lower it)."""
    machine = example[0]["machine"]
    table = {"rotors": ["pump"], "stiffness": [1e6, 1e10], "n_points": 5, "n_modes": 2}
    lib = critical_speed_map(machine, rotors=("pump",), stiffness=(1e6, 1e10), n_points=5, n_modes=2)
    cli = run_ucs({**load_toml(TOML), "ucs": table})
    _same(lib, cli)
    assert lib.summary().keys() == cli.summary().keys()
    bare = Machine(rotors={"shaft": _bare_rotor(1e5)}, drive=DriveSpec(rotor="shaft", node=0))
    w = critical_speed_map(bare, stiffness=(1e4, 1e12), n_points=2, n_modes=1).dataset["critical_speed"].values
    steel, area, inertia = MATERIALS["steel"], math.pi * 0.025**2, math.pi * 0.05**4 / 64
    bounce = math.sqrt(2 * 1e4 / (steel.rho * area * 0.8))
    euler = math.pi**2 * math.sqrt(steel.E * inertia / (steel.rho * area * 0.8**4))
    assert w[0, 0] == pytest.approx(bounce, rel=2e-3)
    assert w[1, 0] == pytest.approx(euler, rel=1e-2) and w[1, 0] < euler


_RUN = {"speed_rpm": [3000.0, 3500.0], "duration": 0.05, "n_output": 51, "n_modes": 20}
_TMASS = [
    {"rotor": "pump", "node": 5, "magnitude": 1e-3},
    {"rotor": "motor", "node": 3, "magnitude": 2e-3, "phase_deg": 90.0},
]


def test_transient_response_is_the_cli_runner_and_both_integrations_agree(example):
    """The transient from Python equals ``rotaflex system transient`` (arrays identical);
    independent check (a second formulation): the modal integration (20 undamped modes at the
    mid speed) and Newmark on all coordinates give the same orbits to 2 % of the peak."""
    machine = example[0]["machine"]
    probes = [{"rotor": "pump", "node": 5}, {"rotor": "motor", "node": 3}]
    masses = [MachineUnbalanceMass(**m) for m in _TMASS]
    lib = transient_response(machine, masses=masses, probes=[Probe(**p) for p in probes], **_RUN)
    cli = run_transient({**load_toml(TOML), "transient": {**_RUN, "mass": _TMASS, "probes": probes}})
    _same(lib, cli)
    a = lib.dataset["displacement"].values
    rad = {**_RUN, "speed_rpm": None, "speed": tuple(v * math.pi / 30 for v in _RUN["speed_rpm"])}
    direct = transient_response(machine, masses=_TMASS, probes=probes, method="direct", **rad)
    b = direct.dataset["displacement"].values
    assert np.abs(a).max() > 1e-5
    assert np.abs(a - b).max() < 0.02 * np.abs(a).max()


def test_static_ucs_and_transient_refuse_bad_input_naming_the_toml_key(example):
    """A wrong rotor name gets the verb's message naming the key (``static.load[0].rotor``,
    ``ucs.rotors[0]``, ``transient.mass[0].rotor``); speed_rpm and speed together are refused."""
    machine, toml = example[0]["machine"], load_toml(TOML)
    fan = {**_LOAD, "rotor": "fan"}
    py = _message(lambda: static_state(machine, loads=[fan]))
    assert py == _message(lambda: run_static({**toml, "static": {"load": [fan]}}))
    assert py.startswith("static.load[0].rotor")
    py = _message(lambda: critical_speed_map(machine, rotors=["fan"], n_points=2))
    assert py == _message(lambda: run_ucs({**toml, "ucs": {"rotors": ["fan"], "n_points": 2}}))
    assert py.startswith("ucs.rotors[0]")
    bad = [{**_TMASS[0], "rotor": "fan"}]
    py = _message(lambda: transient_response(machine, masses=bad, **_RUN))
    assert py == _message(lambda: run_transient({**toml, "transient": {**_RUN, "mass": bad}}))
    assert py.startswith("transient.mass[0].rotor")
    for call, key in (
        (lambda: static_state(machine, speed_rpm=1480.0, speed=155.0), "static.speed_rpm"),
        (lambda: critical_speed_map(machine, speed_rpm=1480.0, speed=155.0), "ucs.speed_rpm"),
        (lambda: transient_response(machine, speed_rpm=(0, 1), speed=(0, 0.1)), "transient.speed_rpm"),
        (lambda: transient_response(machine, duration=0.1), "transient.speed_rpm"),
        (lambda: static_state(machine, loads=_LOAD), "static.load"),
    ):
        assert _message(call).startswith(key)


@pytest.mark.parametrize("name", ["static_state", "critical_speed_map", "transient_response"])
def test_docstring_examples_run(name):
    """The Examples of the three functions run as written (the weight split, the bounce ratio)."""
    import doctest

    from rotaflex.system import study

    finder, runner = doctest.DocTestFinder(), doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
    (test,) = finder.find(getattr(study, name), f"rotaflex.system.study.{name}", globs=vars(study).copy())
    assert test.examples
    assert runner.run(test).failed == 0
