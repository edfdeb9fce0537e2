"""`rotaflex system template` lists every key of [[rotor]] and [[gear_mesh]] (arrays of tables and
their sub-tables), checked against the dataclasses the reader parses and the example gearbox."""

from __future__ import annotations

import dataclasses
import re
import subprocess
import sys
import typing
from pathlib import Path

import pytest

from rotaflex.core.config import load_toml
from rotaflex.gear import PairSpec
from rotaflex.rotor.fe.model import Bearing, Disk, PointMass, Shaft
from rotaflex.system.model import PAIR_KEYS, MeshSpec, RotorSpec

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def sections() -> dict[str, set[str]]:
    """Keys per section of the template printed by the CLI ("" = top level)."""
    env = {"PYTHONPATH": str(ROOT / "src")}
    out = subprocess.run(
        [sys.executable, "-m", "rotaflex", "system", "template"], capture_output=True, text=True, env=env, check=True
    ).stdout
    sec, keys = "", {"": set()}
    for line in out.splitlines():
        head = re.match(r"^#?\s*\[\[?([\w.<>]+)\]\]?\s*$", line)
        if head:
            sec = head.group(1)
            keys.setdefault(sec, set())
            continue
        key = re.match(r"^#?\s*(\w+) = ", line)
        if key:
            keys[sec].add(key.group(1))
    return keys


def _listed(sections: dict[str, set[str]], sec: str) -> set[str]:
    """Keys of a section plus the names of its sub-tables (e.g. blank, tip_relief)."""
    return sections[sec] | {k.split(".")[-1] for k in sections if k.startswith(f"{sec}.")}


def _names(cls) -> set[str]:
    return {f.name for f in dataclasses.fields(cls)}


def test_rotor_keys_and_sub_tables(sections):
    tables = {"shaft": Shaft, "disk": Disk, "point_mass": PointMass, "bearing": Bearing}
    assert _names(RotorSpec) - set(tables) - {"material"} <= sections["rotor"]
    for name, cls in tables.items():
        assert _names(cls) <= _listed(sections, f"rotor.{name}"), name  # bearing: + fluid_film
    assert "rotor.bearing.fluid_film" in sections
    assert "rotor.material.<name>" in sections


def test_gear_mesh_keys_with_the_pair_of_gear_static(sections):
    gear_fields = typing.get_type_hints(PairSpec)["pinion"]
    assert _names(MeshSpec) - {"pinion", "wheel"} <= _listed(sections, "gear_mesh")  # keys and sub-tables (face)
    assert set(PAIR_KEYS) - {"pinion", "wheel"} <= sections["gear_mesh"]
    for gear in ("pinion", "wheel"):
        assert _names(gear_fields) <= _listed(sections, f"gear_mesh.{gear}"), gear


def test_every_key_of_the_example_gearbox_is_in_the_template(sections):
    cfg = load_toml(ROOT / "examples" / "system" / "gearbox.toml")
    for r in cfg["rotor"]:
        assert set(r) - {"shaft", "disk", "bearing", "point_mass"} <= sections["rotor"]
        for sub in ("shaft", "disk", "bearing"):
            for t in r.get(sub, []):
                assert set(t) <= sections[f"rotor.{sub}"]
    for m in cfg["gear_mesh"]:
        assert set(m) - {"pinion", "wheel"} <= sections["gear_mesh"]
        for gear in ("pinion", "wheel"):
            assert set(m[gear]) <= _listed(sections, f"gear_mesh.{gear}")
