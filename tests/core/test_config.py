from dataclasses import dataclass
from typing import Literal

import pytest

from rotaflex.core.config import from_mapping, param, set_dotted
from rotaflex.core.errors import InputError


@dataclass(frozen=True)
class Inner:
    mass: float = param(1.0, unit="kg", gt=0)
    n: int = param(3, ge=1)


@dataclass(frozen=True)
class Outer:
    name: str = param()
    inner: Inner = param(Inner())
    method: Literal["RK45", "DOP853"] = "DOP853"
    axis: tuple[float, float, float] = (0.0, 0.0, 1.0)


def test_valid_config_is_converted():
    cfg = from_mapping(Outer, {"name": "x", "inner": {"mass": 2}, "axis": [1, 0, 0]})
    assert cfg.inner.mass == 2.0 and isinstance(cfg.inner.mass, float)
    assert cfg.axis == (1.0, 0.0, 0.0)
    assert cfg.method == "DOP853"


@pytest.mark.parametrize(
    "data, field, fragment",
    [
        ({"name": "x", "inner": {"mass": -1}}, "inner.mass", "> 0 [kg]"),
        ({"name": "x", "inner": {"mass": "a"}}, "inner.mass", "a number"),
        ({"name": "x", "inner": {"n": 1.5}}, "inner.n", "an integer"),
        ({"name": "x", "method": "Euler"}, "method", "'RK45', 'DOP853'"),
        ({"name": "x", "axis": [1, 0]}, "axis", "3 entries"),
        ({"name": "x", "colour": 1}, "colour", "no such key"),
        ({}, "name", "required"),
        ({"name": "x", "inner": {"mass": float("nan")}}, "inner.mass", "finite"),
    ],
)
def test_bad_values_name_field_value_and_range(data, field, fragment):
    with pytest.raises(InputError) as info:
        from_mapping(Outer, data)
    assert info.value.field == field
    assert fragment in str(info.value)
    assert "\n" not in str(info.value)


def test_set_dotted_copies():
    base = {"a": {"b": 1}}
    new = set_dotted(base, "a.b", 2)
    assert new["a"]["b"] == 2 and base["a"]["b"] == 1


def test_unknown_key_suggests_the_closest_key():
    with pytest.raises(InputError) as info:
        from_mapping(Outer, {"name": "x", "inner": {"mas": 2.0}})
    assert info.value.field == "inner.mas"
    assert "did you mean 'mass'?" in str(info.value) and "allowed keys: mass, n" in str(info.value)
    with pytest.raises(InputError) as info:  # nothing close: no guess, only the list
        from_mapping(Outer, {"name": "x", "zzzz": 1})
    assert "did you mean" not in str(info.value) and "allowed keys: name, inner, method, axis" in str(info.value)


def test_unknown_key_in_an_array_of_tables_is_named_with_its_index():
    from rotaflex.rotor.fe.model import Rotor

    data = {"shaft": [{"outer_diameter": 0.05, "length": 1.0}, {"outer_diamter": 0.05, "length": 1.0}]}
    with pytest.raises(InputError) as info:
        Rotor.from_mapping(data)
    assert "shaft[1].outer_diamter" in str(info.value) and "did you mean 'outer_diameter'?" in str(info.value)
