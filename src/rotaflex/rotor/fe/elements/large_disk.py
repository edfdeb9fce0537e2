"""Rigid disk with exact (large) tilt kinematics, for time integration on the FE shaft.

Orientation: rotation theta_x about x, then theta_y about the new y, then the spin phi about
the new z (a 1-2-3 sequence with the spin last, the sequence of seed A's 1-2-3 analysis). For an
axisymmetric disk the kinetic energy is exact in these angles:

    T = 1/2 Id (theta_x'^2 cos^2 theta_y + theta_y'^2) + 1/2 Ip (Omega + theta_x' sin theta_y)^2

(body rates w1 = theta_x' cos theta_y, w2 = theta_y', w3 = Omega + theta_x' sin theta_y). Its
Lagrange equations, minus the linear disk terms already in M, Omega G and Omega' Kst, leave a
configuration-dependent mass ``dM`` and a remainder force ``h``:

    dM_xx = (Ip - Id) sin^2 theta_y
    h_x = 2 (Ip - Id) sin theta_y cos theta_y theta_x' theta_y'
          + Ip Omega' (sin theta_y - theta_y) + Ip Omega (cos theta_y - 1) theta_y'
    h_y = (Id - Ip) theta_x'^2 sin theta_y cos theta_y - Ip Omega theta_x' (cos theta_y - 1)

The parameterisation is singular at theta_y = +-90 deg, far outside a shaft's tilt range.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class LargeRotationDisk:
    """Nonlinear tilt terms of a rigid disk at ``node`` (added to the linear disk's M, G, Kst).

    Parameters
    ----------
    node : int
    Id, Ip : float  diametral and polar moments of inertia [kg m^2]
    """

    node: int
    Id: float
    Ip: float

    def mass_increment(self, q: np.ndarray) -> float:
        """dM on theta_x [kg m^2] at the node's DOFs ``q = [x, y, theta_x, theta_y]``."""
        return (self.Ip - self.Id) * np.sin(q[3]) ** 2

    def force(self, q: np.ndarray, v: np.ndarray, speed: float, accel: float) -> np.ndarray:
        """Remainder h (4,) [N, N m] moved to the left-hand side of the equation of motion."""
        s, c = np.sin(q[3]), np.cos(q[3])
        tx, ty = v[2], v[3]
        hx = 2 * (self.Ip - self.Id) * s * c * tx * ty + self.Ip * accel * (s - q[3]) + self.Ip * speed * (c - 1) * ty
        hy = (self.Id - self.Ip) * tx * tx * s * c - self.Ip * speed * tx * (c - 1)
        return np.array([0.0, 0.0, hx, hy])

    def M(self) -> np.ndarray:
        """Linear part is the ordinary disk's; this element adds only dM(q) (zero at q = 0)."""
        return np.zeros((4, 4))

    def K(self) -> np.ndarray:
        return np.zeros((4, 4))

    def C(self) -> np.ndarray:
        return np.zeros((4, 4))

    def G(self) -> np.ndarray:
        return np.zeros((4, 4))
