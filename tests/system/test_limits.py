"""Limits and invariances of the coupled gearbox modes, each against an independent result."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rotaflex.rotor.fe import modal as rotor_modal
from rotaflex.rotor.fe import torsional_modes
from rotaflex.system.assembly import coupling_vector, torsion_matrices
from rotaflex.system.modal import campbell, modal
from rotaflex.system.model import Gearbox


def _box(cfg):
    return Gearbox.from_mapping(cfg)


def test_torsion_matrices_give_rotor_fe_torsional_modes(make):
    box = _box(make())
    for pr in box.rotors:
        K, M = torsion_matrices(pr.rotor)
        w = np.sqrt(np.clip(np.sort(np.linalg.eigvals(np.linalg.solve(M, K)).real), 0, None))
        ref = torsional_modes(pr.rotor, 4)[0]
        np.testing.assert_allclose(w[1:4], ref[1:4], rtol=1e-9)


@pytest.mark.parametrize("speed", [0.0, 400.0])
def test_zero_mesh_stiffness_gives_each_rotors_own_modes(make, speed):
    box = _box(make()).with_mesh_stiffness(0.0)
    sys = modal(box, speed, 16).wd[0]
    ref = []
    for pr in box.rotors:
        ref += list(rotor_modal(pr.rotor, abs(pr.ratio * speed), 12).wd[0])
        ref += list(torsional_modes(pr.rotor, 4)[0][1:])  # undamped twist modes (no torsional damping)
    ref = np.sort(ref)[:16]
    np.testing.assert_allclose(sys, ref, rtol=1e-8)


def _rigid(cfg, E=2.1e18, G=8.1e17, k_b=1e15):
    for r in cfg["rotor"]:
        r["shaft"][0].update(E=E, G=G)
        for b in r["bearing"]:
            b.update(kxx=k_b, kyy=k_b, cxx=0.0, cyy=0.0)
    return cfg


def test_rigid_shafts_and_bearings_give_torsional_mesh_frequency(make):
    box = _box(_rigid(make(damping_ratio=0.0)))
    m = box.meshes[0]
    J = [torsion_matrices(pr.rotor)[1].sum() for pr in box.rotors]  # rigid rotor: all twist mass
    rb1, rb2 = m.gear.base_radius
    w_ref = math.sqrt(m.k_mean * (rb1**2 / J[0] + rb2**2 / J[1]))
    w = modal(box, 0.0, 3).wn[0]
    assert w[0] == pytest.approx(w_ref, rel=2e-4)


def _lumped_4x4(J, m, kb, k, r):
    """Closed form of gear steady's [bearings] model: twists theta_1,2 and centre motions y_1,2
    along the line of action, delta = r1 th1 + r2 th2 + y1 - y2 (external pair)."""
    g = np.array([r[0], r[1], 1.0, -1.0])
    K = np.diag([0.0, 0.0, kb[0], kb[1]]) + k * np.outer(g, g)
    M = np.diag([J[0], J[1], m[0], m[1]])
    w2 = np.sort(np.linalg.eigvals(np.linalg.solve(M, K)).real)
    return np.sqrt(np.clip(w2, 0, None))[1:]  # drop the rigid rotation


@pytest.mark.parametrize("angle", [0.0, 0.7])
def test_bearings_along_line_of_action_give_lumped_model(make, angle):
    """One rigid element per shaft, pinned at node 1, gear at node 0 on a bearing acting along
    the line of action only (n = R(angle) (sin a', cos a') for a ccw pinion driving, derived in
    the docs, not taken from the code): the coupled FE model must give the 2-inertia +
    2-mass closed form with m_eff = m + (Id_0 + Id_1) / L^2 (the rigid shaft pivots on node 1)."""
    L, mass, Id, J, kb, kperp = 0.05, (0.8, 1.6), 1e-4, (2e-3, 8e-3), (3e7, 5e7), 4e10
    cfg = make(damping_ratio=0.0, angle=angle)
    cfg["gear_mesh"][0].update(pinion_node=0, wheel_node=0, blanks=False)
    box0 = _box(cfg)
    alpha = box0.meshes[0].gear.pressure_angle
    n = np.array([math.sin(alpha), math.cos(alpha)])
    rot = np.array([[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]])
    n = rot @ n
    t = np.array([-n[1], n[0]])
    for i, r in enumerate(cfg["rotor"]):
        r["shaft"] = [{"outer_diameter": 0.03, "length": L, "elements": 1, "E": 2e15, "G": 8e14, "rho": 1e-3}]
        kk = kb[i] * np.outer(n, n) + kperp * np.outer(t, t)
        r["bearing"] = [
            {"node": 0, "kxx": kk[0, 0], "kxy": kk[0, 1], "kyx": kk[1, 0], "kyy": kk[1, 1]},
            {"node": 1, "kxx": 1e11, "kyy": 1e11},
        ]
        r["disk"] = [{"node": 0, "mass": mass[i], "Id": Id, "Ip": J[i]}, {"node": 1, "mass": 1.0, "Id": Id, "Ip": 1e-6}]
    cfg["drive"]["node"], cfg["load"]["node"], cfg["load"]["inertia"] = 0, 0, 0.0
    box = _box(cfg)
    mesh = box.meshes[0]
    ref = _lumped_4x4(
        (J[0] + 1e-6, J[1] + 1e-6),
        (mass[0] + 2 * Id / L**2, mass[1] + 2 * Id / L**2),
        kb,
        mesh.k_mean,
        mesh.gear.base_radius,
    )
    w = modal(box, 0.0, 8).wn[0]
    for wr in ref:
        assert np.min(np.abs(w - wr)) / wr < 1e-4, (wr, w[:5])


def test_line_of_action_geometry(make):
    """n is tangent to both base circles (through the pitch point), the reaction on the driver
    resists its rotation, and the kinematic gear rotation leaves delta unchanged."""
    for rotation in ("ccw", "cw"):
        for angle in (0.0, 2.0):
            box = _box(make(angle=angle, rotation=rotation))
            m = box.meshes[0]
            cd, cf = box.rotors[m.driver[0]].center, box.rotors[m.driven[0]].center
            a = np.hypot(*(cf - cd))
            rb_d, rb_f = m.radius
            pitch = cd + (cf - cd) * rb_d / (rb_d + rb_f)  # pitch point divides a in the base-radius ratio
            n = m.normal

            def arm(c, n=n, pitch=pitch):
                v = pitch - c
                return v[0] * n[1] - v[1] * n[0]  # z moment of a unit force along n through the pitch point

            assert abs(arm(cd)) == pytest.approx(rb_d, rel=1e-12)
            assert abs(arm(cf)) == pytest.approx(rb_f, rel=1e-12)
            s = box.rotors[m.driver[0]].sense
            assert np.sign(arm(cd) * -1) == -s  # -F n on the driver: torque against its sense s
            assert np.sign(arm(cf)) == -s  # +F n on the driven gear: with its sense -s
            g = coupling_vector(box, 0)
            q = np.zeros(box.n_dof)
            eps = 1e-3
            q[box.torsion_dof(*m.driver)] = s * eps
            q[box.torsion_dof(*m.driven)] = -s * eps * rb_d / rb_f
            assert abs(g @ q) < 1e-15
            q[:] = 0
            q[box.torsion_dof(*m.driver)] = s * eps  # driver ahead of the driven gear: compression
            assert g @ q == pytest.approx(rb_d * eps)
            assert a == pytest.approx(m.gear.center_distance)


@pytest.mark.parametrize("angle", [0.9, 2.5, -1.3])
def test_mounting_angle_does_not_change_frequencies(make, angle):
    """Isotropic bearings: rotating the whole gearbox in its plane changes nothing physical."""
    w0 = modal(_box(make()), 300.0, 12).wd[0]
    w1 = modal(_box(make(angle=angle)), 300.0, 12).wd[0]
    np.testing.assert_allclose(w1, w0, rtol=1e-9)


def test_sense_of_rotation_mirror(make):
    """Reversing every rotation mirrors the gearbox (y -> -y): the same frequencies."""
    w0 = modal(_box(make()), 300.0, 12).wd[0]
    w1 = modal(_box(make(rotation="cw")), 300.0, 12).wd[0]
    np.testing.assert_allclose(w1, w0, rtol=1e-9)


def test_energy_split_and_campbell_tracking(make):
    box = _box(make())
    m = modal(box, 200.0, 10)
    np.testing.assert_allclose(m.energy.sum(-1), 1.0, rtol=1e-12)
    assert np.all((m.mesh_energy >= 0) & (m.mesh_energy <= 1 + 1e-12))
    c = campbell(box, np.linspace(10.0, 600.0, 12), 8, reduce=False)
    np.testing.assert_allclose(
        c.modes.wd[3], modal(box, c.modes.speed[3], 8).wd[0][np.argsort(np.argsort(c.modes.wd[3]))], rtol=1e-9
    )
    # every crossing lies on its line
    lines = {ln["name"]: ln["factor"] for ln in c.lines}
    for cr in c.crossings:
        assert cr["frequency"] == pytest.approx(lines[cr["line"]] * cr["speed"])


def test_ross_multirotor_documentation_example():
    """ROSS's MultiRotor documentation example (petrobras/ross, ``rs.MultiRotor`` docstring:
    Rao, Shiau & Chang 1998 turbo-generator, mesh stiffness 1e8 N/m, 22.5 deg, orientation 0)
    gives its first damped natural frequency at speed 0 as 74.160244 rad/s. Our model differs
    only in the gear geometry (module 3.3375 mm instead of pitch diameters 1.1 / 0.077 m: base
    radii within 0.5 %) and has no axial DOFs (uncoupled from the spur mesh)."""
    from pathlib import Path

    box = Gearbox.from_toml(Path(__file__).resolve().parents[2] / "examples/system/ross_two_shaft.toml")
    wd = modal(box, 0.0, 4).wd[0]
    assert wd[0] == pytest.approx(74.160244, rel=1e-4)
