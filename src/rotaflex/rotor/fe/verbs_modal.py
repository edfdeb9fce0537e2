"""Runners of the FE rotor verbs ``modal``, ``campbell`` and ``ucs``: parsed config -> analysis
-> Result (speeds converted from rpm once, in :mod:`~rotaflex.rotor.fe.case_config`).
"""

from __future__ import annotations

import json
import time

import numpy as np
import xarray as xr

from rotaflex.core.errors import InputError
from rotaflex.rotor.fe.case_config import clamp_modes, parse, speed_range
from rotaflex.rotor.fe.case_output import add_fluid_film_tables, oil_whip, pinned, progress_callback, summary_attrs
from rotaflex.rotor.fe.modal import STABILITY_TOL
from rotaflex.rotor.fe.model import RPM
from rotaflex.rotor.fe.results import CampbellResult, ModalResult, UCSResult

__all__ = ["DOFS", "run_campbell", "run_modal", "run_ucs"]

#: the lateral DOFs of a node, in the order of the mode shapes
DOFS = ["x", "y", "theta_x", "theta_y"]


@pinned
def run_modal(config: dict, *, progress: bool = False) -> ModalResult:
    """Modes at ``[modal] speed_rpm``."""
    from rotaflex.rotor.fe.modal import modal

    t0 = time.perf_counter()
    rotor, spec = parse(config, "modal")
    n_modes, note = clamp_modes(rotor, spec.n_modes, "modal.n_modes")
    m = modal(rotor, spec.speed_rpm * RPM, n_modes)
    nm = m.eigenvalue.shape[1]
    shape = m.shape[0].reshape(nm, rotor.n_nodes, 4)
    ds = xr.Dataset(
        {
            "natural_frequency": (
                "mode",
                m.wn[0],
                {"units": "rad/s", "long_name": "undamped natural frequency |lambda|"},
            ),
            "damped_frequency": ("mode", m.wd[0], {"units": "rad/s"}),
            "damping_ratio": ("mode", m.damping_ratio[0], {"units": "1"}),
            "log_dec": ("mode", m.log_dec[0], {"units": "1", "long_name": "logarithmic decrement"}),
            "forward_fraction": ("mode", m.forward_fraction[0], {"units": "1"}),
            "whirl": ("mode", m.whirl[0].astype(str)),
            "shape_real": (("mode", "node", "dof"), shape.real, {"units": "1"}),
            "shape_imag": (("mode", "node", "dof"), shape.imag, {"units": "1"}),
            "z": ("node", rotor.nodes, {"units": "m"}),
            "speed": ((), spec.speed_rpm * RPM, {"units": "rad/s"}),
        },
        coords={"mode": np.arange(nm), "node": np.arange(rotor.n_nodes), "dof": DOFS},
    )
    from rotaflex.rotor.fe.torsion_axial import axial_modes, torsional_modes

    wt, wa = torsional_modes(rotor, n_modes)[0], axial_modes(rotor, n_modes)[0]
    ds["torsional_frequency"] = ("uncoupled_mode", wt, {"units": "rad/s", "long_name": "torsional (0: rigid)"})
    ds["axial_frequency"] = ("uncoupled_mode", wa, {"units": "rad/s", "long_name": "axial (0: rigid)"})
    extra = {
        "speed": {"value": spec.speed_rpm, "unit": "rpm"},
        "stability_tolerance": {
            "value": STABILITY_TOL,
            "unit": "1",
            "note": "a mode is unstable when its damping ratio < -tolerance (relative to |eigenvalue|)",
        },
    }
    if note:
        extra["note"] = {"value": note, "unit": ""}
    hz = 1 / (2 * np.pi)
    for k in range(nm):
        extra[f"mode_{k}_frequency_hz"] = {"value": float(m.wn[0, k] * hz), "unit": "Hz"}  # = natural frequency
        extra[f"mode_{k}_damped_frequency_hz"] = {"value": float(m.wd[0, k] * hz), "unit": "Hz"}
        extra[f"mode_{k}_natural_frequency_rpm"] = {"value": float(m.wn[0, k] / RPM), "unit": "rpm"}
        extra[f"mode_{k}_damping_ratio"] = {"value": float(m.damping_ratio[0, k]), "unit": "1"}
        extra[f"mode_{k}_log_dec"] = {"value": float(m.log_dec[0, k]), "unit": "1"}
        extra[f"mode_{k}_whirl"] = {"value": str(m.whirl[0, k]), "unit": "", "allowed": "forward|backward|mixed"}
        extra[f"mode_{k}_stable"] = {"value": bool(not m.unstable[0, k]), "unit": ""}
    if wt.size > 1:
        extra["first_torsional_frequency_hz"] = {"value": float(wt[1] * hz), "unit": "Hz"}
        extra["first_axial_frequency_hz"] = {"value": float(wa[1] * hz), "unit": "Hz"}
    unstable = int(np.sum(m.unstable[0]))
    extra["unstable_modes"] = {"value": unstable, "unit": ""}
    msg = (
        f"{nm} modes at {spec.speed_rpm:g} rpm; lowest {m.wn[0, 0] * hz:.4g} Hz "
        f"(log dec {m.log_dec[0, 0]:.3g}); {unstable} unstable" + (f"; {note}" if note else "")
    )
    ds.attrs.update(summary_attrs(config, t0, extra, msg))
    return ModalResult(add_fluid_film_tables(ds, rotor))


