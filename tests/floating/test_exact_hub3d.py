"""The 3-D exact beam on a free hub turning about a fixed axis, driven by a torque slew.

Independent references: the planar exact beam's free hub (a second formulation) for a slew
about z of a point-symmetric hub (whose centre then stays put, so the planar free hub and the
3-D hub on its bearing are the same system); the angular-momentum theorem about the fixed
axis (``H_a(t) = int tau dt``, closed form for the bang-bang torque); the work-energy balance
and its observed order under step halving; the modal body's torque slew (small-deflection
limit, docs/floating.md).
"""

from __future__ import annotations

import copy

import numpy as np
import pytest

from rotaflex.core.errors import InputError
from rotaflex.core.threads import limit_blas_threads
from rotaflex.floating.case import prepare, run_case
from rotaflex.floating.exact_case3d import run
from rotaflex.rotation import quaternion_to_matrix

AXIS = np.array([1.0, 2.0, 2.0]) / 3.0  # an oblique slew axis (unit)

STRIP = {"length": 1.0, "e": 70e9, "rho": 2700.0, "width": 0.02, "thickness": 0.002, "n_modes": 4}
HUB = {
    "body": {
        "type": "hub",
        "model": "exact",
        "hub": {
            "mass": 5.0,
            "inertia": [0.05, 0.05, 0.05],
            "radius": 0.05,
            "appendages": [
                dict(STRIP, root=[0.05, 0.0, 0.0], direction=[1.0, 0.0, 0.0]),
                dict(STRIP, root=[-0.05, 0.0, 0.0], direction=[-1.0, 0.0, 0.0]),
            ],
        },
        "exact": {"elements": 4, "rho_inf": 1.0, "time_step": 0.02},
    },
    "slew": {"angle_deg": 60.0, "duration": 1.0, "profile": "versine", "drive": "torque"},
    "solver": {"t_end": 1.2, "dt_out": 0.2},
    "outputs": {"tip": [1.05, 0.0, 0.0]},
}


@pytest.fixture(autouse=True, scope="module")
def _one_blas_thread():
    with limit_blas_threads():
        yield


def hub_case(dimension=3, **edit) -> dict:
    cfg = copy.deepcopy(HUB)
    cfg["body"]["exact"]["dimension"] = dimension
    for key, value in edit.items():
        cfg[key].update(value)
    return cfg


def test_slew_about_z_is_the_planar_exact_hub():
    # 60 deg in 1 s: the tips bend 0.1 L. Same elements and generalized-alpha in the plane; the
    # clamps differ (planar: index-3 multipliers, the clamped nodes' velocities from the
    # Newmark formulas; 3-D: eliminated, their velocities the hub's exactly), an O(h^2)
    # difference: measured 4.6e-7 rad on the hub and 4.2e-7 m on the tip at h = 0.02 s
    # (1.1e-7 and 9.6e-8 at 0.01 s)
    out = {dim: run_case(hub_case(dim)).dataset.isel(solution=0) for dim in (2, 3)}
    d2, d3 = out[2], out[3]
    assert np.abs(d2["position"].values).max() < 1e-12  # the planar free hub's centre stays put
    angle2 = d2["euler_123"].values[:, 2]
    assert angle2.max() > 0.8  # turned about 60 deg (1.05 rad) and overshooting
    assert np.abs(d3["hub_angle"].values - angle2).max() < 1e-6
    tip2 = d2["point_position"].sel(point="tip").values
    tip3 = d3["point_position"].sel(point="tip").values
    assert np.abs(d2["point_deflection"].sel(point="tip").values).max() > 0.08
    assert np.abs(tip3 - tip2).max() < 1e-6
    assert np.abs(tip3[:, 2]).max() < 1e-12  # stays in the plane
    assert np.abs(d3["hub_rate"].values - d2["angular_velocity"].values[:, 2]).max() < 1e-5
    # the same energy balance (torque's work in work_of_loads)
    assert np.abs(d3["work_of_loads"].values - d2["work_of_loads"].values).max() < 1e-6


