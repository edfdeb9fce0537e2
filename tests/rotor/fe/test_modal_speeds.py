"""Several modal speeds in one run: ``[modal] speed_rpm = [..]`` and ``--speed`` on the command line."""

import json
from pathlib import Path

import numpy as np
from typer.testing import CliRunner

from rotaflex.cli import app
from rotaflex.core.result import load_result

EXAMPLE = Path(__file__).resolve().parents[3] / "examples" / "rotor" / "fe_friswell_5_9_1.toml"


def _run(tmp_path: Path, name: str, *args: str, text: str | None = None):
    cfg = EXAMPLE
    if text is not None:
        cfg = tmp_path / f"{name}.toml"
        cfg.write_text(text)
    out = tmp_path / name
    res = CliRunner().invoke(app, ["rotor", "modal", str(cfg), "--out", str(out), "-q", "--no-figures", *args])
    assert res.exit_code == 0, res.output
    return load_result(out / "result.nc").dataset, json.loads((out / "summary.json").read_text())


def test_several_speeds_equal_single_speed_runs(tmp_path: Path):
    many, summary = _run(tmp_path, "many", "--speed", "0", "--speed", "2500", "--speed", "7000")
    np.testing.assert_array_equal(many["speed_rpm"].values, [0, 2500, 7000])
    assert many["damped_frequency"].dims == ("speed", "mode")
    assert many["shape_real"].dims == ("speed", "mode", "node", "dof") and many["z"].dims == ("node",)
    for i, rpm in enumerate((0, 2500, 7000)):
        one, s1 = _run(tmp_path, f"one{i}", "--speed", str(rpm))  # one value: the single-speed layout
        assert one["damped_frequency"].dims == ("mode",)
        np.testing.assert_array_equal(many["damped_frequency"].values[i], one["damped_frequency"].values)
        assert summary[f"speed_{i}_mode_0_frequency_hz"]["value"] == s1["mode_0_frequency_hz"]["value"]
    # the gyroscopic split of the first pair grows with speed (forward up, backward down)
    wd = many["damped_frequency"].values
    assert wd[0, 1] - wd[0, 0] < 1e-9 * wd[0, 0] < wd[1, 1] - wd[1, 0] < wd[2, 1] - wd[2, 0]


def test_speed_list_in_the_config_equals_the_option(tmp_path: Path):
    text = EXAMPLE.read_text().replace("[modal]\nspeed_rpm = 4000", "[modal]\nspeed_rpm = [1000, 5000]")
    assert "speed_rpm = [1000, 5000]" in text
    a, _ = _run(tmp_path, "cfg", text=text)
    b, _ = _run(tmp_path, "opt", "--speed", "1000", "--speed", "5000")
    np.testing.assert_array_equal(a["damped_frequency"].values, b["damped_frequency"].values)


def test_speed_option_only_where_it_means_something():
    res = CliRunner().invoke(app, ["rotor", "campbell", "--help"])
    assert res.exit_code == 0 and "--speed" not in res.output
