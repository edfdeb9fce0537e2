"""TOML case files for ``rotaflex floating simulate``: config dataclasses and ``run_case``.

Example (``examples/floating/planar_slew.toml``)::

    domain = "floating"
    [body]
    type = "beam"
    [body.beam]
    length = 4.0
    rho_a = 2.0
    ei = 40.0
    n_modes = 10
    [[loads]]
    kind = "torque"
    vector = [0.0, 0.0, 5.0]
    profile = "bang-bang"
    duration = 4.0
    [solver]
    method = "both"
    t_end = 10.0
    [outputs]
    tip = [2.0, 0.0, 0.0]
"""

from __future__ import annotations

import dataclasses
import json
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import numpy as np

from rotaflex.core.config import from_mapping, param
from rotaflex.core.errors import InputError
from rotaflex.floating.exact_case import ExactConfig
from rotaflex.floating.model import Initial, Load, Prescribed, Settings, Vec3, load_from

#: budgets checked before anything is allocated (memory and run time grow like n^2 and n^4)
MAX_BEAM_MODES = 100
MAX_FE_MODES = 200
MAX_FE_NODES = 2000
MAX_OUTPUT_SAMPLES = 1_000_000


@dataclass(frozen=True)
class BeamConfig:
    """Uniform Euler-Bernoulli beam with analytic modes (see ``uniform_beam``)."""

    length: float = param(unit="m", gt=0.0)
    rho_a: float = param(unit="kg/m", gt=0.0)
    ei: float = param(unit="N m^2", gt=0.0, doc="deflection along y")
    n_modes: int = param(5, ge=1, le=MAX_BEAM_MODES, doc="bending modes per plane")
    ei_z: float | None = param(None, unit="N m^2", gt=0.0, doc="deflection along z (spatial)")
    spatial: bool = param(False)
    support: Literal["free-free", "cantilever"] = param("free-free")
    section_radius: float = param(
        0.0,
        unit="m",
        ge=0.0,
        doc="radius of a solid circular section whose rigid-body inertia is added to J; 0 = a "
        "line beam (planar only: a spatial beam needs > 0 for its spin about its own axis)",
    )
    n_quad: int | None = param(None, ge=8, le=5000, doc="Gauss points per segment")


@dataclass(frozen=True)
class FrameConfig:
    """3-D frame FE model (uniform section) reduced to free-free modes (see ``frame_body``)."""

    nodes: tuple[Vec3, ...] = param(unit="m", doc="key points; each segment is subdivided")
    e: float = param(unit="Pa", gt=0.0)
    g: float = param(unit="Pa", gt=0.0)
    rho: float = param(unit="kg/m^3", gt=0.0)
    area: float = param(unit="m^2", gt=0.0)
    iy: float = param(unit="m^4", gt=0.0)
    iz: float = param(unit="m^4", gt=0.0)
    j: float = param(unit="m^4", gt=0.0)
    n_modes: int = param(6, ge=1, le=MAX_FE_MODES)
    elements_per_segment: int = param(10, ge=1, le=MAX_FE_NODES)
    up: Vec3 = param((0.0, 0.0, 1.0))


@dataclass(frozen=True)
class PointsConfig:
    """User-supplied nodes, masses and mass-orthonormal mode shapes."""

    masses: tuple[float, ...] = param(unit="kg")
    positions: tuple[Vec3, ...] = param(unit="m")
    shapes: tuple[tuple[Vec3, ...], ...] = param(doc="shapes[mode][node] = (ux, uy, uz)")
    frequencies: tuple[float, ...] = param(unit="rad/s")
    rotation_shapes: tuple[tuple[Vec3, ...], ...] | None = param(None)
    rotary_inertias: tuple[Vec3, ...] | None = param(
        None,
        unit="kg m^2",
        doc="principal rotary inertias of each node about body x, y, z (rigid-body inertia only)",
    )
    geometric: dict[str, tuple[tuple[float, ...], ...]] | None = param(
        None, doc="unit centrifugal geometric stiffness per pair xx, yy, zz, xy, xz, yz (n x n)"
    )


