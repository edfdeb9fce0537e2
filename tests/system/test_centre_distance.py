"""The working centre distance of a gearbox mesh follows from its rotors' centres (issue 37:
a gearbox file needed both ``center`` and ``center_distance``, worked out by hand)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from rotaflex.cli import app
from rotaflex.core.config import load_toml
from rotaflex.core.errors import InputError
from rotaflex.system.model import Gearbox

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "system" / "gearbox.toml"


def _without_centre_distance(output_centre: float) -> dict:
    cfg = load_toml(EXAMPLE)
    assert "center_distance" not in cfg["gear_mesh"][0] and "backlash" not in cfg["gear_mesh"][0]
    cfg["rotor"][1]["center"] = [output_centre, 0.0]
    return cfg


def test_centres_alone_give_the_working_centre_distance():
    explicit = load_toml(EXAMPLE)
    explicit["gear_mesh"][0]["center_distance"] = 0.09015
    given = Gearbox.from_mapping(explicit)
    derived = Gearbox.from_mapping(_without_centre_distance(0.09015))
    a_given, a_derived = given.meshes[0].gear.center_distance, derived.meshes[0].gear.center_distance
    assert a_derived == pytest.approx(0.09015, rel=1e-15) and a_derived == pytest.approx(a_given, rel=1e-15)
    # the same pair at the same distance: identical mesh (line of action, backlash, stiffness)
    for name in ("backlash", "damping"):
        assert getattr(derived.meshes[0], name) == pytest.approx(getattr(given.meshes[0], name), rel=1e-12)
    np.testing.assert_allclose(derived.meshes[0].gear.table.stiffness, given.meshes[0].gear.table.stiffness)
    # the backlash grows with the centres' distance: 20/40 teeth, module 3 mm, no shift -> a_0 = 90 mm
    wider = Gearbox.from_mapping(_without_centre_distance(0.0905))
    assert wider.meshes[0].backlash > derived.meshes[0].backlash > 0


def test_centres_too_close_name_the_rotor_centre(tmp_path):
    with pytest.raises(InputError) as err:
        Gearbox.from_mapping(_without_centre_distance(0.0895))  # under a_0 = m (z1 + z2) / 2 = 90 mm
    assert err.value.field == "rotor[1].center" and "0.09" in err.value.allowed
    text = "\n".join(ln for ln in EXAMPLE.read_text().splitlines() if not ln.startswith("center_distance"))
    case = tmp_path / "g.toml"
    case.write_text(text.replace("center = [0.09015, 0.0]", "center = [0.0895, 0.0]"))
    r = CliRunner().invoke(app, ["system", "modal", str(case), "--out", str(tmp_path / "o"), "-q", "--no-figures"])
    lines = [ln for ln in r.output.strip().splitlines() if ln]
    assert r.exit_code == 2 and len(lines) == 1 and "rotor[1].center" in lines[0], r.output
