"""Typed, validated configuration: frozen dataclasses filled from TOML tables.

A model is a frozen dataclass whose fields are declared with :func:`param`, which carries the
unit and the allowed range. :func:`from_mapping` builds it from a plain mapping (a parsed TOML
table), rejecting unknown keys, wrong types and out-of-range values with an :class:`InputError`
that names the dotted field, the value and what is allowed.
"""

from __future__ import annotations

import copy
import dataclasses
import difflib
import math
import tomllib
import types
import typing
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, Literal, TypeVar, get_args, get_origin, get_type_hints

from rotaflex.core.errors import InputError
from rotaflex.core.limits import require

T = TypeVar("T")
_MISSING = dataclasses.MISSING


def param(
    default: Any = _MISSING,
    *,
    unit: str | None = None,
    gt: float | None = None,
    ge: float | None = None,
    lt: float | None = None,
    le: float | None = None,
    doc: str = "",
) -> Any:
    """Declare a dataclass field with a unit and an allowed range.

    Parameters
    ----------
    default : object, optional
        Default value; a list/dict default is copied per instance. Omit for a required field.
    unit : str, optional
        SI unit of the value, shown in error messages and result attributes.
    gt, ge, lt, le : float, optional
        Strict/inclusive bounds applied to numbers (element-wise for sequences).
    doc : str
        One-line description.
    """
    meta = {"unit": unit, "gt": gt, "ge": ge, "lt": lt, "le": le, "doc": doc}
    if isinstance(default, (list, dict)):
        return dataclasses.field(default_factory=lambda: copy.deepcopy(default), metadata=meta)
    return dataclasses.field(default=default, metadata=meta)


def _range_text(meta: Mapping[str, Any]) -> str:
    parts = []
    for key, op in (("gt", ">"), ("ge", ">="), ("lt", "<"), ("le", "<=")):
        if meta.get(key) is not None:
            parts.append(f"{op} {meta[key]:g}")
    unit = f" [{meta['unit']}]" if meta.get("unit") else ""
    return (" " + " and ".join(parts) if parts else "") + unit


#: magnitude above which an integer in a config is refused (int64 range; a float cannot hold more
#: than ~1.8e308 and a 400-digit integer is a typing mistake, not a parameter)
INT_LIMIT = 2**63 - 1


#: magnitudes a number of a machine's config can take in SI units (other than 0; the upper
#: bound also for numbers without a unit, such as direction components): beyond, the value is a
#: typing slip, and its square or reciprocal leaves the floats (a slew of 1e-300 s divided by
#: zero, an appendage 1e300 m thick overflowed)
SI_MIN, SI_MAX = 1e-30, 1e30
SI_WHY = " (1e30 kg is half the Sun's mass, 1e-30 s a millionth of the time light takes to cross a proton)"


def _check_range(x: float, meta: Mapping[str, Any], where: str, kind: str) -> None:
    ok = (
        (meta.get("gt") is None or x > meta["gt"])
        and (meta.get("ge") is None or x >= meta["ge"])
        and (meta.get("lt") is None or x < meta["lt"])
        and (meta.get("le") is None or x <= meta["le"])
    )
    if not ok:
        raise InputError(where, x, f"{kind}{_range_text(meta)}")


