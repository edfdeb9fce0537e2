"""Torsional analysis of trains: natural frequencies against closed forms, crossings and margins
against hand-computed excitation lines, the verb."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from rotaflex.core.errors import InputError
from rotaflex.system.case import run_torsional
from rotaflex.system.model import Gearbox
from rotaflex.system.torsion import crossings, excitation_lines, separation_margins, torsional_model, torsional_modes

G, D, L = 8e10, 0.2, 0.01  # stiff, short, nearly massless shafts: springs in series with the couplings
K_SHAFT = G * math.pi * D**4 / 32 / L  # N m/rad, one element
RHO = 1e-6  # kg/m^3: shaft polar inertia ~1e-15 of the disks


def _rotor(name, disks):
    return {
        "name": name,
        "center": [0.0, 0.0],
        "shaft": [{"outer_diameter": D, "length": L, "G": G, "E": 2e11, "rho": RHO}],
        "disk": [{"node": n, "mass": 1.0, "Id": 0.01, "Ip": j} for n, j in disks],
        "bearing": [{"node": 0, "kxx": 1e8, "kyy": 1e8}, {"node": 1, "kxx": 1e8, "kyy": 1e8}],
    }


def series(*k):
    return 1.0 / sum(1.0 / x for x in k)


def two_inertia(J1=2.0, J2=0.5, kc=4e5, speed_rpm=1500.0):
    """J1 on the motor's node 0, coupling motor:1 -> pump:0, J2 on the pump's node 1."""
    return {
        "rotor": [_rotor("motor", [(0, J1)]) | {"speed_rpm": speed_rpm}, _rotor("pump", [(1, J2)])],
        "coupling": [{"rotor_a": "motor", "node_a": 1, "rotor_b": "pump", "node_b": 0, "torsional_stiffness": kc}],
        "drive": {"rotor": "motor", "node": 0, "kind": "torque"},
        "load": {"rotor": "pump", "node": 1},
    }


def test_two_inertia_train_closed_form():
    J1, J2, kc = 2.0, 0.5, 4e5
    box = Gearbox.from_mapping(two_inertia(J1, J2, kc))
    w, shape = torsional_modes(torsional_model(box))
    k = series(K_SHAFT, kc, K_SHAFT)
    want = math.sqrt(k * (J1 + J2) / (J1 * J2))
    assert w[0] == pytest.approx(want, rel=1e-9)
    # the node: J1 theta_1 = -J2 theta_2 (momentum of the free-free mode is zero)
    th1, th2 = shape[0, 0], shape[0, 3]
    assert J1 * th1 == pytest.approx(-J2 * th2, rel=1e-8)


def test_three_inertia_train_characteristic_polynomial():
    """Motor -> coupling -> gearbox-less intermediate inertia -> coupling -> load, against the roots
    of J1 J2 J3 w^4 - (k1 J3 (J1 + J2) + k2 J1 (J2 + J3)) w^2 + k1 k2 (J1 + J2 + J3) = 0."""
    J1, J2, J3, kc1, kc2 = 3.0, 0.8, 1.7, 2e5, 6e5
    cfg = {
        "rotor": [_rotor("a", [(0, J1)]), _rotor("b", [(0, J2)]), _rotor("c", [(1, J3)])],
        "coupling": [
            {"rotor_a": "a", "node_a": 1, "rotor_b": "b", "node_b": 0, "torsional_stiffness": kc1},
            {"rotor_a": "b", "node_a": 1, "rotor_b": "c", "node_b": 0, "torsional_stiffness": kc2},
        ],
        "drive": {"rotor": "a", "node": 0, "kind": "torque"},
    }
    w, _ = torsional_modes(torsional_model(Gearbox.from_mapping(cfg)))
    k1, k2 = series(K_SHAFT, kc1), series(K_SHAFT, kc2, K_SHAFT)
    poly = [J1 * J2 * J3, -(k1 * J3 * (J1 + J2) + k2 * J1 * (J2 + J3)), k1 * k2 * (J1 + J2 + J3)]
    want = np.sqrt(np.sort(np.roots(poly).real))
    np.testing.assert_allclose(w[:2], want, rtol=1e-9)


def test_geared_train_equals_the_chain_referred_to_the_motor(make):
    """20/40 mesh: the twist model (signed base-circle arcs, opposite senses) has the frequencies
    of the textbook chain referred to the motor speed: the output shaft's J and k times
    i^2 = (20/40)^2 and the mesh as k_m r_b1^2 between the two gear stations."""
    from scipy.linalg import block_diag, eigh

    from rotaflex.system.assembly import torsion_matrices

    box = Gearbox.from_mapping(make())
    w, _ = torsional_modes(torsional_model(box))
    k1, m1 = torsion_matrices(box.rotors[0].rotor)
    k2, m2 = torsion_matrices(box.rotors[1].rotor)
    i2 = (20 / 40) ** 2
    K, J = block_diag(k1, i2 * k2), block_diag(m1, i2 * m2)
    e = np.zeros(K.shape[0])
    e[3], e[k1.shape[0] + 3] = 1.0, -1.0
    m = box.meshes[0]
    K += m.k_mean * m.radius[0] ** 2 * np.outer(e, e)
    w2 = eigh(K, J, eigvals_only=True)
    want = np.sqrt(w2[1:])  # the rigid rotation first
    np.testing.assert_allclose(w, want[: w.size], rtol=1e-12)
    assert m.radius[1] / m.radius[0] == pytest.approx(2.0)


def test_crossings_and_margins_against_hand_computed_lines():
    J1, J2, kc = 2.0, 0.5, 4e5
    box = Gearbox.from_mapping(two_inertia(J1, J2, kc))
    w, _ = torsional_modes(torsional_model(box))
    fn = w[0]
    listed = [
        {"kind": "shaft", "rotor": 0, "order": 1.0},
        {"kind": "shaft", "rotor": 1, "order": 2.0},
        {"kind": "fixed", "frequency": 2 * math.pi * 50.0, "order": 2.0},
    ]
    lines = excitation_lines(box, listed)
    assert [ln["factor"] for ln in lines] == [1.0, 2.0, 0.0]
    assert lines[2]["fixed"] == pytest.approx(2 * math.pi * 100.0)
    rng = (0.0, 1.2 * fn)
    cr = crossings(w[:1], lines, rng)
    # 1X meets the mode at Omega = w_n, 2X at w_n / 2; the fixed 100 Hz line has no crossing speed
    assert [c["speed"] for c in cr] == pytest.approx([fn / 2, fn])
    # operating range 0.55 w_n ... 0.6 w_n: 1X band [0.55, 0.6] w_n -> margin 1/0.6 - 1 = 0.667;
    # 2X band [1.1, 1.2] w_n -> margin 1 - 1/1.1 = 0.0909 < 10 % (fails); 100 Hz by its own value
    margin, passed = separation_margins(w[:1], lines, (0.55 * fn, 0.6 * fn))
    want_fixed = max(fn / (2 * math.pi * 100) - 1, 1 - fn / (2 * math.pi * 100))
    np.testing.assert_allclose(margin[0], [1 / 0.6 - 1, 1 - 1 / 1.1, want_fixed], rtol=1e-12)
    assert passed[0].tolist() == [True, False, abs(want_fixed) >= 0.1]


def test_torsional_verb(tmp_path):
    J1, J2, kc = 2.0, 0.5, 4e5
    cfg = two_inertia(J1, J2, kc)
    fn_hz = math.sqrt(series(K_SHAFT, kc, K_SHAFT) * (J1 + J2) / (J1 * J2)) / (2 * math.pi)
    # operating 1000-1100 rpm: 1X at 16.7-18.3 Hz, 2X at 33.3-36.7 Hz, 100 Hz fixed
    cfg["torsional"] = {
        "operating_speed_rpm": [1000.0, 1100.0],
        "excitation": [
            {"kind": "shaft", "rotor": "motor"},
            {"kind": "shaft", "rotor": "motor", "order": 2},
            {"kind": "fixed", "frequency_hz": 50.0, "order": 2, "name": "2x line"},
        ],
    }
    res = run_torsional(cfg)
    s = res.summary()
    assert s["mode_0_frequency_hz"]["value"] == pytest.approx(fn_hz, rel=1e-9)
    f1 = np.array([1000.0, 1100.0]) / 60
    m_1x = fn_hz / f1[1] - 1 if fn_hz > f1[1] else 1 - fn_hz / f1[0]
    ok = abs(m_1x) >= 0.1 and abs(fn_hz / (2 * f1[1]) - 1) >= 0.1 and abs(fn_hz / 100 - 1) >= 0.1
    assert s["api684_verdict"]["value"] == ("pass" if ok else "fail")
    cr = json.loads(res.dataset.attrs["crossings"])
    rpm = sorted(c["speed"] * 30 / math.pi for c in cr)
    want = sorted(x for x in (fn_hz * 60, fn_hz * 30) if x <= 1.25 * 1100)
    assert rpm == pytest.approx(want, rel=1e-9)
    paths = res.save(tmp_path / "out")
    assert any(p.name.startswith("interference") for p in paths)


def test_bad_excitation_names_the_key():
    cfg = two_inertia()
    cfg["torsional"] = {"excitation": [{"kind": "shaft", "rotor": "fan"}]}
    with pytest.raises(InputError) as e:
        run_torsional(cfg)
    assert e.value.field == "torsional.excitation[0].rotor"


def test_each_system_verb_listed_once():
    """A verb is one COMMANDS line plus its settings table; sweeps (``analysis = ...``) reach the
    same function."""
    from rotaflex.core.domains import COMMANDS
    from rotaflex.system.case_specs import ANALYSES

    assert list(COMMANDS["system"]) == list(ANALYSES)


def test_cli_torsional_on_the_train_examples(tmp_path):
    """Both train examples through the CLI: the motor-coupling-pump passes API 684, the turbine-
    gearbox-generator fails it on the pairs its header names (mode 0 vs generator 1X, mode 2 vs
    turbine 2X); each margin recomputed here from the natural frequency and the speed range."""
    from pathlib import Path

    from typer.testing import CliRunner

    from rotaflex.cli import app

    root = Path(__file__).resolve().parents[2] / "examples" / "system"
    out = {}
    for name in ("motor_coupling_pump", "turbine_gearbox_generator"):
        r = CliRunner().invoke(
            app,
            ["system", "torsional", str(root / f"{name}.toml"), "--out", str(tmp_path / name), "-q", "--no-figures"],
        )
        assert r.exit_code == 0, r.output
        out[name] = json.loads((tmp_path / name / "summary.json").read_text())
    assert out["motor_coupling_pump"]["api684_verdict"]["value"] == "pass"
    s = out["turbine_gearbox_generator"]
    assert s["api684_verdict"]["value"] == "fail"
    fails = sorted((s[k]["mode"], s[k]["line"]) for k in s if k.startswith("failure_"))
    assert fails == [(0, "generator 1X"), (2, "turbine 2X")]
    f0, f2 = s["mode_0_frequency_hz"]["value"], s["mode_2_frequency_hz"]["value"]
    gen_lo = 5700 / 4 / 60  # Hz: the generator's 1X at the lowest operating drive speed (ratio 1/4)
    assert s["failure_0"]["value"] == pytest.approx(1 - f0 / gen_lo, rel=1e-12)
    assert 2 * 5700 / 60 < f2 < 2 * 6300 / 60
