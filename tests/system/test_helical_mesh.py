"""Helical gear meshes in geared rotors (docs/geared-rotor.md, "Helical meshes").

References: closed forms written here by hand (rigid gear bodies on axial springs, torsion),
the force laws of a helical mesh (F_n = T / (r_b cos(beta_b)), F_a = T tan(beta_w) / r_w,
e.g. ISO 21771 / Niemann-Winter), and the spur model in the limit beta -> 0.
"""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg as sla

from rotaflex.core.errors import InputError
from rotaflex.gear import pair_from_mapping
from rotaflex.rotor.fe.torsion_axial import axial_modes
from rotaflex.system.assembly import matrices, system_matrices, undamped_modes
from rotaflex.system.helical import axial_reactions, modal_shares, static_state, tilting_moments
from rotaflex.system.modal import campbell, modal
from rotaflex.system.model import Gearbox
from rotaflex.system.response import forced_response
from rotaflex.system.steady import SteadySettings, steady_state

ROOT = Path(__file__).resolve().parents[2]

RIGID = {"E": 2.1e17, "G": 8.1e16, "rho": 7800.0}  # shafts 1e6 x steel, steel's density
D, L = 0.05, 0.1  # shaft diameter, length [m]
DISK = {"pinion": (3.0, 2.0e-3, 4.0e-3), "wheel": (9.0, 1.0e-2, 2.0e-2)}  # mass, Id, Ip
KA = (1.0e8, 2.0e8)  # thrust stiffness of the input / output rotor [N/m]
K_MESH = 2.0e8


def _gear(teeth: int, beta: float, hand: str | None) -> dict:
    g = {"teeth": teeth, "module": 3.0e-3, "face_width": 0.02}
    if beta > 0:
        g |= {"helix_angle_deg": beta, "hand": hand}
    return g


def _pair(beta: float):
    return pair_from_mapping({"pinion": _gear(20, beta, "right"), "wheel": _gear(40, beta, "left")})


def _config(beta: float, kzz=KA, rotation: str = "ccw", rigid: bool = True, elements: int = 1) -> dict:
    """Two one-element rotors with bearings at both ends (rigid: shafts 1e6 x steel, bearings
    1e14 N/m; else steel, 2e8 N/m), a thrust bearing at node 0, the gears as disks at node 1, a
    constant-speed drive at the input's node 0 (``elements`` > 1: the gears at the last node)."""
    a = _pair(beta).working_center_distance

    def rotor(name, x, gear, ka):
        m, Id, Ip = DISK[gear]
        kb = 1e14 if rigid else 2e8
        brg = [{"node": n, "kxx": kb, "kyy": kb} for n in (0, elements)]
        if ka:
            brg[0]["kzz"] = ka
        return {
            "name": name,
            "center": [x, 0.0],
            "shaft": [{"outer_diameter": D, "length": L * elements, "elements": elements, **(RIGID if rigid else {})}],
            "disk": [{"node": elements, "mass": m, "Id": Id, "Ip": Ip}],
            "bearing": brg,
        }

    return {
        "rotor": [rotor("in", 0.0, "pinion", kzz[0]), rotor("out", a, "wheel", kzz[1])],
        "gear_mesh": [
            {
                "pinion_rotor": "in",
                "pinion_node": elements,
                "wheel_rotor": "out",
                "wheel_node": elements,
                "source": "harmonic",
                "k_mean": K_MESH,
                "torque": 100.0,
                "damping_ratio": 0.0,
                "blanks": False,
                "pinion": _gear(20, beta, "right"),
                "wheel": _gear(40, beta, "left"),
            }
        ],
        "drive": {"rotor": "in", "node": 0, "kind": "constant_speed", "rotation": rotation},
    }


def _rigid_masses():
    """Rigid-body axial mass [kg] and polar inertia [kg m^2] of a rotor: shaft + disk."""
    area, jp = math.pi / 4 * D**2, math.pi / 32 * D**4
    rho = RIGID["rho"]
    return {g: (m + rho * area * L, Ip + rho * jp * L) for g, (m, _, Ip) in DISK.items()}


