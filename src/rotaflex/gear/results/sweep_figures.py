"""Figures of a gear sweep (the gear domain's ``sweep_figures`` hook of
:func:`rotaflex.sweep.figures.sweep_figures`): dynamic factor and transmission error against
speed, with the mesh-frequency axis and the speeds where a mesh harmonic meets the pair's
torsional natural frequency.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from rotaflex.core.units import deg_to_rad, rad_s_to_rpm
from rotaflex.gear.pair import paper
from rotaflex.sweep.figures import _STYLES, _base_config, _find, _get, _label, _lines, _speed_dim, display_scale

#: gear-domain defaults (the paper's pair) used when the config omits them
GEAR_DEFAULTS = {
    "gear.module": paper.MODULE,
    "gear.teeth": paper.TEETH,
    "gear.pressure_angle_deg": paper.PRESSURE_ANGLE_DEG,
    "gear.face_width": paper.FACE_WIDTH,
    "disk_inertia": paper.DISK_INERTIA,
}
#: ISO 6336-1 mean mesh stiffness c_gamma of solid steel spur gears [N/(mm um)] = [1e9 N/m^2]
ISO_C_GAMMA = 20.0e9


def gear_mesh_estimate(cfg: dict) -> dict[str, float]:
    """Teeth, base radius and an estimate of the torsional mesh natural frequency of a pair.

    ``f_n = sqrt(c_gamma b r_b^2 (1/I_A + 1/I_B)) / (2 pi)`` with the ISO 6336-1 mean mesh
    stiffness ``c_gamma`` = 20 N/(mm um), face width ``b``, base radius
    ``r_b = m z cos(alpha) / 2`` and the two disk inertias. An estimate for marking resonance
    speeds, not a result of the FE model.
    """
    g = {k: _get(cfg, k, v) for k, v in GEAR_DEFAULTS.items()}
    z = int(g["gear.teeth"])
    rb = g["gear.module"] * z * math.cos(deg_to_rad(g["gear.pressure_angle_deg"])) / 2
    k_mesh = ISO_C_GAMMA * g["gear.face_width"]
    fn = math.sqrt(k_mesh * rb**2 * 2 / g["disk_inertia"]) / (2 * math.pi)
    return {"teeth": z, "base_radius": rb, "mesh_stiffness": k_mesh, "natural_frequency": fn}


def sweep_figures(ds) -> dict[str, Any]:
    """The gear sweep figure: :func:`steady_sweep_figure` for a sweep of ``gear steady``
    (sweep.nc attribute ``verb = "steady"``), else :func:`dynamics_sweep_figure`."""
    if ds.attrs.get("verb") == "steady":
        return steady_sweep_figure(ds)
    return dynamics_sweep_figure(ds)


#: line styles per direction of a continuation (distinct also in black and white)
_DIRECTION_STYLE = {"up": ("^", "-"), "down": ("v", "--")}


def _unsettled(one) -> np.ndarray:
    """Points that did not settle: a sweep case whose status is not success (``not_periodic``),
    or an in-process sweep point with ``converged`` false."""
    if "status" in one:
        return np.asarray(one["status"].values).astype(str) != "success"
    if "converged" in one:
        return ~np.asarray(one["converged"].values, dtype=bool)
    return np.zeros(one["dynamic_factor"].shape, dtype=bool)


def steady_sweep_figure(ds) -> dict[str, Any]:
    """Steady-state sweep (``gear steady``): dynamic factor and DTE peak-to-peak vs speed.

    Up and down directions of a continuation (dimension ``direction``) in distinct markers and
    line styles, one colour per value of any other swept key (e.g. a tip relief: with and
    without); the linear resonance speed of the mesh mode (summary ``resonance_speed``, mesh
    order 1, and ``resonance_speed / 2`` for order 2) of each variant, and ISO 6336-1's main
    resonance speed n_E1 (summary ``iso_resonance_speed``), as vertical lines with their numbers
    in the legend and short tags above the top panel (:func:`_resonance_marks`,
    :func:`_place_tags`); the ISO 6336-1 method B K_v (summary ``iso_kv``) as a black line per
    other-key value. DTE in µm. The title gives f_n only when every variant has the same one.
    """
    from rotaflex.core.plotting import new_figure

    x = _speed_dim(ds, ("speed", "rpm"))
    if x is None or "dynamic_factor" not in ds:
        return {}
    xs = np.asarray(ds[x].values, dtype=float)
    order = np.argsort(xs)
    others = [d for d in ds["dynamic_factor"].dims if d not in (x, "direction")]
    groups: list[tuple[str, dict]] = [("", {})]
    if others:
        o = others[0]
        groups = [(f"{ds[o].attrs.get('config_key', o)} = {v}", {o: i}) for i, v in enumerate(ds[o].values[:8])]
        rest = {d: 0 for d in others[1:]}
        groups = [(lab, {**sel, **rest}) for lab, sel in groups]
    directions = list(ds["direction"].values) if "direction" in ds.dims else [None]
    fig, ax = new_figure(2, 1, sharex=True, figsize=(6.8, 7.0 + 0.25 * len(groups) * (len(directions) + 1)))
    unsettled_shown = False
    for gi, (glabel, sel) in enumerate(groups):
        sub = ds.isel(sel)
        colour = f"C{gi}"
        for d in directions:
            one = sub if d is None else sub.sel(direction=d)
            mk, ls = _DIRECTION_STYLE.get(str(d), ("o", "-"))
            label = ", ".join(t for t in (glabel, "" if d is None else str(d)) if t) or "model"
            kv = np.asarray(one["dynamic_factor"].values, dtype=float)[order]
            ax[0].plot(xs[order], kv, marker=mk, ls=ls, ms=4, color=colour, label=label)
            bad = _unsettled(one)[order]
            if bad.any():  # points that did not become periodic: shown, but marked
                ax[0].plot(xs[order][bad], kv[bad], "kx", ms=8, label=None if unsettled_shown else "not periodic")
                unsettled_shown = True
            if "dte_pp" in one:
                dte = np.asarray(one["dte_pp"].values, dtype=float)[order] * 1e6
                ax[1].plot(xs[order], dte, marker=mk, ls=ls, ms=4, color=colour, label=label)
                if bad.any():
                    ax[1].plot(xs[order][bad], dte[bad], "kx", ms=8)
        if "iso_kv" in sub:
            iso = sub["iso_kv"] if directions == [None] else sub["iso_kv"].isel(direction=0)
            lab = "ISO 6336-1 method B K_v" + (f" ({glabel})" if glabel else "")
            ax[0].plot(
                xs[order],
                np.asarray(iso.values, dtype=float)[order],
                "k",
                ls=("-", ":", "-.")[gi % 3],
                lw=1.2,
                label=lab,
            )
    marks = _resonance_marks(ds, groups, float(xs.min()), float(xs.max()))
    for m in marks:
        for a in ax:
            a.axvline(m["speed"], color=m["colour"], ls=m["ls"], lw=1.0, label=m["legend"] if a is ax[0] else None)
    ax[0].set_ylabel("dynamic factor F_max / F_static [-]")
    ax[1].set_ylabel("DTE peak-to-peak [µm]")
    ax[1].set_xlabel(_speed_label(ds, x))
    for a in ax:
        a.grid(alpha=0.3)
    # one legend under the panels (the curves and every vertical line with its number); the
    # lines' short tags go above the top panel, staggered so that none overlaps another or a curve
    ax[1].legend(
        *ax[0].get_legend_handles_labels(), fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2
    )
    _place_tags(fig, ax[0], marks)
    fns = {round(g["fn"], 0) for g in _variant_resonances(ds, groups) if math.isfinite(g["fn"])}
    title = "Gear steady state vs speed"
    if len(fns) == 1:  # one mesh mode for every variant; else each variant's f_n is in the legend
        title += f" (linear mesh mode f_n = {fns.pop():.0f} Hz)"
    fig.suptitle(title)
    return {"gear_steady_sweep": fig}


#: tag rows above the top panel, and their height [points]
_TAG_ROWS, _TAG_STEP = 4, 9.0


def _value(sub, name: str) -> float:
    """The one value of a per-case scalar over a variant (its median; nan if absent)."""
    if name not in sub:
        return math.nan
    v = np.asarray(sub[name].values, dtype=float)
    v = v[np.isfinite(v)]
    return float(np.median(v)) if v.size else math.nan


def _variant_resonances(ds, groups) -> list[dict]:
    """Per variant (value of the other swept key): its label, the model's linear resonance speed
    n_res [rpm] and mesh-mode f_n [Hz], and ISO 6336-1's main resonance speed n_E1 [rpm] (the
    case's ``iso_resonance_speed``, from :func:`rotaflex.gear.static.iso6336_kv.resonance_speed_rpm`)."""
    return [
        {
            "label": glabel,
            "colour": f"C{gi}",
            "n_res": _value(ds.isel(sel), "resonance_speed"),
            "fn": _value(ds.isel(sel), "mesh_natural_frequency"),
            "n_e1": _value(ds.isel(sel), "iso_resonance_speed"),
        }
        for gi, (glabel, sel) in enumerate(groups)
    ]


