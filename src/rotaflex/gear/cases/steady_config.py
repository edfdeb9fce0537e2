"""The ``gear steady`` config: its schema, the old spellings it accepts, and the checks.

TOML tables (SI unless the key names its unit; all optional, defaults = the paper's pair)::

    [gear]       module, teeth = [z1, z2], pressure_angle_deg, face_width, tip_radius,
                 root_radius (radii of both gears; omitted: derived), youngs_modulus, poisson_ratio
    [mesh_stiffness]  source = "static_fe" | "contact_pattern", pair_stiffness (contact_pattern),
                 unloaded_te_pp, damping_ratio = 0.07, backlash (omitted: no back-side contact),
                 table_points (the old spelling [mesh] for these keys still works)
    [mesh]       the FE tooth mesh as in gear static: preset, n_radii (= model.mesh_preset, n_radii)
    [train]      inertia = [J1, J2], motor_inertia, load_inertia, input_shaft_stiffness,
                 output_shaft_stiffness (omitted: rigid), input_shaft_damping,
                 output_shaft_damping, drive = "motor" | "constant_speed", motor_slope
    [bearings]   stiffness = [k_b1, k_b2], damping, mass: support of the gear centres along the
                 line of action (omitted: rigid)
    [operation]  speed_rpm (pinion), torque [N m] on torque_on = "wheel" | "pinion", ramp_cycles
    [steady]     tol, min_cycles, max_cycles, eval_cycles, fixed_cycles, steps_per_cycle
    [sweep]      speeds_rpm = [...] (two or more: an up-and-down sweep instead of one point),
                 directions = ["up", "down"]
    [iso]        f_pb_eff, f_f_eff, tip_relief (m), application_factor (ISO 6336-1 K_v overlay)
    [model]      method = "lumped" | "elastic_teeth", n_modes, tooth_damping_ratio,
                 corner_contact, mesh_preset, n_radii, relief
    [pinion], [wheel], center_distance
                 the pair as on a drawing (the tables of ``gear static``: shifts, reliefs,
                 materials, blanks) instead of ``[gear]``

:func:`checked` reads a config dict into a :class:`TorsionalCaseConfig` (other verbs' keys of a
shared pair file dropped, old spellings moved, every cross-table rule checked, the torque moved
to the wheel); :func:`validate_config` is the same without the result.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Literal

from rotaflex.core.config import from_mapping, param
from rotaflex.core.errors import InputError
from rotaflex.core.units import deg_to_rad
from rotaflex.gear.cases.pair_config import refuse_other_layout, with_pair_preset
from rotaflex.gear.cases.steady_size import check_size
from rotaflex.gear.models.mesh_stiffness import DEFAULT_DAMPING_RATIO
from rotaflex.gear.pair.drawing import MIN_YOUNGS_MODULUS, PairSpec
from rotaflex.gear.pair.drawing import GearSpec as DrawingGearSpec
from rotaflex.gear.pair.geometry import GearGeometry, contact_ratio
from rotaflex.gear.pair.lead import FaceConfig

__all__ = [
    "SCHEMA",
    "BearingSpec",
    "GearSpec",
    "IsoSpec",
    "MeshSpec",
    "ModelSpec",
    "OperationSpec",
    "SteadySpec",
    "SweepSpec",
    "TorsionalCaseConfig",
    "TrainSpec",
    "checked",
    "mesh_table_name",
    "validate_config",
]


@dataclass(frozen=True)
class GearSpec:
    """The paper's symmetric pair (used when no [pinion]/[wheel] is given)."""

    module: float = param(3.175e-3, unit="m", gt=0.0, le=0.1, doc="module in metres")
    teeth: tuple[int, int] = param((28, 28), doc="(pinion, wheel)")
    pressure_angle_deg: float = param(20.0, unit="deg", gt=5.0, lt=45.0)
    face_width: float = param(6.35e-3, unit="m", gt=0.0)
    tip_radius: tuple[float, float] | None = param(None, unit="m", doc="omitted: derived")
    root_radius: tuple[float, float] | None = param(None, unit="m", doc="omitted: derived")
    youngs_modulus: float = param(210e9, unit="Pa", gt=MIN_YOUNGS_MODULUS, doc="> 1e8 Pa: engineering gear materials")
    poisson_ratio: float = param(0.3, gt=0.0, lt=0.5)
    density: float = param(7800.0, unit="kg/m^3", gt=0.0, doc="tooth mass (elastic_teeth with n_modes > 0)")

    def geometry(self) -> tuple[GearGeometry, GearGeometry]:
        return tuple(
            GearGeometry(
                module=self.module,
                teeth=z,
                face_width=self.face_width,
                pressure_angle=deg_to_rad(self.pressure_angle_deg),
                tip_radius=None if self.tip_radius is None else self.tip_radius[i],
                root_radius=(None if self.root_radius is None else self.root_radius[i]),
            )
            for i, z in enumerate(self.teeth)
        )


