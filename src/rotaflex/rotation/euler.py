"""Euler-angle rotations for all 12 intrinsic sequences, vectorised over leading dimensions.

For sequence "abc" and angles ``(a0, a1, a2)``::

    R = R_a(a0) R_b(a1) R_c(a2)
    omega_body     = R_c^T R_b^T e_a a0' + R_c^T e_b a1' + e_c a2'   = E_body(angles) @ rates
    omega_inertial = e_a a0' + R_a e_b a1' + R_a R_b e_c a2'         = E_inertial(angles) @ rates

Both maps lose rank when the middle angle makes the first and last axes parallel:
``cos(a1) = 0`` for Tait-Bryan sequences, ``sin(a1) = 0`` for proper Euler sequences.
"""

from __future__ import annotations

import numpy as np

from rotaflex.core.errors import InputError, SingularityError

#: the 6 proper Euler and 6 Tait-Bryan sequences
SEQUENCES = ("121", "131", "212", "232", "313", "323", "123", "132", "213", "231", "312", "321")
CONVENTIONS = ("right-handed", "paper")


def check_sequence(sequence: str) -> tuple[int, int, int]:
    """Axis indices (0-based) of a sequence name, or InputError naming the allowed ones."""
    if sequence not in SEQUENCES:
        raise InputError("sequence", sequence, "one of " + ", ".join(SEQUENCES))
    return tuple(int(c) - 1 for c in sequence)  # type: ignore[return-value]


def is_proper(sequence: str) -> bool:
    """True for proper Euler sequences (first and last axis equal)."""
    return sequence[0] == sequence[2]


def elementary_rotation(axis: int, angle) -> np.ndarray:
    """Right-handed active rotation about coordinate axis ``axis`` (0, 1, 2); shape (..., 3, 3)."""
    angle = np.asarray(angle, dtype=float)
    c, s = np.cos(angle), np.sin(angle)
    R = np.zeros(angle.shape + (3, 3))
    i, j = (axis + 1) % 3, (axis + 2) % 3
    R[..., axis, axis] = 1.0
    R[..., i, i] = c
    R[..., j, j] = c
    R[..., i, j] = -s
    R[..., j, i] = s
    return R


def _paper_angles(sequence: str, angles: np.ndarray, convention: str) -> np.ndarray:
    if convention not in CONVENTIONS:
        raise InputError("convention", convention, "one of " + ", ".join(CONVENTIONS))
    if convention == "paper" and sequence == "123":
        # Yun & Ren print R_theta about y1 with the left-handed sign (eq. 6, 10)
        angles = angles * np.array([1.0, -1.0, 1.0])
    return angles


def _angles(angles) -> np.ndarray:
    angles = np.asarray(angles, dtype=float)
    if angles.shape[-1:] != (3,):
        raise InputError("angles", angles.shape, "an array with last dimension 3")
    return angles


def rotation_matrix(sequence: str, angles, convention: str = "right-handed") -> np.ndarray:
    """Rotation matrix ``R = R_a R_b R_c`` of an intrinsic Euler sequence.

    Parameters
    ----------
    sequence : str
        One of :data:`SEQUENCES`, e.g. ``"123"``.
    angles : array_like, shape (..., 3)
        Angles [rad] in the order of the sequence.
    convention : {"right-handed", "paper"}
        ``"paper"`` flips the sign of the second 1-2-3 rotation as printed in the paper.

    Returns
    -------
    ndarray, shape (..., 3, 3)

    Examples
    --------
    >>> R = rotation_matrix("313", [0.1, 0.2, 0.3])
    >>> bool(abs(np.linalg.det(R) - 1) < 1e-12)
    True
    """
    a, b, c = check_sequence(sequence)
    ang = _paper_angles(sequence, _angles(angles), convention)
    return (
        elementary_rotation(a, ang[..., 0]) @ elementary_rotation(b, ang[..., 1]) @ elementary_rotation(c, ang[..., 2])
    )


