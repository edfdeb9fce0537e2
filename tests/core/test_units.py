"""core.units: the conversions at the config boundary, against their definitions."""

import math

import numpy as np
import pytest

from rotaflex.core.units import deg_to_rad, rad_s_to_rpm, rad_to_deg, rpm_to_rad_s


def test_definitions_and_round_trips():
    assert rpm_to_rad_s(60.0) == pytest.approx(2 * math.pi, rel=1e-15)  # one turn per second
    assert deg_to_rad(180.0) == math.pi
    x = np.array([0.0, 1.0, 4000.0, 20200.0])
    assert np.allclose(rad_s_to_rpm(rpm_to_rad_s(x)), x, rtol=1e-15, atol=0)
    assert np.allclose(rad_to_deg(deg_to_rad(x)), x, rtol=1e-15, atol=0)
    assert isinstance(rpm_to_rad_s(3000), float) and isinstance(rpm_to_rad_s([1.0, 2.0]), np.ndarray)


def test_bit_identical_to_the_expressions_it_replaced():
    rng = np.random.default_rng(0)
    for v in rng.uniform(0.0, 1e5, 2000):
        assert rpm_to_rad_s(v) == v * 2 * math.pi / 60 == v * math.pi / 30.0
        assert deg_to_rad(v) == math.radians(v)
