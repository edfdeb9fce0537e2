"""``rotaflex rotor modal|campbell|ucs|unbalance|transient CONFIG.toml``: TOML -> analysis -> Result.

A config holds the rotor tables (``[[shaft]]``, ``[[disk]]``, ``[[point_mass]]``,
``[[bearing]]``, ``[material.<name>]``, ``free``) and one table per analysis (``[modal]``,
``[campbell]``, ``[ucs]``, ``[unbalance]``, ``[transient]``); each verb reads its own table
(defaults when absent). Speeds are given in rpm (``speed_rpm``) and converted to rad/s here,
once. For sweeps, ``analysis = "campbell"`` (etc.) at top level selects the analysis of
:func:`run_case` (domain ``rotor_fe``).
"""

from __future__ import annotations

import json
import time
from dataclasses import asdict, dataclass, field
from typing import Literal

import numpy as np
import xarray as xr

from rotaflex.core.config import from_mapping, param, unknown_key
from rotaflex.core.errors import InputError
from rotaflex.rotor.fe.model import ROTOR_KEYS, RPM, Bearing, Disk, Material, PointMass, Rotor, Shaft
from rotaflex.rotor.fe.results import CampbellResult, ModalResult, TransientResult, UCSResult, UnbalanceResult

DOFS = ["x", "y", "theta_x", "theta_y"]


@dataclass(frozen=True)
class UnbalanceMass:
    """An unbalance u = m e at a station."""

    magnitude: float = param(unit="kg m", ge=0, doc="unbalance m e")
    node: int | None = param(None, ge=0)
    position: float | None = param(None, unit="m")
    phase_deg: float = param(0.0, unit="deg", doc="angle of the unbalance at t = 0")


@dataclass(frozen=True)
class ModalSpec:
    """Modal analysis: damped natural frequencies and mode shapes at one speed."""

    speed_rpm: float = param(0.0, unit="rpm", ge=0, doc="spin speed")
    n_modes: int = param(8, ge=1, doc="number of modes reported")


@dataclass(frozen=True)
class CampbellSpec:
    """Campbell diagram: natural frequencies over a speed range."""

    speed_rpm: tuple[float, float] = param((0.0, 10000.0), unit="rpm", ge=0, doc="speed range start, stop")
    n_speeds: int = param(50, ge=2)
    n_modes: int = param(8, ge=1)
    harmonics: tuple[float, ...] = param((1.0,), gt=0, doc="excitation orders drawn and crossed (1 = 1X)")
    reduce: int | None = param(None, ge=2, doc="solve in a basis of this many undamped modes (faster)")


@dataclass(frozen=True)
class UCSSpec:
    """Undamped critical speed map over a range of bearing stiffness."""

    stiffness: tuple[float, float] = param((1e5, 1e10), unit="N/m", gt=0, doc="bearing stiffness range (log)")
    n_points: int = param(40, ge=2)
    n_modes: int = param(4, ge=1)


@dataclass(frozen=True)
class UnbalanceSpec:
    """Steady unbalance response over a speed range."""

    speed_rpm: tuple[float, float] = param((0.0, 10000.0), unit="rpm", ge=0)
    n_speeds: int = param(500, ge=2)
    probes: tuple[int, ...] = param((), ge=0, doc="probe nodes (default: the unbalance nodes)")
    operating_speed_rpm: float | None = param(None, unit="rpm", gt=0, doc="for the separation margin")
    mass: tuple[UnbalanceMass, ...] = param(())


@dataclass(frozen=True)
class TransientSpec:
    """Time response of the rotor-bearing system."""

    speed_rpm: tuple[float, float] = param((0.0, 0.0), unit="rpm", ge=0, doc="speed at start and end (ramp)")
    duration: float = param(1.0, unit="s", gt=0)
    n_output: int = param(2001, ge=2)
    method: Literal["modal", "direct"] = param("modal")
    n_modes: int = param(20, ge=1, doc="modes kept by the modal method")
    steps_per_output: int = param(4, ge=1, doc="Newmark steps per output interval (direct method)")
    probes: tuple[int, ...] = param((), ge=0)
    large_rotation: tuple[int, ...] = param((), ge=0, doc="disk nodes with exact large-tilt kinematics")
    large_rotation_model: Literal["euler_123", "quaternion"] = param(
        "euler_123",
        doc="euler_123: exact 1-2-3 tilt of the node (constant spin speed, singular at 90 deg); quaternion: "
        "rigid disk with Euler parameters on a hub spring (free spin, any attitude; modal, constant speed)",
    )
    hub_stiffness: float | None = param(
        None, unit="N m/rad", ge=0.0, doc="quaternion disks' hub bending stiffness (default 1000 x the node's)"
    )
    mass: tuple[UnbalanceMass, ...] = param(())


