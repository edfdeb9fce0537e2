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
from contextlib import contextmanager
from dataclasses import asdict, dataclass, field
from typing import Literal

import numpy as np
import xarray as xr

from rotaflex.core.config import from_mapping, param, unknown_key
from rotaflex.core.errors import InputError
from rotaflex.core.result import import_xarray
from rotaflex.rotor.fe.modal import STABILITY_TOL
from rotaflex.rotor.fe.model import ROTOR_KEYS, RPM, Bearing, Disk, Material, PointMass, Rotor, Shaft
from rotaflex.rotor.fe.results import CampbellResult, ModalResult, TransientResult, UCSResult, UnbalanceResult

import_xarray()  # xarray's deferred imports (dask.array) now, not inside the analyses' timers

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
    critical_solve: Literal["direct", "interpolated"] = param(
        "direct", doc="critical speeds: root of omega_d = h Omega (Brent) or linear interpolation between speeds"
    )
    operating_range_rpm: tuple[float, float] | None = param(
        None, unit="rpm", gt=0, doc="[minimum, maximum] continuous speed: shaded, with the API margins marked"
    )


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
    operating_speed_rpm: float | None = param(None, unit="rpm", gt=0, doc="one operating speed (margins from it)")
    operating_range_rpm: tuple[float, float] | None = param(
        None, unit="rpm", gt=0, doc="[minimum, maximum] continuous speed (API margins below/above the band)"
    )
    operating_bands_rpm: tuple[tuple[float, float], ...] = param(
        (), unit="rpm", gt=0, doc="several operating bands [[min, max], ...] (instead of operating_range_rpm)"
    )
    balance_grade: float | None = param(
        None, unit="mm/s", gt=0, doc="ISO 21940 grade G: U = (1000 G / Omega_max) m_plane [g mm] per plane"
    )
    api_unbalance: bool = param(False, doc="API unbalance U = 6350 W / N_max [g mm] per plane (W: journal load [kg])")
    unbalance_scale: float = param(1.0, gt=0, doc="multiplier of the G or API unbalance (API 617 analyses use 2)")
    planes: tuple[int, ...] = param((), ge=0, doc="nodes of the G/API unbalance planes (default: the disk nodes)")
    arrangement: Literal["in_phase", "mode"] = param(
        "in_phase", doc="G/API unbalance phases: all 0, or following the arrangement_mode's shape (worst case)"
    )
    arrangement_mode: int = param(0, ge=0, doc="forward mode (0: lowest) at the maximum speed whose shape sets phases")
    probe_angles_deg: tuple[float, ...] = param(
        (), unit="deg", doc="probe directions from x toward y, at every probe node (e.g. [45, 135])"
    )
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


@dataclass(frozen=True)
class PointLoad:
    """A static point force at a station."""

    node: int | None = param(None, ge=0, doc="node number (or give position)")
    position: float | None = param(None, unit="m")
    fx: float = param(0.0, unit="N", doc="force in x")
    fy: float = param(0.0, unit="N", doc="force in y")


@dataclass(frozen=True)
class StaticSpec:
    """Static deflection under gravity and point loads; bearing reactions, shear, moment."""

    gravity: float = param(9.80665, unit="m/s^2", ge=0, doc="acceleration of gravity (0: point loads only)")
    gravity_direction: tuple[float, float] = param((0.0, -1.0), doc="direction of gravity [g_x, g_y] (default -y)")
    speed_rpm: float | None = param(
        None, unit="rpm", ge=0, doc="speed of the bearing coefficients (default 0 or the table's lowest)"
    )
    load: tuple[PointLoad, ...] = param(())


@dataclass(frozen=True)
class FRFPair:
    """One frequency response: output DOF per unit force (or moment) at the input DOF."""

    input_node: int = param(ge=0, doc="node of the force")
    input_direction: Literal["x", "y", "theta_x", "theta_y"] = param("x", doc="force (x, y) or moment (theta_*)")
    output_node: int | None = param(None, ge=0, doc="node of the response (default: input_node)")
    output_direction: Literal["x", "y", "theta_x", "theta_y"] | None = param(
        None, doc="response DOF (default: input_direction)"
    )