def _resonance_marks(ds, groups, lo: float, hi: float) -> list[dict]:
    """Vertical lines within [lo, hi] rpm: the model's linear resonances ``h f_mesh = f_n``
    (h = 1, 2) of each variant in its colour (grey when every variant has the same one), and
    ISO's n_E1 (black dash-dot; one line per distinct value). Each with a short ``tag`` and a
    ``legend`` text that carries the numbers."""
    rows = _variant_resonances(ds, groups)
    marks: list[dict] = []
    same = len({round(r["n_res"], 1) for r in rows}) == 1
    for r in rows[:1] if same else rows:
        if not math.isfinite(r["n_res"]):
            continue
        who = "" if same or not r["label"] else f", {r['label']}"
        for h in (1, 2):
            speed = r["n_res"] / h
            if lo <= speed <= hi:
                marks.append(
                    {
                        "speed": speed,
                        "colour": "gray" if same else r["colour"],
                        "ls": ":",
                        "tag": f"{h}x",
                        "legend": f"{h}x f_mesh = f_n ({r['fn']:.0f} Hz{who}): {speed:,.0f} rpm",
                    }
                )
    n_e1 = sorted({round(r["n_e1"], 1) for r in rows if math.isfinite(r["n_e1"])})
    for v in n_e1:
        if lo <= v <= hi:
            whose = [r["label"] for r in rows if round(r["n_e1"], 1) == v and r["label"]]
            who = f" ({'; '.join(whose)})" if len(n_e1) > 1 and whose else ""
            marks.append(
                {
                    "speed": v,
                    "colour": "k",
                    "ls": "-.",
                    "tag": "n_E1",
                    "legend": f"ISO 6336-1 main resonance n_E1{who}: {v:,.0f} rpm",
                }
            )
    return sorted(marks, key=lambda m: m["speed"])


