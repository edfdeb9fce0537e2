"""Finite-element rotor-bearing systems (Timoshenko shaft, rigid disks, linear bearings).

Model: :class:`Rotor` (frozen data, SI). Analyses are functions: :func:`modal`,
:func:`campbell`, :func:`ucs_map`, :func:`unbalance_response`, :func:`transient`.
"""

from rotaflex.rotor.fe.modal import campbell, modal, ucs_map
from rotaflex.rotor.fe.model import Bearing, Disk, PointMass, Rotor, Shaft
from rotaflex.rotor.fe.response import peaks, unbalance_response
from rotaflex.rotor.fe.torsion_axial import axial_modes, torsional_modes
from rotaflex.rotor.fe.transient import transient

__all__ = [
    "Bearing",
    "Disk",
    "PointMass",
    "Rotor",
    "Shaft",
    "axial_modes",
    "campbell",
    "modal",
    "peaks",
    "torsional_modes",
    "transient",
    "ucs_map",
    "unbalance_response",
]
