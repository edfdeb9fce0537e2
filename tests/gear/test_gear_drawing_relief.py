"""Tip/root relief start given by diameter, roll angle or fraction of the active profile.

Hand values (ISO 21771 involute): base radius r_b = m z cos(alpha) / 2, roll angle xi at radius r:
r = r_b sqrt(1 + xi^2); start of active profile of a gear in a pair at centre distance a':
u_SAP = a' sin(alpha') - sqrt(r_a,mate^2 - r_b,mate^2), r_SAP = sqrt(r_b^2 + u_SAP^2); a fraction f
of the active profile's roll length: u = u_SAP + f (sqrt(r_a^2 - r_b^2) - u_SAP).
"""

import math

import pytest

from rotaflex.core.errors import InputError
from rotaflex.gear.pair.drawing import pair_from_mapping

# the paper's gear (identical pinion and wheel), no-backlash centre distance a' = m z
M, Z, RA, RF = 3.175e-3, 28, 0.047625, 0.04048
RB = M * Z / 2 * math.cos(math.radians(20.0))
A = M * Z
U_TIP = math.sqrt(RA**2 - RB**2)
U_SAP = A * math.sin(math.radians(20.0)) - U_TIP


def pair(**tip_relief):
    gear = {"teeth": Z, "module": M, "face_width": 6.35e-3, "tip_radius": RA, "root_radius": RF}
    return pair_from_mapping({"pinion": {**gear, "tip_relief": {"amount": 10e-6, **tip_relief}}, "wheel": gear})


def start_radius(p) -> float:
    return p.gears[0].tip_relief.start_radius


def test_roll_angle_gives_the_involute_radius():
    xi = 0.5  # [rad] = 28.6479 deg
    assert start_radius(pair(start_roll_deg=math.degrees(xi))) == pytest.approx(RB * math.sqrt(1 + xi**2), rel=1e-14)


def test_fraction_of_the_active_profile():
    assert pair(start_fraction=0.5).start_of_active_profile()[0] == pytest.approx(math.hypot(RB, U_SAP), rel=1e-12)
    for f in (0.0, 0.3, 0.75):
        r = math.hypot(RB, U_SAP + f * (U_TIP - U_SAP))
        assert start_radius(pair(start_fraction=f)) == pytest.approx(r, rel=1e-12), f


def test_three_forms_of_one_start_give_one_geometry():
    f = 0.4
    u = U_SAP + f * (U_TIP - U_SAP)
    by_fraction = pair(start_fraction=f).gears[0]
    by_diameter = pair(start_diameter=2 * math.hypot(RB, u)).gears[0]
    by_roll = pair(start_roll_deg=math.degrees(u / RB)).gears[0]
    r = by_fraction.tip_relief.start_radius
    assert by_diameter.tip_relief.start_radius == pytest.approx(r, rel=1e-13)
    assert by_roll.tip_relief.start_radius == pytest.approx(r, rel=1e-13)


@pytest.mark.parametrize(
    ("keys", "field"),
    [
        ({"start_diameter": 0.09, "start_fraction": 0.5}, "pinion.tip_relief.start_fraction"),
        ({"start_roll_deg": 25.0, "start_diameter": 0.09}, "pinion.tip_relief.start_roll_deg"),
        ({}, "pinion.tip_relief.start_diameter"),
        ({"start_fraction": 1.0}, "pinion.tip_relief.start_fraction"),
        ({"start_fraction": -0.1}, "pinion.tip_relief.start_fraction"),
        ({"start_roll_deg": 5.0}, "pinion.tip_relief.start_roll_deg"),  # below the form radius
        ({"start_diameter": 2 * RA}, "pinion.tip_relief.start_diameter"),  # at the tip
    ],
)
def test_two_starts_none_or_out_of_range_are_refused(keys, field):
    with pytest.raises(InputError) as exc:
        pair(**keys)
    assert exc.value.field == field
    if len(keys) != 1:
        assert "exactly one of start_diameter, start_roll_deg, start_fraction" in str(exc.value)


def test_fraction_needs_the_pair():
    from rotaflex.core.config import from_mapping
    from rotaflex.gear.pair.drawing import GearSpec

    spec = from_mapping(
        GearSpec,
        {"teeth": Z, "module": M, "face_width": 6.35e-3, "tip_relief": {"amount": 1e-5, "start_fraction": 0.5}},
    )
    with pytest.raises(InputError) as exc:
        spec.geometry("pinion")
    assert exc.value.field == "pinion.tip_relief.start_fraction"