@dataclass(frozen=True)
class FileConfig:
    """Nodes, masses and mass-normalised modes from a NumPy ``.npz``, an HDF5 or a ``.csv`` file (layouts in
    :mod:`rotaflex.floating.modes_file` and docs/floating.md)."""

    path: str = param(doc="the .npz, .h5/.hdf5 or .csv file (relative paths: from the case file's directory)")
    frame: Literal["mean-axes", "attached"] = param(
        "mean-axes", doc="free-free modes in mean axes (checked) or modes clamped to the frame"
    )


@dataclass(frozen=True)
class AppendageConfig:
    """A flexible appendage clamped to the hub: a uniform beam from material and section, or an
    attached-frame modes file (``file``)."""

    root: Vec3 = param(unit="m", doc="clamped root in hub axes")
    direction: Vec3 = param((1.0, 0.0, 0.0), doc="appendage axis (local x) in hub axes")
    length: float | None = param(None, unit="m", gt=0.0, doc="beam length")
    e: float | None = param(None, unit="Pa", gt=0.0, doc="Young's modulus (aluminium 70e9)")
    rho: float | None = param(None, unit="kg/m^3", gt=0.0, doc="density (aluminium 2700)")
    width: float | None = param(None, unit="m", gt=0.0, doc="rectangular section width (out of the slew plane)")
    thickness: float | None = param(None, unit="m", gt=0.0, doc="rectangular section thickness (in the slew plane)")
    area: float | None = param(None, unit="m^2", gt=0.0, doc="or: section area")
    second_moment: float | None = param(None, unit="m^4", gt=0.0, doc="or: section second moment of area")
    n_modes: int = param(4, ge=1, le=MAX_BEAM_MODES, doc="clamped bending modes per plane")
    spatial: bool = param(False, doc="bending in both planes (default: in the slew plane only)")
    file: str | None = param(None, doc="instead of a beam: a modes file with frame 'attached' (local axes)")


@dataclass(frozen=True)
class HubConfig:
    """A rigid hub (the body origin at its centre) carrying flexible appendages as one body."""

    mass: float = param(unit="kg", gt=0.0)
    inertia: tuple[float, float, float] = param(unit="kg m^2", doc="principal moments about hub x, y, z")
    radius: float = param(0.0, unit="m", ge=0.0, doc="points with |r| <= radius are on the rigid hub")
    appendages: tuple[AppendageConfig, ...] = param((), doc="[[body.hub.appendages]] tables")


@dataclass(frozen=True)
class BodyConfig:
    """The flexible body: an analytic beam, an FE frame, point masses with modes, modes from a file,
    or a rigid hub with flexible appendages."""

    type: Literal["beam", "frame", "points", "file", "hub"] = param("beam")
    beam: BeamConfig | None = param(None)
    frame: FrameConfig | None = param(None)
    points: PointsConfig | None = param(None)
    file: FileConfig | None = param(None)
    hub: HubConfig | None = param(None)
    damping_ratio: float = param(0.0, ge=0.0, lt=1.0, doc="modal viscous damping ratio of every elastic mode")
    attachment_points: tuple[Vec3, ...] = param(
        (), unit="m", doc="load points for inertia-relief attachment modes (beam and frame)"
    )
    attach_at_loads: bool = param(
        False,
        doc="add attachment modes at every load point: unit-force shapes for forces, unit-moment shapes for torques",
    )
    model: Literal["modal", "exact"] = param(
        "modal",
        doc="modal (linear elastic body in a moving frame) or exact (planar geometrically exact beam, "
        "for deflections beyond ~1 % of L; docs/floating.md 'When to use which body')",
    )
    exact: ExactConfig | None = param(None, doc="[body.exact]: mesh and integrator of the exact body")

    def __post_init__(self):
        if getattr(self, self.type) is None:
            raise InputError(f"body.{self.type}", "<missing>", f"a [body.{self.type}] table")


@dataclass(frozen=True)
class ParaviewConfig:
    """Deformed-shape series for ParaView, written by ``rotaflex floating simulate`` into
    ``<out>/paraview/<solution>.pvd`` and one ``.vtu`` per kept output time."""

    every: int = param(1, ge=1, doc="keep every n-th output time")
    solution: Literal["full", "perturbation", "prescribed"] | None = param(
        None, doc="which solution (default: the first computed: full, or prescribed)"
    )


