"""Steady-state post-processing on signals with known answers."""

import math

import numpy as np
import pytest

from rotaflex.core.errors import InputError
from rotaflex.gear.results.steady import cycle_change, detect_period, harmonic_amplitudes, steady_metrics

SPC = 64


def _signal(f, n_cycles=12):
    t = np.arange(n_cycles * SPC) / SPC  # time in mesh cycles
    return t, f(t)


def test_periodic_signal_is_detected_with_period_one():
    _, x = _signal(lambda t: 3.0 + np.sin(2 * np.pi * t) + 0.2 * np.cos(4 * np.pi * t))
    per = detect_period(x, SPC, 1e-9)
    assert per.period == 1 and per.change < 1e-12


def test_subharmonic_signal_has_period_two():
    _, x = _signal(lambda t: np.sin(2 * np.pi * t) + 0.5 * np.sin(np.pi * t))
    per = detect_period(x, SPC, 1e-9)
    assert per.period == 2
    assert per.changes[0] > 0.3  # period 1 fails clearly


def test_quasi_periodic_signal_is_not_periodic():
    _, x = _signal(lambda t: np.sin(2 * np.pi * t) + 0.3 * np.sin(2 * np.pi * math.sqrt(2) * t), n_cycles=40)
    per = detect_period(x, SPC, 1e-4, max_period=4)
    assert per.period == 0
    assert per.change > 0.05  # the measured change is reported


def test_change_of_a_decaying_transient_is_the_decay_per_cycle():
    d = 0.9
    _, x = _signal(lambda t: d**t * np.sin(2 * np.pi * t))
    # |x(t) - x(t-1)| = (1-d) d^(t-1) |sin|; relative to p2p of the last cycle ~ 2 d^(n-1)
    c = cycle_change(x, SPC, 1, scale=1.0)
    n = 12
    assert c == pytest.approx((1 / d - 1) * d ** (n - 1 + 0.25), rel=0.05)


def test_harmonic_amplitudes_exact_on_whole_cycles():
    _, x = _signal(lambda t: 5 + 1.5 * np.sin(2 * np.pi * t + 0.3) + 0.25 * np.cos(6 * np.pi * t))
    amp = harmonic_amplitudes(x, SPC, 10)
    assert amp == pytest.approx([1.5, 0.0, 0.25], abs=1e-12)


def test_steady_metrics_known_signal():
    _, f = _signal(lambda t: 100 + 150 * np.sin(2 * np.pi * t))
    force = np.maximum(f, 0.0)
    dte = 1e-6 * np.sin(2 * np.pi * np.arange(len(f)) / SPC)
    m = steady_metrics(dte, force, 100.0, SPC, 10)
    assert m["dynamic_factor"] == pytest.approx(2.5, rel=1e-3)
    # sin < -2/3 on a share acos(2/3) / pi of the time... i.e. (pi - 2 asin(2/3)) / (2 pi)
    share = (math.pi - 2 * math.asin(2 / 3)) / (2 * math.pi)
    assert m["contact_loss_fraction"] == pytest.approx(share, abs=2 / SPC)
    assert m["dte_pp"] == pytest.approx(2e-6, rel=1e-2)
    assert m["dte_rms"] == pytest.approx(1e-6 / math.sqrt(2), rel=1e-9)
    assert m["dte_h1"] == pytest.approx(1e-6, rel=1e-9)
    with pytest.raises(InputError, match="n_cycles"):
        steady_metrics(dte, force, 100.0, SPC, 13)


def test_cli_gear_steady_runs_a_short_sweep(tmp_path):
    """`rotaflex gear steady` runs the example's model over a short sweep and writes the set."""
    import json
    import re
    from pathlib import Path

    from typer.testing import CliRunner

    from rotaflex.cli import app

    example = Path(__file__).parents[2] / "examples" / "gear" / "steady" / "torsional_dynamic_factor.toml"
    text, n = re.subn(r"speeds_rpm = \[[^\]]*\]", "speeds_rpm = [4000.0, 8000.0, 16000.0]", example.read_text())
    assert n == 1
    (tmp_path / "c.toml").write_text(text)
    res = CliRunner().invoke(app, ["gear", "steady", str(tmp_path / "c.toml"), "--out", str(tmp_path / "o"), "-q"])
    assert res.exit_code == 0, res.output
    assert (tmp_path / "o" / "result.nc").exists()
    summary = json.loads((tmp_path / "o" / "summary.json").read_text())
    for d in ("up", "down"):
        assert summary[f"max_dynamic_factor_{d}"]["value"] >= 1.0
        assert summary[f"speed_at_max_dynamic_factor_{d}"]["value"] in (4000.0, 8000.0, 16000.0)
    # the linear resonance speed is a property of the model, not of the sampled speeds
    assert 10000.0 < summary["resonance_speed"]["value"] < 20000.0