@dataclass(frozen=True)
class MeshSpec:
    """Mesh stiffness and unloaded TE source, and mesh damping."""

    source: Literal["static_fe", "contact_pattern"] = param(
        "static_fe", doc="static FE mesh stiffness (gear.static) or the analytic 1/2-pair model"
    )
    pair_stiffness: float = param(1.2e8, unit="N/m", gt=0.0, doc="contact_pattern only")
    unloaded_te_pp: float = param(0.0, unit="m", ge=0.0, doc="triangular unloaded TE per cycle (contact_pattern only)")
    damping_ratio: float = param(DEFAULT_DAMPING_RATIO, ge=0.0, doc="mesh damping ratio zeta")
    backlash: float | None = param(None, unit="m", ge=0.0, doc="omitted: no back-side contact")
    table_points: int = param(400, ge=16, doc="samples per mesh cycle of the stiffness and TE tables")


@dataclass(frozen=True)
class TrainSpec:
    """The torsional train around the pair: drive, motor and load inertias, shafts, backlash."""

    inertia: tuple[float, float] | None = param(
        None,
        unit="kg m^2",
        gt=0.0,
        doc="(pinion, wheel); default: from the [pinion]/[wheel] blanks, or the paper's 2.965e-4 each",
    )
    motor_inertia: float = param(0.0, unit="kg m^2", ge=0.0, doc="motor rotor (drive = 'motor')")
    load_inertia: float = param(0.0, unit="kg m^2", ge=0.0, doc="driven machine on the wheel side")
    input_shaft_stiffness: float | None = param(None, unit="N m/rad", gt=0.0, doc="omitted: rigid")
    input_shaft_damping: float = param(0.0, unit="N m s/rad", ge=0.0, doc="motor-pinion shaft")
    output_shaft_stiffness: float | None = param(None, unit="N m/rad", gt=0.0, doc="omitted: rigid")
    output_shaft_damping: float = param(0.0, unit="N m s/rad", ge=0.0, doc="wheel-load shaft")
    drive: Literal["motor", "constant_speed"] = param(
        "motor", doc="motor: speed set by the torque-speed slope; constant_speed: prescribed input speed"
    )
    motor_slope: float = param(0.5, unit="N m s/rad", gt=0.0, doc="motor torque drop per rad/s above nominal")


@dataclass(frozen=True)
class BearingSpec:
    """Lateral compliance of the gear centres along the line of action (bearings, housing and
    shaft bending at the gear, combined into one spring per gear)."""

    stiffness: tuple[float, float] = param(
        unit="N/m",
        gt=0.0,
        doc="(pinion, wheel) support stiffness along the line of action (bearings, housing, shaft bending)",
    )
    damping: tuple[float, float] = param((0.0, 0.0), unit="N s/m", ge=0.0, doc="(pinion, wheel) support damping")
    mass: tuple[float, float] | None = param(
        None,
        unit="kg",
        gt=0.0,
        doc="(pinion, wheel) masses moving with the centres; default: the [pinion]/[wheel] blanks "
        "(required with [gear] or a blank given by its inertia)",
    )


@dataclass(frozen=True)
class OperationSpec:
    """Operating point: pinion speed, output torque, start-up ramp."""

    speed_rpm: float = param(10000.0, unit="rpm", gt=0.0, doc="pinion (mean) speed")
    torque: float = param(22.25, unit="N m", gt=0.0, doc="torque on the gear named by torque_on")
    torque_on: Literal["pinion", "wheel"] = param(
        "wheel", doc="the gear 'torque' acts on; the other carries it times the tooth ratio"
    )
    ramp_cycles: float = param(0.0, ge=0.0, doc="start-up torque ramp in mesh cycles; 0: start from statics")


