"""Rotor-disk and free rigid-body dynamics with Euler-angle and quaternion parameterisations.

Equations of motion are derived symbolically (sympy, Lagrange) from the kinetic energy for any
Euler sequence and for the spherical-coordinate quaternion of Yun & Ren (2008), compiled once to
plain Python/NumPy and cached on disk (:mod:`rotaflex.rotor.symbolic`).
"""

from rotaflex.rotor.model import Disk, Formulation, FreeBody, Motion, RotorModel, Solver, Support
from rotaflex.rotor.simulate import simulate

__all__ = ["Disk", "Formulation", "FreeBody", "Motion", "RotorModel", "Solver", "Support", "simulate"]
