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
class BodyConfig:
    """The flexible body: an analytic beam, an FE frame, point masses with modes, or modes from a file."""

    type: Literal["beam", "frame", "points", "file"] = param("beam")
    beam: BeamConfig | None = param(None)
    frame: FrameConfig | None = param(None)
    points: PointsConfig | None = param(None)
    file: FileConfig | None = param(None)
    attachment_points: tuple[Vec3, ...] = param(
        (), unit="m", doc="load points for inertia-relief attachment modes (beam and frame)"
    )
    attach_at_loads: bool = param(
        False,
        doc="add attachment modes at every load point: unit-force shapes for forces, unit-moment shapes for torques",
    )

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
class FloatingCase:
    """A floating flexible body case: body, loads, initial state, prescribed motion, solver, outputs, ParaView."""

    body: BodyConfig = param()
    loads: tuple[Load, ...] = param(())
    initial: Initial = param(Initial())
    prescribed: Prescribed | None = param(None)
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
        return _build_body(cfg, loads)
    except InputError as exc:
        if cfg.type == "frame":
            raise renamed(exc, _FRAME_FIELDS, "body.frame.") from None
        raise  # point bodies name body.points.* themselves


def _build_body(cfg: BodyConfig, loads=()):
    from rotaflex.floating.body import point_body, uniform_beam

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
    """Parse and check a case without integrating: ``(case, body, methods)``.

    Raises
    ------
    InputError
        Bad input (one line naming field, value and what is allowed).
    """
    from rotaflex.floating.solve import check_inputs

    case = _parse(config)
    body = build_body(case.body, case.loads)
    for name, pt in case.outputs.items():
        try:
            body.shape_fn(np.array([pt], dtype=float))
        except InputError as exc:
            raise InputError(f"outputs.{name}", list(pt), exc.allowed) from None
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
    pv = case.paraview
    if pv is not None and pv.solution is not None:
        computed = ["prescribed"] if case.prescribed is not None else methods
        if pv.solution not in computed:
            raise InputError("paraview.solution", pv.solution, "a computed solution: one of " + ", ".join(computed))
    return case, body, methods


def resolve_paths(config: dict, base) -> dict:
    """A copy of ``config`` with a relative ``body.file.path`` joined to ``base`` (the directory
    of the case file), so a case runs the same from any working directory."""
    body = config.get("body")
    file = body.get("file") if isinstance(body, dict) else None
    path = file.get("path") if isinstance(file, dict) else None
    if not isinstance(path, str) or Path(path).is_absolute():
        return config  # absent or malformed: the schema check reports it
    body = dict(config["body"])
    body["file"] = {**body["file"], "path": str(Path(base) / path)}
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


def run_case(config: dict, *, progress: bool = False):
    """Validate a parsed TOML config and simulate it; returns a ``FloatingResult``.

    Raises
    ------
    InputError
        Bad input (one line naming field, value and what is allowed).
    """
    from rotaflex.floating.result import build_result
    from rotaflex.floating.solve import simulate

    t0 = time.perf_counter()
    case, body, methods = prepare(config)
    sols = [simulate(body, case.loads, case.initial, case.solver, m, case.prescribed) for m in methods]
    resolved = json.loads(json.dumps(dataclasses.asdict(case)))
    result = build_result(body, sols, dict(case.outputs), resolved, time.perf_counter() - t0)
    if case.paraview is not None:
        from rotaflex.floating.paraview import frames

        name = case.paraview.solution or sols[0].method
        result.paraview = (name, frames(result, body, solution=name, every=case.paraview.every))
    return result