@dataclass(frozen=True)
class SteadySpec:
    """Steady-state detection: tolerance, cycles evaluated, time step."""

    tol: float = param(1e-4, gt=0.0, doc="periodic when the cycle-to-cycle change of force and DTE (scaled) is below")
    min_cycles: int = param(20, ge=2, doc="mesh cycles before the first periodicity check")
    max_cycles: int = param(400, ge=2, doc="give up (status not_periodic) after")
    eval_cycles: int = param(10, ge=1, doc="last mesh cycles evaluated (K_v, DTE, spectra)")
    fixed_cycles: int | None = param(None, ge=2, doc="run exactly this many cycles instead of checking")
    steps_per_cycle: int = param(100, ge=8, doc="RK4 steps per mesh cycle (more where tooth modes need it)")


@dataclass(frozen=True)
class SweepSpec:
    """An in-process speed sweep (for large sweeps use `rotaflex sweep --continuation`)."""

    speeds_rpm: tuple[float, ...] = param((), unit="rpm", gt=0.0, doc="pinion speeds, each continued from the last")
    directions: tuple[str, ...] = param(("up", "down"), doc="sweep order(s)")


@dataclass(frozen=True)
class IsoSpec:
    """Inputs of the ISO 6336-1 method B K_v overlay."""

    f_pb_eff: float = param(0.0, unit="m", ge=0.0, doc="effective base-pitch deviation (after running-in)")
    f_f_eff: float = param(0.0, unit="m", ge=0.0, doc="effective profile form deviation (after running-in)")
    tip_relief: float | None = param(
        None,
        unit="m",
        ge=0.0,
        le=1e-3,
        doc="C_a of B_k; default: the larger tip relief amount of [pinion]/[wheel] "
        "(0 without reliefs or with model.relief = false)",
    )
    application_factor: float = param(1.0, ge=1.0, doc="K_A")
    stiffness: Literal["iso", "model"] = param(
        "iso",
        doc="c' and c_gamma_alpha (hence n_E1) from ISO 6336-1's own formulas, or from the model's mean mesh stiffness",
    )


@dataclass(frozen=True)
class ModelSpec:
    """Mesh model: lumped mesh spring or FE tooth pairs in a travelling window."""

    method: Literal["lumped", "elastic_teeth"] = param(
        "lumped", doc="mesh spring k(phi), e(phi), or the travelling window of FE tooth pairs"
    )
    n_modes: int = param(0, ge=0, le=6, doc="elastic_teeth: tooth modes per gear (0: massless FE teeth)")
    tooth_damping_ratio: float = param(0.02, ge=0.0, lt=1.0, doc="elastic_teeth: modal damping of tooth modes")
    corner_contact: bool = param(True, doc="elastic_teeth: premature tip-corner contact beyond the path")
    mesh_preset: Literal["coarse", "default", "fine"] = param("default", doc="FE tooth mesh ([pinion]/[wheel])")
    n_radii: int = param(9, ge=4, le=40, doc="FE load cases per tooth over its active profile")
    relief: bool = param(True, doc="false: the [pinion]/[wheel] gears without their profile reliefs")


