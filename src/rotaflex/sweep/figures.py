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
import json
import logging
import math
from collections.abc import Callable
from typing import Any

import numpy as np

log = logging.getLogger("rotaflex.sweep")

_BOOKKEEPING = {"status", "error", "case_id", "attempts"}
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
        chunk = names[start : start + _PANELS_PER_FIGURE]
        ncols = min(3, len(chunk))
        nrows = math.ceil(len(chunk) / ncols)
        fig, axes = new_figure(nrows, ncols, squeeze=False, figsize=(4.2 * ncols, 2.9 * nrows))
        for ax, name in zip(axes.flat, chunk, strict=False):
            for label, xv, yv in _lines(ds, name, x):
                ax.plot(xv, yv, "o-", ms=3, label=label or None)
            ax.set_xlabel(_label(ds[x], x))
            ax.set_ylabel(_label(ds[name]))
            ax.grid(alpha=0.3)
        for ax in list(axes.flat)[len(chunk) :]:
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


def _base_config(ds) -> dict:
    try:
        return json.loads(ds.attrs.get("base_config", "{}"))
    except ValueError:
        return {}


def _get(cfg: dict, dotted: str, default=None):
    node = cfg
    for part in dotted.split("."):
        if not isinstance(node, dict) or part not in node:
            return default
        node = node[part]
    return node


def rotor_whirl(spin, polar_inertia: float, diametral_inertia: float, tilt_stiffness: float):
    """Linear whirl of a rigid disk on an isotropic tilt spring, spinning at ``spin`` [rad/s].

    ``Id w^2 -/+ Ip spin w - k = 0`` gives the forward and backward whirl frequencies [rad/s];
    a free response that starts at zero tilt with tilt rate ``r`` has the peak tilt
    ``2 Id r / sqrt((Ip spin)^2 + 4 Id k)`` [rad] (returned per unit ``r``).

    Returns
    -------
    forward, backward, peak_per_rate : arrays like ``spin``
    """
    spin = np.asarray(spin, dtype=float)
    root = np.sqrt((polar_inertia * spin) ** 2 + 4 * diametral_inertia * tilt_stiffness)
    forward = (polar_inertia * spin + root) / (2 * diametral_inertia)
    backward = (-polar_inertia * spin + root) / (2 * diametral_inertia)
    with np.errstate(divide="ignore"):
        peak = 2 * diametral_inertia / root
    return forward, backward, peak


def rotor_reference(ds) -> dict[str, Any] | None:
    """Closed-form whirl over the swept spin of a rotor sweep, and the peak tilt of a free
    response when it starts at zero tilt.

    Returns None unless the sweep varies ``motion.spin_speed`` of a rotor-disk case whose
    equations are the 1-2-3 (spin first) body-energy ones, nonlinear or exactly linearised,
    with the disk's inertia and tilt support fixed. ``peak_tilt`` is None when the initial tilt
    is not zero.
    """
    x = "motion.spin_speed"
    if x not in ds.dims:
        return None
    cfg = _base_config(ds)
    form = cfg.get("formulation", {})
    swept = set(json.loads(ds.attrs.get("swept", "[]")))
    fixed = (
        "disk.polar_inertia",
        "disk.diametral_inertia",
        "support.tilt_stiffness",
        "disk.inertia",
        "motion.initial_tilt_rate",
        "motion.initial_tilt",
    )
    if (
        swept & set(fixed)
        or "free_body" in cfg
        or _get(cfg, "disk.inertia") is not None
        or form.get("parameterisation", "euler") != "euler"
        or form.get("sequence", "123") != "123"
        or form.get("spin_angle") not in (None, 0)
        or form.get("energy", "body") != "body"
        or form.get("convention", "right-handed") != "right-handed"
        or form.get("expansion", "nonlinear") not in ("nonlinear", "second_order")
    ):
        return None
    ip, id_ = _get(cfg, "disk.polar_inertia", 2.0), _get(cfg, "disk.diametral_inertia", 1.0)
    k = _get(cfg, "support.tilt_stiffness", 0.0)
    spin = np.asarray(ds[x].values, dtype=float)
    fwd, bwd, peak = rotor_whirl(spin, ip, id_, k)
    at_rest = not any(_get(cfg, "motion.initial_tilt", (0.0, 0.0)))
    rate = float(np.hypot(*_get(cfg, "motion.initial_tilt_rate", (1.0, 1.0))))
    return {
        "spin": spin,
        "forward": fwd,
        "backward": bwd,
        "peak_tilt": peak * rate if at_rest else None,
        "peak_per_rate": (ip, id_, k, rate) if at_rest else None,
        "backward_critical": np.sqrt(k / (ip + id_)),
        "forward_critical": np.sqrt(k / (id_ - ip)) if id_ > ip else np.nan,
    }