@dataclass(frozen=True)
class SlewConfig:
    """A rest-to-rest slew by ``angle_deg`` in ``duration`` about ``axis``.

    ``drive = "motion"``: the hub (body frame) follows the profile exactly (prescribed motion,
    the appendages respond). ``drive = "torque"``: the body-axis torque at the hub centre that
    would slew the rigid body along the profile (``J theta_ref''``, ``J`` about the centre of
    mass); the flexible body then ends near, not exactly at, the target. Residual vibration
    (after ``start + duration``) goes into the summary.
    """

    angle_deg: float = param(unit="deg", doc="slew angle")
    duration: float = param(unit="s", gt=0.0, doc="manoeuvre time")
    profile: Literal["bang-bang", "versine"] = param("versine", doc="bang-bang or versine (cycloidal)")
    drive: Literal["motion", "torque"] = param("torque", doc="prescribed hub motion or open-loop torque")
    axis: Vec3 = param((0.0, 0.0, 1.0), doc="slew axis (body frame)")
    start: float = param(0.0, unit="s", ge=0.0)
    settle_tolerance: float | None = param(
        None,
        unit="m",
        gt=0.0,
        doc="deflection band for the settling time (default 5 % of the largest deflection during the manoeuvre)",
    )

    @property
    def angle(self) -> float:
        """Slew angle [rad] (the config key is in degrees)."""
        return float(np.radians(self.angle_deg))

    @property
    def end(self) -> float:
        """End of the manoeuvre [s]."""
        return self.start + self.duration


@dataclass(frozen=True)
class FloatingCase:
    """A floating flexible body case: body, loads, initial state, prescribed motion, solver, outputs, ParaView."""

    body: BodyConfig = param()
    loads: tuple[Load, ...] = param(())
    initial: Initial = param(Initial())
    prescribed: Prescribed | None = param(None)
    slew: SlewConfig | None = param(None, doc="rest-to-rest slew manoeuvre (motion or torque)")
    solver: Settings = param(Settings())
    outputs: dict[str, Vec3] = param({}, unit="m", doc="named body points (undeformed, body frame)")
    paraview: ParaviewConfig | None = param(None, doc="write a ParaView series (an empty [paraview] table: defaults)")


_FRAME_FIELDS = {"body.elements": "body.frame.nodes", "body.n_modes": "body.frame.n_modes"}


def build_body(cfg: BodyConfig, loads=()):
    """The :class:`~rotaflex.floating.body.Body` of a body config (``loads`` for attach_at_loads).

    Errors name the field by its path in the case file (``body.points.masses[1]``).
    """
    from rotaflex.floating.body import renamed

    try:
        body = _build_body(cfg, loads)
        if cfg.damping_ratio > 0 and not body.rigid:
            from rotaflex.floating.body import with_damping

            body = with_damping(body, cfg.damping_ratio)
        return body
    except InputError as exc:
        if cfg.type == "frame":
            raise renamed(exc, _FRAME_FIELDS, "body.frame.") from None
        raise  # point bodies name body.points.* themselves


