"""``rotaflex system unbalance``: the rotor verb's one harmonic solve on a machine's matrices."""

from __future__ import annotations

import copy
import json

import numpy as np
import pytest

from rotaflex.core.errors import InputError
from rotaflex.core.units import rpm_to_rad_s
from rotaflex.rotor.fe.verbs_response import run_unbalance as rotor_unbalance
from rotaflex.system.case import run_unbalance as system_unbalance
from rotaflex.system.modal import campbell
from rotaflex.system.model import Gearbox
from rotaflex.system.unbalance import machine_unbalance

#: tabulated, cross-coupled bearing (coefficients vary with speed: the machine must take each
#: rotor's bearings at that rotor's speed, as rotor/fe does)
_TABLE = {
    "speed_rpm": [0.0, 6000.0],
    "kxx": [1.0e6, 3.0e6],
    "kyy": [1.5e6, 2.5e6],
    "kxy": [0.0, 4.0e5],
    "kyx": [0.0, -4.0e5],
    "cxx": [3.0e3, 2.0e3],
    "cyy": [3.5e3, 2.5e3],
}
_SHAFT = [{"outer_diameter": 0.05, "length": 1.5, "elements": 6}]
_DISKS = [{"node": 2, "mass": 30.0, "Id": 0.2, "Ip": 0.35}, {"node": 4, "mass": 45.0, "Id": 0.3, "Ip": 0.6}]
_MASSES = [{"node": 4, "magnitude": 1e-4, "phase_deg": 0.0}, {"node": 2, "magnitude": 5e-5, "phase_deg": 120.0}]
_SETTINGS = {"speed_rpm": [200.0, 6000.0], "n_speeds": 120, "operating_speed_rpm": 3000.0}


def test_one_rotor_machine_gives_the_rotor_verbs_response():
    """A machine of one rotor (speed-dependent cross-coupled bearings, gyroscopics) through
    ``system unbalance`` equals ``rotor unbalance`` of the same rotor: amplitudes and phases at
    every probe and speed to 1e-9, and the same peaks with AF and API margins."""
    rotor_cfg = {
        "shaft": _SHAFT,
        "disk": _DISKS,
        "bearing": {"left": {"node": 0, **_TABLE}, "right": {"node": 6, **_TABLE}},
        "unbalance": {**_SETTINGS, "probes": [2, 4], "mass": _MASSES},
    }
    machine_cfg = {
        "rotor": [
            {
                "name": "r",
                "center": [0.0, 0.0],
                "shaft": _SHAFT,
                "disk": _DISKS,
                "bearing": [{"node": 0, **_TABLE}, {"node": 6, **_TABLE}],
            }
        ],
        "drive": {"rotor": "r", "node": 0},
        "unbalance": {
            **_SETTINGS,
            "probes": [{"rotor": "r", "node": 2}, {"rotor": "r", "node": 4}],
            "mass": [{"rotor": "r", **m} for m in _MASSES],
        },
    }
    a = rotor_unbalance(copy.deepcopy(rotor_cfg)).dataset
    b = system_unbalance(copy.deepcopy(machine_cfg)).dataset.isel(excitation=0)
    scale = float(np.abs(a["major_axis"]).max())
    assert scale > 1e-6  # a resonance in the range: the comparison is not of zeros
    for v in ("x_real", "x_imag", "y_real", "y_imag", "major_axis"):
        np.testing.assert_allclose(b[v].values, a[v].values, rtol=0, atol=1e-9 * scale)

    pa, pb = json.loads(a.attrs["peaks"]), json.loads(b.attrs["peaks"])
    assert len(pa) == len(pb) >= 1
    for p, q in zip(pa, pb, strict=True):
        for k in ("speed", "af", "sm_percent", "sm_required_percent"):
            assert q[k] == pytest.approx(p[k], rel=1e-9, nan_ok=True)


def _rotor(name, d, length, n_el, disk_node, bearings):
    return {
        "name": name,
        "center": [0.0, 0.0],
        "shaft": [{"outer_diameter": d, "length": length, "elements": n_el}],
        "disk": [{"node": disk_node, "mass": 8.0, "Id": 0.04, "Ip": 0.07}],
        "bearing": [{"node": n, "kxx": 2e7, "kyy": 3e7, "cxx": 400.0, "cyy": 500.0} for n in bearings],
    }


def _train(coupling):
    """Motor (4 elements) coupled at its node 4 to a pump (3 elements) at its node 0
    (tests/system/test_coupling.py's train)."""
    return {
        "rotor": [_rotor("motor", 0.05, 0.4, 4, 2, (0, 3)), _rotor("pump", 0.04, 0.3, 3, 2, (1, 3))],
        "coupling": [{"rotor_a": "motor", "node_a": 4, "rotor_b": "pump", "node_b": 0, **coupling}],
        "drive": {"rotor": "motor", "node": 0},
    }