def _convert(value: Any, tp: Any, meta: Mapping[str, Any], where: str) -> Any:
    origin, args = get_origin(tp), get_args(tp)
    if origin in (typing.Union, types.UnionType):
        inner = [a for a in args if a is not type(None)]
        if value is None:
            return None
        errors = []
        for alt in inner:  # first alternative that accepts the value (e.g. [Fx, Fy] or "static")
            try:
                return _convert(value, alt, meta, where)
            except InputError as err:
                errors.append(err)
        if len(errors) == 1:
            raise errors[0]
        raise InputError(where, value, " or ".join(e.allowed for e in errors))
    if origin is Literal:
        if value not in args:
            raise InputError(where, value, "one of " + ", ".join(repr(a) for a in args))
        return value
    if tp is float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise InputError(where, value, f"a number{_range_text(meta)}")
        if isinstance(value, int) and abs(value) > INT_LIMIT:
            raise InputError(where, value, f"a finite number{_range_text(meta)} (magnitude at most {INT_LIMIT:.3g})")
        if not math.isfinite(value):
            raise InputError(where, value, f"a finite number{_range_text(meta)}")
        _check_range(value, meta, where, "a number")
        low = SI_MIN if meta.get("unit") else 0.0  # a tolerance without a unit may be tiny
        if value != 0 and not low <= abs(value) <= SI_MAX:
            span = f"{SI_MIN:g} to {SI_MAX:g}" if low else f"at most {SI_MAX:g}"
            raise InputError(where, value, f"a number{_range_text(meta)} of magnitude {span}{SI_WHY}")
        return float(value)
    if tp is int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise InputError(where, value, f"an integer{_range_text(meta)}")
        if abs(value) > INT_LIMIT:
            raise InputError(where, value, f"an integer{_range_text(meta)} (magnitude at most {INT_LIMIT})")
        _check_range(value, meta, where, "an integer")
        return value
    if tp is bool:
        if not isinstance(value, bool):
            raise InputError(where, value, "true or false")
        return value
    if tp is str:
        if not isinstance(value, str):
            raise InputError(where, value, "a string")
        return value
    if origin is tuple:
        if isinstance(value, (str, bytes)) or not isinstance(value, Sequence):
            raise InputError(where, value, "an array")
        if len(args) == 2 and args[1] is Ellipsis:
            types_ = [args[0]] * len(value)
        else:
            if len(value) != len(args):
                raise InputError(where, value, f"an array of {len(args)} entries")
            types_ = list(args)
        return tuple(_convert(v, t, meta, f"{where}[{i}]") for i, (v, t) in enumerate(zip(value, types_, strict=False)))
    if origin is dict:
        if not isinstance(value, Mapping):
            raise InputError(where, value, "a table")
        return {str(k): _convert(v, args[1], meta, f"{where}.{k}") for k, v in value.items()}
    if dataclasses.is_dataclass(tp):
        return from_mapping(tp, value, where)
    raise TypeError(f"unsupported config type {tp!r} at {where}")  # programming error


def from_mapping(cls: type[T], data: Any, where: str = "") -> T:
    """Build the frozen dataclass ``cls`` from a mapping, validating every field.

    Parameters
    ----------
    cls : type
        A dataclass whose fields were declared with :func:`param` (plain fields work too).
    data : Mapping
        Parsed TOML table.
    where : str
        Dotted path of ``data`` inside the whole config, used in error messages.

    Raises
    ------
    InputError
        Unknown key, missing required key, wrong type or out-of-range value.
    """
    if not isinstance(data, Mapping):
        raise InputError(where or "config", data, "a table")
    hints = get_type_hints(cls)
    fields = {f.name: f for f in dataclasses.fields(cls) if f.init}
    prefix = f"{where}." if where else ""
    for key in data:
        if key not in fields:
            raise unknown_key(f"{prefix}{key}", data[key], list(fields))
    kwargs = {}
    for name, f in fields.items():
        if name in data:
            kwargs[name] = _convert(data[name], hints[name], f.metadata, f"{prefix}{name}")
        elif f.default is _MISSING and f.default_factory is _MISSING:
            raise InputError(f"{prefix}{name}", "<missing>", f"a value{_range_text(f.metadata)} (required)")
    try:
        return cls(**kwargs)
    except InputError as exc:  # checks in __post_init__ name keys relative to this table
        raise exc.relocated(where) from None


