"""Matplotlib helpers (Agg backend, no windows).

Matplotlib itself (0.3-0.7 s to import) is loaded by the first figure, not by importing this
module: the CLI checks ``--format`` against :data:`FORMATS` on every verb, figures or not.
Figures are :class:`matplotlib.figure.Figure` objects drawn by the Agg canvas, made without
``matplotlib.pyplot`` (its import and figure managers cost a verb ~0.02-0.04 s and give a file
nothing): they are freed like any object, no ``close`` needed.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

from rotaflex.core.io import write_atomic


def pyplot():
    """``matplotlib.pyplot`` on the Agg backend (no windows), imported on first use."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def figure_types():
    """``(Figure, FigureCanvasAgg)``, imported on first use (what a figure's import costs)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    return Figure, FigureCanvasAgg


#: keywords of :func:`new_figure` that lay out the axes grid (``Figure.subplots``); the others
#: go to ``Figure`` (as with ``pyplot.subplots``)
_GRID_KEYS = ("sharex", "sharey", "squeeze", "width_ratios", "height_ratios", "subplot_kw", "gridspec_kw")


def new_figure(nrows: int = 1, ncols: int = 1, **kw: Any):
    """A figure and axes with the project's default size (``pyplot.subplots`` without pyplot)."""
    kw.setdefault("figsize", (6.4 * ncols**0.5 + 1.0, 3.6 * nrows))
    kw.setdefault("layout", "constrained")
    grid = {k: kw.pop(k) for k in _GRID_KEYS if k in kw}
    Figure, FigureCanvasAgg = figure_types()
    fig = Figure(**kw)
    FigureCanvasAgg(fig)  # the canvas pyplot's Agg backend would attach
    return fig, fig.subplots(nrows, ncols, **grid)


#: figure file formats the commands accept (``--format``)
FORMATS = ("png", "svg", "pdf")
#: default resolution of PNG figures [dots per inch]
DPI = 150


_CHOSEN: dict[str, Any] = {"fmt": None, "dpi": None}


def configure(*, fmt: str | None = None, dpi: int | None = None) -> None:
    """Set the figure format and resolution of this process (the CLI's ``--format``/``--dpi``).

    Applies to every :func:`save_figure` call that does not pass its own ``fmt``/``dpi``.
    """
    _CHOSEN.update(fmt=fmt, dpi=dpi)


def chosen_format() -> str:
    """The figure format set by :func:`configure` (``"png"`` by default)."""
    return _CHOSEN["fmt"] or "png"


def save_figure(fig, path: str | Path, dpi: int | None = None, fmt: str | None = None) -> Path:
    """Save ``fig`` atomically and close it.

    The format is ``fmt``, else the one chosen with :func:`configure`, else the path's suffix;
    the suffix is adapted to the format.
    """
    path = Path(path)
    fmt = fmt or _CHOSEN["fmt"] or path.suffix.lstrip(".") or "png"
    dpi = dpi or _CHOSEN["dpi"]
    if path.suffix.lstrip(".") != fmt:
        path = path.with_suffix(f".{fmt}")
    try:
        return write_atomic(path, lambda p: fig.savefig(p, format=fmt, dpi=dpi or DPI))
    finally:
        plt = sys.modules.get("matplotlib.pyplot")
        if plt is not None:  # a figure pyplot made is kept until closed; others are just freed
            plt.close(fig)


#: CF unit strings as printed on axes (superscripts, micro sign)
_PRETTY_UNITS = {
    "kg m^2": "kg m²",
    "kg m^2/s": "kg m²/s",
    "m s-1": "m/s",
    "rad s-1": "rad/s",
    "s-1": "1/s",
    "s-2": "1/s²",
    "um": "µm",
    "us": "µs",
    "m^2": "m²",
    "1": "",
}


def pretty_unit(units: str) -> str:
    """A unit string for an axis label: ``kg m^2`` -> ``kg m²``, ``um`` -> ``µm``."""
    return _PRETTY_UNITS.get(units.strip(), units.strip())


def label(var) -> str:
    """Axis label ``long_name [units]`` for an xarray variable."""
    name = var.attrs.get("long_name", var.name)
    units = pretty_unit(str(var.attrs.get("units", "")))
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
            for i, v in enumerate(var[other].values):
                ax.plot(ds["time"], var.sel({other: v}), ls=STYLES[i % len(STYLES)], label=f"{other}={v}")
            legend_outside(ax)
        ax.set_xlabel(label(ds["time"]))
        ax.set_ylabel(label(var))
        ax.set_title(str(var.attrs.get("long_name", name)))
        ax.grid(alpha=0.3)
        figs[name] = fig
    return figs


def legend_outside(ax, **kw: Any):
    """A legend right of the axes, never over the data (constrained layout makes room)."""
    kw.setdefault("fontsize", 8)
    return ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0, **kw)


#: line styles that stay distinguishable where curves overlap (also in black and white)
STYLES = ("-", "--", "-.", ":", (0, (5, 1, 1, 1, 1, 1)), (0, (1, 2)))
