"""The command line end to end: exit codes, one-line errors, files written.

The runs whose point is the files they write go through :func:`rotaflex.cli.main` in this
process (the console script's code path, without one interpreter start and import per run);
the error paths run ``python -m rotaflex`` as a child process (what a user's shell sees).
"""

import json
import subprocess
import sys
from pathlib import Path

import pytest

from rotaflex.cli import main

ROOT = Path(__file__).resolve().parents[1]


def rotaflex(*args, cwd=None):
    return subprocess.run(
        [sys.executable, "-m", "rotaflex", *map(str, args)], capture_output=True, text=True, cwd=cwd, timeout=600
    )


def rotaflex_here(*args) -> int:
    """Exit status of the CLI's entry point run in this process on ``args``."""
    with pytest.raises(SystemExit) as exit_:
        main([str(a) for a in args])
    return exit_.value.code


@pytest.mark.parametrize(
    "example",
    sorted(
        p
        for p in (ROOT / "examples" / "rotor").glob("*.toml")
        if not p.stem.startswith("fe_") and "[[shaft]]" not in p.read_text(encoding="utf-8")
    ),  # FE verbs (fe_*.toml and the other files with [[shaft]] tables): tests/rotor/fe
    ids=lambda p: p.stem,
)
def test_rotor_examples_run(example, tmp_path, capsys):
    code = rotaflex_here("rotor", "simulate", example, "--out", tmp_path, "--quiet")
    expected = 1 if "spherical" in example.stem else 0  # that one stops at its singularity by design
    assert code == expected, capsys.readouterr().err
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["status"]["value"] == ("singular" if expected else "success")
    assert (tmp_path / "result.nc").stat().st_size > 0 and (tmp_path / "omega_body.png").exists()


def test_bad_value_exits_2_with_one_line(tmp_path):
    cfg = tmp_path / "bad.toml"
    cfg.write_text('domain = "rotor"\n[disk]\nmass = -2.0\n')
    proc = rotaflex("rotor", "simulate", cfg, "--out", tmp_path / "o")
    assert proc.returncode == 2
    assert proc.stderr.strip().splitlines() == ["error: disk.mass = -2.0 is invalid: expected a number > 0 [kg]"]
    assert not (tmp_path / "o" / "result.nc").exists()


def test_unknown_key_and_debug_traceback(tmp_path):
    cfg = tmp_path / "bad.toml"
    cfg.write_text("[solver]\ntend = 3\n")
    proc = rotaflex("rotor", "simulate", cfg, "--out", tmp_path / "o")
    assert proc.returncode == 2 and "solver.tend" in proc.stderr and "Traceback" not in proc.stderr
    proc = rotaflex("rotor", "simulate", cfg, "--out", tmp_path / "o", "--debug")
    assert proc.returncode != 0 and "Traceback" in proc.stderr


def test_failed_run_keeps_earlier_results(tmp_path):
    good = ROOT / "examples" / "rotor" / "disk_whirl_linear.toml"
    assert rotaflex_here("rotor", "simulate", good, "--out", tmp_path, "-q") == 0
    before = (tmp_path / "result.nc").read_bytes()
    bad = tmp_path / "bad.toml"
    bad.write_text("[solver]\nrtol = 2.0\n")
    assert rotaflex("rotor", "simulate", bad, "--out", tmp_path).returncode == 2
    assert (tmp_path / "result.nc").read_bytes() == before


def test_reproduce_rotor_fast_writes_report(tmp_path, capsys):
    code = rotaflex_here("reproduce", "rotor", "--out", tmp_path, "--fast", "--quiet")
    assert code == 0, capsys.readouterr().err
    md = (tmp_path / "report.md").read_text()
    for n in range(3, 14):
        assert f"### Fig. {n}" in md
        assert (tmp_path / "rotor" / f"fig{n:02d}.png").exists()
    checks = json.loads((tmp_path / "checks.json").read_text())
    verification = [c for sec in checks.values() for c in sec if not c["claim"]]
    assert verification and all(c["passed"] for c in verification), [c for c in verification if not c["passed"]]
    assert "<img src='rotor/fig03.png'" in (tmp_path / "index.html").read_text()


def test_unknown_reproduce_target(tmp_path):
    proc = rotaflex("reproduce", "planets", "--out", tmp_path)
    assert proc.returncode == 2 and "target = 'planets'" in proc.stderr
