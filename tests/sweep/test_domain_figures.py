"""Domain figures of a sweep, checked by their data (synthetic data sets, no simulation)."""

import json
import math
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from rotaflex.gear.results.sweep_figures import gear_mesh_estimate, sweep_figures
from rotaflex.sweep.figures import floating_figures


def _gear_ds(natural_frequency=None, teeth=20):
    speed = np.linspace(1000.0, 20000.0, 5)
    data = {"dynamic_factor": ("operation.speed_rpm", 1 + speed / 2e4, {"units": "1"})}
    if natural_frequency:
        data["natural_frequency"] = ("operation.speed_rpm", np.full(5, natural_frequency), {"units": "Hz"})
    return xr.Dataset(
        data,
        coords={"operation.speed_rpm": ("operation.speed_rpm", speed, {"units": "rpm"})},
        attrs={"base_config": json.dumps({"gear": {"teeth": teeth}}), "swept": "[]"},
    )


def test_gear_harmonic_marks_where_k_times_mesh_frequency_meets_fn():
    fig = sweep_figures(_gear_ds(natural_frequency=3000.0, teeth=20))["gear_speed_sweep"]
    ax = fig.axes[0]
    marks = sorted(ln.get_xdata()[0] for ln in ax.get_lines() if ln.get_linestyle() == ":")
    # k z n / 60 = f_n  ->  n = 60 f_n / (k z) = 9000, 4500, 3000, 2250 rpm
    np.testing.assert_allclose(marks, [2250.0, 3000.0, 4500.0, 9000.0])
    curve = next(ln for ln in ax.get_lines() if ln.get_linestyle() == "-")
    np.testing.assert_array_equal(curve.get_ydata(), 1 + np.linspace(1000.0, 20000.0, 5) / 2e4)


def test_gear_natural_frequency_estimate_by_hand():
    est = gear_mesh_estimate({})  # gear-domain defaults: m 3.175 mm, z 28, 20 deg, b 6.35 mm
    rb = 3.175e-3 * 28 * math.cos(math.radians(20.0)) / 2
    k = 20.0e9 * 6.35e-3  # ISO 6336-1 c_gamma = 20 N/(mm um) times face width
    fn = math.sqrt(k * rb**2 * 2 / 2.965e-4) / (2 * math.pi)
    assert est["teeth"] == 28 and est["natural_frequency"] == pytest.approx(fn, rel=1e-12)
    assert 5000 < fn < 7000  # order of magnitude of a small steel pair


def test_floating_figure_plots_the_deflection():
    dims = "loads[0].duration"
    ds = xr.Dataset(
        {
            "full.tip.max_deflection": (dims, [3e-3, 2e-3, 1e-3], {"units": "m"}),
            "perturbation.tip.max_deflection": (dims, [3.1e-3, 2e-3, 1e-3], {"units": "m"}),
            "full.energy_change": (dims, [1.0, 2.0, 3.0], {"units": "J"}),
        },
        coords={dims: (dims, [1.0, 2.0, 4.0], {"units": ""})},
    )
    ax = floating_figures(ds)["peak_deflection"].axes[0]
    lines = ax.get_lines()
    assert len(lines) == 2  # the two deflection scalars, not the energy
    np.testing.assert_array_equal(lines[0].get_ydata(), [3e-3, 2e-3, 1e-3])
    np.testing.assert_array_equal(lines[1].get_xdata(), [1.0, 2.0, 4.0])


def test_gear_speed_sweep_from_the_cli(tmp_path):
    """The example gear speed sweep on the process pool. Gear results on Dask: the continuation
    test runs a gear sweep on dask-local (test_dask_local_runs_the_same_chains_as_serial), the
    Dask executor itself is tested in test_sweep_cli.py."""
    from typer.testing import CliRunner

    from rotaflex.cli import app

    example = Path(__file__).resolve().parents[2] / "examples" / "sweep" / "gear_speed.toml"
    out = tmp_path / "out"
    res = CliRunner().invoke(
        app, ["sweep", str(example), "--vary", "operation.speed_rpm=15000,20000", "--out", str(out), "-j", "2", "-q"]
    )
    assert res.exit_code == 0, res.output
    ds = xr.open_dataset(out / "sweep.nc", engine="h5netcdf").load()
    assert ds["dynamic_factor"].dims == ("operation_speed_rpm",)
    assert np.isfinite(ds["dynamic_factor"].values).all() and (ds["dynamic_factor"].values > 0).all()
    cfg = json.loads((out / "cases" / ds["case_id"].values[1] / "case.json").read_text())["config"]
    assert cfg["operation"]["speed_rpm"] == [20000.0, 20000.0]
    assert (out / "figures" / "gear_speed_sweep.png").exists()


def test_floating_slew_time_sweep_from_the_cli(tmp_path):
    from typer.testing import CliRunner

    from rotaflex.cli import app

    example = Path(__file__).resolve().parents[2] / "examples" / "sweep" / "floating_slew.toml"
    out = tmp_path / "out"
    res = CliRunner().invoke(
        app, ["sweep", str(example), "--vary", "loads[0].duration=2,6", "--out", str(out), "-j", "0", "-q"]
    )
    assert res.exit_code == 0, res.output
    ds = xr.open_dataset(out / "sweep.nc", engine="h5netcdf").load()
    peak = ds["full.tip.max_deflection"]
    assert peak.dims == ("loads_0_duration",) and (peak.values > 0).all()
    assert ds["loads_0_duration"].attrs["config_key"] == "loads[0].duration"
    cfg = json.loads((out / "cases" / ds["case_id"].values[1] / "case.json").read_text())["config"]
    assert cfg["loads"][0]["duration"] == 6.0
    assert (out / "figures" / "peak_deflection.png").exists()