def _hand_frequencies(beta: float) -> np.ndarray:
    """The 3-DOF eigenproblem (wheel twist theta_2, axial w_1, w_2; the pinion held by the
    constant-speed drive, gear bodies rigid) written out: the mesh spring along the flank normal
    has the transverse deflection r_b2 theta_2 + tan(beta_b) (w_1 - w_2)."""
    pair = _pair(beta)
    rb2 = pair.gears[1].base_radius
    t = math.tan(pair.base_helix_angle)
    (m1, _), (m2, J2) = _rigid_masses()["pinion"], _rigid_masses()["wheel"]
    a = np.array([rb2, t, -t])
    K = K_MESH * np.outer(a, a) + np.diag([0.0, KA[0], KA[1]])
    M = np.diag([J2, m1, m2])
    return np.sqrt(sla.eigh(K, M, eigvals_only=True))


@pytest.mark.parametrize("beta", [10.0, 25.0])
def test_rigid_two_gear_frequencies_match_the_hand_derived_3dof_problem(beta):
    box = Gearbox.from_mapping(_config(beta))
    wn = np.sort(modal(box, 0.0, 3).wn[0])
    ref = _hand_frequencies(beta)
    # shafts 1e6 x steel, bearings 1e14 N/m: the rigid-body model
    np.testing.assert_allclose(wn, ref, rtol=1e-5)  # measured 1.9e-6
    # the check discriminates: the uncoupled (spur) frequencies are > 1 % away
    (m1, _), (m2, J2) = _rigid_masses()["pinion"], _rigid_masses()["wheel"]
    rb2 = _pair(beta).gears[1].base_radius
    spur = np.sort(np.sqrt([K_MESH * rb2**2 / J2, KA[0] / m1, KA[1] / m2]))
    assert np.max(np.abs(ref / spur - 1)) > 1e-2


def test_helical_mesh_without_thrust_bearing_is_refused_naming_kzz():
    with pytest.raises(InputError, match=r"rotor\[1\]\.bearing\[\]\.kzz"):
        Gearbox.from_mapping(_config(15.0, kzz=(1e8, 0.0)))


def _undamped(box) -> np.ndarray:
    M, _, K = system_matrices(box, 0.0)
    return undamped_modes(M, K)[0]


def _no_tilt(box):
    """The same box with the pitch-point arms zeroed: the axial mesh force without its moment."""
    meshes = tuple(dataclasses.replace(m, arms=(np.zeros(2), np.zeros(2))) for m in box.meshes)
    return dataclasses.replace(box, meshes=meshes)


def test_beta_to_zero_tends_to_the_spur_modes_plus_the_rotors_axial_modes():
    """As beta -> 0 the helical box's frequencies tend to the spur box's plus each rotor's
    uncoupled axial modes (rotor/fe ``axial_modes``, thrust springs included). First order in
    beta: the axial force's moment at the pitch point, ``F tan(beta_b) r_w``, acts on the tilts,
    which the spur modes already move, so it shifts them at first order (the energy's cross term
    ``2 k tan(beta_b) (g_t^T v)(g_a^T v)``); without the moment arms the coupling reaches only the
    new axial DOFs and the shift is second order (tan^2(beta_b); the transverse geometry's
    cos(beta) too)."""
    spur = Gearbox.from_mapping(_config(0.0, rigid=False))
    axial = [axial_modes(pr.rotor, pr.rotor.n_nodes)[0] for pr in spur.rotors]
    ref = np.sort(np.concatenate([_undamped(spur), *axial]))
    err, err_no_tilt = [], []
    betas = (1.0, 0.5, 0.25)
    for beta in betas:
        box = Gearbox.from_mapping(_config(beta, rigid=False))
        err.append(np.max(np.abs(np.sort(_undamped(box)) - ref) / ref))
        err_no_tilt.append(np.max(np.abs(np.sort(_undamped(_no_tilt(box))) - ref) / ref))
    order = np.log2(np.array(err[:-1]) / np.array(err[1:]))
    order2 = np.log2(np.array(err_no_tilt[:-1]) / np.array(err_no_tilt[1:]))
    assert err[-1] < 5e-4 and np.all(np.abs(order - 1) < 0.15), (err, order)
    assert err_no_tilt[-1] < 1e-5 and np.all(np.abs(order2 - 2) < 0.2), (err_no_tilt, order2)


