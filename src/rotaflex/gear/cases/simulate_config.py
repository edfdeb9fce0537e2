"""Configuration of ``rotaflex gear simulate``: the schema and the one conversion to SI.

TOML layout (all tables optional; defaults are the paper's data, :mod:`rotaflex.gear.pair.paper`)::

    domain = "gear"
    # the pair: paper-style (identical gears, explicit radii) ...
    [gear]       module, teeth, pressure_angle_deg, face_width, tip_radius, root_radius
    [material]   youngs_modulus, poisson_ratio, density
    disk_inertia = 2.965e-4
    # ... or as on a drawing (the keys of rotaflex.gear.pair.drawing, shared with `gear static`)
    [pinion], [wheel]   teeth, module, face_width, profile_shift, tip_relief, material, blank, ...
    pair = "lee_jang"   the paper's pair as [pinion]/[wheel] (keys written override it;
                        rotaflex.gear.cases.pair_config)
    center_distance | backlash, driver = "pinion" | "wheel"
    [operation]  torque, theta_2_deg, theta_s_deg, span_deg, direction = "forward" | "reverse",
                 paper-style: speed_rpm = [4000, 4000], driver = "A" | "B";
                 drawing: driver_speed_rpm
    [mesh]       preset = "default" | "coarse" | "fine", n_points, contact_smoothing
    [solver]     method = "paper_rk4" | "reduced_hht", dt (default per method), tolerance,
                 accel_n, max_iter, multipliers = "iterative" | "direct", restitution,
                 modes, hht_alpha
    [output]     every, vtu_snapshots, root_stress
    [model]      teeth_per_gear = 1 .. 12, start_angle_deg, mesh_window_deg

:func:`to_run` is the only place where rpm and degrees become rad/s and rad: it returns a
frozen :class:`Run` (SI) next to the frozen model; a change is a new object
(``dataclasses.replace``). Checks that need the geometry or the step count (contact ratio, the
smallest span, the step and memory budgets) are made there too, before anything is allocated.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Literal

from rotaflex.core.config import param
from rotaflex.core.errors import InputError
from rotaflex.core.limits import require, require_memory
from rotaflex.core.units import deg_to_rad, rad_to_deg, rpm_to_rad_s
from rotaflex.gear.pair import paper
from rotaflex.gear.pair.drawing import MIN_YOUNGS_MODULUS, GearSpec

#: displacement tolerance range [m]: above 1e-6 m the constraint error is comparable to the tooth
#: deflection (~1e-6 m at the paper's load), below 1e-16 m it is under round-off of the positions
TOLERANCE_RANGE = (1e-16, 1e-6)
#: largest number of time steps of one run (about 40 min of paper_rk4 at 236 us/step)
MAX_STEPS = 10_000_000
#: largest memory of the recorded histories of one run [bytes]
MAX_OUTPUT_BYTES = 2_000_000_000
#: largest contact iterations per step (the paper cases converge in ~11; a step that needs more
#: than a few hundred does not converge, and a huge cap only delays the failure by hours)
MAX_ITER = 100_000
#: energy-balance error above which a finished run has status "failed_check"
#: (|E_kin + E_strain - W_ext + D - E_0| / max E_strain; the paper cases stay below 0.5 %)
MAX_ENERGY_BALANCE_ERROR = 0.25
#: tie residual above which a finished run has status "failed_check" [m] (1 um: the size of the
#: tooth deflection; the paper cases stay below 1e-11 m)
MAX_TIE_RESIDUAL = 1e-6


@dataclass(frozen=True)
class GearConfig:
    """Both gears (identical, as in the paper)."""

    module: float = param(paper.MODULE, unit="m", gt=0.0, le=0.1, doc="module in metres (3 mm: 3e-3)")
    teeth: int = param(paper.TEETH, gt=5, doc="number of teeth")
    pressure_angle_deg: float = param(paper.PRESSURE_ANGLE_DEG, unit="deg", gt=5.0, lt=45.0)
    face_width: float = param(paper.FACE_WIDTH, unit="m", gt=0.0)
    tip_radius: float = param(paper.TIP_RADIUS, unit="m", gt=0.0)
    root_radius: float = param(paper.ROOT_RADIUS, unit="m", gt=0.0)

    def __post_init__(self) -> None:
        # the tooth count must put the pitch circle between the root and tip circles given
        # (the radii default to the paper's 28-tooth gear); checked here so that the error
        # names the tooth count and not a radius derived from it
        lo = math.floor(2 * self.root_radius / self.module) + 1
        hi = math.ceil(2 * self.tip_radius / self.module) - 1
        if not lo <= self.teeth <= hi:
            raise InputError(
                "gear.teeth",
                self.teeth,
                f"{lo}..{hi} with module {self.module:g} m, root_radius "
                f"{self.root_radius:g} m and tip_radius {self.tip_radius:g} m "
                "(pitch radius m z / 2 between them; set the radii with the teeth)",
            )

    def geometry(self):
        from rotaflex.gear.pair.geometry import GearGeometry

        try:
            return GearGeometry(
                module=self.module,
                teeth=self.teeth,
                face_width=self.face_width,
                pressure_angle=deg_to_rad(self.pressure_angle_deg),
                tip_radius=self.tip_radius,
                root_radius=self.root_radius,
            )
        except InputError as exc:
            raise InputError(f"gear.{exc.field}", exc.value, exc.allowed) from None


@dataclass(frozen=True)
class MaterialConfig:
    """Elastic material of both gears."""

    youngs_modulus: float = param(
        paper.YOUNGS_MODULUS,
        unit="Pa",
        gt=MIN_YOUNGS_MODULUS,
        doc="Young's modulus (> 1e8 Pa: engineering gear materials)",
    )
    poisson_ratio: float = param(paper.POISSON_RATIO, gt=0.0, lt=0.5)
    density: float = param(paper.DENSITY, unit="kg/m^3", gt=0.0)


@dataclass(frozen=True)
class OperationConfig:
    """Initial speeds, torque and the angles of Fig. 7."""

    speed_rpm: tuple[float, float] = param(
        (paper.SPEED_RPM, paper.SPEED_RPM), unit="rpm", gt=0.0, doc="initial speeds of gear A, gear B"
    )
    torque: float = param(paper.TORQUE, unit="N m", ge=0.0, doc="tau_0 of Fig. 7")
    theta_2_deg: float | None = param(None, unit="deg", gt=0.0, doc="two-pair zone (default from involute geometry)")
    theta_s_deg: float | None = param(
        None, unit="deg", gt=0.0, doc="single-tooth contact angle (default from geometry)"
    )
    span_deg: float | None = param(
        None, unit="deg", gt=0.0, doc="rotation of gear A simulated (default theta_s; at least one output record)"
    )
    driver: Literal["A", "B"] = param(
        "A", doc="[gear] pairs: gear that gets the drive torque; the other gets the load torque"
    )
    driver_speed_rpm: float | None = param(
        None,
        unit="rpm",
        gt=0.0,
        doc="[pinion]/[wheel] pairs (required there): initial speed of the driver; the driven "
        "gear starts at driver speed / ratio",
    )
    driven_speed_rpm: float | None = param(
        None,
        unit="rpm",
        gt=0.0,
        doc="[pinion]/[wheel] pairs: initial speed of the driven gear (default driver speed / ratio; "
        "another value is a speed mismatch: the teeth separate and strike, rattling)",
    )
    torque_on: Literal["pinion", "wheel"] | None = param(
        None,
        doc="[pinion]/[wheel] pairs: the gear 'torque' acts on (default the driver); the other "
        "gear's torque is this one times its tooth ratio (the convention of every gear verb)",
    )
    direction: Literal["forward", "reverse"] = param(
        "forward",
        doc="forward: gear A (pinion) turns counter-clockwise; reverse: clockwise, contact on the "
        "other flanks (run as the mirror image about the line of centres)",
    )


#: default contact smoothing of drawing pairs: their small teeth have short flank elements whose
#: slope kinks the paper's spline surfaces follow (docs/gear-dynamics.md, "Drawing pairs")
DRAWING_SMOOTHING = 12


@dataclass(frozen=True)
class MeshConfig:
    """FE tooth mesh: a preset or explicit element counts."""

    preset: Literal["default", "coarse", "fine"] = param(
        "default", doc="tooth mesh; 'fine' (2x default) needs dt <= 1.7e-8 s"
    )
    n_points: int = param(61, ge=8, le=1000, doc="spline data points per flank")
    contact_smoothing: int | None = param(
        None,
        ge=0,
        le=100,
        doc="contact surfaces without the short-wave flank deformation (the point force's own "
        "indentation, the slope kinks between short flank elements): uniform intervals of the "
        "least-squares cubic fit; 0 = paper's surfaces (paper_rk4 only; at most n_points - 3); "
        f"default: {DRAWING_SMOOTHING} for [pinion]/[wheel] pairs with paper_rk4, else 0",
    )

    def __post_init__(self) -> None:
        if self.contact_smoothing and self.contact_smoothing + 3 > self.n_points:
            raise InputError(
                "mesh.contact_smoothing", self.contact_smoothing, f"0 or 1..{self.n_points - 3} (n_points - 3)"
            )


#: default time step of paper_rk4 [s]; reduced_hht: REDUCED_STEP_ANGLE / omega_A
DEFAULT_DT = {"paper_rk4": 3e-8}
#: rotation of gear A per step of reduced_hht by default [rad] (1.2e-6 s at 4000 rpm,
#: 2.4e-7 s at 20000 rpm; see docs/gear-dynamics.md for the accuracy behind this choice)
REDUCED_STEP_ANGLE = 5e-4


@dataclass(frozen=True)
class SolverConfig:
    """Time integration of the dynamic-contact method."""

    method: Literal["paper_rk4", "reduced_hht"] = param(
        "paper_rk4",
        doc="paper_rk4: the paper's RK4 + multiplier passes; reduced_hht: "
        "Craig-Bampton teeth + implicit HHT-alpha (large steps, docs/gear-dynamics.md)",
    )
    dt: float | None = param(
        None, unit="s", gt=0.0, doc="time step (default 3e-8 s paper_rk4; 5e-4 rad / omega_A reduced_hht)"
    )
    multipliers: Literal["iterative", "direct"] = param(
        "iterative", doc="paper_rk4 passes: the iteration of eq. 19-24 or the direct solve"
    )
    modes: int = param(20, ge=0, le=500, doc="reduced_hht: fixed-interface modes per tooth (>= 1)")
    hht_alpha: float = param(-0.05, ge=-1.0 / 3.0, le=0.0, doc="reduced_hht: HHT alpha")
    tolerance: float = param(
        1e-12,
        unit="m",
        ge=TOLERANCE_RANGE[0],
        le=TOLERANCE_RANGE[1],
        doc="displacement tolerance; velocity/acceleration: tol/dt, tol/dt^2",
    )
    accel_n: int = param(4, ge=1, le=5, doc="acceleration level n of appendix B")
    max_iter: int = param(500, ge=1)
    restitution: float = param(
        0.0,
        ge=0.0,
        le=1.0,
        doc="Newton coefficient e of the contact-point impact law (0 = plastic, the paper's velocity pass)",
    )

    def __post_init__(self) -> None:
        if self.method == "reduced_hht" and self.modes < 1:
            raise InputError(
                "solver.modes",
                self.modes,
                ">= 1 with method = 'reduced_hht' (fixed-interface modes carry the "
                "tooth's inertia beyond its static shapes)",
            )


@dataclass(frozen=True)
class OutputConfig:
    """What is recorded and how often."""

    every: int | None = param(
        None, ge=1, doc="record every n-th step (1 = full rate; default 10 for paper_rk4, 1 for reduced_hht)"
    )
    vtu_snapshots: int = param(0, ge=0, le=1000, doc="number of VTU snapshots")
    root_stress: bool = param(True, doc="record the fillet nodes for root_stress(time, gear)")


@dataclass(frozen=True)
class ModelConfig:
    """Number of elastic teeth per gear."""

    teeth_per_gear: int = param(
        1,
        ge=1,
        le=12,
        doc="1: the paper's model with the Fig. 7 torque ramps; 2-12: "
        "adjacent teeth, several contact pairs alternating by geometry, constant torques "
        "([gear] and [pinion]/[wheel] pairs)",
    )
    start_angle_deg: float = param(
        -0.5, unit="deg", le=0.0, doc="contact angle of the entering pair at t = 0 (several teeth)"
    )
    mesh_window_deg: float = param(
        1.0,
        unit="deg",
        gt=0.0,
        le=5.0,
        doc="pairs are searched from this angle before the start of contact to this angle after its end "
        "(several teeth)",
    )

    def __post_init__(self) -> None:
        if self.start_angle_deg < -self.mesh_window_deg:
            raise InputError(
                "model.start_angle_deg", self.start_angle_deg, f">= -mesh_window_deg = {-self.mesh_window_deg:g}"
            )


@dataclass(frozen=True)
class GearCaseConfig:
    """A gear dynamic-contact case (`rotaflex gear simulate`): pair, material, operation, mesh, solver."""

    gear: GearConfig = field(default_factory=GearConfig)
    pinion: GearSpec | None = param(
        None,
        doc="gear A as on a drawing (keys of gear static); with [wheel], instead of [gear]; "
        'top-level pair = "lee_jang" gives both (the paper\'s pair), keys written here override it',
    )
    wheel: GearSpec | None = param(None, doc="gear B as on a drawing; with [pinion]")
    center_distance: float | None = param(
        None, unit="m", gt=0.0, doc="[pinion]/[wheel]: working centre distance (default: no backlash)"
    )
    backlash: float | None = param(None, unit="m", ge=0.0, doc="[pinion]/[wheel]: normal backlash j_bn")
    driver: Literal["pinion", "wheel"] | None = param(None, doc="[pinion]/[wheel]: gear that drives (default 'pinion')")
    material: MaterialConfig = field(default_factory=MaterialConfig)
    disk_inertia: float = param(paper.DISK_INERTIA, unit="kg m^2", gt=0.0)
    operation: OperationConfig = field(default_factory=OperationConfig)
    mesh: MeshConfig = field(default_factory=MeshConfig)
    solver: SolverConfig = field(default_factory=SolverConfig)
    output: OutputConfig = field(default_factory=OutputConfig)
    model: ModelConfig = field(default_factory=ModelConfig)

    def __post_init__(self) -> None:
        op = self.operation
        if op.theta_2_deg is not None and op.theta_s_deg is not None:
            if 2 * op.theta_2_deg > op.theta_s_deg:
                raise InputError(
                    "operation.theta_2_deg", op.theta_2_deg, f"<= theta_s_deg / 2 = {op.theta_s_deg / 2:g}"
                )
        if self.mesh.contact_smoothing and self.solver.method != "paper_rk4":
            raise InputError(
                "mesh.contact_smoothing", self.mesh.contact_smoothing, "0 unless solver.method = 'paper_rk4'"
            )
        if self.solver.method == "reduced_hht" and self.solver.restitution > 0.0:
            raise InputError(
                "solver.restitution",
                self.solver.restitution,
                "0 with method = 'reduced_hht' (its impact law is plastic)",
            )
        if self.model.teeth_per_gear > 1 and self.solver.method != "paper_rk4":
            raise InputError("solver.method", self.solver.method, "'paper_rk4' with [model] teeth_per_gear > 1")
        if (self.pinion is None) != (self.wheel is None):
            missing = "wheel" if self.wheel is None else "pinion"
            raise InputError(missing, None, "a table: [pinion] and [wheel] go together")
        if self.pinion is not None:
            if self.operation.driver_speed_rpm is None:
                raise InputError("operation.driver_speed_rpm", None, "a driver speed > 0 rpm with [pinion]/[wheel]")

    @property
    def pair(self):
        """The checked :class:`~rotaflex.gear.pair.drawing.PairSpec` of ``[pinion]``/``[wheel]``
        (None for a paper-style ``[gear]`` pair)."""
        if self.pinion is None:
            return None
        from rotaflex.gear.pair.drawing import PairSpec

        return (
            PairSpec(
                pinion=self.pinion,
                wheel=self.wheel,
                center_distance=self.center_distance,
                backlash=self.backlash,
                driver=self.driver or "pinion",
            )
            .check()
            .spur_only("gear simulate")
        )


#: tables and keys only ``gear static`` reads (a file may carry both verbs' tables)
STATIC_ONLY = {
    "load": None,
    "analysis": None,
    "face": None,
    "mesh": ("n_radii",),
    # gear steady's tables and keys (a [pinion]/[wheel] file may serve every verb)
    "mesh_stiffness": None,
    "train": None,
    "bearings": None,
    "steady": None,
    "sweep": None,
    "iso": None,
    "model": ("method", "n_modes", "tooth_damping_ratio", "corner_contact", "mesh_preset", "relief"),
    "operation": ("ramp_cycles",),
}
#: keys that belong to one pair layout only: (table, key or None for the whole table)
PAPER_ONLY = (
    ("gear", None),
    ("material", None),
    ("disk_inertia", None),
    ("operation", "speed_rpm"),
    ("operation", "driver"),
)
DRAWING_ONLY = (
    ("center_distance", None),
    ("backlash", None),
    ("driver", None),
    ("operation", "driver_speed_rpm"),
    ("operation", "driven_speed_rpm"),
    ("operation", "torque_on"),
)


def without(config: dict, drop: dict) -> dict:
    """``config`` without the tables (``drop[name] = None``) or table keys (a tuple) of
    ``drop``: the other verb's part of a file shared by ``gear static`` and ``gear simulate``."""
    out = {}
    for key, val in config.items():
        if key in drop and drop[key] is None:
            continue
        if key in drop and isinstance(val, dict):
            val = {k: v for k, v in val.items() if k not in drop[key]}
        out[key] = val
    return out


