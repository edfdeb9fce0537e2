"""Runners of the FE rotor verbs ``unbalance`` and ``transient``: parsed config -> response ->
Result (speeds converted from rpm once, in :mod:`~rotaflex.rotor.fe.case_config`).
"""

from __future__ import annotations

import json
import time

import numpy as np
import xarray as xr

from rotaflex.core.errors import InputError
from rotaflex.core.units import rad_s_to_rpm, rpm_to_rad_s
from rotaflex.rotor.fe.case_config import clamp_modes, parse, speed_range, unbalances
from rotaflex.rotor.fe.case_output import add_fluid_film_tables, pinned, progress_callback, summary_attrs
from rotaflex.rotor.fe.results import TransientResult, UnbalanceResult

__all__ = ["PEAK_FLOOR", "run_transient", "run_unbalance"]

#: response maxima below this fraction of the largest response of any probe are not rated
#: (round-off ripples of 1e-13 um at a probe on a mode's node line would otherwise be "criticals")
PEAK_FLOOR = 1e-3


@pinned
def run_unbalance(config: dict, *, progress: bool = False) -> UnbalanceResult:
    """Unbalance response (Bode) at the probes; peaks with AF and API separation-margin verdicts."""
    from rotaflex.rotor.fe.api import vibration_limit
    from rotaflex.rotor.fe.response import peaks, unbalance_response

    t0 = time.perf_counter()
    rotor, spec = parse(config, "unbalance")
    bands, n_max = _bands(spec)
    ub, made = _unbalance_planes(rotor, spec, n_max)
    if not ub:
        raise InputError(
            "unbalance.mass", "<missing>", "at least one [[unbalance.mass]] table, or balance_grade / api_unbalance"
        )
    probes = list(spec.probes) or sorted({u[0] for u in ub})
    for p in probes:
        if p >= rotor.n_nodes:
            raise InputError("unbalance.probes", p, f"existing nodes 0..{rotor.n_nodes - 1}")
    speeds = speed_range(spec.speed_rpm, spec.n_speeds, "unbalance")
    with progress_callback(progress, speeds.size, "unbalance", "speed") as report:
        r = unbalance_response(rotor, speeds, ub, progress=report)
    X = np.stack([r.at(p)[0] for p in probes], 1)
    Y = np.stack([r.at(p)[1] for p in probes], 1)
    major = np.stack([r.major_axis(p) for p in probes], 1)
    from rotaflex.rotor.fe.api import merge_probe_peaks, rate_peaks

    # every probe's peaks; per critical, the probe with the largest response governs
    # (maxima below PEAK_FLOOR of the largest response anywhere are round-off, e.g. a probe on a node line)
    floor = PEAK_FLOOR * major.max()
    per_probe = {p: peaks(speeds, major[:, j], range_end=True) for j, p in enumerate(probes)}
    pk = merge_probe_peaks({p: [q for q in v if q["amplitude"] >= floor] for p, v in per_probe.items()})
    if bands:
        pk = rate_peaks(pk, bands)
    u = {"units": "m"}
    ds = xr.Dataset(
        {
            "x_real": (("speed", "probe"), X.real, u),
            "x_imag": (("speed", "probe"), X.imag, u),
            "y_real": (("speed", "probe"), Y.real, u),
            "y_imag": (("speed", "probe"), Y.imag, u),
            "x_amplitude": (("speed", "probe"), np.abs(X), u),
            "y_amplitude": (("speed", "probe"), np.abs(Y), u),
            "x_phase": (("speed", "probe"), np.angle(X), {"units": "rad", "long_name": "phase of x (lag < 0)"}),
            "y_phase": (("speed", "probe"), np.angle(Y), {"units": "rad", "long_name": "phase of y (lag < 0)"}),
            "major_axis": (("speed", "probe"), major, {**u, "long_name": "orbit semi-major axis"}),
            "speed_rpm": ("speed", rad_s_to_rpm(speeds), {"units": "rpm"}),
        },
        coords={"speed": ("speed", speeds, {"units": "rad/s"}), "probe": probes},
    )
    if spec.probe_angles_deg:
        a = np.radians(np.asarray(spec.probe_angles_deg))
        P = X[..., None] * np.cos(a) + Y[..., None] * np.sin(a)  # displacement along each probe's axis
        ds = ds.assign_coords(angle=("angle", np.asarray(spec.probe_angles_deg), {"units": "deg"}))
        ds["probe_amplitude"] = (("speed", "probe", "angle"), np.abs(P), {**u, "long_name": "probe reading, 0-peak"})
        ds["probe_phase"] = (("speed", "probe", "angle"), np.angle(P), {"units": "rad"})
    extra = {"unbalance_planes": {"value": made, "unit": "g mm, deg"}} if made else {}
    limit = None
    if n_max:
        limit = vibration_limit(rad_s_to_rpm(n_max))
        ds.attrs["vibration_limit"] = limit
        pp = 2 * major.max(0)
        extra["max_continuous_speed"] = {"value": rad_s_to_rpm(n_max), "unit": "rpm"}
        extra["vibration_limit_pp"] = {"value": limit, "unit": "m", "rule": "API 617: 25.4 sqrt(12000/N) um <= 25.4"}
        in_band = np.zeros(speeds.size, bool)
        for lo, hi in bands:
            in_band |= (speeds >= lo) & (speeds <= hi)
        if in_band.any():
            pp_band = 2 * major[in_band].max(0)
            extra["max_pp_in_operating_range"] = {"value": pp_band.tolist(), "unit": "m", "probes": probes}
            extra["meets_vibration_limit"] = {"value": bool(np.all(pp_band <= limit)), "unit": ""}
        extra["max_pp_overall"] = {"value": pp.tolist(), "unit": "m", "probes": probes}
    extra.update(peak_entries(pk))
    verdict = margin_verdict(pk, bands)
    if bands:
        from rotaflex.rotor.fe.api import stability_summary

        verdict += "; " + stability_summary(rotor, bands, extra)
        reasons = [
            f"critical at {rad_s_to_rpm(p['speed']):.0f} rpm misses its separation margin" for p in pk if not p["sm_ok"]
        ]
        if not extra.get("meets_vibration_limit", {"value": True})["value"]:
            reasons.append("vibration above the API 617 limit in the operating range")
        if not extra["stable_in_operating_range"]["value"]:
            reasons.append("a mode is unstable (log dec < 0) in the operating range")
        extra["verdict"] = {"value": "fail" if reasons else "pass", "unit": "", "reasons": reasons}
        verdict += "; verdict: " + ("FAIL" if reasons else "pass")
    rated = [p for p in pk if p["kind"] == "resonance"]
    msg = (
        f"{spec.n_speeds} speeds, {len(probes)} probes; peaks [rpm]: "
        + (", ".join(f"{rad_s_to_rpm(p['speed']):.0f} (AF {p['af']:.1f}, node {p['probe']})" for p in rated) or "none")
        + "".join(
            f"; {p['kind']}: {p['amplitude'] * 1e6:.3g} um at {rad_s_to_rpm(p['speed']):.0f} rpm (node {p['probe']})"
            for p in pk
            if p["kind"] != "resonance"
        )
        + verdict
    )
    ds.attrs.update(summary_attrs(config, t0, extra, msg))
    ds.attrs["peaks"] = json.dumps(pk)
    ds.attrs["bands"] = json.dumps(bands)
    return UnbalanceResult(add_fluid_film_tables(ds, rotor))


