"""Template and config reference completeness: every key of every schema, walked here from the
dataclasses themselves (not from the generator's own key list), including the keys inside arrays
of tables (``[[shaft]]``) and tables of named tables (``[material.<name>]``)."""

import dataclasses
import importlib
import re
import tomllib
import types
import typing
from typing import get_args, get_origin, get_type_hints

import pytest

from rotaflex.cli import config_reference, domain_template
from rotaflex.core.domains import CASES, COMMANDS, command_module


def _inner(tp):
    """``(kind, dataclass)`` for a table, an optional table, an array or a map of tables."""
    origin, args = get_origin(tp), get_args(tp)
    if dataclasses.is_dataclass(tp):
        return "table", tp
    if origin in (typing.Union, types.UnionType):
        dcs = [a for a in args if dataclasses.is_dataclass(a)]
        if len(dcs) == 1 and len(args) == 2:
            return "table", dcs[0]
    if origin is tuple and len(args) == 2 and args[1] is Ellipsis and dataclasses.is_dataclass(args[0]):
        return "array", args[0]
    if origin is dict and dataclasses.is_dataclass(args[1]):
        return "map", args[1]
    return None


def leaves(schema, path=()):
    """``(parents, name)`` of every value key; a parent is ``(kind, name)``."""
    hints = get_type_hints(schema)
    for f in dataclasses.fields(schema):
        if not f.init:
            continue
        sub = _inner(hints[f.name])
        if sub is None:
            yield path, f.name
        else:
            yield from leaves(sub[1], (*path, (sub[0], f.name)))


def _header(table, parents):
    names = ([table] if table else []) + [n for _, n in parents]
    path = ".".join(names)
    kind = parents[-1][0] if parents else "table"
    return {"table": f"[{path}]", "array": f"[[{path}]]", "map": f"[{path}.<name>]"}[kind]


def _dotted(parents, name):
    text = ""
    for kind, n in parents:
        text += n + {"table": ".", "array": "[].", "map": ".<name>."}[kind]
    return text + name


def _verbs():
    for domain in CASES:
        for verb in ["simulate", *COMMANDS.get(domain, {})]:
            yield domain, verb


def _roots(domain, verb):
    module = importlib.import_module(CASES[domain]) if verb == "simulate" else command_module(domain, verb)
    roots = [("", module.SCHEMA)] if getattr(module, "SCHEMA", None) is not None else []
    return roots + list(getattr(module, "ALTERNATIVES", {}).items())


def _sections(text):
    """Header (comment marks stripped) -> the key names written under it (commented or not)."""
    out, current = {"": set()}, ""
    for line in text.splitlines():
        bare = line.lstrip("# ").rstrip()
        # a header is the whole line (an optional table says so after it); "[kg] number" is a unit
        m = re.fullmatch(r"(\[\[?[^\]\s]+\]\]?)(   \(optional table.*)?", bare)
        if m:
            current = m.group(1)
            out.setdefault(current, set())
        else:
            m = re.match(r"^(\w+) = ", bare)
            if m:
                out[current].add(m.group(1))
    return out


@pytest.mark.parametrize(("domain", "verb"), list(_verbs()))
def test_every_schema_key_is_in_the_template_under_its_table(domain, verb):
    roots = _roots(domain, verb)
    if not roots:
        pytest.skip(f"{domain} {verb} has no SCHEMA")  # reported, not silent
    text = domain_template(domain, verb)
    tomllib.loads(text)  # and it still loads
    sections = _sections(text)
    missing = []
    for table, schema in roots:
        for parents, name in leaves(schema):
            where = _header(table, parents) if (table or parents) else ""
            if name not in sections.get(where, set()):
                missing.append(f"{where or '<top>'} {name}")
    assert not missing, missing[:10]
    assert "Masss" not in text and "numberss" not in text


def test_every_schema_key_is_in_the_config_reference():
    text = config_reference()
    missing = []
    for domain, verb in _verbs():
        for table, schema in _roots(domain, verb):
            prefix = f"{table}." if table else ""
            for parents, name in leaves(schema):
                key = prefix + _dotted(parents, name)
                if f"| `{key}` |" not in text:
                    missing.append(f"{domain} {verb}: {key}")
    assert not missing, missing[:10]


def test_arrays_of_tables_are_shown_with_their_keys():
    text = domain_template("rotor", "modal")
    i = text.index("# [[shaft]]")
    assert "# outer_diameter = <required>" in text[i : i + 400]
    assert "array of Shaft tables" in text and "at least one required" in text
    assert "# [material.<name>]" in text
    assert "| `shaft[].outer_diameter` | `required` | m |" in config_reference()


def test_a_mistyped_sweep_key_gets_a_did_you_mean():
    from rotaflex.core.errors import InputError
    from rotaflex.core.schema import default_of
    from rotaflex.rotor.model import RotorModel

    with pytest.raises(InputError, match=r"did you mean 'motion\.spin_speed'\?"):
        default_of(RotorModel, "motion.spin_sped")
    with pytest.raises(InputError) as info:
        default_of(RotorModel, "zzz.qqq")
    assert "did you mean" not in str(info.value)
