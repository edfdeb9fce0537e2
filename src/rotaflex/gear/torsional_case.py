"""Config -> torsional steady-state point or speed sweep -> result.

TOML tables (SI unless the key names its unit; all optional, defaults = the paper's pair)::

    [gear]       module, teeth = [z1, z2], pressure_angle_deg, face_width, tip_radius,
                 root_radius (radii of both gears; omitted: derived), youngs_modulus, poisson_ratio
    [mesh]       source = "static_fe" | "contact_pattern", pair_stiffness (contact_pattern),
                 unloaded_te_pp, damping_ratio = 0.07, backlash (omitted: no back-side contact),
                 table_points
    [train]      inertia = [J1, J2], motor_inertia, load_inertia, input_shaft_stiffness,
                 output_shaft_stiffness (omitted: rigid), input_shaft_damping,
                 output_shaft_damping, drive = "motor" | "constant_speed", motor_slope
    [operation]  speed_rpm, torque (output, N m), ramp_cycles
    [steady]     tol, min_cycles, max_cycles, eval_cycles, fixed_cycles, steps_per_cycle
    [sweep]      speeds_rpm = [...] (two or more: an up-and-down sweep instead of one point),
                 directions = ["up", "down"]
    [iso]        f_pb_eff, f_f_eff, tip_relief (m), application_factor (ISO 6336-1 K_v overlay)

:func:`run_torsional` has the signature of the domain command registry
(``fn(config, *, progress=False) -> Result``); with ``initial_state`` (the ``final_state()`` of
an earlier single-point result) one steady state continues from that state, which is how
``rotaflex sweep --continuation operation.speed_rpm`` chains the speeds of a sweep.
:func:`validate_config` checks a config without running it.
"""

from __future__ import annotations

import functools
import json
import math
from dataclasses import dataclass
from typing import Literal

import numpy as np

from rotaflex.core.config import from_mapping, param, to_mapping
from rotaflex.core.errors import InputError
from rotaflex.core.result import Result
from rotaflex.gear.geometry import GearGeometry, contact_ratio
from rotaflex.gear.iso6336_kv import iso_kv
from rotaflex.gear.torsional import (
    OperatingPoint,
    State,
    TorsionalSystem,
    contact_pattern_mesh,
    mesh_table_from_static,
    natural_frequencies,
    steady_state,
)
from rotaflex.gear.torsional_sweep import iso_input, speed_sweep

__all__ = ["SCHEMA", "TorsionalCaseConfig", "build_system", "run_torsional", "validate_config"]


@dataclass(frozen=True)
class GearSpec:
    module: float = param(3.175e-3, unit="m", gt=0.0)
    teeth: tuple[int, int] = param((28, 28), doc="(pinion, wheel)")
    pressure_angle_deg: float = param(20.0, unit="deg", gt=5.0, lt=45.0)
    face_width: float = param(6.35e-3, unit="m", gt=0.0)
    tip_radius: tuple[float, float] | None = param(None, unit="m", doc="omitted: derived")
    root_radius: tuple[float, float] | None = param(None, unit="m", doc="omitted: derived")
    youngs_modulus: float = param(210e9, unit="Pa", gt=0.0)
    poisson_ratio: float = param(0.3, gt=0.0, lt=0.5)

    def geometry(self) -> tuple[GearGeometry, GearGeometry]:
        return tuple(
            GearGeometry(
                module=self.module,
                teeth=z,
                face_width=self.face_width,
                pressure_angle_deg=self.pressure_angle_deg,
                tip_radius=None if self.tip_radius is None else self.tip_radius[i],
                root_radius=(None if self.root_radius is None else self.root_radius[i]),
            )
            for i, z in enumerate(self.teeth)
        )


