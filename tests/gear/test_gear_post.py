"""Gear post-processing and options: DTE, fillet stress, driver choice, restitution, sweep panel."""

import json
import math
from dataclasses import replace

import numpy as np
import pytest

from rotaflex.core.errors import InputError
from rotaflex.core.units import rpm_to_rad_s
from rotaflex.gear.kernels.contact import flank_weights
from rotaflex.gear.models import fe_pair as dynamics
from rotaflex.gear.pair.geometry import GearGeometry, contact_angles
from rotaflex.gear.pair.tooth_mesh import COARSE, build_tooth_mesh
from rotaflex.gear.results import post
from rotaflex.gear.static.tooth_analysis import flank_contact_point

E, NU = 210e9, 0.3


@pytest.fixture(scope="module")
def gear():
    g = GearGeometry(module=3.175e-3, teeth=28, face_width=6.35e-3, tip_radius=0.047625, root_radius=0.04048)
    return g, build_tooth_mesh(g, **COARSE)


def _model(gear):
    g, m = gear
    return dynamics.build_model(
        g, g, m, m, youngs_modulus=E, poisson_ratio=NU, density=7800.0, inertia=(2.965e-4, 2.965e-4)
    )


def test_quasi_static_dte_and_root_stress_match_static_fe(gear):
    """In the single-pair zone the DTE equals the static FE deflection of the same point load
    plus the unloaded kinematic error of the discretised profiles, and the fillet stress equals
    the static FE fillet stress of that load (tooth inertia negligible at 4000 rpm)."""
    g, _ = gear
    mod = _model(gear)
    ths, th2 = contact_angles(g, g)
    probe = post.root_stress_probe(mod, E, NU)
    out = dynamics.simulate(
        mod,
        speeds=rpm_to_rad_s((4000.0, 4000.0)),
        torque=22.25,
        theta_2=th2,
        theta_s=ths,
        span=math.radians(9.6),
        dt=3e-8,
        record_every=20,
        record_nodes=probe.nodes,
    )
    r = out.records
    sig = post.root_stress_history(mod, probe, out.node_positions, np.column_stack([r["phi_A"], r["phi_B"]]))
    rb = g.base_radius
    dte = post.transmission_error(r["phi_A"], -r["phi_B"], rb, rb)
    picks = np.nonzero(r["phi_A"] > th2 + math.radians(0.5))[0][::8]
    assert picks.size >= 3
    for i in picks:
        f = r["force"][i]
        assert f > 400.0
        normals = []
        for c, cen in (("cpA", 0), ("cpB", 1)):
            rad = np.hypot(r[f"{c}_x"][i] - mod.centres[cen, 0], r[f"{c}_y"][i] - mod.centres[cen, 1])
            normals.append(flank_contact_point(g, min(rad, g.tip_radius_), "left")[1])
        te = post.static_point_load_te(mod, E, NU, f, r["param_a"][i], r["param_b"][i], normals)
        kin = post.kinematic_transmission_error(mod, [r["phi_A"][i]])[0]
        assert dte[i] == pytest.approx(te + kin, rel=0.02)
        for gi, par in ((0, r["param_a"][i]), (1, r["param_b"][i])):
            ref = post.static_root_stress(mod, E, NU, f, par, normals[gi], gear=gi)
            assert ref[0] > 0 > ref[1]  # loaded fillet in tension, the other in compression
            np.testing.assert_allclose(sig[i, gi], ref, rtol=0.04)


def test_kinematic_error_vanishes_at_start_and_stays_sub_micron(gear):
    mod = _model(gear)
    te = post.kinematic_transmission_error(mod, np.radians([0.0, 2.0, 10.0, 20.0]))
    assert abs(te[0]) < 1e-12
    assert np.all(np.abs(te) < 1e-6)  # coarse quadratic edges: profile error < 1 um


