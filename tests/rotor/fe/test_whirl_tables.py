"""Bearing mass coefficients and coefficients tabulated over whirl frequency (frequency dependent):
the modal solve iterates each mode on its own damped frequency."""

import numpy as np
import pytest
import scipy.linalg as sla
from scipy.optimize import brentq

from rotaflex.core.errors import InputError
from rotaflex.rotor.fe.modal import WHIRL_TOL, campbell, modal
from rotaflex.rotor.fe.model import Bearing, Disk, PointMass, Rotor, Shaft

RPM = np.pi / 30
SHAFT = (Shaft(outer_diameter=0.05, length=1.0, elements=6),)
DISK = (Disk(node=2, mass=12.0, Id=0.06, Ip=0.1),)  # off centre: gyroscopic
K0 = 4e6  # N/m


def _rotor(*bearings, **kw):
    return Rotor(shaft=SHAFT, disk=DISK, bearing=bearings, **kw)


def test_mass_coefficients_act_as_a_point_mass():
    """A bearing mass mxx = myy = m to ground is the force -m x'': the same as a point mass m."""
    with_mass = _rotor(Bearing(node=0, kxx=K0, kyy=K0, mxx=2.5, myy=2.5), Bearing(node=6, kxx=K0, kyy=K0))
    with_point = Rotor(
        shaft=SHAFT,
        disk=DISK,
        point_mass=(PointMass(node=0, mass=2.5),),
        bearing=(Bearing(node=0, kxx=K0, kyy=K0), Bearing(node=6, kxx=K0, kyy=K0)),
    )
    np.testing.assert_array_equal(with_mass.M, with_point.M)
    a, b = modal(with_mass, 3000 * RPM, 6), modal(with_point, 3000 * RPM, 6)
    np.testing.assert_allclose(a.eigenvalue, b.eigenvalue, rtol=1e-12)
    # cross-coupled mass coefficients land where the equation of motion puts them
    cross = _rotor(Bearing(node=0, kxx=K0, kyy=K0, mxy=0.3, myx=-0.2), Bearing(node=6, kxx=K0, kyy=K0))
    d = cross.M - _rotor(Bearing(node=0, kxx=K0, kyy=K0), Bearing(node=6, kxx=K0, kyy=K0)).M
    assert d[0, 1] == 0.3 and d[1, 0] == -0.2 and np.count_nonzero(d) == 2


def _whirl_bearing(node, whirl_hz, k):
    return Bearing(node=node, kxx=tuple(k), kyy=tuple(k), whirl_hz=tuple(whirl_hz))


def test_stiffness_linear_in_whirl_frequency_solved_exactly():
    """k(w) = K0 + a w, tabulated at two frequencies (linear interpolation reproduces it exactly).
    Reference: non-rotating and undamped, each natural frequency is a root of
    w - sqrt(eig_j(K_shaft + k(w) at both bearings, M)) = 0, found by Brent's method."""
    a = 2e3  # N s/m per rad/s of whirl
    hz = np.array([0.0, 400.0])
    k = K0 + a * 2 * np.pi * hz
    rotor = _rotor(_whirl_bearing(0, hz, k), _whirl_bearing(6, hz, k))
    assert rotor.frequency_dependent
    got = modal(rotor, 0.0, 4).wd[0][::2]  # each plane gives the same frequency: one of each pair

    def omega(w, j):
        const = _rotor(Bearing(node=0, kxx=K0 + a * w, kyy=K0 + a * w), Bearing(node=6, kxx=K0 + a * w, kyy=K0 + a * w))
        return np.sqrt(sla.eigh(const.KC(0.0)[0][0], const.M, eigvals_only=True)[j])

    ref = [brentq(lambda w, j=j: w - omega(w, j), 1.0, 2 * np.pi * 400, xtol=1e-12) for j in (0, 2)]
    np.testing.assert_allclose(got, ref, rtol=1e-9)
    # the iteration moved the answer: at the synchronous guess (w = 0) the frequencies are lower
    assert got[0] > omega(0.0, 0) * 1.01


def _quadratic(n, m_a):
    """k(w) = K0 + m_a w^2 on n whirl frequencies 0 .. 400 Hz (x and y), at both bearings."""
    hz = np.linspace(0.0, 400.0, n)
    k = K0 + m_a * (2 * np.pi * hz) ** 2
    return _rotor(_whirl_bearing(0, hz, k), _whirl_bearing(6, hz, k))


