"""Figures of a combined sweep dataset.

:func:`sweep_figures` returns the domain's own figures and the generic panels:

1. a ``sweep_figures(dataset) -> dict[str, Figure]`` function in the domain's case module (the
   domain hook; the rotor's Campbell diagram lives in :mod:`rotaflex.rotor.sweep_figures`), if
   it defines one; otherwise the built-in figures for that domain in :data:`DOMAIN_FIGURES`;
2. always, the generic panels: every numeric summary scalar against the first swept parameter
   (one line per value of a second swept parameter), physical results and solver diagnostics
   (wall time, evaluations, attempts) in separate figures.

Helpers for domain hooks: :func:`lines_of`, :func:`axis_label`, :func:`base_config`,
:func:`config_value`, :func:`sweep_dim`.

A figure function that fails is logged and skipped: figures never fail a sweep.
"""

from __future__ import annotations

import functools
import importlib
import json
import logging
import math
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import Any

import numpy as np

log = logging.getLogger("rotaflex.sweep")

_BOOKKEEPING = {"status", "error", "case_id"}
#: line styles that stay distinct where curves overlap (and in black and white)
_STYLES = ("o-", "s--", "^-.", "v:", "D-", "x--", "P-.", "*:")
_PANELS_PER_FIGURE = 9


def _numeric_vars(ds) -> list[str]:
    return [
        n
        for n, v in ds.data_vars.items()
        if n not in _BOOKKEEPING and v.dtype.kind in "fiu" and np.isfinite(v.values).any()
    ]


def _x_dim(ds) -> str | None:
    """The swept parameter to use as abscissa: the first numeric dimension coordinate."""
    for d in ds.dims:
        if d != "case" and d in ds.coords and ds[d].dtype.kind in "fiu":
            return d
    if "case" in ds.dims:
        for name, c in ds.coords.items():
            if name != "case" and c.dims == ("case",) and c.dtype.kind in "fiu":
                return name
    return None


#: unit suffixes of config keys (``speed_rpm``): the label says the unit in brackets instead
_KEY_UNITS = {"rpm": "rpm", "deg": "deg", "hz": "Hz", "mm": "mm", "um": "um"}


#: words written as acronyms in labels (``dte_peak_to_peak`` -> ``DTE peak to peak``)
_ACRONYMS = {"dte", "ste", "rms", "iso", "fe", "mac"}


def _words(name: str, leaf_only: bool = True) -> str:
    """A readable name from a config key (its last dotted part) or a variable name (every
    part: ``full.tip.max_deflection`` -> ``full tip max deflection``), without a unit suffix,
    underscores as spaces (``operation.speed_rpm`` -> ``speed``)."""
    leaf = str(name).rsplit(".", 1)[-1] if leaf_only else str(name).replace(".", " ")
    head, _, suffix = leaf.rpartition("_")
    if head and suffix.lower() in _KEY_UNITS:
        leaf = head
    return " ".join(w.upper() if w in _ACRONYMS else w for w in leaf.replace(" ", "_").split("_") if w)


#: SI units drawn with a prefix: (smallest magnitude, unit, factor), largest first; a
#: magnitude below every threshold keeps the plain unit
_PREFIXED = {
    "m": ((1.0, "m", 1.0), (1e-3, "mm", 1e3), (1e-6, "um", 1e6), (1e-12, "nm", 1e9)),
    "Pa": ((1e9, "GPa", 1e-9), (1e6, "MPa", 1e-6), (1e3, "kPa", 1e-3)),
    "N": ((1e6, "MN", 1e-6), (1e4, "kN", 1e-3)),
}


def display_scale(var) -> tuple[float, str]:
    """``(factor, unit)`` to draw ``var`` in a readable unit: a displacement of 3e-6 m as 3 um,
    a stress of 7e7 Pa as 70 MPa (no axis offset like ``1e-6``); ``(1, unit)`` otherwise."""
    unit = str(var.attrs.get("units", "")).strip()
    v = np.asarray(var.values, dtype=float)
    v = v[np.isfinite(v)]
    if unit not in _PREFIXED or v.size == 0:
        return 1.0, unit
    big = float(np.max(np.abs(v)))
    for threshold, name, factor in _PREFIXED[unit]:
        if big >= threshold:
            return factor, name
    return 1.0, unit


