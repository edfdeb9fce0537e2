"""`gear steady` with model.method = "elastic_teeth" and drawing pairs: config to result."""

import copy
import tomllib
from pathlib import Path

import numpy as np
import pytest

from rotaflex.core.errors import InputError
from rotaflex.gear.cases.steady import run_torsional, validate_config

EXAMPLE = Path(__file__).parents[2] / "examples" / "gear" / "steady" / "elastic_teeth_relief.toml"


@pytest.fixture(scope="module")
def config():
    cfg = tomllib.loads(EXAMPLE.read_text())
    cfg.pop("domain"), cfg.pop("verb")
    cfg["model"]["mesh_preset"] = "coarse"
    cfg["steady"] = {"fixed_cycles": 20, "eval_cycles": 10}
    return cfg


def _with(cfg, **tables):
    out = copy.deepcopy(cfg)
    for table, values in tables.items():
        out.setdefault(table, {}).update(values)
    return out


def test_relief_lowers_the_dynamic_factor_and_dte_of_the_drawing_pair(config):
    with_relief = run_torsional(config).dataset
    without = run_torsional(_with(config, model={"relief": False})).dataset
    assert with_relief.attrs["method"] == "elastic_teeth"
    # the relief is sized for this load: the loaded TE (and so the excitation) is much smaller
    assert float(with_relief.dte_pp) < 0.5 * float(without.dte_pp)
    assert float(with_relief.dynamic_factor) < float(without.dynamic_factor)
    for ds in (with_relief, without):
        assert float(ds.fillet_stress_max_pinion) > 0 and float(ds.fillet_stress_max_wheel) > 0
        assert float(ds.contact_loss_fraction) == 0.0
    # gear inertias from the blanks (train.inertia not given) set the mesh mode
    assert 5e3 < float(with_relief.mesh_natural_frequency) < 5e4


def test_lumped_and_elastic_teeth_share_the_pair_data(config):
    """Same drawing pair, both methods: the lumped model gets the loaded k(phi), e(phi) of the
    same FE data, so its mean DTE (the static deflection) is the window model's."""
    et = run_torsional(config).dataset
    lu = run_torsional(_with(config, model={"method": "lumped"})).dataset
    assert lu.attrs["method"] == "lumped"
    assert abs(float(lu.dte_mean) / float(et.dte_mean) - 1) < 0.02
    assert float(lu.mesh_natural_frequency) == pytest.approx(float(et.mesh_natural_frequency), rel=1e-12)


def test_continuation_carries_the_tooth_states(config):
    first = run_torsional(_with(config, model={"n_modes": 1}))
    state = first.final_state()
    assert "modal" in state and len(state["modal"]) > 0
    nxt = run_torsional(_with(config, model={"n_modes": 1}, operation={"speed_rpm": 6100.0}), initial_state=state)
    assert nxt.dataset.attrs["status"] in ("success", "not_periodic")
    assert np.isfinite(float(nxt.dataset.dynamic_factor))
    with pytest.raises(InputError, match="model.method"):
        run_torsional(_with(config, model={"method": "lumped"}), initial_state=state)


@pytest.mark.parametrize(
    ("change", "field"),
    [
        ({"gear": {"module": 2e-3}}, "gear"),
        ({"model": {"method": "elastic_teeth"}, "mesh": {"backlash": 1e-4}}, "mesh.backlash"),
        ({"mesh": {"source": "contact_pattern"}}, "mesh.source"),
        ({"model": {"n_modes": 9}}, "model.n_modes"),
        ({"pinion": {"profile_shift": 3.0}}, "pinion.profile_shift"),
    ],
)
def test_bad_input_names_the_field(config, change, field):
    bad = copy.deepcopy(config)
    for table, values in change.items():
        bad.setdefault(table, {}).update(values)
    with pytest.raises(InputError) as err:
        validate_config(bad)
    assert err.value.field.startswith(field), err.value.field


def test_a_lone_pinion_table_is_rejected(config):
    bad = copy.deepcopy(config)
    bad.pop("wheel")
    with pytest.raises(InputError, match="wheel"):
        validate_config(bad)


def test_tooth_mesh_refinement_converges(config):
    """coarse -> default FE tooth mesh: the dynamic quantities move by far less than the
    fillet stress (a stress concentration, converging slowest; docs: 220/254/266 MPa)."""
    out = {}
    for preset in ("coarse", "default"):
        out[preset] = run_torsional(_with(config, model={"mesh_preset": preset})).dataset
    c, d = out["coarse"], out["default"]
    assert abs(float(c.dte_mean) / float(d.dte_mean) - 1) < 0.02
    assert abs(float(c.dynamic_factor) / float(d.dynamic_factor) - 1) < 0.01
    assert abs(float(c.dte_pp) / float(d.dte_pp) - 1) < 0.05
    assert 0.7 < float(c.fillet_stress_max_pinion) / float(d.fillet_stress_max_pinion) < 0.95