def test_motion_slew_of_the_hub_is_the_planar_exact_hub():
    # drive = "motion": the hub follows the versine profile; the clamps' O(h^2) difference as
    # above (measured 3.9e-7 m on the tip at h = 0.02 s). The hub's kinetic energy is the
    # drive's work on it in both (measured difference in work_of_drive 2.6e-4 of its peak)
    out = {dim: run_case(hub_case(dim, slew={"drive": "motion"})).dataset.isel(solution=0) for dim in (2, 3)}
    d2, d3 = out[2], out[3]
    assert np.abs(d3["euler_123"].values[:, 2] - d2["euler_123"].values[:, 2]).max() < 1e-12
    assert np.abs(d2["point_deflection"].sel(point="tip").values).max() > 0.1
    assert np.abs(d3["point_position"].values - d2["point_position"].values).max() < 1e-6
    w2, w3 = d2["work_of_drive"].values, d3["work_of_drive"].values
    assert np.abs(w3 - w2).max() < 1e-3 * w2.max()
    assert np.abs(d3["energy_balance"].values).max() < 1e-3 * w2.max()


#: a torque on the hub off the slew axis, turning with the hub (its component along the axis
#: acts: 0.02 (1, 2, 2)/3 . (1, 0, 0) = 0.00667 N m), and a force fixed in space on the tip
HUB_TORQUE = {"kind": "torque", "point": [0.0, 0.0, 0.0], "vector": [0.02, 0.0, 0.0], "frame": "body"}
TIP_FORCE = {"kind": "force", "point": [1.05, 0.0, 0.0], "vector": [0.0, 0.0, 0.01], "frame": "inertial"}


def oblique(h: float, profile: str, loads=()):
    """One strip on the hub slewed 30 deg in 1 s about the oblique axis: it bends in and out of
    the slew plane and twists. Returns the case, the solution and the hub drive."""
    cfg = hub_case(
        slew={"axis": list(AXIS), "profile": profile, "angle_deg": 30.0},
        solver={"t_end": 1.2, "dt_out": 0.1},
    )
    cfg["loads"] = [dict(ld) for ld in loads]
    cfg["body"]["hub"]["appendages"].pop()
    cfg["body"]["exact"].update(elements=3, time_step=h)
    case, _, plan = prepare(cfg)
    return case, run(case, plan)[0], plan


def axial_momentum(plan, sol) -> np.ndarray:
    """Angular momentum of hub and beam about the fixed axis (T,) [kg m^2/s]: ``a . (sum x x
    M_t v + sum R J W) + J_hub phi'`` (consistent translational mass, lumped rotary inertia)."""
    beam, hub = plan["beam"], plan["hub"]
    n, M = beam.n_nodes, beam.mass_matrix()
    out = []
    for q, v, state in zip(sol.q, sol.v, sol.hub, strict=True):
        p = (M @ v).reshape(-1, 6)[:n]
        blocks = q.reshape(-1, 7)[:n]
        spin = np.einsum("bij,bj->i", quaternion_to_matrix(blocks[:, 3:]), p[:, 3:])
        out.append(hub.axis @ (np.cross(blocks[:, :3], p[:, :3]).sum(axis=0) + spin) + hub.inertia * state[1])
    return np.array(out)


