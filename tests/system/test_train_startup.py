"""Start-up transient of a motor-coupling-pump train: energy balance, steady speed of the motor
curve against the load, passage through the torsional critical of a synchronous motor's
pulsating torque."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rotaflex.core.errors import InputError
from rotaflex.system.case import run_startup
from rotaflex.system.torsion import torsional_model, torsional_modes

CURVE_RPM = [0.0, 1200.0, 1450.0, 1500.0]
CURVE_NM = [300.0, 350.0, 400.0, 0.0]
Q = 150.0 / (1480 * math.pi / 30) ** 2  # N m s^2/rad^2: 150 N m at 1480 rpm


def train(pulsating=0.0, t0=20.0, duration=1.5, damping=4.0, max_frequency_hz=100.0):
    def rotor(name, d, length, disk_node, ip):
        return {
            "name": name,
            "center": [0.0, 0.0],
            "shaft": [{"outer_diameter": d, "length": length, "elements": 2}],
            "disk": [{"node": disk_node, "mass": 20.0, "Id": 0.2, "Ip": ip}],
            "bearing": [{"node": 0, "kxx": 1e8, "kyy": 1e8}, {"node": 2, "kxx": 1e8, "kyy": 1e8}],
        }

    return {
        "rotor": [rotor("motor", 0.06, 0.5, 0, 1.0), rotor("pump", 0.05, 0.4, 2, 0.4)],
        "coupling": [
            {
                "rotor_a": "motor",
                "node_a": 2,
                "rotor_b": "pump",
                "node_b": 0,
                "torsional_stiffness": 2e4,
                "torsional_damping": damping,
            }
        ],
        "drive": {
            "rotor": "motor",
            "node": 0,
            "kind": "torque",
            "curve_speed_rpm": CURVE_RPM,
            "curve_torque": CURVE_NM,
            "pulsating_torque": pulsating,
            "line_frequency_hz": 50.0,
            "poles": 4,
        },
        "load": {"rotor": "pump", "node": 2, "torque": t0, "quadratic": Q},
        "startup": {"duration": duration, "n_out": 3001, "max_frequency_hz": max_frequency_hz},
    }


def steady_speed(t0=20.0):
    """Motor = load on the last segment of the curve: a + b w = t0 + q w^2 (rad/s), by hand."""
    w3, w4 = (x * math.pi / 30 for x in CURVE_RPM[2:])
    b = (CURVE_NM[3] - CURVE_NM[2]) / (w4 - w3)
    a = CURVE_NM[2] - b * w3
    return (b + math.sqrt(b * b - 4 * Q * (t0 - a))) / (2 * Q)


def test_steady_speed_where_motor_torque_equals_load_torque():
    res = run_startup(train(max_frequency_hz=None))  # all modes: the static twist exact
    ds = res.dataset
    want = steady_speed() * 30 / math.pi
    s = res.summary()
    assert s["steady_speed_rpm"]["value"] == pytest.approx(want, rel=1e-10)
    assert float(ds["drive_speed_rpm"][-1]) == pytest.approx(want, rel=1e-7)
    # both rotors at the same speed (a coupling), the motor torque equals the load torque at the end
    assert float(ds["rotor_speed"][-1, 1]) == pytest.approx(float(ds["rotor_speed"][-1, 0]), rel=1e-7)
    assert float(ds["motor_torque"][-1]) == pytest.approx(20.0 + Q * steady_speed() ** 2, rel=1e-6)
    # the coupling carries the load torque in the steady state
    assert float(ds["coupling_torque"][-1, 0]) == pytest.approx(float(ds["load_torque"][-1]), rel=1e-6)


@pytest.mark.parametrize("pulsating", [0.0, 150.0])
def test_energy_balance(pulsating):
    """E_kin + E_pot = W_motor - W_load - W_damping: with the work integrated along the states
    (to round-off), and with the work from the written torques and speeds by the trapezoidal rule
    (to its sampling error); all torsional modes kept."""
    res = run_startup(train(pulsating, duration=0.6, max_frequency_hz=None))
    ds = res.dataset
    e = ds["energy"].values.sum(1)
    w = ds["work"].values
    assert np.max(np.abs(e - (w[:, 0] - w[:, 1] - w[:, 2]))) < 1e-9 * np.max(w[:, 0])
    assert res.summary()["energy_balance_error"]["value"] < 1e-9
    t = ds["time"].values
    speed = ds["rotor_speed"].values  # node 0 of each rotor: the motor inertia, the pump's hub
    pump = ds["twist"].values[:, -1]  # the impeller node, relative to the rigid rotation
    n_imp = speed[:, 0] + np.gradient(pump, t)
    p_m = ds["motor_torque"].values * speed[:, 0]
    p_l = ds["load_torque"].values * n_imp
    w_m = np.concatenate([[0], np.cumsum(0.5 * (p_m[1:] + p_m[:-1]) * np.diff(t))])
    w_l = np.concatenate([[0], np.cumsum(0.5 * (p_l[1:] + p_l[:-1]) * np.diff(t))])
    np.testing.assert_allclose(w_m[-1], w[-1, 0], rtol=1e-4)
    np.testing.assert_allclose(w_l[-1], w[-1, 1], rtol=1e-3)
    if pulsating == 0.0:  # the motor's work ends as the rotation's kinetic energy plus losses
        jt = 1.0 + 0.4 + sum(math.pi / 32 * d**4 * length * 7850.0 for d, length in ((0.06, 0.5), (0.05, 0.4)))
        assert ds["energy"].values[-1, 0] == pytest.approx(0.5 * jt * speed[-1, 0] ** 2, rel=1e-3)


def test_synchronous_pulsation_peaks_past_the_torsional_critical():
    """The pulsating torque at 2 x slip frequency, 2 f_line (1 - n / n_sync), sweeps down from
    100 Hz and meets the first torsional mode at the hand-computed speed n_x. The coupling's
    dynamic torque peaks after it (a downward sweep's response lags: here at an excitation
    frequency within 25 % below f_n) and stands well above the response away from the mode."""
    from rotaflex.system.model import Gearbox

    cfg = train(pulsating=150.0, duration=1.0, damping=20.0)
    fn = torsional_modes(torsional_model(Gearbox.from_mapping(cfg)))[0][0] / (2 * math.pi)
    n_cross = 1500.0 * (1 - fn / 100.0)  # rpm, the line 2 f_line (1 - n / 1500) at f_n
    n_lag = 1500.0 * (1 - 0.75 * fn / 100.0)
    ds = run_startup(cfg).dataset
    ct = ds["coupling_torque"].values[:, 0] - ds["load_torque"].values  # dynamic part
    n = ds["drive_speed_rpm"].values
    i = int(np.argmax(np.abs(ct) * (n < 1440)))  # before the pull-in, where the pulsation runs
    assert n_cross < n[i] < n_lag
    away = np.abs(ct[(n > 100) & (n < 0.5 * n_cross)]).max()
    assert np.abs(ct[i]) > 2 * away


def test_bad_curve_names_the_key():
    cfg = train()
    cfg["drive"]["curve_torque"] = [10.0, 350.0, 400.0, 0.0]  # below the load's 20 N m at rest
    with pytest.raises(InputError) as e:
        run_startup(cfg)
    assert e.value.field == "drive.curve_torque"
    cfg = train()
    cfg["drive"]["curve_speed_rpm"] = [0.0, 1200.0, 1100.0, 1500.0]
    with pytest.raises(InputError) as e:
        run_startup(cfg)
    assert e.value.field == "drive.curve_speed_rpm"


def test_geared_train_runs_up_to_the_referred_balance(make):
    """Motor on the 20-tooth pinion shaft, 100 N m + viscous 0.5 N m s/rad on the 40-tooth wheel
    shaft: both turn in their senses at 1 : 1/2, and the drive settles where the curve meets the
    load torque referred through the mesh, 2 (1100 - n) = (100 + 0.5 w_out) / 2, by hand."""
    cfg = make()
    cfg["drive"].update(curve_speed_rpm=[0.0, 1000.0, 1100.0], curve_torque=[200.0, 200.0, 0.0])
    cfg["load"]["damping"] = 0.5
    cfg["startup"] = {"duration": 0.2, "max_frequency_hz": 1000.0}
    res = run_startup(cfg)
    ds = res.dataset
    # 200 (1100 - n) / 100 = 0.5 (100 + 0.5 (n / 2) pi / 30)
    n = (2200.0 - 50.0) / (2.0 + 0.125 * math.pi / 30)
    assert float(ds["drive_speed_rpm"][-1]) == pytest.approx(n, rel=1e-7)
    w_in, w_out = ds["rotor_speed"].values[-1]
    assert w_out == pytest.approx(0.5 * w_in, rel=1e-7)
    assert res.summary()["energy_balance_error"]["value"] < 1e-7
