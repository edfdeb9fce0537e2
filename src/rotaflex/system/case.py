"""``rotaflex system modal|campbell|response|steady|unbalance|frf CONFIG.toml``: gearbox TOML -> analysis -> Result.

A config holds the model tables (``[[rotor]]`` with ``[[rotor.shaft]]``/``[[rotor.disk]]``/
``[[rotor.bearing]]``, ``[[gear_mesh]]``, ``[drive]``, ``[load]``; see :mod:`.model`) and one
table per analysis (``[modal]``, ``[campbell]``, ``[response]``, ``[steady]``), defaults when
absent. Speeds are the drive rotor's, in rpm (``speed_rpm``), converted to rad/s here, once.
For sweeps, ``analysis = "steady"`` (etc.) at top level selects the analysis of :func:`run_case`
(domain ``system``); ``rotaflex sweep --continuation steady.speed_rpm`` chains steady states.
"""

from __future__ import annotations

import json
import time
from dataclasses import asdict
from pathlib import Path

import numpy as np
import xarray as xr

from rotaflex.core.config import from_mapping
from rotaflex.core.errors import InputError
from rotaflex.core.limits import require_memory
from rotaflex.core.result import summary_attrs
from rotaflex.core.units import rad_s_to_rpm, rpm_to_rad_s
from rotaflex.system import helical
from rotaflex.system.case_specs import ANALYSES, SCHEMA, TorsionalSpec

__all__ = ["SCHEMA", "parse", "run_case", "validate_config"]
from rotaflex.system.model import MODEL_KEYS, Gearbox, drive_speed_rpm
from rotaflex.system.size import clamp_modes


def parse(config: dict, analysis: str, base=None):
    """Gearbox and the ``analysis`` spec of a parsed config (unknown top-level keys rejected)."""
    allowed = (*MODEL_KEYS, *ANALYSES, "analysis")
    for key in config:
        if key not in allowed:
            raise InputError(key, config[key], "no such key; allowed keys: " + ", ".join(allowed))
    box = _gearbox({k: v for k, v in config.items() if k in MODEL_KEYS}, base)
    spec = from_mapping(ANALYSES[analysis], config.get(analysis, {}), analysis)
    return box, spec


#: models built in this process, by content (a sweep's cases differ mostly in the analysis table)
_MODELS: dict[str, Gearbox] = {}


def _gearbox(model: dict, base) -> Gearbox:
    """:meth:`Gearbox.from_mapping`, reused when the same model (keys, values, base directory and
    the modification times of its pair files) was built before in this process. Gearbox is
    frozen, so a sweep's workers build each distinct model once instead of once per case."""
    try:
        text = json.dumps(model, sort_keys=True, default=repr)
    except (TypeError, ValueError):  # not plain data: no caching
        return Gearbox.from_mapping(model, base)
    stamps = []
    for m in model.get("gear_mesh", []) if isinstance(model.get("gear_mesh"), list) else []:
        f = m.get("pair_file") if isinstance(m, dict) else None
        if isinstance(f, str):
            path = Path(base or ".") / f
            stamps.append(path.stat().st_mtime_ns if path.exists() else None)
    key = f"{text}|{base}|{stamps}"
    box = _MODELS.get(key)
    if box is None:
        box = Gearbox.from_mapping(model, base)
        if len(_MODELS) >= 8:
            _MODELS.pop(next(iter(_MODELS)))
        _MODELS[key] = box
    return box


def _speed(box, value, where) -> float:
    v = value if value is not None else drive_speed_rpm(box)
    if v is None:
        raise InputError(f"{where}.speed_rpm", "<missing>", "a drive speed [rpm] (or a rotor's speed_rpm)")
    _check_drive_speed(box, float(v), f"{where}.speed_rpm", v)
    return rpm_to_rad_s(float(v))


def _ordered(rng, key: str, *, equal: bool = False) -> None:
    """Refuse a speed pair [rpm] out of order: ``[start, stop]`` with stop > start, or with
    ``equal`` a ``[min, max]`` with max >= min (InputError naming ``key``, the pair as typed)."""
    if rng[1] < rng[0] or (rng[1] == rng[0] and not equal):
        raise InputError(key, list(rng), "[min, max], max >= min" if equal else "[start, stop] with stop > start")


