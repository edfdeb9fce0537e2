"""Finite-element rotor-bearing systems (Timoshenko shaft, rigid disks, linear bearings).

Model: :class:`Rotor` (frozen data, SI). Analyses are functions: :func:`modal`,
:func:`campbell`, :func:`ucs_map`, :func:`unbalance_response`, :func:`transient`.
"""

from rotaflex.rotor.fe.model import Bearing, Disk, PointMass, Rotor, Shaft

__all__ = ["Bearing", "Disk", "PointMass", "Rotor", "Shaft"]