def test_beta_zero_with_axial_dofs_is_the_spur_system_exactly():
    """A spur box given axial DOFs: the spur matrices unchanged bit for bit, no coupling to the
    axial block, the frequencies the union of both."""
    spur = Gearbox.from_mapping(_config(0.0, rigid=False))
    ax = dataclasses.replace(spur, rotors=tuple(dataclasses.replace(pr, axial=True) for pr in spur.rotors))
    ms, ma = matrices(spur), matrices(ax)
    old = np.concatenate([np.arange(o, o + nl + nt) for o, nl, nt in ax.layout])
    new = np.setdiff1d(np.arange(ax.n_dof), old)
    for Xs, Xa in ((ms.M, ma.M), (ms.K0, ma.K0), (ms.g.T @ ms.g, ma.g.T @ ma.g)):
        assert np.array_equal(Xa[np.ix_(old, old)], Xs)
    assert not np.any(ma.g[:, new])
    axial = [axial_modes(pr.rotor, pr.rotor.n_nodes)[0] for pr in spur.rotors]
    np.testing.assert_allclose(np.sort(_undamped(ax)), np.sort(np.concatenate([_undamped(spur), *axial])), rtol=1e-10)


@pytest.mark.parametrize("beta", [0.0, 15.0])
def test_axial_torsional_coupling_only_for_a_helix(beta):
    """The stiffness block between the axial DOFs and the twists is ``k sigma tan(beta_b) s_d
    r_b`` (zero for spur), and the mesh mode carries axial kinetic energy only for beta > 0."""
    box = Gearbox.from_mapping(_config(beta, rigid=False))
    if beta == 0:
        box = dataclasses.replace(box, rotors=tuple(dataclasses.replace(pr, axial=True) for pr in box.rotors))
    mats = matrices(box)
    Km = (mats.g.T * mats.k_mean) @ mats.g
    m = box.meshes[0]
    pair = _pair(beta)
    t = math.tan(pair.base_helix_angle)
    # right-hand pinion driving counter-clockwise: thrust on the pinion along +z, i.e. sigma = -1
    want = K_MESH * (-t) * 1 * pair.gears[0].base_radius
    got = Km[box.axial_dof(*m.driver), box.torsion_dof(*m.driver)]
    assert got == pytest.approx(want, rel=1e-12, abs=1e-300)
    shapes = modal(box, 0.0, 8).shape[0]
    k = int(np.argmax(np.abs(shapes @ mats.g[0])))  # the mode that strains the mesh most
    share = modal_shares(box, shapes, 0.0)["axial_kinetic"][k]
    assert (share > 1e-3) if beta else (share < 1e-20)


@pytest.mark.parametrize("rotation", ["ccw", "cw"])
def test_static_forces_follow_the_helical_force_laws(rotation):
    """Under a load torque T on the wheel (T_p = T / 2 on the pinion): the resultant the mesh
    applies to the driven gear is T_p / (r_b1 cos(beta_b)); each rotor's thrust bearing takes
    T_p tan(beta_w) / r_w1 with the hand rule's sign (right-hand pinion driving: thrust on the
    pinion along its rotation vector); tilting moments F_a r_w."""
    beta, T_load = 20.0, 200.0
    cfg = _config(beta, rotation=rotation, rigid=False)
    cfg["load"] = {"rotor": "out", "node": 1, "torque": T_load}
    box = Gearbox.from_mapping(cfg)
    pair = _pair(beta)
    Tp = T_load / 2
    rb1, rw1, rw2 = (
        pair.gears[0].base_radius,
        *(g.base_radius / math.cos(pair.operating_pressure_angle) for g in pair.gears),
    )
    q, F = static_state(box, 0.0)
    mats = matrices(box)
    m = box.meshes[0]
    f, node = m.driven
    dofs = [box.lateral_dof(f, node, 0), box.lateral_dof(f, node, 1), box.axial_dof(f, node)]
    normal = np.linalg.norm(-F[0] * mats.g[0, dofs])
    assert normal == pytest.approx(Tp / (rb1 * math.cos(pair.base_helix_angle)), rel=1e-9)
    fa = Tp * math.tan(pair.working_helix_angle) / rw1
    spin = 1.0 if rotation == "ccw" else -1.0
    r_in, r_out = axial_reactions(box, q)  # one thrust bearing per rotor, on the rotor
    assert r_in == pytest.approx(-spin * fa, rel=1e-9)  # the mesh pushes the pinion along +spin z
    assert r_out == pytest.approx(spin * fa, rel=1e-9)
    tm = np.linalg.norm(tilting_moments(box, F)[0], axis=-1)
    np.testing.assert_allclose(tm, [fa * rw1, fa * rw2], rtol=1e-9)


