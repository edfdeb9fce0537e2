"""Bad FE rotor input: exit status 2, one stderr line naming the field.

The CLI runs in-process (Click's runner, stderr kept apart) so that the thirteen cases cost
milliseconds each; one case also goes through a real subprocess.
"""

import subprocess
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

from rotaflex.cli import app

BASE = """
[[shaft]]
outer_diameter = 0.05
length = 1.0
elements = 4
[[bearing]]
node = 0
kxx = 1e6
kyy = 1e6
[[bearing]]
node = 4
kxx = 1e6
kyy = 1e6
"""

CASES = {
    "overlap": (
        """
[[shaft]]
outer_diameter = 0.05
length = 1.0
[[shaft]]
outer_diameter = 0.05
start = 0.8
length = 0.5
[[bearing]]
node = 0
kxx = 1e6
kyy = 1e6
""",
        "modal",
        "shaft[1].start",
    ),
    "gap": (
        """
[[shaft]]
outer_diameter = 0.05
length = 1.0
[[shaft]]
outer_diameter = 0.05
start = 1.1
length = 0.5
""",
        "modal",
        "shaft[1].start",
    ),
    "missing_node": (BASE + "[[disk]]\nnode = 9\nmass = 1.0\nId = 0.1\nIp = 0.2\n", "modal", "disk[0].node"),
    "bearing_missing_node": (BASE.replace("node = 4", "node = 7"), "modal", "bearing[1].node"),
    "bearing_off_node_position": (BASE.replace("node = 4", "position = 0.6"), "modal", "bearing[1].position"),
    "negative_diameter": (
        BASE.replace("outer_diameter = 0.05", "outer_diameter = -0.05"),
        "modal",
        "shaft[0].outer_diameter",
    ),
    "non_finite_stiffness": (
        BASE.replace("kxx = 1e6\nkyy = 1e6\n[[bearing]]", "kxx = nan\nkyy = 1e6\n[[bearing]]"),
        "modal",
        "bearing[0].kxx",
    ),
    "free_free_without_flag": (
        """
[[shaft]]
outer_diameter = 0.05
length = 1.0
elements = 4
""",
        "modal",
        "free",
    ),
    "speed_table_not_covering": (
        BASE.replace(
            "kxx = 1e6\nkyy = 1e6\n[[bearing]]",
            "kxx = [1e6, 2e6]\nkyy = [1e6, 2e6]\nspeed_rpm = [0, 3000]\n[[bearing]]",
        )
        + "[campbell]\nspeed_rpm = [0, 5000]\n",
        "campbell",
        "campbell.speed_rpm",  # the analysis key to change (issue 38; was the table's key)
    ),
    "table_length_mismatch": (
        BASE.replace("kxx = 1e6\nkyy = 1e6\n[[bearing]]", "kxx = [1e6, 2e6, 3e6]\nspeed_rpm = [0, 3000]\n[[bearing]]"),
        "modal",
        "bearing[0].kxx",
    ),
    "unknown_key": (BASE + "[modal]\nspeed = 100\n", "modal", "modal.speed"),
    "unbalance_without_mass": (BASE + "[unbalance]\nspeed_rpm = [0, 1000]\n", "unbalance", "unbalance.mass"),
}


@pytest.mark.parametrize("name", list(CASES))
def test_bad_input_cli(name, tmp_path: Path):
    text, verb, field = CASES[name]
    cfg = tmp_path / "case.toml"
    cfg.write_text(text)
    res = CliRunner().invoke(app, ["rotor", verb, str(cfg), "--out", str(tmp_path / "o"), "-q", "--no-figures"])
    assert res.exit_code == 2, res.stderr
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1, res.stderr
    assert lines[0].startswith(f"error: {field}"), lines[0]
    assert not (tmp_path / "o" / "result.nc").exists()


def test_bad_input_subprocess(tmp_path: Path):
    text, verb, field = CASES["gap"]
    cfg = tmp_path / "case.toml"
    cfg.write_text(text)
    root = Path(__file__).resolve().parents[3]
    proc = subprocess.run(
        [sys.executable, "-m", "rotaflex", "rotor", verb, str(cfg), "--out", str(tmp_path / "o"), "-q"],
        capture_output=True,
        text=True,
        cwd=root,
        env={"PYTHONPATH": str(root / "src"), "PATH": "/usr/bin:/bin", "OMP_NUM_THREADS": "1"},
    )
    assert proc.returncode == 2
    assert proc.stderr.strip().splitlines() == [
        "error: shaft[1].start = 1.1 is invalid: expected 1 m: the section leaves a gap after the previous one "
        "(sections must be contiguous, left to right)"
    ]