def _range(rng, n, where, box=None):
    _ordered(rng, f"{where}.speed_rpm")
    if box is not None:
        _check_drive_speed(box, float(rng[1]), f"{where}.speed_rpm", list(rng))
    return rpm_to_rad_s(np.linspace(rng[0], rng[1], n))


def _check_drive_speed(box, rpm: float, key: str, shown) -> None:
    """Refuse a drive speed at which some rotor passes its rim-speed bound
    (:func:`rotaflex.rotor.fe.bounds.max_speed`: hoop strain 1)."""
    from rotaflex.rotor.fe.bounds import max_speed

    limit = rad_s_to_rpm(min(max_speed(pr.rotor) / pr.ratio for pr in box.rotors))
    if not abs(rpm) <= limit:
        raise InputError(
            key,
            shown,
            f"drive speeds of at most {limit:.4g} rpm (there a rotor's rim speed reaches the bar wave speed "
            "sqrt(E/rho): a hoop strain of 1, far beyond any material)",
        )


def run_modal(config: dict, *, progress: bool = False):
    """Coupled modes at ``[modal] speed_rpm`` with the energy split of each mode."""
    from rotaflex.system.assembly import free_dofs
    from rotaflex.system.modal import modal
    from rotaflex.system.results import SystemModalResult

    t0 = time.perf_counter()
    box, spec = parse(config, "modal")
    w = _speed(box, spec.speed_rpm, "modal")
    n_modes, note = clamp_modes(spec.n_modes, free_dofs(box).size, "modal.n_modes")
    m = modal(box, w, n_modes)
    nm = m.eigenvalue.shape[1]
    ds = xr.Dataset(
        {
            "natural_frequency": ("mode", m.wn[0], {"units": "rad/s"}),
            "damped_frequency": ("mode", m.wd[0], {"units": "rad/s"}),
            "damping_ratio": ("mode", m.damping_ratio[0], {"units": "1"}),
            "energy": (("mode", "group"), m.energy[0], {"units": "1", "long_name": "kinetic-energy fraction"}),
            "mesh_energy": ("mode", m.mesh_energy[0], {"units": "1", "long_name": "mesh strain-energy fraction"}),
            "torsional_fraction": ("mode", m.torsional_fraction[0], {"units": "1"}),
            "shape_real": (("mode", "dof"), m.shape[0].real, {"units": "1", "long_name": "v^H M v = 1"}),
            "shape_imag": (("mode", "dof"), m.shape[0].imag, {"units": "1"}),
            "speed": ((), w, {"units": "rad/s", "long_name": "drive speed"}),
        },
        coords={"mode": np.arange(nm), "group": m.groups, "dof": np.arange(box.n_dof)},
    )
    extra = {}
    shares = helical.dataset_shares(box, ds, m.shape[0], w, ("mode",))
    for k in range(nm):
        extra[f"mode_{k}_frequency_hz"] = {"value": float(m.wn[0, k] / (2 * np.pi)), "unit": "Hz"}
        extra[f"mode_{k}_mesh_energy"] = {"value": float(m.mesh_energy[0, k]), "unit": "1"}
        extra[f"mode_{k}_torsional_fraction"] = {"value": float(m.torsional_fraction[0, k]), "unit": "1"}
        for key, v in shares.items():
            extra[f"mode_{k}_{key}"] = {"value": float(v[k]), "unit": "1"}
    k_mesh = int(np.argmax(m.mesh_energy[0]))
    mesh_msg = "no gear mesh"  # a train of couplings only
    if len(box.meshes):
        extra["mesh_mode"] = {"value": k_mesh, "unit": "", "frequency_hz": float(m.wn[0, k_mesh] / (2 * np.pi))}
        mesh_msg = (
            f"largest mesh energy: mode {k_mesh} ({m.wn[0, k_mesh] / (2 * np.pi):.4g} Hz, "
            f"{100 * m.mesh_energy[0, k_mesh]:.0f} %)"
        )
    if note:
        extra["note"] = {"value": note, "unit": ""}
    msg = (
        f"{nm} coupled modes at {rad_s_to_rpm(w):g} rpm; lowest {m.wn[0, 0] / (2 * np.pi):.4g} Hz; "
        + mesh_msg
        + (f"; {note}" if note else "")
    )
    ds.attrs.update(summary_attrs(config, t0, extra, msg))
    return SystemModalResult(ds)