def _pinion_speed(config: dict) -> dict:
    """A drawing pair's ``operation.speed_rpm = N`` (the pinion speed, as ``gear steady`` reads
    it) as ``driver_speed_rpm`` when the pinion drives."""
    op = config.get("operation")
    if not isinstance(op, dict) or "speed_rpm" not in op or isinstance(op["speed_rpm"], (list, tuple)):
        return config
    n = op["speed_rpm"]
    if config.get("driver", "pinion") != "pinion":
        return config  # refused below: a wheel driver's speed is operation.driver_speed_rpm
    if op.get("driver_speed_rpm", n) != n:
        raise InputError(
            "operation.speed_rpm", n, f"omitted, or equal to operation.driver_speed_rpm = {op['driver_speed_rpm']}"
        )
    op = {k: v for k, v in op.items() if k != "speed_rpm"}
    return {**config, "operation": {**op, "driver_speed_rpm": n}}


def load_config(config: dict) -> GearCaseConfig:
    """The validated :class:`GearCaseConfig` of a parsed TOML mapping (no ``domain`` key).

    Static-only tables (:data:`STATIC_ONLY`) are ignored. A paper-style pair (``[gear]``,
    ``[material]``, ``disk_inertia``, ``operation.speed_rpm``/``driver``) and a drawing pair
    (``[pinion]``/``[wheel]``, ``center_distance``/``backlash``, top-level ``driver``,
    ``operation.driver_speed_rpm``) exclude each other: a key of the other layout is an
    InputError naming it.
    """
    from rotaflex.core.config import from_mapping
    from rotaflex.gear.cases.pair_config import refuse_other_layout, with_pair_preset

    config = with_pair_preset({k: v for k, v in config.items() if k != "domain"}, "simulate")
    refuse_other_layout(config, "simulate")
    config = without(config, STATIC_ONLY)
    drawing = "pinion" in config or "wheel" in config
    if drawing:
        config = _pinion_speed(config)
    for table, key in PAPER_ONLY if drawing else DRAWING_ONLY:
        sub = config.get(table)
        if key is None and table in config or key is not None and isinstance(sub, dict) and key in sub:
            name = table if key is None else f"{table}.{key}"
            value = config[table] if key is None else sub[key]
            if isinstance(value, dict):
                value = f"[{table}]"
            allowed = (
                "omitted with [pinion]/[wheel] (drawing pair: materials, blanks and the driver speed are "
                "in the pair tables and operation.driver_speed_rpm)"
                if drawing
                else "omitted with a paper-style [gear] pair (it belongs to a [pinion]/[wheel] pair)"
            )
            raise InputError(name, value, allowed)
    cfg = from_mapping(GearCaseConfig, config)
    it = cfg.solver.max_iter
    require("solver.max_iter", it, it, MAX_ITER, "iterations per step", "fixed (gear simulate MAX_ITER)")
    return cfg


