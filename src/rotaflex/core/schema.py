"""Read a config schema (the frozen dataclasses of a domain): defaults of any key, a commented
TOML template, and the Markdown config reference.

Everything here is generated from the dataclass fields and their :func:`~rotaflex.core.config.param`
metadata (unit, bounds, doc), so the template and the reference cannot drift from the code.
"""

from __future__ import annotations

import dataclasses
import difflib
import types
import typing
from collections.abc import Iterator
from typing import Any, Literal, get_args, get_origin, get_type_hints

from rotaflex.core.errors import InputError

_MISSING = dataclasses.MISSING


@dataclasses.dataclass
class Entry:
    """One key of a schema."""

    key: str  # dotted path
    type: str  # in words
    default: Any  # plain data, or _MISSING when required
    unit: str
    allowed: str
    doc: str
    table: bool  # a nested table (dataclass), an array of tables or a table of tables
    kind: str = "value"  # "value", "table", "array" (``[[key]]``) or "map" (``[key.<name>]``)


#: the dotted-key part that stands for "each entry" of an array of tables / a table of tables
EACH = {"array": "[]", "map": ".<name>"}


def _nested(tp: Any) -> type | None:
    """The dataclass inside ``tp`` (``X`` or ``X | None``), or None."""
    if dataclasses.is_dataclass(tp):
        return tp
    if get_origin(tp) in (typing.Union, types.UnionType):
        inner = [a for a in get_args(tp) if a is not type(None)]
        if len(inner) == 1 and dataclasses.is_dataclass(inner[0]):
            return inner[0]
    return None


def _collection(tp: Any) -> tuple[str, type] | None:
    """``("array", X)`` for ``tuple[X, ...]`` and ``("map", X)`` for ``dict[str, X]`` with a
    dataclass ``X`` (a TOML array of tables / a table of named tables), else None."""
    origin, args = get_origin(tp), get_args(tp)
    if origin is tuple and len(args) == 2 and args[1] is Ellipsis and dataclasses.is_dataclass(args[0]):
        return "array", args[0]
    if origin is dict and len(args) == 2 and dataclasses.is_dataclass(args[1]):
        return "map", args[1]
    return None


_WORDS = {float: "number", int: "integer", bool: "boolean", str: "string"}


def _type_text(tp: Any, plural: bool = False) -> str:
    """``tp`` in words: ``"array of 3 numbers"``, ``"arrays of 3 numbers"`` with ``plural``."""
    origin, args = get_origin(tp), get_args(tp)
    s = "s" if plural else ""
    if origin in (typing.Union, types.UnionType):
        inner = [a for a in args if a is not type(None)]
        text = " or ".join(_type_text(a, plural) for a in inner)
        return text + (" (optional)" if len(inner) < len(args) else "")
    if origin is Literal:
        return ("values, each " if plural else "") + "one of " + ", ".join(repr(a) for a in args)
    if origin is tuple:
        if len(args) == 2 and args[1] is Ellipsis:
            return f"array{s} of {_type_text(args[0], True)}"
        return f"array{s} of {len(args)} {_type_text(args[0], True)}"
    if origin is dict:
        return f"table{s} of {_type_text(args[1], True)}"
    if dataclasses.is_dataclass(tp):
        return f"{tp.__name__} table{s}"
    return _WORDS.get(tp, getattr(tp, "__name__", str(tp))) + s


def _bounds(meta) -> str:
    parts = []
    for key, op in (("gt", ">"), ("ge", ">="), ("lt", "<"), ("le", "<=")):
        if meta.get(key) is not None:
            parts.append(f"{op} {meta[key]:g}")
    return " and ".join(parts)


def _plain(value: Any) -> Any:
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {f.name: _plain(getattr(value, f.name)) for f in dataclasses.fields(value) if f.init}
    if isinstance(value, (tuple, list)):
        return [_plain(v) for v in value]
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    return value


def _default(f: dataclasses.Field) -> Any:
    if f.default is not _MISSING:
        return _plain(f.default)
    if f.default_factory is not _MISSING:
        return _plain(f.default_factory())
    return _MISSING