def _impact(gear, e, dt=1e-8):
    """Gears 0.05 um apart approaching at ~0.06 m/s (no torque): one impact."""
    g, _ = gear
    mod = _model(gear)
    # open the initial contact
    mod = replace(mod, theta0=mod.theta0 - np.array([0.0, 0.05e-6 / g.base_radius]))
    out = dynamics.simulate(
        mod,
        speeds=rpm_to_rad_s((4000.0, 3990.0)),
        torque=0.0,
        theta_2=0.14,
        theta_s=0.37,
        span=math.radians(0.05),
        dt=dt,
        record_every=1,
        restitution=e,
    )
    r = out.records
    k = int(np.argmax(r["force_disp"] > 0.0))  # first step with a contact force
    assert k > 5 and np.all(r["force_disp"][:k] == 0.0)
    v0, v1 = r["normal_velocity"][k - 1], r["normal_velocity"][k]
    loss = r["velocity_pass_loss"][k] - r["velocity_pass_loss"][k - 1]
    # effective mass of the contact point: lumped masses of the two quadratic contact edges
    inv_m = 0.0
    for gi, s in ((0, r["param_a"][k]), (1, r["param_b"][k])):
        nodes, w = np.empty(3, np.int64), np.empty(3)
        flank_weights(mod.flank[gi], int(mod.nedge[gi]), float(s), nodes, w)
        inv_m += np.sum(w**2 * mod.minv[nodes])
    balance = (
        r["kinetic_energy"] + r["strain_energy"] - r["external_work"] + r["velocity_pass_loss"] - out.initial_energy
    )
    return v0, v1, loss, 0.5 * v0**2 / inv_m, balance[k - 1 : k + 1], r


@pytest.mark.parametrize("e", [0.0, 0.5, 1.0])
def test_restitution_velocity_jump_and_energy_loss(gear, e):
    v0, v1, loss, ek, balance, _ = _impact(gear, e)
    assert 0.05 < v0 < 0.08  # approach velocity at the contact point [m/s]
    assert v1 / v0 == pytest.approx(-e, abs=0.01)
    # energy removed = (1 - e^2) x kinetic energy of the effective mass of the approach
    assert loss == pytest.approx((1.0 - e * e) * ek, abs=0.03 * ek)
    # and it is accounted: the energy balance does not jump across the impact step
    assert abs(balance[1] - balance[0]) < 0.01 * ek


def test_restitution_out_of_range_is_refused(gear):
    from rotaflex.gear.cases.simulate import run_case

    with pytest.raises(InputError, match="solver.restitution"):
        run_case({"solver": {"restitution": 1.5}})


def test_driver_sign_logic_and_mirror(gear):
    """The driven gear lags under load: DTE (> 0 when B lags) changes sign with the driver;
    driver B is the mirror image of driver A with the speeds swapped."""
    from rotaflex.gear.cases.simulate import run_case

    base = {
        "operation": {"span_deg": 3.0, "speed_rpm": [4000.0, 4000.0]},
        "mesh": {"preset": "coarse"},
        "output": {"every": 10},
    }
    a = run_case(base).dataset
    b = run_case({**base, "operation": {**base["operation"], "driver": "B"}}).dataset
    late = slice(-20, None)
    assert np.all(a["transmission_error"].values[late] > 0.5e-6)
    assert np.all(b["transmission_error"].values[late] < -0.5e-6)
    np.testing.assert_allclose(b["transmission_error"], -a["transmission_error"], atol=1e-12)
    np.testing.assert_allclose(b["rotation_angle"].sel(gear="B"), a["rotation_angle"].sel(gear="A"), atol=1e-14)
    np.testing.assert_allclose(b["root_stress"].sel(gear="A"), a["root_stress"].sel(gear="B"))
    # contact point: mirrored about y = a/2, on A's side of the pitch point at the start
    cen = float(np.linalg.norm(_model(gear).centres[1]))
    np.testing.assert_allclose(
        b["contact_point"].values[..., 1], cen - a["contact_point"].values[..., ::-1, 1], atol=1e-12
    )
    assert b["torque"].attrs["long_name"].endswith("drive on B)")
    # B (faster) drives: contact at once (impact; 1 deg is 5x the ~0.2 deg it takes to exceed
    # 100 N), A (faster) driving would separate
    speeds = {"operation": {"span_deg": 1.0, "speed_rpm": [4000.0, 4040.0]}}
    c = run_case({**base, **speeds, "operation": {**speeds["operation"], "driver": "B"}})
    assert float(c.dataset["contact_force"].max()) > 100.0


