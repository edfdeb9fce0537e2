"""``rotaflex system ucs``: undamped critical speed map of a machine (rotor/fe's ``ucs_solve`` on the
machine's matrices) against the rotor verb, one continuous rotor, closed forms and an independent
first-order eigen-solve of a geared pair."""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest
import scipy.linalg as sla

from rotaflex.core.errors import InputError
from rotaflex.core.units import rad_s_to_rpm
from rotaflex.rotor.fe.model import Rotor
from rotaflex.rotor.fe.ucs import ucs_map
from rotaflex.rotor.fe.verbs_modal import run_ucs as rotor_ucs
from rotaflex.system.assembly import matrices, system_matrices
from rotaflex.system.case import run_ucs as system_ucs
from rotaflex.system.model import Gearbox
from rotaflex.system.ucs import machine_ucs

_SHAFT = [{"outer_diameter": 0.05, "length": 1.2, "elements": 8}]
_DISKS = [{"node": 3, "mass": 30.0, "Id": 0.2, "Ip": 0.35}, {"node": 8, "mass": 12.0, "Id": 0.15, "Ip": 0.28}]
_UCS = {"stiffness": [1e5, 1e10], "n_points": 12, "n_modes": 4}


@pytest.mark.parametrize("rotation", ["ccw", "cw"])
def test_one_rotor_machine_gives_the_rotor_verbs_map(rotation):
    """A machine of one rotor (gyroscopic disks, an overhung disk, a bearing on a pedestal) through
    ``system ucs`` equals ``rotor ucs`` to 1e-9, whichever its sense of rotation."""
    bearings = [{"node": 1, "kxx": 1e7, "kyy": 2e7}, {"node": 6, "kxx": 1e7, "kyy": 2e7}]
    bearings[1]["pedestal"] = {"mass": 40.0, "kxx": 5e7, "kyy": 5e7}
    rotor_cfg = {"shaft": _SHAFT, "disk": _DISKS, "bearing": {"a": bearings[0], "b": bearings[1]}, "ucs": _UCS}
    machine_cfg = {
        "rotor": [{"name": "r", "center": [0.0, 0.0], "shaft": _SHAFT, "disk": _DISKS, "bearing": bearings}],
        "drive": {"rotor": "r", "node": 0, "rotation": rotation},
        "ucs": _UCS,
    }
    a = rotor_ucs(copy.deepcopy(rotor_cfg)).dataset["critical_speed"].values
    b = system_ucs(copy.deepcopy(machine_cfg)).dataset
    assert np.all(np.isfinite(a)) and a.shape == (12, 4)
    np.testing.assert_allclose(b["critical_speed"].values, a, rtol=1e-9)
    assert np.all(b["forward_fraction"].values >= 1 - 1e-9)  # isotropic supports: circular forward whirl


def _rotor(name, d, length, n_el, disk_node, bearings):
    return {
        "name": name,
        "center": [0.0, 0.0],
        "shaft": [{"outer_diameter": d, "length": length, "elements": n_el}],
        "disk": [{"node": disk_node, "mass": 8.0, "Id": 0.04, "Ip": 0.07}],
        "bearing": [{"node": n, "kxx": 2e7, "kyy": 3e7} for n in bearings],
    }


def test_rigid_coupling_train_equals_one_continuous_rotor():
    """Motor and pump joined by a rigid coupling (tests/system/test_trains.py's rigid limit) =
    the rotor built in one piece: every critical speed of the map within 1e-6."""
    train = {
        "rotor": [_rotor("motor", 0.05, 0.4, 4, 2, (0, 3)), _rotor("pump", 0.04, 0.3, 3, 2, (1, 3))],
        "coupling": [{"rotor_a": "motor", "node_a": 4, "rotor_b": "pump", "node_b": 0, "rigid": True}],
        "drive": {"rotor": "motor", "node": 0},
    }
    one = _rotor("shaft", 0.05, 0.4, 4, 2, (0, 3, 5, 7))
    one["shaft"].append({"outer_diameter": 0.04, "length": 0.3, "elements": 3})
    one["disk"].append({"node": 6, "mass": 8.0, "Id": 0.04, "Ip": 0.07})
    k = np.geomspace(1e5, 1e10, 9)
    W, _, f, _ = machine_ucs(Gearbox.from_mapping(train), k, [0, 1], 0, None, 5)
    ref = ucs_map(Rotor.from_mapping({key: one[key] for key in ("shaft", "disk", "bearing")}), k, 5)
    assert np.all(np.isfinite(ref))
    np.testing.assert_allclose(W, ref, rtol=1e-6)