@pytest.mark.parametrize(
    ("tables", "expected"),
    [
        ({}, 10.0e-6),  # the larger of the drawing's tip reliefs (pinion 9.6 um, wheel 10 um)
        ({"model": {"relief": False}}, 0.0),  # the gears run without their reliefs
        ({"iso": {"tip_relief": 4e-6}}, 4e-6),  # given explicitly
    ],
)
def test_iso_tip_relief_follows_the_drawing(config, tables, expected):
    from rotaflex.gear.cases.steady import _checked, _iso_tip_relief

    assert _iso_tip_relief(_checked(_with(config, **tables))) == expected


def test_iso_overlay_uses_the_standards_own_stiffness_and_reference_circle_load(config):
    import math

    from rotaflex.gear.cases.steady import _checked, pair_data
    from rotaflex.gear.static.tooth_analysis import iso6336_stiffness

    cfg_point = {k: v for k, v in config.items() if k != "sweep"}
    res = run_torsional(_with(cfg_point, steady={"fixed_cycles": 4, "eval_cycles": 2}))
    cfg = _checked(cfg_point)
    pd = pair_data(cfg)
    g1, g2 = pd.gears
    b = pd.face_width
    # ISO 6336-1: F_t at the wheel's reference circle, per mm of face width; C_R of the blanks
    ft_b = cfg.operation.torque / (g2.module * g2.teeth / 2) / (b * 1e3)
    c_r = 0.5 * (cfg.pair.pinion.blank_factor() + cfg.pair.wheel.blank_factor())
    c_gamma = iso6336_stiffness(g1, g2, load_per_width=ft_b, eps_alpha=cfg.pair.contact_ratio, c_r=c_r)["c_gamma"]
    (j1, j2), (r1, r2) = pd.inertias, (g1.base_radius, g2.base_radius)
    m_red = j1 * j2 / (j1 * r2**2 + j2 * r1**2) / (b * 1e3)  # kg/mm
    n_e1 = 30000.0 / (math.pi * g1.teeth) * math.sqrt(c_gamma / m_red)  # ISO 6336-1 (min^-1)
    assert abs(float(res.dataset["iso_resonance_speed"]) / n_e1 - 1.0) < 1e-9
    # iso.stiffness = "model": n_E1 from the model's own mean mesh stiffness, i.e. its mesh mode
    # with rigid shafts and no motor/load inertia
    res_m = run_torsional(_with(cfg_point, steady={"fixed_cycles": 4, "eval_cycles": 2}, iso={"stiffness": "model"}))
    assert float(res_m.dataset["iso_resonance_speed"]) != float(res.dataset["iso_resonance_speed"])


def test_sweep_figure_marks_points_that_did_not_settle():
    import xarray as xr

    from rotaflex.gear.results.sweep_figures import steady_sweep_figure

    speeds = np.array([1000.0, 2000.0, 3000.0])
    status = np.array([["success", "success"], ["not_periodic", "success"], ["success", "success"]])
    ds = xr.Dataset(
        {
            "dynamic_factor": (("operation_speed_rpm", "direction"), np.array([[1.1, 1.1], [1.6, 1.4], [1.2, 1.2]])),
            "dte_pp": (("operation_speed_rpm", "direction"), np.full((3, 2), 2e-6)),
            "status": (("operation_speed_rpm", "direction"), status),
        },
        coords={"operation_speed_rpm": speeds, "direction": ["up", "down"]},
    )
    fig = steady_sweep_figure(ds)["gear_steady_sweep"]
    marks = [ln for ln in fig.axes[0].lines if ln.get_marker() == "x"]
    assert len(marks) == 1 and marks[0].get_label() == "not periodic"
    assert list(marks[0].get_xdata()) == [2000.0] and list(marks[0].get_ydata()) == [1.6]


def test_a_drawing_pair_case_records_what_it_used(config):
    import json

    res = run_torsional(_with(config, steady={"fixed_cycles": 4, "eval_cycles": 2}))
    ds = res.dataset
    stored = json.loads(ds.attrs["config"])
    # no paper [gear] table and no default inertia pretend to describe this pair
    assert stored["gear"] is None and stored["train"]["inertia"] is None
    from rotaflex.gear.cases.steady import _checked, pair_data

    j1, j2 = pair_data(_checked(config)).inertias
    assert float(ds["inertia_pinion"]) == j1 and float(ds["inertia_wheel"]) == j2
    g2 = pair_data(_checked(config)).gears[1]
    assert abs(float(ds["static_mesh_force"]) - config["operation"]["torque"] / g2.base_radius) < 1e-9
    assert float(ds["mean_mesh_stiffness"]) > 0 and float(ds["reduced_mass"]) > 0


def test_backlash_sets_the_centre_distance_as_in_gear_static(config):
    from rotaflex.gear.cases.steady import _checked

    cfg = _checked(_with(config, **{}) | {"backlash": 50e-6})
    a0 = cfg.pair.center_distance_no_backlash
    assert cfg.pair.working_center_distance > a0
    assert abs(cfg.pair.normal_backlash_at(cfg.pair.working_center_distance) - 50e-6) < 1e-12
    with pytest.raises(InputError) as exc:
        _checked(_with(config) | {"backlash": 50e-6, "center_distance": a0})
    assert exc.value.field == "backlash"
