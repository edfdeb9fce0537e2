"""Inputs typed in mm and values that overflow the assembly name their own field (not `free`)."""

import pytest

from rotaflex.core.errors import InputError
from rotaflex.rotor.fe.model import Bearing, Disk, Rotor, Shaft


def _rotor(shaft=None, disk=None, bearing=None):
    return Rotor(
        shaft=(shaft or Shaft(outer_diameter=0.06, length=1.2, elements=4),),
        disk=(disk or Disk(node=2, width=0.05, outer_diameter=0.3, inner_diameter=0.06),),
        bearing=(bearing or Bearing(node=0, kxx=1e7, kyy=1e7), Bearing(node=4, kxx=1e7, kyy=1e7)),
    )


@pytest.mark.parametrize(
    "kw, field, words",
    [
        ({"shaft": Shaft(outer_diameter=60.0, length=1.2, elements=4)}, "shaft[0].outer_diameter", "millimetres"),
        ({"shaft": Shaft(outer_diameter=0.06, length=1200.0, elements=4)}, "shaft[0].length", "millimetres"),
        ({"disk": Disk(node=2, width=0.05, outer_diameter=300.0, inner_diameter=0.06)}, "disk[0].outer_diameter", "mm"),
        ({"shaft": Shaft(outer_diameter=0.06, length=1.2, elements=4, E=1e300)}, "shaft[0].E", "1e+20"),
        ({"bearing": Bearing(node=0, kxx=1e7, kyy=1e7, kxy=1e300)}, "bearing[0].kxy", "1e+15"),
        ({"bearing": Bearing(node=0, kxx=1e7, kyy=1e7, cxx=float("inf"))}, "bearing[0].cxx", "finite"),
    ],
)
def test_field_is_named(kw, field, words):
    with pytest.raises(InputError) as e:
        _rotor(**kw)
    assert e.value.field == field and words in str(e.value)


def test_mm_message_suggests_the_metre_value():
    with pytest.raises(InputError) as e:
        _rotor(shaft=Shaft(outer_diameter=60.0, length=1.2, elements=4))
    assert "write 0.06 for 60 mm" in str(e.value)


def test_missing_support_is_still_free():
    with pytest.raises(InputError) as e:
        Rotor(shaft=(Shaft(outer_diameter=0.06, length=1.2, elements=4),), bearing=(Bearing(node=0, kxx=1e7, kyy=1e7),))
    assert e.value.field == "free"
    with pytest.raises(InputError) as e:  # y unrestrained
        Rotor(
            shaft=(Shaft(outer_diameter=0.06, length=1.2, elements=4),),
            bearing=(Bearing(node=0, kxx=1e7), Bearing(node=4, kxx=1e7)),
        )
    assert e.value.field == "free"
