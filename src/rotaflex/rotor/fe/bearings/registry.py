"""The bearing kinds that have a sub-table in ``[bearing.NAME]`` (docs/architecture.md, element contract).

``KINDS[name] = (schema dataclass, build(bearing, where) -> element)``: ``build`` receives the
whole :class:`~rotaflex.rotor.fe.model.Bearing` (the fluid film also reads its mass coefficients
and table interpolation); a computed kind's module only provides ``element(spec, where)`` and is
wrapped by :func:`computed`. A bearing without any of these sub-tables is the linear kind
(coefficient keys, constant or over ``speed_rpm``/``whirl_hz``: ``BearingElement.from_table``).
"""

from __future__ import annotations

from rotaflex.core.errors import InputError
from rotaflex.rotor.fe.bearings.fluid_film import FluidFilm
from rotaflex.rotor.fe.bearings.labyrinth import Labyrinth
from rotaflex.rotor.fe.bearings.labyrinth import element as labyrinth_element
from rotaflex.rotor.fe.bearings.liquid_seal import LiquidSeal
from rotaflex.rotor.fe.bearings.liquid_seal import element as liquid_seal_element
from rotaflex.rotor.fe.bearings.magnetic import Magnetic
from rotaflex.rotor.fe.bearings.magnetic import element as magnetic_element
from rotaflex.rotor.fe.elements.bearing import COEFFICIENTS, MASS_COEFFICIENTS, BearingElement, flat


def computed(element):
    """``build(bearing, where)`` of a computed kind: its coefficient, mass and table keys refused
    (the kind computes them at any speed), then ``element(spec, where.kind)``."""

    def build(bearing, where: str):
        kind = kind_of(bearing, where)
        for key in (*COEFFICIENTS, *MASS_COEFFICIENTS):
            if any(flat(getattr(bearing, key))):
                raise InputError(f"{where}.{key}", getattr(bearing, key), f"no coefficients with {kind}")
        for key in ("speed_rpm", "whirl_hz"):
            if getattr(bearing, key) is not None:
                raise InputError(f"{where}.{key}", list(getattr(bearing, key)), f"no {key} with {kind} (any speed)")
        return element(getattr(bearing, kind), f"{where}.{kind}")

    return build


KINDS = {
    "fluid_film": (FluidFilm, BearingElement.from_fluid_film),
    "magnetic": (Magnetic, computed(magnetic_element)),
    "labyrinth": (Labyrinth, computed(labyrinth_element)),
    "liquid_seal": (LiquidSeal, computed(liquid_seal_element)),
}

#: kinds that are seals (API 617 Level I leaves them out; Level II adds them one by one)
SEALS: tuple[str, ...] = ("labyrinth", "liquid_seal")


def kind_of(bearing, where: str = "bearing") -> str | None:
    """The sub-table kind of a :class:`~rotaflex.rotor.fe.model.Bearing` (None: linear)."""
    given = [k for k in KINDS if getattr(bearing, k, None) is not None]
    if len(given) > 1:
        raise InputError(f"{where}.{given[1]}", "<table>", f"one kind per bearing ({given[0]} is given)")
    return given[0] if given else None


def element(bearing, where: str = "bearing"):
    """The element of a bearing with a kind sub-table."""
    return KINDS[kind_of(bearing, where)][1](bearing, where)
