"""``rotaflex system frf``: the rotor verb's one FRF solve on a machine's matrices."""

from __future__ import annotations

import copy

import numpy as np
import pytest

from rotaflex.core.errors import InputError
from rotaflex.core.units import rpm_to_rad_s
from rotaflex.rotor.fe.frf import half_power
from rotaflex.rotor.fe.verbs import run_frf as rotor_frf
from rotaflex.system.case import run_frf as system_frf
from rotaflex.system.frf import machine_frf
from rotaflex.system.modal import modal
from rotaflex.system.model import Gearbox

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
_FREQ = {"speed_rpm": 3000.0, "frequency_hz": [1.0, 60.0], "n_frequencies": 400}


def test_one_rotor_machine_gives_the_rotor_verbs_frf():
    """A machine of one rotor (speed-dependent cross-coupled bearings, gyroscopics at 3000 rpm)
    through ``system frf`` equals ``rotor frf`` of the same rotor: real and imaginary parts of
    every pair at every frequency to 1e-9 of the largest, the same half-power peaks."""
    rotor_cfg = {
        "shaft": _SHAFT,
        "disk": _DISKS,
        "bearing": {"left": {"node": 0, **_TABLE}, "right": {"node": 6, **_TABLE}},
        "frf": {
            **_FREQ,
            "kind": "mobility",
            "pair": [
                {"input_node": 4, "input_direction": "x"},
                {"input_node": 4, "input_direction": "x", "output_node": 2, "output_direction": "y"},
                {"input_node": 2, "input_direction": "theta_y", "output_node": 4, "output_direction": "x"},
            ],
        },
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
        "frf": {
            **_FREQ,
            "kind": "mobility",
            "inputs": [{"rotor": "r", "node": 4, "direction": "x"}, {"node": 2, "direction": "theta_y"}],
            "outputs": [{"rotor": "r", "node": 4, "direction": "x"}, {"rotor": "r", "node": 2, "direction": "y"}],
        },
    }
    a = rotor_frf(copy.deepcopy(rotor_cfg)).dataset
    b = system_frf(copy.deepcopy(machine_cfg)).dataset
    # machine pairs: output fastest -> (4x/4x, 2y/4x, 4x/2ty, 2y/2ty); the rotor's three of them
    H_a = a["H_real"].values + 1j * a["H_imag"].values
    H_b = (b["H_real"].values + 1j * b["H_imag"].values)[:, [0, 1, 2]]
    scale = np.abs(H_a).max()
    assert scale > 0
    np.testing.assert_allclose(H_b, H_a, rtol=0, atol=1e-9 * scale)
    pa, pb = half_power(a["frequency"].values, np.abs(H_a[:, 0])), half_power(b["frequency"].values, np.abs(H_b[:, 0]))
    assert len(pa) == len(pb) >= 1
    for p, q in zip(pa, pb, strict=True):
        assert q["frequency"] == pytest.approx(p["frequency"], rel=1e-9)
        assert q["zeta"] == pytest.approx(p["zeta"], rel=1e-9)


def _rotor(name, d, length, n_el, disk_node, bearings):
    return {
        "name": name,
        "center": [0.0, 0.0],
        "shaft": [{"outer_diameter": d, "length": length, "elements": n_el}],
        "disk": [{"node": disk_node, "mass": 8.0, "Id": 0.04, "Ip": 0.07}],
        "bearing": [{"node": n, "kxx": 2e7, "kyy": 3e7, "cxx": 400.0, "cyy": 500.0} for n in bearings],
    }


def _train(coupling, drive_kind=None):
    """Motor (4 elements) coupled at its node 4 to a pump (3 elements) at its node 0
    (tests/system/test_coupling.py's train)."""
    drive = {"rotor": "motor", "node": 0} | ({"kind": drive_kind} if drive_kind else {})
    return {
        "rotor": [_rotor("motor", 0.05, 0.4, 4, 2, (0, 3)), _rotor("pump", 0.04, 0.3, 3, 2, (1, 3))],
        "coupling": [{"rotor_a": "motor", "node_a": 4, "rotor_b": "pump", "node_b": 0, **coupling}],
        "drive": drive,
    }