def _bands(spec) -> tuple[list[tuple[float, float]], float | None]:
    """Operating bands [rad/s] and the maximum continuous speed [rad/s] (None: no operating speed)."""
    from rotaflex.rotor.fe.api import check_bands

    given = [k for k in ("operating_speed_rpm", "operating_range_rpm") if getattr(spec, k) is not None]
    given += ["operating_bands_rpm"] if spec.operating_bands_rpm else []
    if len(given) > 1:
        raise InputError(
            f"unbalance.{given[1]}", getattr(spec, given[1]), f"absent when {given[0]} is given (one of them)"
        )
    if spec.operating_range_rpm is not None:
        bands = check_bands([spec.operating_range_rpm], "unbalance.operating_range_rpm")
    elif spec.operating_bands_rpm:
        bands = check_bands(spec.operating_bands_rpm, "unbalance.operating_bands_rpm")
    elif spec.operating_speed_rpm is not None:
        bands = [(rpm_to_rad_s(spec.operating_speed_rpm), rpm_to_rad_s(spec.operating_speed_rpm))]
    else:
        return [], None
    return bands, max(hi for _, hi in bands)


def _unbalance_planes(rotor, spec, n_max):
    """Explicit [[unbalance.mass]] plus the ISO-grade or API unbalance of ``planes``; and a record of the latter."""
    ub = unbalances(rotor, spec.mass, "unbalance")
    if spec.balance_grade is None and not spec.api_unbalance:
        return ub, []
    from rotaflex.rotor.fe.api import api_plane_unbalance, arrangement_phases, iso_specific_unbalance, plane_masses

    key = "balance_grade" if spec.balance_grade is not None else "api_unbalance"
    if spec.balance_grade is not None and spec.api_unbalance:
        raise InputError("unbalance.api_unbalance", True, "false when balance_grade is given (one of them)")
    if n_max is None:
        raise InputError(
            "unbalance.operating_range_rpm", "<missing>", f"the operating speed range: {key} needs the maximum speed"
        )
    planes = list(spec.planes) or sorted({n for n, _ in rotor.disks}) or [rotor.n_nodes // 2]
    for p in planes:
        if p >= rotor.n_nodes:
            raise InputError("unbalance.planes", p, f"existing nodes 0..{rotor.n_nodes - 1}")
    share = plane_masses(rotor, planes)  # [kg]
    shape = None
    if spec.arrangement == "mode":
        from rotaflex.rotor.fe.modal import modal

        m = modal(rotor, n_max, min(rotor.n_dof, 4 * (spec.arrangement_mode + 2)))
        fw = np.flatnonzero(m.forward_fraction[0] >= 0.5)
        if spec.arrangement_mode >= fw.size:
            raise InputError("unbalance.arrangement_mode", spec.arrangement_mode, f"0..{fw.size - 1} (forward modes)")
        shape = m.shape[0, fw[spec.arrangement_mode]]
    if spec.balance_grade is not None:
        U = iso_specific_unbalance(spec.balance_grade, n_max) * share  # g mm
    else:
        U = api_plane_unbalance(rotor, planes, rad_s_to_rpm(n_max), shape)
    U = U * spec.unbalance_scale
    ph = np.where(U > 0, arrangement_phases(rotor, planes, shape), 0.0)  # a plane on a node line: no phase
    made = [
        {"node": int(p), "magnitude_g_mm": float(u), "phase_deg": float(np.degrees(a)), "mass_share_kg": float(w)}
        for p, u, a, w in zip(planes, U, ph, share, strict=True)
    ]
    return ub + [(p, u * 1e-6, a) for p, u, a in zip(planes, U, ph, strict=True)], made


@pinned
def run_transient(config: dict, *, progress: bool = False) -> TransientResult:
    """Time response: constant speed or linear run-up, with unbalance."""
    from rotaflex.rotor.fe.transient import transient

    t0 = time.perf_counter()
    rotor, spec = parse(config, "transient")
    n_modes, note = clamp_modes(rotor, spec.n_modes, "transient.n_modes")
    ub = unbalances(rotor, spec.mass, "transient")
    probes = list(spec.probes) or (sorted({u[0] for u in ub}) or [rotor.n_nodes // 2])
    for p in probes:
        if p >= rotor.n_nodes:
            raise InputError("transient.probes", p, f"existing nodes 0..{rotor.n_nodes - 1}")
    with progress_callback(progress, spec.duration, "transient", "s") as report:
        tr = transient(
            rotor,
            spec.duration,
            speed_start=rpm_to_rad_s(spec.speed_rpm[0]),
            speed_end=rpm_to_rad_s(spec.speed_rpm[1]),
            unbalance=ub,
            n_output=spec.n_output,
            method=spec.method,
            n_modes=n_modes,
            steps_per_output=spec.steps_per_output,
            large_rotation=spec.large_rotation,
            large_rotation_model=spec.large_rotation_model,
            hub_stiffness=spec.hub_stiffness,
            progress=report,
        )
    disp = np.stack([tr.q[:, 4 * p : 4 * p + 2] for p in probes], 1)
    ds = xr.Dataset(
        {
            "displacement": (("time", "probe", "axis"), disp, {"units": "m"}),
            "speed": ("time", tr.speed, {"units": "rad/s"}),
        },
        coords={"time": ("time", tr.time, {"units": "s"}), "probe": probes, "axis": ["x", "y"]},
    )
    if tr.quaternion is not None:
        nodes = [el.node for el in tr.disks]
        ds["disk_quaternion"] = (("time", "disk", "component"), tr.quaternion, {"units": "1"})
        ds["disk_body_rate"] = (("time", "disk", "body_axis"), tr.omega, {"units": "rad/s"})
        ds = ds.assign_coords(disk=nodes, component=["e0", "e1", "e2", "e3"], body_axis=["1", "2", "3"])
    extra, msg = transient_peak(tr, disp, [f"node {p}" for p in probes])
    if tr.quaternion is not None:
        extra["quaternion_norm_drift"] = {"value": tr.quaternion_norm_drift, "unit": "1"}
    if note:
        extra["note"] = {"value": note, "unit": ""}
    ds.attrs.update(summary_attrs(config, t0, extra, msg + (f"; {note}" if note else "")))
    ds.attrs["nfev"] = tr.nfev
    return TransientResult(add_fluid_film_tables(ds, rotor))


def transient_peak(tr, disp: np.ndarray, names: list[str]) -> tuple[dict, str]:
    """summary.json entries and the one-line outcome of a time response (rotor and machine).

    ``disp`` (time, probe, axis) [m] at the probes ``names``; the largest radial displacement
    over all probes, the probe and the (drive) speed at which it occurs, and the integrator.
    """
    radial = np.hypot(disp[..., 0], disp[..., 1])
    i, j = np.unravel_index(int(np.argmax(radial)), radial.shape)
    rpm = float(rad_s_to_rpm(tr.speed[i]))
    extra = {
        "max_radial_displacement": {"value": float(radial[i, j]), "unit": "m", "probe": names[j]},
        "speed_at_max_rpm": {"value": rpm, "unit": "rpm", "note": "speed at the largest radial displacement"},
        "function_evaluations": {"value": tr.nfev, "unit": ""},
    }
    r0, r1 = (float(rad_s_to_rpm(tr.speed[k])) for k in (0, -1))
    run = f"{r0:.6g} rpm" if r0 == r1 else f"{r0:.6g} -> {r1:.6g} rpm"
    method, _, detail = tr.message.partition(": ")  # "modal: <the ODE solver's own words>"
    how = detail if method == "direct" else f"{method}, {tr.nfev} evaluations"
    msg = (
        f"{run} over {tr.time[-1] - tr.time[0]:.4g} s: largest orbit radius {radial[i, j] * 1e6:.4g} um "
        f"at {names[j]}, {rpm:.6g} rpm, t = {tr.time[i]:.4g} s ({how})"
    )
    return extra, msg


def peak_entries(pk: list[dict]) -> dict:
    """summary.json entries ``peak_<i>_*`` of rated response peaks (``merge_probe_peaks`` /
    ``rate_peaks``): speed [rpm], amplitude, governing probe, AF, API 684 margins, position."""
    extra = {}
    for i, p in enumerate(pk):
        extra[f"peak_{i}_speed_rpm"] = {"value": rad_s_to_rpm(p["speed"]), "unit": "rpm", "kind": p["kind"]}
        extra[f"peak_{i}_amplitude"] = {"value": p["amplitude"], "unit": "m", "note": "orbit semi-major axis (0-pk)"}
        extra[f"peak_{i}_probe"] = {
            "value": p["probe"],
            "unit": "",
            "note": "the probe with the largest response at this peak (governs)",
            "probes": p["probes"],
            "af_by_probe": p["af_by_probe"],
        }
        extra[f"peak_{i}_amplification_factor"] = {"value": p["af"], "unit": ""}
        extra[f"peak_{i}_separation_margin"] = {"value": p.get("sm_percent", np.nan), "unit": "%"}
        extra[f"peak_{i}_required_separation_margin"] = {"value": p.get("sm_required_percent", np.nan), "unit": "%"}
        extra[f"peak_{i}_meets_api684_margin"] = {"value": p.get("sm_ok", np.nan), "unit": ""}
        if "position" in p:
            extra[f"peak_{i}_position"] = {
                "value": p["position"],
                "unit": "",
                "note": "relative to the operating bands",
            }
    return extra


def margin_verdict(pk: list[dict], bands) -> str:
    """ "; API margins: all met" or the peaks that miss their API 684 separation margin ("" when
    no operating bands or no peaks)."""
    if not (bands and pk):
        return ""
    fails = [p for p in pk if not p["sm_ok"]]
    return "; API margins: " + (
        "all met"
        if not fails
        else ", ".join(f"{rad_s_to_rpm(p['speed']):.0f} rpm fails ({p['position']})" for p in fails)
    )
