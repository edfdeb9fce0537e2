"""Matplotlib helpers (Agg backend, no windows); imported only when figures are made."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from rotaflex.core.io import write_atomic  # noqa: E402


def new_figure(nrows: int = 1, ncols: int = 1, **kw: Any):
    """A figure and axes with the project's default size."""
    kw.setdefault("figsize", (6.4 * ncols**0.5 + 1.0, 3.6 * nrows))
    kw.setdefault("layout", "constrained")
    return plt.subplots(nrows, ncols, **kw)


def save_figure(fig, path: str | Path, dpi: int = 110) -> Path:
    """Save ``fig`` as PNG atomically and close it."""
    try:
        return write_atomic(path, lambda p: fig.savefig(p, format="png", dpi=dpi))
    finally:
        plt.close(fig)


def label(var) -> str:
    """Axis label ``long_name [units]`` for an xarray variable."""
    name = var.attrs.get("long_name", var.name)
    units = var.attrs.get("units", "")
    return f"{name} [{units}]" if units else str(name)


def time_series_figures(ds) -> dict[str, Any]:
    """One figure per data variable that has a ``time`` dimension (other dims as lines)."""
    figs = {}
    for name, var in ds.data_vars.items():
        if "time" not in var.dims or var.ndim > 2:
            continue
        fig, ax = new_figure()
        if var.ndim == 1:
            ax.plot(ds["time"], var)
        else:
            other = next(d for d in var.dims if d != "time")
            for v in var[other].values:
                ax.plot(ds["time"], var.sel({other: v}), label=f"{other}={v}")
            ax.legend(fontsize=8)
        ax.set_xlabel(label(ds["time"]))
        ax.set_ylabel(label(var))
        ax.grid(alpha=0.3)
        figs[name] = fig
    return figs