_FLEX = {"torsional_stiffness": 5e4, "lateral_stiffness": 2e6, "angular_stiffness": 5e3, "torsional_damping": 2.0}
_W = 2 * np.pi * np.linspace(5.0, 900.0, 300)


def test_reciprocity_at_zero_speed():
    """At rest with symmetric bearings, shafts and coupling the dynamic stiffness is symmetric,
    so H_ij = H_ji (Maxwell-Betti) over DOFs of both rotors, lateral, tilt and twist, to
    round-off; at 20 000 rpm the gyroscopic moments break it (the check can fail)."""
    box = Gearbox.from_mapping(_train(_FLEX, "torque"))
    dofs = [
        box.lateral_dof(0, 2, 0),
        box.lateral_dof(0, 1, 3),
        box.lateral_dof(1, 2, 0),
        box.lateral_dof(1, 2, 2),
        box.torsion_dof(0, 2),
        box.torsion_dof(1, 2),
    ]
    H = machine_frf(box, _W, 0.0, dofs).H
    scale = np.abs(H).max()
    assert np.abs(H - H.transpose(0, 2, 1)).max() <= 1e-12 * scale
    Hs = machine_frf(box, _W, rpm_to_rad_s(20000.0), dofs).H
    assert np.abs(Hs - Hs.transpose(0, 2, 1)).max() > 1e-4 * np.abs(Hs).max()


def test_zero_coupling_lateral_stiffness_gives_no_lateral_transfer():
    """Lateral and angular coupling stiffness 0 (torsion still joined): a force or moment on the
    motor moves no lateral DOF of the pump (round-off), while the twist still passes."""
    box = Gearbox.from_mapping(_train({"torsional_stiffness": 5e4, "mass": 2.0, "Ip": 0.01, "Id": 0.006}, "torque"))
    ins = [box.lateral_dof(0, 2, 0), box.lateral_dof(0, 2, 3), box.torsion_dof(0, 2)]
    motor = [box.lateral_dof(0, j, x) for j in range(5) for x in range(4)]
    pump = [box.lateral_dof(1, j, x) for j in range(4) for x in range(4)]
    H = machine_frf(box, _W, rpm_to_rad_s(3000.0), ins, motor + pump + [box.torsion_dof(1, 2)]).H
    assert np.abs(H[:, : len(motor), :2]).max() > 1e-9
    assert np.abs(H[:, len(motor) : -1, :]).max() <= 1e-14 * np.abs(H[:, : len(motor), :2]).max()
    assert np.abs(H[:, -1, 2]).max() > 1e-6  # twist of the pump per unit motor torque


def test_rigid_coupling_train_equals_one_continuous_rotor():
    """Rigid coupling (exact constraint) = the rotor built in one piece (pump node j = node 4 + j):
    every lateral DOF's receptance to forces on both rotors agrees to 1e-6 at 12 000 rpm."""
    one = _rotor("shaft", 0.05, 0.4, 4, 2, (0, 3))
    one["shaft"].append({"outer_diameter": 0.04, "length": 0.3, "elements": 3})
    one["disk"].append({"node": 6, "mass": 8.0, "Id": 0.04, "Ip": 0.07})
    one["bearing"] += [{"node": n, "kxx": 2e7, "kyy": 3e7, "cxx": 400.0, "cyy": 500.0} for n in (5, 7)]
    box = Gearbox.from_mapping(_train({"rigid": True}))
    ref = Gearbox.from_mapping({"rotor": [one], "drive": {"rotor": "shaft", "node": 0}})
    lat = [box.lateral_dof(0, j, x) if j <= 4 else box.lateral_dof(1, j - 4, x) for j in range(8) for x in range(4)]
    ref_lat = [ref.lateral_dof(0, j, x) for j in range(8) for x in range(4)]
    speed = rpm_to_rad_s(12000.0)
    a = machine_frf(box, _W, speed, [box.lateral_dof(1, 2, 0), box.lateral_dof(0, 2, 1)], lat).H
    b = machine_frf(ref, _W, speed, [ref.lateral_dof(0, 6, 0), ref.lateral_dof(0, 2, 1)], ref_lat).H
    np.testing.assert_allclose(a, b, rtol=0, atol=1e-6 * np.abs(b).max())


