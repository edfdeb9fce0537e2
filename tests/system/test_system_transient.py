"""``rotaflex system transient``: rotor/fe's one linear time integration on a machine's matrices."""

from __future__ import annotations

import copy

import numpy as np
import pytest

from rotaflex.core.errors import InputError
from rotaflex.core.units import rpm_to_rad_s
from rotaflex.rotor.fe.verbs_response import run_transient as rotor_transient
from rotaflex.system.case import run_transient as system_transient
from rotaflex.system.model import Gearbox
from rotaflex.system.transient import machine_transient
from rotaflex.system.unbalance import machine_unbalance

#: tabulated, cross-coupled bearing: the pencil is interpolated over the table's speeds
_TABLE = {
    "speed_rpm": [0.0, 1500.0, 6000.0],
    "kxx": [1.0e6, 1.6e6, 3.0e6],
    "kyy": [1.5e6, 1.8e6, 2.5e6],
    "kxy": [0.0, 1.0e5, 4.0e5],
    "kyx": [0.0, -1.0e5, -4.0e5],
    "cxx": [3.0e3, 2.7e3, 2.0e3],
    "cyy": [3.5e3, 3.2e3, 2.5e3],
}
_SHAFT = [{"outer_diameter": 0.05, "length": 0.8, "elements": 4}]
#: small polar inertias keep the first torsional mode (970 rad/s) above the four lateral modes
#: (183-376 rad/s) the modal runs keep, so the machine's basis is the rotor's
_DISKS = [{"node": 1, "mass": 30.0, "Id": 0.2, "Ip": 0.05}, {"node": 3, "mass": 45.0, "Id": 0.3, "Ip": 0.08}]
_MASSES = [{"node": 3, "magnitude": 1e-4, "phase_deg": 0.0}, {"node": 1, "magnitude": 5e-5, "phase_deg": 120.0}]


def _pair(settings):
    """The same rotor as a rotor case and as a machine of one rotor, with ``settings`` in [transient]."""
    rotor_cfg = {
        "shaft": _SHAFT,
        "disk": _DISKS,
        "bearing": {"left": {"node": 0, **_TABLE}, "right": {"node": 4, **_TABLE}},
        "transient": {**settings, "probes": [1, 3], "mass": _MASSES},
    }
    machine_cfg = {
        "rotor": [
            {
                "name": "r",
                "center": [0.0, 0.0],
                "shaft": _SHAFT,
                "disk": _DISKS,
                "bearing": [{"node": 0, **_TABLE}, {"node": 4, **_TABLE}],
            }
        ],
        "drive": {"rotor": "r", "node": 0},
        "transient": {
            **settings,
            "probes": [{"rotor": "r", "node": 1}, {"rotor": "r", "node": 3}],
            "mass": [{"rotor": "r", **m} for m in _MASSES],
        },
    }
    return rotor_cfg, machine_cfg


@pytest.mark.parametrize(
    "settings",
    [
        {"speed_rpm": [2000.0, 2000.0], "duration": 0.15, "n_output": 151, "n_modes": 4},
        {"speed_rpm": [0.0, 3000.0], "duration": 0.3, "n_output": 301, "n_modes": 4},
        {"speed_rpm": [500.0, 2500.0], "duration": 0.1, "n_output": 101, "method": "direct"},
    ],
    ids=["constant", "ramp", "ramp_direct"],
)
def test_one_rotor_machine_gives_the_rotor_verbs_response(settings):
    """A machine of one rotor (speed-table cross-coupled bearings crossed at 1500 rpm,
    gyroscopics, spin acceleration) through ``system transient`` equals ``rotor transient``:
    displacements at every probe and time to 1e-9 of their largest value, the same speed."""
    rotor_cfg, machine_cfg = _pair(settings)
    a = rotor_transient(copy.deepcopy(rotor_cfg)).dataset
    b = system_transient(copy.deepcopy(machine_cfg)).dataset
    scale = float(np.abs(a["displacement"]).max())
    assert scale > 1e-7  # the comparison is not of zeros
    np.testing.assert_allclose(b["displacement"].values, a["displacement"].values, rtol=0, atol=1e-9 * scale)
    np.testing.assert_allclose(b["speed"].values, a["speed"].values, rtol=1e-15)
    assert list(b["probe"].values) == ["r:1", "r:3"]