@dataclass(frozen=True)
class FRFSpec:
    """Frequency response functions at one spin speed (Bode and Nyquist)."""

    speed_rpm: float = param(0.0, unit="rpm", ge=0, doc="spin speed")
    frequency_hz: tuple[float, float] = param((1.0, 200.0), unit="Hz", ge=0, doc="excitation frequency range")
    n_frequencies: int = param(2000, ge=2)
    kind: Literal["receptance", "mobility", "accelerance"] = param(
        "receptance", doc="H = X/F [m/N], i w H [m/(N s)] or -w^2 H [m/(N s^2)]"
    )
    pair: tuple[FRFPair, ...] = param((), doc="default: direct x and y at the first disk (or mid-shaft) node")


ANALYSES = {
    "static": StaticSpec,
    "modal": ModalSpec,
    "campbell": CampbellSpec,
    "ucs": UCSSpec,
    "unbalance": UnbalanceSpec,
    "transient": TransientSpec,
    "frf": FRFSpec,
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
    max_dof: int = param(4004, ge=4, doc="refuse models with more lateral DOFs; raise it deliberately")
    analysis: Literal["static", "modal", "campbell", "ucs", "unbalance", "transient", "frf"] | None = param(None)
    static: StaticSpec = field(default_factory=StaticSpec)
    modal: ModalSpec = field(default_factory=ModalSpec)
    campbell: CampbellSpec = field(default_factory=CampbellSpec)
    ucs: UCSSpec = field(default_factory=UCSSpec)
    unbalance: UnbalanceSpec = field(default_factory=UnbalanceSpec)
    transient: TransientSpec = field(default_factory=TransientSpec)
    frf: FRFSpec = field(default_factory=FRFSpec)


SCHEMA = FECase


def parse(config: dict, analysis: str):
    """Rotor and the ``analysis`` spec of a parsed config (unknown top-level keys rejected)."""
    allowed = (*ROTOR_KEYS, *ANALYSES, "analysis")
    for key in config:
        if key not in allowed:
            raise unknown_key(key, config[key], allowed)
    rotor = Rotor.from_mapping({k: v for k, v in config.items() if k in ROTOR_KEYS})
    st = from_mapping(StaticSpec, config.get("static", {}), "static")
    if rotor.static_load_bearings:  # fluid-film load = "static": from [static] (gravity, point loads)
        default = StaticSpec()
        same = (st.gravity, tuple(st.gravity_direction), st.speed_rpm, st.load) == (
            default.gravity,
            tuple(default.gravity_direction),
            None,
            (),
        )
        # the rotor resolved itself under standard gravity when it was built; redo only if [static] differs
        rotor = rotor.resolved if same else _resolve_static_loads(rotor, st)
    spec = from_mapping(ANALYSES[analysis], config.get(analysis, {}), analysis)
    _check_size(rotor, spec, analysis)
    return rotor, spec


def _resolve_static_loads(rotor: Rotor, st: StaticSpec) -> Rotor:
    """The rotor with its ``load = "static"`` bearings loaded as the static analysis of ``st`` says."""
    from rotaflex.rotor.fe.bearings.static_load import resolve_static_loads

    loads = [(rotor.station(ld.node, ld.position, f"static.load[{i}]"), ld.fx, ld.fy) for i, ld in enumerate(st.load)]
    speed = None if st.speed_rpm is None else st.speed_rpm * RPM
    return resolve_static_loads(
        rotor, gravity=st.gravity, direction=st.gravity_direction, loads=loads, speed=speed
    ).rotor


#: largest counts accepted (speeds, output points, steps); memory is checked separately against --max-memory
MAX_POINTS = 1_000_000
MAX_STEPS = 100_000_000


def _check_size(rotor: Rotor, spec, analysis: str) -> None:
    """Estimate the points and memory an analysis will need and refuse what is beyond the limits."""
    from rotaflex.core.limits import require, require_memory

    n = rotor.n_dof
    state = 8.0 * (2 * n) ** 2  # one real state matrix [bytes]
    if analysis == "modal":
        require_memory("modal.n_modes", spec.n_modes, 6 * state, "the state eigenproblem")
    elif analysis == "campbell":
        require("campbell.n_speeds", spec.n_speeds, spec.n_speeds, MAX_POINTS, "speeds")
        m = min(spec.reduce or n, n)
        require_memory("campbell.n_speeds", spec.n_speeds, spec.n_speeds * 40.0 * (2 * m) ** 2, "the eigenproblems")
    elif analysis == "ucs":
        require("ucs.n_points", spec.n_points, spec.n_points, MAX_POINTS, "stiffness values")
    elif analysis == "unbalance":
        require("unbalance.n_speeds", spec.n_speeds, spec.n_speeds, MAX_POINTS, "speeds")
        require_memory("unbalance.n_speeds", spec.n_speeds, spec.n_speeds * 64.0 * n**2, "the batched solve")
    elif analysis == "transient":
        require("transient.n_output", spec.n_output, spec.n_output, MAX_POINTS * 10, "output points")
        steps = spec.n_output * spec.steps_per_output if spec.method == "direct" else spec.n_output
        require("transient.steps_per_output", spec.steps_per_output, steps, MAX_STEPS, "integration steps")
        require_memory("transient.n_output", spec.n_output, spec.n_output * 3 * 8.0 * n + 6 * state, "the history")
    elif analysis == "frf":
        require("frf.n_frequencies", spec.n_frequencies, spec.n_frequencies, MAX_POINTS, "frequencies")
        require_memory("frf.n_frequencies", spec.n_frequencies, spec.n_frequencies * 48.0 * n**2, "the batched solve")
    elif analysis == "static":
        require_memory("shaft", "<mesh>", 4 * 8.0 * n**2, "the static solve")


def clamp_modes(rotor, n_modes: int, field: str) -> tuple[int, str]:
    """``n_modes`` clamped to the lateral DOF count (a model has at most n_dof oscillatory modes), and a note."""
    if n_modes <= rotor.n_dof:
        return n_modes, ""
    return rotor.n_dof, f"{field} = {n_modes} clamped to {rotor.n_dof} (the model has {rotor.n_dof} lateral DOFs)"


def _speeds(rng, n, where):
    if rng[1] <= rng[0]:
        raise InputError(f"{where}.speed_rpm", list(rng), "[start, stop] with stop > start")
    return np.linspace(rng[0], rng[1], n) * RPM


def _unbalances(rotor, masses, where):
    return [
        (rotor.station(m.node, m.position, f"{where}.mass[{i}]"), m.magnitude, np.radians(m.phase_deg))
        for i, m in enumerate(masses)
    ]


def add_fluid_film_tables(ds: xr.Dataset, rotor: Rotor) -> xr.Dataset:
    """``ds`` with the coefficient table of every fluid-film bearing of ``rotor`` (variables ``ff_*``).

    Dimensions ``fluid_film`` (bearing names) and ``ff_speed`` (table index; a shorter table is
    padded with NaN): speed, eccentricity ratio, attitude angle, journal position, Sommerfeld
    number and the 8 coefficients with units (:meth:`FluidFilmTable.to_dataset`), plus the static
    load each bearing carries (``ff_load_x``, ``ff_load_y`` [N]) and its node.
    """
    parts, names = [], []
    for i, (b, (node, _, el)) in enumerate(zip(rotor.resolved.bearing, rotor.bearings, strict=True)):
        if el.table is None:
            continue
        t = el.table.to_dataset().drop_vars("speed").rename({"speed": "ff_speed"})
        t = t.rename({k: f"ff_{k}" for k in t.data_vars})
        t["ff_node"] = node
        t["ff_load_x"] = xr.DataArray(b.fluid_film.load[0], attrs={"units": "N"})
        t["ff_load_y"] = xr.DataArray(b.fluid_film.load[1], attrs={"units": "N"})
        parts.append(t)
        names.append(b.name or f"bearing[{i}]")
    if not parts:
        return ds
    tables = xr.concat(parts, dim="fluid_film", join="outer", combine_attrs="override")
    tables = tables.assign_coords(fluid_film=names)
    for k in tables.data_vars:  # concat keeps the first part's attributes; make sure of the units
        tables[k].attrs = parts[0][k].attrs
    return ds.merge(tables)


def _oil_whip(rotor: Rotor, unstable: list[dict]) -> dict:
    """Summary entry of the oil-whip onset (lowest speed at which a mode goes unstable) on fluid film."""
    if not unstable or not any(el.table is not None for _, _, el in rotor.bearings):
        return {}
    first = min(unstable, key=lambda u: u["speed"])
    return {"oil_whip_onset_rpm": {"value": first["speed"] / RPM, "unit": "rpm", "mode": first["mode"]}}


def _pinned(run):
    """Run an analysis with the BLAS/OpenMP pools pinned to one thread (``ROTAFLEX_BLAS_THREADS``
    overrides), as the CLI and the sweep workers do, so that library calls get the same speed:
    the matrices are small and idle pool threads spinning between calls cost far more than
    they gain on a shared machine (the example's Campbell with direct critical speeds: 13.2 s
    CPU unpinned, see docs/fluid-film-bearings.md)."""
    import functools

    @functools.wraps(run)
    def wrapper(config: dict, *, progress: bool = False):
        import os

        from threadpoolctl import threadpool_limits

        with threadpool_limits(limits=int(os.environ.get("ROTAFLEX_BLAS_THREADS", "1"))):
            return run(config, progress=progress)

    return wrapper


@contextmanager
def _progress(enabled: bool, total: float, desc: str, unit: str):
    """``progress(done, total)`` for a solver: a :class:`~rotaflex.core.progress.Progress` bar on a
    terminal, one line per 10 % when stderr is not one; None (nothing shown) when disabled."""
    if not enabled:
        yield None
        return
    from rotaflex.core.progress import Progress

    with Progress(total, desc, unit) as bar:
        yield bar.update


def _attrs(config, t0, extra, message):
    return {
        "status": "success",
        "message": message,
        "wall_time": time.perf_counter() - t0,
        "config": json.dumps(config, default=str),
        "summary_extra": json.dumps(extra, default=float),
    }


@_pinned
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
    ds.attrs.update(_attrs(config, t0, extra, msg))
    return ModalResult(add_fluid_film_tables(ds, rotor))


@_pinned
def run_campbell(config: dict, *, progress: bool = False) -> CampbellResult:
    """Campbell diagram over ``[campbell] speed_rpm`` with MAC tracking."""
    from rotaflex.rotor.fe.modal import campbell

    t0 = time.perf_counter()
    rotor, spec = parse(config, "campbell")
    speeds = _speeds(spec.speed_rpm, spec.n_speeds, "campbell")
    n_modes, note = clamp_modes(rotor, spec.n_modes, "campbell.n_modes")
    reduce = spec.reduce if spec.reduce is None or spec.reduce < rotor.n_dof else None
    if reduce is None and spec.reduce is not None:
        note = (note + "; " if note else "") + f"campbell.reduce = {spec.reduce} >= the {rotor.n_dof} DOFs: full solve"
    with _progress(progress, speeds.size, "campbell", "speed") as report:
        c = campbell(rotor, speeds, n_modes, spec.harmonics, reduce=reduce, progress=report)
    critical = c.critical
    if spec.critical_solve == "direct" and reduce is None:
        from rotaflex.rotor.fe.critical import critical_speeds

        with _progress(progress, 1, "critical speeds", "crossing") as report:
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
    extra |= _oil_whip(rotor, c.unstable)
    extra.update(
        {f"unstable_mode_{u['mode']}_onset_rpm": {"value": u["speed"] / RPM, "unit": "rpm"} for u in c.unstable}
    )
    fw = [cr for cr in critical if cr["whirl"] == "forward" and cr["harmonic"] == 1]
    msg = (
        f"{n_modes} modes over {spec.n_speeds} speeds; forward 1X critical speeds [rpm]: "
        + (", ".join(f"{cr['speed'] / RPM:.0f}" for cr in fw) or "none")
        + (f"; {len(c.unstable)} unstable mode(s)" if c.unstable else "")
    )
    ds.attrs.update(_attrs(config, t0, extra, msg))
    ds.attrs["critical_speeds"] = json.dumps(critical)
    if spec.operating_range_rpm is not None:
        from rotaflex.rotor.fe.api import check_bands

        ds.attrs["bands"] = json.dumps(check_bands([spec.operating_range_rpm], "campbell.operating_range_rpm"))
    ds.attrs["unstable"] = json.dumps(c.unstable)
    ds.attrs["harmonics"] = json.dumps(list(spec.harmonics))
    return CampbellResult(add_fluid_film_tables(ds, rotor))


@_pinned
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
    with _progress(progress, k.size, "ucs", "stiffness") as report:
        w = ucs_map(rotor, k, n_modes, progress=report)
    ds = xr.Dataset(
        {"critical_speed": (("stiffness", "mode"), w, {"units": "rad/s"})},
        coords={"stiffness": ("stiffness", k, {"units": "N/m"}), "mode": np.arange(n_modes)},
    )
    extra = {"note": {"value": note, "unit": ""}} if note else {}
    msg = f"{spec.n_points} stiffness values, {n_modes} critical speeds each" + (f"; {note}" if note else "")
    ds.attrs.update(_attrs(config, t0, extra, msg))
    return UCSResult(add_fluid_film_tables(ds, rotor))


@_pinned
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
    speeds = _speeds(spec.speed_rpm, spec.n_speeds, "unbalance")
    with _progress(progress, speeds.size, "unbalance", "speed") as report:
        r = unbalance_response(rotor, speeds, ub, progress=report)
    X = np.stack([r.at(p)[0] for p in probes], 1)
    Y = np.stack([r.at(p)[1] for p in probes], 1)
    major = np.stack([r.major_axis(p) for p in probes], 1)
    pk = peaks(speeds, major[:, 0])
    if bands:
        from rotaflex.rotor.fe.api import rate_peaks

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
            "speed_rpm": ("speed", speeds / RPM, {"units": "rpm"}),
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
        limit = vibration_limit(n_max / RPM)
        ds.attrs["vibration_limit"] = limit
        pp = 2 * major.max(0)
        extra["max_continuous_speed"] = {"value": n_max / RPM, "unit": "rpm"}
        extra["vibration_limit_pp"] = {"value": limit, "unit": "m", "rule": "API 617: 25.4 sqrt(12000/N) um <= 25.4"}
        in_band = np.zeros(speeds.size, bool)
        for lo, hi in bands:
            in_band |= (speeds >= lo) & (speeds <= hi)
        if in_band.any():
            pp_band = 2 * major[in_band].max(0)
            extra["max_pp_in_operating_range"] = {"value": pp_band.tolist(), "unit": "m", "probes": probes}
            extra["meets_vibration_limit"] = {"value": bool(np.all(pp_band <= limit)), "unit": ""}
        extra["max_pp_overall"] = {"value": pp.tolist(), "unit": "m", "probes": probes}
    for i, p in enumerate(pk):
        extra[f"peak_{i}_speed_rpm"] = {"value": p["speed"] / RPM, "unit": "rpm"}
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
    verdict = ""
    if bands and pk:
        fails = [p for p in pk if not p["sm_ok"]]
        verdict = "; API margins: " + (
            "all met" if not fails else ", ".join(f"{p['speed'] / RPM:.0f} rpm fails ({p['position']})" for p in fails)
        )
    msg = (
        f"{spec.n_speeds} speeds, {len(probes)} probes; peaks [rpm]: "
        + (", ".join(f"{p['speed'] / RPM:.0f} (AF {p['af']:.1f})" for p in pk) or "none")
        + verdict
    )
    ds.attrs.update(_attrs(config, t0, extra, msg))
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
        bands = [(spec.operating_speed_rpm * RPM, spec.operating_speed_rpm * RPM)]
    else:
        return [], None
    return bands, max(hi for _, hi in bands)


def _unbalance_planes(rotor, spec, n_max):
    """Explicit [[unbalance.mass]] plus the ISO-grade or API unbalance of ``planes``; and a record of the latter."""
    ub = _unbalances(rotor, spec.mass, "unbalance")
    if spec.balance_grade is None and not spec.api_unbalance:
        return ub, []
    from rotaflex.rotor.fe.api import api_unbalance, arrangement_phases, iso_specific_unbalance, plane_masses
    from rotaflex.rotor.fe.static import static_analysis

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
    share = plane_masses(rotor, planes, static_analysis(rotor, gravity=1.0).reactions)  # [kg]
    if spec.balance_grade is not None:
        U = iso_specific_unbalance(spec.balance_grade, n_max) * share  # g mm
    else:
        U = np.array([api_unbalance(w, n_max / RPM) for w in share])
    U = U * spec.unbalance_scale
    shape = None
    if spec.arrangement == "mode":
        from rotaflex.rotor.fe.modal import modal

        m = modal(rotor, n_max, min(rotor.n_dof, 4 * (spec.arrangement_mode + 2)))
        fw = np.flatnonzero(m.forward_fraction[0] >= 0.5)
        if spec.arrangement_mode >= fw.size:
            raise InputError("unbalance.arrangement_mode", spec.arrangement_mode, f"0..{fw.size - 1} (forward modes)")
        shape = m.shape[0, fw[spec.arrangement_mode]]
    ph = arrangement_phases(rotor, planes, shape)
    made = [
        {"node": int(p), "magnitude_g_mm": float(u), "phase_deg": float(np.degrees(a)), "mass_share_kg": float(w)}
        for p, u, a, w in zip(planes, U, ph, share, strict=True)
    ]
    return ub + [(p, u * 1e-6, a) for p, u, a in zip(planes, U, ph, strict=True)], made


@_pinned
def run_transient(config: dict, *, progress: bool = False) -> TransientResult:
    """Time response: constant speed or linear run-up, with unbalance."""
    from rotaflex.rotor.fe.transient import transient

    t0 = time.perf_counter()
    rotor, spec = parse(config, "transient")
    n_modes, note = clamp_modes(rotor, spec.n_modes, "transient.n_modes")
    ub = _unbalances(rotor, spec.mass, "transient")
    probes = list(spec.probes) or (sorted({u[0] for u in ub}) or [rotor.n_nodes // 2])
    for p in probes:
        if p >= rotor.n_nodes:
            raise InputError("transient.probes", p, f"existing nodes 0..{rotor.n_nodes - 1}")
    with _progress(progress, spec.duration, "transient", "s") as report:
        tr = transient(
            rotor,
            spec.duration,
            speed_start=spec.speed_rpm[0] * RPM,
            speed_end=spec.speed_rpm[1] * RPM,
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
    amax = np.max(np.hypot(disp[..., 0], disp[..., 1]), 0)
    i = int(np.argmax(np.hypot(disp[:, 0, 0], disp[:, 0, 1])))
    extra = {
        "max_radial_displacement": {"value": float(amax.max()), "unit": "m"},
        "speed_at_max_rpm": {"value": float(tr.speed[i] / RPM), "unit": "rpm"},
        "function_evaluations": {"value": tr.nfev, "unit": ""},
    }
    if tr.quaternion is not None:
        extra["quaternion_norm_drift"] = {"value": tr.quaternion_norm_drift, "unit": "1"}
    if note:
        extra["note"] = {"value": note, "unit": ""}
    ds.attrs.update(_attrs(config, t0, extra, tr.message + (f"; {note}" if note else "")))
    ds.attrs["nfev"] = tr.nfev
    return TransientResult(add_fluid_film_tables(ds, rotor))


@_pinned
def run_static(config: dict, *, progress: bool = False):
    """Static deflection, bearing reactions, shear force and bending moment (``[static]``)."""
    from rotaflex.rotor.fe.verbs import run_static as _run

    return _run(config, progress=progress)


@_pinned
def run_frf(config: dict, *, progress: bool = False):
    """Frequency response functions of ``[frf]`` (receptance, mobility or accelerance)."""
    from rotaflex.rotor.fe.verbs import run_frf as _run

    return _run(config, progress=progress)


RUNNERS = {
    "static": run_static,
    "frf": run_frf,
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
