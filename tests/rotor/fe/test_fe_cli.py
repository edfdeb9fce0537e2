"""Every FE rotor verb runs on the example file and writes result.nc + summary.json."""

import json
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from rotaflex.cli import app
from rotaflex.core.config import load_toml
from rotaflex.core.result import load_result

EXAMPLE = Path(__file__).resolve().parents[3] / "examples" / "rotor" / "fe_friswell_5_9_1.toml"


@pytest.mark.parametrize("verb", ["modal", "campbell", "ucs", "unbalance"])
def test_verbs_write_results(verb, tmp_path: Path):
    res = CliRunner().invoke(app, ["rotor", verb, str(EXAMPLE), "--out", str(tmp_path), "-q", "--no-figures"])
    assert res.exit_code == 0, res.output
    r = load_result(tmp_path / "result.nc")
    assert r.kind == f"rotor_fe_{verb}" and r.status == "success"
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["status"]["value"] == "success"
    if verb == "modal":
        # 4000 rpm, bearings damped (3 kN s/m): still the two lowest modes near 13.6/14.0 Hz
        assert 13.0 < summary["mode_0_frequency_hz"]["value"] < 14.5


def test_sweep_hook_runs_named_analysis(tmp_path: Path):
    from rotaflex.rotor.fe.case import run_case, validate_config

    cfg = load_toml(EXAMPLE)
    cfg["analysis"] = "modal"
    cfg["bearing"]["left"]["kxx"] = 2e6  # a dotted sweep key: bearing.left.kxx
    validate_config(cfg)
    r = run_case(cfg)
    assert r.kind == "rotor_fe_modal" and np.all(np.diff(r.dataset["damped_frequency"].values) >= 0)


def test_transient_verb_short_runup(tmp_path: Path):
    text = (
        EXAMPLE.read_text()
        .replace("duration = 4.0", "duration = 0.3")
        .replace("n_output = 4001", "n_output = 301")
        .replace("n_modes = 12", "n_modes = 6")
    )
    cfg = tmp_path / "short.toml"
    cfg.write_text(text)
    res = CliRunner().invoke(app, ["rotor", "transient", str(cfg), "--out", str(tmp_path / "o"), "-q"])
    assert res.exit_code == 0, res.output
    r = load_result(tmp_path / "o" / "result.nc")
    assert r.kind == "rotor_fe_transient"
    assert abs(r.dataset["speed"].values[-1] - 2000 * np.pi / 30) < 1e-9
    assert (tmp_path / "o" / "time_response.png").exists() and (tmp_path / "o" / "model.png").exists()


def test_from_toml_equals_python_construction():
    from rotaflex.rotor.fe import Bearing, Disk, Rotor, Shaft

    a = Rotor.from_toml(EXAMPLE)
    b = Rotor(
        shaft=(Shaft(outer_diameter=0.05, length=1.5, elements=6),),
        disk=(
            Disk(node=2, width=0.07, outer_diameter=0.28, inner_diameter=0.05),
            Disk(node=4, width=0.07, outer_diameter=0.35, inner_diameter=0.05),
        ),
        bearing=(
            Bearing(node=0, kxx=1e6, kyy=1e6, cxx=3e3, cyy=3e3),
            Bearing(node=6, kxx=1e6, kyy=1e6, cxx=3e3, cyy=3e3),
        ),
    )
    for x, y in ((a.M, b.M), (a.G, b.G), (a.KC(100.0)[0], b.KC(100.0)[0]), (a.KC(100.0)[1], b.KC(100.0)[1])):
        assert np.array_equal(x, y)
    assert [bb.name for bb in a.bearing] == ["left", "right"]