def _key_unit(name: str) -> str:
    suffix = str(name).rsplit(".", 1)[-1].rpartition("_")[2].lower()
    return _KEY_UNITS.get(suffix, "")


def _label(var, name: str | None = None, unit: str | None = None) -> str:
    """Axis label ``long name [unit]``: the variable's ``long_name`` if it has a short one, else
    words from its config key or name (not the raw key); the unit is always shown (``[-]`` for
    a dimensionless number) so that no axis leaves its unit to be guessed."""
    from rotaflex.core.plotting import pretty_unit

    key = var.attrs.get("config_key") or name or str(var.name)
    long = str(var.attrs.get("long_name", ""))
    short_long = long if long and len(long) <= 40 and not var.attrs.get("config_key") and not name else ""
    text = short_long or _words(key, leaf_only=bool(var.attrs.get("config_key")))
    units = unit if unit is not None else (str(var.attrs.get("units", "")) or _key_unit(key))
    return f"{text} [{pretty_unit(units) or '-'}]"


def sweep_dim(ds, key: str) -> str | None:
    """The dimension of ``ds`` that sweeps the config key ``key`` (dimension names are
    identifier-safe, e.g. ``motion_spin_speed``; the key is in the ``config_key`` attribute)."""
    for d in ds.dims:
        if d in ds.coords and (ds[d].attrs.get("config_key") == key or d == key):
            return str(d)
    return None


def _lines(ds, var: str, x: str):
    """``(label, xvalues, yvalues)`` per line of ``var`` against ``x``: one line per point of
    the second swept dimension (at most 8, others at their first value)."""
    da = ds[var]
    if "case" in da.dims:  # list layout: one scattered line sorted by x
        xv = np.asarray(ds[x].values, dtype=float)
        order = np.argsort(xv)
        return [("", xv[order], np.asarray(da.values, dtype=float)[order])]
    others = [d for d in da.dims if d != x]
    if others:
        sel = {d: 0 for d in others[1:]}
        da = da.isel(sel)
        second = others[0]
        return [
            (
                f"{second}={ds[second].values[i]:g}"
                if ds[second].dtype.kind in "fiu"
                else f"{second}={ds[second].values[i]}",
                ds[x].values,
                da.isel({second: i}).values,
            )
            for i in range(min(ds.sizes[second], 8))
        ]
    return [("", ds[x].values, da.values)]


#: a panel whose values spread less than this fraction of their largest magnitude is constant
CONSTANT_RTOL = 1e-9
#: magnitude below which every value of a panel is round-off, by unit: a picometre is below any
#: displacement, gap or residual these models resolve (a 1e-18 m backlash, a tie residual of
#: 1e-16 m); other units: 1e-12 of the unit
ROUND_OFF = {"m": 1e-12, "mm": 1e-9, "um": 1e-6}


def uninformative(var) -> str:
    """Why the panel of ``var`` would tell nothing (``"constant"``, ``"round-off"``), or ``""``.

    Constant: the finite values spread by less than :data:`CONSTANT_RTOL` of their largest
    magnitude (all zeros included). Round-off: every value is smaller than :data:`ROUND_OFF` of
    its unit (1e-12 for other units), so whatever it shows is floating-point noise.
    """
    v = np.asarray(var.values, dtype=float)
    v = v[np.isfinite(v)]
    if v.size == 0:
        return "constant"
    big = float(np.max(np.abs(v)))
    if float(np.ptp(v)) <= CONSTANT_RTOL * big:
        return "constant"
    if big < ROUND_OFF.get(str(var.attrs.get("units", "")).strip(), 1e-12):
        return "round-off"
    return ""