#: 2x the default tooth mesh (1125 nodes; RK4 limit 1.74e-8 s, see docs/gear-fe.md)
FINE = dict(n_flank=20, n_through=10, n_fillet=4, n_rim=8)


@dataclass(frozen=True)
class Run:
    """What to integrate, in SI units (the kernel's gear A is the driver)."""

    method: str
    speeds: tuple[float, float]  # initial speeds of the kernel's gears A, B [rad/s]
    torque: float  # tau_0 [N m]
    theta_2: float  # [rad]
    theta_s: float  # [rad]
    span: float  # rotation of the driver [rad]
    dt: float  # [s]
    every: int
    n_steps: int
    driver: str
    teeth_per_gear: int
    start_angle: float  # [rad]
    window: float  # [rad]
    options: dict = field(default_factory=dict)  # method keywords (tolerances, ...)
    gain: tuple[float, float] = (1.0, 1.0)  # gear-ratio factor of the kernel's gears (1, z_B / z_A)
    direction: str = "forward"


def default_span(n_teeth: int, pitch: float, theta_s: float, start_angle: float) -> float:
    """Rotation of A simulated by default with several teeth: pair 1 from its start angle up to
    the entry of the next pair (two teeth), or up to the end of contact of pair ``n - 2`` (three
    or more: pair 1 over its whole contact theta_s, then one pitch more per further tooth)."""
    if n_teeth == 2:
        return pitch - start_angle
    return (n_teeth - 3) * pitch + theta_s - start_angle