def test_rigid_coupling_train_equals_one_continuous_rotor():
    """Rigid coupling (exact constraint) = the rotor built in one piece (pump node j = node 4 + j):
    the response to unbalances on both rotors agrees at every lateral DOF to 1e-6."""
    one = _rotor("shaft", 0.05, 0.4, 4, 2, (0, 3))
    one["shaft"].append({"outer_diameter": 0.04, "length": 0.3, "elements": 3})
    one["disk"].append({"node": 6, "mass": 8.0, "Id": 0.04, "Ip": 0.07})
    one["bearing"] += [{"node": n, "kxx": 2e7, "kyy": 3e7, "cxx": 400.0, "cyy": 500.0} for n in (5, 7)]
    box = Gearbox.from_mapping(_train({"rigid": True}))
    ref = Gearbox.from_mapping({"rotor": [one], "drive": {"rotor": "shaft", "node": 0}})
    speeds = rpm_to_rad_s(np.linspace(500.0, 30000.0, 60))
    a = machine_unbalance(box, speeds, [(1, 2, 1e-4, 0.3), (0, 2, 2e-4, 1.0)]).Q[0]
    b = machine_unbalance(ref, speeds, [(0, 6, 1e-4, 0.3), (0, 2, 2e-4, 1.0)]).Q[0]
    lat = [box.lateral_dof(0, j, x) if j <= 4 else box.lateral_dof(1, j - 4, x) for j in range(8) for x in range(4)]
    ref_lat = [ref.lateral_dof(0, j, x) for j in range(8) for x in range(4)]
    scale = np.abs(b[:, ref_lat]).max()
    np.testing.assert_allclose(a[:, lat], b[:, ref_lat], rtol=0, atol=1e-6 * scale)


def test_zero_coupling_lateral_stiffness_isolates_the_rotors():
    """Lateral and angular coupling stiffness 0 (torsion still joined): an unbalance on the motor
    moves no lateral DOF of the pump (lateral and torsion do not couple without gears)."""
    box = Gearbox.from_mapping(_train({"torsional_stiffness": 5e4, "mass": 2.0, "Ip": 0.01, "Id": 0.006}))
    speeds = rpm_to_rad_s(np.linspace(500.0, 30000.0, 60))
    Q = machine_unbalance(box, speeds, [(0, 2, 1e-4, 0.0)]).Q[0]
    motor = [box.lateral_dof(0, j, x) for j in range(5) for x in range(4)]
    pump = [box.lateral_dof(1, j, x) for j in range(4) for x in range(4)]
    assert np.abs(Q[:, motor]).max() > 1e-6
    assert np.abs(Q[:, pump]).max() <= 1e-14 * np.abs(Q[:, motor]).max()


def test_peaks_at_the_campbell_1x_crossings():
    """Each rated response peak of the flexibly coupled train lies at a forward mode's crossing
    of the 1X line in the machine's Campbell diagram, within one step of the speed grid."""
    cfg = _train({"torsional_stiffness": 5e4, "lateral_stiffness": 2e6, "angular_stiffness": 5e3})
    box = Gearbox.from_mapping(cfg)
    speeds = rpm_to_rad_s(np.linspace(500.0, 40000.0, 400))
    step = speeds[1] - speeds[0]
    c = campbell(box, speeds[::4], n_modes=10, harmonics=(), reduce=False)
    x1 = np.array([x["speed"] for x in c.crossings if x["line"] == "motor 1X"])
    ds = system_unbalance(
        {
            **copy.deepcopy(cfg),
            "unbalance": {
                "speed_rpm": [500.0, 40000.0],
                "n_speeds": 400,
                "mass": [
                    {"rotor": "motor", "node": 2, "magnitude": 1e-4},
                    {"rotor": "pump", "node": 2, "magnitude": 1e-4},
                ],
                "probes": [{"rotor": "motor", "node": 2}, {"rotor": "pump", "node": 2}],
            },
        }
    ).dataset

    rated = [p["speed"] for p in json.loads(ds.attrs["peaks"]) if p["kind"] == "resonance"]
    assert len(rated) >= 2
    for s in rated:
        assert np.min(np.abs(x1 - s)) <= step, (s, x1)


@pytest.mark.parametrize(
    ("mass", "key"),
    [
        ({"rotor": "fan", "node": 2, "magnitude": 1e-4}, "unbalance.mass[1].rotor"),
        ({"rotor": "pump", "node": 9, "magnitude": 1e-4}, "unbalance.mass[1].node"),
        ({"node": 2, "magnitude": 1e-4}, "unbalance.mass[1].rotor"),
    ],
)
def test_bad_unbalance_names_the_key(mass, key):
    cfg = _train({"rigid": True})
    cfg["unbalance"] = {"mass": [{"rotor": "motor", "node": 1, "magnitude": 1e-4}, mass], "n_speeds": 5}
    with pytest.raises(InputError) as e:
        system_unbalance(cfg)
    assert e.value.field == key


def test_bode_figure_draws_the_dataset():
    """``plot()`` gives the rotor verb's Bode figure: its major-axis curves are the dataset's
    peak-to-peak major axis [um] vs drive speed [rpm], one curve per probe."""
    cfg = _train({"torsional_stiffness": 5e4, "lateral_stiffness": 2e6, "angular_stiffness": 5e3})
    cfg["unbalance"] = {
        "speed_rpm": [500.0, 20000.0],
        "n_speeds": 40,
        "mass": [{"rotor": "pump", "node": 2, "magnitude": 1e-4}],
        "probes": [{"rotor": "motor", "node": 2}, {"rotor": "pump", "node": 2}],
    }
    res = system_unbalance(cfg)
    fig = res.plot()["bode"]
    ds = res.dataset.isel(excitation=0)
    lines = {ln.get_label(): ln for ln in fig.axes[0].get_lines()}
    for j, p in enumerate(ds["probe"].values):
        ln = lines[f"node {p}: major axis"]
        np.testing.assert_allclose(ln.get_xdata(), ds["speed_rpm"].values, rtol=1e-12)
        np.testing.assert_allclose(ln.get_ydata(), 2e6 * ds["major_axis"].values[:, j], rtol=1e-12)
