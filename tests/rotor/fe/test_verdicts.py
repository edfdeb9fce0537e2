"""Verdicts over an operating range: stability is part of them (issue 37, item 1).

The oil-whip rotor of ``examples/rotor/fe_fluid_film.toml`` goes unstable near 4,570 rpm; a
verdict over 4,000-8,000 rpm must fail and say so, one over 3,000-4,000 rpm must not.
"""

import json
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq
from typer.testing import CliRunner

from rotaflex.cli import app
from rotaflex.core.config import load_toml
from rotaflex.rotor.fe.modal import modal
from rotaflex.rotor.fe.model import Rotor

EXAMPLE = Path(__file__).resolve().parents[3] / "examples" / "rotor" / "fe_fluid_film.toml"
RAD_PER_RPM = np.pi / 30


def _case(tmp_path: Path, band: tuple[float, float]) -> Path:
    """The example with coarser tables (24 speeds: the test's run time) and the given operating range."""
    text = (
        EXAMPLE.read_text()
        .replace("n_speeds = 50", "n_speeds = 24")
        .replace("n_speeds = 400", "n_speeds = 120")
        .replace("operating_range_rpm = [3000, 4000]", f"operating_range_rpm = [{band[0]}, {band[1]}]")
    )
    p = tmp_path / f"ff_{band[0]}_{band[1]}.toml"
    p.write_text(text)
    return p


def _run(verb: str, case: Path, out: Path, *extra: str):
    res = CliRunner().invoke(app, ["rotor", verb, str(case), "--out", str(out), "-q", *extra])
    assert res.exit_code == 0, res.output
    return res.output, json.loads((out / "summary.json").read_text())


@pytest.fixture(scope="module")
def whip_onset():
    """Onset [rpm] from an independent path: the largest real part of the lowest 12 modes of
    :func:`modal` (not the verdict's all-eigenvalue search), its zero by Brent's method."""
    cfg = load_toml(EXAMPLE)
    for b in cfg["bearing"].values():
        b["fluid_film"]["n_speeds"] = 24
    rotor = Rotor.from_mapping({k: cfg[k] for k in ("shaft", "disk", "bearing")})

    def growth(rpm):
        return modal(rotor, rpm * RAD_PER_RPM, 12).eigenvalue[0].real.max()

    assert growth(3000) < 0 < growth(8000)
    return brentq(growth, 3000, 8000, xtol=1e-4)


def test_unbalance_verdict_fails_on_an_unstable_mode_in_the_range(tmp_path, whip_onset):
    out, s = _run("unbalance", _case(tmp_path, (4000, 8000)), tmp_path / "u", "--no-figures")
    assert s["stable_in_operating_range"]["value"] is False
    assert s["instability_onset_in_operating_range_rpm"]["value"] == pytest.approx(whip_onset, rel=1e-5)
    assert s["min_log_dec_in_operating_range"]["value"] < 0
    assert s["verdict"]["value"] == "fail"
    assert any("unstable" in r for r in s["verdict"]["reasons"])
    assert "UNSTABLE from" in out and "verdict: FAIL" in out


def test_unbalance_verdict_passes_below_the_onset(tmp_path, whip_onset):
    assert whip_onset > 4000
    out, s = _run("unbalance", _case(tmp_path, (3000, 4000)), tmp_path / "u", "--no-figures")
    assert s["stable_in_operating_range"]["value"] is True
    assert s["min_log_dec_in_operating_range"]["value"] >= 0
    assert s["verdict"]["value"] == "pass" and "verdict: pass" in out


def test_onset_already_below_the_range_is_reported_at_its_lower_end(tmp_path, whip_onset):
    out, s = _run("unbalance", _case(tmp_path, (5000, 8000)), tmp_path / "u", "--no-figures")
    assert whip_onset < 5000
    assert s["instability_onset_in_operating_range_rpm"]["value"] == pytest.approx(5000)
    assert "UNSTABLE already at 5000 rpm" in out


def test_campbell_has_a_log_dec_panel_a_verdict_and_a_frequency_limit(tmp_path, whip_onset):
    from rotaflex.core.result import load_result

    case = _case(tmp_path, (4000, 8000))
    text = case.read_text().replace(
        "operating_range_rpm = [4000, 8000]", "operating_range_rpm = [4000, 8000]\nfrequency_limit_hz = 60", 1
    )
    case.write_text(text)
    out, s = _run("campbell", case, tmp_path / "c")
    assert "UNSTABLE from" in out
    assert s["instability_onset_in_operating_range_rpm"]["value"] == pytest.approx(whip_onset, rel=1e-5)
    assert (tmp_path / "c" / "campbell.png").exists()
    fig = load_result(tmp_path / "c" / "result.nc").plot()["campbell"]
    fig.canvas.draw()
    top, panel = fig.axes[:2]
    assert "log decrement" in panel.get_ylabel()
    levels = {round(float(line.get_ydata()[0]), 6) for line in panel.get_lines() if len(set(line.get_ydata())) == 1}
    assert {0.0, 0.1} <= levels
    assert top.get_ylim()[1] == pytest.approx(60.0)
    # the modes above 60 Hz all along (the 140-145 Hz pair) are not drawn
    drawn = [line for line in top.get_lines() if line.get_linestyle() in ("-", "--") and len(line.get_xdata()) > 2]
    assert all(
        np.nanmin(np.asarray(line.get_ydata(), float)) <= 60 for line in drawn if np.any(np.isfinite(line.get_ydata()))
    )
    # the operating range is shaded in the log-dec panel too; no legend inside either panel
    assert any(p.get_label() == "operating range" for p in panel.patches)
    assert top.get_legend() is None and panel.get_legend() is None and fig.legends
