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


@pytest.mark.parametrize(("domain", "verb"), [("gear", "steady"), ("gear", "static"), ("rotor", "modal")])
def test_verb_templates_name_their_own_keys_and_are_accepted_by_the_verb(domain, verb):
    from rotaflex.core.domains import validate_command

    text = domain_template(domain, verb)
    data = tomllib.loads(text)
    assert data.pop("domain") == domain
    if verb == "steady":  # keys only the steady-state verb has, with their meaning
        assert data.pop("verb") == "steady"
        for key in ("[steady]", "[iso]", "[train]", "[model]", "tol = ", "tip_relief"):
            assert key in text, key
        assert "# [m] number (optional), >= 0 and <= 0.001. C_a of B_k" in text
    # required keys are written commented out: a template without them is refused by name
    try:
        validate_command(domain, verb, data)
    except InputError as exc:
        assert "<required>" in text and exc.field in text
    assert "Config(" not in text.splitlines()[1], "the title is a sentence, not a dataclass signature"


def test_config_reference_has_a_section_per_verb_schema():
    text = config_reference()
    for heading in ("`rotaflex gear steady`", "`rotaflex gear static`", "`rotaflex rotor modal|campbell"):
        assert f"### {heading}" in text
    assert "TorsionalCaseConfig(" not in text and "FloatingCase(" not in text
    assert "| `iso.tip_relief` |" in text and "| `steady.eval_cycles` |" in text


def test_booleans_are_shown_as_typed_in_toml():
    assert str(InputError("solver.geometric_stiffness", True, "false")).startswith(
        "solver.geometric_stiffness = true is invalid"
    )


def test_unknown_template_verb_is_named_as_the_option():
    with pytest.raises(InputError) as exc:
        domain_template("gear", "stedy")
    assert exc.value.field == "--verb" and "'steady'" in exc.value.allowed
