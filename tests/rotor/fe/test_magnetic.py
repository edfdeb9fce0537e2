"""Active magnetic bearing: closed-loop K(w), C(w), the ISO 14839-3 sensitivity peak, refusals."""

import numpy as np
import pytest

from rotaflex.core.errors import InputError
from rotaflex.rotor.fe import Disk, Rotor, Shaft
from rotaflex.rotor.fe.bearings.magnetic import Magnetic, MagneticElement, iso14839_zone, sensitivity_peak
from rotaflex.rotor.fe.model import Bearing

# g = k_i g_s g_a = 1e6 N/m per unit controller gain
AMB = dict(k_i=100.0, k_s=1.0e6, sensor_gain=1.0e4, amplifier_gain=1.0, p_gain=2.0)


def test_pd_on_a_mass_is_a_spring_and_a_damper():
    """PD, no filter: K = k_i g_s g_a k_p - k_s and C = k_i g_s g_a k_D at every whirl frequency, and the
    receptance of the element on a mass m is the closed loop's 1 / (m s^2 - k_s + k_i g_s g_a (k_p + k_D s))."""
    el = MagneticElement(Magnetic(**AMB, d_gain=1e-3), "amb")
    w = np.array([0.0, 10.0, 300.0, 3000.0])
    K, C = el.coefficients(np.zeros(4), w)
    np.testing.assert_allclose(K[:, 0, 0], 1e6, rtol=1e-12)
    np.testing.assert_allclose(C[:, 0, 0], 1e3, rtol=1e-12)
    assert np.all(K[:, 0, 1] == 0) and np.all(C[:, 1, 0] == 0)
    # with a low-pass filter at 500 Hz: K(w) + i w C(w) = Z(i w) of the transfer function written out
    el = MagneticElement(Magnetic(**AMB, d_gain=1e-3, i_gain=50.0, lowpass_hz=500.0), "amb")
    w = np.geomspace(1.0, 1e4, 9)
    K, C = el.coefficients(np.zeros(9), w)
    s, tau = 1j * w, 1 / (2 * np.pi * 500.0)
    m = 12.0
    tf = 1 / (m * s**2 - 1e6 + 1e6 * (2.0 + 1e-3 * s + 50.0 / s) / (1 + tau * s))
    np.testing.assert_allclose(1 / (m * s**2 + K[:, 0, 0] + s * C[:, 0, 0]), tf, rtol=1e-10)


@pytest.mark.parametrize("d_gain, peak2, zone", [(1e-3, 40.0, "D"), (3e-3, 4e12 / 9e11, "A")])
def test_sensitivity_peak_by_hand(d_gain, peak2, zone):
    """|S|^2 = (m x + k_s)^2 / ((a - m x)^2 + b x), x = w^2, a = g k_p - k_s, b = (g k_D)^2: its
    maximum is at x* = (2 m a (a + k_s) - b k_s) / (m (2 m (a + k_s) - b)) = 1e5 rad^2/s^2 for
    m = 10 kg, k_s = 1e6 N/m, g k_p = 2e6 N/m, g k_D = 1e3 (3e3) N s/m: |S|^2 = 40 (4.44)."""
    spec = Magnetic(**AMB, d_gain=d_gain, mass=10.0)
    peak, w = sensitivity_peak(spec)
    assert peak == pytest.approx(np.sqrt(peak2), rel=1e-9)
    assert w == pytest.approx(np.sqrt(1e5), rel=1e-4)
    assert iso14839_zone(peak) == zone
    assert MagneticElement(spec, "amb").outputs(0.0)["sensitivity_peak"].attrs["iso14839_zone"] == zone


def amb_rotor(**ctrl) -> Rotor:
    amb = Magnetic(**{**AMB, **ctrl})
    return Rotor(
        # near-rigid (E 1000 x steel, not the rigid penalty, whose round-off would blur the frequencies)
        shaft=(Shaft(outer_diameter=0.1, length=0.4, elements=2, E=2e14, G=8e13),),
        disk=(Disk(node=1, mass=60.0, Id=0.6, Ip=1.0),),
        bearing=(Bearing(node=0, magnetic=amb, name="a"), Bearing(node=2, magnetic=amb, name="b")),
    )


def test_rigid_rotor_on_ambs_first_forward_mode():
    """The first forward mode of a rigid rotor on two AMBs: PD = the exact root of m s^2 + 2 C s + 2 K;
    with a 300 Hz low-pass the mode iterated on its own frequency against the exact root of
    m s^2 (1 + tau s) + 2 g (k_p + k_D s) - 2 k_s (1 + tau s) = 0 (the iteration evaluates the filter
    at s = i w_d instead of the complex pole: the difference is first order in the damping ratio)."""
    from rotaflex.rotor.fe.stability import _System, first_forward

    rotor = amb_rotor(d_gain=1e-3)
    m = rotor.mass
    lam = first_forward(_System(rotor, 0.0), [True, True])
    ref = np.roots([m, 2e3, 2e6])
    # rel 2e-5: the shaft's flexibility (bending stiffness ~ 3e11 N/m against 1e6 N/m bearings)
    assert lam == pytest.approx(ref[np.argmax(ref.imag)], rel=2e-5)
    rotor = amb_rotor(d_gain=1e-3, lowpass_hz=300.0)
    lam = first_forward(_System(rotor, 0.0), [True, True])
    tau = 1 / (2 * np.pi * 300.0)
    ref = np.roots([m * tau, m, 2e3 - 2e6 * tau, 2e6])
    ref = ref[np.argmin(np.abs(ref - lam))]
    zeta = abs(ref.real) / abs(ref)
    assert abs(lam - ref) < 0.5 * zeta * abs(ref)


def test_controller_unstable_on_its_own_is_refused():
    """Static stiffness k_i g_s g_a k_p - k_s <= 0: one line naming bearing.NAME.magnetic.p_gain."""
    data = {
        "shaft": [{"outer_diameter": 0.1, "length": 0.4, "elements": 2}],
        "bearing": {
            "de": {"node": 0, "magnetic": {**AMB, "p_gain": 0.9}},
            "nde": {"node": 2, "magnetic": AMB},
        },
    }
    with pytest.raises(InputError) as err:
        Rotor.from_mapping(data)
    assert err.value.field == "bearing.de.magnetic.p_gain"
    data["bearing"]["de"]["magnetic"] = {**AMB, "mass": 30.0}  # no derivative gain: no damping, poles on the axis
    data["bearing"]["de"]["magnetic"]["lowpass_hz"] = 200.0  # the filter's lag then destabilises
    with pytest.raises(InputError) as err:
        Rotor.from_mapping(data)
    assert err.value.field == "bearing.de.magnetic.d_gain"
