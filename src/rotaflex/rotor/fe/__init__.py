"""Finite-element rotor-bearing systems (Timoshenko shaft, rigid disks, linear bearings).

Model: :class:`Rotor` (frozen data, SI). Analyses are functions: :func:`static_analysis`,
:func:`modal`, :func:`campbell`, :func:`critical_speeds`, :func:`ucs_map`,
:func:`unbalance_response`, :func:`frf`, :func:`transient`; API 684 rules in :mod:`.api`.
The same analyses with the command line's result objects (summary, verdicts, plot methods):
:func:`modes`, :func:`campbell_diagram`, :func:`unbalance_response_study`,
:func:`static_state`, :func:`critical_speed_map`, :func:`transient_response`; ``study.frf`` and
``study.stability`` stay in :mod:`.study` (here ``frf`` is the analysis function and
``stability`` the module).
"""

from rotaflex.rotor.fe.critical import critical_speeds
from rotaflex.rotor.fe.frf import frf
from rotaflex.rotor.fe.modal import campbell, modal
from rotaflex.rotor.fe.model import Bearing, Disk, PointMass, Rotor, Shaft
from rotaflex.rotor.fe.response import peaks, unbalance_response
from rotaflex.rotor.fe.static import static_analysis
from rotaflex.rotor.fe.study import (
    campbell_diagram,
    critical_speed_map,
    modes,
    static_state,
    transient_response,
    unbalance_response_study,
)
from rotaflex.rotor.fe.torsion_axial import axial_modes, torsional_modes
from rotaflex.rotor.fe.transient import transient
from rotaflex.rotor.fe.ucs import ucs_map

__all__ = [
    "Bearing",
    "Disk",
    "PointMass",
    "Rotor",
    "Shaft",
    "axial_modes",
    "campbell",
    "campbell_diagram",
    "critical_speed_map",
    "critical_speeds",
    "frf",
    "modal",
    "modes",
    "peaks",
    "static_analysis",
    "static_state",
    "torsional_modes",
    "transient",
    "transient_response",
    "ucs_map",
    "unbalance_response",
    "unbalance_response_study",
]