def test_steady_state_energy_balance_with_a_helical_mesh():
    """Varying mesh stiffness and TE, thrust dampers: E - E0 = int P dt, and the thrust
    reactions' mean over the evaluated cycles is near the static one (small TE, 5 % stiffness
    variation)."""
    cfg = _config(15.0, rigid=False)
    cfg["load"] = {"rotor": "out", "node": 1, "torque": 200.0, "damping": 2.0}
    for r in cfg["rotor"]:
        r["bearing"][0]["czz"] = 2.0e3
    cfg["gear_mesh"][0].update(k_harmonics=[0.05 * K_MESH], te_harmonics=[2e-7], damping_ratio=0.05)
    del cfg["gear_mesh"][0]["torque"]
    box = Gearbox.from_mapping(cfg)
    st = SteadySettings(steps_per_cycle=128, min_cycles=10, max_cycles=30, eval_cycles=4)
    s = steady_state(box, 300.0, st)
    assert s.energy_error < 1e-5, s.energy_error  # measured 3.0e-6 (1.3e-5 at 64 steps, 7.4e-7 at 256)
    q, _ = static_state(box, 300.0)
    static = axial_reactions(box, q)
    np.testing.assert_allclose(s.axial_force.mean(0), static, rtol=1e-2)  # measured 9e-4


def test_cli_helical_mesh_without_thrust_bearing_exits_2_naming_kzz(tmp_path):
    from typer.testing import CliRunner

    from rotaflex.cli import app

    text = (ROOT / "examples/system/helical_gearbox.toml").read_text()
    cfg = tmp_path / "bad.toml"
    cfg.write_text(text.replace("kzz = 1.5e8", "kzz = 0.0"))
    r = CliRunner().invoke(app, ["system", "modal", str(cfg), "--out", str(tmp_path / "o"), "-q", "--no-figures"])
    assert r.exit_code == 2
    lines = [ln for ln in r.output.strip().splitlines() if ln]
    assert len(lines) == 1 and "rotor[1].bearing[].kzz" in lines[0], r.output


def test_te_response_thrust_reactions_match_the_hand_derived_forced_problem():
    """Rigid two-gear case (as the 3-DOF frequency test) excited by a TE harmonic e at the mesh
    frequency w (z_p Omega): ``(K - w^2 M) X = k a e`` written by hand; the thrust reactions are
    ``-k_a1 w_1`` and ``-k_a2 w_2`` and the dynamic mesh force ``k (a^T X - e)``."""
    beta, e, speed = 15.0, 1e-6, 100.0  # mesh frequency 2000 rad/s, below the lowest mode (~4200)
    cfg = _config(beta)
    cfg["gear_mesh"][0].update(te_harmonics=[e], damping_ratio=0.0)
    box = Gearbox.from_mapping(cfg)
    r = forced_response(box, [speed], harmonics=1, cutoff=None)
    pair = _pair(beta)
    t = math.tan(pair.base_helix_angle)
    (m1, _), (m2, J2) = _rigid_masses()["pinion"], _rigid_masses()["wheel"]
    a = np.array([pair.gears[1].base_radius, t, -t])
    K = K_MESH * np.outer(a, a) + np.diag([0.0, KA[0], KA[1]])
    w = 20 * speed
    X = np.linalg.solve(K - w**2 * np.diag([J2, m1, m2]), K_MESH * a * e)
    thrust = np.abs([KA[0] * X[1], KA[1] * X[2]])
    np.testing.assert_allclose(np.abs(r.axial_bearing_force[0, 0, 0]), thrust, rtol=1e-5)
    assert abs(r.mesh_force[0, 0, 0]) == pytest.approx(abs(K_MESH * (a @ X - e)), rel=1e-5)
    assert thrust.min() > 1.0  # N (8.7 and 9.1 N): the check is not of zeros