def kernel_specs(cfg: GearCaseConfig, pair=None):
    """The drawing specs of a ``[pinion]``/``[wheel]`` pair in the kernel's order (driver
    first), or None for a ``[gear]`` pair."""
    pair = cfg.pair if pair is None else pair
    if pair is None:
        return None
    return (pair.pinion, pair.wheel) if pair.driver == "pinion" else (pair.wheel, pair.pinion)


def elastic_constants(cfg: GearCaseConfig) -> tuple[tuple[float, float], tuple[float, float]]:
    """((E_A, E_B) [Pa], (nu_A, nu_B)) of the kernel's gears (driver first)."""
    specs = kernel_specs(cfg)
    if specs is None:
        m = cfg.material
        return (m.youngs_modulus,) * 2, (m.poisson_ratio,) * 2
    return tuple(s.elastic[0] for s in specs), tuple(s.elastic[1] for s in specs)


def build(cfg: GearCaseConfig):
    """Geometry, tooth mesh and the assembled (unloaded) two-gear model of a configuration.

    For a ``[pinion]``/``[wheel]`` pair the kernel's gear A is the driver: the model holds
    (driver, driven) geometries, meshes, materials and blank inertias at the working centre
    distance, and the returned geometry and mesh are the driver's. With ``[model]
    teeth_per_gear > 1`` the model is :func:`rotaflex.gear.models.multitooth.build_multi_model` of the
    same per-gear data.
    """
    from rotaflex.gear.models import fe_pair as dynamics
    from rotaflex.gear.pair.tooth_mesh import COARSE, DEFAULT, build_tooth_mesh

    kw = {"coarse": COARSE, "default": DEFAULT, "fine": FINE}[cfg.mesh.preset]
    pair = cfg.pair
    n_teeth = cfg.model.teeth_per_gear
    if pair is not None:
        from rotaflex.gear.pair.drawing import pair_meshes

        geos, meshes = pair.gears, pair_meshes(pair, kw)
        inertia = (pair.pinion.inertia("pinion"), pair.wheel.inertia("wheel"))
        order = (0, 1) if pair.driver == "pinion" else (1, 0)
        mats = [s.material.values for s in kernel_specs(cfg, pair)]
        geo, mesh = (geos[order[0]], geos[order[1]]), (meshes[order[0]], meshes[order[1]])
        common = dict(
            youngs_modulus=tuple(m[0] for m in mats),
            poisson_ratio=tuple(m[1] for m in mats),
            density=tuple(m[2] for m in mats),
            inertia=tuple(inertia[i] for i in order),
            n_points=cfg.mesh.n_points,
            centre_distance=pair.working_center_distance,
        )
    else:
        g = cfg.gear.geometry()
        geo, mesh = (g, g), (build_tooth_mesh(g, **kw),) * 2
        mat = cfg.material
        common = dict(
            youngs_modulus=mat.youngs_modulus,
            poisson_ratio=mat.poisson_ratio,
            density=mat.density,
            inertia=(cfg.disk_inertia, cfg.disk_inertia),
            n_points=cfg.mesh.n_points,
        )
    if n_teeth > 1:
        from rotaflex.gear.models.multitooth import build_multi_model

        start = deg_to_rad(cfg.model.start_angle_deg)
        model = build_multi_model(geo, mesh, n_teeth, start_angle=start, **common)
    else:
        model = dynamics.build_model(*geo, *mesh, **common)
    return geo[0], mesh[0], model