def run_campbell(config: dict, *, progress: bool = False):
    """Campbell diagram over ``[campbell] speed_rpm`` with mesh-order lines and crossings."""
    from rotaflex.system.assembly import free_dofs
    from rotaflex.system.modal import campbell
    from rotaflex.system.results import SystemCampbellResult, campbell_dataset

    t0 = time.perf_counter()
    box, spec = parse(config, "campbell")
    speeds = _range(spec.speed_rpm, spec.n_speeds, "campbell", box)
    n_modes, note = clamp_modes(spec.n_modes, free_dofs(box).size, "campbell.n_modes")
    c = campbell(box, speeds, n_modes, spec.harmonics, reduce=spec.reduce)
    ds = campbell_dataset(c)
    helical.dataset_shares(box, ds, c.modes.shape, 0.0, ("speed", "mode"))
    mesh_x = [cr for cr in c.crossings if cr["line"].startswith("mesh")]
    extra = {
        f"crossing_{i}_rpm": {
            "value": rad_s_to_rpm(cr["speed"]),
            "unit": "rpm",
            "line": cr["line"],
            "frequency_hz": cr["frequency"] / (2 * np.pi),
            "mesh_energy": cr["mesh_energy"],
        }
        for i, cr in enumerate(mesh_x)
    }
    if note:
        extra["note"] = {"value": note, "unit": ""}
    strong = [cr for cr in mesh_x if cr["mesh_energy"] > 0.05]
    msg = f"{n_modes} modes over {spec.n_speeds} speeds; mesh-order crossings of mesh modes [rpm]: " + (
        ", ".join(f"{rad_s_to_rpm(cr['speed']):.0f} ({cr['line']})" for cr in strong[:8]) or "none"
    )
    msg += f"; {note}" if note else ""
    ds.attrs.update(summary_attrs(config, t0, extra, msg))
    return SystemCampbellResult(ds)


def _probes(box, probes, where: str = "response"):
    if not probes:
        out = []
        for m in box.meshes:
            out += [m.driver, m.driven]
        return out
    out = []
    for i, p in enumerate(probes):
        r = box.rotor_index(p.rotor, f"{where}.probes[{i}].rotor")
        nn = box.rotors[r].rotor.n_nodes
        if p.node >= nn:
            raise InputError(f"{where}.probes[{i}].node", p.node, f"an existing node 0..{nn - 1}")
        out.append((r, p.node))
    return out