def entries(schema: type, prefix: str = "") -> Iterator[Entry]:
    """Every key of ``schema``, tables before their keys, in declaration order."""
    hints = get_type_hints(schema)
    for f in dataclasses.fields(schema):
        if not f.init:
            continue
        key = f"{prefix}{f.name}"
        tp = hints[f.name]
        meta = f.metadata
        doc = meta.get("doc", "") or ""
        nested = _nested(tp)
        if nested is not None:
            yield Entry(key, "table", _default(f), "", "", doc or title_of(nested), True, "table")
            yield from entries(nested, key + ".")
            continue
        coll = _collection(tp)
        if coll is not None:  # [[key]] or [key.<name>]: the keys of one entry follow
            kind, item = coll
            yield Entry(key, _type_text(tp), _default(f), "", _type_text(tp), doc or title_of(item), True, kind)
            yield from entries(item, key + EACH[kind] + ".")
            continue
        allowed = _type_text(tp)
        b = _bounds(meta)
        if b:
            allowed += f", {b}"
        yield Entry(key, _type_text(tp), _default(f), meta.get("unit") or "", allowed, doc, False)


def default_of(schema: type, dotted: str) -> Any:
    """The default value of the dotted key ``dotted`` in ``schema`` (as plain data).

    Raises
    ------
    InputError
        No such key, or the key is required (has no default).
    """
    # keys inside arrays/tables of tables are not addressed here (a sweep names an entry by
    # index, and the entry's default is the array's)
    known = {e.key: e for e in entries(schema) if not any(m in e.key for m in EACH.values())}
    base = dotted.split("[", 1)[0]
    if base not in known:
        # the same leaf in another table first (``spin_speed`` -> ``motion.spin_speed``), else the
        # closest spelling (``motion.spin_sped``), as for unknown keys in a config file
        close = [k for k in known if k.rsplit(".", 1)[-1] == base.rsplit(".", 1)[-1]]
        close = close or difflib.get_close_matches(base, list(known), n=1, cutoff=0.6)
        hint = f"; did you mean {close[0]!r}?" if close else ""
        raise InputError(dotted, "<missing>", f"a key of the config schema{hint}")
    e = known[base]
    if e.default is _MISSING:
        raise InputError(dotted, "<missing>", "a value in the base config (this key has no default)")
    return e.default


def _toml(value: Any) -> str:
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    return str(value)


def _toml_order(ents: list[Entry]) -> list[Entry]:
    """Entries in an order TOML reads back: in every table its own keys before its sub-tables
    (a key written after a sub-table's header would belong to the sub-table)."""
    children: dict[str, list[Entry]] = {}
    for e in ents:
        children.setdefault(e.key.rpartition(".")[0], []).append(e)
    out: list[Entry] = []

    def emit(parent: str) -> None:
        kids = children.get(parent, [])
        out.extend(e for e in kids if not e.table)
        for e in kids:
            if e.table:
                out.append(e)
                emit(_children(e))

    emit("")
    return out


def _children(e: Entry) -> str:
    """The dotted prefix (without the final dot) of the keys under the table entry ``e``."""
    return e.key + EACH.get(e.kind, "")


def _header(e: Entry, prefix: str) -> str:
    """The TOML header of the table entry ``e``: ``[a.b]``, ``[[a.b]]`` or ``[a.b.<name>]``
    (inside an array of tables a sub-table belongs to the last entry: ``[a.b]``)."""
    path = prefix + e.key.replace("[]", "")
    if e.kind == "array":
        return f"[[{path}]]"
    if e.kind == "map":
        return f"[{path}.<name>]"
    return f"[{path}]"


def _info(e: Entry) -> str:
    return " ".join(x for x in (f"[{e.unit}]" if e.unit else "", e.allowed + ".", e.doc) if x)


def _collection_note(e: Entry, prefix: str) -> str:
    one = f"one {_header(e, prefix)} table per " + ("entry" if e.kind == "array" else "name")
    if e.default is _MISSING:
        state = "at least one required"
    elif not e.default:
        state = "none by default"
    else:
        state = f"{len(e.default)} by default"
    return f"# {e.allowed}: {one}, {state}; each has the keys below. {e.doc}".rstrip()


def title_of(schema: type) -> str:
    """First line of the schema's docstring; the class name where the docstring is only the
    signature that ``dataclasses`` writes for an undocumented class."""
    doc = (schema.__doc__ or "").strip().splitlines()
    if not doc or doc[0].startswith(schema.__name__ + "("):
        return schema.__name__
    return doc[0]