def contact_smoothing(cfg: GearCaseConfig) -> int:
    """Contact-smoothing intervals of a case: as set, or the default (0 = the paper's surfaces
    for the paper's gear, :data:`DRAWING_SMOOTHING` for drawing pairs, which fit whenever
    ``n_points`` leaves room)."""
    if cfg.mesh.contact_smoothing is not None:
        return cfg.mesh.contact_smoothing
    drawing = cfg.pinion is not None and cfg.solver.method == "paper_rk4"
    return DRAWING_SMOOTHING if drawing and DRAWING_SMOOTHING + 3 <= cfg.mesh.n_points else 0


def to_run(cfg: GearCaseConfig, geo, model) -> Run:
    """Angles, speeds and the step count of a configuration in SI, with the size checks."""
    from rotaflex.gear.pair.geometry import contact_angles, contact_ratio

    op = cfg.operation
    sol = cfg.solver
    drawing = cfg.pinion is not None
    # kernel order (driver first); a [pinion]/[wheel] pair is checked by PairSpec.check in build
    g_a, g_b = model.geometry if drawing else (geo, geo)
    try:
        eps = contact_ratio(g_a, g_b, model.centre_distance if drawing else None)
        ths, th2 = contact_angles(g_a, g_b, model.centre_distance if drawing else None)
    except InputError as exc:
        raise InputError(f"gear.{exc.field}", exc.value, exc.allowed) from None
    del eps
    if op.theta_s_deg is not None:
        ths = deg_to_rad(op.theta_s_deg)
    if op.theta_2_deg is not None:
        th2 = deg_to_rad(op.theta_2_deg)
    if 2 * th2 > ths:
        raise InputError(
            "operation.theta_2_deg",
            op.theta_2_deg if op.theta_2_deg is not None else round(rad_to_deg(th2), 6),
            f"<= theta_s / 2 = {rad_to_deg(ths) / 2:g} deg",
        )
    # kernel gear A is always the driver (driver = "B": mirror image, see rotaflex.gear.results.transient)
    if drawing:
        # u = z_driven / z_driver: the driven gear turns u times slower and carries u x the torque
        ratio = g_b.teeth / g_a.teeth
        driven = op.driven_speed_rpm if op.driven_speed_rpm is not None else op.driver_speed_rpm / ratio
        rpm = (op.driver_speed_rpm, driven)
        driver = "B" if cfg.driver == "wheel" else "A"
        gain = (1.0, ratio)
    else:
        rpm = tuple(op.speed_rpm) if op.driver == "A" else tuple(op.speed_rpm[::-1])
        driver = op.driver
        gain = (1.0, 1.0)
    speeds = rpm_to_rad_s(rpm)
    n = cfg.model.teeth_per_gear
    start = deg_to_rad(cfg.model.start_angle_deg)
    window = deg_to_rad(cfg.model.mesh_window_deg)
    if op.span_deg is not None:
        span = deg_to_rad(op.span_deg)
    elif n > 1:
        span = default_span(n, 2 * math.pi / geo.teeth, ths, start)
    else:
        span = ths
    if n > 1:
        limit = (n - 1) * 2 * math.pi / geo.teeth - start
        if span > limit * (1 + 1e-9):
            raise InputError(
                "operation.span_deg",
                op.span_deg,
                f"<= {rad_to_deg(limit):.4g} deg with {n} teeth per gear (beyond "
                "it a pair of teeth that is not modelled would be in contact)",
            )
    if sol.dt is not None:
        dt = sol.dt
    elif sol.method == "reduced_hht":
        # per gear A's speed as typed (with driver = "B" too), as before the config split
        dt = REDUCED_STEP_ANGLE / float(rpm_to_rad_s(rpm[0] if drawing else op.speed_rpm[0]))
    else:
        dt = DEFAULT_DT[sol.method]
    every = cfg.output.every or (1 if sol.method == "reduced_hht" else 10)
    step_angle = float(speeds[0]) * dt
    n_steps = max(1, int(round(span / step_angle)))
    if span < every * step_angle * (1 - 1e-9):
        raise InputError(
            "operation.span_deg",
            op.span_deg,
            f">= {rad_to_deg(every * step_angle):.3g} deg: at least one output "
            f"record ({every} steps of {rad_to_deg(step_angle):.3g} deg)",
        )
    if n_steps > MAX_STEPS:
        key, value = (
            ("solver.dt", sol.dt) if sol.dt is not None or op.span_deg is None else ("operation.span_deg", op.span_deg)
        )
        raise InputError(
            key,
            value,
            f"a run of <= {MAX_STEPS:.0e} steps (this one: {n_steps:.3g} steps of "
            f"dt = {dt:g} s over {rad_to_deg(span):.4g} deg; raise solver.dt or "
            "shorten operation.span_deg)",
        )
    nn = int(model.n_nodes)
    n_rec = n_steps // every + 1
    per_rec = 8 * (19 + 13 * n + 2 * len(model.tie_node) + 16)
    mem = n_rec * per_rec + 8 * 2 * nn * cfg.output.vtu_snapshots
    if mem > MAX_OUTPUT_BYTES:
        raise InputError(
            "output.every",
            cfg.output.every,
            f"a decimation with recorded histories <= {MAX_OUTPUT_BYTES / 1e9:g} GB "
            f"(this one: {n_rec:.3g} records, {mem / 1e9:.3g} GB)",
        )
    require_memory("output.every", cfg.output.every, mem, "the recorded histories")
    if sol.method == "reduced_hht":
        options = dict(
            alpha=sol.hht_alpha, tol=sol.tolerance, max_iter=min(sol.max_iter, 100), modes=sol.modes, gain=gain
        )
    else:
        options = dict(
            tol=sol.tolerance,
            n_accel=sol.accel_n,
            max_iter=sol.max_iter,
            restitution=sol.restitution,
            multipliers=sol.multipliers,
            smoothing=contact_smoothing(cfg),
            gain=gain,
        )
    torque = op.torque
    if drawing and op.torque_on is not None and op.torque_on != (cfg.driver or "pinion"):
        torque = op.torque / ratio  # given on the driven gear: tau_0 on the driver
    return Run(
        method=sol.method,
        speeds=(float(speeds[0]), float(speeds[1])),
        torque=torque,
        theta_2=th2,
        theta_s=ths,
        span=span,
        dt=dt,
        every=every,
        n_steps=n_steps,
        driver=driver,
        teeth_per_gear=n,
        start_angle=start,
        window=window,
        options=options,
        gain=gain,
        direction=op.direction,
    )