def run_response(config: dict, *, progress: bool = False):
    """TE-harmonic response vs ``[response] speed_rpm``: DTE, mesh force, bearing forces, orbits."""
    from rotaflex.system.response import forced_response, orbit_semi_axes
    from rotaflex.system.results import SystemResponseResult

    t0 = time.perf_counter()
    box, spec = parse(config, "response")
    speeds = _range(spec.speed_rpm, spec.n_speeds, "response", box)
    probes = _probes(box, spec.probes)
    r = forced_response(
        box, speeds, harmonics=spec.harmonics, probes=probes, excitation=spec.excitation, cutoff=spec.cutoff
    )
    major, _ = orbit_semi_axes(r.orbit[..., 0], r.orbit[..., 1])
    dims = ("mesh", "speed", "harmonic")
    fb = np.sqrt(np.sum(np.abs(r.bearing_force) ** 2, -1))
    ds = xr.Dataset(
        {
            "frequency": (dims, r.frequency, {"units": "rad/s"}),
            "excitation": (("mesh", "harmonic"), np.abs(r.excitation), {"units": "m", "long_name": "TE harmonic"}),
            "dte": (dims, np.abs(r.dte), {"units": "m", "long_name": "DTE amplitude (twist part)"}),
            "deflection": (dims, np.abs(r.deflection), {"units": "m", "long_name": "dynamic mesh deflection"}),
            "mesh_force": (dims, np.abs(r.mesh_force), {"units": "N", "long_name": "dynamic mesh force amplitude"}),
            "bearing_force": ((*dims, "bearing"), fb, {"units": "N", "long_name": "|(Fx, Fy)| amplitude"}),
            "orbit_major": ((*dims, "probe"), major, {"units": "m", "long_name": "orbit semi-major axis"}),
            "static_force": ("mesh", r.static_force, {"units": "N"}),
            "speed_rpm": ("speed", rad_s_to_rpm(speeds), {"units": "rpm"}),
        },
        coords={
            "speed": ("speed", speeds, {"units": "rad/s"}),
            "harmonic": np.arange(1, spec.harmonics + 1),
            "mesh": np.arange(len(box.meshes)),
            "bearing": [f"{n}:{k}" for n, k in r.bearings],
            "probe": [f"{box.rotors[p[0]].name}:{p[1]}" for p in probes],
        },
    )
    # rms over harmonics of the dynamic mesh force, and the dynamic factor bound 1 + sum |F_h| / F_0
    f_sum = np.abs(r.mesh_force).sum(-1)
    i = int(np.argmax(f_sum[0]))
    extra = {
        "peak_dynamic_force": {"value": float(f_sum[0, i]), "unit": "N", "speed_rpm": float(rad_s_to_rpm(speeds[i]))},
        "peak_dynamic_factor_bound": {"value": float(1 + f_sum[0, i] / r.static_force[0]), "unit": "1"},
        "peak_bearing_force": {"value": float(fb.sum(2).max()), "unit": "N"},
        "peak_dte": {"value": float(np.abs(r.dte).sum(-1).max()), "unit": "m"},
    }
    if box.axial:
        from rotaflex.system.helical import mesh_axial_force

        fa = np.abs(mesh_axial_force(box, np.moveaxis(r.mesh_force, 0, -1)))
        ds["axial_mesh_force"] = (("speed", "harmonic", "mesh"), fa, {"units": "N", "long_name": "dynamic, amplitude"})
        fb_a = np.abs(r.axial_bearing_force)
        ds["axial_bearing_force"] = ((*dims, "thrust"), fb_a, {"units": "N", "long_name": "thrust, amplitude"})
        extra["peak_dynamic_axial_force"] = {"value": float(fa.sum(1).max()), "unit": "N"}
        extra["peak_axial_bearing_force"] = {"value": float(fb_a.sum(2).max()), "unit": "N"}
        helical.dataset_static(box, ds, extra, float(np.median(speeds)))
    msg = (
        f"{spec.n_speeds} speeds x {spec.harmonics} TE harmonics; largest dynamic mesh force "
        f"{f_sum[0, i]:.4g} N (sum over harmonics) at {rad_s_to_rpm(speeds[i]):.0f} rpm; static "
        f"{r.static_force[0]:.4g} N"
    )
    ds.attrs.update(summary_attrs(config, t0, extra, msg))
    return SystemResponseResult(ds)


