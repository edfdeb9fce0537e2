"""Rigid disk at a node: mass m, diametral moment Id, polar moment Ip."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class DiskElement:
    """Rigid disk on DOFs [x, y, theta_x, theta_y] of one node.

    The kinetic energy 1/2 m (x'^2 + y'^2) + 1/2 Id (theta_x'^2 + theta_y'^2)
    + 1/2 Ip (Omega + theta_x' theta_y)^2 gives M = diag(m, m, Id, Id) and the gyroscopic
    terms +Ip Omega theta_y' (theta_x equation) and -Ip Omega theta_x' (theta_y equation).

    Parameters
    ----------
    mass : float  [kg]
    Id : float  diametral moment of inertia [kg m^2]
    Ip : float  polar moment of inertia [kg m^2]

    Examples
    --------
    >>> DiskElement.from_geometry(0.07, 0.28, 0.05, 7810.0).mass  # doctest: +ELLIPSIS
    32.58...
    """

    mass: float
    Id: float
    Ip: float

    @classmethod
    def from_geometry(cls, width: float, outer_diameter: float, inner_diameter: float, rho: float) -> DiskElement:
        """Uniform annular disk of ``width`` [m], diameters [m] and density ``rho`` [kg/m^3]."""
        ro, ri = outer_diameter / 2, inner_diameter / 2
        m = rho * np.pi * (ro**2 - ri**2) * width
        Ip = m * (ro**2 + ri**2) / 2
        Id = m * (3 * (ro**2 + ri**2) + width**2) / 12
        return cls(float(m), float(Id), float(Ip))

    def M(self) -> np.ndarray:
        """Mass matrix (4, 4)."""
        return np.diag([self.mass, self.mass, self.Id, self.Id])

    def K(self) -> np.ndarray:
        """Stiffness (4, 4): zero, the disk is rigid."""
        return np.zeros((4, 4))

    def C(self) -> np.ndarray:
        """Damping (4, 4): zero."""
        return np.zeros((4, 4))

    def G(self) -> np.ndarray:
        """Gyroscopic matrix per unit spin speed (4, 4) [kg m^2]."""
        g = np.zeros((4, 4))
        g[2, 3], g[3, 2] = self.Ip, -self.Ip
        return g

    def Kst(self) -> np.ndarray:
        """Matrix multiplying the spin acceleration d(Omega)/dt (4, 4) [kg m^2]."""
        k = np.zeros((4, 4))
        k[2, 3] = self.Ip
        return k
