"""``rotaflex system stability``: the rotor verb's API 617 analysis on a machine's matrices."""

from __future__ import annotations

import copy

import numpy as np
import pytest

from rotaflex.core.errors import InputError
from rotaflex.rotor.fe.verbs_stability import run_stability as rotor_stability
from rotaflex.system.case import run_stability as system_stability

_SEAL = {
    "radius": 0.05,
    "length": 0.03,
    "clearance": 0.3e-3,
    "inlet_pressure": 4.0e6,
    "outlet_pressure": 1.0e6,
    "density": 920.0,
    "viscosity": 1.8e-4,
}


def _bearings(nodes, k=2e7, c=800.0, kxy=2e6):
    """Plain bearings with a destabilising cross-coupling (as a fixed-geometry film has)."""
    return [{"node": n, "kxx": k, "kyy": 1.5 * k, "kxy": kxy, "kyx": -kxy, "cxx": c, "cyy": c} for n in nodes]


def _rotor(name, d, length, n_el, disk_node, bearings, **bearing):
    return {
        "name": name,
        "center": [0.0, 0.0],
        "shaft": [{"outer_diameter": d, "length": length, "elements": n_el}],
        "disk": [{"node": disk_node, "mass": 8.0, "Id": 0.04, "Ip": 0.07}],
        "bearing": _bearings(bearings, **bearing),
    }


def _alone(rotor: dict, stability: dict) -> dict:
    """The rotor verb's case of one machine rotor (bearings as named tables)."""
    bearing = {b.pop("name", f"b{i}"): b for i, b in enumerate(copy.deepcopy(rotor["bearing"]))}
    return {"shaft": rotor["shaft"], "disk": rotor["disk"], "bearing": bearing, "stability": stability}


_COMPRESSOR = {
    "speed_rpm": 9000.0,
    "machine": "centrifugal_compressor",
    "location": "stages",
    "stage": [{"power": 3.0e5, "diameter": 0.3, "width": 0.01, "density_ratio": 1.4, "node": 2}],
    "n_points": 5,
}


def test_one_rotor_machine_gives_the_rotor_verbs_levels():
    """A machine of one rotor (cross-coupled bearings, a liquid seal, gyroscopics at the MCS)
    gives ``rotor stability``'s Level II log decrements of every case and Level I's Q_0, sweep
    and log dec at Q_A to 1e-9."""
    r = _rotor("c", 0.06, 0.8, 6, 3, (0, 6))
    r["disk"].append({"node": 2, "mass": 5.0, "Id": 0.02, "Ip": 0.03})
    r["bearing"].append({"name": "eye", "node": 2, "liquid_seal": _SEAL})
    spec = {**_COMPRESSOR, "mean_density": 20.0}
    a = rotor_stability(_alone(r, copy.deepcopy(spec))).dataset
    b = system_stability({"rotor": [r], "drive": {"rotor": "c", "node": 0}, "stability": spec}).dataset
    assert len(a["case"]) == len(b["case"]) == 6  # bearings, + seal, + Q_A, - seal, - Q_A, all
    np.testing.assert_allclose(b["log_dec_level2"], a["log_dec_level2"], rtol=0, atol=1e-9)
    np.testing.assert_allclose(b["frequency_level2"], a["frequency_level2"], rtol=1e-9)
    np.testing.assert_allclose(b["log_dec_level1"], a["log_dec_level1"], rtol=0, atol=1e-9)
    for key in ("q_a", "q_0", "csr"):
        assert float(b[key]) == pytest.approx(float(a[key]), rel=1e-9)
    assert 0 < float(a["q_0"]) < np.inf


def test_uncoupled_train_has_the_smaller_log_dec_of_its_rotors():
    """A coupling without lateral and angular stiffness leaves the two rotors' lateral motions
    independent: the machine's Level II log dec is the smaller of the two rotors' own (rotor
    verb), here the one of the rotor whose first forward mode is the higher, so the lowest
    machine mode alone would not give it."""
    a = _rotor("motor", 0.05, 0.4, 4, 2, (0, 3), c=150.0, kxy=4e6)
    b = _rotor("pump", 0.04, 0.5, 4, 2, (0, 4), c=3000.0)
    spec = {"speed_rpm": 6000.0, "machine": "pump"}
    machine = {
        "rotor": [a, b],
        "coupling": [{"rotor_a": "motor", "node_a": 4, "rotor_b": "pump", "node_b": 0, "torsional_stiffness": 1e4}],
        "drive": {"rotor": "motor", "node": 0},
        "stability": spec,
    }
    own = [rotor_stability(_alone(x, dict(spec))).dataset for x in (a, b)]
    ld = [float(d["log_dec_level2"][-1]) for d in own]
    wd = [float(d["frequency_level2"][-1]) for d in own]
    assert np.argmin(ld) == np.argmax(wd)  # the weaker rotor's mode is not the machine's lowest
    got = system_stability(machine).dataset
    assert float(got["log_dec_level2"][-1]) == pytest.approx(min(ld), abs=1e-9)
    # each rotor's own first forward mode in the machine is the one it has alone
    np.testing.assert_allclose(got["log_dec_rotor"], ld, rtol=0, atol=1e-9)
    np.testing.assert_allclose(got["frequency_rotor"], wd, rtol=1e-9)


