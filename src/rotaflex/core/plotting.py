"""Matplotlib helpers (Agg backend, no windows).

Matplotlib itself (0.3-0.7 s to import) is loaded by the first figure, not by importing this
module: the CLI checks ``--format`` against :data:`FORMATS` on every verb, figures or not.
Figures are :class:`matplotlib.figure.Figure` objects drawn by the Agg canvas, made without
``matplotlib.pyplot`` (its import and figure managers cost a verb ~0.02-0.04 s and give a file
nothing): they are freed like any object, no ``close`` needed.
"""

from __future__ import annotations

import re
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


#: pixels two boxes may share before they count as overlapping (antialiased edges touch)
_LAYOUT_SLACK_PX = 1.0


def _drawn_texts(fig, renderer) -> list[tuple[str, Any]]:
    """``(description, bbox)`` of every text the saved image shows, legends as one box each.

    Texts: figure texts and titles, axes titles, axis labels, the tick labels matplotlib draws
    (inside the view interval), axis offset texts, axes texts and annotations; a legend's
    entries are inside its own frame, so the legend counts as one box.
    """
    out: list[tuple[str, Any]] = []

    def add(where: str, t) -> None:
        if t is None or not t.get_visible() or not t.get_text().strip():
            return
        box = t.get_window_extent(renderer)
        if box.width > 0 and box.height > 0:
            out.append((f"{where} '{t.get_text().strip()[:40]}'", box))

    for t in fig.texts:  # suptitle, supxlabel, fig.text(...)
        add("figure text", t)
    for name in ("_suptitle", "_supxlabel", "_supylabel"):
        t = getattr(fig, name, None)
        if t is not None and t not in fig.texts:
            add("figure title", t)
    for i, ax in enumerate(fig.axes):
        if not ax.get_visible():
            continue
        tag = f"axes {i}" + (f" ({ax.get_title()[:30]!r})" if ax.get_title() else "")
        for t in (ax.title, getattr(ax, "_left_title", None), getattr(ax, "_right_title", None)):
            add(f"{tag} title", t)
        for axis in _axes_of(ax):
            if not axis.get_visible():  # e.g. the shared x axis of a twinx
                continue
            add(f"{tag} axis label", axis.label)
            add(f"{tag} offset text", axis.offsetText)
            # the ticks matplotlib draws: those inside the view interval (its own selection)
            for tick in axis._update_ticks():
                add(f"{tag} tick label", tick.label1)
                add(f"{tag} tick label", tick.label2)
        for t in ax.texts:  # ax.text and ax.annotate
            add(f"{tag} text", t)
    for i, leg in enumerate(_legends(fig)):
        if leg.get_visible():
            out.append((f"legend {i}", leg.get_window_extent(renderer)))
    return out


def _axes_of(ax) -> list:
    """The axis objects of ``ax``: x, y (and z of a 3-D axes)."""
    return [ax.xaxis, ax.yaxis] + ([ax.zaxis] if hasattr(ax, "zaxis") else [])


def _legends(fig) -> list:
    """Every legend of ``fig``: the figure's and each axes'."""
    legs = list(fig.legends)
    legs += [ax.get_legend() for ax in fig.axes if ax.get_legend() is not None]
    return legs


def _densify(d, step: float = 2.0):
    """The polyline ``d`` (display px, shape (n, 2)) with points every ``step`` px or closer."""
    import numpy as np

    seg = np.diff(d, axis=0)
    n = np.maximum(1, np.ceil(np.hypot(seg[:, 0], seg[:, 1]) / step).astype(int))
    start = np.repeat(d[:-1], n, axis=0)
    frac = (np.arange(n.sum()) - np.repeat(np.cumsum(n) - n, n)) / np.repeat(n, n)
    return np.vstack([start + np.repeat(seg, n, axis=0) * frac[:, None], d[-1:]])


