"""Fluid-film outputs: coefficient tables in result.nc, their figure, the oil-whip onset in the summary."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from typer.testing import CliRunner

from rotaflex.cli import app
from rotaflex.core.result import load_result
from rotaflex.rotor.fe.bearings import FluidFilm, coefficients_from_reaction
from rotaflex.rotor.fe.case import run_modal

RPM = np.pi / 30
FILM = {  # short model: closed form, fast
    "diameter": 0.05,
    "length": 0.0125,
    "clearance": 50e-6,
    "viscosity": 0.01,
    "speed_rpm": [1000.0, 12000.0],
    "n_speeds": 12,
    "model": "short",
}
CASE = f"""
[[shaft]]
outer_diameter = 0.05
length = 0.8
elements = 6

[[disk]]
node = 3
mass = 40.0
Id = 0.2
Ip = 0.4

[bearing.left]
node = 0
[bearing.left.fluid_film]
{chr(10).join(f"{k} = {json.dumps(v)}" for k, v in FILM.items())}
load = "static"

[bearing.right]
node = 6
[bearing.right.fluid_film]
{chr(10).join(f"{k} = {json.dumps(v)}" for k, v in FILM.items())}
load = [0.0, -250.0]

[campbell]
speed_rpm = [1000, 12000]
n_speeds = 23
n_modes = 4
"""


def test_campbell_cli_writes_tables_figure_and_whip_onset(tmp_path: Path):
    cfg = tmp_path / "ff.toml"
    cfg.write_text(CASE)
    out = ["--out", str(tmp_path / "o"), "-q", "--dpi", "30"]  # low resolution: drawing dominates the run time
    res = CliRunner().invoke(app, ["rotor", "campbell", str(cfg), *out])
    assert res.exit_code == 0, res.output
    assert (tmp_path / "o" / "bearing_coefficients.png").exists()
    ds = load_result(tmp_path / "o" / "result.nc").dataset
    assert list(ds["fluid_film"].values) == ["left", "right"]
    assert ds["ff_kxy"].attrs["units"] == "N/m" and ds["ff_cyy"].attrs["units"] == "N s/m"
    assert ds["ff_speed_rpm"].attrs["units"] == "rpm" and ds["ff_attitude_angle"].attrs["units"] == "deg"
    # the tables are those of the bearings for their loads, computed here independently
    ff = FluidFilm(**{**FILM, "speed_rpm": tuple(FILM["speed_rpm"])}, load=(0.0, -250.0))
    right = coefficients_from_reaction(ff, (0.0, 250.0))
    t = ds.sel(fluid_film="right")
    np.testing.assert_allclose(t["ff_kxy"].values, right.k[:, 0, 1], rtol=1e-10)
    np.testing.assert_allclose(t["ff_cyy"].values, right.c[:, 1, 1], rtol=1e-10)
    np.testing.assert_allclose(t["ff_sommerfeld"].values, right.sommerfeld, rtol=1e-12)
    np.testing.assert_allclose(t["ff_speed_rpm"].values, np.linspace(1000, 12000, 12), rtol=1e-12)
    # the left load comes from statics: half the weight of this symmetric rotor (whatever the right
    # bearing's explicit load says: two supports are statically determinate)
    left = ds.sel(fluid_film="left")
    weight = (40.0 + 7810 * np.pi / 4 * 0.05**2 * 0.8) * 9.80665
    assert abs(float(left["ff_load_y"]) + weight / 2) < 1e-9 * weight
    assert float(left["ff_load_x"]) == 0.0 or abs(float(left["ff_load_x"])) < 1e-9 * weight
    # oil whip: the summary names the lowest speed at which a log decrement turns negative
    summary = json.loads((tmp_path / "o" / "summary.json").read_text())
    onset = summary["oil_whip_onset_rpm"]
    assert onset["unit"] == "rpm"
    ld, rpm = ds["log_dec"].values, ds["speed_rpm"].values
    s = np.where((ld < 0).any(axis=1))[0][0]  # first analysed speed with an unstable mode
    k = onset["mode"]
    assert ld[s, k] < 0 <= ld[s - 1, k] and np.all(ld[:s] >= 0)
    # between the two speeds the onset is the zero of the linearly interpolated log decrement
    expected = rpm[s - 1] + ld[s - 1, k] / (ld[s - 1, k] - ld[s, k]) * (rpm[s] - rpm[s - 1])
    assert abs(onset["value"] - expected) < 1e-9 * expected


def test_rigid_bearing_rotor_has_no_tables():
    cfg = {
        "shaft": [{"outer_diameter": 0.05, "length": 0.8, "elements": 4}],
        "bearing": [{"node": 0, "kxx": 1e7, "kyy": 1e7}, {"node": 4, "kxx": 1e7, "kyy": 1e7}],
        "modal": {"n_modes": 2},
    }
    r = run_modal(cfg)
    assert "fluid_film" not in r.dataset.dims and "oil_whip_onset_rpm" not in r.summary()
    assert "bearing_coefficients" not in r.plot()