@dataclass(frozen=True)
class MeshSpec:
    source: Literal["static_fe", "contact_pattern"] = param(
        "static_fe", doc="static FE mesh stiffness (gear.static) or the analytic 1/2-pair model"
    )
    pair_stiffness: float = param(1.2e8, unit="N/m", gt=0.0, doc="contact_pattern only")
    unloaded_te_pp: float = param(0.0, unit="m", ge=0.0, doc="triangular unloaded TE per cycle (contact_pattern only)")
    damping_ratio: float = param(0.07, ge=0.0, doc="mesh damping ratio zeta")
    backlash: float | None = param(None, unit="m", ge=0.0, doc="omitted: no back-side contact")
    table_points: int = param(400, ge=16)


@dataclass(frozen=True)
class TrainSpec:
    inertia: tuple[float, float] = param((2.965e-4, 2.965e-4), unit="kg m^2")
    motor_inertia: float = param(0.0, unit="kg m^2", ge=0.0)
    load_inertia: float = param(0.0, unit="kg m^2", ge=0.0)
    input_shaft_stiffness: float | None = param(None, unit="N m/rad", gt=0.0, doc="omitted: rigid")
    input_shaft_damping: float = param(0.0, unit="N m s/rad", ge=0.0)
    output_shaft_stiffness: float | None = param(None, unit="N m/rad", gt=0.0, doc="omitted: rigid")
    output_shaft_damping: float = param(0.0, unit="N m s/rad", ge=0.0)
    drive: Literal["motor", "constant_speed"] = param("motor")
    motor_slope: float = param(0.5, unit="N m s/rad", gt=0.0)


@dataclass(frozen=True)
class OperationSpec:
    speed_rpm: float = param(10000.0, unit="rpm", gt=0.0)
    torque: float = param(22.25, unit="N m", gt=0.0, doc="output torque")
    ramp_cycles: float = param(0.0, ge=0.0)


@dataclass(frozen=True)
class SteadySpec:
    tol: float = param(1e-4, gt=0.0)
    min_cycles: int = param(20, ge=2)
    max_cycles: int = param(400, ge=2)
    eval_cycles: int = param(10, ge=1)
    fixed_cycles: int | None = param(None, ge=2)
    steps_per_cycle: int = param(100, ge=8)


@dataclass(frozen=True)
class SweepSpec:
    speeds_rpm: tuple[float, ...] = param((), unit="rpm", gt=0.0)
    directions: tuple[str, ...] = param(("up", "down"))


@dataclass(frozen=True)
class IsoSpec:
    f_pb_eff: float = param(0.0, unit="m", ge=0.0)
    f_f_eff: float = param(0.0, unit="m", ge=0.0)
    tip_relief: float = param(0.0, unit="m", ge=0.0)
    application_factor: float = param(1.0, ge=1.0)


@dataclass(frozen=True)
class TorsionalCaseConfig:
    gear: GearSpec = param(GearSpec())
    mesh: MeshSpec = param(MeshSpec())
    train: TrainSpec = param(TrainSpec())
    operation: OperationSpec = param(OperationSpec())
    steady: SteadySpec = param(SteadySpec())
    sweep: SweepSpec = param(SweepSpec())
    iso: IsoSpec = param(IsoSpec())


SCHEMA = TorsionalCaseConfig


@functools.lru_cache(maxsize=8)
def _mesh_table(gear: GearSpec, mesh_spec: MeshSpec, torque: float):
    """Mesh table and contact ratio; cached per process because the static FE table (~0.5 s)
    is the same for every speed of a sweep (frozen specs are hashable keys)."""
    g1, g2 = gear.geometry()
    eps = contact_ratio(g1, g2)
    if mesh_spec.source == "static_fe":
        from rotaflex.gear.static import mesh_stiffness

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


