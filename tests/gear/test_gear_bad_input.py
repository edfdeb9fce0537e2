"""Gear input that the configuration refuses up front: exit code 2 and one line on stderr that
names the dotted field (and, for sizes, the estimate), before anything is simulated.

Each case is a short TOML on the coarse mesh; a refused case must not write a result.
"""

import pytest
from typer.testing import CliRunner

from rotaflex.cli import app

BASE = 'domain = "gear"\n[mesh]\npreset = "coarse"\n'


def _run(tmp_path, text):
    cfg = tmp_path / "case.toml"
    cfg.write_text(BASE + text)
    res = CliRunner().invoke(app, ["gear", "simulate", str(cfg), "--out", str(tmp_path / "o"), "-q"])
    return res


@pytest.mark.parametrize(
    "text, start, must",
    [
        # the tooth count is refused by name, not through a radius derived from it
        ("[gear]\nteeth = 6\n", "error: gear.teeth = 6 is invalid", ("26..29",)),
        # contact ratio < 1 (tip radius 45.8 mm: eps_alpha = 0.77)
        ("[gear]\ntip_radius = 0.0458\n", "error: gear.tip_radius = 0.0458 is invalid", ("contact ratio >= 1",)),
        # E = 1 Pa: physically meaningless (bound 1e8 Pa, see rotaflex.gear.cases.simulate_config)
        ("[material]\nyoungs_modulus = 1\n", "error: material.youngs_modulus = 1", ("> 1e+08",)),
        ("[solver]\ntolerance = 1.0\n", "error: solver.tolerance = 1.0", ("<= 1e-06", ">= 1e-16")),
        ('[solver]\nmethod = "reduced_hht"\nmodes = 0\n', "error: solver.modes = 0", (">= 1",)),
        # a span shorter than one output record (10 steps of 7.2e-4 deg at 4000 rpm, dt 3e-8 s)
        (
            "[operation]\nspan_deg = 1e-9\n",
            "error: operation.span_deg = 1e-09",
            ("at least one output record", "0.0072 deg"),
        ),
        # step budget: theta_s = 21.06 deg / (418.9 rad/s x 1e-13 s) = 8.78e9 steps
        ("[solver]\ndt = 1e-13\n", "error: solver.dt = 1e-13", ("<= 1e+07 steps", "8.78e+09 steps")),
        # memory budget: every step recorded over 3000 deg (4.2e6 records)
        (
            "[operation]\nspan_deg = 3000.0\n[output]\nevery = 1\n",
            "error: output.every = 1",
            ("<= 2 GB", "4.17e+06 records"),
        ),
        # the value is echoed as typed (60, not 59.99999999999999 from a degree round trip)
        (
            "[model]\nteeth_per_gear = 2\n[operation]\nspan_deg = 60\n",
            "error: operation.span_deg = 60",
            ("with 2 teeth per gear",),
        ),
    ],
)
def test_refused_with_one_line_naming_the_field(tmp_path, text, start, must):
    res = _run(tmp_path, text)
    assert res.exit_code == 2, res.output
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1, res.stderr
    assert lines[0].startswith(start), lines[0]
    for m in must:
        assert m in lines[0], (m, lines[0])
    assert "59.9999" not in lines[0]
    assert not (tmp_path / "o" / "result.nc").exists()


def test_result_failing_its_own_check_exits_1_and_names_the_check(tmp_path, monkeypatch):
    """A finished run whose tie residual is above the threshold has status failed_check.

    The threshold is lowered to 0 m here (the paper cases stay below 1e-11 m, far under the
    1 um default) to exercise the status, the message and the exit code on a short run."""
    from rotaflex.gear.cases import simulate_config as config

    monkeypatch.setattr(config, "MAX_TIE_RESIDUAL", 0.0)
    res = _run(tmp_path, "[operation]\nspan_deg = 0.05\n")
    assert res.exit_code == 1, res.output
    assert "failed check" in res.output and "constraint residual" in res.output
    assert (tmp_path / "o" / "result.nc").exists()


@pytest.mark.parametrize(
    "config, field",
    [
        ({"gear": {"teeth": 6}}, "gear.teeth"),
        ({"operation": {"span_deg": 1e-9}}, "operation.span_deg"),
        ({"solver": {"method": "reduced_hht", "modes": 0}}, "solver.modes"),
        ({"solver": {"dt": 1e-7}}, "solver.dt"),  # above the RK4 limit of the coarse mesh
    ],
)
def test_validate_config_refuses_without_running(config, field):
    """validate_config raises the same InputError as a run, without integrating."""
    from rotaflex.core.errors import InputError
    from rotaflex.gear.cases.simulate import validate_config

    with pytest.raises(InputError) as exc:
        validate_config({"mesh": {"preset": "coarse"}, **config})
    assert exc.value.field == field


def test_validate_config_accepts_every_shipped_example():
    import tomllib
    from pathlib import Path

    from rotaflex.core.errors import InputError
    from rotaflex.gear.cases.simulate import validate_config

    for path in sorted((Path(__file__).resolve().parents[2] / "examples" / "gear").glob("*.toml")):
        cfg = {k: v for k, v in tomllib.loads(path.read_text()).items() if k != "domain"}
        cfg.setdefault("mesh", {})["preset"] = "coarse"  # cheap assembly; limits checked alike
        if cfg.get("pinion", {}).get("helix_angle_deg", 0.0) > 0.0:  # static + steady only
            with pytest.raises(InputError, match="pinion.helix_angle_deg"):
                validate_config(cfg)
            continue
        assert validate_config(cfg) is None, path.name