def _build_body(cfg: BodyConfig, loads=()):
    from rotaflex.floating.beam import uniform_beam
    from rotaflex.floating.body import point_body

    att = [tuple(p) for p in cfg.attachment_points]
    mom = []
    if cfg.attach_at_loads:
        att += [tuple(ld.point) for ld in loads if ld.kind == "force" and ld.point not in att]
        for ld in loads:
            if ld.kind == "torque" and tuple(ld.point) not in mom:
                mom.append(tuple(ld.point))
    if (att or mom) and cfg.type in ("points", "file"):
        raise InputError(
            "body.attach_at_loads" if cfg.attach_at_loads else "body.attachment_points",
            True if cfg.attach_at_loads else [list(p) for p in att],
            "none for a points body (supply the attachment shapes as extra modes from the FE program)",
        )

    if cfg.type == "beam":
        b = cfg.beam
        return uniform_beam(
            b.length,
            b.rho_a,
            b.ei,
            b.n_modes,
            ei_z=b.ei_z,
            spatial=b.spatial,
            support=b.support,
            n_quad=b.n_quad,
            section_radius=b.section_radius,
            attachment_points=att,
            moment_points=mom,
        )
    if cfg.type == "frame":
        from rotaflex.floating.fe import frame_body

        f = cfg.frame
        key = np.asarray(f.nodes, dtype=float)
        if len(key) < 2:
            raise InputError("body.frame.nodes", len(key), "at least 2 key points")
        k = f.elements_per_segment
        if (len(key) - 1) * k + 1 > MAX_FE_NODES:
            raise InputError(
                "body.frame.elements_per_segment",
                k,
                f"at most {(MAX_FE_NODES - 1) // (len(key) - 1)} for {len(key)} key points "
                f"(<= {MAX_FE_NODES} FE nodes: the dense eigensolution grows like nodes^3)",
            )
        nodes = [key[0]] + [
            key[i] + (key[i + 1] - key[i]) * s / k for i in range(len(key) - 1) for s in range(1, k + 1)
        ]
        return frame_body(
            np.array(nodes),
            e=f.e,
            g=f.g,
            rho=f.rho,
            area=f.area,
            iy=f.iy,
            iz=f.iz,
            j=f.j,
            n_modes=f.n_modes,
            up=f.up,
            attachment_points=att,
            moment_points=mom,
        )
    if cfg.type == "file":
        from rotaflex.floating.modes_file import load_modes

        return load_modes(cfg.file.path, cfg.file.frame)
    if cfg.type == "hub":
        return _hub(cfg.hub)
    p = cfg.points
    return point_body(
        p.masses,
        p.positions,
        p.shapes,
        frequencies=p.frequencies,
        rotation_shapes=p.rotation_shapes,
        rotary_inertias=p.rotary_inertias,
        geometric=p.geometric,
    )


def _hub(h: HubConfig):
    from rotaflex.floating.hub import beam_appendage, hub_body

    apps = []
    for i, a in enumerate(h.appendages):
        where = f"body.hub.appendages[{i}]"
        if a.file is not None:
            from rotaflex.floating.modes_file import load_modes

            app = load_modes(a.file, "attached", where=where + ".file")
        else:
            for key in ("length", "e", "rho"):
                if getattr(a, key) is None:
                    raise InputError(f"{where}.{key}", "<missing>", "a number > 0 for a beam appendage (or file = ...)")
            app = beam_appendage(
                a.length,
                a.e,
                a.rho,
                a.n_modes,
                width=a.width,
                thickness=a.thickness,
                area=a.area,
                second_moment=a.second_moment,
                spatial=a.spatial,
                where=where,
            )
        apps.append((app, a.root, a.direction))
    return hub_body(h.mass, h.inertia, apps, radius=h.radius)


#: root schema of a floating case file (for templates and generated config docs)
SCHEMA = FloatingCase


def _parse(config: dict) -> FloatingCase:
    """Config dataclasses from a parsed TOML table; errors name ``loads[i].field``."""
    if not isinstance(config, dict):
        raise InputError("config", type(config).__name__, "a table")
    loads = config.get("loads", ())
    if isinstance(loads, (list, tuple)):
        for i, ld in enumerate(loads):
            load_from(ld, f"loads[{i}]")
    case = from_mapping(FloatingCase, config)
    s = case.solver
    n_out = s.t_end / s.dt_out + 1.0
    if n_out > MAX_OUTPUT_SAMPLES:
        raise InputError(
            "solver.dt_out",
            s.dt_out,
            f"an interval >= t_end / {MAX_OUTPUT_SAMPLES - 1} = "
            f"{s.t_end / (MAX_OUTPUT_SAMPLES - 1):.3g} s (at most {MAX_OUTPUT_SAMPLES} output "
            "samples)",
        )
    return case