def rotor_figures(ds) -> dict[str, Any]:
    """Campbell-style picture of a rotor spin sweep (``motion.spin_speed`` swept).

    Top: whirl frequencies of the linear disk-on-tilt-spring model against spin, with the
    synchronous 1x line; crossings (critical speeds) marked. Bottom: the simulated peak and RMS
    tilt against spin, with the linear closed-form peak tilt of a free response.
    """
    from rotaflex.core.plotting import new_figure

    x = "motion.spin_speed"
    if x not in ds.dims or "max_tilt_angle" not in ds:
        return {}
    ref = rotor_reference(ds)
    spin = np.asarray(ds[x].values, dtype=float)
    fig, (top, bottom) = new_figure(2, 1, sharex=True, figsize=(6.4, 6.4))
    if ref is not None:
        top.plot(spin, ref["forward"], "-", label="forward whirl (linear model)")
        top.plot(spin, ref["backward"], "-", label="backward whirl (linear model)")
        for name in ("backward_critical", "forward_critical"):
            if np.isfinite(ref[name]) and spin.min() <= ref[name] <= spin.max():
                top.axvline(ref[name], color="0.5", ls=":", lw=1)
                top.annotate(
                    name.replace("_", " "),
                    (ref[name], 0),
                    xytext=(3, 3),
                    textcoords="offset points",
                    fontsize=7,
                    rotation=90,
                )
    top.plot(spin, np.abs(spin), "k--", lw=1, label="1x spin")
    top.set_ylabel("whirl frequency [rad/s]")
    top.legend(fontsize=7)
    top.grid(alpha=0.3)
    da = ds["max_tilt_angle"]
    for label, xv, yv in _lines(ds, "max_tilt_angle", x):
        bottom.plot(xv, yv, "o", ms=4, label=f"peak tilt (simulated) {label}".strip())
    if "rms_tilt_angle" in ds:
        for label, xv, yv in _lines(ds, "rms_tilt_angle", x):
            bottom.plot(xv, yv, "s", ms=3, mfc="none", label=f"RMS tilt (simulated) {label}".strip())
    if ref is not None and ref["peak_per_rate"] is not None:
        ip, id_, k, rate = ref["peak_per_rate"]
        fine = np.linspace(spin.min(), spin.max(), 400)
        bottom.plot(fine, rotor_whirl(fine, ip, id_, k)[2] * rate, "-", lw=1, label="peak tilt, linear closed form")
    bottom.set_xlabel("spin speed [rad/s]")
    bottom.set_ylabel(_label(da, "tilt"))
    bottom.legend(fontsize=7)
    bottom.grid(alpha=0.3)
    fig.suptitle("Rotor: Campbell-style whirl and response vs spin")
    return {"campbell": fig}


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


#: gear-domain defaults (the paper's pair, rotaflex.gear.case) used when the config omits them
GEAR_DEFAULTS = {
    "gear.module": 3.175e-3,
    "gear.teeth": 28,
    "gear.pressure_angle_deg": 20.0,
    "gear.face_width": 6.35e-3,
    "disk_inertia": 2.965e-4,
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


def gear_figures(ds) -> dict[str, Any]:
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
    "rotor": rotor_figures,
    "gear": gear_figures,
    "floating": floating_figures,
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
            log.warning("sweep figures %s failed", getattr(source, "__name__", source), exc_info=True)
    return figs
