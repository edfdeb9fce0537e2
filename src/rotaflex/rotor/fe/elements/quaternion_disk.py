"""Rigid disk with Euler-parameter (quaternion) attitude, for time integration on the FE shaft.

Seed A's rigid-body kinematics carried onto a shaft node. State of the disk: the unit quaternion
``e = (e0, e1, e2, e3)`` (scalar first, body -> inertial, ``R(e) = I + 2 e0 e~ + 2 e~ e~``) and
the body angular velocity ``w`` (body axes 1, 2 diametral, 3 the disk axis). Equations:

    de/dt = 1/2 A(e) (0, w)                 (seed A, eq. 20a; A as in rotaflex.rotation.quaternion)
    J dw/dt = R^T tau - w x J w,  J = diag(Id, Id, Ip)   (Euler's equations)

Coupling to the shaft node (translation x, y and small tilts theta_x, theta_y):

* translation: the disk's centre is the node; its mass stays in the FE mass matrix;
* rotation: a bending hub joint of stiffness ``k`` [N m/rad] between the disk axis
  ``n = R e_3`` and the node's slope, with energy

      V = k/2 [(n_x - theta_y)^2 + (n_y + theta_x)^2]

  (``n = (theta_y, -theta_x, 1)`` to first order, so this is the linear disk's slope when
  ``k -> inf``). It exerts the spatial torque ``tau = a x n``, ``a = k (n_x - theta_y,
  n_y + theta_x, 0)``, on the disk and ``(-k (n_y + theta_x), k (n_x - theta_y))`` on
  ``(theta_x, theta_y)``. ``n`` is defined for every attitude, so nothing is singular at
  90 deg tilt. The torque is normal to ``n``: the joint transmits no torque about the disk axis,
  so the disk's spin rate ``w_3`` is an exact constant of the motion (axisymmetric disk).

The disk's Id and Ip are carried here, not in the FE matrices (the caller removes them).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


def rotation_matrix(e: np.ndarray) -> np.ndarray:
    """``R(e/|e|)`` (3, 3): the attitude is renormalised in use, the state itself is not."""
    u = e / np.sqrt(e @ e)
    e0, x, y, z = u
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - e0 * z), 2 * (x * z + e0 * y)],
            [2 * (x * y + e0 * z), 1 - 2 * (x * x + z * z), 2 * (y * z - e0 * x)],
            [2 * (x * z - e0 * y), 2 * (y * z + e0 * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def quaternion_rate(e: np.ndarray, w: np.ndarray) -> np.ndarray:
    """``1/2 A(e) (0, w)`` (4,): scalar part ``-e.w / 2``, vector part ``(e0 w + e x w) / 2``."""
    return 0.5 * np.concatenate([[-(e[1:] @ w)], e[0] * w + np.cross(e[1:], w)])


@dataclass(frozen=True)
class QuaternionDisk:
    """Rigid disk at ``node`` with quaternion attitude, joined to the node by a bending hub spring.

    Parameters
    ----------
    node : int
    Id, Ip : float  diametral and polar moments of inertia [kg m^2]
    hub_stiffness : float  bending stiffness k of the joint [N m/rad] (0: a free disk)
    """

    node: int
    Id: float
    Ip: float
    hub_stiffness: float

    @property
    def J(self) -> np.ndarray:
        return np.array([self.Id, self.Id, self.Ip])

    def _misfit(self, R: np.ndarray, tilt: np.ndarray) -> np.ndarray:
        n = R[:, 2]
        return np.array([n[0] - tilt[1], n[1] + tilt[0], 0.0])

    def rates(self, e: np.ndarray, w: np.ndarray, tilt: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(de/dt (4,), dw/dt (3,), moment on (theta_x, theta_y) (2,) [N m])``.

        ``tilt`` = the node's ``(theta_x, theta_y)`` [rad].
        """
        R = rotation_matrix(e)
        a = self.hub_stiffness * self._misfit(R, tilt)
        tau_body = R.T @ np.cross(a, R[:, 2])
        J = self.J
        dw = (tau_body - np.cross(w, J * w)) / J
        return quaternion_rate(e, w), dw, np.array([-a[1], a[0]])

    def energy(self, e: np.ndarray, w: np.ndarray, tilt: np.ndarray) -> float:
        """Kinetic energy of rotation plus the hub spring's energy [J]."""
        d = self._misfit(rotation_matrix(e), tilt)
        return 0.5 * float(self.J @ (w * w)) + 0.5 * self.hub_stiffness * float(d @ d)

    def angular_momentum(self, e: np.ndarray, w: np.ndarray) -> np.ndarray:
        """Inertial angular momentum ``R J w`` about the disk's centre [kg m^2/s]."""
        return rotation_matrix(e) @ (self.J * w)

    @staticmethod
    def initial_state(tilt, tilt_rate, speed: float) -> tuple[np.ndarray, np.ndarray]:
        """Quaternion and body rates matching a 1-2-3 start (spin angle 0) [rad, rad/s].

        ``R = Rx(theta_x) Ry(theta_y)``; ``w = (theta_x' cos theta_y, theta_y',
        Omega + theta_x' sin theta_y)``, the rates of
        :class:`~rotaflex.rotor.fe.elements.large_disk.LargeRotationDisk`.
        """
        tx, ty = tilt
        qx = np.array([np.cos(tx / 2), np.sin(tx / 2), 0.0, 0.0])
        c, s = np.cos(ty / 2), np.sin(ty / 2)
        # qx (x) qy with qy = (c, 0, s, 0)
        e = np.array([qx[0] * c, qx[1] * c, qx[0] * s, qx[1] * s])
        w = np.array([tilt_rate[0] * np.cos(ty), tilt_rate[1], speed + tilt_rate[0] * np.sin(ty)])
        return e, w
