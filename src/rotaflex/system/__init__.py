"""Geared rotor systems: FE rotors (:mod:`rotaflex.rotor.fe`) coupled through gear meshes
(:mod:`rotaflex.gear`'s public mesh interface).

Model: :class:`Gearbox` (frozen, from TOML). Analyses are functions: :func:`modal`,
:func:`campbell`, :func:`forced_response`, :func:`steady_state`. Conventions and checks:
docs/geared-rotor.md.
"""

from rotaflex.system.modal import campbell, modal
from rotaflex.system.model import Gearbox
from rotaflex.system.response import forced_response
from rotaflex.system.steady import SteadySettings, steady_state

__all__ = ["Gearbox", "SteadySettings", "campbell", "forced_response", "modal", "steady_state"]
