"""Config -> torsional steady-state point or speed sweep -> result.

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

Mesh model (``model.method``): ``lumped`` drives the torsional chain with a mesh table
``k(phi), e(phi)`` (from ``gear.static`` for ``[gear]``; from the loaded TE of
:mod:`~.loaded_te` at the operating torque for a ``[pinion]``/``[wheel]`` pair, so tip
relief enters as unloaded TE); ``elastic_teeth`` replaces the mesh spring by the FE tooth pairs
of :mod:`~.window` (per-pair compliance, relief gaps, load sharing, corner contact,
optional tooth inertia).

:func:`run_torsional` has the signature of the domain command registry
(``fn(config, *, progress=False) -> Result``); with ``initial_state`` (the ``final_state()`` of
an earlier single-point result) one steady state continues from that state, which is how
``rotaflex sweep --continuation operation.speed_rpm`` chains the speeds of a sweep.
:func:`validate_config` checks a config without running it.
"""

from __future__ import annotations

import dataclasses
import functools
import json
import math
import time
from dataclasses import dataclass
from typing import Literal

import numpy as np

from rotaflex.core.config import from_mapping, param, to_mapping
from rotaflex.core.errors import InputError
from rotaflex.core.result import Result
from rotaflex.core.units import deg_to_rad
from rotaflex.gear.cases.pair_config import refuse_other_layout, with_pair_preset
from rotaflex.gear.cases.steady_size import announce_kernels, check_model_size, check_size
from rotaflex.gear.models.chain import (
    OperatingPoint,
    State,
    TorsionalSystem,
    iso_input,
    natural_frequencies,
)
from rotaflex.gear.models.mesh_stiffness import contact_pattern_mesh, mesh_table_from_static
from rotaflex.gear.pair.drawing import MIN_YOUNGS_MODULUS, PairSpec
from rotaflex.gear.pair.drawing import GearSpec as DrawingGearSpec
from rotaflex.gear.pair.geometry import GearGeometry, center_distance_no_backlash, contact_ratio
from rotaflex.gear.results.steady_sweep import sweep_dataset
from rotaflex.gear.solvers.registry import METHODS
from rotaflex.gear.solvers.steady_driver import LateProgress, continuation
from rotaflex.gear.static.iso6336_kv import iso_kv

__all__ = ["SCHEMA", "TorsionalCaseConfig", "build_model", "build_system", "run_torsional", "validate_config"]


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
    damping_ratio: float = param(0.07, ge=0.0, doc="mesh damping ratio zeta")
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


def _iso_tip_relief(cfg) -> float:
    """ISO's single C_a [m]: as given, else the larger drawing tip relief of the pair in use."""
    if cfg.iso.tip_relief is not None:
        return cfg.iso.tip_relief
    if cfg.pinion is None or not cfg.model.relief:
        return 0.0
    return max((g.tip_relief.amount for g in (cfg.pinion, cfg.wheel) if g.tip_relief is not None), default=0.0)


