"""The pair tables of a gear config before a verb reads them: named presets and old layouts.

Every gear verb (``simulate``, ``static``, ``steady``) reads the pair as ``[pinion]``/``[wheel]``
(:class:`~rotaflex.gear.pair.drawing.GearSpec`). Two things happen to a parsed TOML mapping first,
here and nowhere else:

* ``pair = "lee_jang"`` (top-level key) is replaced by the preset's ``[pinion]``, ``[wheel]`` and
  ``[operation]`` tables (:data:`PAIR_PRESETS`; the data is :mod:`rotaflex.gear.pair.paper`'s).
  Keys written in the file override the preset's one by one; a table inside a gear
  (``material``, ``blank``, ``tip_relief``, ``root_relief``) replaces the preset's whole (a
  ``material = { name = "aluminium" }`` is aluminium, not the paper's steel values under a new
  name). An ``[operation]`` key written for the speed (``speed_rpm``, ``driver_speed_rpm``) or the
  torque (``torque``) drops the preset's keys of the same quantity (``torque`` takes the
  preset's ``torque_on`` with it).
* A ``[gear]`` table the verb does not read (``gear static`` reads none; ``gear simulate`` the
  paper's one-gear-for-both layout; ``gear steady`` its two-gear ``teeth = [z1, z2]`` layout)
  is refused with one line saying what to write instead (:func:`refuse_other_layout`).
"""

from __future__ import annotations

from rotaflex.core.errors import InputError
from rotaflex.gear.pair import paper

__all__ = ["PAIR_PRESETS", "refuse_other_layout", "with_pair_preset"]

#: named pairs: name -> function(verb) giving the ``pinion``/``wheel``/``operation`` tables
PAIR_PRESETS = {"lee_jang": paper.pair_tables}

#: [operation] keys that give the same quantity: a key of a group written in the file drops the
#: preset's keys of that group
_OPERATION_GROUPS = ({"speed_rpm", "driver_speed_rpm"}, {"torque", "torque_on"})

#: what to write instead of a [gear] table, for any verb
INSTEAD = 'write [pinion]/[wheel] (see rotaflex gear template --verb {verb}) or pair = "lee_jang"'


def _operation(preset: dict, given: dict) -> dict:
    out = dict(preset)
    for group in _OPERATION_GROUPS:
        if "torque" in group and "torque" not in given:
            continue  # torque_on alone moves the preset's torque to the other gear
        if group & set(given):
            for key in group:
                out.pop(key, None)
    out.update(given)
    return out


def with_pair_preset(config: dict, verb: str) -> dict:
    """``config`` with a ``pair = NAME`` preset expanded into its tables (module docstring);
    ``config`` itself when it names none. ``verb`` is ``"simulate"``, ``"static"`` or
    ``"steady"`` (the preset's ``[operation]`` keys in that verb's spelling)."""
    if "pair" not in config:
        return config
    name = config["pair"]
    if name not in PAIR_PRESETS:
        raise InputError("pair", name, "one of " + ", ".join(repr(k) for k in PAIR_PRESETS) + " (a named gear pair)")
    for key in ("gear", "material", "disk_inertia"):
        if key in config:
            raise InputError(
                key,
                f"a [{key}] table" if isinstance(config[key], dict) else config[key],
                f'omitted with pair = "{name}" (change the preset\'s gears in [pinion]/[wheel])',
            )
    out = {k: v for k, v in config.items() if k != "pair"}
    for table, values in PAIR_PRESETS[name](verb).items():
        given = config.get(table)
        if given is None:
            out[table] = values
        elif isinstance(given, dict):
            out[table] = _operation(values, given) if table == "operation" else {**values, **given}
        # another value: the verb's schema names it
    return out


def _is_list(value) -> bool:
    return isinstance(value, (list, tuple))


def refuse_other_layout(config: dict, verb: str) -> None:
    """Raise one InputError saying what to write instead when ``config`` carries a ``[gear]``
    layout that ``verb`` does not read (the pre-``[pinion]/[wheel]`` schemas of the other verbs).

    ``gear simulate`` reads ``[gear]`` as the paper's two identical gears (``teeth`` an integer,
    ``[material]``, ``disk_inertia``); ``gear steady`` as two gears (``teeth = [z1, z2]``, the
    material keys inside ``[gear]``); ``gear static`` reads no ``[gear]``.
    """
    gear = config.get("gear")
    instead = INSTEAD.format(verb=verb)
    if verb == "static":
        for key in ("gear", "material", "disk_inertia"):
            if key in config:
                value = f"a [{key}] table" if isinstance(config[key], dict) else config[key]
                raise InputError(key, value, f"no [gear] layout in gear static: {instead}")
        if "pinion" not in config and "wheel" not in config:
            raise InputError("pinion", None, f"the pair of gear static: {instead}")
        return
    if not isinstance(gear, dict):
        gear = {}
    if verb == "simulate":
        two = [k for k in ("teeth", "tip_radius", "root_radius") if _is_list(gear.get(k))]
        two += [k for k in ("youngs_modulus", "poisson_ratio", "density") if k in gear]
        if two:
            raise InputError(
                f"gear.{two[0]}",
                gear[two[0]],
                "gear simulate's [gear]: one gear for both (teeth an integer, the material in "
                f"[material]); for two gears {instead}",
            )
    elif verb == "steady":
        one = [f"gear.{k}" for k in ("teeth",) if k in gear and not _is_list(gear[k])]
        one += [k for k in ("material", "disk_inertia") if k in config]
        op = config.get("operation")
        if isinstance(op, dict):
            one += [f"operation.{k}" for k in ("speed_rpm",) if _is_list(op.get(k))]
            one += [f"operation.{k}" for k in ("driver",) if k in op]
        if one:
            table, _, key = one[0].partition(".")
            value = config[table] if not key else config[table][key]
            if isinstance(value, dict):
                value = f"a [{table}] table"
            raise InputError(
                one[0],
                value,
                "gear steady's [gear] (teeth = [z_pinion, z_wheel], youngs_modulus etc. inside "
                f"[gear], the pinion's operation.speed_rpm), or {instead}",
            )