def body_rate_matrix(sequence: str, angles, convention: str = "right-handed") -> np.ndarray:
    """Map ``E_body`` with ``omega_body = E_body @ angle_rates``; shape (..., 3, 3).

    With ``convention="paper"`` for "123" this is the paper's eq. 6 (not the map of any
    rotation matrix: the printed matrices mix two handedness conventions).
    """
    a, b, c = check_sequence(sequence)
    ang = _paper_angles(sequence, _angles(angles), convention)
    Rb = elementary_rotation(b, ang[..., 1])
    Rc = elementary_rotation(c, ang[..., 2])
    E = np.empty(ang.shape[:-1] + (3, 3))
    # columns: R_c^T R_b^T e_a, R_c^T e_b, e_c (rows of R_b R_c / R_c are columns of their transpose)
    E[..., :, 0] = (Rb @ Rc)[..., a, :]
    E[..., :, 1] = Rc[..., b, :]
    E[..., :, 2] = 0.0
    E[..., c, 2] = 1.0
    return E


def inertial_rate_matrix(sequence: str, angles, convention: str = "right-handed") -> np.ndarray:
    """Map ``E_inertial`` with ``omega_inertial = E_inertial @ angle_rates``; shape (..., 3, 3).

    With ``convention="paper"`` for "123" this is the paper's eq. 10.
    """
    a, b, c = check_sequence(sequence)
    ang = _paper_angles(sequence, _angles(angles), convention)
    Ra = elementary_rotation(a, ang[..., 0])
    Rab = Ra @ elementary_rotation(b, ang[..., 1])
    E = np.empty(ang.shape[:-1] + (3, 3))
    E[..., :, 0] = 0.0
    E[..., a, 0] = 1.0
    E[..., :, 1] = Ra[..., :, b]
    E[..., :, 2] = Rab[..., :, c]
    return E


def singularity_measure(sequence: str, angles) -> np.ndarray:
    """``|det E|``: 0 at gimbal lock, 1 farthest from it (``|cos a1|`` or ``|sin a1|``)."""
    check_sequence(sequence)
    mid = _angles(angles)[..., 1]
    return np.abs(np.sin(mid)) if is_proper(sequence) else np.abs(np.cos(mid))


def _rates(E: np.ndarray, omega, sequence: str, angles, tol: float) -> np.ndarray:
    measure = singularity_measure(sequence, angles)
    if np.any(measure < tol):
        worst = float(np.min(measure))
        raise SingularityError(
            f"Euler {sequence} angular-velocity map",
            detail=f"|det E| = {worst:.3e} < {tol:g}: first and last rotation axes aligned",
        )
    return np.linalg.solve(E, np.asarray(omega, dtype=float)[..., None])[..., 0]


def euler_rates_from_body(
    sequence: str, angles, omega_body, tol: float = 1e-10, convention: str = "right-handed"
) -> np.ndarray:
    """Angle rates from body-frame angular velocity (inverse of :func:`body_rate_matrix`).

    Raises
    ------
    SingularityError
        When the configuration is within ``tol`` of gimbal lock.
    """
    return _rates(body_rate_matrix(sequence, angles, convention), omega_body, sequence, angles, tol)


def euler_rates_from_inertial(
    sequence: str, angles, omega_inertial, tol: float = 1e-10, convention: str = "right-handed"
) -> np.ndarray:
    """Angle rates from inertial-frame angular velocity (inverse of :func:`inertial_rate_matrix`)."""
    E = inertial_rate_matrix(sequence, angles, convention)
    return _rates(E, omega_inertial, sequence, angles, tol)


def euler_from_matrix(sequence: str, R) -> np.ndarray:
    """Angles of ``sequence`` reproducing rotation matrix ``R`` (..., 3, 3).

    The middle angle lies in [0, pi] (proper) or [-pi/2, pi/2] (Tait-Bryan). At gimbal lock the
    split between first and last angle is arbitrary (scipy sets the last to zero).
    """
    from scipy.spatial.transform import Rotation

    check_sequence(sequence)
    R = np.asarray(R, dtype=float)
    letters = "".join("XYZ"[int(c) - 1] for c in sequence)  # upper case = intrinsic in scipy
    flat = R.reshape(-1, 3, 3)
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # gimbal-lock warning: documented above
        angles = Rotation.from_matrix(flat).as_euler(letters)
    return angles.reshape(R.shape[:-2] + (3,))
