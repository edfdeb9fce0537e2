"""Combine the cases of a sweep: ``sweep.nc`` (parameters as dimensions), ``summary.csv``.

When the cases' parameter values form a full Cartesian grid (what ``--vary`` builds) every swept
parameter is a dimension and every summary scalar a variable over them. Otherwise (an arbitrary
list of cases from the Python API) the dimension is ``case`` and the parameters are coordinates
along it.
"""

from __future__ import annotations

import csv
import io
import json
import logging
import math
import re
from pathlib import Path
from typing import Any

import numpy as np

from rotaflex.core.io import write_json_atomic, write_netcdf, write_text_atomic

log = logging.getLogger("rotaflex.sweep")

#: units of swept config keys named with a non-SI suffix (style rule: ``speed_rpm``)
_SUFFIX_UNITS = {"_rpm": "rpm", "_deg": "deg", "_hz": "Hz", "_mm": "mm", "_percent": "%"}


def param_units(key: str, units: dict[str, str] | None = None) -> str:
    """Unit of a swept config key: from ``units`` (the domain schema) if given there, else from
    its naming convention (``""`` when neither says)."""
    if units and units.get(key):
        return units[key]
    each = re.sub(r"\[\d+\]", "[]", key)  # loads[0].duration: the schema lists loads[].duration
    if units and units.get(each):
        return units[each]
    leaf = key.rsplit(".", 1)[-1]
    return next((u for s, u in _SUFFIX_UNITS.items() if leaf.endswith(s)), "")


def dim_name(key: str) -> str:
    """Identifier-safe name of a swept config key (``motion.spin_speed`` -> ``motion_spin_speed``,
    ``loads[0].duration`` -> ``loads_0_duration``), usable in netCDF tools and as a Python name."""
    name = re.sub(r"_+", "_", re.sub(r"[^0-9A-Za-z_]", "_", key)).strip("_")
    return name if name and not name[0].isdigit() else f"p_{name}"


def _dim_names(keys: list[str]) -> dict[str, str]:
    names: dict[str, str] = {}
    for k in keys:
        n = dim_name(k)
        while n in names.values():  # two keys that differ only in punctuation
            n += "_"
        names[k] = n
    return names


def _is_number(v: Any) -> bool:
    return isinstance(v, (int, float, np.integer, np.floating, bool, np.bool_))


def _axes(records) -> tuple[list[str], dict[str, list[Any]], bool]:
    keys: list[str] = []
    for r in records:
        keys += [k for k in r.params if k not in keys]
    values = {k: [] for k in keys}
    for r in records:
        for k in keys:
            v = r.params.get(k)
            if v not in values[k]:
                values[k].append(v)
    n_grid = math.prod(len(v) for v in values.values()) if keys else 0
    combos = {tuple(repr(r.params.get(k)) for k in keys) for r in records}
    is_grid = bool(keys) and n_grid == len(records) == len(combos)
    return keys, values, is_grid