def test_summary_has_dte_and_root_stress(gear):
    from rotaflex.gear.cases.simulate import run_case

    res = run_case({"operation": {"span_deg": 0.5}, "mesh": {"preset": "coarse"}, "output": {"every": 5}})
    s = res.summary()
    ds = res.dataset
    assert s["dte_peak_to_peak"]["unit"] == "m"
    assert s["dte_peak_to_peak"]["value"] == pytest.approx(np.ptp(ds["transmission_error"].values))
    assert s["root_stress_peak"]["value"] == pytest.approx(float(ds["root_stress"].max()))
    assert ds["root_stress"].dims == ("time", "gear")
    assert "transmission_error" in res.plot() and "root_stress" in res.plot()
    off = run_case({"operation": {"span_deg": 0.2}, "mesh": {"preset": "coarse"}, "output": {"root_stress": False}})
    assert "root_stress" not in off.dataset


def test_sweep_gear_figure_draws_dte_panel():
    import xarray as xr

    from rotaflex.gear.results.sweep_figures import sweep_figures

    speed = np.array([2000.0, 4000.0, 8000.0])
    ds = xr.Dataset(
        {
            "dynamic_factor": ("operation.speed_rpm", [1.1, 1.2, 1.5], {"units": "1"}),
            "dte_peak_to_peak": ("operation.speed_rpm", [2e-6, 3e-6, 5e-6], {"units": "m"}),
            "root_stress_peak": ("operation.speed_rpm", [7e7, 8e7, 9e7], {"units": "Pa"}),
        },
        coords={"operation.speed_rpm": ("operation.speed_rpm", speed, {"units": "rpm"})},
        attrs={"base_config": json.dumps({}), "swept": "[]"},
    )
    fig = sweep_figures(ds)["gear_speed_sweep"]
    axes = [ax for ax in fig.axes if ax.get_ylabel()]
    labels = [ax.get_ylabel() for ax in axes]
    assert any("DTE peak to peak" in lb for lb in labels)  # words, not the raw variable name
    dte_ax = axes[[i for i, lb in enumerate(labels) if "DTE" in lb][0]]
    data = [ln for ln in dte_ax.get_lines() if ln.get_linestyle() == "-"][0]
    assert "µm" in dte_ax.get_ylabel()  # drawn in micrometres (no 1e-6 offset on an axis in m)
    np.testing.assert_allclose(data.get_ydata(), [2.0, 3.0, 5.0], rtol=1e-15)


def test_recording_fillet_nodes_does_not_change_the_trajectory(gear):
    """Recording node positions calls the kernel once per record; the state carried between
    calls (incl. the contact-parameter rates) must make the run identical to one long call."""
    g, _ = gear
    ths, th2 = contact_angles(g, g)
    runs = []
    for nodes in (None, [0, 1]):
        out = dynamics.simulate(
            _model(gear),
            speeds=rpm_to_rad_s((4000.0, 4040.0)),
            torque=22.25,
            theta_2=th2,
            theta_s=ths,
            span=math.radians(2.0),
            dt=3e-8,
            record_every=10,
            record_nodes=nodes,
        )
        runs.append(out)
    for name in ("force", "phi_A", "phi_B", "gap", "velocity_pass_loss"):
        np.testing.assert_array_equal(runs[0].records[name], runs[1].records[name])
    assert runs[1].node_positions.shape == (len(runs[1].records["time"]), 2, 2)
