"""Sweep figures of the rotor domain: a Campbell-style diagram over the swept spin speed.

The case module's ``sweep_figures`` hook (see :mod:`rotaflex.sweep.figures`) calls
:func:`rotor_figures`; :func:`rotor_reference` gives the closed-form linear whirl it draws
and the reproduce report checks against.
"""

from __future__ import annotations

import json
from typing import Any

import numpy as np

from rotaflex.sweep.figures import axis_label as _label
from rotaflex.sweep.figures import base_config as _base_config
from rotaflex.sweep.figures import config_value as _get
from rotaflex.sweep.figures import lines_of as _lines
from rotaflex.sweep.figures import sweep_dim

SPIN = "motion.spin_speed"


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
    x = sweep_dim(ds, SPIN)
    if x is None:
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
    from rotaflex.core.plotting import legend_outside, new_figure

    x = sweep_dim(ds, SPIN)
    if x is None or "max_tilt_angle" not in ds:
        return {}
    ref = rotor_reference(ds)
    spin = np.asarray(ds[x].values, dtype=float)
    fig, (top, bottom) = new_figure(2, 1, sharex=True, figsize=(8.4, 6.4))
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
    top.set_ylabel("whirl frequency ω [rad/s]")
    legend_outside(top, fontsize=7)
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
    bottom.set_xlabel("spin speed Ω [rad/s]")
    bottom.set_ylabel(_label(da, "tilt angle β"))
    legend_outside(bottom, fontsize=7)
    bottom.grid(alpha=0.3)
    fig.suptitle("Rotor disk on a tilt spring: whirl frequencies (Campbell diagram) and peak tilt vs spin speed")
    return {"campbell": fig}