def build_system(cfg: TorsionalCaseConfig) -> tuple[TorsionalSystem, float]:
    """The torsional model and the contact ratio of ``cfg``."""
    g1, g2 = cfg.gear.geometry()
    mesh, eps = _mesh_table(cfg.gear, cfg.mesh, cfg.operation.torque)
    t = cfg.train
    sys = TorsionalSystem(
        mesh=mesh,
        teeth=tuple(cfg.gear.teeth),
        base_radius=(g1.base_radius, g2.base_radius),
        inertia=tuple(t.inertia),
        motor_inertia=t.motor_inertia,
        load_inertia=t.load_inertia,
        input_shaft_stiffness=t.input_shaft_stiffness or math.inf,
        input_shaft_damping=t.input_shaft_damping,
        output_shaft_stiffness=t.output_shaft_stiffness or math.inf,
        output_shaft_damping=t.output_shaft_damping,
        mesh_damping_ratio=cfg.mesh.damping_ratio,
        backlash=-1.0 if cfg.mesh.backlash is None else cfg.mesh.backlash,
        drive=t.drive,
        motor_slope=t.motor_slope,
    )
    return sys, eps


def _checked(config: dict) -> TorsionalCaseConfig:
    cfg = from_mapping(TorsionalCaseConfig, config)
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
    g1, g2 = cfg.gear.geometry()
    eps = contact_ratio(g1, g2)
    if cfg.mesh.source == "contact_pattern" and not 1.0 < eps < 2.0:
        raise InputError("gear", f"contact ratio {eps:.3f}", "1 < eps < 2 for mesh.source = 'contact_pattern'")
    return cfg


def validate_config(config: dict) -> None:
    """Check a ``gear steady`` config completely without running it (InputError otherwise)."""
    _checked(config)


def _state_of(initial_state) -> State:
    try:
        return State(
            np.asarray(initial_state["theta"], dtype=float),
            np.asarray(initial_state["omega"], dtype=float),
            float(initial_state["time"]),
            np.asarray(initial_state["nominal"], dtype=float),
        )
    except (KeyError, TypeError, ValueError) as exc:
        what = f"a final_state() of gear steady ({exc})"
        raise InputError("initial_state", type(initial_state).__name__, what) from None


def _point_extras(res, sys: TorsionalSystem, st: State, cfg: TorsionalCaseConfig, eps: float) -> None:
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
    iso = iso_input(
        sys,
        op.torque,
        cfg.gear.face_width,
        eps,
        f_pb_eff=cfg.iso.f_pb_eff,
        f_f_eff=cfg.iso.f_f_eff,
        tip_relief=cfg.iso.tip_relief,
        application_factor=cfg.iso.application_factor,
    )
    ds["iso_kv"] = ((), float(iso_kv(iso, [op.speed_rpm])[0]), {"units": "1", "long_name": "ISO 6336-1 method B K_v"})
    ds["iso_resonance_speed"] = ((), float(iso.resonance_speed_rpm), {"units": "rpm"})
    ds["state_theta"] = ("chain_node", st.theta, {"units": "rad", "long_name": "final angles"})
    ds["state_omega"] = ("chain_node", st.omega, {"units": "rad/s", "long_name": "final speeds"})
    ds["state_nominal"] = ("chain_node", st.nominal, {"units": "rad/s", "long_name": "final nominal speeds"})
    ds.attrs["state_time"] = st.time


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
    sys, eps = build_system(cfg)
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
    if len(cfg.sweep.speeds_rpm) >= 2:
        iso = iso_input(
            sys,
            op.torque,
            cfg.gear.face_width,
            eps,
            f_pb_eff=cfg.iso.f_pb_eff,
            f_f_eff=cfg.iso.f_f_eff,
            tip_relief=cfg.iso.tip_relief,
            application_factor=cfg.iso.application_factor,
        )
        res = speed_sweep(sys, op.torque, cfg.sweep.speeds_rpm, directions=cfg.sweep.directions, iso=iso, **kw)
    else:
        res, st = steady_state(sys, OperatingPoint(op.speed_rpm, op.torque, op.ramp_cycles), state=state, **kw)
        _point_extras(res, sys, st, cfg, eps)
    res.dataset.attrs["config"] = json.dumps(to_mapping(cfg))
    return res
