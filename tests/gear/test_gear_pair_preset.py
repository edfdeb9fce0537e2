"""``pair = "lee_jang"``: the paper's pair as a preset of the one [pinion]/[wheel] description.

The explicit tables below are typed from the paper (Lee & Jang, section 4: 28 teeth, 8 diametral
pitch = 3.175 mm module, 20 deg, face 0.25 in = 6.35 mm, r_a = 1.875 in, r_f = 1.5937 in, steel,
disk inertia 2.965e-4 kg m^2, tau_0 = 22.25 N m, 4000 rpm), not taken from the preset.
"""

import math

import numpy as np
import pytest
from typer.testing import CliRunner

from rotaflex.cli import app
from rotaflex.core.errors import InputError
from rotaflex.gear.cases.simulate_config import build, load_config, to_run
from rotaflex.gear.cases.static import load_config as load_static
from rotaflex.gear.cases.static import run_static
from rotaflex.gear.cases.steady import validate_config as validate_steady

GEAR = {
    "teeth": 28,
    "module": 3.175e-3,
    "face_width": 6.35e-3,
    "pressure_angle_deg": 20.0,
    "tip_radius": 0.047625,
    "root_radius": 0.04048,
    "material": {"youngs_modulus": 210e9, "poisson_ratio": 0.3, "density": 7800.0},
    "blank": {"inertia": 2.965e-4},
}
#: a cheap gear static case (coarse mesh, few load cases and angles, no refinement study)
CHEAP = {"mesh": {"preset": "coarse", "n_radii": 4}, "analysis": {"n_angles": 24, "refinement": [1]}}


def explicit(operation: dict) -> dict:
    return {"pinion": dict(GEAR), "wheel": dict(GEAR), "operation": operation}


def test_static_preset_equals_the_explicit_pair_config_and_result():
    preset = {"pair": "lee_jang", **CHEAP}
    written = {**explicit({"torque": 22.25, "torque_on": "pinion"}), **CHEAP}
    assert load_static(preset) == load_static(written)
    a, b = run_static(preset).dataset, run_static(written).dataset
    for name in a.data_vars:
        assert np.array_equal(a[name].values, b[name].values), name
    assert a.attrs["pair_geometry"] == b.attrs["pair_geometry"]


def test_simulate_preset_builds_the_same_model_and_run():
    mesh = {"mesh": {"preset": "coarse"}}
    preset = load_config({"pair": "lee_jang", **mesh})
    written = load_config({**explicit({"torque": 22.25, "driver_speed_rpm": 4000.0}), **mesh})
    assert preset == written
    (g1, _, m1), (g2, _, m2) = build(preset), build(written)
    assert g1 == g2
    for key in ("xloc", "minv", "tie_node", "centres", "inertia", "flank"):
        assert np.array_equal(getattr(m1, key), getattr(m2, key)), key
    assert (m1.stiffness != m2.stiffness).nnz == 0
    assert m1.centre_distance == m2.centre_distance
    assert m1.dt_limit == pytest.approx(m2.dt_limit, rel=1e-12)  # an eigenvalue estimate: round-off apart
    run = to_run(preset, g1, m1)
    assert run.speeds[0] == pytest.approx(4000.0 * math.pi / 30.0, rel=1e-15)
    assert run.torque == 22.25


def test_steady_reads_the_preset():
    from rotaflex.gear.cases.steady import _checked

    cheap = {"mesh": {"preset": "coarse"}, "model": {"method": "lumped"}}
    preset = _checked({"pair": "lee_jang", **cheap})
    written = _checked({**explicit({"torque": 22.25, "torque_on": "pinion", "speed_rpm": 4000.0}), **cheap})
    assert preset == written
    assert preset.operation.speed_rpm == 4000.0  # the paper's speed, not steady's 10000 rpm default
    validate_steady({"pair": "lee_jang", **cheap})


def test_written_keys_override_the_preset():
    cfg = load_config(
        {
            "pair": "lee_jang",
            "pinion": {"face_width": 0.01, "material": {"name": "aluminium"}},
            "operation": {"speed_rpm": 2000.0},
        }
    )
    assert cfg.pinion.face_width == 0.01 and cfg.wheel.face_width == 6.35e-3
    # a table inside a gear replaces the preset's whole: aluminium, not the paper's steel values
    assert cfg.pinion.material.values == (70e9, 0.33, 2700.0)
    assert cfg.wheel.material.values == (210e9, 0.3, 7800.0)
    # a speed written in the verb's other spelling drops the preset's driver_speed_rpm
    assert cfg.operation.driver_speed_rpm == 2000.0


def test_static_torque_written_without_torque_on_is_asked_for():
    with pytest.raises(InputError) as exc:
        load_static({"pair": "lee_jang", "operation": {"torque": 40.0}, **CHEAP})
    assert exc.value.field == "operation.torque_on"


@pytest.mark.parametrize(
    ("config", "field"),
    [
        ({"pair": "paper"}, "pair"),
        ({"pair": "lee_jang", "gear": {"teeth": 28}}, "gear"),
        ({"pair": "lee_jang", "disk_inertia": 1e-4}, "disk_inertia"),
    ],
)
def test_bad_preset_use_is_refused_by_name(config, field):
    for load in (load_config, load_static):
        with pytest.raises(InputError) as exc:
            load(config)
        assert exc.value.field == field


def test_preset_with_a_relief_by_fraction_from_the_cli_with_progress(tmp_path):
    path = tmp_path / "preset.toml"
    path.write_text(
        'domain = "gear"\npair = "lee_jang"\n'
        "[pinion]\ntip_relief = { amount = 10e-6, start_fraction = 0.6 }\n"
        '[mesh]\npreset = "coarse"\nn_radii = 4\n[analysis]\nn_angles = 24\nrefinement = [1]\n'
    )
    res = CliRunner().invoke(app, ["gear", "static", str(path), "--out", str(tmp_path / "out"), "--no-figures"])
    assert res.exit_code == 0, res.output
    # progress, one line per stage in a log: relieved and unrelieved FE pairs, loaded TE, the
    # compliance study of each gear at one level
    stages = [line for line in res.output.splitlines() if line.startswith("gear static: ")]
    assert [line.split(" (")[1].split(")")[0] for line in stages] == [f"{k}/5 stage" for k in range(1, 6)]
    import xarray as xr

    ds = xr.open_dataset(tmp_path / "out" / "result.nc")
    assert float(ds["relief_gap"].max()) == pytest.approx(10e-6, rel=1e-6)  # the full amount at the tip
    assert float(ds["ste_ptp"]) != float(ds["ste_ptp_unrelieved"])