def _data_points(ax) -> Any:
    """Display coordinates [px] of the drawn data of ``ax``: every line drawn with a line style
    (curves, and marked speeds or levels such as ``axvline``), vertices and every 2 px between
    them; marker-only lines and scatter offsets at their points; only those inside the axes
    (clipped points are not drawn), shape (n, 2)."""
    import numpy as np

    pts = []
    for line in ax.get_lines():
        if not line.get_visible():
            continue
        xy = np.asarray(line.get_xydata(), float)
        d = line.get_transform().transform(xy[np.all(np.isfinite(xy), axis=1)])
        if line.get_linestyle() not in ("None", "", " ") and len(d) > 1:
            d = _densify(d)  # a sparse curve (or a marker line such as axvline) crosses a box between its vertices
        pts.append(d)
    for coll in ax.collections:
        offsets = np.asarray(coll.get_offsets(), float)
        if coll.get_visible() and offsets.ndim == 2 and len(offsets) > 1:  # scatter-like
            xy = offsets[np.all(np.isfinite(offsets), axis=1)]
            pts.append(coll.get_offset_transform().transform(xy))
    if not pts:
        return np.zeros((0, 2))
    d = np.concatenate([p.reshape(-1, 2) for p in pts])
    box = ax.get_window_extent()
    inside = (d[:, 0] >= box.x0) & (d[:, 0] <= box.x1) & (d[:, 1] >= box.y0) & (d[:, 1] <= box.y1)
    return d[inside]


def layout_problems(fig) -> list[str]:
    """What a reader of the saved ``fig`` cannot read, measured from the rendered artists.

    The figure is drawn (constrained layout done, as :func:`save_figure` would) and the boxes
    the renderer gives are compared:

    * two texts overlapping (titles, axis labels, tick labels, offset texts, texts and
      annotations, legends; more than :data:`_LAYOUT_SLACK_PX` px in both directions),
    * a text or legend reaching outside the figure,
    * an axis with a unit drawn with a scale offset (``1e-6`` above the axis: the reader must
      multiply; a prefixed unit says it at once),
    * a legend whose box contains drawn data (a point of a data curve, vertices and every 2 px
      between them, or a scatter point) of any axes, twin axes included.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        A figure with a canvas (as :func:`new_figure` makes).

    Returns
    -------
    list of str
        One sentence per problem; empty when the figure is readable.

    Examples
    --------
    >>> fig, ax = new_figure()
    >>> _ = ax.plot([0, 1], [0, 1], label="line")
    >>> _ = ax.legend(loc="upper left")  # the line runs from lower left to upper right
    >>> layout_problems(fig)
    []
    """
    import numpy as np

    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    problems: list[str] = []
    texts = _drawn_texts(fig, renderer)
    s = _LAYOUT_SLACK_PX
    for i, (wa, a) in enumerate(texts):
        for wb, b in texts[i + 1 :]:
            if min(a.x1, b.x1) - max(a.x0, b.x0) > s and min(a.y1, b.y1) - max(a.y0, b.y0) > s:
                problems.append(f"{wa} overlaps {wb}")
    page = fig.bbox
    for w, a in texts:
        if a.x0 < page.x0 - s or a.y0 < page.y0 - s or a.x1 > page.x1 + s or a.y1 > page.y1 + s:
            problems.append(f"{w} reaches outside the figure")
    for i, ax in enumerate(fig.axes):
        for axis in _axes_of(ax):
            offset = axis.offsetText.get_text().strip() if axis.get_visible() else ""
            unit = re.search(r"\[([^\]]*)\]\s*$", axis.label.get_text())
            if offset and unit and unit.group(1).strip() not in ("", "-", "1"):
                problems.append(
                    f"axes {i} axis '{axis.label.get_text()}' is scaled by '{offset}': draw it in a prefixed unit"
                )
    for leg in _legends(fig):
        if not leg.get_visible():
            continue
        box = leg.get_window_extent(renderer)
        for i, ax in enumerate(fig.axes):
            d = _data_points(ax)
            n = int(np.count_nonzero((d[:, 0] > box.x0) & (d[:, 0] < box.x1) & (d[:, 1] > box.y0) & (d[:, 1] < box.y1)))
            if n:
                title = leg.get_title().get_text() or ", ".join(t.get_text() for t in leg.get_texts()[:2])
                problems.append(f"legend ({title[:40]!r}) covers {n} data points of axes {i}")
    return problems


