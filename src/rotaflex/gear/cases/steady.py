"""``rotaflex gear steady``: config -> torsional steady-state point or speed sweep -> result.

The config (tables, defaults, checks) is :mod:`~rotaflex.gear.cases.steady_config`; what a point
writes besides the solver's metrics is :mod:`~rotaflex.gear.cases.steady_output`. This module
builds the model (pair data, mesh table, torsional system, elastic-tooth window; each cached by
content so the cases of a sweep share it) and runs it.

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

import numpy as np

from rotaflex.core.config import to_mapping
from rotaflex.core.errors import InputError
from rotaflex.core.result import Result
from rotaflex.gear.cases.steady_config import (
    SCHEMA,
    GearSpec,
    IsoSpec,
    MeshSpec,
    ModelSpec,
    OperationSpec,
    SteadySpec,
    SweepSpec,
    TorsionalCaseConfig,
    checked,
    validate_config,
)
from rotaflex.gear.cases.steady_output import helical_extras, iso_data, iso_tip_relief, node_names, point_extras
from rotaflex.gear.cases.steady_size import announce_kernels, check_model_size
from rotaflex.gear.models.chain import OperatingPoint, State, TorsionalSystem
from rotaflex.gear.models.mesh_stiffness import contact_pattern_mesh, mesh_table_from_static
from rotaflex.gear.pair.geometry import center_distance_no_backlash, contact_ratio
from rotaflex.gear.results.steady_sweep import sweep_dataset
from rotaflex.gear.solvers.registry import METHODS
from rotaflex.gear.solvers.steady_driver import LateProgress, continuation

__all__ = [
    "SCHEMA",
    "ModelSpec",
    "PairData",
    "TorsionalCaseConfig",
    "build_model",
    "build_system",
    "pair_data",
    "pair_line_of",
    "run_torsional",
    "validate_config",
]

#: the names of the former one-module layout (tests and scripts import them from here)
_checked = checked
_iso_tip_relief = iso_tip_relief


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
        if cfg.pair is not None and (cfg.pair.sliced or cfg.face.misalignment != 0.0):  # helical / lead-modified
            from rotaflex.gear.models.mesh_stiffness import sliced_mesh_table
            from rotaflex.gear.static.helical import face_model

            f = cfg.face
            face = face_model(cfg.pair, f.slices, f.coupling_length_coef, f.misalignment)
            mesh = sliced_mesh_table(line, face, line.force, cfg.mesh_stiffness.table_points)
        else:
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


def run_torsional(config: dict, *, progress: bool = False, initial_state: dict | None = None) -> Result:
    """Validate ``config`` (module docstring), run one steady state or a speed sweep.

    ``initial_state`` (single point only): continue from this ``final_state()`` of an earlier
    point (angles and vibration velocities kept, mean speeds moved to this speed) instead of
    starting from the static equilibrium.
    """
    cfg = checked(config)
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
    if state is not None and len(state.theta) != len(names := node_names(sys, cfg)):
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

        iso = iso_data(cfg, sys, eps, face_width)
        points = continuation(point, speeds, directions)
        res = sweep_dataset(points, speeds, directions, sys, op.torque, iso=iso, started=t0)
        helical_extras(res.dataset, cfg.pair, op.torque, sys.base_radius[1])
    else:
        res, _ = _steady_point(cfg, sys, eps, model, face_width, state, kw, progress=bar)
    bar.close()
    res.dataset["iso_tip_relief"] = (
        (),
        iso_tip_relief(cfg),
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
    point_extras(res, sys, st, cfg, eps, face_width)
    ds = res.dataset
    kv, n_res = float(ds["dynamic_factor"]), float(ds["resonance_speed"])
    if cfg.model.method == "lumped" and op.speed_rpm < 0.25 * n_res and kv > LOW_SPEED_KV:
        ds.attrs["message"] += (
            f"; note: K_v {kv:.3f} far below the resonance ({n_res:.0f} rpm) comes from the lumped "
            "mesh spring's step response where the stiffness changes between one and two pairs; "
            "model.method = 'elastic_teeth' resolves each pair's engagement (docs/gear-steady-state.md)"
        )
    return res, st
