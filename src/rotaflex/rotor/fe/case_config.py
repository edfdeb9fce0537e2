"""The FE rotor case file: its schema (rotor tables plus one table per analysis), reading it into
a :class:`~rotaflex.rotor.fe.model.Rotor` and an analysis spec, the size limits, and the
conversions of its rpm and degree keys to SI (done here, once).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from rotaflex.core.config import from_mapping, param, unknown_key
from rotaflex.core.errors import InputError
from rotaflex.core.units import rpm_to_rad_s
from rotaflex.rotor.fe.bounds import check_frequencies, check_speeds
from rotaflex.rotor.fe.model import ROTOR_KEYS, Bearing, Disk, Material, PointMass, Rotor, Shaft
from rotaflex.rotor.fe.stability import StabilitySpec

__all__ = [
    "ANALYSES",
    "MAX_POINTS",
    "MAX_STEPS",
    "SCHEMA",
    "CampbellSpec",
    "FECase",
    "FRFPair",
    "FRFSpec",
    "ModalSpec",
    "PointLoad",
    "StaticSpec",
    "TransientSpec",
    "UCSSpec",
    "UnbalanceMass",
    "UnbalanceSpec",
    "clamp_modes",
    "parse",
    "speed_range",
    "unbalances",
]


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

    speed_rpm: float | tuple[float, ...] = param(
        0.0, unit="rpm", ge=0, doc="spin speed, or a list of speeds (a speed dimension in the result)"
    )
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
        None,
        unit="rpm",
        gt=0,
        doc="[minimum, maximum] continuous speed: shaded, with the API margins marked; stability checked in it",
    )
    frequency_limit_hz: float | None = param(
        None, unit="Hz", gt=0, doc="figures: draw the modes up to this frequency (Campbell and log-dec panels)"
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
    "stability": StabilitySpec,
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
    analysis: Literal["static", "modal", "campbell", "ucs", "unbalance", "transient", "frf", "stability"] | None = (
        param(None)
    )
    static: StaticSpec = field(default_factory=StaticSpec)
    modal: ModalSpec = field(default_factory=ModalSpec)
    campbell: CampbellSpec = field(default_factory=CampbellSpec)
    ucs: UCSSpec = field(default_factory=UCSSpec)
    unbalance: UnbalanceSpec = field(default_factory=UnbalanceSpec)
    transient: TransientSpec = field(default_factory=TransientSpec)
    frf: FRFSpec = field(default_factory=FRFSpec)
    stability: StabilitySpec = field(default_factory=StabilitySpec)


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
    check_speeds(rotor, st, "static")  # physical bounds first (rim speed), then the tables' ranges
    check_speeds(rotor, spec, analysis)
    if hasattr(spec, "frequency_hz"):
        check_frequencies(rotor, f"{analysis}.frequency_hz", spec.frequency_hz)
    speeds = getattr(spec, "speed_rpm", None)
    if speeds is not None:  # ucs has none; static's default is each table's lowest
        rotor.check_speeds(rpm_to_rad_s(np.atleast_1d(np.asarray(speeds, float))), f"{analysis}.speed_rpm")
    return rotor, spec


def _resolve_static_loads(rotor: Rotor, st: StaticSpec) -> Rotor:
    """The rotor with its ``load = "static"`` bearings loaded as the static analysis of ``st`` says."""
    from rotaflex.rotor.fe.bearings.static_load import resolve_static_loads

    loads = [(rotor.station(ld.node, ld.position, f"static.load[{i}]"), ld.fx, ld.fy) for i, ld in enumerate(st.load)]
    speed = None if st.speed_rpm is None else rpm_to_rad_s(st.speed_rpm)
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


def speed_range(rng, n, where):
    """``n`` speeds [rad/s] evenly over the ``[start, stop]`` rpm range ``rng`` of table ``where``."""
    if rng[1] <= rng[0]:
        raise InputError(f"{where}.speed_rpm", list(rng), "[start, stop] with stop > start")
    return rpm_to_rad_s(np.linspace(rng[0], rng[1], n))


def unbalances(rotor, masses, where):
    """``(node, magnitude [kg m], phase [rad])`` of the ``[[<where>.mass]]`` tables."""
    return [
        (rotor.station(m.node, m.position, f"{where}.mass[{i}]"), m.magnitude, np.radians(m.phase_deg))
        for i, m in enumerate(masses)
    ]
