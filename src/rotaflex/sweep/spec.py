"""Sweep specifications: ``KEY=START:STOP:N`` / ``KEY=v1,v2`` parsing, grids and case ids.

A sweep over a TOML config is a Cartesian product of one or more *varied* keys (dotted paths
into the config). Each point of the grid is a :class:`Case` whose ``data`` is the full config
with the varied keys set, and whose ``id`` is stable across runs of the same sweep (index plus a
hash of the case data), so that a re-run can recognise the cases already done.
"""

from __future__ import annotations

import copy
import hashlib
import itertools
import json
import math
import re
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from rotaflex.core.errors import InputError

_VARY_FORMS = "KEY=START:STOP:N (N evenly spaced values) or KEY=v1,v2,... (a list)"

#: most cases one sweep may plan; refused before any case is built (a 1e8-point grid would need
#: several GB for its configs alone). Split bigger studies into several sweeps.
MAX_CASES = 100_000


@dataclass(frozen=True)
class Case:
    """One case of a sweep.

    Parameters
    ----------
    id : str
        Directory name of the case under ``DIR/cases/``; unique within a sweep.
    params : dict
        Values of the swept parameters for this case (they become coordinates of ``sweep.nc``).
    data : object
        The argument handed to the case function (plain, picklable data, e.g. a config dict).
    """

    id: str
    params: dict[str, Any]
    data: Any = field(default=None, compare=False)


def _scalar(text: str) -> Any:
    """A TOML-like scalar literal: integer, float, true/false, otherwise a (unquoted) string."""
    s = text.strip()
    low = s.lower()
    if low in ("true", "false"):
        return low == "true"
    try:
        return int(s.replace("_", "")) if s.lstrip("+-").replace("_", "").isdigit() else float(s)
    except ValueError:
        pass
    if len(s) >= 2 and s[0] == s[-1] and s[0] in "'\"":
        return s[1:-1]
    return s


def _number(text: str, key: str, what: str) -> float:
    value = _scalar(text)
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise InputError(f"--vary {key}", text, f"a finite number for {what} ({_VARY_FORMS})")
    return value


def parse_vary(spec: str) -> tuple[str, list[Any]]:
    """Parse one ``--vary`` specification.

    Parameters
    ----------
    spec : str
        ``KEY=START:STOP:N`` for ``N`` evenly spaced values from ``START`` to ``STOP`` (both
        included), or ``KEY=v1,v2,...`` for an explicit list (one value is allowed).

    Returns
    -------
    key : str
        The dotted config key.
    values : list
        The values, in order. Range values are floats unless START, STOP and every step are
        integers (then ints); :func:`coerce_values` adapts them to the config's type.

    Examples
    --------
    >>> parse_vary("drive.speed_rpm=1000:3000:3")
    ('drive.speed_rpm', [1000, 2000, 3000])
    >>> parse_vary("mesh.kind=coarse,fine")
    ('mesh.kind', ['coarse', 'fine'])
    """
    if "=" not in spec:
        raise InputError("--vary", spec, _VARY_FORMS)
    key, rhs = (s.strip() for s in spec.split("=", 1))
    if not key or any(not part for part in key.split(".")):
        raise InputError("--vary", spec, f"a dotted config key before '=' ({_VARY_FORMS})")
    check_key(key)
    if not rhs:
        raise InputError(f"--vary {key}", rhs, _VARY_FORMS)
    if ":" in rhs and "," not in rhs:
        parts = rhs.split(":")
        if len(parts) != 3:
            raise InputError(f"--vary {key}", rhs, "START:STOP:N with three fields")
        start = _number(parts[0], key, "START")
        stop = _number(parts[1], key, "STOP")
        n = _scalar(parts[2])
        if isinstance(n, bool) or not isinstance(n, int) or n < 1:
            raise InputError(f"--vary {key}", parts[2], "an integer N >= 1 (number of values)")
        if n > MAX_CASES:
            raise InputError(f"--vary {key}", parts[2], f"an integer N from 1 to {MAX_CASES} (cases per sweep)")
        if n == 1:
            if start != stop:
                raise InputError(f"--vary {key}", rhs, "START == STOP when N = 1")
            return key, [start]
        step = (stop - start) / (n - 1)
        if all(isinstance(v, int) for v in (start, stop)) and float(step).is_integer():
            return key, [int(start + i * int(step)) for i in range(n)]
        # end points exact, interior values as numpy.linspace computes them
        values = [start + i * step for i in range(n)]
        values[0], values[-1] = float(start), float(stop)
        return key, [float(v) for v in values]
    if rhs.count(",") >= MAX_CASES:
        raise InputError(f"--vary {key}", f"<{rhs.count(',') + 1} values>", f"at most {MAX_CASES} values")
    values = [_scalar(v) for v in rhs.split(",")]
    if any(isinstance(v, str) and not v for v in values):
        raise InputError(f"--vary {key}", rhs, "a comma-separated list without empty entries")
    return key, values


