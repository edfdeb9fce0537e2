"""Unit quaternions (Euler parameters), scalar first: ``e = (e0, e1, e2, e3)``.

The paper's 4x4 matrices (Yun & Ren 2008, eq. 17) with ``e~`` the skew matrix of ``e[1:]``::

    A = [[e0, -e^T], [e,  e0 I + e~]]     omega^*  = 2 A^T de/dt,  de/dt = 1/2 A omega^*
    B = [[e0, -e^T], [e,  e0 I - e~]]     omega^   = 2 B^T de/dt,  de/dt = 1/2 B omega^
    C = [[e0,  e^T], [e, -e0 I - e~]]

where ``omega^* = (0, omega_body)`` and ``omega^ = (0, omega_inertial)``. The paper also writes
``omega^* = 2 C^T de/dt`` and ``omega^ = 2 C de/dt``; both hold only up to the sign of the vector
part (see docs/rotation.md); A and B are the ones used here.
"""

from __future__ import annotations

import numpy as np

from rotaflex.core.errors import InputError


def _q(e) -> np.ndarray:
    e = np.asarray(e, dtype=float)
    if e.shape[-1:] != (4,):
        raise InputError("quaternion", e.shape, "an array with last dimension 4 (e0, e1, e2, e3)")
    return e


def skew(v) -> np.ndarray:
    """Skew-symmetric matrix ``v~`` with ``v~ @ w = v x w``; shape (..., 3, 3)."""
    v = np.asarray(v, dtype=float)
    S = np.zeros(v.shape[:-1] + (3, 3))
    S[..., 0, 1], S[..., 0, 2] = -v[..., 2], v[..., 1]
    S[..., 1, 0], S[..., 1, 2] = v[..., 2], -v[..., 0]
    S[..., 2, 0], S[..., 2, 1] = -v[..., 1], v[..., 0]
    return S


def quaternion_to_matrix(e) -> np.ndarray:
    """Rotation matrix ``R(e) = I + 2 e0 e~ + 2 e~ e~`` (eq. 14) of a unit quaternion."""
    e = _q(e)
    S = skew(e[..., 1:])
    return np.eye(3) + 2.0 * e[..., 0, None, None] * S + 2.0 * S @ S


def quaternion_matrices(e) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The paper's 4x4 matrices ``A(e), B(e), C(e)`` of eq. 17; each shape (..., 4, 4)."""
    e = _q(e)
    e0, v = e[..., 0], e[..., 1:]
    S = skew(v)
    eye = np.eye(3) * e0[..., None, None]

    def build(top_sign: float, block: np.ndarray) -> np.ndarray:
        M = np.empty(e.shape[:-1] + (4, 4))
        M[..., 0, 0] = e0
        M[..., 0, 1:] = top_sign * v
        M[..., 1:, 0] = v
        M[..., 1:, 1:] = block
        return M

    return build(-1.0, eye + S), build(-1.0, eye - S), build(1.0, -eye - S)


def rates_from_quaternion(e, e_dot) -> tuple[np.ndarray, np.ndarray]:
    """Body and inertial angular velocity from ``e`` and ``de/dt`` (eq. 15-16).

    Returns
    -------
    omega_body, omega_inertial : ndarray, shape (..., 3)
        [rad/s]. The scalar parts of ``2 A^T de/dt`` and ``2 B^T de/dt`` vanish for unit ``e``
        (eq. 19) and are dropped.
    """
    A, B, _ = quaternion_matrices(e)
    e_dot = np.asarray(e_dot, dtype=float)[..., None]
    wb = 2.0 * np.swapaxes(A, -1, -2) @ e_dot
    wi = 2.0 * np.swapaxes(B, -1, -2) @ e_dot
    return wb[..., 1:, 0], wi[..., 1:, 0]


def _hat(omega) -> np.ndarray:
    omega = np.asarray(omega, dtype=float)
    return np.concatenate([np.zeros(omega.shape[:-1] + (1,)), omega], axis=-1)[..., None]


def quaternion_rates_from_body(e, omega_body) -> np.ndarray:
    """``de/dt = 1/2 A(e) (0, omega_body)`` (eq. 20a)."""
    A, _, _ = quaternion_matrices(e)
    return 0.5 * (A @ _hat(omega_body))[..., 0]


def quaternion_rates_from_inertial(e, omega_inertial) -> np.ndarray:
    """``de/dt = 1/2 B(e) (0, omega_inertial)`` (eq. 20b)."""
    _, B, _ = quaternion_matrices(e)
    return 0.5 * (B @ _hat(omega_inertial))[..., 0]