def template(schema: type, domain: str, *, table: str = "", verb: str = "") -> str:
    """A commented TOML config with every key at its default, its unit and allowed values.

    Keys without a default are written commented out with ``<required>``; optional keys whose
    default is "not set" are commented out too, so the file loads as it is.
    """
    command = f"{domain} {verb}" if verb else domain
    lines = [
        f"# rotaflex {command} case: every key with its default, unit and allowed values.",
        f"# {title_of(schema)}",
        f"# Generated from the schema (rotaflex {domain} template"
        + (f" --verb {verb}" if verb else "")
        + "); delete what you do not change.",
        "",
        f'domain = "{domain}"',
    ] + ([f'verb = "{verb}"'] if verb else [])
    prefix = f"{table}." if table else ""
    if table:
        lines += ["", f"[{table}]"]
    # an optional table (default None, e.g. an alternative layout) and the entries of an array
    # of tables or a table of tables are written commented out, with everything under them
    off: list[str] = []
    for e in _toml_order(list(entries(schema))):
        if any(e.key.startswith(o + ".") for o in off):
            if e.table:
                lines += ["", f"# {_header(e, prefix)}"]
                lines += [_collection_note(e, prefix)] if e.kind in EACH else []
                if e.kind in EACH:
                    off.append(_children(e))
            else:
                val = "<required>" if e.default is _MISSING else _toml(e.default) or "  (not set by default)"
                lines += [f"# {_info(e)}", f"# {e.key.rsplit('.', 1)[-1]} = {val}"]
            continue
        if e.kind in EACH:
            off.append(_children(e))
            lines += ["", _collection_note(e, prefix), f"# {_header(e, prefix)}"]
            continue
        if e.table:
            if e.default is None:
                off.append(e.key)
                lines += ["", f"# {_header(e, prefix)}   (optional table, not set by default)"]
                lines += [f"# {e.doc}"] if e.doc else []
                continue
            lines += ["", _header(e, prefix)] + ([f"# {e.doc}"] if e.doc else [])
            continue
        name = e.key.rsplit(".", 1)[-1]
        lines.append(f"# {_info(e)}")
        if e.default is _MISSING:
            lines.append(f"# {name} = <required>")
        elif e.default is None:
            lines.append(f"# {name} =   (not set by default)")
        else:
            lines.append(f"{name} = {_toml(e.default)}")
    return "\n".join(lines).replace("\n\n\n", "\n\n") + "\n"


def reference_markdown(schemas: dict[str, list[tuple[str, str, type]]]) -> str:
    """The config reference: one table of keys per domain, per alternative root table and per
    verb with its own schema; ``schemas[domain]`` lists ``(heading, table, schema)``."""
    out = [
        "# Configuration reference",
        "",
        "Generated from the code by `rotaflex docs config-reference` (do not edit by hand; a test checks",
        "that this file is up to date). `rotaflex <domain> template [--verb VERB]` prints the same keys as",
        "a commented TOML file. Values are SI unless the key's name says otherwise (`speed_rpm`,",
        "`span_deg`). An array of tables (`[[shaft]]`, one table per entry) lists its keys as",
        "`shaft[].key`; a table of named tables (`[material.<name>]`) as `material.<name>.key`.",
        "",
    ]
    for domain, roots in schemas.items():
        out += [f"## {domain}", ""]
        for heading, table, schema in roots:
            out += [f"### {heading}: {title_of(schema)}", ""]
            out += ["| key | default | unit | allowed | description |", "|---|---|---|---|---|"]
            prefix = f"{table}." if table else ""
            for e in entries(schema):
                if e.table and e.kind not in EACH:
                    continue
                if e.table:  # an array of tables / a table of tables: its keys follow
                    if e.default is _MISSING:
                        default = "`required`"
                    else:
                        empty = "`[]`" if e.kind == "array" else "`{}`"
                        default = f"{len(e.default)} entries" if e.default else empty
                    cells = [f"`{prefix}{e.key}`", default, "", e.allowed, e.doc]
                    out.append("| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |")
                    continue
                default = (
                    "required" if e.default is _MISSING else ("not set" if e.default is None else _toml(e.default))
                )
                cells = [f"`{prefix}{e.key}`", f"`{default}`", e.unit, e.allowed, e.doc]
                out.append("| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |")
            out.append("")
    return "\n".join(out)
