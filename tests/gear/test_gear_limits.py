"""Size limits of `gear steady`, `gear static` and `gear simulate`, checked before the run starts.

Each refusal is exit 2 / an InputError naming the key and the estimate; a run just under a limit
is accepted; the step estimate is compared with the steps the solver actually takes.
"""

import copy
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest
from typer.testing import CliRunner

from rotaflex.cli import app
from rotaflex.core.errors import InputError
from rotaflex.core.limits import set_max_memory
from rotaflex.gear.cases import steady_size
from rotaflex.gear.cases.static import load_config as static_config
from rotaflex.gear.cases.steady import run_torsional, validate_config

ROOT = Path(__file__).resolve().parents[2]
#: a lumped steady state that is cheap to build (analytic mesh table) and to run
SMALL = {
    "mesh_stiffness": {"source": "contact_pattern", "table_points": 64},
    "steady": {"fixed_cycles": 12, "eval_cycles": 4, "steps_per_cycle": 60},
}


def _with(base: dict, **tables) -> dict:
    cfg = copy.deepcopy(base)
    for table, keys in tables.items():
        cfg.setdefault(table, {}).update(keys)
    return cfg


def _refused(cfg: dict, run=validate_config) -> InputError:
    with pytest.raises(InputError) as exc:
        run(cfg)
    return exc.value


def test_cli_refuses_a_billion_steady_cycles_with_one_line(tmp_path):
    case = tmp_path / "case.toml"
    case.write_text('domain = "gear"\n[steady]\nmax_cycles = 1000000000\n')
    proc = subprocess.run(
        [sys.executable, "-m", "rotaflex", "gear", "steady", str(case), "--out", str(tmp_path / "o"), "-q"],
        capture_output=True,
        text=True,
        cwd=ROOT,
        env={"PYTHONPATH": str(ROOT / "src"), "PATH": "/usr/bin:/bin", "OMP_NUM_THREADS": "1"},
        timeout=120,
    )
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1, proc.stderr
    # 1e9 cycles x 100 steps per cycle = 1e11 steps, against 5e7
    assert lines[0].startswith("error: steady.max_cycles = 1000000000"), lines[0]
    assert "~1e+11" in lines[0] and "5e+07" in lines[0] and "MAX_STEPS" in lines[0]
    assert not (tmp_path / "o" / "result.nc").exists()


@pytest.mark.parametrize(
    "tables, field, must",
    [
        ({"mesh_stiffness": {"table_points": 10**9}}, "mesh_stiffness.table_points", "~1e+09"),
        # the old spelling of the table is the one named
        ({"mesh": {"table_points": 10**9}}, "mesh.table_points", "~1e+09"),
        ({"steady": {"steps_per_cycle": 10**9}}, "steady.steps_per_cycle", "~4e+11"),
        ({"steady": {"fixed_cycles": 10**8}}, "steady.fixed_cycles", "~1e+10"),
        # 20,000 speeds x 2 directions: 4e4 steady states against 1e4
        ({"sweep": {"speeds_rpm": [1000.0 + i for i in range(20000)]}}, "sweep.speeds_rpm", "~4e+04"),
    ],
)
def test_steady_refuses_sizes_at_the_config_boundary(tables, field, must):
    err = _refused(_with({}, **tables))
    assert err.field == field and must in str(err), str(err)


def test_steady_history_memory_is_held_to_the_memory_limit():
    # 2,000 steps per cycle x 10 evaluated cycles: 60 cycles of rows x 16 values x 8 B = 15.4 MB
    cfg = _with(SMALL, steady={"steps_per_cycle": 2000, "eval_cycles": 10, "fixed_cycles": 12})
    est = steady_size.planned_size(steady_size_cfg(cfg))["history_bytes"]
    assert est == pytest.approx(8 * 16 * (10 + 2 * (10 + 10)) * 2000)
    try:
        set_max_memory(est * 0.99)
        err = _refused(cfg)
        assert err.field == "steady.steps_per_cycle" and "memory" in str(err) and "--max-memory" in str(err)
        set_max_memory(est * 1.01)
        validate_config(cfg)
    finally:
        set_max_memory(None)