def coerce_values(key: str, values: Sequence[Any], current: Any) -> list[Any]:
    """Adapt swept ``values`` to the type of the config's ``current`` value at ``key``.

    Integers become floats where the config holds a float; floats with an integral value become
    ints where it holds an int; anything else must match the config's type.
    """
    out = []
    for v in values:
        if isinstance(current, bool):
            ok = isinstance(v, bool)
        elif isinstance(current, int):
            if isinstance(v, float) and v.is_integer():
                v = int(v)
            ok = isinstance(v, int) and not isinstance(v, bool)
        elif isinstance(current, float):
            ok = isinstance(v, (int, float)) and not isinstance(v, bool)
            if ok and isinstance(v, int) and abs(v) > 2**63 - 1:
                raise InputError(key, v, "a finite number (magnitude at most 9.22e+18)")
            v = float(v) if ok else v
        elif isinstance(current, str):
            ok = isinstance(v, str)
        else:
            raise InputError(key, current, "a scalar config value (number, boolean or string) to sweep")
        if not ok:
            raise InputError(
                f"--vary {key}",
                v,
                f"a value of the same type as the config's {current!r} ({type(current).__name__})",
            )
        out.append(v)
    if len(set(map(repr, out))) != len(out):
        raise InputError(f"--vary {key}", out, "distinct values")
    return out


def case_id(index: int, data: Any) -> str:
    """Stable case id: zero-padded index and 8 hex digits of a hash of the case data."""
    blob = json.dumps(data, sort_keys=True, default=repr, separators=(",", ":"))
    return f"{index:04d}-{hashlib.sha1(blob.encode()).hexdigest()[:8]}"


_SEGMENT = re.compile(r"^(?P<name>[^\[\]]+)(?P<indices>(?:\[\d+\])*)$")
#: characters a swept key may hold: config keys are TOML bare keys (letters, digits, _ and -)
#: joined by dots, with [i] for array entries; '/' and the like would also break the names of
#: case directories and sweep.nc variables
_KEY_CHARS = re.compile(r"^[A-Za-z0-9_\-.\[\]]+$")


def check_key(key: str) -> None:
    """InputError unless ``key`` is a dotted config key of bare-key characters (no '/', spaces...)."""
    if not isinstance(key, str) or not _KEY_CHARS.match(key):
        bad = sorted({c for c in str(key) if not _KEY_CHARS.match(c)})
        raise InputError(
            "--vary",
            key,
            "a dotted config key of letters, digits, '_' and '-' with [i] for array entries"
            + (f" (not {' '.join(repr(c) for c in bad)})" if bad else ""),
        )


def _split_key(key: str) -> list[str | int]:
    """``"loads[0].duration"`` -> ``["loads", 0, "duration"]``."""
    path: list[str | int] = []
    for part in key.split("."):
        m = _SEGMENT.match(part)
        if not m:
            raise InputError("--vary", key, "a dotted config key; NAME[i] selects array entry i")
        path.append(m["name"])
        path += [int(i) for i in re.findall(r"\[(\d+)\]", m["indices"])]
    return path


def _walk(node: Any, key: str, path: list[str | int]) -> Any:
    for step in path:
        if isinstance(step, int):
            if not isinstance(node, (list, tuple)) or step >= len(node):
                raise InputError(key, "<missing>", f"an array with an entry [{step}] in the config")
            node = node[step]
        else:
            if not isinstance(node, Mapping) or step not in node:
                raise InputError(key, "<missing>", "a key present in the config")
            node = node[step]
    return node


def _current(base: Mapping[str, Any], key: str) -> tuple[Any, int]:
    """The config's value at ``key`` and the array length to fill (0: set the value itself;
    n: a scalar swept value is broadcast to all n entries of an array of numbers)."""
    path = _split_key(key)
    value = _walk(base, key, path)  # InputError naming the key when absent
    if (
        not isinstance(path[-1], int)
        and isinstance(value, (list, tuple))
        and value
        and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value)
    ):
        return value[0], len(value)
    return value, 0