def prepare(config: dict):
    """Parse and check a case without integrating: ``(case, body, methods)``; ``case`` has the
    slew (if any) applied: its torque among the loads or its motion as ``prescribed``.

    Raises
    ------
    InputError
        Bad input (one line naming field, value and what is allowed).
    """
    from rotaflex.floating.solve import check_inputs, check_step_budget

    case = _parse(config)
    body = build_body(case.body, case.loads)
    case = _with_slew(case, body)
    for name, pt in case.outputs.items():
        try:
            body.shape_fn(np.array([pt], dtype=float))
        except InputError as exc:
            raise InputError(f"outputs.{name}", list(pt), exc.allowed) from None
    if case.body.model == "exact":
        from rotaflex.floating.exact_case import check
        from rotaflex.floating.exact_case3d import check as check3d

        if case.paraview is not None and case.paraview.solution not in (None, "full", "prescribed"):
            raise InputError(
                "paraview.solution", case.paraview.solution, "unset with body.model = 'exact' (one solution)"
            )
        three_d = (case.body.exact or ExactConfig()).dimension == 3
        return case, body, (check3d if three_d else check)(case, body)
    methods = ["full", "perturbation"] if case.solver.method == "both" else [case.solver.method]
    if case.prescribed is not None:
        if case.solver.method == "perturbation":
            raise InputError(
                "solver.method",
                "perturbation",
                "'full' or 'both' with [prescribed] motion (the frame's motion is given, so there is no "
                "rigid-body part to perturb; one 'prescribed' solution is computed)",
            )
        methods = ["full"]
    for m in methods:
        check_inputs(body, case.loads, case.initial, case.solver, m, case.prescribed is not None)
        check_step_budget(body, case.solver, m, case.prescribed)
    pv = case.paraview
    if pv is not None and pv.solution is not None:
        computed = ["prescribed"] if case.prescribed is not None else methods
        if pv.solution not in computed:
            raise InputError("paraview.solution", pv.solution, "a computed solution: one of " + ", ".join(computed))
    return case, body, methods


def _with_slew(case: FloatingCase, body) -> FloatingCase:
    """The case with its ``[slew]`` turned into a load (drive = torque) or prescribed motion."""
    sl = case.slew
    if sl is None:
        return case
    if float(np.linalg.norm(sl.axis)) == 0.0:
        raise InputError("slew.axis", list(sl.axis), "a non-zero vector")
    if sl.drive == "motion":
        if case.prescribed is not None:
            raise InputError("slew.drive", "motion", "'torque' with a [prescribed] table (one prescribed motion)")
        pres = Prescribed(axis=sl.axis, profile=sl.profile, angle=sl.angle, duration=sl.duration, start=sl.start)
        return dataclasses.replace(case, prescribed=pres)
    if case.prescribed is not None:
        raise InputError("slew.drive", "torque", "no [prescribed] table with a torque slew (the motion is computed)")
    from rotaflex.floating.hub import slew_torque

    ld = slew_torque(body, sl.angle, sl.duration, sl.profile, axis=sl.axis, start=sl.start)
    return dataclasses.replace(case, loads=(*case.loads, ld))


def resolve_paths(config: dict, base) -> dict:
    """A copy of ``config`` with a relative ``body.file.path`` joined to ``base`` (the directory
    of the case file), so a case runs the same from any working directory."""
    body = config.get("body")
    if not isinstance(body, dict):
        return config  # absent or malformed: the schema check reports it
    body = dict(body)
    file = body.get("file")
    path = file.get("path") if isinstance(file, dict) else None
    if isinstance(path, str) and not Path(path).is_absolute():
        body["file"] = {**file, "path": str(Path(base) / path)}
    hub = body.get("hub")
    apps = hub.get("appendages") if isinstance(hub, dict) else None
    if isinstance(apps, list):
        apps = [
            {**a, "file": str(Path(base) / a["file"])}
            if isinstance(a, dict) and isinstance(a.get("file"), str) and not Path(a["file"]).is_absolute()
            else a
            for a in apps
        ]
        body["hub"] = {**hub, "appendages": apps}
    return {**config, "body": body}


def validate_config(config: dict) -> None:
    """Check a parsed TOML case (without the ``domain`` key) the way ``run_case`` does, without
    integrating; used by sweeps for every case up front.

    Raises
    ------
    InputError
        Bad input (one line naming field, value and what is allowed).
    """
    prepare(config)


def _progress_for(progress, label: str, t_end: float):
    """Progress over simulated time of one solver run (:class:`rotaflex.core.progress.Progress`:
    a bar on a terminal, one line per 10 % otherwise); ``progress``: False, True, or
    ``"lines"`` (lines even on a terminal)."""
    from rotaflex.core.progress import Progress

    desc = f"simulating {label}".strip()
    return Progress(t_end, desc, "s", enabled=bool(progress), tty=False if progress == "lines" else None)


#: first-run compilation of the floating kernels [s]: the largest cold compile of any one
#: examples/floating case (benchmarks/bench_floating_compile.py; a run compiles only the
#: integrator loop and right-hand side of its method)
COMPILE_SECONDS = 28.0