def _beam(rho, n_el=2, length=1.0, d=0.03, disk=None, kappa=0.9):
    """A uniform steel shaft on two end bearings (a disk at mid-span if given)."""
    shaft = {"outer_diameter": d, "length": length, "elements": n_el, "E": 2.1e11, "G": 8.1e10}
    shaft |= {"rho": rho, "shear_coefficient": kappa} if rho else {"mass": False, "shear_coefficient": kappa}
    rotor = {"name": "s", "center": [0.0, 0.0], "shaft": [shaft], "bearing": [{"node": 0}, {"node": n_el}]}
    if disk:
        rotor["disk"] = [{"node": n_el // 2, "mass": disk, "Id": 0.0, "Ip": 0.0}]
    for b in rotor["bearing"]:
        b.update(kxx=1e6, kyy=1e6)
    return Gearbox.from_mapping({"rotor": [rotor], "drive": {"rotor": "s", "node": 0}})


def test_jeffcott_rotor_closed_form():
    """Massless shaft, disk m at mid-span, two bearings k: omega = sqrt(k_eq / m) with
    1/k_eq = 1/k_s + 1/(2 k) and the Timoshenko mid-span stiffness 1/k_s = L^3/(48 E I) + L/(4 kappa G A)
    (the two-node elements are exact for nodal loads); one forward root only (no gyroscopic
    moments: the equal backward root is split off, not counted twice)."""
    L, d, m, kappa = 1.0, 0.03, 20.0, 0.9
    I, A = math.pi * d**4 / 64, math.pi * d**2 / 4
    k_s = 1 / (L**3 / (48 * 2.1e11 * I) + L / (4 * kappa * 8.1e10 * A))
    k = np.geomspace(1e4, 1e9, 7)
    W, _, f, _ = machine_ucs(_beam(None, disk=m, kappa=kappa), k, [0], 0, None, 2)
    np.testing.assert_allclose(W[:, 0], np.sqrt(1 / (1 / k_s + 1 / (2 * k)) / m), rtol=1e-9)
    assert np.all(np.isnan(W[:, 1]))  # the disk's x, y: one forward and one backward root
    np.testing.assert_allclose(f[:, 0], 1.0, atol=1e-9)


def test_soft_and_stiff_support_asymptotes():
    """Uniform shaft (L/d = 200, 24 elements): k -> 0 gives two rigid-body roots and then the
    free-free beam (beta L = 4.7300, 7.8532), k -> infinity the pinned-pinned beam (n pi):
    omega = (beta L)^2 sqrt(E I / (rho A L^4)). Shear and rotary inertia move these by < 1e-4
    at this slenderness, the mesh by less."""
    L, d, rho = 2.0, 0.01, 7800.0
    I, A = math.pi * d**4 / 64, math.pi * d**2 / 4
    scale = math.sqrt(2.1e11 * I / (rho * A * L**4))
    box = _beam(rho, n_el=24, length=L, d=d)
    W, _, _, _ = machine_ucs(box, [1e-3, 1e12], [0], 0, None, 4)
    free = np.array([4.730041, 7.853205]) ** 2 * scale
    pinned = np.array([1.0, 2.0]) ** 2 * math.pi**2 * scale
    assert np.all(W[0, :2] < 1e-2 * free[0])  # rigid translation and tilt on the soft springs
    np.testing.assert_allclose(W[0, 2:], free, rtol=2e-4)
    np.testing.assert_allclose(W[1, :2], pinned, rtol=2e-4)


@pytest.mark.parametrize("drive", ["torque", "constant_speed"])
@pytest.mark.parametrize("chosen", ["in", "out"])
def test_geared_pair_against_the_first_order_eigenproblem(make, drive, chosen):
    """Geared pair (gear meshes couple x, y and twist; a torque drive leaves a rigid-body twist):
    at every critical drive speed W found, the machine's undamped equations at that speed
    (``system_matrices``: every rotor at its own signed speed in its G; assembled apart from the
    UCS pencil) have an eigenvalue i r_c W (first-order state matrix, dense real eig), within
    1e-8, with a forward-whirling eigenvector."""
    cfg = make(drive=drive, damping_ratio=0.0)
    for r in cfg["rotor"]:
        for b in r["bearing"]:
            b.update(cxx=0.0, cyy=0.0)
    box = Gearbox.from_mapping(cfg)
    c = box.rotor_index(chosen, "ucs.rotor")
    # the "in" rotor's own bearings are 2e8 N/m: the sweep passes through the real machine
    W, w, f, _ = machine_ucs(box, [2e8], [0], c, None, 6)
    assert np.all(np.isfinite(W[0]))
    mats = matrices(box)
    r_c = box.rotors[c].sense * box.rotors[c].ratio
    for Wk, wk in zip(W[0], w[0], strict=True):
        assert wk == pytest.approx(abs(r_c) * Wk, rel=1e-14)
        M, D, K = system_matrices(box, float(Wk), mats)
        n = M.shape[0]
        A = np.block([[np.zeros((n, n)), np.eye(n)], [-sla.solve(M, K), -sla.solve(M, D)]])
        lam, V = sla.eig(A)
        j = int(np.argmin(np.abs(lam - 1j * wk * np.sign(r_c))))
        assert abs(lam[j] - 1j * wk * np.sign(r_c)) <= 1e-8 * wk
        v = mats.expand(V[:n, j])
        fw = bw = 0.0
        for i, pr in enumerate(box.rotors):  # whirl sense relative to each rotor's own spin
            s = np.sign(pr.sense * pr.ratio * r_c)  # orbit sense of e^{i Omega_c t} vs the rotor's spin
            X = v[[box.lateral_dof(i, q, 0) for q in range(pr.rotor.n_nodes)]]
            Y = v[[box.lateral_dof(i, q, 1) for q in range(pr.rotor.n_nodes)]]
            fw += np.sum(np.abs(X + 1j * s * Y) ** 2)
            bw += np.sum(np.abs(X - 1j * s * Y) ** 2)
        assert fw / (fw + bw) >= 0.5 - 1e-3


@pytest.mark.parametrize(
    ("ucs", "key"),
    [
        ({"rotors": ["in", "nope"]}, "ucs.rotors[1]"),
        ({"rotor": "nope"}, "ucs.rotor"),
        ({"stiffness": [1e8, 1e6]}, "ucs.stiffness"),
    ],
)
def test_bad_ucs_input_names_the_key(make, ucs, key):
    cfg = make()
    cfg["ucs"] = ucs
    with pytest.raises(InputError) as e:
        system_ucs(cfg)
    assert e.value.field == key


def test_ucs_figure_draws_the_dataset(make):
    """The map's figure (the rotor verb's): one curve per critical, its points the dataset's in
    rpm, the swept bearings' stiffness line, nothing overlapping."""
    cfg = make()
    cfg["ucs"] = {"stiffness": [1e6, 1e10], "n_points": 5, "n_modes": 3, "rotors": ["in"]}
    res = system_ucs(cfg)
    fig = res.plot()["ucs_map"]
    ax = fig.axes[0]
    rpm = rad_s_to_rpm(res.dataset["critical_speed"].values)
    for k in range(3):
        np.testing.assert_allclose(ax.lines[k].get_ydata(), rpm[:, k])
    assert any("in:1 kxx = 2e+08" in t.get_text() for t in ax.get_legend().get_texts())
    from rotaflex.core.plotting import layout_problems

    assert not layout_problems(fig)  # tests/core/test_figure_layout.py's readability checks
