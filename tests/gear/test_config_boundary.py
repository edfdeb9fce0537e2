"""Refusals at the config boundary name the key the user wrote, alike in every gear verb."""

import copy
from pathlib import Path

import pytest

from rotaflex.core.config import load_toml
from rotaflex.core.errors import InputError
from rotaflex.gear.cases import simulate, static, steady

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "gear" / "one_pair_all_verbs.toml"


def _static_check(config):
    static.load_config(config).pair  # noqa: B018  (checks the pair)


def _simulate_check(config):
    simulate.load_config(config).pair  # noqa: B018


VERBS = {"static": _static_check, "steady": steady.validate_config, "simulate": _simulate_check}


@pytest.fixture(scope="module")
def base():
    return {k: v for k, v in load_toml(EXAMPLE).items() if k != "domain"}


@pytest.mark.parametrize("verb", VERBS)
@pytest.mark.parametrize(
    ("change", "field"),
    [
        (lambda c: c["pinion"].update(teeth=4), "pinion.teeth"),
        (lambda c: c["wheel"].update(teeth=0), "wheel.teeth"),
        (lambda c: c.update(backlash=0.01), "backlash"),  # 10 mm: the centre distance follows from it
        (lambda c: c["pinion"].update(material={"name": "steel", "youngs_modulus": 1.0}), "pinion.material"),
    ],
)
def test_every_verb_refuses_alike_naming_the_key_written(base, verb, change, field):
    cfg = copy.deepcopy(base)
    change(cfg)
    with pytest.raises(InputError) as exc:
        VERBS[verb](cfg)
    assert exc.value.field.startswith(field)


def test_steady_refuses_a_zero_train_inertia(base):
    cfg = copy.deepcopy(base)
    cfg["train"] = {"inertia": [0.0, 1e-4]}
    with pytest.raises(InputError, match=r"train\.inertia"):
        steady.validate_config(cfg)


def test_old_mesh_table_of_gear_steady_still_reads_as_mesh_stiffness(base):
    old = copy.deepcopy(base)
    old["mesh"] = {"damping_ratio": 0.05, "preset": "coarse"}
    del old["mesh_stiffness"]
    new = copy.deepcopy(base)
    new["mesh_stiffness"] = {"damping_ratio": 0.05}
    assert steady._checked(old) == steady._checked(new)
    old["mesh"]["source"] = "contact_pattern"  # refused with [pinion]/[wheel]: named as written
    with pytest.raises(InputError, match=r"^mesh\.source"):
        steady.validate_config(old)


def test_torque_on_converts_once_with_the_tooth_ratio(base):
    on_wheel = copy.deepcopy(base)
    on_wheel["operation"].update(torque=160.0, torque_on="wheel")
    assert steady._checked(on_wheel).operation == steady._checked(base).operation  # 80 N m on the pinion x 40/20