def _gearbox(make):
    """tests/system/conftest.py's 20/40 gearbox (4 elements per shaft) at a constant drive speed,
    with bearing damping 3000 N s/m and a load damper 20 N m s/rad: every mode decays within the
    run (the torsional mode at 1960 rad/s has zeta 0.22 with the damper, 0.002 without)."""
    cfg = make(drive="constant_speed", elements=4)
    for r in cfg["rotor"]:
        for b in r["bearing"]:
            b["cxx"] = b["cyy"] = 3000.0
    cfg["load"]["damping"] = 20.0
    return Gearbox.from_mapping(cfg)


def test_late_response_is_the_harmonic_unbalance_solution(make):
    """Constant drive speed W = 300 rad/s, unbalances on the input (1X = W) and on the output
    shaft (turning at -W/2): after the start transient has decayed, the 1X components of the
    time response at every lateral DOF, taken over the last two periods of the slower rotor,
    equal ``system unbalance``'s harmonic solution of each excitation (amplitude and phase: the
    complex amplitude) to 1e-4. Newmark (all DOFs) with 0.105 ms steps: its frequency error
    (W h)^2 / 12 = 8e-5 relative keeps the 1X amplitudes within 1.4e-5."""
    box = _gearbox(make)
    ub = [(0, 0, 1e-5, 0.4), (1, 2, 2e-5, 1.3)]
    w, per = 300.0, 100
    slow = 2 * np.pi / 150.0  # the output shaft's period [s]
    tr = machine_transient(
        box, 5 * slow, speed_start=w, unbalance=ub, method="direct", n_output=5 * per + 1, steps_per_output=4
    )
    ref = machine_unbalance(box, [w], ub)
    np.testing.assert_allclose(sorted(ref.factor), [-0.5, 1.0])
    lat = [box.lateral_dof(r, j, a) for r in range(2) for j in range(5) for a in range(2)]
    late = slice(3 * per, 5 * per)  # two whole periods of both excitations
    for g, f in enumerate(ref.factor):
        z = 2 * (tr.q[late][:, lat] * np.exp(-1j * f * w * tr.time[late])[:, None]).mean(0)
        q = ref.Q[g, 0, lat]
        assert np.abs(q).max() > 1e-10
        np.testing.assert_allclose(z, q, rtol=0, atol=1e-4 * np.abs(q).max())


def _coupled(coupling, torsion=True):
    """Motor (4 elements) coupled at its node 4 to a pump (3 elements) at its node 0
    (tests/system/test_coupling.py's train)."""

    def rotor(name, d, length, n_el, disk_node, bearings):
        return {
            "name": name,
            "center": [0.0, 0.0],
            "torsion": torsion,
            "shaft": [{"outer_diameter": d, "length": length, "elements": n_el}],
            "disk": [{"node": disk_node, "mass": 8.0, "Id": 0.04, "Ip": 0.07}],
            "bearing": [{"node": n, "kxx": 2e7, "kyy": 3e7, "cxx": 400.0, "cyy": 500.0} for n in bearings],
        }

    one = rotor("shaft", 0.05, 0.4, 4, 2, (0, 3))
    one["shaft"].append({"outer_diameter": 0.04, "length": 0.3, "elements": 3})
    one["disk"].append({"node": 6, "mass": 8.0, "Id": 0.04, "Ip": 0.07})
    one["bearing"] += [{"node": n, "kxx": 2e7, "kyy": 3e7, "cxx": 400.0, "cyy": 500.0} for n in (5, 7)]
    train = {
        "rotor": [rotor("motor", 0.05, 0.4, 4, 2, (0, 3)), rotor("pump", 0.04, 0.3, 3, 2, (1, 3))],
        "coupling": [{"rotor_a": "motor", "node_a": 4, "rotor_b": "pump", "node_b": 0, **coupling}],
        "drive": {"rotor": "motor", "node": 0},
    }
    return Gearbox.from_mapping(train), Gearbox.from_mapping({"rotor": [one], "drive": {"rotor": "shaft", "node": 0}})


def test_rigid_coupling_train_equals_one_continuous_rotor():
    """Rigid coupling (exact constraint) = the rotor built in one piece (pump node j = node 4 + j):
    a run-up 0 -> 3000 rad/s (gyroscopics and spin acceleration) with unbalances on both rotors
    gives the same motion at every lateral DOF to 1e-6 of its largest value."""
    box, ref = _coupled({"rigid": True})
    kw = {"speed_start": 0.0, "speed_end": 3000.0, "method": "direct", "n_output": 201, "steps_per_output": 2}
    a = machine_transient(box, 0.05, unbalance=[(1, 2, 1e-4, 0.3), (0, 2, 2e-4, 1.0)], **kw)
    b = machine_transient(ref, 0.05, unbalance=[(0, 6, 1e-4, 0.3), (0, 2, 2e-4, 1.0)], **kw)
    lat = [box.lateral_dof(0, j, x) if j <= 4 else box.lateral_dof(1, j - 4, x) for j in range(8) for x in range(4)]
    ref_lat = [ref.lateral_dof(0, j, x) for j in range(8) for x in range(4)]
    scale = np.abs(b.q[:, ref_lat]).max()
    assert scale > 1e-7
    np.testing.assert_allclose(a.q[:, lat], b.q[:, ref_lat], rtol=0, atol=1e-6 * scale)