@dataclass(frozen=True)
class TorsionalCaseConfig:
    """A steady-state gear dynamics case (`rotaflex gear steady`): pair, mesh model, train, operation."""

    gear: GearSpec | None = param(
        None, doc="the paper's 28:28 pair, keys changeable; default when no [pinion]/[wheel] is given"
    )
    mesh_stiffness: MeshSpec = param(MeshSpec(), doc="the mesh-spring model (was [mesh]; [mesh] is the FE tooth mesh)")
    train: TrainSpec = param(TrainSpec())
    bearings: BearingSpec | None = param(None, doc="omitted: rigid bearings")
    operation: OperationSpec = param(OperationSpec())
    steady: SteadySpec = param(SteadySpec())
    sweep: SweepSpec = param(SweepSpec())
    iso: IsoSpec = param(IsoSpec())
    model: ModelSpec = param(ModelSpec())
    face: FaceConfig = param(FaceConfig(), doc="[pinion]/[wheel] helical or lead-modified: the face in slices")
    pinion: DrawingGearSpec | None = param(None, doc="gear 1 as on a drawing (instead of [gear])")
    wheel: DrawingGearSpec | None = param(None, doc="gear 2 as on a drawing")
    center_distance: float | None = param(None, unit="m", gt=0.0, doc="[pinion]/[wheel]: working centre distance")
    backlash: float | None = param(
        None,
        unit="m",
        ge=0.0,
        doc="[pinion]/[wheel]: normal backlash j_bn (alternative to center_distance); it sets the "
        "centre distance only: the lumped model's back flank is mesh.backlash",
    )

    def __post_init__(self):
        if self.gear is None and self.pinion is None:
            object.__setattr__(self, "gear", GearSpec())

    @property
    def pair(self) -> PairSpec | None:
        """The checked drawing pair, or None with ``[gear]``."""
        if self.pinion is None:
            return None
        pair = PairSpec(
            pinion=self.pinion, wheel=self.wheel, center_distance=self.center_distance, backlash=self.backlash
        ).check()
        if self.model.method != "lumped":  # the FE tooth window is transverse (spur) only
            pair.spur_only("gear steady with model.method = 'elastic_teeth'")
        return pair


SCHEMA = TorsionalCaseConfig


#: keys of the other gear verbs a shared [pinion]/[wheel] file may carry; ``gear steady`` ignores
#: them: (table, key) or (table, None) for the whole table
OTHER_VERBS = (
    ("load", None),
    ("analysis", None),
    ("solver", None),
    ("output", None),
    ("driver", None),
    ("operation", "driver_speed_rpm"),
    ("operation", "driven_speed_rpm"),
    ("operation", "direction"),
    ("operation", "theta_2_deg"),
    ("operation", "theta_s_deg"),
    ("operation", "span_deg"),
    ("model", "teeth_per_gear"),
    ("model", "start_angle_deg"),
    ("model", "mesh_window_deg"),
    ("mesh", "n_points"),
    ("mesh", "contact_smoothing"),
)
#: [mesh] keys of the FE tooth mesh (as in gear static) -> their [model] key here
FE_MESH_KEYS = {"preset": "mesh_preset", "n_radii": "n_radii"}


def mesh_table_name(config: dict) -> str:
    """'mesh' for a file that gives the mesh-spring model in [mesh] (the old spelling)."""
    return (
        "mesh" if set(config.get("mesh") or {}) & {f.name for f in dataclasses.fields(MeshSpec)} else "mesh_stiffness"
    )


def _normalised(config: dict) -> dict:
    """``config`` in this verb's spelling: other verbs' keys dropped, [mesh] FE keys moved to
    [model], mesh-spring keys of an old [mesh] table moved to [mesh_stiffness]."""
    out = {k: dict(v) if isinstance(v, dict) else v for k, v in config.items()}
    for table, key in OTHER_VERBS:
        if key is None:
            out.pop(table, None)
        elif isinstance(out.get(table), dict):
            out[table].pop(key, None)
    mesh = out.pop("mesh", None)
    if isinstance(mesh, dict):
        spring = {f.name for f in dataclasses.fields(MeshSpec)}
        for key, value in mesh.items():
            table, name = ("model", FE_MESH_KEYS[key]) if key in FE_MESH_KEYS else ("mesh_stiffness", key)
            if key not in FE_MESH_KEYS and key not in spring:
                allowed = "a key of [mesh] (" + ", ".join([*FE_MESH_KEYS, *sorted(spring)]) + ")"
                raise InputError(f"mesh.{key}", value, allowed)
            dest = out.setdefault(table, {})
            if not isinstance(dest, dict):
                raise InputError(table, dest, "a table")
            if name in dest and dest[name] != value:
                raise InputError(f"mesh.{key}", value, f"omitted, or equal to {table}.{name} = {dest[name]!r}")
            dest[name] = value
    elif mesh is not None:
        raise InputError("mesh", mesh, "a table")
    return out


def _wheel_torque(cfg: TorsionalCaseConfig) -> TorsionalCaseConfig:
    """``cfg`` with the operating torque on the wheel (the chain's convention)."""
    op = cfg.operation
    if op.torque_on == "wheel":
        return cfg
    g1, g2 = cfg.gear.geometry() if cfg.pair is None else cfg.pair.gears
    wheel = dataclasses.replace(op, torque=op.torque * g2.teeth / g1.teeth, torque_on="wheel")
    return dataclasses.replace(cfg, operation=wheel)


