"""``rotaflex system static``: the machine's static state against the rotor verb, the one-piece
rotor of a rigid train, closed forms (T / r_b, the lever rule) and force and moment balance."""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest

from rotaflex.core.errors import InputError
from rotaflex.rotor.fe.static import STANDARD_GRAVITY
from rotaflex.system.case import run_static
from rotaflex.system.model import Gearbox
from rotaflex.system.static import machine_static

G = STANDARD_GRAVITY


def _rotor():
    """A stepped shaft on three bearings (statically indeterminate), a disk and an overhang."""
    return {
        "shaft": [
            {"outer_diameter": 0.05, "length": 0.4, "elements": 4},
            {"outer_diameter": 0.04, "length": 0.3, "elements": 3},
        ],
        "disk": [{"node": 2, "mass": 8.0, "Id": 0.04, "Ip": 0.07}, {"node": 7, "mass": 3.0, "Id": 0.01, "Ip": 0.02}],
        "bearing": [
            {"node": 0, "kxx": 2e7, "kyy": 3e7, "kxy": 1e6},
            {"node": 3, "kxx": 5e7, "kyy": 4e7},
            {"node": 5, "kxx": 1e8, "kyy": 1e8},
        ],
    }


def _balance(rotor, st, g, loads=()):
    """Force (2,) [N] and moment (2,) [N m] about z = 0 of everything acting on a rotor: the
    consistent weight M r g (its rotations carry the weight's moment exactly), point loads,
    bearing reactions and the external forces and couples, each as the work in a rigid
    translation (x, y) or rotation (about x: y = -z, theta_x = 1; about y: x = z, theta_y = 1)."""
    n, z = rotor.n_rotor_dof, rotor.nodes
    r = np.zeros(rotor.n_dof)
    r[0:n:4], r[1:n:4] = g
    f = (rotor.M @ r)[:n].reshape(-1, 4)
    for node, fx, fy in loads:
        f[node, :2] += (fx, fy)
    for b, (node, _, _) in enumerate(rotor.bearings):
        f[node, :2] += st.reactions[b]
    f += st.external
    force = f[:, :2].sum(0)
    moment = np.array([np.sum(-f[:, 1] * z + f[:, 2]), np.sum(f[:, 0] * z + f[:, 3])])
    return force, moment


def test_one_rotor_machine_equals_the_rotor_verb():
    """Deflection, reactions, shear, moment and stress of a one-rotor machine are the rotor
    verb's to 1e-9 (oblique gravity, a point load, cross-coupled bearings)."""
    from rotaflex.rotor.fe.verbs import run_static as rotor_static

    static = {"gravity": 9.81, "gravity_direction": [0.3, -1.0], "load": [{"node": 6, "fx": 120.0, "fy": -40.0}]}
    a = rotor_static({**_rotor(), "static": static}).dataset
    machine = {
        "rotor": [{"name": "r", "center": [0.0, 0.0], **_rotor()}],
        "drive": {"rotor": "r", "node": 0},
        "static": static,
    }
    b = run_static(machine).dataset
    assert b.attrs["status"] == "success"
    for v in ("deflection", "reaction", "shear", "moment", "stress", "deflection_curve"):
        scale = np.abs(a[v].values).max()
        np.testing.assert_allclose(b[v].values, a[v].values, rtol=0, atol=1e-9 * scale, err_msg=v)
    assert not b["external_force"].values.any()


def _film(node, name):
    """A short (Ocvirk) journal bearing whose load comes from the static analysis."""
    film = {"diameter": 0.06, "length": 0.03, "clearance": 6e-5, "viscosity": 0.02, "load": "static"}
    return {
        "name": name,
        "node": node,
        "fluid_film": {**film, "speed_rpm": [500, 12000], "n_speeds": 4, "model": "short"},
    }