def test_zero_coupling_lateral_stiffness_isolates_the_motor():
    """Lateral and angular coupling stiffness 0 (torsion still joined, hub masses on both sides):
    an unbalance on the pump leaves every lateral DOF of the motor exactly at rest (lateral and
    torsion do not couple without gears; Newmark's solves keep the decoupled block's zeros)."""
    box, _ = _coupled({"torsional_stiffness": 5e4, "mass": 2.0, "Ip": 0.01, "Id": 0.006})
    tr = machine_transient(
        box, 0.05, speed_start=500.0, speed_end=2500.0, unbalance=[(1, 2, 1e-4, 0.0)], method="direct", n_output=101
    )
    motor = [box.lateral_dof(0, j, x) for j in range(5) for x in range(4)]
    pump = [box.lateral_dof(1, j, x) for j in range(4) for x in range(4)]
    assert np.abs(tr.q[:, pump]).max() > 1e-8
    assert np.all(tr.q[:, motor] == 0.0)


def test_slow_ramp_peaks_after_the_campbell_1x_crossing_by_the_ramp_lag():
    """A run-up 190 -> 320 rad/s through the first critical of a flexibly coupled motor-pump
    train (``system campbell``: motor 1X crossing at 250.54 rad/s, omega_n = 251.33 rad/s,
    zeta = 0.078) peaks after the crossing by the steady-state shift of an unbalance peak,
    omega_n (1 / sqrt(1 - 2 zeta^2) - 1) = 1.55 rad/s, plus the ramp lag. Expected lag: the
    quasi-steady delay of one modal time constant, delta = alpha / (zeta omega_n) (5.09 rad/s at
    alpha = 100 rad/s^2), times a factor between 1 and 2 (measured 1.63 at 100 and 1.52 at
    200 rad/s^2: peaks at 260.4 and 267.6 rad/s); the lag is first order in alpha: behind
    ``system unbalance``'s steady peak (252.9 rad/s) it doubles with alpha (measured 1.96)."""
    from rotaflex.system.modal import campbell

    def rotor(name, d, length, n_el, disk, bearings):
        return {
            "name": name,
            "center": [0.0, 0.0],
            "shaft": [{"outer_diameter": d, "length": length, "elements": n_el}],
            "disk": [disk],
            "bearing": [{"node": n, "kxx": 2e6, "kyy": 2e6, "cxx": 2e3, "cyy": 2e3} for n in bearings],
        }

    box = Gearbox.from_mapping(
        {
            "rotor": [
                rotor("motor", 0.05, 0.8, 4, {"node": 2, "mass": 30.0, "Id": 0.3, "Ip": 0.05}, (0, 4)),
                rotor("pump", 0.04, 0.4, 3, {"node": 2, "mass": 10.0, "Id": 0.05, "Ip": 0.02}, (1, 3)),
            ],
            "coupling": [
                {
                    "rotor_a": "motor",
                    "node_a": 4,
                    "rotor_b": "pump",
                    "node_b": 0,
                    "torsional_stiffness": 1e4,
                    "lateral_stiffness": 1e5,
                    "angular_stiffness": 1e3,
                }
            ],
            "drive": {"rotor": "motor", "node": 0},
        }
    )
    cm = campbell(box, np.linspace(0.0, 600.0, 31), 4, reduce=False)
    first = [c for c in cm.crossings if c["line"] == "motor 1X" and c["speed"] < 400.0]
    cross = min(c["speed"] for c in first)
    k = min(c["mode"] for c in first)
    wn, zeta = cm.modes.wn[0, k], cm.modes.damping_ratio[0, k]
    assert 0.05 < zeta < 0.1
    ub = [(0, 2, 1e-4, 0.0)]
    i = box.lateral_dof(0, 2, 0)
    w0, w1 = 190.0, 320.0
    sweep = np.linspace(w0, w1, 1301)
    q = machine_unbalance(box, sweep, ub).Q[0][:, [i, i + 1]]
    steady = sweep[np.argmax(np.abs(q[:, 0] + 1j * q[:, 1]) + np.abs(q[:, 0] - 1j * q[:, 1]))]
    shift = wn * (1 / np.sqrt(1 - 2 * zeta**2) - 1)
    lags = []
    for alpha in (100.0, 200.0):
        tr = machine_transient(
            box, (w1 - w0) / alpha, speed_start=w0, speed_end=w1, unbalance=ub, n_modes=4, n_output=1301
        )
        peak = tr.speed[np.argmax(np.hypot(tr.q[:, i], tr.q[:, i + 1]))]
        delta = alpha / (zeta * wn)
        assert cross + shift + delta <= peak <= cross + shift + 2 * delta, (alpha, peak, cross, delta)
        lags.append(peak - steady)
    assert 1.7 < lags[1] / lags[0] < 2.3