def _place_tags(fig, ax, marks: list[dict]) -> list:
    """Short tags of the vertical lines above ``ax``, each in the lowest row where it overlaps
    no tag already placed (rows of :data:`_TAG_STEP` points, at most :data:`_TAG_ROWS`; measured
    with the renderer, so any font and dpi); returns the text artists."""
    renderer = fig.canvas.get_renderer()
    placed: list = []
    for m in marks:
        for row in range(_TAG_ROWS):
            t = ax.annotate(
                m["tag"],
                (m["speed"], 1.0),
                xycoords=("data", "axes fraction"),
                xytext=(0, 2 + _TAG_STEP * row),
                textcoords="offset points",
                ha="center",
                va="bottom",
                fontsize=7,
                color=m["colour"],
                annotation_clip=False,
            )
            box = t.get_window_extent(renderer).expanded(1.1, 1.0)
            if not any(box.overlaps(o.get_window_extent(renderer)) for o in placed) or row == _TAG_ROWS - 1:
                placed.append(t)
                break
            t.remove()
    return placed


def _speed_label(ds, x: str) -> str:
    """x label: ``operation.speed_rpm`` is the pinion's speed (the gear domain's convention)."""
    if ds[x].attrs.get("config_key", x) in ("operation.speed_rpm", "operation_speed_rpm"):
        return _label(ds[x], x).replace("speed", "pinion speed", 1)
    return _label(ds[x], x)