@pinned
def run_campbell(config: dict, *, progress: bool = False) -> CampbellResult:
    """Campbell diagram over ``[campbell] speed_rpm`` with MAC tracking."""
    from rotaflex.rotor.fe.modal import campbell

    t0 = time.perf_counter()
    rotor, spec = parse(config, "campbell")
    speeds = speed_range(spec.speed_rpm, spec.n_speeds, "campbell")
    n_modes, note = clamp_modes(rotor, spec.n_modes, "campbell.n_modes")
    reduce = spec.reduce if spec.reduce is None or spec.reduce < rotor.n_dof else None
    if reduce is None and spec.reduce is not None:
        note = (note + "; " if note else "") + f"campbell.reduce = {spec.reduce} >= the {rotor.n_dof} DOFs: full solve"
    with progress_callback(progress, speeds.size, "campbell", "speed") as report:
        c = campbell(rotor, speeds, n_modes, spec.harmonics, reduce=reduce, progress=report)
    critical = c.critical
    if spec.critical_solve == "direct" and reduce is None:
        from rotaflex.rotor.fe.critical import critical_speeds

        with progress_callback(progress, 1, "critical speeds", "crossing") as report:
            critical = critical_speeds(rotor, speeds, n_modes, spec.harmonics, data=c, progress=report)
    m = c.modes
    ds = xr.Dataset(
        {
            "damped_frequency": (("speed", "mode"), m.wd, {"units": "rad/s"}),
            "natural_frequency": (("speed", "mode"), m.wn, {"units": "rad/s"}),
            "log_dec": (("speed", "mode"), m.log_dec, {"units": "1"}),
            "damping_ratio": (("speed", "mode"), m.damping_ratio, {"units": "1"}),
            "forward_fraction": (("speed", "mode"), m.forward_fraction, {"units": "1"}),
            "mac_min": ("speed", c.mac_min, {"units": "1", "long_name": "smallest MAC of the tracking step"}),
            "speed_rpm": ("speed", speeds / RPM, {"units": "rpm"}),
        },
        coords={"speed": ("speed", speeds, {"units": "rad/s"}), "mode": np.arange(n_modes)},
    )
    extra = {
        "critical_solve": {"value": spec.critical_solve if reduce is None else "interpolated", "unit": ""},
        **({"note": {"value": note, "unit": ""}} if note else {}),
    }
    extra |= {
        f"critical_{i}_rpm": {
            "value": cr["speed"] / RPM,
            "unit": "rpm",
            "whirl": cr["whirl"],
            "harmonic": cr["harmonic"],
        }
        for i, cr in enumerate(critical)
    }
    extra["unstable_modes"] = {"value": len(c.unstable), "unit": ""}
    extra |= oil_whip(rotor, c.unstable)
    extra.update(
        {f"unstable_mode_{u['mode']}_onset_rpm": {"value": u["speed"] / RPM, "unit": "rpm"} for u in c.unstable}
    )
    fw = [cr for cr in critical if cr["whirl"] == "forward" and cr["harmonic"] == 1]
    msg = (
        f"{n_modes} modes over {spec.n_speeds} speeds; forward 1X critical speeds [rpm]: "
        + (", ".join(f"{cr['speed'] / RPM:.0f}" for cr in fw) or "none")
        + (f"; {len(c.unstable)} unstable mode(s)" if c.unstable else "")
    )
    if spec.operating_range_rpm is not None:
        from rotaflex.rotor.fe.api import check_bands, stability_summary

        bands = check_bands([spec.operating_range_rpm], "campbell.operating_range_rpm")
        msg += "; " + stability_summary(rotor, bands, extra)
        ds.attrs["bands"] = json.dumps(bands)
    if spec.frequency_limit_hz is not None:
        ds.attrs["frequency_limit_hz"] = spec.frequency_limit_hz
    ds.attrs.update(summary_attrs(config, t0, extra, msg))
    ds.attrs["critical_speeds"] = json.dumps(critical)
    ds.attrs["unstable"] = json.dumps(c.unstable)
    ds.attrs["harmonics"] = json.dumps(list(spec.harmonics))
    return CampbellResult(add_fluid_film_tables(ds, rotor))


@pinned
def run_ucs(config: dict, *, progress: bool = False) -> UCSResult:
    """Undamped critical speed map over ``[ucs] stiffness``."""
    from rotaflex.rotor.fe.modal import ucs_map

    t0 = time.perf_counter()
    rotor, spec = parse(config, "ucs")
    if spec.stiffness[1] <= spec.stiffness[0]:
        raise InputError("ucs.stiffness", list(spec.stiffness), "[low, high] with high > low")
    k = np.geomspace(spec.stiffness[0], spec.stiffness[1], spec.n_points)
    n_modes, note = spec.n_modes, ""
    if n_modes > rotor.n_dof // 2:  # the one-plane UCS problem has n_dof / 2 DOFs
        n_modes, note = rotor.n_dof // 2, f"ucs.n_modes = {spec.n_modes} clamped to {rotor.n_dof // 2} (one-plane DOFs)"
    with progress_callback(progress, k.size, "ucs", "stiffness") as report:
        w = ucs_map(rotor, k, n_modes, progress=report)
    ds = xr.Dataset(
        {"critical_speed": (("stiffness", "mode"), w, {"units": "rad/s"})},
        coords={"stiffness": ("stiffness", k, {"units": "N/m"}), "mode": np.arange(n_modes)},
    )
    extra = {"note": {"value": note, "unit": ""}} if note else {}
    msg = f"{spec.n_points} stiffness values, {n_modes} critical speeds each" + (f"; {note}" if note else "")
    ds.attrs.update(summary_attrs(config, t0, extra, msg))
    return UCSResult(add_fluid_film_tables(ds, rotor))
