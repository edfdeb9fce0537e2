"""[[coupling]]: rotors joined in series on one axis (rigid limit, flexible split, element, input)."""

from __future__ import annotations

import copy

import numpy as np
import pytest

from rotaflex.core.errors import InputError
from rotaflex.system.assembly import matrices
from rotaflex.system.modal import modal
from rotaflex.system.model import Gearbox


def _rotor(name, d, length, n_el, disk_node, bearings, torsion=True):
    return {
        "name": name,
        "center": [0.0, 0.0],
        "torsion": torsion,
        "shaft": [{"outer_diameter": d, "length": length, "elements": n_el}],
        "disk": [{"node": disk_node, "mass": 8.0, "Id": 0.04, "Ip": 0.07}],
        "bearing": [{"node": n, "kxx": 2e7, "kyy": 3e7, "cxx": 400.0, "cyy": 500.0} for n in bearings],
    }


def _train(coupling, torsion=True, drive="constant_speed"):
    """Motor rotor (4 elements) coupled at its node 4 to a pump rotor (3 elements) at its node 0."""
    a = _rotor("motor", 0.05, 0.4, 4, 2, (0, 3), torsion)
    b = _rotor("pump", 0.04, 0.3, 3, 2, (1, 3), torsion)
    return {
        "rotor": [a, b],
        "coupling": [{"rotor_a": "motor", "node_a": 4, "rotor_b": "pump", "node_b": 0, **coupling}],
        "drive": {"rotor": "motor", "node": 0, "kind": drive},
    }


def _one_piece(torsion=True, drive="constant_speed"):
    """The same train as one rotor: the pump's elements continue the motor's (pump node j = node 4 + j)."""
    a = _rotor("shaft", 0.05, 0.4, 4, 2, (0, 3), torsion)
    a["shaft"].append({"outer_diameter": 0.04, "length": 0.3, "elements": 3})
    a["disk"].append({"node": 6, "mass": 8.0, "Id": 0.04, "Ip": 0.07})
    a["bearing"] += [{"node": n, "kxx": 2e7, "kyy": 3e7, "cxx": 400.0, "cyy": 500.0} for n in (5, 7)]
    return {"rotor": [a], "drive": {"rotor": "shaft", "node": 0, "kind": drive}}


@pytest.mark.parametrize("drive", ["constant_speed", "torque"])
def test_rigid_coupling_equals_one_continuous_rotor(drive):
    """Exact constraint: the modes (lateral with gyroscopics at speed, torsional) of the coupled
    train equal those of the rotor built in one piece to 1e-9."""
    box = Gearbox.from_mapping(_train({"rigid": True}, drive=drive))
    one = Gearbox.from_mapping(_one_piece(drive=drive))
    n = one.n_dof - (drive == "constant_speed")
    w = 900.0  # rad/s: gyroscopic coupling of forward and backward whirl
    a, b = modal(box, w, n - 2), modal(one, w, n - 2)
    assert np.isfinite(a.eigenvalue).all()
    np.testing.assert_allclose(a.eigenvalue, b.eigenvalue, rtol=1e-9)
    # the mode shapes agree too: one-piece node j is motor node j (j <= 4) or pump node j - 4
    lat = [box.lateral_dof(0, j, x) if j <= 4 else box.lateral_dof(1, j - 4, x) for j in range(8) for x in range(4)]
    tw = [box.torsion_dof(0, j) if j <= 4 else box.torsion_dof(1, j - 4) for j in range(8)]
    sa, sb = a.shape[0][:, lat + tw], b.shape[0]
    mac = np.abs(np.sum(np.conj(sa) * sb, 1)) ** 2 / (np.sum(np.abs(sa) ** 2, 1) * np.sum(np.abs(sb) ** 2, 1))
    np.testing.assert_allclose(mac, 1.0, atol=1e-9)


def test_stiff_coupling_converges_to_the_rigid_limit():
    """Penalty form: the error in the modes against the exact constraint falls as 1/k."""
    rigid = modal(Gearbox.from_mapping(_train({"rigid": True})), 0.0, 8).wn[0]
    errs = []
    for k in (1e10, 1e11, 1e12):
        c = {"torsional_stiffness": k, "lateral_stiffness": k, "angular_stiffness": k}
        w = modal(Gearbox.from_mapping(_train(c)), 0.0, 8).wn[0]
        errs.append(np.max(np.abs(w / rigid - 1)))
    ratio = np.array(errs[:-1]) / np.array(errs[1:])
    np.testing.assert_allclose(ratio, 10.0, rtol=0.05)