ANALYSES = {
    "modal": ModalSpec,
    "campbell": CampbellSpec,
    "ucs": UCSSpec,
    "unbalance": UnbalanceSpec,
    "transient": TransientSpec,
}


@dataclass(frozen=True)
class FECase:
    """Root schema of an FE rotor case file (rotor tables plus analysis tables)."""

    shaft: tuple[Shaft, ...] = param()
    disk: tuple[Disk, ...] = param(())
    point_mass: tuple[PointMass, ...] = param(())
    bearing: tuple[Bearing, ...] = param(())
    material: dict[str, Material] = param({})
    free: bool = param(False)
    analysis: Literal["modal", "campbell", "ucs", "unbalance", "transient"] | None = param(None)
    modal: ModalSpec = field(default_factory=ModalSpec)
    campbell: CampbellSpec = field(default_factory=CampbellSpec)
    ucs: UCSSpec = field(default_factory=UCSSpec)
    unbalance: UnbalanceSpec = field(default_factory=UnbalanceSpec)
    transient: TransientSpec = field(default_factory=TransientSpec)


SCHEMA = FECase


def parse(config: dict, analysis: str):
    """Rotor and the ``analysis`` spec of a parsed config (unknown top-level keys rejected)."""
    allowed = (*ROTOR_KEYS, *ANALYSES, "analysis")
    for key in config:
        if key not in allowed:
            raise unknown_key(key, config[key], allowed)
    rotor = Rotor.from_mapping({k: v for k, v in config.items() if k in ROTOR_KEYS})
    spec = from_mapping(ANALYSES[analysis], config.get(analysis, {}), analysis)
    return rotor, spec


def _speeds(rng, n, where):
    if rng[1] <= rng[0]:
        raise InputError(f"{where}.speed_rpm", list(rng), "[start, stop] with stop > start")
    return np.linspace(rng[0], rng[1], n) * RPM


def _unbalances(rotor, masses, where):
    return [
        (rotor.station(m.node, m.position, f"{where}.mass[{i}]"), m.magnitude, np.radians(m.phase_deg))
        for i, m in enumerate(masses)
    ]


def _attrs(config, t0, extra, message):
    return {
        "status": "success",
        "message": message,
        "wall_time": time.perf_counter() - t0,
        "config": json.dumps(config, default=str),
        "summary_extra": json.dumps(extra, default=float),
    }


def run_modal(config: dict, *, progress: bool = False) -> ModalResult:
    """Modes at ``[modal] speed_rpm``."""
    from rotaflex.rotor.fe.modal import modal

    t0 = time.perf_counter()
    rotor, spec = parse(config, "modal")
    m = modal(rotor, spec.speed_rpm * RPM, spec.n_modes)
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

    wt, wa = torsional_modes(rotor, spec.n_modes)[0], axial_modes(rotor, spec.n_modes)[0]
    ds["torsional_frequency"] = ("uncoupled_mode", wt, {"units": "rad/s", "long_name": "torsional (0: rigid)"})
    ds["axial_frequency"] = ("uncoupled_mode", wa, {"units": "rad/s", "long_name": "axial (0: rigid)"})
    extra = {f"mode_{k}_frequency_hz": {"value": float(m.wn[0, k] / (2 * np.pi)), "unit": "Hz"} for k in range(nm)}
    if wt.size > 1:
        extra["first_torsional_frequency_hz"] = {"value": float(wt[1] / (2 * np.pi)), "unit": "Hz"}
        extra["first_axial_frequency_hz"] = {"value": float(wa[1] / (2 * np.pi)), "unit": "Hz"}
    extra.update({f"mode_{k}_whirl": {"value": str(m.whirl[0, k]), "unit": ""} for k in range(nm)})
    unstable = int(np.sum(m.log_dec[0] < 0))
    msg = f"{nm} modes at {spec.speed_rpm:g} rpm; lowest {m.wn[0, 0] / (2 * np.pi):.4g} Hz; {unstable} unstable"
    ds.attrs.update(_attrs(config, t0, extra, msg))
    return ModalResult(ds)