def steady_size_cfg(cfg):
    from rotaflex.gear.cases.steady import _checked

    return _checked(cfg)


def test_step_estimate_matches_the_steps_run_and_the_limit_is_inclusive(monkeypatch):
    """Config boundary: 12 cycles x 60 steps = 720 steps (a lower bound); the model check knows
    that the solver raises the steps per cycle to resolve the fastest mode at 40 points a period
    (66 here), so its estimate 12 x 66 = 792 is the exact count for fixed_cycles. A limit of
    exactly that runs; one step less is refused."""
    cfg_checked = steady_size_cfg(SMALL)
    assert steady_size.planned_size(cfg_checked)["steps"] == 720
    monkeypatch.setattr(steady_size, "MAX_STEPS", 792)
    ds = run_torsional(SMALL).dataset
    actual = int(ds["cycles_run"]) * int(ds.attrs["samples_per_cycle"])
    assert actual == 792
    # the config-boundary estimate is within a factor 1.25 of the count at this speed
    assert 720 <= actual <= 1.25 * 720
    monkeypatch.setattr(steady_size, "MAX_STEPS", 791)
    err = _refused(SMALL, run_torsional)
    assert err.field == "steady.fixed_cycles" and "~792" in str(err)


def test_low_speed_is_refused_by_the_model_check_naming_the_speed():
    """At 1 rpm the mesh cycle is 10,000 x longer than at 10,000 rpm while the modes stay: the
    solver would take ~10,000 x more steps per cycle, which only the model check can see."""
    cfg = _with(SMALL, operation={"speed_rpm": 1.0}, steady={"fixed_cycles": 400})
    validate_config(cfg)  # 400 x 60 steps: fine at the config boundary
    err = _refused(cfg, run_torsional)
    assert err.field == "operation.speed_rpm" and "steps per mesh cycle" in str(err), str(err)


def _static_example() -> dict:
    cfg = tomllib.loads((ROOT / "examples" / "gear" / "unequal_shifted_relief.toml").read_text())
    cfg.pop("domain", None)
    return cfg


@pytest.mark.parametrize(
    "analysis, field, must",
    [
        ({"refinement": [1, 2, 3, 4, 1, 2, 3, 4, 1]}, "analysis.refinement", "~9"),
        ({"compliance_diameters_wheel": [0.1] * 1001}, "analysis.compliance_diameters_wheel", "~1e+03"),
    ],
)
def test_static_refuses_list_lengths(analysis, field, must):
    cfg = _with(_static_example(), analysis=analysis)
    err = _refused(cfg, static_config)
    assert err.field == field and must in str(err), str(err)


def test_static_accepts_the_largest_refinement_list():
    cfg = _with(_static_example(), analysis={"refinement": [1, 2, 3, 4, 1, 2, 3, 4]})
    assert len(static_config(cfg).analysis.refinement) == 8


def test_simulate_refuses_a_huge_iteration_cap_and_honours_the_memory_limit(tmp_path, monkeypatch):
    # --max-memory also sets ROTAFLEX_MAX_MEMORY for sweep workers: restored after the test
    monkeypatch.setenv("ROTAFLEX_MAX_MEMORY", "8GiB")
    base = 'domain = "gear"\n[mesh]\npreset = "coarse"\n'
    cases = [
        ("[solver]\nmax_iter = 1000000000\n", "error: solver.max_iter = 1000000000", "1e+05 iterations per step"),
        # 0.05 deg at every step: ~70 records of 8 x 68 B, over a 1 kB limit
        ("[operation]\nspan_deg = 0.05\n[output]\nevery = 1\n", "error: output.every = 1", "--max-memory"),
    ]
    for i, (text, start, must) in enumerate(cases):
        case = tmp_path / f"c{i}.toml"
        case.write_text(base + text)
        args = ["--max-memory", "1kB"] if i == 1 else []
        res = CliRunner().invoke(app, [*args, "gear", "simulate", str(case), "--out", str(tmp_path / "o"), "-q"])
        set_max_memory(None)
        assert res.exit_code == 2, res.output
        lines = res.stderr.strip().splitlines()
        assert len(lines) == 1 and lines[0].startswith(start) and must in lines[0], res.stderr
