"""`system response` without an excitation is refused, naming the key that would give one
(issue 37: "no silent zeros"; it reported "largest dynamic mesh force 0 N" with exit 0)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from rotaflex.cli import app
from rotaflex.core.config import load_toml
from rotaflex.core.errors import InputError
from rotaflex.system.model import Gearbox
from rotaflex.system.response import forced_response, te_harmonics

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "system" / "gearbox.toml"


def _case(tmp_path: Path, source: str, te_pp: str = "5.0e-6") -> Path:
    text = EXAMPLE.read_text()
    assert 'source = "contact_pattern"' in text and "unloaded_te_pp = 5.0e-6" in text
    p = tmp_path / f"{source}.toml"
    text = text.replace('source = "contact_pattern"', f'source = "{source}"')
    p.write_text(text.replace("unloaded_te_pp = 5.0e-6", f"unloaded_te_pp = {te_pp}"))
    return p


def _cli(*args):
    return CliRunner().invoke(app, [*args, "-q", "--no-figures"])


def test_iso6336_mesh_has_no_te_harmonics(tmp_path):
    """The premise, by the model's definition: ISO 6336's c_gamma_alpha b is one constant, so the
    loaded TE F_0 / k is constant and its mesh-frequency harmonics are round-off of it."""
    box = Gearbox.from_mapping(load_toml(_case(tmp_path, "iso6336")))
    g = box.meshes[0].gear
    assert np.ptp(g.table.stiffness) == 0 and not np.any(g.table.unloaded_te)
    static = g.torque / g.base_radius[0] / g.table.stiffness[0]
    assert np.max(np.abs(te_harmonics(box, 0, 3))) < 1e-12 * static
    with pytest.raises(InputError) as err:
        forced_response(box, [100.0, 200.0])
    assert err.value.field == "gear_mesh[0].source" and err.value.value == "iso6336"


def test_cli_refuses_with_one_line_naming_the_key(tmp_path):
    r = _cli("system", "response", str(_case(tmp_path, "iso6336")), "--out", str(tmp_path / "o"))
    assert r.exit_code == 2
    lines = [ln for ln in r.output.strip().splitlines() if ln]
    assert len(lines) == 1 and "gear_mesh[0].source" in lines[0] and "loaded_te" in lines[0], r.output
    assert not (tmp_path / "o" / "result.nc").exists()


def test_unloaded_te_of_a_perfect_pair_names_the_excitation_key(tmp_path):
    """contact_pattern with no unloaded TE: only the loaded TE varies; asking for the unloaded
    one names response.excitation (the loaded default runs)."""
    box = Gearbox.from_mapping(load_toml(_case(tmp_path, "contact_pattern", "0.0")))
    assert not np.any(box.meshes[0].gear.table.unloaded_te)
    with pytest.raises(InputError) as err:
        forced_response(box, [100.0, 200.0], excitation="unloaded_te")
    assert err.value.field == "response.excitation"
    r = forced_response(box, [100.0, 200.0])  # loaded_te: the stiffness variation excites
    assert np.max(np.abs(r.mesh_force)) > 0