def test_zero_lateral_stiffness_splits_the_train():
    """Lateral and angular stiffness 0: the lateral modes are those of each rotor alone (torsion
    still joins them through k_t, and lateral and torsion do not couple without gears)."""
    box = Gearbox.from_mapping(_train({"torsional_stiffness": 5e4, "mass": 2.0, "Ip": 0.01, "Id": 0.006}))
    w = 700.0
    m = modal(box, w, box.n_dof - 1)
    lateral = m.torsional_fraction[0] < 0.5
    alone = []
    for r, node in ((0, 4), (1, 0)):
        cfg = _train({})
        rot = copy.deepcopy(cfg["rotor"][r])
        rot["disk"].append({"node": node, "mass": 1.0, "Id": 0.003, "Ip": 0.005})  # its half of the coupling
        one = Gearbox.from_mapping({"rotor": [rot], "drive": {"rotor": rot["name"], "node": 0}})
        mm = modal(one, w, one.n_dof - 1)
        alone.append(mm.eigenvalue[0][mm.torsional_fraction[0] < 0.5])
    want = np.sort_complex(np.concatenate(alone))
    np.testing.assert_allclose(np.sort_complex(m.eigenvalue[0][lateral]), want, rtol=1e-9)
    # a small lateral stiffness joins them again, continuously (first order in k)
    d = []
    for k in (1e2, 1e3):
        b = Gearbox.from_mapping(
            _train({"torsional_stiffness": 5e4, "lateral_stiffness": k, "mass": 2.0, "Ip": 0.01, "Id": 0.006})
        )
        mk = modal(b, w, b.n_dof - 1)
        d.append(np.max(np.abs(np.sort_complex(mk.eigenvalue[0][mk.torsional_fraction[0] < 0.5]) / want - 1)))
    assert 0 < d[0] < d[1] and d[1] / d[0] == pytest.approx(10.0, rel=0.05)


def test_coupling_element_stiffness_on_its_hubs():
    """K of the assembly holds k_r, k_b, k_t between the hub DOFs; the coupled rotors turn together."""
    c = {"torsional_stiffness": 3e4, "lateral_stiffness": 2e6, "angular_stiffness": 5e3, "torsional_damping": 7.0}
    base = matrices(Gearbox.from_mapping(_train({"rigid": False, "torsional_stiffness": 1.0})))
    box = Gearbox.from_mapping(_train(c))
    mats = matrices(box)
    dK, dC = mats.K0 - base.K0, mats.C0 - base.C0
    ia = [box.lateral_dof(0, 4, a) for a in range(4)] + [box.torsion_dof(0, 4)]
    ib = [box.lateral_dof(1, 0, a) for a in range(4)] + [box.torsion_dof(1, 0)]
    want = np.array([2e6, 2e6, 5e3, 5e3, 3e4 - 1.0])
    np.testing.assert_allclose(np.diag(dK)[ia], want)
    np.testing.assert_allclose(dK[ia, ib], -want)
    assert dC[ia[4], ia[4]] == 7.0 and dC[ia[4], ib[4]] == -7.0
    assert np.count_nonzero(dK) == 4 * 5
    assert box.speeds(10.0) == pytest.approx([10.0, 10.0])  # a coupling keeps speed and sense


def test_hub_masses_split():
    box = Gearbox.from_mapping(_train({"torsional_stiffness": 1e4, "mass": 3.0, "Ip": 0.02, "Id": 0.01, "split": 0.25}))
    ma, mb = matrices(box).M, matrices(Gearbox.from_mapping(_train({"torsional_stiffness": 1e4}))).M
    d = np.diag(ma - mb)
    assert d[box.lateral_dof(0, 4, 0)] == pytest.approx(0.75)
    assert d[box.lateral_dof(1, 0, 1)] == pytest.approx(2.25)
    assert d[box.torsion_dof(0, 4)] == pytest.approx(0.005)
    assert d[box.torsion_dof(1, 0)] == pytest.approx(0.015)
    assert d.sum() == pytest.approx(2 * 3.0 + 2 * 0.01 + 0.02)


@pytest.mark.parametrize(
    ("change", "key"),
    [
        ({"rigid": True, "torsional_stiffness": 1e4}, "coupling[0].torsional_stiffness"),
        ({}, "coupling[0].torsional_stiffness"),
        ({"torsional_stiffness": 1e4, "rotor_b": "motor"}, "coupling[0].rotor_b"),
        ({"torsional_stiffness": 1e4, "rotor_b": "fan"}, "coupling[0].rotor_b"),
        ({"torsional_stiffness": 1e4, "node_b": 9}, "coupling[0].node_b"),
        ({"torsional_stiffness": -1.0}, "coupling[0].torsional_stiffness"),
    ],
)
def test_bad_coupling_names_the_key(change, key):
    with pytest.raises(InputError) as e:
        Gearbox.from_mapping(_train(change))
    assert e.value.field == key


def test_coupling_needs_one_axis():
    cfg = _train({"torsional_stiffness": 1e4})
    cfg["rotor"][1]["center"] = [0.0, 0.1]
    with pytest.raises(InputError) as e:
        Gearbox.from_mapping(cfg)
    assert e.value.field == "rotor[1].center"


def test_rigid_coupling_in_the_torsional_model():
    """The train torsional model (free-free, twists only) of the rigidly coupled rotors has the
    torsional frequencies of the rotor built in one piece, and its mode shapes on the same twists."""
    from rotaflex.system.torsion import torsional_model, torsional_modes

    wa, sa = torsional_modes(torsional_model(Gearbox.from_mapping(_train({"rigid": True}, drive="torque"))))
    wb, sb = torsional_modes(torsional_model(Gearbox.from_mapping(_one_piece(drive="torque"))))
    np.testing.assert_allclose(wa, wb, rtol=1e-10)
    # train twists: motor 0..4, pump 0..3 (pump 0 = motor 4); one piece: nodes 0..7
    # shapes by MAC: two pairs of modes lie 1 % apart, where shapes are conditioned ~1e-6
    a = np.delete(sa, 5, axis=1)
    mac = np.sum(a * sb, 1) ** 2 / (np.sum(a * a, 1) * np.sum(sb * sb, 1))
    np.testing.assert_allclose(mac, 1.0, atol=1e-9)
    np.testing.assert_allclose(sa[:, 5], sa[:, 4], rtol=0, atol=0)
