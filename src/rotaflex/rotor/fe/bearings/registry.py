"""The bearing kinds that have a sub-table in ``[bearing.NAME]`` (docs/architecture.md, element contract).

``KINDS[name] = (schema dataclass, element(spec, where) -> element)``. A bearing without any of
these sub-tables is the linear kind (coefficient keys, constant or over ``speed_rpm``).
"""

from __future__ import annotations

from rotaflex.core.errors import InputError
from rotaflex.rotor.fe.bearings.fluid_film import FluidFilm, fluid_film_table
from rotaflex.rotor.fe.bearings.labyrinth import Labyrinth
from rotaflex.rotor.fe.bearings.labyrinth import element as labyrinth_element
from rotaflex.rotor.fe.bearings.liquid_seal import LiquidSeal
from rotaflex.rotor.fe.bearings.liquid_seal import element as liquid_seal_element
from rotaflex.rotor.fe.bearings.magnetic import Magnetic
from rotaflex.rotor.fe.bearings.magnetic import element as magnetic_element
from rotaflex.rotor.fe.elements.bearing import COEFFICIENTS, BearingElement


def fluid_film_element(spec: FluidFilm, where: str) -> BearingElement:
    """Speed-tabulated element of a plain or tilting-pad journal bearing."""
    table = fluid_film_table(spec, where)
    return BearingElement(table.k, table.c, table.speed, where, table)


KINDS = {
    "fluid_film": (FluidFilm, fluid_film_element),
    "magnetic": (Magnetic, magnetic_element),
    "labyrinth": (Labyrinth, labyrinth_element),
    "liquid_seal": (LiquidSeal, liquid_seal_element),
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
    """The element of a bearing with a kind sub-table (its coefficient keys and speed_rpm refused)."""
    kind = kind_of(bearing, where)
    for key in COEFFICIENTS:
        if any(getattr(bearing, key)):
            raise InputError(f"{where}.{key}", list(getattr(bearing, key)), f"no coefficients with {kind}")
    if bearing.speed_rpm is not None:
        allowed = "fluid_film.speed_rpm instead" if kind == "fluid_film" else f"no speed_rpm with {kind} (any speed)"
        raise InputError(f"{where}.speed_rpm", list(bearing.speed_rpm), allowed)
    return KINDS[kind][1](getattr(bearing, kind), f"{where}.{kind}")