def test_film_bearings_on_three_supports_iterate_as_the_rotor_verb():
    """Three journal bearings with ``load = "static"`` (statically indeterminate: the loads
    depend on the film stiffness, which depends on the loads): the machine's iteration reaches
    the rotor verb's fixed point, deflections and reactions to 1e-8."""
    from rotaflex.rotor.fe.verbs import run_static as rotor_static

    rotor = {
        "shaft": [{"outer_diameter": 0.06, "length": 1.2, "elements": 8}],
        "disk": [{"node": 2, "mass": 60.0, "Id": 0.5, "Ip": 0.9}, {"node": 6, "mass": 40.0, "Id": 0.3, "Ip": 0.5}],
        "bearing": [_film(0, "a"), _film(4, "b"), _film(8, "c")],
    }
    static = {"speed_rpm": 3000.0, "load": [{"node": 6, "fx": 200.0}]}
    a = rotor_static({**copy.deepcopy(rotor), "static": static}).dataset
    b = run_static(
        {"rotor": [{"name": "r", "center": [0.0, 0.0], **rotor}], "drive": {"rotor": "r", "node": 0}, "static": static}
    ).dataset
    assert b.attrs["status"] == "success"
    for v in ("deflection", "reaction", "moment"):
        np.testing.assert_allclose(b[v].values, a[v].values, rtol=0, atol=1e-8 * np.abs(a[v].values).max(), err_msg=v)


def _train(coupling, drive="constant_speed"):
    """Motor (4 elements, bearings 0, 3) coupled at its node 4 to a pump (3 elements, bearings 1, 3) at node 0."""

    def rotor(name, d, length, n_el, bearings):
        return {
            "name": name,
            "center": [0.0, 0.0],
            "shaft": [{"outer_diameter": d, "length": length, "elements": n_el}],
            "disk": [{"node": 2, "mass": 8.0, "Id": 0.04, "Ip": 0.07}],
            "bearing": [{"node": n, "kxx": 2e7, "kyy": 3e7} for n in bearings],
        }

    return {
        "rotor": [rotor("motor", 0.05, 0.4, 4, (0, 3)), rotor("pump", 0.04, 0.3, 3, (1, 3))],
        "coupling": [{"rotor_a": "motor", "node_a": 4, "rotor_b": "pump", "node_b": 0, **coupling}],
        "drive": {"rotor": "motor", "node": 0, "kind": drive},
    }


@pytest.mark.parametrize("drive", ["constant_speed", "torque"])
def test_rigid_train_equals_one_continuous_rotor(drive):
    """A rigid coupling makes the two rotors one: deflections, reactions and the shear and
    moment diagrams of both rotors (the pump's carried over the coupling as the external force
    and couple at its node 0) equal the rotor built in one piece to 1e-6."""
    from rotaflex.rotor.fe.model import Rotor
    from rotaflex.rotor.fe.static import static_analysis

    cfg = _train({"rigid": True}, drive)
    box = Gearbox.from_mapping(cfg)
    s = machine_static(box, gravity=G, direction=(0.2, -1.0), loads=[(1, 3, 50.0, 0.0)], speed=0.0)
    one = copy.deepcopy(cfg["rotor"][0])
    del one["name"], one["center"]
    one["shaft"].append({"outer_diameter": 0.04, "length": 0.3, "elements": 3})
    one["disk"].append({"node": 6, "mass": 8.0, "Id": 0.04, "Ip": 0.07})
    one["bearing"] += [{"node": n, "kxx": 2e7, "kyy": 3e7} for n in (5, 7)]
    ref = static_analysis(Rotor.from_mapping(one), direction=(0.2, -1.0), loads=[(7, 50.0, 0.0)])
    motor, pump = s.rotors
    defl = np.concatenate([motor.q[:20], pump.q[4:]])  # pump node 0 is motor node 4
    np.testing.assert_allclose(defl, ref.q, rtol=0, atol=1e-6 * np.abs(ref.q).max())
    np.testing.assert_allclose(np.concatenate([motor.reactions, pump.reactions]), ref.reactions, rtol=1e-6)
    for key in ("shear", "moment"):
        got = np.concatenate([getattr(motor, key), getattr(pump, key)])
        want = getattr(ref, key)
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-6 * np.abs(want).max(), err_msg=key)
    for rotor, st, ld in ((box.rotors[0].rotor, motor, ()), (box.rotors[1].rotor, pump, [(3, 50.0, 0.0)])):
        g = G * np.array([0.2, -1.0]) / math.hypot(0.2, 1.0)
        force, moment = _balance(rotor, st, g, ld)
        assert np.abs(force).max() < 1e-9 * rotor.mass * G
        assert np.abs(moment).max() < 1e-9 * rotor.mass * G * rotor.nodes[-1]


