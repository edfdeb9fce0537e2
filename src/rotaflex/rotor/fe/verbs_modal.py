"""Runners of the FE rotor verbs ``modal``, ``campbell`` and ``ucs``: parsed config -> analysis
-> Result (speeds converted from rpm once, in :mod:`~rotaflex.rotor.fe.case_config`).
"""

from __future__ import annotations

import json
import time

import numpy as np
import xarray as xr

from rotaflex.core.errors import InputError
from rotaflex.core.units import rad_s_to_rpm, rpm_to_rad_s
from rotaflex.rotor.fe.case_config import clamp_modes, parse, speed_range
from rotaflex.rotor.fe.case_output import add_fluid_film_tables, oil_whip, pinned, progress_callback, summary_attrs
from rotaflex.rotor.fe.modal import STABILITY_TOL
from rotaflex.rotor.fe.results import CampbellResult, ModalResult, UCSResult, campbell_dataset

__all__ = ["DOFS", "run_campbell", "run_modal", "run_ucs"]

#: the lateral DOFs of a node, in the order of the mode shapes
DOFS = ["x", "y", "theta_x", "theta_y"]


def _modes_dataset(rotor, m, i: int, speed_rpm: float) -> xr.Dataset:
    """The modes of speed ``i`` of ``m`` as a dataset (mode, node, dof); shapes on the shaft's nodes."""
    nm = m.eigenvalue.shape[1]
    shape = m.shape[i][:, : rotor.n_rotor_dof].reshape(nm, rotor.n_nodes, 4)
    return xr.Dataset(
        {
            "natural_frequency": (
                "mode",
                m.wn[i],
                {"units": "rad/s", "long_name": "undamped natural frequency |lambda|"},
            ),
            "damped_frequency": ("mode", m.wd[i], {"units": "rad/s"}),
            "damping_ratio": ("mode", m.damping_ratio[i], {"units": "1"}),
            "log_dec": ("mode", m.log_dec[i], {"units": "1", "long_name": "logarithmic decrement"}),
            "forward_fraction": ("mode", m.forward_fraction[i], {"units": "1"}),
            "whirl": ("mode", m.whirl[i].astype(str)),
            "shape_real": (("mode", "node", "dof"), shape.real, {"units": "1"}),
            "shape_imag": (("mode", "node", "dof"), shape.imag, {"units": "1"}),
            "z": ("node", rotor.nodes, {"units": "m"}),
            "speed": ((), rpm_to_rad_s(speed_rpm), {"units": "rad/s"}),
        },
        coords={"mode": np.arange(nm), "node": np.arange(rotor.n_nodes), "dof": DOFS},
    )


def _mode_summary(m, i: int, prefix: str = "") -> dict:
    hz = 1 / (2 * np.pi)
    extra = {}
    for k in range(m.eigenvalue.shape[1]):
        p = f"{prefix}mode_{k}"
        extra[f"{p}_frequency_hz"] = {"value": float(m.wn[i, k] * hz), "unit": "Hz"}  # = natural frequency
        extra[f"{p}_damped_frequency_hz"] = {"value": float(m.wd[i, k] * hz), "unit": "Hz"}
        extra[f"{p}_natural_frequency_rpm"] = {"value": float(rad_s_to_rpm(m.wn[i, k])), "unit": "rpm"}
        extra[f"{p}_damping_ratio"] = {"value": float(m.damping_ratio[i, k]), "unit": "1"}
        extra[f"{p}_log_dec"] = {"value": float(m.log_dec[i, k]), "unit": "1"}
        extra[f"{p}_whirl"] = {"value": str(m.whirl[i, k]), "unit": "", "allowed": "forward|backward|mixed"}
        extra[f"{p}_stable"] = {"value": bool(not m.unstable[i, k]), "unit": ""}
    return extra