def combine(records, attrs: dict[str, Any] | None = None, units: dict[str, str] | None = None):
    """An ``xarray.Dataset`` of every case's summary scalars.

    Parameters
    ----------
    records : list of CaseRecord
    attrs : dict, optional
        Global attributes to add (``domain``, base config, ...).
    units : dict, optional
        Units of the swept keys (from the domain schema); default: from the key's name.

    Returns
    -------
    xarray.Dataset
        Dimensions: the swept parameters (grid, identifier-safe names from :func:`dim_name`,
        the config key in each coordinate's ``config_key`` attribute) or ``case``. Variables: each numeric summary
        scalar (``units`` attribute from the summary, its ``long_name`` as ``description``;
        NaN where a case failed), ``status``,
        ``error`` (first line), ``case_id``, ``attempts``, ``case_wall_time`` [s].
    """
    import xarray as xr

    keys, values, is_grid = _axes(records)
    safe = _dim_names(keys)

    def cattrs(k: str) -> dict[str, str]:
        return {"units": param_units(k, units), "long_name": k, "config_key": k}

    if is_grid:
        dims = [safe[k] for k in keys]
        shape = tuple(len(values[k]) for k in keys)
        index = [tuple(values[k].index(r.params.get(k)) for k in keys) for r in records]
        coords = {safe[k]: (safe[k], np.asarray(values[k]), cattrs(k)) for k in keys}
    else:
        dims, shape = ["case"], (len(records),)
        index = [(i,) for i in range(len(records))]
        coords = {"case": ("case", np.arange(len(records)), {"units": ""})}
        for k in keys:
            col = [r.params.get(k, np.nan) for r in records]
            if not all(_is_number(v) for v in col):
                col = [str(v) for v in col]
            coords[safe[k]] = ("case", np.asarray(col), cattrs(k))

    names: list[str] = []
    units: dict[str, str] = {}
    about: dict[str, str] = {}  # the summary's long_name: what the number is (drawn as a note)
    numeric: dict[str, bool] = {}
    for r in records:
        for name, item in r.summary.items():
            if name == "status":
                continue
            if name not in names:
                names.append(name)
                units[name] = str(item.get("unit", ""))
                numeric[name] = True
            if item.get("long_name") and name not in about:
                about[name] = str(item["long_name"])
            numeric[name] &= item.get("value") is None or _is_number(item.get("value"))

    def filled(kind: str):
        return np.full(shape, np.nan) if kind == "f" else np.full(shape, "", dtype=object)

    data = {n: filled("f" if numeric[n] else "s") for n in names}
    extra = {
        "status": filled("s"),
        "error": filled("s"),
        "case_id": filled("s"),
        "attempts": np.zeros(shape, dtype=np.int64),
        "case_wall_time": filled("f"),
    }
    for r, idx in zip(records, index, strict=True):
        for n in names:
            item = r.summary.get(n)
            if item is not None and item.get("value") is not None:
                data[n][idx] = float(item["value"]) if numeric[n] else str(item["value"])
        extra["status"][idx] = r.status
        extra["error"][idx] = r.error.splitlines()[0] if r.error else ""
        extra["case_id"][idx] = r.id
        extra["attempts"][idx] = r.attempts
        extra["case_wall_time"][idx] = r.wall_time
    variables = {
        n: (dims, a, {"units": units[n], **({"description": about[n]} if n in about else {})}) for n, a in data.items()
    }
    variables["status"] = (dims, extra["status"].astype(str), {"units": ""})
    variables["error"] = (dims, extra["error"].astype(str), {"units": ""})
    variables["case_id"] = (dims, extra["case_id"].astype(str), {"units": ""})
    variables["attempts"] = (dims, extra["attempts"], {"units": ""})
    variables["case_wall_time"] = (dims, extra["case_wall_time"], {"units": "s"})
    n_failed = sum(not r.ok for r in records)  # a finding (not_periodic) is not a failure
    meta = {
        "n_cases": len(records),
        "n_failed": n_failed,
        "swept": json.dumps(keys),
        "layout": "grid" if is_grid else "list",
    }
    for k, v in (attrs or {}).items():
        meta[k] = v if isinstance(v, (str, int, float)) else json.dumps(v, default=str)
    return xr.Dataset(variables, coords=coords, attrs=meta)


def summary_csv(records, units: dict[str, str] | None = None) -> str:
    """CSV text: one row per case (id, parameters, status, summary scalars ``name [unit]``)."""
    keys, _, _ = _axes(records)
    names: list[str] = []
    units: dict[str, str] = {}
    for r in records:
        for name, item in r.summary.items():
            if name != "status" and name not in names:
                names.append(name)
                units[name] = str(item.get("unit", ""))
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(
        [
            "case_id",
            *(f"{k} [{param_units(k, units)}]" if param_units(k, units) else k for k in keys),
            "status",
            *(f"{n} [{units[n]}]" if units[n] else n for n in names),
            "attempts",
            "case_wall_time [s]",
            "error",
        ]
    )
    for r in records:
        vals = [r.summary.get(n, {}).get("value", "") for n in names]
        w.writerow(
            [
                r.id,
                *(r.params.get(k, "") for k in keys),
                r.status,
                *("" if v is None else v for v in vals),
                r.attempts,
                f"{r.wall_time:.6g}",
                r.error.splitlines()[0] if r.error else "",
            ]
        )
    return buf.getvalue()


def write_outputs(result, *, domain: str | None, figures: bool = True, pools=()) -> list[Path]:
    """Write ``sweep.nc``, ``summary.csv``, ``sweep.json``, ``figures/*.png``; return the PNGs.

    ``pools``: local process pools ``(executor, workers)`` that draw some of the figures while
    this process draws the others (:func:`rotaflex.sweep.figures.draw_sweep_figures`).
    """
    out = result.out_dir
    ds = result.dataset
    write_netcdf(out / "sweep.nc", ds)
    key_units = {
        str(c.attrs["config_key"]): str(c.attrs.get("units", "")) for c in ds.coords.values() if "config_key" in c.attrs
    }
    write_text_atomic(out / "summary.csv", summary_csv(result.records, key_units))
    manifest = {
        "n_cases": result.n_cases,
        "n_failed": result.n_failed,
        "n_computed": result.n_computed,
        "domain": domain or "",
        "swept": json.loads(ds.attrs["swept"]),
        "failed": [{"id": r.id, "params": r.params, "status": r.status, "error": r.error} for r in result.failed],
    }
    write_json_atomic(out / "sweep.json", manifest)
    if figures and any(r.ok for r in result.records):
        from rotaflex.sweep.figures import draw_sweep_figures

        return draw_sweep_figures(ds, domain, out / "figures", pools)
    return []