def checked(config: dict) -> TorsionalCaseConfig:
    config = with_pair_preset(config, "steady")  # pair = "lee_jang"; a [gear] of another verb refused
    refuse_other_layout(config, "steady")
    written, config = config, _normalised(config)
    try:
        cfg = from_mapping(TorsionalCaseConfig, config)
    except InputError as exc:  # name the table written: an old file's [mesh]
        if mesh_table_name(written) == "mesh" and exc.field.startswith("mesh_stiffness."):
            raise InputError("mesh." + exc.field.partition(".")[2], exc.value, exc.allowed) from None
        raise
    if (cfg.pinion is None) != (cfg.wheel is None):
        missing = "wheel" if cfg.wheel is None else "pinion"
        raise InputError(missing, None, f"a [{missing}] table together with the other gear's")
    if cfg.pinion is not None and "gear" in config:
        raise InputError("gear", "a [gear] table", "either [gear] or [pinion]/[wheel], not both")
    if cfg.pinion is None and cfg.center_distance is not None:
        raise InputError("center_distance", cfg.center_distance, "only with [pinion]/[wheel]")
    if cfg.pinion is None and cfg.backlash is not None:
        raise InputError("backlash", cfg.backlash, "only with [pinion]/[wheel]")
    if cfg.model.method == "elastic_teeth" and cfg.mesh_stiffness.source != "static_fe":
        raise InputError(
            f"{mesh_table_name(written)}.source",
            cfg.mesh_stiffness.source,
            "'static_fe' with model.method = 'elastic_teeth'",
        )
    if cfg.pinion is not None and cfg.mesh_stiffness.source != "static_fe":
        raise InputError(
            f"{mesh_table_name(written)}.source", cfg.mesh_stiffness.source, "'static_fe' with [pinion]/[wheel]"
        )
    if cfg.model.method == "elastic_teeth" and cfg.mesh_stiffness.backlash is not None:
        raise InputError(
            f"{mesh_table_name(written)}.backlash",
            cfg.mesh_stiffness.backlash,
            "omitted with model.method = 'elastic_teeth'",
        )
    cfg.pair  # noqa: B018  (checks the drawing pair)
    if cfg.bearings is not None and cfg.bearings.mass is None:
        if cfg.pinion is None:
            raise InputError("bearings.mass", None, "(pinion, wheel) masses in kg with [gear]")
        for name, g in (("pinion", cfg.pinion), ("wheel", cfg.wheel)):
            if g.mass(name) is None:
                what = f"(pinion, wheel) masses in kg: {name}.blank gives only an inertia"
                raise InputError("bearings.mass", None, what)
    s = cfg.steady
    if s.min_cycles > s.max_cycles:
        raise InputError("steady.min_cycles", s.min_cycles, f"<= steady.max_cycles = {s.max_cycles}")
    if s.fixed_cycles is not None and s.fixed_cycles < max(s.eval_cycles, 2):
        least = max(s.eval_cycles, 2)
        raise InputError("steady.fixed_cycles", s.fixed_cycles, f">= max(steady.eval_cycles, 2) = {least}")
    sp = cfg.sweep.speeds_rpm
    if len(sp) == 1 or any(b <= a for a, b in zip(sp, sp[1:], strict=False)):
        raise InputError("sweep.speeds_rpm", list(sp), "empty, or two or more ascending speeds")
    for d in cfg.sweep.directions:
        if d not in ("up", "down"):
            raise InputError("sweep.directions", d, "'up' or 'down'")
    g1, g2 = cfg.gear.geometry() if cfg.pair is None else cfg.pair.gears
    eps = contact_ratio(g1, g2) if cfg.pair is None else cfg.pair.contact_ratio
    if cfg.mesh_stiffness.source == "contact_pattern" and not 1.0 < eps < 2.0:
        raise InputError("gear", f"contact ratio {eps:.3f}", "1 < eps < 2 for mesh.source = 'contact_pattern'")
    check_size(cfg, mesh_table_name(written))
    return _wheel_torque(cfg)


def validate_config(config: dict) -> None:
    """Check a ``gear steady`` config completely without running it (InputError otherwise)."""
    checked(config)
