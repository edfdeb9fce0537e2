"""``rotaflex gear simulate`` end to end on the shipped examples (shortened, coarse mesh)."""

import tomllib
from pathlib import Path

import meshio
import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

from rotaflex.cli import app
from rotaflex.core.config import from_mapping
from rotaflex.core.errors import InputError
from rotaflex.gear.cases.simulate import GearCaseConfig
from rotaflex.gear.cases.simulate_config import load_config

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "gear"
#: the four paper examples differ only in the two speeds and take the same CLI path; the two
#: 4000 rpm files (5x the steps of the 20000 rpm ones for the same 2 deg) run with ``-m slow``,
#: and every example is loaded by test_every_gear_example_is_a_valid_config
PAPER_CASES = (
    pytest.param("4000rpm", marks=pytest.mark.slow),
    "20000rpm",
    pytest.param("4000_4040rpm", marks=pytest.mark.slow),
    "20000_20200rpm",
)


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("*.toml")), ids=lambda p: p.stem)
def test_every_gear_example_is_a_valid_config(path):
    data = tomllib.loads(path.read_text())
    if data.get("pinion", {}).get("helix_angle_deg", 0.0) > 0.0:  # a helical pair: gear static + steady
        from rotaflex.gear.cases.static import load_config as load_static

        assert load_static(data).pair.helical
        with pytest.raises(InputError, match="pinion.helix_angle_deg"):
            _ = load_config(data).pair
        return
    cfg = load_config(data)
    if cfg.pinion is None:  # the paper's cases
        assert cfg == from_mapping(GearCaseConfig, {k: v for k, v in data.items() if k != "domain"})
        assert cfg.operation.torque == pytest.approx(22.25)
    else:  # a drawing pair: the same file is a valid `gear static` config
        from rotaflex.gear.cases.static import load_config as load_static

        static = load_static(data)
        assert static.pair == cfg.pair
        assert static.load.torque == cfg.operation.torque


def test_one_file_runs_gear_static_and_gear_simulate(tmp_path):
    """examples/gear/unequal_shifted_relief.toml through both verbs (coarse mesh, short span)."""
    text = (EXAMPLES / "unequal_shifted_relief.toml").read_text()
    text = text.replace('preset = "default"', 'preset = "coarse"').replace("refinement = [1, 2]", "refinement = [1]")
    text = text.replace("n_angles = 240", "n_angles = 60")  # static: the file runs; accuracy is tested elsewhere
    text = text.replace("[operation]\n", "[operation]\nspan_deg = 0.5\n", 1).replace("dt = 1.8e-8", "dt = 2.4e-8")
    cfg = tmp_path / "pair.toml"
    cfg.write_text(text)
    for verb in ("static", "simulate"):
        out = tmp_path / verb
        res = CliRunner().invoke(app, ["gear", verb, str(cfg), "--out", str(out), "-q", "--no-figures"])
        assert res.exit_code == 0, res.output
        assert (out / "result.nc").exists()
    dyn = xr.open_dataset(tmp_path / "simulate" / "result.nc")
    assert float(dyn["gear_ratio"]) == 2.0
    assert np.degrees(float(dyn["rotation_angle"].sel(gear="A")[-1])) == pytest.approx(0.5, abs=0.05)
    # the driven wheel turns at half the pinion's speed (initial speeds: 1000 and 500 rpm)
    om = dyn["angular_velocity"].values[0]
    assert om[0] / om[1] == pytest.approx(2.0, rel=1e-3)
    static = xr.open_dataset(tmp_path / "static" / "result.nc")
    assert "ste_engagement" in static


def _shortened(name: str, tmp_path: Path, extra: str = "") -> Path:
    """The example with a coarse mesh and a 2-deg span (same tables, edited in place)."""
    text = (EXAMPLES / f"{name}.toml").read_text()
    assert 'preset = "default"' in text
    text = text.replace('preset = "default"', 'preset = "coarse"')
    text = text.replace("[operation]\n", "[operation]\nspan_deg = 2.0\n", 1)
    path = tmp_path / f"{name}.toml"
    path.write_text(text + extra)
    return path


@pytest.mark.parametrize("name", PAPER_CASES)
def test_paper_case_runs_from_the_cli(name, tmp_path):
    out = tmp_path / "out"
    extra = "" if "[output]" in (EXAMPLES / f"{name}.toml").read_text() else "\n[output]\n"
    cfg = _shortened(name, tmp_path, extra)
    cfg.write_text(cfg.read_text().replace("[output]\n", "[output]\nvtu_snapshots = 2\n", 1))
    res = CliRunner().invoke(app, ["gear", "simulate", str(cfg), "--out", str(out), "-q"])
    assert res.exit_code == 0, res.output
    assert "peak contact force" in res.output and "energy balance" in res.output
    ds = xr.open_dataset(out / "result.nc")
    for name_ in (
        "contact_force",
        "rotation_angle",
        "gap",
        "contact_point",
        "tie_multiplier",
        "strain_energy",
        "kinetic_energy",
        "external_work",
        "transmission_error",
    ):
        assert name_ in ds, name_
    assert ds["rotation_angle"].sizes["gear"] == 2
    # the run covered the requested 2 deg of gear A's rotation
    assert np.degrees(float(ds["rotation_angle"].sel(gear="A")[-1])) == pytest.approx(2.0, abs=0.05)
    assert np.all(np.isfinite(ds["contact_force"].values))
    snaps = sorted(out.glob("snapshot_*.vtu"))
    assert len(snaps) == 2
    assert meshio.read(snaps[0]).points.shape[0] > 0
    assert (out / "summary.json").exists() and (out / "contact_force.png").exists()


def test_bad_mesh_preset_is_one_clear_line(tmp_path):
    cfg = _shortened("4000rpm", tmp_path)
    cfg.write_text(cfg.read_text().replace('preset = "coarse"', 'preset = "medium"'))
    res = CliRunner().invoke(app, ["gear", "simulate", str(cfg), "--out", str(tmp_path / "o")])
    assert res.exit_code == 2
    assert "mesh.preset" in res.output and "medium" in res.output
    assert not (tmp_path / "o" / "result.nc").exists()


@pytest.mark.parametrize(
    "extra, field",
    [
        ('[model]\nteeth_per_gear = 2\n[solver]\nmethod = "reduced_hht"\n', "solver.method"),
        ('[solver]\nmethod = "reduced_hht"\nrestitution = 0.5\n', "solver.restitution"),
    ],
)
def test_unsupported_option_combinations_are_one_clear_line(extra, field, tmp_path):
    cfg = tmp_path / "case.toml"
    cfg.write_text('domain = "gear"\n[mesh]\npreset = "coarse"\n' + extra)
    res = CliRunner().invoke(app, ["gear", "simulate", str(cfg), "--out", str(tmp_path / "o")])
    assert res.exit_code == 2, res.output
    assert field in res.output
    assert len([ln for ln in res.output.splitlines() if ln.strip()]) == 1
