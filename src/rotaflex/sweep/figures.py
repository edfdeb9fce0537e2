"""Figures of a combined sweep dataset.

:func:`sweep_figures` returns the domain's own figures and the generic panels:

1. a ``sweep_figures(dataset) -> dict[str, Figure]`` function in the domain's case module, if
   it defines one; otherwise the built-in figures for that domain in :data:`DOMAIN_FIGURES`
   (gear, rotor, floating), written against the summary keys those domains expose;
2. always, the generic fallback: every numeric summary scalar against the first swept
   parameter (one line per value of a second swept parameter).

A figure function that fails is logged and skipped: figures never fail a sweep.
"""

from __future__ import annotations

import importlib
import logging
import math
from collections.abc import Callable
from typing import Any

import numpy as np

log = logging.getLogger("rotaflex.sweep")

_BOOKKEEPING = {"status", "error", "case_id", "attempts"}
_PANELS_PER_FIGURE = 9


def _numeric_vars(ds) -> list[str]:
    return [n for n, v in ds.data_vars.items()
            if n not in _BOOKKEEPING and v.dtype.kind in "fiu" and np.isfinite(v.values).any()]


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


def _label(var, name: str | None = None) -> str:
    name = name or str(var.name)
    units = var.attrs.get("units", "")
    return f"{name} [{units}]" if units else name


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
        return [(f"{second}={ds[second].values[i]:g}" if ds[second].dtype.kind in "fiu"
                 else f"{second}={ds[second].values[i]}",
                 ds[x].values, da.isel({second: i}).values)
                for i in range(min(ds.sizes[second], 8))]
    return [("", ds[x].values, da.values)]


def generic_figures(ds) -> dict[str, Any]:
    """Every numeric summary scalar against the first swept parameter (panels of 3 x 3)."""
    from rotaflex.core.plotting import new_figure

    x = _x_dim(ds)
    names = _numeric_vars(ds)
    if x is None or not names:
        return {}
    leaf = x.rsplit(".", 1)[-1]
    figs = {}
    for start in range(0, len(names), _PANELS_PER_FIGURE):
        chunk = names[start:start + _PANELS_PER_FIGURE]
        ncols = min(3, len(chunk))
        nrows = math.ceil(len(chunk) / ncols)
        fig, axes = new_figure(nrows, ncols, squeeze=False, figsize=(4.2 * ncols, 2.9 * nrows))
        for ax, name in zip(axes.flat, chunk):
            for label, xv, yv in _lines(ds, name, x):
                ax.plot(xv, yv, "o-", ms=3, label=label or None)
            ax.set_xlabel(_label(ds[x], x))
            ax.set_ylabel(_label(ds[name]))
            ax.grid(alpha=0.3)
        for ax in list(axes.flat)[len(chunk):]:
            ax.set_visible(False)
        handles, labels = axes.flat[0].get_legend_handles_labels()
        if labels:
            axes.flat[0].legend(fontsize=7)
        suffix = "" if start == 0 else f"_{start // _PANELS_PER_FIGURE + 1}"
        figs[f"summary_vs_{leaf}{suffix}"] = fig
    return figs


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


def rotor_figures(ds) -> dict[str, Any]:
    """Campbell-style picture of a spin sweep.

    Top: every summary frequency (unit Hz or rad/s) against spin, with the synchronous 1x line
    (frequency = spin) - crossings are the critical speeds. Bottom: the response amplitudes
    (summary scalars in m or rad) against spin on a log axis.
    """
    from rotaflex.core.plotting import new_figure

    x = _speed_dim(ds, ("spin", "omega", "speed"))
    if x is None:
        return {}
    unit = ds[x].attrs.get("units", "") or ("rpm" if x.endswith("_rpm") else "rad/s")
    spin_hz = _to_hz(ds[x].values, unit)
    freqs = [n for n in _numeric_vars(ds) if ds[n].attrs.get("units") in ("Hz", "rad/s")]
    resp = [n for n in _numeric_vars(ds) if ds[n].attrs.get("units") in ("m", "rad")]
    if not freqs and not resp:
        return {}
    fig, axes = new_figure(2 if freqs and resp else 1, 1, squeeze=False, sharex=True)
    row = 0
    xs = ds[x].values
    if freqs:
        ax = axes[row, 0]
        for n in freqs:
            f = _to_hz(ds[n].values, ds[n].attrs["units"])
            ax.plot(xs, f.reshape(len(xs), -1)[:, 0], "o-", ms=3, label=n)
        if spin_hz is not None:
            ax.plot(xs, spin_hz, "k--", lw=1, label="1x spin")
        ax.set_ylabel("frequency [Hz]")
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3)
        row += 1
    if resp:
        ax = axes[row, 0]
        for n in resp:
            y = np.abs(np.asarray(ds[n].values, dtype=float)).reshape(len(xs), -1)[:, 0]
            ax.semilogy(xs, np.where(y > 0, y, np.nan), "o-", ms=3, label=_label(ds[n]))
        ax.set_ylabel("response amplitude")
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3, which="both")
    axes[-1, 0].set_xlabel(_label(ds[x], x))
    fig.suptitle("Campbell-style response vs spin")
    return {"campbell": fig}


#: domain -> built-in figure function (used when the domain's case module has no hook)
DOMAIN_FIGURES: dict[str, Callable[[Any], dict[str, Any]]] = {
    "rotor": rotor_figures,
}


def sweep_figures(ds, domain: str | None = None) -> dict[str, Any]:
    """The domain's figures (hook or built-in) followed by the generic panels."""
    figs: dict[str, Any] = {}
    fn = None
    if domain:
        from rotaflex.core.domains import CASES

        if domain in CASES:
            try:
                fn = getattr(importlib.import_module(CASES[domain]), "sweep_figures", None)
            except ImportError:
                fn = None
        fn = fn or DOMAIN_FIGURES.get(domain)
    for source in ([fn] if fn else []) + [generic_figures]:
        try:
            figs.update(source(ds))
        except Exception:  # noqa: BLE001 - a figure never fails the sweep
            log.warning("sweep figures %s failed", getattr(source, "__name__", source),
                        exc_info=True)
    return figs
