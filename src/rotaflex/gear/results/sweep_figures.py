"""Figures of a gear sweep (the gear domain's ``sweep_figures`` hook of
:func:`rotaflex.sweep.figures.sweep_figures`): dynamic factor and transmission error against
speed, with the mesh-frequency axis and the speeds where a mesh harmonic meets the pair's
torsional natural frequency.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from rotaflex.gear.pair import paper
from rotaflex.sweep.figures import _base_config, _find, _get, _label, _lines, _speed_dim

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
    rb = g["gear.module"] * z * math.cos(math.radians(g["gear.pressure_angle_deg"])) / 2
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
    order 1, and ``resonance_speed / 2`` for order 2) as vertical lines; the ISO 6336-1
    method B K_v (summary ``iso_kv``) as a black line per other-key value. DTE in µm.
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
    if "resonance_speed" in ds:
        res = np.unique(np.round(np.asarray(ds["resonance_speed"].values, dtype=float), 3))
        res = res[np.isfinite(res)]
        # resonances of the swept variants within 2 % of each other share one line and label
        groups = []
        for r in res:
            if groups and r <= 1.02 * groups[-1][0]:
                groups[-1].append(r)
            else:
                groups.append([r])
        for grp in groups:
            for h in (1, 2):
                speed = float(np.mean(grp)) / h
                text = f"{grp[0] / h:.0f}" + (f"-{grp[-1] / h:.0f}" if len(grp) > 1 else "")
                if xs.min() <= speed <= xs.max():
                    for a in ax:
                        a.axvline(speed, color="gray", ls=":", lw=1)
                    ax[1].annotate(
                        f"{h}x f_mesh = f_n ({text} rpm)",
                        (speed, 0.97),
                        xycoords=("data", "axes fraction"),
                        xytext=(2, 0),
                        textcoords="offset points",
                        fontsize=7,
                        color="gray",
                        rotation=90,
                        va="top",
                    )
    ax[0].set_ylabel("dynamic factor F_max / F_static [-]")
    ax[1].set_ylabel("DTE peak-to-peak [µm]")
    ax[1].set_xlabel(_label(ds[x], x))
    for a in ax:
        a.grid(alpha=0.3)
    # one legend under the panels: the curves and the resonance labels stay readable
    ax[1].legend(
        *ax[0].get_legend_handles_labels(), fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2
    )
    fn = float(np.nanmedian(ds["mesh_natural_frequency"].values)) if "mesh_natural_frequency" in ds else math.nan
    title = "Gear steady state vs speed"
    if math.isfinite(fn):
        title += f" (linear mesh mode f_n = {fn:.0f} Hz)"
    fig.suptitle(title)
    return {"gear_steady_sweep": fig}


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
    to_rpm = {"rpm": 1.0, "rad/s": 60 / (2 * math.pi)}.get(unit)
    est = gear_mesh_estimate(_base_config(ds))
    z = est["teeth"]
    fn_name = _find(ds, ("natural_frequency",))
    if fn_name:
        fn, fn_label = float(np.nanmedian(ds[fn_name].values)), "f_n"
    else:
        fn, fn_label = est["natural_frequency"], "f_n (ISO estimate)"
    panels = [n for n in (kv, dte) if n is not None]
    fig, axes = new_figure(len(panels), 1, squeeze=False, sharex=True, figsize=(6.8, 3.3 * len(panels) + 0.6))
    xs = np.asarray(ds[x].values, dtype=float)
    for ax, name in zip(axes[:, 0], panels, strict=True):
        for label, xv, yv in _lines(ds, name, x):
            ax.plot(xv, yv, "o-", ms=3, label=label or None)
        ax.set_ylabel(_label(ds[name]))
        ax.grid(alpha=0.3)
        if to_rpm is None:
            continue
        for k in range(1, 5):
            speed_k = 60 * fn / (k * z) / to_rpm  # k z n / 60 = f_n
            if xs.min() <= speed_k <= xs.max():
                ax.axvline(speed_k, color="C3", ls=":", lw=1)
                ax.annotate(
                    f"{k} f_mesh = {fn_label}",
                    (speed_k, 1),
                    xycoords=("data", "axes fraction"),
                    xytext=(2, -10),
                    textcoords="offset points",
                    fontsize=7,
                    color="C3",
                    rotation=90,
                    va="top",
                )
    if to_rpm is not None:
        top = axes[0, 0].secondary_xaxis(
            "top", functions=(lambda v: v * to_rpm * z / 60, lambda f: f * 60 / (z * to_rpm))
        )
        top.set_xlabel(f"mesh frequency z n / 60 [Hz] (z = {z})")
    axes[-1, 0].set_xlabel(_label(ds[x], x))
    fig.suptitle(f"Gear: dynamic response vs speed ({fn_label} = {fn:.0f} Hz)")
    return {"gear_speed_sweep": fig}
