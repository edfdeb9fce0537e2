"""Rotation module vs scipy, finite differences of R(t), and the quaternion identities."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from rotaflex.core.errors import InputError, SingularityError
from rotaflex.rotation import (
    SEQUENCES,
    body_rate_matrix,
    euler_from_matrix,
    euler_rates_from_body,
    euler_rates_from_inertial,
    inertial_rate_matrix,
    integrate_attitude,
    kinetic_energy_body,
    kinetic_energy_inertial,
    quaternion_from_euler,
    quaternion_from_matrix,
    quaternion_matrices,
    quaternion_rates_from_body,
    quaternion_rates_from_inertial,
    quaternion_to_matrix,
    rates_from_quaternion,
    rotation_matrix,
)
from rotaflex.rotation.quaternion import skew

angle = st.floats(-3.0, 3.0)


def scipy_matrix(seq, angles):
    return Rotation.from_euler("".join("XYZ"[int(c) - 1] for c in seq), angles).as_matrix()


@pytest.mark.parametrize("seq", SEQUENCES)
@settings(max_examples=30, deadline=None)
@given(a=angle, b=angle, c=angle)
def test_rotation_matrix_matches_scipy(seq, a, b, c):
    np.testing.assert_allclose(rotation_matrix(seq, [a, b, c]), scipy_matrix(seq, [a, b, c]), atol=1e-13)


def trajectory(t):
    """A smooth angle history far from gimbal lock for every sequence (middle angle ~ 0.7-1.0)."""
    return np.stack([0.4 + np.sin(1.3 * t), 0.8 + 0.2 * np.cos(0.7 * t), -0.5 + 2.0 * t], axis=-1)


def trajectory_rates(t):
    return np.stack([1.3 * np.cos(1.3 * t), -0.14 * np.sin(0.7 * t), 2.0 + 0 * t], axis=-1)


@pytest.mark.parametrize("seq", SEQUENCES)
def test_angular_velocity_maps_match_finite_difference_of_R(seq):
    t = np.linspace(0.0, 2.0, 7)
    h = 1e-6
    R = rotation_matrix(seq, trajectory(t))
    R_dot = (rotation_matrix(seq, trajectory(t + h)) - rotation_matrix(seq, trajectory(t - h))) / (2 * h)
    W_body = np.swapaxes(R, -1, -2) @ R_dot  # skew(omega_body)
    W_inertial = R_dot @ np.swapaxes(R, -1, -2)
    wb = body_rate_matrix(seq, trajectory(t)) @ trajectory_rates(t)[..., None]
    wi = inertial_rate_matrix(seq, trajectory(t)) @ trajectory_rates(t)[..., None]
    np.testing.assert_allclose(skew(wb[..., 0]), W_body, atol=1e-8)
    np.testing.assert_allclose(skew(wi[..., 0]), W_inertial, atol=1e-8)
    np.testing.assert_allclose(wi, R @ wb, atol=1e-12)
    # inverse maps
    rates = euler_rates_from_body(seq, trajectory(t), wb[..., 0])
    np.testing.assert_allclose(rates, trajectory_rates(t), atol=1e-12)
    rates = euler_rates_from_inertial(seq, trajectory(t), wi[..., 0])
    np.testing.assert_allclose(rates, trajectory_rates(t), atol=1e-12)


def test_paper_convention_reproduces_printed_123_maps():
    phi, th, ps = 0.3, 0.2, -0.4
    c, s = np.cos, np.sin
    eq6 = [[c(th) * c(ps), s(ps), 0], [-s(ps) * c(th), c(ps), 0], [-s(th), 0, 1]]
    eq10 = [[1, 0, -s(th)], [0, c(phi), -c(th) * s(phi)], [0, s(phi), c(phi) * c(th)]]
    np.testing.assert_allclose(body_rate_matrix("123", [phi, th, ps], "paper"), eq6, atol=1e-15)
    np.testing.assert_allclose(inertial_rate_matrix("123", [phi, th, ps], "paper"), eq10, atol=1e-15)
    # the digest's right-handed maps
    rh6 = [[c(th) * c(ps), s(ps), 0], [-s(ps) * c(th), c(ps), 0], [s(th), 0, 1]]
    np.testing.assert_allclose(body_rate_matrix("123", [phi, th, ps]), rh6, atol=1e-15)


def test_313_maps_match_paper_eq11():
    ps, ph, th = 0.3, 0.5, -0.2  # order of the 3-1-3 sequence: psi, phi, theta
    c, s = np.cos, np.sin
    eq11a = [[s(ph) * s(th), c(th), 0], [s(ph) * c(th), -s(th), 0], [c(ph), 0, 1]]
    eq11b = [[0, c(ps), s(ps) * s(ph)], [0, s(ps), -c(ps) * s(ph)], [1, 0, c(ph)]]
    np.testing.assert_allclose(body_rate_matrix("313", [ps, ph, th]), eq11a, atol=1e-15)
    np.testing.assert_allclose(inertial_rate_matrix("313", [ps, ph, th]), eq11b, atol=1e-15)


@pytest.mark.parametrize("seq, middle", [("123", np.pi / 2), ("313", 0.0), ("321", -np.pi / 2)])
def test_gimbal_lock_is_reported(seq, middle):
    with pytest.raises(SingularityError, match="singular"):
        euler_rates_from_body(seq, [0.2, middle, 0.1], [0.0, 0.0, 1.0])
    # just away from it the inverse still works and is accurate
    ang = [0.2, middle + 1e-4, 0.1]
    rates = np.array([0.1, 0.2, 0.3])
    w = body_rate_matrix(seq, ang) @ rates
    np.testing.assert_allclose(euler_rates_from_body(seq, ang, w), rates, rtol=1e-8)


@pytest.mark.parametrize("seq", SEQUENCES)
def test_euler_quaternion_matrix_round_trips(seq):
    rng = np.random.default_rng(int(seq))
    ang = rng.uniform(-3, 3, size=(20, 3))
    ang[:3, 1] = [0.0, 1e-7, np.pi / 2] if seq[0] == seq[2] else [np.pi / 2, np.pi / 2 - 1e-7, 0.0]
    R = rotation_matrix(seq, ang)
    back = rotation_matrix(seq, euler_from_matrix(seq, R))
    np.testing.assert_allclose(back[3:], R[3:], atol=1e-12)
    # at/within 1e-7 of gimbal lock scipy's as_euler splits the angles with ~1e-7 error
    np.testing.assert_allclose(back[:3], R[:3], atol=5e-7)
    e = quaternion_from_euler(seq, ang)
    np.testing.assert_allclose(np.linalg.norm(e, axis=-1), 1.0, atol=1e-14)
    np.testing.assert_allclose(quaternion_to_matrix(e), R, atol=1e-13)
    np.testing.assert_allclose(quaternion_from_matrix(R), e, atol=1e-12)


def test_quaternion_matrix_identities_eq17_to_20():
    rng = np.random.default_rng(1)
    e = rng.normal(size=(10, 4))
    e /= np.linalg.norm(e, axis=-1, keepdims=True)
    A, B, C = quaternion_matrices(e)
    eye = np.broadcast_to(np.eye(4), A.shape)
    for M in (A, B, C):  # eq. 18
        np.testing.assert_allclose(M @ np.swapaxes(M, -1, -2), eye, atol=1e-14)
    # a random body rate, its e_dot, and the inverse maps (eq. 15, 16, 20)
    wb = rng.normal(size=(10, 3))
    e_dot = quaternion_rates_from_body(e, wb)
    np.testing.assert_allclose(np.sum(e * e_dot, axis=-1), 0.0, atol=1e-14)  # eq. 19
    wb2, wi = rates_from_quaternion(e, e_dot)
    np.testing.assert_allclose(wb2, wb, atol=1e-14)
    np.testing.assert_allclose(wi, (quaternion_to_matrix(e) @ wb[..., None])[..., 0], atol=1e-14)
    np.testing.assert_allclose(quaternion_rates_from_inertial(e, wi), e_dot, atol=1e-14)
    # the paper's C relations hold with the opposite sign of the vector part
    wc = 2 * np.swapaxes(C, -1, -2) @ e_dot[..., None]
    np.testing.assert_allclose(wc[..., 1:, 0], -wb, atol=1e-14)
    # finite difference of R(e(t)) along e_dot agrees with the body rate
    h = 1e-6
    R_dot = (quaternion_to_matrix(e + h * e_dot) - quaternion_to_matrix(e - h * e_dot)) / (2 * h)
    np.testing.assert_allclose(np.swapaxes(quaternion_to_matrix(e), -1, -2) @ R_dot, skew(wb), atol=1e-7)


def test_integrate_attitude_unit_norm_and_fourth_order():
    # rates linear in time about a fixed tilted axis + a constant part: compare to a fine solution
    def omega(t):
        return np.stack([1.0 + 0.5 * t, 0.3 * np.ones_like(t), -0.2 + 0.1 * t], axis=-1)

    errors = []
    t_ref = np.linspace(0, 2.0, 2**14 + 1)
    e_ref = integrate_attitude(t_ref, omega(t_ref))[-1]
    for n in (16, 32, 64):
        t = np.linspace(0, 2.0, n + 1)
        e = integrate_attitude(t, omega(t))
        assert np.max(np.abs(np.linalg.norm(e, axis=-1) - 1)) < 1e-14
        errors.append(np.linalg.norm(e[-1] - e_ref))
    order = np.log2(np.array(errors[:-1]) / errors[1:])
    assert np.all(order > 3.7), order


def test_kinetic_energy_is_frame_invariant_only_with_rotated_inertia():
    J = np.diag([2.0, 1.0, 1.0])
    R = rotation_matrix("123", [0.3, 0.4, 0.5])
    wb = np.array([1.0, -2.0, 0.5])
    wi = R @ wb
    assert kinetic_energy_inertial(J, R, wi) == pytest.approx(kinetic_energy_body(J, wb), rel=1e-14)
    assert abs(0.5 * wi @ J @ wi - kinetic_energy_body(J, wb)) > 1e-2


def test_bad_input_is_named():
    with pytest.raises(InputError, match="sequence = '124'"):
        rotation_matrix("124", [0, 0, 0])
    with pytest.raises(InputError, match="angles"):
        rotation_matrix("123", [0, 0])