def run_campbell(config: dict, *, progress: bool = False) -> CampbellResult:
    """Campbell diagram over ``[campbell] speed_rpm`` with MAC tracking."""
    from rotaflex.rotor.fe.modal import campbell

    t0 = time.perf_counter()
    rotor, spec = parse(config, "campbell")
    speeds = _speeds(spec.speed_rpm, spec.n_speeds, "campbell")
    c = campbell(rotor, speeds, spec.n_modes, spec.harmonics, reduce=spec.reduce)
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
        coords={"speed": ("speed", speeds, {"units": "rad/s"}), "mode": np.arange(spec.n_modes)},
    )
    extra = {
        f"critical_{i}_rpm": {
            "value": cr["speed"] / RPM,
            "unit": "rpm",
            "whirl": cr["whirl"],
            "harmonic": cr["harmonic"],
        }
        for i, cr in enumerate(c.critical)
    }
    extra["unstable_modes"] = {"value": len(c.unstable), "unit": ""}
    extra.update(
        {f"unstable_mode_{u['mode']}_onset_rpm": {"value": u["speed"] / RPM, "unit": "rpm"} for u in c.unstable}
    )
    fw = [cr for cr in c.critical if cr["whirl"] == "forward" and cr["harmonic"] == 1]
    msg = (
        f"{spec.n_modes} modes over {spec.n_speeds} speeds; forward 1X critical speeds [rpm]: "
        + (", ".join(f"{cr['speed'] / RPM:.0f}" for cr in fw) or "none")
        + (f"; {len(c.unstable)} unstable mode(s)" if c.unstable else "")
    )
    ds.attrs.update(_attrs(config, t0, extra, msg))
    ds.attrs["critical_speeds"] = json.dumps(c.critical)
    ds.attrs["unstable"] = json.dumps(c.unstable)
    ds.attrs["harmonics"] = json.dumps(list(spec.harmonics))
    return CampbellResult(ds)


def run_ucs(config: dict, *, progress: bool = False) -> UCSResult:
    """Undamped critical speed map over ``[ucs] stiffness``."""
    from rotaflex.rotor.fe.modal import ucs_map

    t0 = time.perf_counter()
    rotor, spec = parse(config, "ucs")
    if spec.stiffness[1] <= spec.stiffness[0]:
        raise InputError("ucs.stiffness", list(spec.stiffness), "[low, high] with high > low")
    k = np.geomspace(spec.stiffness[0], spec.stiffness[1], spec.n_points)
    w = ucs_map(rotor, k, spec.n_modes)
    ds = xr.Dataset(
        {"critical_speed": (("stiffness", "mode"), w, {"units": "rad/s"})},
        coords={"stiffness": ("stiffness", k, {"units": "N/m"}), "mode": np.arange(spec.n_modes)},
    )
    ds.attrs.update(_attrs(config, t0, {}, f"{spec.n_points} stiffness values, {spec.n_modes} critical speeds each"))
    return UCSResult(ds)


