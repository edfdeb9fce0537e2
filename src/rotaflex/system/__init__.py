"""Geared rotor systems: FE rotors (:mod:`rotaflex.rotor.fe`) coupled through gear meshes
(:mod:`rotaflex.gear`'s public mesh interface). Model: :class:`Gearbox`; analyses are functions:
:func:`modal`, :func:`campbell`, :func:`forced_response`, :func:`steady_state`.
Conventions and checks: docs/geared-rotor.md.
"""

from rotaflex.system.model import Gearbox

__all__ = ["Gearbox"]