def _assign(data: dict[str, Any], key: str, value: Any, fill: int) -> dict[str, Any]:
    """A deep copy of ``data`` with ``value`` (or ``[value] * fill``) at ``key``."""
    path = _split_key(key)
    out = copy.deepcopy(data)
    parent = _walk(out, key, path[:-1])
    if isinstance(parent, tuple):  # a tuple inside the config: rebuild it as a list
        parent = list(parent)
        _walk(out, key, path[:-2])[path[-2]] = parent
    parent[path[-1]] = [value] * fill if fill else value
    return out


def _insert(base: Mapping[str, Any], key: str, value: Any) -> dict[str, Any]:
    """A copy of ``base`` with ``value`` at the dotted ``key`` (array indices stripped),
    creating missing tables."""
    out = copy.deepcopy(dict(base))
    names = [p for p in _split_key(key) if isinstance(p, str)]
    node = out
    for name in names[:-1]:
        child = node.setdefault(name, {})
        if not isinstance(child, dict):
            raise InputError(key, child, f"a path through tables, but {name!r} is a value")
        node = child
    node[names[-1]] = copy.deepcopy(value)
    return out


def grid_cases(
    base: Mapping[str, Any],
    vary: Mapping[str, Sequence[Any]],
    defaults: Callable[[str], Any] | None = None,
) -> list[Case]:
    """Cases of the Cartesian product of ``vary`` applied to the config ``base``.

    Parameters
    ----------
    base : dict
        Parsed TOML config (may carry the top-level ``domain`` key).
    vary : dict
        Dotted key -> list of values; the first key varies slowest. ``name[i]`` selects entry
        ``i`` of an array (``loads[0].duration``, ``operation.speed_rpm[1]``); a key whose value
        is an array of numbers sets every entry to the value (both gears'
        ``operation.speed_rpm``).
    defaults : callable, optional
        ``defaults(key)`` -> the schema default of a key not written in ``base`` (raising
        InputError for a key the schema does not have); without it, every varied key must be
        in ``base``.

    Raises
    ------
    InputError
        A key not present in ``base`` (named in the message), the ``domain`` key, an empty
        list, or values of the wrong type.
    """
    if not vary:
        raise InputError("--vary", "<none>", "at least one KEY=... to sweep")
    n_cases = math.prod(len(v) for v in vary.values())
    if n_cases > MAX_CASES:
        raise InputError(
            "--vary", f"<{' x '.join(str(len(v)) for v in vary.values())} grid>", f"at most {MAX_CASES} cases"
        )
    checked: dict[str, list[Any]] = {}
    fills: dict[str, int] = {}
    for key, values in vary.items():
        if _split_key(key) == ["domain"]:
            raise InputError("--vary domain", values, "a key inside the domain's config, not 'domain'")
        if defaults is not None:
            base_key = key.split("[", 1)[0]
            try:
                _walk(base, key, _split_key(base_key))
            except InputError:
                base = _insert(base, base_key, defaults(base_key))
        current, fills[key] = _current(base, key)
        if not values:
            raise InputError(f"--vary {key}", values, "at least one value")
        checked[key] = coerce_values(key, values, current)
    cases = []
    for index, combo in enumerate(itertools.product(*checked.values())):
        data = dict(base)
        for key, value in zip(checked, combo, strict=True):
            data = _assign(data, key, value, fills[key])
        cases.append(Case(case_id(index, data), dict(zip(checked, combo, strict=True)), data))
    return cases


def as_cases(cases: Iterable[Case | Mapping[str, Any]]) -> list[Case]:
    """Normalise ``cases``: :class:`Case` objects pass through; a plain mapping becomes a case
    whose ``params`` and ``data`` are that mapping (its scalar entries are the coordinates)."""
    out = []
    for index, c in enumerate(cases):
        if isinstance(c, Case):
            out.append(c)
        elif isinstance(c, Mapping):
            params = {k: v for k, v in c.items() if isinstance(v, (int, float, str, bool))}
            out.append(Case(case_id(index, dict(c)), params, dict(c)))
        else:
            raise TypeError(f"a sweep case must be a Case or a mapping, not {type(c).__name__}")
    ids = [c.id for c in out]
    if len(set(ids)) != len(ids):
        dup = next(i for i in ids if ids.count(i) > 1)
        raise InputError("cases", dup, "unique case ids")
    return out