def proportional(ds, name: str, x: str) -> float | None:
    """The factor ``a`` when ``name`` is a speed or frequency equal to ``a`` times the swept
    speed or frequency ``x`` at every point (to :data:`CONSTANT_RTOL`), e.g. the speed in
    rad/s or the mesh frequency of a sweep over the speed in rpm: its panel would draw the
    abscissa against itself. None otherwise (other quantities proportional to the swept one
    are results: their panels stay)."""
    rate = ("rpm", "rad/s", "rad s-1", "Hz", "1/s")
    if name == x or x not in ds[name].dims:
        return None
    units = str(ds[name].attrs.get("units", "")).strip(), str(ds[x].attrs.get("units", "")).strip() or _key_unit(x)
    if not all(u in rate for u in units):
        return None
    y, xv = xr_broadcast(ds[name], ds[x])
    y, xv = np.asarray(y, float).ravel(), np.asarray(xv, float).ravel()
    ok = np.isfinite(y) & np.isfinite(xv) & (xv != 0)
    if ok.sum() < 2 or np.ptp(xv[ok]) == 0:
        return None
    ratio = y[ok] / xv[ok]
    a = float(np.median(ratio))
    return a if a != 0 and float(np.ptp(ratio)) <= CONSTANT_RTOL * abs(a) else None


def xr_broadcast(a, b):
    """``a`` and ``b`` (xarray) broadcast against each other, as NumPy arrays."""
    import xarray as xr

    a2, b2 = xr.broadcast(a, b)
    return a2.values, b2.values


def generic_figures(ds, only: set[str] | None = None) -> dict[str, Any]:
    """Every numeric summary scalar against the first swept parameter (panels of 3 x 3):
    ``summary_vs_<key>`` for results, ``diagnostics_vs_<key>`` for solver diagnostics.

    Constant and round-off-only scalars (:func:`uninformative`) get no panel; the figure's
    footnote names them with their value, so nothing is hidden. ``only``: draw just the
    figures of these names (:func:`generic_pages` lists them without drawing).
    """
    figs = {}
    for stem, (x, chunk, title, note) in _generic_plan(ds).items():
        if only is None or stem in only:
            figs[stem] = _panel_figure(ds, x, chunk, title, note)
    return figs


def generic_pages(ds) -> dict[str, int]:
    """Name -> number of panels of each figure :func:`generic_figures` draws (none drawn)."""
    return {stem: len(plan[1]) for stem, plan in _generic_plan(ds).items()}


def _generic_plan(ds) -> dict[str, tuple[str, list[str], str, str]]:
    """Per figure of :func:`generic_figures`: abscissa, panel variables, title, footnote."""
    x = _x_dim(ds)
    names = _numeric_vars(ds)
    if x is None or not names:
        return {}
    key = ds[x].attrs.get("config_key", x)
    leaf = key.rsplit(".", 1)[-1]
    plan = {}
    dropped = {n: uninformative(ds[n]) or ("proportional" if proportional(ds, n, x) else "") for n in names}
    for stem, diagnostic, title in (
        (f"summary_vs_{leaf}", False, "Results"),
        (f"diagnostics_vs_{leaf}", True, "Solver diagnostics"),
    ):
        group = [n for n in names if _is_diagnostic(n) == diagnostic]
        shown = [n for n in group if not dropped[n]]
        note = _dropped_note(ds, [n for n in group if dropped[n]], dropped, x)
        for start in range(0, len(shown), _PANELS_PER_FIGURE):
            suffix = "" if start == 0 else f"_{start // _PANELS_PER_FIGURE + 1}"
            chunk = shown[start : start + _PANELS_PER_FIGURE]
            plan[f"{stem}{suffix}"] = (x, chunk, f"{title} vs {_label(ds[x], key)}", note)
    return plan