def _train_rigid(c=800.0):
    a = _rotor("motor", 0.05, 0.4, 4, 2, (0, 3), c=c)
    b = _rotor("pump", 0.04, 0.3, 3, 2, (1, 3), c=c)
    return {
        "rotor": [a, b],
        "coupling": [{"rotor_a": "motor", "node_a": 4, "rotor_b": "pump", "node_b": 0, "rigid": True}],
        "drive": {"rotor": "motor", "node": 0},
    }


def _one_piece(c=800.0):
    """The rigid train as one rotor: pump node j is node 4 + j."""
    a = _rotor("shaft", 0.05, 0.4, 4, 2, (0, 3, 5, 7), c=c)
    a["shaft"].append({"outer_diameter": 0.04, "length": 0.3, "elements": 3})
    a["disk"].append({"node": 6, "mass": 8.0, "Id": 0.04, "Ip": 0.07})
    return a


def test_rigid_coupling_train_equals_one_continuous_rotor():
    """Exact constraint: Level II and Level I of the train (Q_A at the pump's impeller, lightly
    damped bearings so that Q_0 is finite) equal the rotor verb's on the rotor built in one piece
    (the impeller at its node 6) to 1e-9."""
    stage = {**_COMPRESSOR["stage"][0], "node": 2}
    spec = {**_COMPRESSOR, "speed_rpm": 6000.0, "stage": [stage], "rotor": "pump"}
    got = system_stability({**_train_rigid(c=100.0), "stability": spec}).dataset
    one = {**spec, "stage": [{**stage, "node": 6}]}
    one.pop("rotor")
    ref = rotor_stability(_alone(_one_piece(c=100.0), one)).dataset
    np.testing.assert_allclose(got["log_dec_level2"], ref["log_dec_level2"], rtol=0, atol=1e-9)
    np.testing.assert_allclose(got["log_dec_level1"], ref["log_dec_level1"], rtol=0, atol=1e-9)
    assert 0 < float(ref["q_0"]) < np.inf
    assert float(got["q_0"]) == pytest.approx(float(ref["q_0"]), rel=1e-9)


def test_anticipated_cross_coupling_lowers_the_log_dec():
    """Q_A (k_xy = Q, k_yx = -Q) drives forward whirl: at the named rotor's stage it lowers the
    first forward log dec (Level II 'bearings + Q_A' below 'bearings'; Level I falls with Q)."""
    a = _rotor("motor", 0.05, 0.4, 4, 2, (0, 4), kxy=0.0)
    b = _rotor("comp", 0.04, 0.5, 4, 2, (0, 4), kxy=0.0)
    spec = {**_COMPRESSOR, "rotor": "comp"}
    machine = {
        "rotor": [a, b],
        "coupling": [
            {"rotor_a": "motor", "node_a": 4, "rotor_b": "comp", "node_b": 0, "torsional_stiffness": 1e4}
            | {"lateral_stiffness": 1e6, "angular_stiffness": 1e4}
        ],
        "drive": {"rotor": "motor", "node": 0},
        "stability": spec,
    }
    ds = system_stability(machine).dataset
    ld = dict(zip(ds["case"].values, ds["log_dec_level2"].values, strict=True))
    assert ld["bearings + Q_A"] < ld["bearings"]
    assert np.all(np.diff(ds["log_dec_level1"].values) < 0)


@pytest.mark.parametrize("name", ["fan", None])
def test_unknown_or_missing_rotor_names_the_key(name):
    spec = {**_COMPRESSOR, "rotor": name} if name else dict(_COMPRESSOR)
    with pytest.raises(InputError) as err:
        system_stability({**_train_rigid(), "stability": spec})
    assert err.value.field == "stability.rotor"


def test_magnetic_bearings_at_the_modes_own_frequency():
    """Magnetic bearings (frequency-dependent: each rotor's elements at the mode's damped
    frequency, iterated): a one-rotor machine gives the rotor verb's Level II to 1e-9."""
    amb = {
        "k_i": 200.0,
        "k_s": 8.0e5,
        "sensor_gain": 1.0e4,
        "amplifier_gain": 1.0,
        "p_gain": 1.2,
        "i_gain": 5.0,
        "d_gain": 2.5e-3,
        "lowpass_hz": 3000.0,
        "mass": 30.0,
    }
    r = {
        "name": "r",
        "center": [0.0, 0.0],
        "shaft": [{"outer_diameter": 0.08, "length": 0.8, "elements": 8}],
        "disk": [{"node": 4, "mass": 15.0, "Id": 0.06, "Ip": 0.11}, {"node": 5, "mass": 15.0, "Id": 0.06, "Ip": 0.11}],
        "bearing": [{"name": "de", "node": 1, "magnetic": amb}, {"name": "nde", "node": 7, "magnetic": amb}],
    }
    spec = {"speed_rpm": 15000.0, "machine": "pump"}
    a = rotor_stability(_alone(r, dict(spec))).dataset
    b = system_stability({"rotor": [r], "drive": {"rotor": "r", "node": 0}, "stability": spec}).dataset
    assert np.isfinite(a["log_dec_level2"]).all()
    np.testing.assert_allclose(b["log_dec_level2"], a["log_dec_level2"], rtol=0, atol=1e-9)
    np.testing.assert_allclose(b["frequency_level2"], a["frequency_level2"], rtol=1e-9)