def test_oblique_slew_angular_momentum_is_the_torque_impulse():
    # bang-bang torque +T on [0, 0.5), -T on [0.5, 1): impulse T min(t, 1 - t), 0 after. The
    # step onto the switch sees +T and the next restarts from -T, so the impulse is exact and
    # the rest is the integrator's O(h^2): measured 5.7e-5 / 1.2e-5 of the peak at h = 0.02 / 0.01
    # plus a constant torque on the hub off the axis: impulse (a . tau) t
    case, sol, plan = oblique(0.02, "bang-bang", [HUB_TORQUE])
    hub = plan["hub"]
    assert np.allclose(hub.axis, AXIS, atol=1e-15)
    assert hub.inertia == pytest.approx(AXIS**2 @ np.array([0.05, 0.05, 0.05]))
    T = hub.torque[-1]  # the slew's torque comes last
    t = sol.time
    tau = AXIS @ np.array(HUB_TORQUE["vector"])
    impulse = T * np.clip(np.minimum(t, 1.0 - t), 0.0, None) + tau * t
    # the slew torque of a rigid body turned on its bearing: 4 angle / duration^2 times the
    # inertia about the axis (hub + the strip's B^T M B; the torque comes from the modal body's)
    beam = plan["beam"]
    from rotaflex.floating.exact_solve3d import frame_state

    B = frame_state(beam, AXIS, 0.0, 1.0, 0.0)[1]
    j_rigid = hub.inertia + B @ beam.mass_matrix() @ B
    assert T == pytest.approx(4.0 * np.radians(30.0) * j_rigid, rel=1e-4)  # measured 2.3e-5
    assert sol.hub[:, 2] == pytest.approx(np.where(t < 0.5, T, np.where(t < 1.0, -T, 0.0)) + tau)
    # the strip left the slew plane (bending out of it and twisting)
    tip = sol.q[-1].reshape(-1, 7)[beam.n_nodes - 1, :3]
    assert abs(np.dot(tip, AXIS) - np.dot(beam.nodes[-1], AXIS)) > 1e-4
    err = np.abs(axial_momentum(plan, sol) - impulse).max()
    assert err < 2e-4 * np.abs(impulse).max()


def test_oblique_slew_energy_balance_is_second_order():
    # versine torque: kinetic + strain energy = the work of the torque and of the tip force;
    # the balance error falls with h^2 (measured 5.5e-6, 1.2e-6, 3.0e-7, 7.3e-8 J at h = 0.02
    # ... 0.0025 s: ratios 4.58, 4.02, 4.12; the bearing does no work)
    errs = []
    for h in (0.02, 0.01):
        _, sol, _ = oblique(h, "versine", [TIP_FORCE])
        errs.append(np.abs(sol.balance).max())
        assert np.all(sol.energy[:, 3] == 0.0)
    peak = np.abs(sol.energy[:, 2]).max()
    assert peak > 0.01  # the torque did work
    assert errs[1] < 1e-4 * peak
    assert 3.2 < errs[0] / errs[1] < 5.0, errs


APP = {"length": 1.0, "e": 1e4, "rho": 1.0, "area": 1.0, "second_moment": 1e-4, "n_modes": 4}
SMALL_SLEW = {
    "body": {
        "type": "hub",
        "hub": {
            "mass": 1.0,
            "inertia": [1.0, 1.0, 1.0],
            "radius": 0.1,
            "appendages": [
                dict(APP, root=[0.1, 0.0, 0.0], direction=[1.0, 0.0, 0.0]),
                dict(APP, root=[-0.1, 0.0, 0.0], direction=[-1.0, 0.0, 0.0]),
            ],
        },
    },
    "slew": {"angle_deg": 0.1, "duration": 3.0, "profile": "versine", "drive": "torque"},
    "solver": {"t_end": 4.0, "dt_out": 0.25, "rtol": 1e-10, "atol": 1e-13, "method": "full"},
    "outputs": {"tip": [1.1, 0.0, 0.0]},
}


def test_small_slow_slew_is_the_modal_hub():
    # EI = 1 N m^2, 1 kg/m strips on a 1 kg m^2 hub, 0.1 deg in 3 s (first clamped period 1.8
    # s): tip deflection 2e-4 L, the small-deflection limit. The modal body (4 modes per
    # strip) is converged in its modes; the difference is the exact beam's mesh and step
    # error: measured 4.2 % (4 elements) of the peak deflection, the hub angle 1.8e-3 (4, 8,
    # 16 elements at h = 0.005 s: 4.3 %, 0.84 %, 0.17 %, observed order 2.3)
    cfg = copy.deepcopy(SMALL_SLEW)
    cfg["body"]["model"] = "modal"
    modal = run_case(cfg).dataset.isel(solution=0)
    um = modal["point_deflection"].sel(point="tip").values
    am = modal["euler_123"].values[:, 2]
    peak = np.abs(um).max()
    assert 1e-4 < peak < 1e-3
    cfg = copy.deepcopy(SMALL_SLEW)
    cfg["body"]["model"] = "exact"
    cfg["body"]["exact"] = {"dimension": 3, "elements": 4, "rho_inf": 1.0, "time_step": 0.02}
    cfg["solver"] = {"t_end": 4.0, "dt_out": 0.25}
    exact = run_case(cfg).dataset.isel(solution=0)
    ue = exact["point_deflection"].sel(point="tip").values
    assert np.abs(ue[:, :2] - um[:, :2]).max() < 0.05 * peak
    assert np.abs(ue[:, 2]).max() == 0.0
    assert np.abs(exact["hub_angle"].values - am).max() < 3e-3 * np.abs(am).max()