def test_coupling_without_lateral_stiffness_carries_no_weight():
    """A coupling stiff in torsion only: each rotor's bearings carry its own weight (its hub's
    share of the coupling mass included) and nothing crosses the coupling."""
    cfg = _train({"torsional_stiffness": 1e4, "mass": 6.0, "split": 0.5})
    box = Gearbox.from_mapping(cfg)
    s = machine_static(box, gravity=G, speed=0.0)
    for pr, st in zip(box.rotors, s.rotors, strict=True):
        assert pr.rotor.disks[-1][1].mass == pytest.approx(3.0)  # the hub: half the coupling
        np.testing.assert_allclose(st.reactions.sum(0), [0.0, pr.rotor.mass * G], rtol=1e-12, atol=1e-9)
        assert np.abs(st.external).max() < 1e-9 * pr.rotor.mass * G


def _gears(make, torque=100.0):
    """conftest's 20/40 spur pair with the gears at node 2 of bearings at nodes 1 and 5 (unequal arms)."""
    cfg = make(drive="constant_speed")
    m = cfg["gear_mesh"][0]
    m["pinion_node"] = m["wheel_node"] = 2
    cfg["load"]["torque"] = torque
    return cfg


@pytest.mark.parametrize(("torque", "film"), [(100.0, False), (400.0, False), (400.0, True)])
def test_spur_pair_mesh_force_and_lever_rule(make, torque, film):
    """Mesh force = T / r_b of the wheel (r_b = m z cos(20 deg) / 2) along the line of action
    (working pressure angle of the 0.0901 m centre distance); on each shaft the two
    bearing reactions are the lever-rule split (bearings at z = 0.04, 0.20 m) of every disk's
    weight at its node, the uniform shaft's weight at mid-length and the mesh force at the gear."""
    cfg = _gears(make, torque)
    if film:  # journal bearings loaded by the static state: the mesh force sets their loads
        for r in cfg["rotor"]:
            r["bearing"] = [_film(1, "a"), _film(5, "b")]
    box = Gearbox.from_mapping(cfg)
    s = machine_static(box, gravity=G, speed=300.0 if film else 0.0)
    rb = 3e-3 * 40 * math.cos(math.radians(20.0)) / 2
    assert s.mesh_force[0] == pytest.approx(torque / rb, rel=1e-9)
    m = box.meshes[0]
    # line of action at the working pressure angle: cos(alpha_w) = (r_b1 + r_b2) / a, centres along x
    assert abs(m.normal[1]) == pytest.approx(1.5 * rb / 0.0901, rel=1e-12)
    za, zb = 0.04, 0.20
    for r, pr in enumerate(box.rotors):
        rotor = pr.rotor
        loads = [(rotor.nodes[n], el.mass * np.array([0.0, -G])) for n, el in rotor.disks]
        shaft = rotor.mass - sum(el.mass for _, el in rotor.disks)
        loads.append((0.12, shaft * np.array([0.0, -G])))
        side = 1.0 if r == m.driven[0] else -1.0  # +F n on the driven gear, -F n on the driver
        loads.append((rotor.nodes[2], side * s.mesh_force[0] * m.normal))
        want = np.zeros((2, 2))
        for zl, F in loads:
            want[0] -= F * (zb - zl) / (zb - za)
            want[1] -= F * (zl - za) / (zb - za)
        np.testing.assert_allclose(s.rotors[r].reactions, want, rtol=1e-9, atol=1e-9 * np.abs(want).max())
        if film:  # converged: each film carries the load the static state puts on it
            got = np.array([b.fluid_film.load for b in s.box.rotors[r].rotor.bearing])
            np.testing.assert_allclose(got, -want, rtol=0, atol=1e-9 * np.abs(want).max())
            alone = np.array([b.fluid_film.load for b in rotor.resolved.bearing])  # the rotor's own weight only
            assert np.abs(alone + want).max() > 0.5 * np.abs(want).max()
        force, moment = _balance(rotor, s.rotors[r], np.array([0.0, -G]))
        assert np.abs(force).max() < 1e-9 * np.abs(want).max()
        assert np.abs(moment).max() < 1e-9 * np.abs(want).max() * 0.24