def run_unbalance(config: dict, *, progress: bool = False) -> UnbalanceResult:
    """Unbalance response (Bode) at the probes, peaks with amplification factor and margin."""
    from rotaflex.rotor.fe.response import peaks, unbalance_response

    t0 = time.perf_counter()
    rotor, spec = parse(config, "unbalance")
    if not spec.mass:
        raise InputError("unbalance.mass", "<missing>", "at least one [[unbalance.mass]] table")
    ub = _unbalances(rotor, spec.mass, "unbalance")
    probes = list(spec.probes) or sorted({u[0] for u in ub})
    for p in probes:
        if p >= rotor.n_nodes:
            raise InputError("unbalance.probes", p, f"existing nodes 0..{rotor.n_nodes - 1}")
    speeds = _speeds(spec.speed_rpm, spec.n_speeds, "unbalance")
    r = unbalance_response(rotor, speeds, ub)
    X = np.stack([r.at(p)[0] for p in probes], 1)
    Y = np.stack([r.at(p)[1] for p in probes], 1)
    major = np.stack([r.major_axis(p) for p in probes], 1)
    op = spec.operating_speed_rpm * RPM if spec.operating_speed_rpm else None
    pk = peaks(speeds, major[:, 0], op)
    u = {"units": "m"}
    ds = xr.Dataset(
        {
            "x_real": (("speed", "probe"), X.real, u),
            "x_imag": (("speed", "probe"), X.imag, u),
            "y_real": (("speed", "probe"), Y.real, u),
            "y_imag": (("speed", "probe"), Y.imag, u),
            "x_amplitude": (("speed", "probe"), np.abs(X), u),
            "x_phase": (("speed", "probe"), np.angle(X), {"units": "rad", "long_name": "phase of x (lag < 0)"}),
            "major_axis": (("speed", "probe"), major, {**u, "long_name": "orbit semi-major axis"}),
            "speed_rpm": ("speed", speeds / RPM, {"units": "rpm"}),
        },
        coords={"speed": ("speed", speeds, {"units": "rad/s"}), "probe": probes},
    )
    extra = {}
    for i, p in enumerate(pk):
        extra[f"peak_{i}_speed_rpm"] = {"value": p["speed"] / RPM, "unit": "rpm"}
        extra[f"peak_{i}_amplification_factor"] = {"value": p["af"], "unit": ""}
        extra[f"peak_{i}_separation_margin"] = {"value": p["sm_percent"], "unit": "%"}
        extra[f"peak_{i}_required_separation_margin"] = {"value": p["sm_required_percent"], "unit": "%"}
        extra[f"peak_{i}_meets_api684_margin"] = {"value": p["sm_ok"], "unit": ""}
    msg = f"{spec.n_speeds} speeds, {len(probes)} probes; peaks [rpm]: " + (
        ", ".join(f"{p['speed'] / RPM:.0f} (AF {p['af']:.1f})" for p in pk) or "none"
    )
    ds.attrs.update(_attrs(config, t0, extra, msg))
    ds.attrs["peaks"] = json.dumps(pk)
    return UnbalanceResult(ds)


def run_transient(config: dict, *, progress: bool = False) -> TransientResult:
    """Time response: constant speed or linear run-up, with unbalance."""
    from rotaflex.rotor.fe.transient import transient

    t0 = time.perf_counter()
    rotor, spec = parse(config, "transient")
    ub = _unbalances(rotor, spec.mass, "transient")
    probes = list(spec.probes) or (sorted({u[0] for u in ub}) or [rotor.n_nodes // 2])
    for p in probes:
        if p >= rotor.n_nodes:
            raise InputError("transient.probes", p, f"existing nodes 0..{rotor.n_nodes - 1}")
    tr = transient(
        rotor,
        spec.duration,
        speed_start=spec.speed_rpm[0] * RPM,
        speed_end=spec.speed_rpm[1] * RPM,
        unbalance=ub,
        n_output=spec.n_output,
        method=spec.method,
        n_modes=spec.n_modes,
        steps_per_output=spec.steps_per_output,
        large_rotation=spec.large_rotation,
        large_rotation_model=spec.large_rotation_model,
        hub_stiffness=spec.hub_stiffness,
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
    amax = np.max(np.hypot(disp[..., 0], disp[..., 1]), 0)
    i = int(np.argmax(np.hypot(disp[:, 0, 0], disp[:, 0, 1])))
    extra = {
        "max_radial_displacement": {"value": float(amax.max()), "unit": "m"},
        "speed_at_max_rpm": {"value": float(tr.speed[i] / RPM), "unit": "rpm"},
        "function_evaluations": {"value": tr.nfev, "unit": ""},
    }
    if tr.quaternion is not None:
        extra["quaternion_norm_drift"] = {"value": tr.quaternion_norm_drift, "unit": "1"}
    ds.attrs.update(_attrs(config, t0, extra, tr.message))
    ds.attrs["nfev"] = tr.nfev
    return TransientResult(ds)


RUNNERS = {
    "modal": run_modal,
    "campbell": run_campbell,
    "ucs": run_ucs,
    "unbalance": run_unbalance,
    "transient": run_transient,
}


def run_case(config: dict, *, progress: bool = False):
    """Sweep entry point (domain ``rotor_fe``): runs the analysis named by ``analysis``."""
    name = config.get("analysis")
    if name not in RUNNERS:
        raise InputError("analysis", name if name is not None else "<missing>", "one of " + ", ".join(RUNNERS))
    return RUNNERS[name](config, progress=progress)


def validate_config(config: dict) -> None:
    """Sweep hook: reject a bad case before any worker starts."""
    name = config.get("analysis")
    if name not in RUNNERS:
        raise InputError("analysis", name if name is not None else "<missing>", "one of " + ", ".join(RUNNERS))
    parse(config, name)


def schema_dict() -> dict:
    """Defaults of the analysis tables (for generated templates)."""
    return {k: asdict(v()) for k, v in ANALYSES.items()}