@pytest.mark.parametrize(
    ("change", "key"),
    [
        ({"mass": [{"rotor": "fan", "node": 1, "magnitude": 1e-4}]}, "transient.mass[0].rotor"),
        ({"probes": [{"rotor": "r", "node": 3}, {"rotor": "r", "node": 9}]}, "transient.probes[1].node"),
        ({"probes": [{"rotor": "fan", "node": 1}]}, "transient.probes[0].rotor"),
        ({"mass": [{"rotor": "r", "node": 9, "magnitude": 1e-4}]}, "transient.mass[0]"),
        ({"large_rotation": [1]}, "transient.large_rotation"),
        ({"n_output": 20_000_000}, "transient.n_output"),  # refused before anything is assembled
        ({"method": "direct", "n_output": 2_000_000, "steps_per_output": 100}, "transient.steps_per_output"),
    ],
)
def test_bad_input_names_the_key(change, key):
    """Unknown rotor or node of a mass or probe, the rotor-only large-rotation keys and a run
    beyond the size limits (the rotor verb's: 1e7 output points, 1e8 integration steps) are
    refused with the key as written in the TOML."""
    _, cfg = _pair({"duration": 0.01, "n_output": 11})
    cfg["transient"].update(change)
    with pytest.raises(InputError) as e:
        system_transient(cfg)
    assert e.value.field.startswith(key), e.value.field


def test_cli_plot_reuses_the_rotor_figures():
    """The machine's figures are the rotor verb's (one function): the time-response panel holds
    each probe's x [um] over time, the speed panel the drive speed in rpm; no layout problem
    (:func:`rotaflex.core.plotting.layout_problems`)."""
    _, cfg = _pair({"speed_rpm": [0.0, 600.0], "duration": 0.02, "n_output": 21, "n_modes": 4})
    res = system_transient(cfg)
    figs = res.plot()
    ds = res.dataset
    lines = figs["time_response"].axes[0].get_lines()
    assert [ln.get_label() for ln in lines] == ["r:1 x", "r:3 x"]
    np.testing.assert_allclose(lines[1].get_ydata(), 1e6 * ds["displacement"].sel(probe="r:3", axis="x").values)
    np.testing.assert_allclose(figs["time_response"].axes[1].get_lines()[0].get_ydata()[-1], 600.0)
    assert "orbit" in figs and "system" in figs
    from rotaflex.core.plotting import layout_problems

    assert not [p for fig in figs.values() for p in layout_problems(fig)]
    assert rpm_to_rad_s(600.0) == pytest.approx(float(ds["speed"][-1]))


@pytest.mark.parametrize("method", ["modal", "direct"])
def test_progress_lines_at_every_tenth(capsys, method):
    """``--progress`` off a terminal: one line per tenth of the simulated time, in order, ending
    at 100 % (the rotor verb's progress, tests/rotor/fe/test_fe_progress.py); nothing without;
    the same response either way."""
    import re

    _, cfg = _pair({"speed_rpm": [0.0, 600.0], "duration": 0.04, "n_output": 41, "n_modes": 4, "method": method})
    quiet = system_transient(copy.deepcopy(cfg), progress=False)
    assert capsys.readouterr().err == ""
    shown = system_transient(copy.deepcopy(cfg), progress=True)
    pct = [int(p) for p in re.findall(r"^transient: (\d+) % \(", capsys.readouterr().err, flags=re.M)]
    assert {p // 10 for p in pct} >= set(range(1, 11))
    assert pct == sorted(pct) and pct[-1] == 100
    np.testing.assert_array_equal(shown.dataset["displacement"].values, quiet.dataset["displacement"].values)