def _dropped_note(ds, names: list[str], why: dict[str, str], x: str | None = None) -> str:
    """``"Not drawn (constant: a = 3 m, ...; round-off only: b; proportional to the swept
    speed: speed = 0.1047 x speed [rad/s])"``."""
    parts = []
    kinds = {"constant": "constant", "round-off": "round-off only"}
    if x is not None:
        xlabel = _label(ds[x], ds[x].attrs.get("config_key", x))
        kinds["proportional"] = f"proportional to the swept {_words(ds[x].attrs.get('config_key', x))}"
    for kind, title in kinds.items():
        items = []
        for n in (n for n in names if why[n] == kind):
            unit = str(ds[n].attrs.get("units", ""))
            unit = f" {unit}" if unit and unit != "1" else ""
            v = np.asarray(ds[n].values, dtype=float)
            v = v[np.isfinite(v)]
            if kind == "constant" and v.size:
                items.append(f"{n} = {v[0]:.4g}{unit}")
            elif kind == "proportional":
                items.append(f"{n}{f' [{unit.strip()}]' if unit else ''} = {proportional(ds, n, x):.4g} × {xlabel}")
            else:
                items.append(n)
        if items:
            parts.append(f"{title}: " + ", ".join(items))
    return ("Not drawn (" + "; ".join(parts) + ")") if parts else ""


#: summary names that describe the computation rather than the physics
_DIAGNOSTIC_WORDS = ("wall_time", "evaluations", "nfev", "attempts", "steps", "iterations", "time_per_step", "residual")


def _is_diagnostic(name: str) -> bool:
    return any(w in name for w in _DIAGNOSTIC_WORDS)


def _panel_figure(ds, x: str, chunk: list[str], title: str, note: str = ""):
    """One figure of up to :data:`_PANELS_PER_FIGURE` panels, ``chunk`` against ``x``."""
    import textwrap

    from rotaflex.core.plotting import new_figure

    ncols = min(3, len(chunk))
    nrows = math.ceil(len(chunk) / ncols)
    fig, axes = new_figure(nrows, ncols, squeeze=False, figsize=(4.4 * ncols, 3.0 * nrows + 0.4))
    for ax, name in zip(axes.flat, chunk, strict=False):
        factor, unit = display_scale(ds[name])
        for label, xv, yv in _lines(ds, name, x):
            ax.plot(xv, np.asarray(yv, dtype=float) * factor, "o-", ms=3, label=label or None)
        ax.set_xlabel(_label(ds[x]))
        # wrapped, so that a long label never runs into the neighbouring panel
        ax.set_ylabel("\n".join(textwrap.wrap(_label(ds[name], unit=unit), 30)), fontsize=8)
        if ds[name].attrs.get("description"):  # what the number is, in the domain's words
            ax.set_title("\n".join(textwrap.wrap(ds[name].attrs["description"], 55)), fontsize=7)
        ax.grid(alpha=0.3)
    for ax in list(axes.flat)[len(chunk) :]:
        ax.set_visible(False)
    handles, labels = axes.flat[0].get_legend_handles_labels()
    if labels:  # one legend for all panels, outside the data
        fig.legend(handles, labels, loc="outside right upper", fontsize=7)
    fig.suptitle(title)
    if note:
        fig.supxlabel("\n".join(textwrap.wrap(note, 40 * ncols)), fontsize=7, ha="left", x=0.01)
    fig.rotaflex_dropped = note  # for callers and tests: what the footnote says
    return fig


# public names for domain hooks (the private ones stay for the built-in domain figures)
lines_of = _lines
axis_label = _label


def _first(ds, candidates: tuple[str, ...]) -> str | None:
    return next((c for c in candidates if c in ds.data_vars), None)


def _speed_dim(ds, hints: tuple[str, ...]) -> str | None:
    for d in ds.dims:
        leaf = d.rsplit(".", 1)[-1].lower()
        if any(h in leaf for h in hints) and ds[d].dtype.kind in "fiu":
            return d
    return None


def _to_hz(values, unit: str):
    """Angular speed or frequency values in Hz (rev/s); None if the unit is not one of those."""
    v = np.asarray(values, dtype=float)
    unit = unit.strip()
    if unit == "rpm":
        return v / 60.0
    if unit in ("rad/s", "rad s-1"):
        return v / (2 * np.pi)
    if unit in ("Hz", "1/s"):
        return v
    return None


