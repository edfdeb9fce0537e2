"""Rotor finite elements: each has ``M()``, ``K()``, ``C()``, ``G()`` on its own DOFs.

Node DOFs are ``[x, y, theta_x, theta_y]``: translations and small rotations about the fixed
x and y axes, with the shaft along z and the spin Omega about +z. Then dx/dz = theta_y and
dy/dz = -theta_x. Elements never assemble; :mod:`rotaflex.rotor.fe.assembly` does.
"""

from rotaflex.rotor.fe.elements.bearing import BearingElement
from rotaflex.rotor.fe.elements.disk import DiskElement
from rotaflex.rotor.fe.elements.point_mass import PointMassElement
from rotaflex.rotor.fe.elements.shaft import ShaftElement, shaft_matrices

__all__ = ["BearingElement", "DiskElement", "PointMassElement", "ShaftElement", "shaft_matrices"]