def _mass_model(m_a):
    return _rotor(
        Bearing(node=0, kxx=K0, kyy=K0, mxx=-m_a, myy=-m_a), Bearing(node=6, kxx=K0, kyy=K0, mxx=-m_a, myy=-m_a)
    )


def test_stiffness_quadratic_in_whirl_equals_negative_added_mass():
    """k(w) = K0 + m_a w^2: for undamped motion x'' = -w^2 x, so the force -(K0 + m_a w^2) x is
    -K0 x + m_a x'', a bearing mass of -m_a. Rotating (gyroscopic: forward and backward modes
    differ). With table knots at the mass model's frequencies, the interpolated k is exact at
    them, so those frequencies are the fixed point the iteration must find (to WHIRL_TOL); with
    knots elsewhere the error falls with the knot spacing h as linear interpolation's h^2."""
    m_a, speed = 0.2, 6000 * RPM
    exact = modal(_mass_model(m_a), speed, 4).wd[0]
    assert exact[1] > exact[0] * 1.001  # forward and backward split by the gyroscopic moments
    w = np.concatenate([[0.0], exact, [2 * np.pi * 400]])
    k = K0 + m_a * w**2
    rotor = _rotor(_whirl_bearing(0, w / (2 * np.pi), k), _whirl_bearing(6, w / (2 * np.pi), k))
    np.testing.assert_allclose(modal(rotor, speed, 4).wd[0], exact, rtol=1e-9)
    err = [np.max(np.abs(modal(_quadratic(n, m_a), speed, 4).wd[0] - exact) / exact) for n in (11, 41)]
    assert err[1] < 1e-4 and 8 < err[0] / err[1] < 32  # h / 4: 16 for order 2 (position in the interval varies)


def test_campbell_iterates_each_mode_and_reports_convergence_tolerance():
    """The Campbell diagram of the frequency-dependent rotor equals, speed by speed, its modes
    (each mode on its own frequency), and those agree with the mass model to the table's error."""
    m_a = 0.2
    rotor = _quadratic(401, m_a)
    mass = _mass_model(m_a)
    speeds = np.linspace(0, 8000, 5) * RPM
    c = campbell(rotor, speeds, n_modes=4)
    ref = campbell(mass, speeds, n_modes=4)
    # x/y pairs are degenerate at speed 0, so the two diagrams may number a pair differently
    np.testing.assert_allclose(np.sort(c.modes.wd[:, :4]), np.sort(ref.modes.wd[:, :4]), rtol=1e-6)
    assert 1e-12 <= WHIRL_TOL <= 1e-8


def test_whirl_table_out_of_range_names_the_table():
    hz = np.array([10.0, 20.0])
    rotor = _rotor(_whirl_bearing(0, hz, K0 + 0 * hz), Bearing(node=6, kxx=K0, kyy=K0))
    with pytest.raises(InputError) as e:  # the modes lie far above 20 Hz
        modal(rotor, 0.0, 2)
    assert e.value.field == "bearing[0].whirl_hz" and e.value.value > 20 and "10..20 Hz" in str(e.value)


def test_speed_and_whirl_table_bilinear_is_exact():
    """Rows over speed_rpm of values over whirl_hz: the tensor-product linear interpolation
    reproduces a bilinear k = a + b Omega + c w + d Omega w exactly."""
    rpm = np.array([0.0, 3000.0, 9000.0])
    hz = np.array([0.0, 50.0, 300.0])
    f = lambda s, w: 1e6 + 300.0 * s + 2e3 * w + 0.5 * s * w  # noqa: E731  (s, w in rad/s)
    rows = [[f(s * RPM, 2 * np.pi * h) for h in hz] for s in rpm]
    data = {
        "shaft": [{"outer_diameter": 0.05, "length": 1.0, "elements": 6}],
        "bearing": {
            "left": {"node": 0, "kxx": rows, "kyy": rows, "speed_rpm": list(rpm), "whirl_hz": list(hz)},
            "right": {"node": 6, "kxx": K0, "kyy": K0},
        },
    }
    rotor = Rotor.from_mapping(data)
    rng = np.random.default_rng(3)
    s, w = rng.uniform(0, 9000 * RPM, 20), rng.uniform(0, 300 * 2 * np.pi, 20)
    K = rotor.KC(s, w)[0] - rotor.K_shaft
    np.testing.assert_allclose(K[:, 0, 0], f(s, w), rtol=1e-13)
