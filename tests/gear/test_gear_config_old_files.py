"""Old [gear] files: each verb reads its own old layout as before, and a [gear] layout it does not
read gets one line (exit 2) saying what to write instead."""

import tomllib
from pathlib import Path

import pytest
from typer.testing import CliRunner

from rotaflex.cli import app

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "gear"
INSTEAD = 'write [pinion]/[wheel] (see rotaflex gear template --verb {verb}) or pair = "lee_jang"'
#: gear steady's old [gear] layout: two gears, the material inside [gear]
STEADY_GEAR = 'domain = "gear"\n[gear]\nteeth = [28, 28]\nmodule = 3.175e-3\nyoungs_modulus = 210e9\n'


def cli(verb: str, path: Path, tmp_path: Path):
    return CliRunner().invoke(app, ["gear", verb, str(path), "--out", str(tmp_path / "out"), "-q", "--no-figures"])


@pytest.mark.parametrize(
    ("verb", "text", "field"),
    [
        # the paper's simulate file (no [gear] table: its defaults) and one with [gear] + [material]
        ("static", (EXAMPLES / "4000rpm.toml").read_text(), "pinion"),
        ("static", 'domain = "gear"\n[gear]\nteeth = 28\n[material]\ndensity = 7800.0\n', "gear"),
        ("static", STEADY_GEAR, "gear"),
        ("simulate", STEADY_GEAR, "gear.teeth"),
        ("steady", (EXAMPLES / "4000rpm.toml").read_text(), "operation.speed_rpm"),
        ("steady", 'domain = "gear"\n[gear]\nteeth = 28\n', "gear.teeth"),
        ("steady", 'domain = "gear"\ndisk_inertia = 3e-4\n', "disk_inertia"),
    ],
)
def test_a_gear_layout_the_verb_does_not_read_gets_one_line(verb, text, field, tmp_path):
    path = tmp_path / "old.toml"
    path.write_text(text)
    res = cli(verb, path, tmp_path)
    assert res.exit_code == 2, res.output
    lines = res.output.strip().splitlines()
    assert len(lines) == 1, res.output
    assert lines[0].startswith(f"error: {field} = ")
    assert INSTEAD.format(verb=verb) in lines[0]


def test_each_verb_still_reads_its_own_old_layout():
    from rotaflex.gear.cases.simulate_config import load_config
    from rotaflex.gear.cases.steady import _checked

    paper = load_config(tomllib.loads((EXAMPLES / "4000rpm.toml").read_text()))
    assert paper.pinion is None and paper.gear.teeth == 28  # the paper layout, unchanged
    cfg = load_config(tomllib.loads("[gear]\nteeth = 30\ntip_radius = 0.051\nroot_radius = 0.0437\n"))
    assert cfg.gear.teeth == 30
    steady = _checked(tomllib.loads(STEADY_GEAR.replace('domain = "gear"\n', "") + '[model]\nmethod = "lumped"\n'))
    assert steady.pinion is None and steady.gear.teeth == (28, 28)
