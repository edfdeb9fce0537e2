"""Bad input (one line naming the field, exit 2) and the CLI verbs on the example gearbox."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from rotaflex.core.errors import InputError
from rotaflex.system.model import Gearbox

ROOT = Path(__file__).resolve().parents[2]


def _both_speeds(c):
    c["rotor"][0].update(speed_rpm=3000.0)
    c["rotor"][1].update(speed_rpm=3000.0)  # 20/40 teeth: must be 1500


def _drive_on_wheel(c):
    c["drive"].update(rotor="out", node=0)
    c["load"].update(rotor="in", node=0)


@pytest.mark.parametrize(
    ("edit", "field"),
    [
        (lambda c: c["rotor"][1].update(center=[0.095, 0.0]), "rotor[1].center"),
        (lambda c: c["gear_mesh"][0].update(pinion_node=99), "gear_mesh[0].pinion_node"),
        (lambda c: c["gear_mesh"][0].update(wheel_rotor="nope"), "gear_mesh[0].wheel_rotor"),
        (lambda c: c["rotor"][1].update(torsion=False), "gear_mesh[0].wheel_node"),
        (_both_speeds, "rotor[1].speed_rpm"),
        (lambda c: c["rotor"][1].update(rotation="ccw"), "rotor[1].rotation"),
        (lambda c: c["gear_mesh"][0].update(driver="wheel"), "gear_mesh[0].driver"),
        (_drive_on_wheel, "gear_mesh[0].driver"),
    ],
)
def test_bad_input_names_the_field(make, edit, field):
    cfg = make()
    edit(cfg)
    with pytest.raises(InputError) as exc:
        Gearbox.from_mapping(cfg)
    assert exc.value.field == field


def test_consistent_speeds_and_senses_accepted(make):
    cfg = make()
    cfg["rotor"][0].update(speed_rpm=3000.0, rotation="ccw")
    cfg["rotor"][1].update(speed_rpm=1500.0, rotation="cw")  # 20/40 teeth: half the speed, reversed
    box = Gearbox.from_mapping(cfg)
    assert box.speeds(100.0) == pytest.approx([100.0, -50.0])
    assert box.mesh_frequency(0, 100.0) == pytest.approx(2000.0)


def _cli(*args):
    from typer.testing import CliRunner

    from rotaflex.cli import app

    return CliRunner().invoke(app, [*args, "-q", "--no-figures"])


def test_cli_bad_centre_exits_2(tmp_path):
    text = (ROOT / "examples/system/gearbox.toml").read_text()
    cfg = tmp_path / "bad.toml"
    cfg.write_text(text.replace("center = [0.09015, 0.0]", "center = [0.1, 0.0]"))
    r = _cli("system", "modal", str(cfg), "--out", str(tmp_path / "o"))
    assert r.exit_code == 2
    lines = [ln for ln in r.output.strip().splitlines() if ln]
    assert len(lines) == 1 and "rotor[1].center" in lines[0], r.output


def test_cli_modal_on_example(tmp_path):
    r = _cli("system", "modal", str(ROOT / "examples/system/gearbox.toml"), "--out", str(tmp_path / "m"))
    assert r.exit_code == 0, r.output
    s = json.loads((tmp_path / "m" / "summary.json").read_text())
    assert s["mode_0_frequency_hz"]["unit"] == "Hz"
    k = s["mesh_mode"]["value"]
    assert 0.3 < s[f"mode_{k}_mesh_energy"]["value"] <= 1.0


def test_validate_config_checks_every_analysis_table(make):
    from rotaflex.system.case import validate_config

    cfg = make()
    validate_config(cfg)
    cfg["steady"] = {"speed_rpm": -5.0}
    with pytest.raises(InputError) as exc:
        validate_config(cfg)
    assert exc.value.field == "steady.speed_rpm"