def _iso_data(cfg, sys: TorsionalSystem, eps: float, face_width: float):
    """ISO 6336-1 method B input of the case: ISO's F_t at the wheel's reference circle and, with
    ``iso.stiffness = "iso"``, ISO's own c' and c_gamma_alpha (blank factor C_R of the drawing)."""
    from rotaflex.gear.static.tooth_analysis import iso6336_stiffness

    g1, g2 = cfg.gear.geometry() if cfg.pair is None else cfg.pair.gears
    iso = cfg.iso
    stiff = {}
    if iso.stiffness == "iso":
        pair = cfg.pair
        c_r = 1.0 if pair is None else 0.5 * (pair.pinion.blank_factor() + pair.wheel.blank_factor())
        load = iso.application_factor * cfg.operation.torque / g2.pitch_radius / (face_width * 1e3)  # N/mm
        c = iso6336_stiffness(g1, g2, load_per_width=load, eps_alpha=eps, c_r=c_r)
        stiff = {"c_single": c["c_single"] * 1e9, "c_gamma_alpha": c["c_gamma"] * 1e9}  # N/(mm um) -> N/m^2
    return iso_input(
        sys,
        cfg.operation.torque,
        face_width,
        eps,
        reference_radius=g2.pitch_radius,
        f_pb_eff=iso.f_pb_eff,
        f_f_eff=iso.f_f_eff,
        tip_relief=_iso_tip_relief(cfg),
        application_factor=iso.application_factor,
        **stiff,
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
        return PairSpec(
            pinion=self.pinion, wheel=self.wheel, center_distance=self.center_distance, backlash=self.backlash
        ).check()


SCHEMA = TorsionalCaseConfig


@dataclass(frozen=True)
class PairData:
    """What the mesh models need from the pair: geometries, FE meshes, working centre
    distance [m], (E1, nu1, E2, nu2), densities [kg/m^3], gear inertias [kg m^2], face width [m]."""

    gears: tuple
    meshes: tuple
    center_distance: float
    elastic: tuple
    densities: tuple
    inertias: tuple | None
    face_width: float


# The caches below are keyed by content: each by a copy of the config that keeps only the parts
# its data depends on (frozen dataclasses hash and compare by value), so the cases of a sweep
# over the speed (or any key the data does not depend on) build it once per process.
def _pair_part(cfg: TorsionalCaseConfig) -> TorsionalCaseConfig:
    """``cfg`` reduced to what :func:`pair_data` reads: the pair, the FE mesh preset, reliefs."""
    m = cfg.model
    return TorsionalCaseConfig(
        gear=cfg.gear,
        pinion=cfg.pinion,
        wheel=cfg.wheel,
        center_distance=cfg.center_distance,
        backlash=cfg.backlash,
        model=ModelSpec(mesh_preset=m.mesh_preset, relief=m.relief),
    )


def pair_data(cfg: TorsionalCaseConfig) -> PairData:
    """Geometry, meshes and materials of ``cfg``'s pair ([gear] or [pinion]/[wheel]); built once
    per process for each pair (cached by content)."""
    return _pair_data(_pair_part(cfg))


@functools.lru_cache(maxsize=8)
def _pair_data(cfg: TorsionalCaseConfig) -> PairData:
    from rotaflex.gear.pair.tooth_mesh import build_tooth_mesh

    pair = cfg.pair
    if pair is None:
        g = cfg.gear
        g1, g2 = g.geometry()
        meshes = (build_tooth_mesh(g1), build_tooth_mesh(g2))
        e = (g.youngs_modulus, g.poisson_ratio)
        return PairData(
            (g1, g2), meshes, center_distance_no_backlash(g1, g2), 2 * e, (g.density,) * 2, None, g.face_width
        )
    from rotaflex.gear.cases.static import gear_meshes

    gears = pair.gears
    if not cfg.model.relief:
        gears = tuple(dataclasses.replace(x, tip_relief=None, root_relief=None) for x in gears)
    meshes = gear_meshes(pair, cfg.model.mesh_preset, relief=cfg.model.relief)
    (e1, nu1, r1), (e2, nu2, r2) = pair.pinion.material.values, pair.wheel.material.values
    return PairData(
        gears,
        meshes,
        pair.working_center_distance,
        (e1, nu1, e2, nu2),
        (r1, r2),
        (pair.pinion.inertia("pinion"), pair.wheel.inertia("wheel")),
        min(pair.pinion.face_width, pair.wheel.face_width),
    )


def pair_line_of(cfg: TorsionalCaseConfig):
    """FE pair data along the line of action at the operating torque (cached by content: the
    pair, the torque and ``model.n_radii``)."""
    return _pair_line(_pair_part(cfg), cfg.operation.torque, cfg.model.n_radii)


@functools.lru_cache(maxsize=8)
def _pair_line(pair_cfg: TorsionalCaseConfig, torque: float, n_radii: int):
    from rotaflex.gear.static.loaded_te import pair_line

    pd = _pair_data(pair_cfg)
    g1, g2 = pd.gears
    force = torque / g2.base_radius
    return pair_line(g1, g2, *pd.meshes, pd.center_distance, force, pd.elastic, n_radii)


@functools.lru_cache(maxsize=8)
def _mesh_table(gear: GearSpec, mesh_spec: MeshSpec, torque: float):
    """Mesh table and contact ratio; cached per process because the static FE table (~0.5 s)
    is the same for every speed of a sweep (frozen specs are hashable keys)."""
    g1, g2 = gear.geometry()
    eps = contact_ratio(g1, g2)
    if mesh_spec.source == "static_fe":
        from rotaflex.gear.static.tooth_analysis import mesh_stiffness

        ms = mesh_stiffness(
            g1,
            g2,
            gear.youngs_modulus,
            gear.poisson_ratio,
            torque=torque * g1.base_radius / g2.base_radius,
        )
        mesh = mesh_table_from_static(ms, g1.teeth, mesh_spec.table_points)
    else:
        mesh = contact_pattern_mesh(mesh_spec.pair_stiffness, eps, mesh_spec.table_points, mesh_spec.unloaded_te_pp)
    return mesh, eps


#: lumped model: a dynamic factor above this far below resonance is noted as the mesh spring's
#: step response (the stiffness jump between one and two pairs rings the mesh mode)
LOW_SPEED_KV = 1.1

#: gear inertias of the paper's pair [kg m^2] (train.inertia's default with [gear])
PAPER_INERTIA = (2.965e-4, 2.965e-4)


def build_system(cfg: TorsionalCaseConfig) -> tuple[TorsionalSystem, float]:
    """The torsional model and the contact ratio of ``cfg``; gear inertias from
    ``train.inertia``, else a drawing pair's blanks, else the paper's."""
    t = cfg.train
    inertia = PAPER_INERTIA if t.inertia is None else tuple(t.inertia)
    if cfg.pair is None and cfg.model.method == "lumped":
        g1, g2 = cfg.gear.geometry()
        mesh, eps = _mesh_table(cfg.gear, cfg.mesh_stiffness, cfg.operation.torque)
    else:
        from rotaflex.gear.models.mesh_stiffness import loaded_mesh_table

        pd = pair_data(cfg)
        g1, g2 = pd.gears
        line = pair_line_of(cfg)
        mesh = loaded_mesh_table(line, line.force, cfg.mesh_stiffness.table_points)
        eps = contact_ratio(g1, g2, pd.center_distance)
        if pd.inertias is not None and t.inertia is None:
            inertia = pd.inertias
    sys = TorsionalSystem(
        mesh=mesh,
        teeth=(g1.teeth, g2.teeth),
        base_radius=(g1.base_radius, g2.base_radius),
        inertia=inertia,
        motor_inertia=t.motor_inertia,
        load_inertia=t.load_inertia,
        input_shaft_stiffness=t.input_shaft_stiffness or math.inf,
        input_shaft_damping=t.input_shaft_damping,
        output_shaft_stiffness=t.output_shaft_stiffness or math.inf,
        output_shaft_damping=t.output_shaft_damping,
        mesh_damping_ratio=cfg.mesh_stiffness.damping_ratio,
        backlash=-1.0 if cfg.mesh_stiffness.backlash is None else cfg.mesh_stiffness.backlash,
        drive=t.drive,
        motor_slope=t.motor_slope,
        **_bearing_keys(cfg),
    )
    return sys, eps


def build_model(cfg: TorsionalCaseConfig):
    """``(system, contact ratio, model)`` of ``cfg``: the torsional system and the model the
    method runs (the system itself, or the elastic-tooth window model around it). Built once per
    process for each model (cached by content: ``cfg`` without the operating speed, start-up
    ramp, [steady], [sweep] and [iso], which the model does not depend on), so the cases of a
    speed sweep share it."""
    op = cfg.operation
    default = OperationSpec()
    key = dataclasses.replace(
        cfg,
        operation=dataclasses.replace(op, speed_rpm=default.speed_rpm, ramp_cycles=default.ramp_cycles),
        steady=SteadySpec(),
        sweep=SweepSpec(),
        iso=IsoSpec(),
    )
    return _built_model(key)


@functools.lru_cache(maxsize=4)
def _built_model(cfg: TorsionalCaseConfig):
    sys, eps = build_system(cfg)
    if cfg.model.method != "elastic_teeth":
        return sys, eps, sys
    from rotaflex.gear.models.window import build_window_model

    pd = pair_data(cfg)
    m = cfg.model
    model = build_window_model(
        sys,
        pair_line_of(cfg),
        pd.meshes,
        pd.densities,
        n_modes=m.n_modes,
        tooth_damping_ratio=m.tooth_damping_ratio,
        corner_contact=m.corner_contact,
    )
    return sys, eps, model


def _bearing_keys(cfg: TorsionalCaseConfig) -> dict:
    """TorsionalSystem keywords of ``[bearings]``; masses from the drawing blanks if not given."""
    b = cfg.bearings
    if b is None:
        return {}
    mass = b.mass
    if mass is None:
        mass = (cfg.pinion.mass("pinion"), cfg.wheel.mass("wheel"))
    return {"bearing_stiffness": tuple(b.stiffness), "bearing_damping": tuple(b.damping), "gear_mass": tuple(mass)}


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


def _mesh_table_name(config: dict) -> str:
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


def _checked(config: dict) -> TorsionalCaseConfig:
    config = with_pair_preset(config, "steady")  # pair = "lee_jang"; a [gear] of another verb refused
    refuse_other_layout(config, "steady")
    written, config = config, _normalised(config)
    try:
        cfg = from_mapping(TorsionalCaseConfig, config)
    except InputError as exc:  # name the table written: an old file's [mesh]
        if _mesh_table_name(written) == "mesh" and exc.field.startswith("mesh_stiffness."):
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
            f"{_mesh_table_name(written)}.source",
            cfg.mesh_stiffness.source,
            "'static_fe' with model.method = 'elastic_teeth'",
        )
    if cfg.pinion is not None and cfg.mesh_stiffness.source != "static_fe":
        raise InputError(
            f"{_mesh_table_name(written)}.source", cfg.mesh_stiffness.source, "'static_fe' with [pinion]/[wheel]"
        )
    if cfg.model.method == "elastic_teeth" and cfg.mesh_stiffness.backlash is not None:
        raise InputError(
            f"{_mesh_table_name(written)}.backlash",
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
    check_size(cfg, _mesh_table_name(written))
    return _wheel_torque(cfg)


def validate_config(config: dict) -> None:
    """Check a ``gear steady`` config completely without running it (InputError otherwise)."""
    _checked(config)


def _state_of(initial_state):
    """A lumped :class:`State` or, with ``modal`` data, a window-model state."""
    try:
        th, om, nom, t = (
            np.asarray(initial_state["theta"], dtype=float),
            np.asarray(initial_state["omega"], dtype=float),
            np.asarray(initial_state["nominal"], dtype=float),
            float(initial_state["time"]),
        )
        if "modal" in initial_state:
            from rotaflex.gear.solvers.window_run import WindowState

            return WindowState(
                th, om, t, nom, np.asarray(initial_state["modal"], dtype=float), int(initial_state["n_hi"])
            )
        return State(th, om, t, nom)
    except (KeyError, TypeError, ValueError) as exc:
        what = f"a final_state() of gear steady ({exc})"
        raise InputError("initial_state", type(initial_state).__name__, what) from None


def _point_extras(res, sys: TorsionalSystem, st, cfg: TorsionalCaseConfig, eps: float, face_width: float) -> None:
    """Scalars a speed sweep of single points needs (linear resonance, ISO K_v at this speed)
    and the final state (continuation, also after reading result.nc back)."""
    ds = res.dataset
    op = cfg.operation
    nf = natural_frequencies(sys)
    f_mesh_mode = float(nf["frequency"][nf["mesh_mode"]])
    ds["mesh_natural_frequency"] = ((), f_mesh_mode, {"units": "Hz", "long_name": "linear mesh-mode frequency"})
    ds["resonance_speed"] = (
        (),
        60.0 * f_mesh_mode / sys.teeth[0],
        {"units": "rpm", "long_name": "pinion speed where the mesh frequency meets the mesh mode"},
    )
    # the model data behind the numbers, for checking by hand
    ds["static_mesh_force"] = ((), float(op.torque / sys.base_radius[1]), {"units": "N", "long_name": "T_out / r_b2"})
    ds["mean_mesh_stiffness"] = ((), float(sys.mesh.mean_stiffness), {"units": "N/m", "long_name": "k_mean"})
    ds["reduced_mass"] = ((), float(sys.reduced_mass), {"units": "kg", "long_name": "m_red along the line of action"})
    if cfg.pair is not None:
        pair = cfg.pair
        ds["normal_backlash"] = (
            (),
            float(pair.normal_backlash_at(pair.working_center_distance)),
            {"units": "m", "long_name": "normal backlash j_bn of the drawing pair"},
        )
    for name, j in zip(("pinion", "wheel"), sys.inertia, strict=True):
        ds[f"inertia_{name}"] = ((), float(j), {"units": "kg m^2", "long_name": f"{name} polar inertia used"})
    iso = _iso_data(cfg, sys, eps, face_width)
    ds["iso_kv"] = ((), float(iso_kv(iso, [op.speed_rpm])[0]), {"units": "1", "long_name": "ISO 6336-1 method B K_v"})
    ds["iso_resonance_speed"] = ((), float(iso.resonance_speed_rpm), {"units": "rpm"})
    ds.coords["chain_node"] = _node_names(sys, cfg)
    ds["state_theta"] = (
        "chain_node",
        st.theta,
        {"units": "rad", "long_name": "final angles (lateral nodes: displacements in m)"},
    )
    ds["state_omega"] = (
        "chain_node",
        st.omega,
        {"units": "rad/s", "long_name": "final speeds (lateral nodes: velocities in m/s)"},
    )
    ds["state_nominal"] = ("chain_node", st.nominal, {"units": "rad/s", "long_name": "final nominal speeds"})
    ds.attrs["state_time"] = st.time
    if hasattr(st, "modal"):
        ds["state_modal"] = ("modal_dof", st.modal, {"units": "sqrt(kg) m", "long_name": "final tooth modal states"})
        ds.attrs["state_n_hi"] = st.n_hi


def _node_names(sys: TorsionalSystem, cfg: TorsionalCaseConfig) -> list[str]:
    """Chain nodes of the model (motor, pinion, wheel, load as present; lateral nodes)."""
    from rotaflex.gear.models.chain import build_chain

    op = cfg.operation
    return build_chain(sys, OperatingPoint(op.speed_rpm, op.torque)).names


def run_torsional(config: dict, *, progress: bool = False, initial_state: dict | None = None) -> Result:
    """Validate ``config`` (module docstring), run one steady state or a speed sweep.

    ``initial_state`` (single point only): continue from this ``final_state()`` of an earlier
    point (angles and vibration velocities kept, mean speeds moved to this speed) instead of
    starting from the static equilibrium.
    """
    cfg = _checked(config)
    if initial_state is not None and len(cfg.sweep.speeds_rpm) >= 2:
        raise InputError(
            "sweep.speeds_rpm",
            list(cfg.sweep.speeds_rpm),
            "empty when a case continues from a previous state (sweep operation.speed_rpm instead)",
        )
    state = None if initial_state is None else _state_of(initial_state)
    sys, eps, model = build_model(cfg)
    face_width = cfg.gear.face_width if cfg.pair is None else pair_data(cfg).face_width
    if state is not None and isinstance(model, TorsionalSystem) == hasattr(state, "modal"):
        raise InputError("initial_state", "a final_state()", f"one of the same model.method ({cfg.model.method})")
    if state is not None and len(state.theta) != len(names := _node_names(sys, cfg)):
        raise InputError(
            "initial_state", f"{len(state.theta)} chain nodes", f"{len(names)} ({', '.join(names)}): the same train"
        )
    check_model_size(model, cfg)
    announce_kernels(cfg.model.method)
    s = cfg.steady
    kw = dict(
        tol=s.tol,
        min_cycles=s.min_cycles,
        max_cycles=s.max_cycles,
        eval_cycles=s.eval_cycles,
        fixed_cycles=s.fixed_cycles,
        steps_per_cycle=s.steps_per_cycle,
    )
    op = cfg.operation
    bar = LateProgress("gear steady", enabled=progress)
    if len(cfg.sweep.speeds_rpm) >= 2:
        t0 = time.perf_counter()
        speeds, directions = np.asarray(cfg.sweep.speeds_rpm, dtype=float), cfg.sweep.directions
        n_points = len(speeds) * len(directions)

        def point(rpm, st):  # the steady state a `rotaflex sweep --continuation` case runs
            at = dataclasses.replace(cfg, operation=dataclasses.replace(op, speed_rpm=rpm), sweep=SweepSpec())
            out = _steady_point(at, sys, eps, model, face_width, st, kw)
            bar.update(bar.done + 1, n_points, "speed")
            return out

        iso = _iso_data(cfg, sys, eps, face_width)
        points = continuation(point, speeds, directions)
        res = sweep_dataset(points, speeds, directions, sys, op.torque, iso=iso, started=t0)
    else:
        res, _ = _steady_point(cfg, sys, eps, model, face_width, state, kw, progress=bar)
    bar.close()
    res.dataset["iso_tip_relief"] = (
        (),
        _iso_tip_relief(cfg),
        {"units": "m", "long_name": "C_a used for ISO 6336-1 B_k (iso.tip_relief or the drawing's)"},
    )
    res.dataset.attrs["config"] = json.dumps(to_mapping(cfg))
    res.dataset.attrs["method"] = cfg.model.method
    return res


def _steady_point(cfg: TorsionalCaseConfig, sys, eps, model, face_width, state, kw, progress=None):
    """One steady state of ``cfg`` from ``state`` (None: static equilibrium): the one path of a
    single point, of each case of ``rotaflex sweep --continuation`` and of each speed of an
    in-process ``[sweep]``. Returns the result and its final state."""
    op = cfg.operation
    settings = dict(kw, op=OperatingPoint(op.speed_rpm, op.torque, op.ramp_cycles), state=state)
    if progress is not None:
        settings["progress"] = lambda done, total: progress.update(done, total, "mesh cycle")
    res, st = METHODS[cfg.model.method](model, settings)
    _point_extras(res, sys, st, cfg, eps, face_width)
    ds = res.dataset
    kv, n_res = float(ds["dynamic_factor"]), float(ds["resonance_speed"])
    if cfg.model.method == "lumped" and op.speed_rpm < 0.25 * n_res and kv > LOW_SPEED_KV:
        ds.attrs["message"] += (
            f"; note: K_v {kv:.3f} far below the resonance ({n_res:.0f} rpm) comes from the lumped "
            "mesh spring's step response where the stiffness changes between one and two pairs; "
            "model.method = 'elastic_teeth' resolves each pair's engagement (docs/gear-steady-state.md)"
        )
    return res, st
