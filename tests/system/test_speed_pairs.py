"""Speed pairs of the system verbs are checked by one rule (system/case.py ``_ordered``): a
``[start, stop]`` range needs stop > start, an operating ``[min, max]`` allows max = min; the
refusal names the key as written and the pair as typed."""

from __future__ import annotations

import math

import pytest

from rotaflex.core.errors import InputError
from rotaflex.system.case import run_campbell, run_torsional

G, D, L = 8e10, 0.2, 0.01  # stiff, short shafts of negligible inertia (as test_train_torsional.py)
K_SHAFT = G * math.pi * D**4 / 32 / L  # N m/rad, one element


def _rotor(name, node, inertia):
    return {
        "name": name,
        "center": [0.0, 0.0],
        "shaft": [{"outer_diameter": D, "length": L, "G": G, "E": 2e11, "rho": 1e-6}],
        "disk": [{"node": node, "mass": 1.0, "Id": 0.01, "Ip": inertia}],
        "bearing": [{"node": 0, "kxx": 1e8, "kyy": 1e8}, {"node": 1, "kxx": 1e8, "kyy": 1e8}],
    }


def two_inertia(J1=2.0, J2=0.5, kc=4e5):
    """J1 on the motor's node 0, coupling motor:1 -> pump:0, J2 on the pump's node 1, 1500 rpm."""
    return {
        "rotor": [_rotor("motor", 0, J1) | {"speed_rpm": 1500.0}, _rotor("pump", 1, J2)],
        "coupling": [{"rotor_a": "motor", "node_a": 1, "rotor_b": "pump", "node_b": 0, "torsional_stiffness": kc}],
        "drive": {"rotor": "motor", "node": 0, "kind": "torque"},
        "load": {"rotor": "pump", "node": 1},
    }


@pytest.mark.parametrize(
    ("verb", "table", "allowed"),
    [
        ("campbell", {"speed_rpm": [3000.0, 1000.0]}, "stop > start"),
        ("torsional", {"speed_rpm": [2000.0, 2000.0]}, "stop > start"),
        ("torsional", {"operating_speed_rpm": [1800.0, 1200.0]}, "max >= min"),
    ],
)
def test_a_pair_out_of_order_is_refused_by_its_key(verb, table, allowed):
    run = {"campbell": run_campbell, "torsional": run_torsional}[verb]
    key = next(iter(table))
    with pytest.raises(InputError) as err:
        run(two_inertia() | {verb: table})
    assert err.value.field == f"{verb}.{key}"
    assert err.value.value == table[key]
    assert allowed in str(err.value)


def test_an_operating_point_of_one_speed_is_accepted():
    """[1500, 1500]: a train run at one speed (1500 rpm = 50 pi rad/s); its first torsional
    frequency is the two-inertia closed form sqrt(k (J1 + J2) / (J1 J2))."""
    J1, J2, kc = 2.0, 0.5, 4e5
    res = run_torsional(two_inertia(J1, J2, kc) | {"torsional": {"operating_speed_rpm": [1500.0, 1500.0]}})
    assert res.dataset["operating_speed"].values == pytest.approx([50 * math.pi] * 2, rel=1e-15)
    k = 1.0 / (2.0 / K_SHAFT + 1.0 / kc)  # shaft, coupling, shaft in series
    w1 = math.sqrt(k * (J1 + J2) / (J1 * J2))  # rad/s
    assert res.dataset["natural_frequency"].values[0] == pytest.approx(w1, rel=1e-9)
