"""Sweeps of the rotor domain through the CLI and the reproduce hook."""

from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

from rotaflex.cli import app
from rotaflex.rotor.sweep_figures import rotor_figures, rotor_reference, rotor_whirl

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "sweep" / "rotor_spin.toml"
runner = CliRunner()


def test_whirl_closed_form_satisfies_its_characteristic_equation():
    spin = np.array([0.0, 3.0, 40.0])
    fwd, bwd, peak = rotor_whirl(spin, 2.0, 1.0, 100.0)
    for w, sign in ((fwd, -1), (-bwd, -1)):  # backward whirl: negative root of the same equation
        np.testing.assert_allclose(1.0 * w**2 + sign * 2.0 * spin * w - 100.0, 0.0, atol=1e-9)
    assert fwd[0] == bwd[0] == 10.0 and peak[0] == pytest.approx(2 / 20.0)


def test_rotor_spin_sweep_cli_matches_closed_form(tmp_path):
    out = tmp_path / "out"
    res = runner.invoke(
        app,
        [
            "sweep",
            str(EXAMPLE),
            "--vary",
            "motion.spin_speed=0:40:3",
            "--vary",
            "solver.t_end=0.6",
            "--out",
            str(out),
            "-j",
            "0",  # serial: three 0.6 s runs, less than a worker pool's start-up
            "-q",
        ],
    )
    assert res.exit_code == 0, res.output
    ds = xr.open_dataset(out / "sweep.nc", engine="h5netcdf").load()
    assert ds["max_tilt_angle"].dims == ("motion_spin_speed", "solver_t_end")
    assert ds["motion_spin_speed"].attrs == {
        "units": "rad/s",
        "long_name": "motion.spin_speed",
        "config_key": "motion.spin_speed",
    }
    assert ds["solver_t_end"].attrs["units"] == "s"  # from the schema, not from the key's name
    assert ds.attrs["domain"] == "rotor"
    ref = rotor_reference(ds.isel({"solver_t_end": 0}, drop=True))
    assert ref is not None and ref["peak_tilt"] is not None
    sim = ds["max_tilt_angle"].values[:, 0]
    np.testing.assert_allclose(sim, ref["peak_tilt"], rtol=1e-2)
    assert (out / "figures" / "campbell.png").exists()
    fig = rotor_figures(ds.isel({"solver_t_end": 0}, drop=True))["campbell"]
    bottom = fig.axes[1]
    dots = next(ln for ln in bottom.get_lines() if ln.get_label().startswith("peak tilt (sim"))
    np.testing.assert_array_equal(dots.get_ydata(), sim)


def test_rotor_sweep_unknown_key_is_named(tmp_path):
    res = runner.invoke(
        app,
        ["sweep", str(EXAMPLE), "--vary", "motion.spin=0:40:3", "--out", str(tmp_path / "o"), "-q"],
    )
    assert res.exit_code == 2 and "motion.spin" in res.output


@pytest.mark.slow  # 25 s; the same section runs in `rotaflex reproduce all` (the main job)
def test_reproduce_sweep_section_passes(tmp_path):
    from rotaflex.reproduce.sweep import run

    section = run(tmp_path, fast=True, progress=False)
    checks = section.all_checks()
    assert len(checks) >= 4 and all(c.passed for c in checks), [(c.name, c.measured) for c in checks]
    assert (tmp_path / section.figures[0].image).exists()
    assert section.figures[0].image.startswith("sweep/rotor/")
