"""Figures of a gear sweep (the gear domain's ``sweep_figures`` hook of
:func:`rotaflex.sweep.figures.sweep_figures`): dynamic factor and transmission error against
speed, with the mesh-frequency axis and the speeds where a mesh harmonic meets the pair's
torsional natural frequency.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from rotaflex.gear import paper
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