#: API 684's largest separation margins: 16 % below the minimum, 26 % above the maximum speed
API_MARGINS = (0.16, 0.26)


def shade_operating_bands(axes, bands, *, margins: bool = False, alpha: float = 0.15) -> None:
    """Shade operating speed ranges on axes whose x is speed in rpm (each axes once).

    Parameters
    ----------
    axes : sequence of matplotlib.axes.Axes
        Axes to shade; the first carries the legend labels, the others repeat them (a figure
        legend built from several axes shows each label once).
    bands : sequence of (float, float)
        ``(lo, hi)`` operating ranges [rad/s]; ``lo == hi`` is one operating speed, drawn as a
        line (a band of zero width would not show).
    margins : bool
        Also hatch API 684's largest separation margins (:data:`API_MARGINS`) beside each
        band on the first axes.
    alpha : float
        Opacity of the shading.
    """
    from rotaflex.core.units import rad_s_to_rpm

    for i, (lo, hi) in enumerate(bands):
        lo_rpm, hi_rpm = rad_s_to_rpm(lo), rad_s_to_rpm(hi)
        for a in axes:
            if hi > lo:
                a.axvspan(
                    lo_rpm, hi_rpm, color="tab:green", alpha=alpha, lw=0, label="operating range" if i == 0 else None
                )
            else:
                a.axvline(lo_rpm, color="tab:green", lw=2.0, label="operating speed" if i == 0 else None)
        if margins:
            below, above = API_MARGINS
            hatch = {"fill": False, "hatch": "//", "ec": "tab:green", "lw": 0, "alpha": 0.5}
            axes[0].axvspan(lo_rpm * (1 - below), lo_rpm, **hatch)
            axes[0].axvspan(
                hi_rpm, hi_rpm * (1 + above), **hatch, label="largest API margins (16 % / 26 %)" if i == 0 else None
            )


def place_labels(ax, items, *, fontsize: float = 7.0, max_shift: int = 12) -> list:
    """Write labels beside data points, none over another or outside the axes.

    Each label starts right of its point (vertically centred on it); where its box, measured
    by the renderer after the figure's layout is done, overlaps a label placed before or
    leaves the axes, it is moved up or down by its own height (0, +1, -1, +2, -2, ... up to
    ``max_shift``) and kept at the first free place (at the last try, if none is free, where
    :func:`layout_problems` will report it). Labels do not take part in the layout, so placing
    them moves nothing already measured.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    items : iterable of (float, float, str, color)
        ``(x, y, text, color)``: the point in data coordinates, the label and its colour.
    fontsize : float
        Font size [pt].
    max_shift : int
        Largest shift tried, in label heights.

    Returns
    -------
    list of matplotlib.text.Annotation
    """
    fig = ax.figure
    fig.canvas.draw()  # the layout first: boxes measured after it stay where they are
    renderer = fig.canvas.get_renderer()
    area = ax.get_window_extent(renderer)
    placed: list = []
    for x, y, text, color in sorted(items, key=lambda it: it[1]):
        t = ax.annotate(
            text, (x, y), xytext=(3, 0), textcoords="offset points", fontsize=fontsize, color=color, va="center"
        )
        t.set_in_layout(False)
        height_pt = t.get_window_extent(renderer).height * 72.0 / fig.dpi
        for k in range(2 * max_shift + 1):
            shift = (k + 1) // 2 * (1 if k % 2 else -1) if k else 0
            t.set_position((3, shift * height_pt * 1.05))
            box = t.get_window_extent(renderer)
            inside = box.y0 >= area.y0 and box.y1 <= area.y1 and box.x1 <= area.x1
            if inside and not any(box.overlaps(o.get_window_extent(renderer)) for o in placed):
                break
        placed.append(t)
    return placed