def test_helical_mesh_couples_are_the_axial_force_moments():
    """A helical mesh's axial force at the pitch point tilts each gear: the couple on each
    rotor at its gear node equals system/helical's tilting moment ``F_a r_w`` (a second
    formulation, from the mesh force alone) to 1e-9, and the mesh force is helical.static_state's."""
    from rotaflex.core.examples import example_path
    from rotaflex.system import helical

    box = Gearbox.from_toml(example_path("system/helical_gearbox.toml"))
    s = machine_static(box, gravity=G, speed=300.0)
    assert s.mesh_force == pytest.approx(helical.static_state(box, 300.0)[1], rel=1e-9)
    tm = helical.tilting_moments(box, s.mesh_force)[0]
    m = box.meshes[0]
    for k, (r, node) in enumerate((m.driver, m.driven)):
        np.testing.assert_allclose(s.rotors[r].external[node, 2:], tm[k], rtol=0, atol=1e-9 * np.abs(tm).max())
    assert np.abs(tm).max() > 10.0  # N m: the couple is there to be checked


def test_example_runs_with_balanced_rotors_and_a_figure_per_rotor():
    """examples/system/motor_coupling_pump.toml: the verb's checks pass, the coupling's force on
    the motor is the opposite of that on the pump, and plot() draws the rotor verb's figure per rotor."""
    from rotaflex.core.config import load_toml
    from rotaflex.core.examples import example_path

    res = run_static(load_toml(example_path("system/motor_coupling_pump.toml")))
    ds = res.dataset
    assert ds.attrs["status"] == "success"
    ext = ds["external_force"].values
    on_motor = ext[ds["node_rotor"].values == "motor"].sum(0)
    on_pump = ext[ds["node_rotor"].values == "pump"].sum(0)
    np.testing.assert_allclose(on_motor, -on_pump, atol=1e-9 * np.abs(on_pump).max())
    assert abs(on_pump[1]) > 1.0  # the hub weights and the pump's overhang load the coupling
    figs = res.plot()
    assert set(figs) >= {"static_motor", "static_pump"}
    line = figs["static_pump"].axes[2].lines[0]  # M in the y-z plane
    pump = ds.isel(cut=ds["cut_rotor"].values == "pump")
    np.testing.assert_array_equal(line.get_ydata(), pump["moment"].sel(axis="y").values)


@pytest.mark.parametrize(
    ("load", "key"),
    [
        ({"rotor": "fan", "node": 1, "fy": 1.0}, "static.load[1].rotor"),
        ({"rotor": "pump", "node": 9}, "static.load[1].node"),
    ],
)
def test_bad_load_names_its_key(load, key):
    cfg = _train({"torsional_stiffness": 1e4})
    cfg["static"] = {"load": [{"rotor": "motor", "node": 1, "fy": 5.0}, load]}
    with pytest.raises(InputError) as err:
        run_static(cfg)
    assert err.value.field == key


def test_film_bearings_at_rest_are_refused():
    """A journal bearing loaded by the static state needs a speed: 0 rpm names static.speed_rpm."""
    cfg = _train({"torsional_stiffness": 1e4})
    cfg["rotor"][1]["bearing"] = [_film(1, "a"), _film(3, "b")]
    cfg["static"] = {"speed_rpm": 0.0}
    with pytest.raises(InputError) as err:
        run_static(cfg)
    assert err.value.field == "static.speed_rpm"