def quaternion_from_matrix(R) -> np.ndarray:
    """Unit quaternion (scalar first, ``e0 >= 0``) of a rotation matrix (..., 3, 3)."""
    from scipy.spatial.transform import Rotation

    R = np.asarray(R, dtype=float)
    xyzw = Rotation.from_matrix(R.reshape(-1, 3, 3)).as_quat()
    e = np.concatenate([xyzw[:, 3:], xyzw[:, :3]], axis=1)  # scipy stores the scalar last
    e *= np.where(e[:, :1] < 0, -1.0, 1.0)
    return e.reshape(R.shape[:-2] + (4,))


def quaternion_from_euler(sequence: str, angles, convention: str = "right-handed") -> np.ndarray:
    """Unit quaternion of an Euler-angle attitude (product of three axis quaternions)."""
    from rotaflex.rotation.euler import _angles, _paper_angles, check_sequence

    axes = check_sequence(sequence)
    ang = _paper_angles(sequence, _angles(angles), convention)
    e = None
    for k, axis in enumerate(axes):
        half = 0.5 * ang[..., k]
        qk = np.zeros(half.shape + (4,))
        qk[..., 0] = np.cos(half)
        qk[..., 1 + axis] = np.sin(half)
        e = qk if e is None else quaternion_product(e, qk)
    return e * np.where(e[..., :1] < 0, -1.0, 1.0)


def euler_from_quaternion(sequence: str, e) -> np.ndarray:
    """Euler angles of ``sequence`` for unit quaternion(s) ``e`` (see :func:`euler_from_matrix`)."""
    from rotaflex.rotation.euler import euler_from_matrix

    return euler_from_matrix(sequence, quaternion_to_matrix(e))


def quaternion_product(p, q) -> np.ndarray:
    """Hamilton product ``p (x) q``; ``R(p (x) q) = R(p) R(q)``."""
    p, q = _q(p), _q(q)
    p0, pv, q0, qv = p[..., :1], p[..., 1:], q[..., :1], q[..., 1:]
    scalar = p0 * q0 - np.sum(pv * qv, axis=-1, keepdims=True)
    vector = p0 * qv + q0 * pv + np.cross(pv, qv)
    return np.concatenate([scalar, vector], axis=-1)


def _exp_body(omega_dt) -> np.ndarray:
    """Quaternion of the rotation vector ``omega_dt`` (..., 3)."""
    angle = np.linalg.norm(omega_dt, axis=-1, keepdims=True)
    half = 0.5 * angle
    # sin(x/2)/x -> 1/2 as x -> 0 (np.sinc(x/pi) = sin(x)/x)
    scale = 0.5 * np.sinc(half / np.pi)
    return np.concatenate([np.cos(half), scale * omega_dt], axis=-1)


def integrate_attitude(time, omega_body, e_initial=(1.0, 0.0, 0.0, 0.0)) -> np.ndarray:
    """Attitude history from sampled body rates, exactly unit norm at every sample.

    Each interval uses the fourth-order commutator-free Magnus step with the rates interpolated
    linearly in time (second order in the sample spacing for sampled data, fourth order when the
    rates are linear in time); the update multiplies by unit quaternions, so ``|e| = 1`` holds to
    rounding regardless of step size.

    Parameters
    ----------
    time : array_like, shape (n,)
        Increasing sample times [s].
    omega_body : array_like, shape (n, 3)
        Body-frame angular velocity at those times [rad/s].
    e_initial : array_like, shape (4,)
        Initial unit quaternion.

    Returns
    -------
    ndarray, shape (n, 4)
    """
    t = np.asarray(time, dtype=float)
    w = np.asarray(omega_body, dtype=float)
    if t.ndim != 1 or w.shape != (t.size, 3):
        raise InputError("omega_body", w.shape, f"shape ({t.size}, 3) matching time")
    if np.any(np.diff(t) <= 0):
        raise InputError("time", "non-increasing", "strictly increasing sample times")
    e0 = _q(e_initial)
    e0 = e0 / np.linalg.norm(e0)
    h = np.diff(t)[:, None]
    # Gauss points of the linear interpolant, then the 4th-order two-exponential Magnus scheme
    g = np.sqrt(3.0) / 6.0
    w1 = w[:-1] * (0.5 + g) + w[1:] * (0.5 - g)
    w2 = w[:-1] * (0.5 - g) + w[1:] * (0.5 + g)
    a, b = 0.25 + g, 0.25 - g
    steps = quaternion_product(_exp_body(h * (a * w1 + b * w2)), _exp_body(h * (b * w1 + a * w2)))
    out = np.empty((t.size, 4))
    out[0] = e0
    for k in range(t.size - 1):  # sequential product: O(n) quaternion multiplies, no solves
        out[k + 1] = quaternion_product(out[k], steps[k])
    return out