def unknown_key(field: str, value: Any, allowed: Sequence[str]) -> InputError:
    """The error for a key that is not in ``allowed``: the closest allowed key as a "did you
    mean" (as the CLI does for a mistyped command), then the full list.

    Parameters
    ----------
    field : str
        Dotted path of the unknown key as typed, e.g. ``"shaft[0].outer_diamter"``.
    value : object
        Its value as typed.
    allowed : sequence of str
        The keys allowed at that level.
    """
    name = str(field).rsplit(".", 1)[-1]
    close = difflib.get_close_matches(name, list(allowed), n=1, cutoff=0.6)
    hint = f"did you mean {close[0]!r}? " if close else ""
    return InputError(field, value, f"no such key; {hint}allowed keys: " + ", ".join(allowed))


def to_mapping(obj: Any) -> dict[str, Any]:
    """Plain-data view of a config dataclass (for provenance and sweeps)."""
    return dataclasses.asdict(obj)


#: largest config file read [bytes]; a case file is a few kB (this also bounds ``/dev/zero``)
MAX_CONFIG_BYTES = 4 * 2**20


def load_toml(path: str | Path, field: str = "config", typed: str | None = None) -> dict[str, Any]:
    """Read a TOML file (at most :data:`MAX_CONFIG_BYTES`), every failure an :class:`InputError`.

    Refused with the file named: missing, a directory, unreadable, too large (or endless, like
    ``/dev/zero``), not UTF-8, not valid TOML, nested too deeply. ``field`` is the key that named
    the file (``"gear_mesh[0].pair_file"``), ``"config"`` for the file given on the command line;
    ``typed`` the path as written there when ``path`` was resolved from it.
    """
    text_path = str(path) if typed is None else typed
    path = Path(path)
    try:
        with path.open("rb") as fh:
            raw = fh.read(MAX_CONFIG_BYTES + 1)
    except FileNotFoundError:
        where = "" if str(path) == text_path else f" (looked for {path})"
        raise InputError(field, text_path, f"an existing TOML file{where}") from None
    except IsADirectoryError:
        raise InputError(field, text_path, "a TOML file, not a directory") from None
    except OSError as exc:
        raise InputError(field, text_path, f"a readable TOML file ({exc.strerror})") from None
    if len(raw) > MAX_CONFIG_BYTES:
        raise InputError(field, text_path, f"a TOML file of at most {MAX_CONFIG_BYTES // 2**20} MiB")
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise InputError(field, text_path, f"a UTF-8 text file (byte {exc.start} is not UTF-8)") from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(field, text_path, f"valid TOML ({exc})") from None
    except RecursionError:
        raise InputError(field, text_path, "TOML nested less deeply (arrays/tables nested too deep)") from None


def budget(field: str, value: Any, estimate: float, limit: float, what: str) -> None:
    """Refuse a value whose estimated cost exceeds a budget, before anything is allocated.

    Parameters
    ----------
    field : str
        Dotted config field to blame (the one the user would change).
    value : object
        Its value as typed.
    estimate : float
        Estimated cost (samples, steps, cases, bytes...) of running with it.
    limit : float
        The largest cost accepted.
    what : str
        Unit of the estimate in words, e.g. ``"output samples"``.
    """
    require(field, value, estimate, limit, what)


def set_dotted(data: dict[str, Any], key: str, value: Any) -> dict[str, Any]:
    """Return a deep copy of ``data`` with the dotted ``key`` (e.g. ``"drive.speed_rpm"``) set."""
    out = copy.deepcopy(data)
    node = out
    parts = key.split(".")
    for part in parts[:-1]:
        child = node.setdefault(part, {})
        if not isinstance(child, dict):
            raise InputError(key, value, f"a path through tables, but {part!r} is a value")
        node = child
    node[parts[-1]] = value
    return out


def get_dotted(data: Mapping[str, Any], key: str) -> Any:
    """Value at a dotted ``key``; raises :class:`InputError` when absent."""
    node: Any = data
    for part in key.split("."):
        if not isinstance(node, Mapping) or part not in node:
            raise InputError(key, "<missing>", "a key present in the config")
        node = node[part]
    return node