def dynamics_sweep_figure(ds) -> dict[str, Any]:
    """Gear speed sweep: dynamic factor and peak-to-peak dynamic transmission error vs speed.

    Summary keys used (gear domain): ``dynamic_factor`` (peak contact force over the static
    tau / r_b) and, when the domain provides it, a peak-to-peak dynamic transmission error
    (a name containing ``transmission_error`` or ``dte``). The swept speed is
    ``operation.speed_rpm`` (or any dimension named ``*speed*``/``*rpm*``). The mesh frequency
    ``f_mesh = n z / 60`` is the top axis; the speeds where a mesh harmonic meets the pair's
    torsional natural frequency, ``k f_mesh = f_n`` (k = 1..4), are marked, with ``f_n`` from a
    ``natural_frequency`` summary variable if present, else :func:`gear_mesh_estimate`.
    """
    from rotaflex.core.plotting import new_figure

    x = _speed_dim(ds, ("speed", "rpm"))
    kv = _find(ds, ("dynamic_factor",))
    dte = _find(ds, ("transmission_error",), ("dte",))
    if x is None or (kv is None and dte is None):
        return {}
    unit = ds[x].attrs.get("units", "") or ("rpm" if x.endswith("_rpm") else "rad/s")
    to_rpm = {"rpm": 1.0, "rad/s": rad_s_to_rpm(1.0)}.get(unit)
    est = gear_mesh_estimate(_base_config(ds))
    z = est["teeth"]
    fn_name = _find(ds, ("natural_frequency",))
    if fn_name:
        fn, fn_label = float(np.nanmedian(ds[fn_name].values)), "f_n"
    else:
        fn, fn_label = est["natural_frequency"], "f_n (ISO estimate)"
    panels = [n for n in (kv, dte) if n is not None]
    fig, axes = new_figure(len(panels), 1, squeeze=False, sharex=True, figsize=(8.4, 3.3 * len(panels) + 0.6))
    xs = np.asarray(ds[x].values, dtype=float)
    for ax, name in zip(axes[:, 0], panels, strict=True):
        factor, shown_unit = display_scale(ds[name])  # a DTE of 8e-6 m drawn as 8 um, no axis offset
        for i, (label, xv, yv) in enumerate(_lines(ds, name, x)):
            ax.plot(xv, np.asarray(yv, float) * factor, _STYLES[i % len(_STYLES)], ms=3, label=label or None)
        ax.set_ylabel(_label(ds[name], unit=shown_unit))
        ax.grid(alpha=0.3)
        if to_rpm is None:
            continue
        for k in range(1, 5):
            speed_k = 60 * fn / (k * z) / to_rpm  # k z n / 60 = f_n
            if xs.min() <= speed_k <= xs.max():
                # named in the legend, not written across the panel's curves
                ax.axvline(
                    speed_k,
                    color="C3",
                    ls=":",  # which k: the legend entry gives its speed
                    lw=1,
                    label=f"{k} f_mesh = {fn_label}: {speed_k * to_rpm:,.0f} rpm" if ax is axes[0, 0] else None,
                )
    handles, labels = axes[0, 0].get_legend_handles_labels()
    if labels:  # outside the panels, right of them: inside, it would cover points
        fig.legend(handles, labels, loc="outside right upper", fontsize=7)
    if to_rpm is not None:
        top = axes[0, 0].secondary_xaxis(
            "top", functions=(lambda v: v * to_rpm * z / 60, lambda f: f * 60 / (z * to_rpm))
        )
        top.set_xlabel(f"mesh frequency z n / 60 [Hz] (z = {z})")
    axes[-1, 0].set_xlabel(_label(ds[x], x))
    fig.suptitle(f"Gear: dynamic response vs speed ({fn_label} = {fn:.0f} Hz)")
    return {"gear_speed_sweep": fig}