def test_half_power_peaks_at_the_machines_modal_frequencies():
    """Each half-power peak of direct receptances of the flexibly coupled train at 6000 rpm (motor
    disk x, pump disk y, pump twist) lies at a damped natural frequency of ``system modal`` at
    that speed within one grid step (0.75 Hz); where the mode is isolated (no other mode within
    three half-power bandwidths) the half-power damping ratio is the mode's ``-Re(lambda)/|lambda|``
    within 5 %. (A DOF where two modes a few bandwidths apart both respond, e.g. the pump's x at
    its node 3, has its peaks pulled by the neighbour: 14.6 rad/s off at 2635 rad/s.)"""
    box = Gearbox.from_mapping(_train(_FLEX, "torque"))
    speed = rpm_to_rad_s(6000.0)
    w = 2 * np.pi * np.linspace(5.0, 900.0, 1200)
    lam = modal(box, speed, n_modes=20).eigenvalue[0]
    wd, zeta = np.abs(lam.imag), -lam.real / np.abs(lam)
    ins = [box.lateral_dof(0, 2, 0), box.lateral_dof(1, 2, 1), box.torsion_dof(1, 2)]
    H = machine_frf(box, w, speed, ins).H
    found = isolated = 0
    for j in range(len(ins)):
        for p in half_power(w, np.abs(H[:, j, j])):
            found += 1
            k = np.argmin(np.abs(wd - p["frequency"]))
            assert abs(wd[k] - p["frequency"]) <= w[1] - w[0], (p["frequency"], wd)
            if np.sort(np.abs(wd - wd[k]))[1] > 3 * 2 * zeta[k] * wd[k]:
                isolated += 1
                assert p["zeta"] == pytest.approx(zeta[k], rel=0.05)
    assert found >= 4
    assert isolated >= 3


@pytest.mark.parametrize(
    ("dof", "key"),
    [
        ({"rotor": "fan", "node": 2}, "frf.inputs[1].rotor"),
        ({"rotor": "pump", "node": 9}, "frf.inputs[1].node"),
        ({"node": 2}, "frf.inputs[1].rotor"),
        ({"rotor": "pump", "node": 2, "direction": "z"}, "frf.inputs[1].direction"),
    ],
)
def test_bad_dof_names_the_key(dof, key):
    cfg = _train({"rigid": True})
    cfg["frf"] = {"inputs": [{"rotor": "motor", "node": 1}, dof], "n_frequencies": 5}
    with pytest.raises(InputError) as e:
        system_frf(cfg)
    assert e.value.field == key


def test_figures_draw_the_dataset():
    """``plot()`` gives the rotor verb's Bode figure: one |H| curve per (output, input) pair, the
    dataset's amplitude vs frequency [Hz]."""
    cfg = _train(_FLEX, "torque")
    cfg["frf"] = {
        "speed_rpm": 3000.0,
        "frequency_hz": [5.0, 500.0],
        "n_frequencies": 50,
        "inputs": [{"rotor": "motor", "node": 2, "direction": "x"}],
        "outputs": [{"rotor": "motor", "node": 2, "direction": "x"}, {"rotor": "pump", "node": 2, "direction": "x"}],
    }
    res = system_frf(cfg)
    figs = res.plot()
    ds = res.dataset
    lines = {ln.get_label(): ln for ln in figs["frf_bode"].axes[0].get_lines()}
    assert list(ds["pair"].values) == ["motor:2 x / motor:2 Fx", "pump:2 x / motor:2 Fx"]
    for j, lab in enumerate(ds["pair"].values):
        np.testing.assert_allclose(lines[lab].get_xdata(), ds["frequency_hz"].values, rtol=1e-12)
        np.testing.assert_allclose(lines[lab].get_ydata(), ds["amplitude"].values[:, j], rtol=1e-12)