def test_campbell_reduced_basis_keeps_the_axial_coupling():
    """Campbell of a helical box in the reduced basis (modes + static mesh-force shapes, which
    carry the axial response) against all DOFs."""
    box = Gearbox.from_mapping(_config(15.0, rigid=False, elements=6))
    speeds = np.linspace(0.0, 600.0, 3)
    full = campbell(box, speeds, 8, reduce=False)
    red = campbell(box, speeds, 8, reduce=True)
    np.testing.assert_allclose(red.modes.wd, full.modes.wd, rtol=1e-5)  # measured 7.9e-9 (31 of 83 DOFs)
    assert any(g.endswith(".axial") for g in full.modes.groups)


def test_cli_modal_on_the_helical_example_reports_axial_shares(tmp_path):
    """The example's modal run: the axial energy groups (modal's group split) equal the axial
    kinetic share (computed apart, from the mode shapes and M), and the groups sum to 1."""
    import xarray as xr
    from typer.testing import CliRunner

    from rotaflex.cli import app

    out = tmp_path / "m"
    args = ["system", "modal", str(ROOT / "examples/system/helical_gearbox.toml"), "--out", str(out), "-q"]
    r = CliRunner().invoke(app, [*args, "--no-figures"])
    assert r.exit_code == 0, r.output
    ds = xr.load_dataset(out / "result.nc")
    axial = [g for g in ds.group.values if str(g).endswith(".axial")]
    assert len(axial) == 2
    np.testing.assert_allclose(ds.energy.sel(group=axial).sum("group"), ds.axial_kinetic, atol=1e-12)
    np.testing.assert_allclose(ds.energy.sum("group"), 1.0, atol=1e-12)
    assert float(ds.axial_kinetic.max()) > 0.9  # the thrust-bearing modes
    s = json.loads((out / "summary.json").read_text())
    assert s["mode_0_axial_kinetic"]["unit"] == "1"


def test_thrust_springs_to_ground_and_between_nodes_in_the_axial_matrices():
    """kzz/czz of a bearing to ground add on the node's diagonal; between two nodes (to_node)
    they add the two-node spring [[k, -k], [-k, k]] (the bars' E A / L removed for the check)."""
    from rotaflex.rotor.fe.model import Bearing, Rotor, Shaft
    from rotaflex.rotor.fe.torsion_axial import axial_matrices

    shaft = (Shaft(outer_diameter=0.05, length=0.3, elements=3),)
    lateral = [Bearing(node=n, kxx=1e8, kyy=1e8) for n in (0, 3)]
    bare = Rotor(shaft=shaft, bearing=tuple(lateral))
    thrust = (Bearing(node=0, kzz=3e7, czz=50.0), Bearing(node=1, to_node=3, kzz=2e7, czz=20.0))
    rotor = Rotor(shaft=shaft, bearing=(*lateral, *thrust))
    K0, M0, C0 = axial_matrices(bare)
    K, M, C = axial_matrices(rotor)
    want_k, want_c = np.zeros((4, 4)), np.zeros((4, 4))
    want_k[0, 0], want_c[0, 0] = 3e7, 50.0
    want_k[np.ix_([1, 3], [1, 3])] += 2e7 * np.array([[1, -1], [-1, 1]])
    want_c[np.ix_([1, 3], [1, 3])] += 20.0 * np.array([[1, -1], [-1, 1]])
    np.testing.assert_allclose(K - K0, want_k, rtol=1e-12, atol=1e-6)
    np.testing.assert_array_equal(C, want_c)
    np.testing.assert_array_equal(M, M0)
    assert not np.any(C0)
