"""Size limits every run is checked against before it starts.

A verb estimates what it will need (DOFs, steps, output points, table points, bytes) from the
validated config and calls :func:`require` (counts) or :func:`require_memory` (bytes) before
anything is allocated. A refusal is an :class:`~rotaflex.core.errors.InputError` naming the key
the user would change, its value, the estimate and the limit, and how to raise the limit.

The memory limit is one process-wide number: ``ROTAFLEX_MAX_MEMORY`` (e.g. ``"16GiB"``) or the
CLI's ``--max-memory``, default :data:`DEFAULT_MAX_MEMORY` (half of this machine's 24 GiB class,
so that two sweep workers fit side by side).
"""

from __future__ import annotations

import os
import re

from rotaflex.core.errors import InputError

__all__ = ["DEFAULT_MAX_MEMORY", "max_memory", "parse_bytes", "require", "require_memory", "set_max_memory"]

#: default memory a single run may plan to use [bytes]
DEFAULT_MAX_MEMORY = 8 * 1024**3

_UNITS = {
    "": 1,
    "b": 1,
    "kb": 1e3,
    "mb": 1e6,
    "gb": 1e9,
    "tb": 1e12,
    "kib": 1024,
    "mib": 1024**2,
    "gib": 1024**3,
    "tib": 1024**4,
}
_override: float | None = None


def parse_bytes(text: str | int | float, field: str = "--max-memory") -> float:
    """``"16GiB"``, ``"500 MB"``, ``2e9`` -> bytes (float); InputError naming ``field`` otherwise."""
    if isinstance(text, (int, float)) and not isinstance(text, bool):
        value = float(text)
    else:
        m = re.fullmatch(r"\s*([0-9.]+(?:[eE][+-]?[0-9]+)?)\s*([A-Za-z]*)\s*", str(text))
        if not m or m.group(2).lower() not in _UNITS:
            raise InputError(field, text, "a size such as 16GiB, 500MB or 2e9 (bytes)")
        value = float(m.group(1)) * _UNITS[m.group(2).lower()]
    if not (value > 0 and value < float("inf")):
        raise InputError(field, text, "a size > 0")
    return value


def set_max_memory(value: str | float | None) -> None:
    """Set the process-wide memory limit (``None`` restores the environment/default)."""
    global _override
    _override = None if value is None else parse_bytes(value)


def max_memory() -> float:
    """The memory limit in force [bytes]: ``set_max_memory``, else ``ROTAFLEX_MAX_MEMORY``, else the default."""
    if _override is not None:
        return _override
    env = os.environ.get("ROTAFLEX_MAX_MEMORY")
    return parse_bytes(env, "ROTAFLEX_MAX_MEMORY") if env else float(DEFAULT_MAX_MEMORY)


def _size(n: float) -> str:
    for unit, scale in (("TiB", 1024**4), ("GiB", 1024**3), ("MiB", 1024**2), ("KiB", 1024)):
        if n >= scale:
            return f"{n / scale:.3g} {unit}"
    return f"{n:.0f} B"


def require(field: str, value: object, estimate: float, limit: float, what: str, raise_with: str = "") -> None:
    """Refuse a run whose estimated count exceeds ``limit`` (also refuses nan).

    Parameters
    ----------
    field, value : str, object
        The config key the user would change and its value as typed.
    estimate, limit : float
        Estimated count and the largest accepted.
    what : str
        What is counted, in words (``"integration steps"``, ``"shaft elements"``).
    raise_with : str
        How to raise the limit if the user means it (``"raise solver.max_steps"``); empty if fixed.
    """
    if not (estimate <= limit):
        how = f"; {raise_with}" if raise_with else ""
        raise InputError(field, value, f"a value needing at most {limit:.3g} {what} (this needs ~{estimate:.3g}{how})")


def require_memory(field: str, value: object, estimate_bytes: float, what: str = "") -> None:
    """Refuse a run whose planned memory exceeds :func:`max_memory`.

    Parameters
    ----------
    field, value : str, object
        The config key the user would change and its value as typed.
    estimate_bytes : float
        Planned peak memory of the arrays the run will allocate [bytes].
    what : str
        What takes the memory (``"the transient history"``), for the message.
    """
    limit = max_memory()
    if not (estimate_bytes <= limit):
        of = f" for {what}" if what else ""
        raise InputError(
            field,
            value,
            f"a value needing at most {_size(limit)} of memory (this needs ~{_size(estimate_bytes)}{of}; "
            "raise the limit with --max-memory or ROTAFLEX_MAX_MEMORY if the machine has it)",
        )
