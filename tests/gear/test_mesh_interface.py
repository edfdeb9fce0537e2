"""The public mesh interface: gear_mesh() from a drawing pair, each source, geometry, errors."""

import math

import numpy as np
import pytest

from rotaflex.core.errors import InputError
from rotaflex.gear import GearMesh, gear_mesh, pair_from_mapping

PAIR = {
    "pinion": {"teeth": 20, "module": 3e-3, "face_width": 0.02},
    "wheel": {"teeth": 40, "module": 3e-3, "face_width": 0.02},
}


@pytest.fixture(scope="module")
def pair():
    return pair_from_mapping(PAIR)


def test_geometry_of_the_mesh_is_the_drawing(pair):
    m = gear_mesh(pair, 50.0, source="iso6336")
    assert isinstance(m, GearMesh)
    assert m.teeth == (20, 40) and m.ratio == 2.0
    # standard pair without shift or backlash: working = reference pressure angle, a = m (z1 + z2) / 2
    assert math.isclose(m.pressure_angle, math.radians(20.0), rel_tol=1e-12)
    assert math.isclose(m.center_distance, 3e-3 * 60 / 2, rel_tol=1e-12)
    assert math.isclose(m.base_radius[0], 3e-3 * 20 / 2 * math.cos(math.radians(20)), rel_tol=1e-12)
    assert m.base_radius[1] / m.base_radius[0] == pytest.approx(2.0, rel=1e-12)
    assert math.isclose(m.mesh_frequency(2 * math.pi * 50), 20 * 50, rel_tol=1e-12)


def test_iso_source_is_c_gamma_times_face_width(pair):
    from rotaflex.gear.static.tooth_analysis import iso6336_stiffness

    m = gear_mesh(pair, 50.0, source="iso6336")
    g1, g2 = pair.gears
    load = 50.0 / (3e-3 * 10) / 20.0  # T / r_ref / b[mm], N/mm
    expect = iso6336_stiffness(g1, g2, load, eps_alpha=pair.contact_ratio)["c_gamma"] * 20.0 * 1e6
    assert m.mean_stiffness == pytest.approx(expect, rel=1e-12)
    assert np.all(m.table.unloaded_te == 0)


def test_harmonic_and_contact_pattern_sources(pair):
    h = gear_mesh(pair, 50.0, source="harmonic", k_mean=3e8, k_harmonics=(5e7,), te_harmonics=(2e-6,), table_points=64)
    assert h.mean_stiffness == pytest.approx(3e8, rel=1e-12)
    assert np.ptp(h.table.stiffness) == pytest.approx(1e8, rel=1e-3)
    c = gear_mesh(pair, 50.0, source="contact_pattern", k_pair=2e8, table_points=1000)
    # single/double contact: mean = k_pair * eps (share of double contact eps - 1)
    assert c.mean_stiffness == pytest.approx(2e8 * pair.contact_ratio, rel=2e-3)


def test_loaded_te_source_is_between_one_and_two_pairs(pair):
    m = gear_mesh(pair, 50.0, source="loaded_te", mesh_preset="coarse", n_radii=5, table_points=100)
    k = m.table.stiffness
    # two pairs carry for (eps - 1) of the cycle: the stiffest phase is well above the softest
    assert k.max() / k.min() > 1.3
    assert 1e8 < m.mean_stiffness < 1e9  # steel spur teeth of 20 mm face: ISO's c_gamma b ~ 4e8 N/m


@pytest.mark.parametrize(
    ("kw", "field"),
    [
        ({"source": "magic"}, "mesh.source"),
        ({"source": "harmonic"}, "mesh.k_mean"),
        ({"source": "contact_pattern", "k_pair": -1.0}, "mesh.k_pair"),
    ],
)
def test_bad_input_names_the_field(pair, kw, field):
    with pytest.raises(InputError, match=field.replace(".", r"\.")):
        gear_mesh(pair, 50.0, **kw)


def test_bad_torque(pair):
    with pytest.raises(InputError, match="torque"):
        gear_mesh(pair, 0.0, source="iso6336")
