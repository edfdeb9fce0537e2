"""What a sweep can check before its first case is checked then: swept keys, a continuation base
file that keeps its own [sweep] table. Each refusal: exit 2, one line, no case directory."""

import pytest
from typer.testing import CliRunner

from rotaflex.cli import app
from rotaflex.core.errors import InputError
from rotaflex.sweep import plan_study
from rotaflex.sweep.spec import parse_vary

runner = CliRunner()

# the gear steady base of tests/sweep/test_continuation.py, plus the verb's own speed sweep table
STEADY = """domain = "gear"
verb = "steady"
[mesh]
source = "contact_pattern"
pair_stiffness = 1.2e8
unloaded_te_pp = 2e-6
damping_ratio = 0.05
table_points = 400
[train]
inertia = [2.965e-4, 2.965e-4]
drive = "motor"
motor_slope = 0.5
[operation]
torque = 22.25
[steady]
eval_cycles = 10
max_cycles = 300
"""
INNER = "[sweep]\nspeeds_rpm = [10000.0, 12000.0, 15000.0]\n"
CONT = ["--vary", "operation.speed_rpm=10000,15000", "--continuation", "operation.speed_rpm"]


@pytest.mark.parametrize("key", ["disk/mass", "disk.mass/2", "a b", "disk.mass;x", "disk.mass\\n"])
def test_keys_outside_config_key_characters_are_refused(key):
    with pytest.raises(InputError) as info:
        parse_vary(f"{key}=1,2")
    assert info.value.field == "--vary" and "\n" not in str(info.value)


def test_a_slash_in_a_swept_key_is_one_line_before_any_case(tmp_path, selftest_domain):
    cfg = tmp_path / "s.toml"
    cfg.write_text('domain = "selftest"\nx = 1.0\n')
    with pytest.raises(InputError, match="not '/'"):
        plan_study({"domain": "selftest", "x": 1.0}, {"x/y": [1.0, 2.0]})
    res = runner.invoke(app, ["sweep", str(cfg), "--vary", "x/y=1,2", "--out", str(tmp_path / "o"), "-j", "0"])
    assert res.exit_code == 2 and res.output.count("\n") == 1 and "--vary = 'x/y'" in res.output
    assert not (tmp_path / "o").exists()


def test_continuation_base_with_its_own_sweep_table_is_refused_before_the_first_case(tmp_path):
    cfg = tmp_path / "c.toml"
    cfg.write_text(STEADY + INNER)
    res = runner.invoke(app, ["sweep", str(cfg), "--out", str(tmp_path / "o"), *CONT, "-j", "0"])
    assert res.exit_code == 2 and res.output.count("\n") == 1, res.output
    assert res.output.startswith("error: sweep = ") and "--continuation operation.speed_rpm" in res.output
    assert not (tmp_path / "o").exists()


def test_the_same_base_without_the_table_plans_and_without_continuation_the_table_is_allowed(tmp_path):
    from rotaflex.core.config import load_toml

    base = tmp_path / "b.toml"
    base.write_text(STEADY)
    study = plan_study(load_toml(base), ["operation.speed_rpm=10000,15000"], "operation.speed_rpm")
    assert len(study.cases) == 4  # two speeds, up and down
    inner = tmp_path / "i.toml"
    inner.write_text(STEADY + INNER)
    assert len(plan_study(load_toml(inner), ["operation.torque=10,20"]).cases) == 2  # a sweep of inner sweeps
