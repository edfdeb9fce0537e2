"""Facts of the FE rotor that the model, the static analysis and the bearing modules share.

The DOF layout per node and the key paths of the user's ``[bearing.*]`` tables live here, below
:mod:`rotaflex.rotor.fe.model`, so that :mod:`rotaflex.rotor.fe.static` and
:mod:`rotaflex.rotor.fe.bearings.static_load` (which the model calls to resolve
``load = "static"``) need not import the model.
"""

from __future__ import annotations

NDOF_NODE = 4  #: [x, y, theta_x, theta_y]


def table_key(array: str, name: str) -> str:
    """``bearing.left`` for the table ``[bearing.left]`` (the name quoted where TOML needs it)."""
    bare = name and all(c.isascii() and (c.isalnum() or c in "_-") for c in name)
    return f"{array}.{name}" if bare else f'{array}."{name}"'


def bearing_path(i: int, b) -> str:
    """The key path of bearing ``i`` (a :class:`~rotaflex.rotor.fe.model.Bearing`) as the user
    wrote it: ``bearing.left`` for a named ``[bearing.left]`` table, ``bearing[i]`` for the i-th
    ``[[bearing]]``."""
    return table_key("bearing", b.name) if b.name else f"bearing[{i}]"