def _announce_kernels(case, methods) -> bool:
    """Say once, before the first kernel call, that the kernels this run uses compile now (cold
    numba cache only): the integrator loop and right-hand side of each of its methods."""
    from rotaflex.core.jit import announce_compilation
    from rotaflex.floating.integrator import kernels
    from rotaflex.floating.solve import run_mode

    used = [k for m in methods for k in kernels(run_mode(m, case.prescribed, case.solver))]
    return announce_compilation("floating-body", used, COMPILE_SECONDS)


def run_case(config: dict, *, progress: bool | str = False):
    """Validate a parsed TOML config and simulate it; returns a ``FloatingResult``.

    ``progress``: True shows a bar over simulated time on a terminal and one line per 10 % of
    it otherwise; ``"lines"`` always lines; False nothing.

    Raises
    ------
    InputError
        Bad input (one line naming field, value and what is allowed).
    """
    from rotaflex.floating.result import build_result
    from rotaflex.floating.solve import simulate

    t0 = time.perf_counter()
    case, body, methods = prepare(config)
    if case.body.model == "exact":
        return _run_exact(case, body, methods, progress, t0)
    _announce_kernels(case, methods)
    sols = []
    for m in methods:
        with _progress_for(progress, m if len(methods) > 1 else "", case.solver.t_end) as bar:
            call = bar.update if progress else None
            sols.append(simulate(body, case.loads, case.initial, case.solver, m, case.prescribed, progress=call))
    resolved = json.loads(json.dumps(dataclasses.asdict(case)))
    result = build_result(body, sols, dict(case.outputs), resolved, time.perf_counter() - t0)
    _set_manoeuvre(result, case)
    if case.paraview is not None:
        from rotaflex.floating.paraview import frames

        name = case.paraview.solution or sols[0].method
        result.paraview = (name, frames(result, body, solution=name, every=case.paraview.every))
    return result


def _run_exact(case, body, plan, progress, t0):
    """``run_case`` for ``body.model = "exact"`` (``plan`` from :func:`rotaflex.floating.exact_case.check`)."""
    from rotaflex.core.jit import announce_compilation
    from rotaflex.floating import exact_kernels
    from rotaflex.floating.exact_case import COMPILE_SECONDS_3D
    from rotaflex.floating.exact_case import run as run2d
    from rotaflex.floating.exact_case3d import run as run3d
    from rotaflex.floating.exact_result import build_exact_result, paraview_frames

    if plan["exact"].dimension == 3:
        from rotaflex.floating import exact_kernels3d

        announce_compilation("exact-beam-3d", [exact_kernels3d], COMPILE_SECONDS_3D)

        def run(case, body, plan, progress=None):
            return run3d(case, plan, progress)
    else:
        announce_compilation("exact-beam", [exact_kernels.integrate], EXACT_COMPILE_SECONDS)
        run = run2d
    label = {"dynamic": "", "static": "static", "both": "exact, then static"}[plan["exact"].analysis]
    with _progress_for(progress, label, case.solver.t_end) as bar:
        sols = run(case, body, plan, progress=bar.update if progress else None)
    resolved = json.loads(json.dumps(dataclasses.asdict(case)))
    result = build_exact_result(
        plan["beam"], sols, dict(case.outputs), resolved, time.perf_counter() - t0, plan["frame"]
    )
    _set_manoeuvre(result, case)
    if case.paraview is not None:
        result.paraview = (sols[0].method, paraview_frames(result, case.paraview.every))
    return result


def _set_manoeuvre(result, case) -> None:
    """The slew (if any) as ``attrs["manoeuvre"]`` (read by the summary's residual vibration)."""
    if case.slew is None:
        return
    sl = case.slew
    result.dataset.attrs["manoeuvre"] = json.dumps(
        {
            "profile": sl.profile,
            "drive": sl.drive,
            "angle": sl.angle,
            "axis": list(np.asarray(sl.axis) / np.linalg.norm(sl.axis)),
            "start": sl.start,
            "end": sl.end,
            "settle_tolerance": sl.settle_tolerance,
        }
    )


#: first-run compilation of the exact-beam kernels [s]: 28 s CPU measured cold (docs/floating.md)
EXACT_COMPILE_SECONDS = 30.0