def _base_config(ds) -> dict:
    try:
        return json.loads(ds.attrs.get("base_config", "{}"))
    except ValueError:
        return {}


def base_config(ds) -> dict:
    """The sweep's base config (``base_config`` attribute of ``sweep.nc``)."""
    return _base_config(ds)


def config_value(cfg: dict, dotted: str, default=None):
    """Value at a dotted key of a plain config dict, or ``default``."""
    return _get(cfg, dotted, default)


def _get(cfg: dict, dotted: str, default=None):
    node = cfg
    for part in dotted.split("."):
        if not isinstance(node, dict) or part not in node:
            return default
        node = node[part]
    return node


def _find(ds, *needles: tuple[str, ...]) -> str | None:
    """First numeric variable whose name contains every substring of one of the ``needles``."""
    names = _numeric_vars(ds)
    for group in needles:
        for n in names:
            if all(s in n.lower() for s in group):
                return n
    return None


def _first_int(value) -> int | None:
    if isinstance(value, (list, tuple)) and value:
        value = value[0]
    return int(value) if isinstance(value, (int, float)) and not isinstance(value, bool) else None


def floating_figures(ds) -> dict[str, Any]:
    """Floating body: peak elastic deflection against the first swept parameter.

    Plots every summary scalar whose name contains ``deflection`` and ``max`` or ``peak`` (the
    floating domain's ``<solution>.<point>.max_deflection``, e.g. full and perturbation
    solutions at the tip), else any ``*deflection*`` scalar.
    """
    from rotaflex.core.plotting import new_figure

    x = _x_dim(ds)
    names = [n for n in _numeric_vars(ds) if "deflection" in n.lower()]
    peaks = [n for n in names if "max" in n.lower() or "peak" in n.lower()]
    names = peaks or names
    if x is None or not names:
        return {}
    fig, ax = new_figure()
    for name in names:
        for label, xv, yv in _lines(ds, name, x):
            ax.plot(xv, yv, "o-", ms=3, label=f"{name} {label}".strip())
    ax.set_xlabel(_label(ds[x], x))
    ax.set_ylabel(f"peak elastic deflection [{ds[names[0]].attrs.get('units', '')}]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    ax.set_title("Floating body: peak elastic deflection")
    return {"peak_deflection": fig}


#: domain -> built-in figure function (used when the domain's case module has no hook)
DOMAIN_FIGURES: dict[str, Callable[[Any], dict[str, Any]]] = {
    "floating": floating_figures,
}


#: name of the domain's own figures among the parts of :func:`sweep_figures` (the generic
#: pages are named by their file stems)
DOMAIN_PART = ""


def sweep_figures(
    ds, domain: str | None = None, parts: Iterable[str] | None = None, errors: list[str] | None = None
) -> dict[str, Any]:
    """The domain's figures (hook or built-in) followed by the generic panels.

    ``parts``: draw only these (:func:`figure_parts`: :data:`DOMAIN_PART` for the domain's
    figures, a page name of :func:`generic_pages`); all by default. A figure function that
    raises is logged (and its message appended to ``errors``) and skipped.
    """
    parts = None if parts is None else set(parts)
    figs: dict[str, Any] = {}
    fn = None
    if domain and (parts is None or DOMAIN_PART in parts):
        from rotaflex.core.domains import CASES

        if domain in CASES:
            try:
                fn = getattr(importlib.import_module(CASES[domain]), "sweep_figures", None)
            except ImportError:
                fn = None
        fn = fn or DOMAIN_FIGURES.get(domain)
    only = None if parts is None else parts - {DOMAIN_PART}
    sources = ([fn] if fn else []) + ([functools.partial(generic_figures, only=only)] if only != set() else [])
    for source in sources:
        name = getattr(source, "__name__", None) or getattr(getattr(source, "func", None), "__name__", str(source))
        try:
            figs.update(source(ds))
        except Exception as exc:  # noqa: BLE001 - a figure never fails the sweep
            log.warning("sweep figures %s failed", name, exc_info=True)
            if errors is not None:
                errors.append(f"sweep figures {name} failed: {type(exc).__name__}: {exc}")
    return figs


#: cost of the domain's own figures in panels of :func:`generic_figures` (the gear's steady
#: figure, two panels with many lines, draws in about the time of three generic panels)
DOMAIN_COST = 3.0
#: matplotlib's import and first figure in a worker that has not drawn yet, in panels (~0.6 s
#: against ~0.11 s a panel on the 9-panel pages, CPU)
FIRST_FIGURE_COST = 5.0


def figure_parts(ds, domain: str | None) -> dict[str, float]:
    """Part -> estimated drawing cost (in panels) of each part of :func:`sweep_figures`."""
    parts = {DOMAIN_PART: DOMAIN_COST} if domain else {}
    parts.update({stem: 1.0 + n for stem, n in generic_pages(ds).items()})
    return parts


def draw_figures(ds, domain: str | None, parts: list[str], out_dir: str, fmt: str, dpi: int | None):
    """Draw and save the ``parts`` of :func:`sweep_figures` into ``out_dir`` (in a worker or the
    client); return the saved paths and the messages of the figure functions that failed."""
    from rotaflex.core.plotting import save_figure

    errors: list[str] = []
    paths = [
        str(save_figure(fig, Path(out_dir) / f"{stem}.png", dpi=dpi, fmt=fmt))
        for stem, fig in sweep_figures(ds, domain, parts, errors).items()
    ]
    return paths, errors


def split_parts(costs: dict[str, float], n_workers: int) -> list[list[str]]:
    """The parts split into ``1 + n_workers`` groups of about equal cost, the client's first
    (longest part first to the least loaded group; a worker's group starts with
    :data:`FIRST_FIGURE_COST`, the client has drawn already). Empty groups are dropped,
    except the client's."""
    loads = [0.0] + [FIRST_FIGURE_COST] * n_workers
    groups: list[list[str]] = [[] for _ in loads]
    for part in sorted(costs, key=lambda p: -costs[p]):
        i = min(range(len(loads)), key=lambda j: loads[j] + costs[part])
        groups[i].append(part)
        loads[i] += costs[part]
    return [groups[0]] + [g for g in groups[1:] if g]


def draw_sweep_figures(ds, domain: str | None, out_dir: Path, pools: list[tuple[Any, int]] = ()) -> list[Path]:
    """Draw the sweep figures into ``out_dir``, shared between this process and the local
    process ``pools`` (``(executor, workers)``, e.g. the sweep's workers once the cases are
    done): each worker draws a group of pages (:func:`split_parts`) while this process draws
    its own, so the pages are not drawn one after the other. A group whose worker fails is
    drawn here. Paths in the order of :func:`sweep_figures`."""
    from rotaflex.core import plotting

    fmt, dpi = plotting.chosen_format(), plotting._CHOSEN["dpi"]  # the client's --format/--dpi
    costs = figure_parts(ds, domain)
    n = sum(w for _, w in pools)
    groups = split_parts(costs, n)
    futures = []
    slots = [ex for ex, w in pools for _ in range(w)]
    for ex, group in zip(slots, groups[1:], strict=False):
        try:
            futures.append((ex.submit(draw_figures, ds, domain, group, str(out_dir), fmt, dpi), group))
        except Exception:  # noqa: BLE001 - a broken pool: drawn here
            groups[0] += group
    paths, errors = draw_figures(ds, domain, groups[0], str(out_dir), fmt, dpi)
    for fut, group in futures:
        try:
            more, errs = fut.result()
        except Exception:  # noqa: BLE001 - the worker died: drawn here
            log.warning("a worker drawing sweep figures failed; drawing %s here", ", ".join(group), exc_info=True)
            more, errs = draw_figures(ds, domain, group, str(out_dir), fmt, dpi)
        else:
            for e in errs:
                log.warning("%s", e)
        paths += more
    order = {p: i for i, p in enumerate(costs)}
    return sorted((Path(p) for p in paths), key=lambda p: order.get(p.stem, -1))  # stable: domain's first