@pinned
def run_modal(config: dict, *, progress: bool = False) -> ModalResult:
    """Modes at ``[modal] speed_rpm``: one speed, or a list (a ``speed`` dimension in the result,
    summary keys ``speed_<i>_mode_<k>_...``)."""
    from rotaflex.rotor.fe.modal import modal

    t0 = time.perf_counter()
    rotor, spec = parse(config, "modal")
    n_modes, note = clamp_modes(rotor, spec.n_modes, "modal.n_modes")
    several = not isinstance(spec.speed_rpm, float)
    rpm = [float(v) for v in np.atleast_1d(spec.speed_rpm)]
    if several and not rpm:
        raise InputError("modal.speed_rpm", [], "a speed [rpm] or a list of speeds")
    m = modal(rotor, rpm_to_rad_s(np.asarray(rpm)), n_modes)
    parts = [_modes_dataset(rotor, m, i, r) for i, r in enumerate(rpm)]
    ds = xr.concat([p.set_coords("speed") for p in parts], "speed") if several else parts[0]
    if several:
        ds["speed_rpm"] = ("speed", np.asarray(rpm), {"units": "rpm"})
        for name in ("z",):
            ds[name] = parts[0][name]
    from rotaflex.rotor.fe.torsion_axial import axial_modes, torsional_modes

    wt, wa = torsional_modes(rotor, n_modes)[0], axial_modes(rotor, n_modes)[0]
    ds["torsional_frequency"] = ("uncoupled_mode", wt, {"units": "rad/s", "long_name": "torsional (0: rigid)"})
    ds["axial_frequency"] = ("uncoupled_mode", wa, {"units": "rad/s", "long_name": "axial (0: rigid)"})
    extra = {
        "speed": {"value": rpm if several else rpm[0], "unit": "rpm"},
        "stability_tolerance": {
            "value": STABILITY_TOL,
            "unit": "1",
            "note": "a mode is unstable when its damping ratio < -tolerance (relative to |eigenvalue|)",
        },
    }
    if note:
        extra["note"] = {"value": note, "unit": ""}
    hz = 1 / (2 * np.pi)
    for i in range(len(rpm)):
        extra |= _mode_summary(m, i, f"speed_{i}_" if several else "")
    if wt.size > 1:
        extra["first_torsional_frequency_hz"] = {"value": float(wt[1] * hz), "unit": "Hz"}
        extra["first_axial_frequency_hz"] = {"value": float(wa[1] * hz), "unit": "Hz"}
    unstable = int(np.sum(m.unstable))
    extra["unstable_modes"] = {"value": unstable, "unit": ""}
    at = ", ".join(f"{r:g}" for r in rpm)
    msg = (
        f"{m.eigenvalue.shape[1]} modes at {at} rpm; lowest {m.wn[0, 0] * hz:.4g} Hz "
        f"(log dec {m.log_dec[0, 0]:.3g})" + (" at the first speed" if several else "") + f"; {unstable} unstable"
    ) + (f"; {note}" if note else "")
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
    lines = [{"name": f"{h:g}X", "factor": float(h)} for h in spec.harmonics]
    ds = campbell_dataset(c.modes, c.mac_min, lines, critical, "critical_speeds")
    extra = {
        "critical_solve": {"value": spec.critical_solve if reduce is None else "interpolated", "unit": ""},
        **({"note": {"value": note, "unit": ""}} if note else {}),
    }
    extra |= {
        f"critical_{i}_rpm": {
            "value": rad_s_to_rpm(cr["speed"]),
            "unit": "rpm",
            "whirl": cr["whirl"],
            "harmonic": cr["harmonic"],
        }
        for i, cr in enumerate(critical)
    }
    extra["unstable_modes"] = {"value": len(c.unstable), "unit": ""}
    extra |= oil_whip(rotor, c.unstable)
    extra.update(
        {f"unstable_mode_{u['mode']}_onset_rpm": {"value": rad_s_to_rpm(u["speed"]), "unit": "rpm"} for u in c.unstable}
    )
    fw = [cr for cr in critical if cr["whirl"] == "forward" and cr["harmonic"] == 1]
    msg = (
        f"{n_modes} modes over {spec.n_speeds} speeds; forward 1X critical speeds [rpm]: "
        + (", ".join(f"{rad_s_to_rpm(cr['speed']):.0f}" for cr in fw) or "none")
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
    ds.attrs["unstable"] = json.dumps(c.unstable)
    ds.attrs["harmonics"] = json.dumps(list(spec.harmonics))
    return CampbellResult(add_fluid_film_tables(ds, rotor))


@pinned
def run_ucs(config: dict, *, progress: bool = False) -> UCSResult:
    """Undamped critical speed map over ``[ucs] stiffness``."""
    from rotaflex.rotor.fe.ucs import ucs_map

    t0 = time.perf_counter()
    rotor, spec = parse(config, "ucs")
    if spec.stiffness[1] <= spec.stiffness[0]:
        raise InputError("ucs.stiffness", list(spec.stiffness), "[low, high] with high > low")
    k = np.geomspace(spec.stiffness[0], spec.stiffness[1], spec.n_points)
    n_modes, note = spec.n_modes, ""
    if n_modes > rotor.n_dof // 2:  # at most half the lateral DOFs whirl forward (the note keeps its old words)
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