@pytest.mark.parametrize(
    ("edit", "key"),
    [
        ({"body.hub.inertia": [0.0, 0.05, 0.05]}, "body.hub.inertia"),
        ({"loads": [{"kind": "force", "vector": [1.0, 0.0, 0.0]}]}, "loads[0].kind"),
        ({"slew": None}, "slew"),
        ({"body.exact.analysis": "both"}, "body.exact.analysis"),
        ({"body.exact.rho_i": 1e-3}, "body.exact.rho_i"),
        ({"body.exact.bend_radius": 2.0}, "body.exact.bend_radius"),
        ({"outputs.tip": [0.0, 0.0, 0.0]}, "outputs.tip"),
        ({"outputs.tip": [1.05, 0.1, 0.0]}, "outputs.tip"),
        ({"body.hub.appendages": []}, "body.hub.appendages"),
        ({"body.damping_ratio": 0.01}, "body.damping_ratio"),
    ],
)
def test_bad_hub_input_names_the_key(edit, key):
    cfg = hub_case()
    for path, value in edit.items():
        *head, last = path.split(".")
        node = cfg
        for p in head:
            node = node[p]
        if value is None:
            node.pop(last)
        else:
            node[last] = value
    with pytest.raises(InputError) as err:
        prepare(cfg)
    assert err.value.field == key


def test_hub_drive_needs_inertia_about_its_axis():
    from rotaflex.floating.exact_solve3d import HubDrive

    with pytest.raises(InputError) as err:
        HubDrive(axis=np.array([0.0, 0.0, 1.0]), inertia=0.0)
    assert err.value.field == "body.hub.inertia"


def test_example_slews_the_hub_by_the_rigid_body_torque():
    import tomllib
    from pathlib import Path

    path = Path(__file__).resolve().parents[2] / "examples" / "floating" / "hub_slew_3d_exact.toml"
    cfg = tomllib.loads(path.read_text())
    cfg.pop("domain")
    cfg["solver"].update(t_end=0.1, dt_out=0.05)
    case, _, plan = prepare(cfg)
    hub = plan["hub"]
    a = np.array([0.0, 0.6, 0.8])
    # closed form: hub a.I.a plus two strips along +-x from 0.05 to 1.05 m, |a x x|^2 = x^2
    rho_a = 2700.0 * 0.02 * 0.002
    j_rigid = 0.05 + 2.0 * rho_a * (1.05**3 - 0.05**3) / 3.0
    assert hub.inertia == pytest.approx(0.05)
    assert hub.torque[0] == pytest.approx(j_rigid * 4.0 * np.radians(60.0), rel=1e-9)  # measured 9e-16
    assert np.allclose(hub.axis, a)
    ds = run_case(cfg).dataset.isel(solution=0)
    # from rest the strips lag behind the hub: it turns faster than the rigid body and slower
    # than the hub alone, T t^2 / (2 J_rigid) < phi < T t^2 / (2 J_hub) (measured 0.0209 <
    # 0.0322 < 0.0559 rad at 0.1 s)
    phi = ds["hub_angle"].values[-1]
    assert hub.torque[0] * 0.1**2 / (2.0 * j_rigid) < phi < hub.torque[0] * 0.1**2 / (2.0 * hub.inertia)
    assert ds["hub_torque"].values[0] == pytest.approx(hub.torque[0])
