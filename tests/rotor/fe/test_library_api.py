"""The FE rotor library (rotaflex.rotor.fe.study): a rotor built in Python gives the command
line's results, speeds are explicit in their names, results plot themselves with the CLI's
figures, and 0.5X crossings are labelled 0.5 (issue 37, "The library")."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from rotaflex.cli import app
from rotaflex.core.errors import InputError
from rotaflex.rotor.fe import Bearing, Disk, Rotor, Shaft, campbell, modal
from rotaflex.rotor.fe.study import campbell_diagram, modes, unbalance_response_study

ROOT = Path(__file__).resolve().parents[3]
EXAMPLE = ROOT / "examples" / "rotor" / "fe_friswell_5_9_1.toml"
RAD_PER_RPM = np.pi / 30


def friswell_rotor() -> Rotor:
    """examples/rotor/fe_friswell_5_9_1.toml, written in Python."""
    disk = dict(width=0.07, inner_diameter=0.05)
    brg = dict(kxx=1e6, kyy=1e6, cxx=3e3, cyy=3e3)
    return Rotor(
        shaft=(Shaft(outer_diameter=0.05, length=1.5, elements=6, material="steel"),),
        disk=(Disk(position=0.5, outer_diameter=0.28, **disk), Disk(position=1.0, outer_diameter=0.35, **disk)),
        bearing=(Bearing(node=0, name="left", **brg), Bearing(position=1.5, name="right", **brg)),
    )


def test_half_x_crossings_are_labelled_half(tmp_path):
    """campbell(...).critical gave int(0.5) = 0; the 0.5X crossing is where the tracked mode's
    damped frequency is half the spin speed (checked with modal() at that speed)."""
    rotor = friswell_rotor()
    speeds = np.linspace(0, 4000, 81) * RAD_PER_RPM
    c = campbell(rotor, speeds, 6, harmonics=(0.5, 1))
    half = [cr for cr in c.critical if cr["harmonic"] == 0.5]
    assert half and {cr["harmonic"] for cr in c.critical} == {0.5, 1.0}
    for cr in half:
        wd = modal(rotor, cr["speed"], 6).wd[0]
        assert np.min(np.abs(wd - 0.5 * cr["speed"])) < 5e-3 * cr["speed"]  # linear interpolation on 50 rpm
    lib = campbell_diagram(rotor, speed_rpm=(0, 4000), n_speeds=81, n_modes=6, harmonics=(0.5, 1))
    assert sorted({cr["harmonic"] for cr in lib.critical}) == [0.5, 1.0]


def test_python_rotor_gives_the_cli_results(tmp_path):
    """The same rotor from TOML through the CLI and from Python through the library: the same
    critical speeds and peaks (two routes through the one runner, equal to the last bit)."""
    r = CliRunner().invoke(app, ["rotor", "campbell", str(EXAMPLE), "--out", str(tmp_path / "c"), "-q", "--no-figures"])
    assert r.exit_code == 0, r.output
    cli = json.loads((tmp_path / "c" / "summary.json").read_text())
    lib = campbell_diagram(friswell_rotor(), speed_rpm=(0, 4000), n_speeds=50, n_modes=6, harmonics=(1, 2))
    s = lib.summary()
    keys = [k for k in cli if k.startswith("critical_") and k.endswith("_rpm")]
    assert keys and all(s[k]["value"] == cli[k]["value"] for k in keys)
    r = CliRunner().invoke(
        app, ["rotor", "unbalance", str(EXAMPLE), "--out", str(tmp_path / "u"), "-q", "--no-figures"]
    )
    cli = json.loads((tmp_path / "u" / "summary.json").read_text())
    ub = unbalance_response_study(
        friswell_rotor(),
        [{"position": 1.0, "magnitude": 1e-4, "phase_deg": 0.0}],
        speed_rpm=(0, 4000),
        n_speeds=500,
        probes=(2, 4),
    )
    assert ub.summary()["peak_0_speed_rpm"]["value"] == cli["peak_0_speed_rpm"]["value"]
    assert ub.summary()["peak_0_probe"]["value"] == cli["peak_0_probe"]["value"]


def test_speeds_are_explicit_in_their_names():
    rotor = friswell_rotor()
    a = modes(rotor, speed_rpm=3000.0, n_modes=4)
    b = modes(rotor, speed=3000.0 * RAD_PER_RPM, n_modes=4)
    np.testing.assert_allclose(a.dataset["damped_frequency"], b.dataset["damped_frequency"], rtol=1e-12)
    with pytest.raises(InputError, match="one of speed_rpm"):
        modes(rotor, speed_rpm=3000.0, speed=314.0)
    with pytest.raises(InputError, match="one of speed_rpm"):
        modes(rotor)
    with pytest.raises(TypeError):
        modes(rotor, 3000.0)  # a bare number: no unit, refused
    with pytest.raises(InputError, match="start, stop"):
        campbell_diagram(rotor, speed_rpm=3000.0)


def _overlap(a, b) -> bool:
    return a.x0 < b.x1 and b.x0 < a.x1 and a.y0 < b.y1 and b.y0 < a.y1


def test_plot_methods_are_the_cli_figures_and_legends_hide_no_data(tmp_path):
    rotor = friswell_rotor()
    c = campbell_diagram(rotor, speed_rpm=(0, 4000), n_speeds=30, n_modes=4, operating_range_rpm=(2500, 3500))
    one, cli = c.plot_campbell(), c.plot()["campbell"]
    la, lb = one.axes[0].get_lines(), cli.axes[0].get_lines()
    assert len(la) == len(lb)
    assert all(np.array_equal(x.get_xydata(), y.get_xydata(), equal_nan=True) for x, y in zip(la, lb, strict=True))
    assert c.plot_campbell(frequency_limit_hz=30).axes[0].get_ylim()[1] == pytest.approx(30)
    ub = unbalance_response_study(
        rotor,
        [{"position": 1.0, "magnitude": 1e-4}],
        speed_rpm=(0, 4000),
        n_speeds=200,
        operating_range_rpm=(2500, 3500),
    )
    m = modes(rotor, speed_rpm=3000.0, n_modes=4)
    for fig in (one, ub.plot_bode(), ub.plot_orbit(), m.plot_mode(1)):
        fig.canvas.draw()
        r = fig.canvas.get_renderer()
        for leg in fig.legends:  # figure legends sit outside every axes
            for ax in fig.axes:
                assert not _overlap(leg.get_window_extent(r), ax.get_window_extent(r))
        for ax in fig.axes:  # an axes legend covers none of its data points
            leg = ax.get_legend()
            if leg is not None:
                box = leg.get_window_extent(r)
                for line in ax.get_lines():
                    xy = line.get_xydata()
                    d = ax.transData.transform(xy[np.all(np.isfinite(xy), 1)])
                    inside = (d[:, 0] > box.x0) & (d[:, 0] < box.x1) & (d[:, 1] > box.y0) & (d[:, 1] < box.y1)
                    assert not inside.any(), (fig, line.get_label())
    assert "[\u00b5m]" in ub.plot_orbit().axes[0].get_xlabel()
    assert "mode 1" in m.plot_mode(1).axes[0].get_title()
    with pytest.raises(InputError):
        m.plot_mode(7)


def test_readme_rotor_example_runs(tmp_path, python_json):
    """examples/python/readme_rotor.py builds the README rotor and writes its Campbell and Bode plots."""
    script = ROOT / "examples" / "python" / "readme_rotor.py"
    out = python_json(
        f"""
        import json, runpy, sys
        sys.argv = ["readme_rotor.py", {str(tmp_path)!r}]
        ns = runpy.run_path({str(script)!r}, run_name="__main__")
        print(json.dumps(ns["REPORT"]))
        """
    )
    assert (tmp_path / "campbell.png").exists() and (tmp_path / "bode.png").exists()
    assert out["status"] == "success" and out["critical_rpm"]
