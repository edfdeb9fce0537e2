"""Generated templates and config reference: they load, round-trip, and the committed file is current."""

import tomllib
from pathlib import Path

import pytest

from rotaflex.cli import config_reference, domain_template
from rotaflex.core.config import from_mapping
from rotaflex.core.errors import InputError
from rotaflex.core.schema import default_of

ROOT = Path(__file__).resolve().parents[2]


def test_rotor_template_loads_to_the_default_model():
    from rotaflex.rotor.case import model_from_config, validate_config
    from rotaflex.rotor.model import RotorModel

    data = tomllib.loads(domain_template("rotor"))
    assert data.pop("domain") == "rotor"
    validate_config(data)
    assert model_from_config(data) == RotorModel()  # every default written as the dataclass has it


def test_template_lists_every_key_with_its_unit():
    text = domain_template("rotor")
    for key, unit in [("mass", "[kg]"), ("tilt_stiffness", "[N m/rad]"), ("t_end", "[s]"), ("max_steps", "")]:
        i = text.index(f"\n{key} = ")
        comment = text[:i].rsplit("\n", 1)[-1]
        assert comment.startswith("#") and unit in comment


def test_default_of():
    from rotaflex.rotor.model import RotorModel

    assert default_of(RotorModel, "solver.t_end") == 10.0
    assert default_of(RotorModel, "motion.initial_tilt") == [0.0, 0.0]
    with pytest.raises(InputError, match="nosuch"):
        default_of(RotorModel, "nosuch.key")


def test_committed_config_reference_is_up_to_date():
    committed = (ROOT / "docs" / "config-reference.md").read_text(encoding="utf-8")
    assert committed == config_reference(), "run: rotaflex docs config-reference --out docs/config-reference.md"


def test_from_mapping_refuses_huge_integers_without_overflow():
    from rotaflex.rotor.model import Disk

    with pytest.raises(InputError, match=r"disk.mass = 100000\.\.\.000 \(401 digits\)"):
        from_mapping(Disk, {"mass": 10**400}, "disk")