def run_steady(config: dict, *, progress: bool = False, initial_state: dict | None = None):
    """Nonlinear steady state at ``[steady] speed_rpm`` (time domain); ``initial_state``: the
    ``final_state()`` of an earlier point (continuation)."""
    from rotaflex.system.results import SystemSteadyResult
    from rotaflex.system.steady import SteadySettings, steady_state

    t0 = time.perf_counter()
    box, spec = parse(config, "steady")
    w = _speed(box, spec.speed_rpm, "steady")
    st = SteadySettings(
        steps_per_cycle=spec.steps_per_cycle,
        min_cycles=spec.min_cycles,
        max_cycles=max(spec.max_cycles, spec.min_cycles),
        eval_cycles=spec.eval_cycles,
        tol=spec.tol,
        cutoff=spec.cutoff,
        harmonics=spec.harmonics,
        stiffness=None if spec.stiffness == "mesh" else spec.stiffness,
        max_steps=spec.max_steps,
    )
    s = steady_state(box, w, st, initial_state)
    spc = s.steps_per_cycle
    n = spc * (s.time.size // spc)
    F = s.force[:, 0]
    amp = _harmonics(F[-n:] if n else F, spc)
    ds = xr.Dataset(
        {
            "dte": (("time", "mesh"), s.dte, {"units": "m", "long_name": "dynamic transmission error (twist)"}),
            "deflection": (("time", "mesh"), s.deflection, {"units": "m"}),
            "mesh_force": (("time", "mesh"), s.force, {"units": "N"}),
            "bearing_force": (("time", "bearing", "axis"), s.bearing_force, {"units": "N"}),
            "static_force": ("mesh", s.static_force, {"units": "N"}),
            "state_q": ("dof", s.final_q, {"units": "m|rad"}),
            "state_qdot": ("dof", s.final_qdot, {"units": "m/s|rad/s"}),
            "state_phase": ("mesh", s.final_phase, {"units": "cycles"}),
            "speed": ((), w, {"units": "rad/s", "long_name": "drive speed"}),
        },
        coords={
            "time": ("time", s.time, {"units": "s"}),
            "mesh": np.arange(len(box.meshes)),
            "bearing": [f"{a}:{b}" for a, b in s.bearings],
            "axis": ["x", "y"],
            "dof": np.arange(box.n_dof),
        },
    )
    f0 = float(s.static_force[0])
    dte = s.dte[:, 0]
    extra = {
        "speed_rpm": {"value": rad_s_to_rpm(w), "unit": "rpm"},
        "mesh_frequency": {"value": s.mesh_frequency, "unit": "Hz"},
        "dynamic_factor": {"value": float(F.max() / f0), "unit": "1", "long_name": "max mesh force / static"},
        "force_max": {"value": float(F.max()), "unit": "N", "long_name": "largest mesh force (static + dynamic)"},
        "force_min": {
            "value": float(F.min()),
            "unit": "N",
            # a viscous mesh damper c d(delta)/dt acts while the flanks touch: as they separate
            # it pulls, so the total force dips below 0 in the steps before contact is lost
            "long_name": "smallest mesh force (static + dynamic); below 0: the mesh damper pulls as the "
            "teeth separate (contact lost where contact_loss_fraction > 0) or back-flank contact",
        },
        **{
            f"force_h{h}": {
                "value": float(amp[h - 1]),
                "unit": "N",
                "long_name": f"mesh force amplitude (0-pk) at {h}× mesh frequency",
            }
            for h in (1, 2, 3)
        },
        "dte_pp": {"value": float(dte.max() - dte.min()), "unit": "m"},
        "contact_loss_fraction": {
            "value": float(s.contact_loss[0]),
            "unit": "1",
            "long_name": "fraction of the evaluated samples with the teeth out of contact",
        },
        "bearing_force_max": {
            "value": float(np.abs(s.bearing_force).max()) if s.bearing_force.size else 0.0,
            "unit": "N",
        },
        "period_cycles": {"value": s.period, "unit": "mesh cycles", "long_name": "0: not periodic"},
        "change": {"value": s.change, "unit": "1"},
        "cycles": {"value": s.cycles, "unit": ""},
        "steps_per_cycle": {"value": spc, "unit": ""},
        "basis_size": {"value": s.basis_size, "unit": ""},
        "energy_balance_error": {"value": s.energy_error, "unit": "1"},
        "phase_shift_pp": {
            "value": float(np.ptp(s.phase_shift[:, 0])),
            "unit": "mesh cycles",
            "long_name": "pinion twist as mesh phase, peak-to-peak (left out by the nominal phase)",
        },
    }
    if box.axial:
        helical.dataset_steady(box, ds, extra, s, w)
    msg = (
        f"{rad_s_to_rpm(w):g} rpm: dynamic factor {F.max() / f0:.4f}, contact loss "
        f"{100 * s.contact_loss[0]:.1f} % of the "
        f"time, period {s.period} cycle(s) after {s.cycles} cycles ({spc} steps/cycle, basis {s.basis_size})"
    )
    ds.attrs.update(summary_attrs(config, t0, extra, msg))
    ds.attrs["state_time"] = 0.0
    ds.attrs["samples_per_cycle"] = spc
    ds.attrs["mesh_frequency"] = s.mesh_frequency
    return SystemSteadyResult(ds)


def _harmonics(x, spc, orders=(1, 2, 3)):
    """Amplitudes of x at multiples of the mesh frequency (whole cycles)."""
    n = (x.size // spc) * spc
    if n == 0:
        return np.full(len(orders), np.nan)
    seg = x[-n:]
    sp = np.fft.rfft(seg)
    nc = n // spc
    return np.array([2 * abs(sp[k * nc]) / n if k * nc < sp.size else np.nan for k in orders])


def _excitations(box, spec: TorsionalSpec) -> list[dict]:
    """The listed excitations with rotor and mesh indices (line frequency converted to rad/s)."""
    from rotaflex.system.torsion import default_excitations

    if not spec.excitation:
        return default_excitations(box)
    out = []
    for i, e in enumerate(spec.excitation):
        w = f"torsional.excitation[{i}]"
        d = {"kind": e.kind, "order": e.order, "name": e.name}
        if e.kind == "shaft":
            d["rotor"] = box.rotor_index(e.rotor, f"{w}.rotor")
        elif e.kind == "mesh":
            if e.mesh is None or e.mesh >= len(box.meshes):
                raise InputError(f"{w}.mesh", e.mesh, f"a [[gear_mesh]] index 0..{len(box.meshes) - 1}")
            d["mesh"] = e.mesh
        else:
            if e.frequency_hz is None:
                raise InputError(f"{w}.frequency_hz", "<missing>", "a frequency [Hz] > 0 for kind = 'fixed'")
            d["frequency"] = 2 * np.pi * e.frequency_hz
        out.append(d)
    return out


def run_torsional(config: dict, *, progress: bool = False):
    """Torsional natural frequencies and shapes, interference diagram, API 684 separation margins."""
    from rotaflex.system.results import TorsionalResult, torsional_dataset
    from rotaflex.system.torsion import (
        crossings,
        excitation_lines,
        separation_margins,
        torsional_model,
        torsional_modes,
    )

    t0 = time.perf_counter()
    box, spec = parse(config, "torsional")
    if spec.operating_speed_rpm is None:
        n = drive_speed_rpm(box)
        if n is None:
            raise InputError(
                "torsional.operating_speed_rpm", "<missing>", "[min, max] drive speed [rpm] (or a speed_rpm)"
            )
        op = (rpm_to_rad_s(n), rpm_to_rad_s(n))
    else:
        _ordered(spec.operating_speed_rpm, "torsional.operating_speed_rpm", equal=True)
        op = tuple(rpm_to_rad_s(spec.operating_speed_rpm))
    if spec.speed_rpm is not None:
        _ordered(spec.speed_rpm, "torsional.speed_rpm")
    # the default range 0 ... 1.25 x the operating maximum (> 0 rpm by the schema) is never empty
    rng = (0.0, 1.25 * op[1]) if spec.speed_rpm is None else tuple(rpm_to_rad_s(spec.speed_rpm))
    model = torsional_model(box)
    w, shape = torsional_modes(model, spec.n_modes)
    lines = excitation_lines(box, _excitations(box, spec))
    cr = crossings(w, lines, rng)
    margin, passed = separation_margins(w, lines, op, spec.margin)
    ds = torsional_dataset(model, w, shape, lines, margin, passed, op, rng, spec.margin)
    bad = [(k, j) for k in range(w.size) for j in range(len(lines)) if not passed[k, j]]
    extra = {f"mode_{k}_frequency_hz": {"value": float(w[k] / (2 * np.pi)), "unit": "Hz"} for k in range(w.size)}
    extra["api684_verdict"] = {"value": "pass" if not bad else "fail", "unit": "", "required_margin": spec.margin}
    extra["api684_failures"] = {"value": len(bad), "unit": "", "long_name": "(mode, excitation) pairs under the margin"}
    for i, (k, j) in enumerate(bad):
        extra[f"failure_{i}"] = {"value": float(margin[k, j]), "unit": "1", "mode": k, "line": lines[j]["name"]}
    for i, c in enumerate(cr):
        extra[f"crossing_{i}_rpm"] = {
            "value": rad_s_to_rpm(c["speed"]),
            "unit": "rpm",
            "line": c["line"],
            "mode": c["mode"],
        }
    verdict = "pass" if not bad else f"fail ({len(bad)} mode/excitation pairs under {100 * spec.margin:g} %)"
    msg = (
        f"{w.size} torsional modes, lowest {w[0] / (2 * np.pi):.4g} Hz; {len(cr)} crossings in "
        f"{rad_s_to_rpm(rng[0]):.0f}-{rad_s_to_rpm(rng[1]):.0f} rpm; API 684 separation: {verdict}"
    )
    ds.attrs.update(summary_attrs(config, t0, extra, msg))
    ds.attrs["crossings"] = json.dumps(cr)
    return TorsionalResult(ds)


def run_startup(config: dict, *, progress: bool = False):
    """Run-up from rest under the [drive] torque-speed curve against the [load] (torsional model)."""
    from rotaflex.system.results import StartupResult, startup_dataset
    from rotaflex.system.startup import Motor, check_start, startup
    from rotaflex.system.torsion import torsional_model

    t0 = time.perf_counter()
    box, spec = parse(config, "startup")
    d = box.spec.drive
    if len(d.curve_speed_rpm) < 2 or len(d.curve_torque) != len(d.curve_speed_rpm):
        raise InputError(
            "drive.curve_torque", list(d.curve_torque), "a torque [N m] per drive.curve_speed_rpm (>= 2 points)"
        )
    n = rpm_to_rad_s(d.curve_speed_rpm)
    if np.any(np.diff(n) <= 0):
        raise InputError("drive.curve_speed_rpm", list(d.curve_speed_rpm), "increasing speeds")
    motor = Motor(n, np.asarray(d.curve_torque, float), d.pulsating_torque, 2 * np.pi * d.line_frequency_hz, d.poles)
    ld = box.spec.load
    load = (ld.torque, ld.quadratic) if ld is not None else (0.0, 0.0)
    n_steady = check_start(box, motor, load)
    fmax = None if spec.max_frequency_hz is None else 2 * np.pi * spec.max_frequency_hz
    model = torsional_model(box)
    # histories written: twists, rates, twists relative to the drive, shaft torques (< n), a few more
    n_tw = model.dofs.size
    require_memory("startup.n_out", spec.n_out, 8.0 * spec.n_out * (5 * n_tw + 12), "the start-up histories")
    run = startup(box, model, motor, load, spec.duration, spec.n_out, fmax, spec.rtol)
    ds, extra = startup_dataset(box, model, run, n_steady)
    msg = (
        f"{spec.duration:g} s run-up: drive at {extra['final_speed_rpm']['value']:.1f} rpm "
        f"(motor = load at {rad_s_to_rpm(n_steady):.1f} rpm); {run.n_modes} torsional modes kept; "
        f"energy balance {extra['energy_balance_error']['value']:.1e} of the motor work"
    )
    ds.attrs.update(summary_attrs(config, t0, extra, msg))
    return StartupResult(ds)


def run_unbalance(config: dict, *, progress: bool = False):
    """Unbalance response vs ``[unbalance] speed_rpm`` of the drive
    (:func:`rotaflex.system.unbalance.unbalance_result`)."""
    from rotaflex.system.unbalance import unbalance_result

    t0 = time.perf_counter()
    box, spec = parse(config, "unbalance")
    probes = _probes(box, spec.probes, "unbalance") if spec.probes else None
    speeds = _range(spec.speed_rpm, spec.n_speeds, "unbalance", box)
    return unbalance_result(config, box, spec, probes, speeds, t0, progress)


def run_frf(config: dict, *, progress: bool = False):
    """FRFs of ``[frf]`` at a drive speed (:func:`rotaflex.system.frf.frf_result`)."""
    from rotaflex.system.frf import frf_result

    t0 = time.perf_counter()
    box, spec = parse(config, "frf")
    _check_drive_speed(box, spec.speed_rpm, "frf.speed_rpm", spec.speed_rpm)
    return frf_result(config, box, spec, t0)


def run_stability(config: dict, *, progress: bool = False):
    """API 617 Level I and II of ``[stability]`` at the drive's MCS
    (:func:`rotaflex.system.stability.stability_result`)."""
    from rotaflex.system.stability import stability_result

    t0 = time.perf_counter()
    box, spec = parse(config, "stability")
    if spec.speed_rpm is not None:
        _check_drive_speed(box, spec.speed_rpm, "stability.speed_rpm", spec.speed_rpm)
    return stability_result(config, box, spec, t0)


def run_static(config: dict, *, progress: bool = False):
    """Static state of ``[static]`` at a drive speed (:func:`rotaflex.system.static.static_result`)."""
    from rotaflex.system.static import default_drive_speed, static_result

    t0 = time.perf_counter()
    box, spec = parse(config, "static")
    rpm = spec.speed_rpm if spec.speed_rpm is not None else drive_speed_rpm(box)
    speed = default_drive_speed(box) if rpm is None else _speed(box, rpm, "static")
    return static_result(config, box, spec, speed, t0)


def run_ucs(config: dict, *, progress: bool = False):
    """Undamped critical speed map over ``[ucs] stiffness`` (:func:`rotaflex.system.ucs.ucs_result`)."""
    from rotaflex.system.ucs import ucs_result

    t0 = time.perf_counter()
    box, spec = parse(config, "ucs")
    rpm = spec.speed_rpm if spec.speed_rpm is not None else drive_speed_rpm(box)
    if rpm is not None:
        _check_drive_speed(box, float(rpm), "ucs.speed_rpm", rpm)
    return ucs_result(config, box, spec, None if rpm is None else rpm_to_rad_s(float(rpm)), t0, progress)


def run_transient(config: dict, *, progress: bool = False):
    """Time response of ``[transient]``: unbalance, constant drive speed or linear ramp
    (:func:`rotaflex.system.transient.transient_result`)."""
    from rotaflex.system.transient import transient_result

    t0 = time.perf_counter()
    box, spec = parse(config, "transient")
    probes = _probes(box, spec.probes, "transient") if spec.probes else None
    _check_drive_speed(box, max(spec.speed_rpm), "transient.speed_rpm", list(spec.speed_rpm))
    return transient_result(config, box, spec, probes, t0, progress)


def run_case(config: dict, *, progress: bool = False):
    """Sweep entry point (domain ``system``): runs the analysis named by ``analysis``, the function
    that ``rotaflex system <analysis>`` runs (:data:`rotaflex.core.domains.COMMANDS`: each verb is
    listed there once, its settings table in :data:`ANALYSES`)."""
    from rotaflex.core.domains import command

    name = config.get("analysis")
    if name not in ANALYSES:
        raise InputError("analysis", name if name is not None else "<missing>", "one of " + ", ".join(ANALYSES))
    return command("system", name)({k: v for k, v in config.items() if k != "analysis"}, progress=progress)


def validate_config(config: dict) -> None:
    """Check a config without running it: the model (pairs, centres, stations, ratios) and every
    analysis table present."""
    name = config.get("analysis", "modal")
    if name not in ANALYSES:
        raise InputError("analysis", name, "one of " + ", ".join(ANALYSES))
    body = {k: v for k, v in config.items() if k != "analysis"}
    parse(body, name)
    for other, spec in ANALYSES.items():
        if other in body:
            from_mapping(spec, body[other], other)


def resolve_paths(config: dict, base) -> dict:
    """``pair_file`` paths made relative to the case file's directory."""
    meshes = config.get("gear_mesh")
    if not isinstance(meshes, list):
        return config
    out = []
    for m in meshes:
        if isinstance(m, dict) and isinstance(m.get("pair_file"), str) and not Path(m["pair_file"]).is_absolute():
            m = {**m, "pair_file": str(Path(base) / m["pair_file"])}
        out.append(m)
    return {**config, "gear_mesh": out}


def schema_dict() -> dict:
    return {k: asdict(v()) for k, v in ANALYSES.items()}


def sweep_example(fast: bool) -> tuple[dict, dict]:
    """Sweep hook (``rotaflex reproduce sweep``): steady states of the example gearbox vs speed."""
    from rotaflex.core.config import load_toml
    from rotaflex.core.examples import example_path

    cfg = load_toml(example_path("system/gearbox.toml"))
    cfg = {k: v for k, v in cfg.items() if k in MODEL_KEYS}
    cfg["analysis"] = "steady"
    speeds = [2000.0, 3500.0] if fast else [float(v) for v in np.linspace(1000.0, 6000.0, 11)]
    cfg["steady"] = {"speed_rpm": speeds[0], "min_cycles": 20, "max_cycles": 40 if fast else 200, "eval_cycles": 4}
    return cfg, {"steady.speed_rpm": speeds}
