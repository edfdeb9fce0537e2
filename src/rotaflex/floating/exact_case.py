"""``body.model = "exact"``: a floating case run on the planar geometrically exact beam.

The same case file as the modal body (``[body.beam]`` or ``[body.hub]`` with beam appendages,
``[[loads]]``, ``[slew]``/``[prescribed]``, ``[initial]``, ``[solver]``, ``[outputs]``,
``[paraview]``) plus an optional ``[body.exact]`` table (:class:`ExactConfig`). The modal body of
the same config is still built: it gives the slew torque (rigid inertia), the first natural
frequency (default time step, material damping) and checks the output points.

What the frame is:

* ``type = "beam"``, ``support = "cantilever"``: the root (x = 0) is clamped to the body frame,
  which is fixed in space, or follows ``[prescribed]`` (spin-up, slews). (A modal cantilever
  without ``[prescribed]`` floats with its root frame; the exact one is clamped to the ground:
  use a hub for a floating root.)
* ``type = "beam"``, ``support = "free-free"``: a free beam (x from -L/2 to L/2); outputs are
  read in the frame of its centre of mass turned by the mass-weighted best fit of the nodes to
  their reference positions (the rotation that zeros ``sum m r0 x u``, the mean axes' condition).
* ``type = "hub"``: a rigid hub (free, or following ``[prescribed]`` / a motion slew) with the
  appendages clamped at their roots.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Literal

import numpy as np

from rotaflex.core.config import param
from rotaflex.core.errors import InputError
from rotaflex.floating.exact_beam import MAX_ELEMENTS, ExactBeam, PointLoads, assemble, solve_static, straight

#: default EA L^2 / EI and GA L^2 / EI of a [body.beam] (which gives only EI): axial and shear
#: strains ~1e-5 of the bending ones, the inextensible, shear-rigid limit of the reference
#: (:mod:`rotaflex.floating.reference`)
STIFF_RATIO = 3.2e5
#: Poisson's ratio and shear coefficient of a hub appendage's default GA = k E / (2 (1 + nu)) A
POISSON, SHEAR_COEFFICIENT = 0.3, 5.0 / 6.0
#: default time step: this fraction of the first elastic period
STEPS_PER_PERIOD = 200
#: first-run compilation of the 3-D kernels [s]: 27 s CPU measured cold (docs/floating.md)
COMPILE_SECONDS_3D = 27.0


@dataclass(frozen=True)
class ExactConfig:
    """``[body.exact]``: mesh, section stiffnesses the modal body does not need, integrator."""

    elements: int = param(20, ge=1, le=MAX_ELEMENTS, doc="elements per beam (or per appendage)")
    ea: float | None = param(None, unit="N", gt=0.0, doc="axial stiffness (default: E A, or 3.2e5 EI / L^2)")
    ga: float | None = param(
        None, unit="N", gt=0.0, doc="shear stiffness (default: 5/6 E A / 2.6 (nu 0.3), or 3.2e5 EI / L^2)"
    )
    rho_i: float | None = param(None, unit="kg m", ge=0.0, doc="rotary inertia per length (default rho_a EI / EA)")
    analysis: Literal["dynamic", "static", "both"] = param(
        "dynamic",
        doc="'dynamic' (time history), 'static' (equilibrium under the loads at each output time, "
        "inertia ignored, frame held) or 'both'",
    )
    time_step: float | None = param(None, unit="s", gt=0.0, doc="largest step (default: first period / 200)")
    rho_inf: float = param(0.9, ge=0.0, le=1.0, doc="generalized-alpha spectral radius at infinity (1: no damping)")
    gravity: tuple[float, float, float] = param((0.0, 0.0, 0.0), unit="m/s^2", doc="gravity (inertial)")
    mass: Literal["consistent", "lumped"] = param(
        "consistent",
        doc="'consistent' or 'lumped' (lumped: much smaller errors in the higher modes, docs/floating.md)",
    )

    dimension: Literal[2, 3] = param(
        2,
        doc="2: the planar Reissner beam (x-y plane); 3: the 3-D Simo-Reissner beam "
        "(cantilever on a prescribed frame, or appendages of a hub on a fixed axis)",
    )
    gj: float | None = param(None, unit="N m^2", gt=0.0, doc="3-D: torsional stiffness (default (EI2 + EI3) / 2.6)")
    bend_radius: float | None = param(
        None, unit="m", gt=0.0, doc="3-D: the beam bent in the x-y plane towards +y with this radius (default straight)"
    )

    def __post_init__(self):
        if self.dimension not in (2, 3):
            raise InputError("body.exact.dimension", self.dimension, "2 (planar) or 3")
        for key in ("gj", "bend_radius"):
            if self.dimension == 2 and getattr(self, key) is not None:
                raise InputError(f"body.exact.{key}", getattr(self, key), "unset unless body.exact.dimension = 3")
        if self.mass not in ("consistent", "lumped"):
            raise InputError("body.exact.mass", self.mass, "'consistent' or 'lumped'")
        if self.analysis not in ("dynamic", "static", "both"):
            raise InputError("body.exact.analysis", self.analysis, "'dynamic', 'static' or 'both'")


def _pieces(cfg, exact: ExactConfig):
    """Beams, clamp flags, hub data and the frame kind of a body config."""
    if cfg.type == "beam":
        b = cfg.beam
        if b.spatial:
            raise InputError("body.beam.spatial", True, "false with body.model = 'exact' (planar beams)")
        ea = exact.ea or STIFF_RATIO * b.ei / b.length**2
        ga = exact.ga or STIFF_RATIO * b.ei / b.length**2
        cant = b.support == "cantilever"
        start = (0.0, 0.0) if cant else (-0.5 * b.length, 0.0)
        p = straight(b.length, exact.elements, ea=ea, ga=ga, ei=b.ei, rho_a=b.rho_a, rho_i=exact.rho_i, start=start)
        return [p], [cant], {}
    if cfg.type != "hub":
        raise InputError("body.model", "exact", f"'modal' for a {cfg.type} body (the exact body is a beam or a hub)")
    from rotaflex.floating.hub import section

    h = cfg.hub
    pieces = []
    for i, a in enumerate(h.appendages):
        where = f"body.hub.appendages[{i}]"
        if a.file is not None:
            raise InputError(
                f"{where}.file", a.file, "a beam appendage (length, e, rho, section) for body.model = 'exact'"
            )
        if a.spatial:
            raise InputError(f"{where}.spatial", True, "false with body.model = 'exact' (planar)")
        for key in ("direction", "root"):
            if abs(getattr(a, key)[2]) > 0:
                raise InputError(f"{where}.{key}", list(getattr(a, key)), "in the hub's x-y plane (z = 0; planar)")
        for key in ("length", "e", "rho"):
            if getattr(a, key) is None:
                raise InputError(f"{where}.{key}", "<missing>", "a number > 0 for a beam appendage")
        area, i_y, _ = section(a.width, a.thickness, a.area, a.second_moment, where)
        ea = exact.ea or a.e * area
        ga = exact.ga or SHEAR_COEFFICIENT * a.e / (2.0 * (1.0 + POISSON)) * area
        ri = a.rho * i_y if exact.rho_i is None else exact.rho_i
        ang = float(np.arctan2(a.direction[1], a.direction[0]))
        pieces.append(
            straight(
                a.length,
                exact.elements,
                ea=ea,
                ga=ga,
                ei=a.e * i_y,
                rho_a=a.rho * area,
                rho_i=ri,
                start=a.root[:2],
                angle=ang,
            )
        )
    if not pieces:
        raise InputError("body.hub.appendages", [], "at least one beam appendage for body.model = 'exact'")
    hub = {"hub_mass": h.mass, "hub_inertia": h.inertia[2], "hub_radius": h.radius}
    return pieces, [True] * len(pieces), hub


def build(case, body) -> tuple[ExactBeam, str, PointLoads]:
    """The exact beam of a prepared case, its frame kind and its loads."""
    exact = case.body.exact or ExactConfig()
    pieces, clamped, hub = _pieces(case.body, exact)
    beam = assemble(pieces, clamped, **hub, lumped=exact.mass == "lumped")
    if case.body.type == "hub":
        frame = "prescribed" if case.prescribed is not None else "free"
    elif clamped[0]:
        frame = "prescribed" if case.prescribed is not None else "fixed"
    else:
        if case.prescribed is not None:
            raise InputError(
                "prescribed", "<table>", "no [prescribed] motion for a free-free exact beam (use a cantilever or a hub)"
            )
        frame = "fixed"
    if case.slew is not None and np.abs(np.asarray(case.slew.axis)[:2]).max() > 0:
        raise InputError("slew.axis", list(case.slew.axis), "[0, 0, 1] (planar exact body)")
    if case.prescribed is not None and np.abs(np.asarray(case.prescribed.axis)[:2]).max() > 0:
        raise InputError("prescribed.axis", list(case.prescribed.axis), "[0, 0, 1] (planar exact body)")
    return beam, frame, _loads(case, beam, frame, exact)


def _loads(case, beam: ExactBeam, frame: str, exact: ExactConfig) -> PointLoads:
    from rotaflex.floating.kernels import PROFILES

    pts, kinds, frames, vecs, profs, pars = [], [], [], [], [], []
    free_beam = frame == "fixed" and len(beam.clamps) == 0
    for i, ld in enumerate(case.loads):
        v = np.asarray(ld.vector, dtype=float)
        if ld.kind == "force" and v[2] != 0 or ld.kind == "torque" and np.abs(v[:2]).max() > 0:
            raise InputError(
                f"loads[{i}].vector",
                list(ld.vector),
                "in the x-y plane: a force [fx, fy, 0] or a torque [0, 0, mz] (3-D loads: body.exact.dimension = 3)",
            )
        if ld.kind == "force" and ld.frame == "body" and free_beam:
            raise InputError(
                f"loads[{i}].frame", "body", "'inertial' or 'material' (a free exact beam has no body frame)"
            )
        a, _, _ = beam.locate(ld.point, f"loads[{i}].point")
        if a < 0:  # on the rigid hub: a torque, or a force at the centre, on the frame DOFs
            if ld.kind == "force" and np.abs(np.asarray(ld.point)[:2]).max() > 0:
                raise InputError(f"loads[{i}].point", list(ld.point), "the hub centre [0, 0, 0] for a force on the hub")
        pts.append(ld.point)
        kinds.append(ld.kind)
        frames.append(ld.frame)
        vecs.append((v[2], 0.0) if ld.kind == "torque" else (v[0], v[1]))
        profs.append(PROFILES.index(ld.profile))
        pars.append((ld.start, ld.duration, ld.frequency, ld.phase))
    g = np.asarray(exact.gravity, dtype=float)
    if g[2] != 0:
        raise InputError("body.exact.gravity", list(exact.gravity), "in the x-y plane [gx, gy, 0]")
    return PointLoads.build(beam, pts, kinds, frames, vecs, profs, pars, distributed=beam.rho_a[:, None] * g[:2])


def _rot(phi):
    c, s = np.cos(phi), np.sin(phi)
    return np.array([[c, -s], [s, c]])


def initial_state(case, beam: ExactBeam, frame: str) -> tuple[np.ndarray, np.ndarray]:
    """``q0, v0`` from ``[initial]``: the undeformed body moved and turned (about z) rigidly,
    with the frame's velocity and spin; the modal entries must be empty."""
    ini = case.initial
    for key in ("modal_displacement", "modal_velocity"):
        if len(getattr(ini, key)):
            raise InputError(f"initial.{key}", list(getattr(ini, key)), "empty with body.model = 'exact'")
    e = np.asarray(ini.quaternion, dtype=float)
    if abs(e[1]) > 1e-12 or abs(e[2]) > 1e-12:
        raise InputError("initial.quaternion", list(ini.quaternion), "a rotation about z [e0, 0, 0, e3] (planar)")
    for key, vec, idx in (("position", ini.position, 2), ("velocity", ini.velocity, 2)):
        if vec[idx] != 0:
            raise InputError(f"initial.{key}", list(vec), "in the x-y plane (planar exact body)")
    if np.abs(np.asarray(ini.angular_velocity)[:2]).max() > 0:
        raise InputError("initial.angular_velocity", list(ini.angular_velocity), "about z [0, 0, wz] (planar)")
    moving = np.any(np.asarray(ini.velocity) != 0) or ini.angular_velocity[2] != 0
    if moving and frame != "free" and len(beam.clamps):
        raise InputError(
            "initial.velocity", list(ini.velocity), "zero for a beam clamped to a fixed or prescribed frame"
        )
    psi = 2.0 * float(np.arctan2(e[3], e[0]))
    R = _rot(psi)
    P = np.asarray(ini.position, dtype=float)[:2]
    n = beam.n_nodes
    q = np.zeros(beam.n_dof)
    xy = P + beam.nodes @ R.T
    q[0 : 3 * n : 3], q[1 : 3 * n : 3] = xy[:, 0], xy[:, 1]
    q[2 : 3 * n : 3] = beam.angles + psi
    q[3 * n :] = (*P, psi)
    w = float(ini.angular_velocity[2])
    V = R @ np.asarray(ini.velocity, dtype=float)[:2]
    v = np.zeros(beam.n_dof)
    v[0 : 3 * n : 3] = V[0] - w * (xy[:, 1] - P[1])
    v[1 : 3 * n : 3] = V[1] + w * (xy[:, 0] - P[0])
    v[2 : 3 * n : 3] = w
    v[3 * n :] = (*V, w)
    return q, v


def first_frequency(body) -> float:
    """Lowest elastic natural frequency [rad/s] of the modal body of the same config."""
    w2 = np.diag(np.asarray(body.stiffness, dtype=float))
    w2 = w2[w2 > 0]
    return float(np.sqrt(w2.min())) if len(w2) else float("nan")


def check_step_budget(case, h: float) -> None:
    """Refuse a dynamic run over its step budget (``solver.max_steps``) before it starts; ``h``
    is the time step [s]. Planar and 3-D exact beams alike."""
    from rotaflex.core.limits import require
    from rotaflex.floating.exact_solve import time_grid

    steps = len(time_grid(case.solver.t_end, case.solver.dt_out, h)[0]) - 1
    require(
        "solver.max_steps",
        case.solver.max_steps,
        steps,
        case.solver.max_steps,
        f"generalized-alpha steps (t_end = {case.solver.t_end:g} s, step {h:.4g} s)",
        "raise solver.max_steps, or a longer body.exact.time_step, or a shorter solver.t_end",
    )


def check(case, body):
    """Build and check everything a run needs (bad input raises before any integration)."""
    exact = case.body.exact or ExactConfig()
    beam, frame, loads = build(case, body)
    q0, v0 = initial_state(case, beam, frame)
    w1 = first_frequency(body)
    h = exact.time_step or min(case.solver.dt_out, 2 * np.pi / w1 / STEPS_PER_PERIOD)
    if exact.analysis != "dynamic":
        if not len(beam.clamps):
            raise InputError("body.exact.analysis", exact.analysis, "'dynamic' for a beam that is not clamped")
        if case.prescribed is not None:
            raise InputError("body.exact.analysis", exact.analysis, "'dynamic' with a prescribed motion (inertia)")
    if exact.analysis != "static":
        check_step_budget(case, h)
    return {"beam": beam, "frame": frame, "loads": loads, "q0": q0, "v0": v0, "h": h, "w1": w1, "exact": exact}


def run(case, body, plan, progress=None):
    """Solve a checked case (:func:`check`); returns a list of
    :class:`~rotaflex.floating.exact_solve.ExactSolution` (``exact`` and/or ``static``)."""
    from rotaflex.floating.exact_solve import simulate_exact
    from rotaflex.floating.solve import _breaks

    exact = plan["exact"]
    sols = []
    if exact.analysis != "static":
        eta = 2.0 * case.body.damping_ratio / plan["w1"] if case.body.damping_ratio > 0 else 0.0
        pres = case.prescribed.packed() if case.prescribed is not None else None
        sols.append(
            simulate_exact(
                plan["beam"],
                plan["loads"],
                t_end=case.solver.t_end,
                dt_out=case.solver.dt_out,
                time_step=plan["h"],
                rho_inf=exact.rho_inf,
                eta=eta,
                frame=plan["frame"],
                prescribed=pres,
                q0=plan["q0"],
                v0=plan["v0"],
                breakpoints=_breaks(case.loads, case.prescribed, case.solver.t_end),
                max_steps=case.solver.max_steps,
                progress=progress if exact.analysis == "dynamic" else None,
            )
        )
    if exact.analysis != "dynamic":
        sols.append(quasi_static(plan, case.solver.t_end, case.solver.dt_out, progress))
    return sols


def quasi_static(plan, t_end: float, dt_out: float, progress=None):
    """Equilibrium at every output time under the loads' values then (inertia ignored, frame
    held), each from the one before; an :class:`~rotaflex.floating.exact_solve.ExactSolution`
    named ``static`` (its energy columns: 0, strain energy, NaN, NaN)."""
    from rotaflex.floating import exact_kernels as ek
    from rotaflex.floating.exact_solve import ExactSolution
    from rotaflex.floating.solve import output_times

    beam, loads = plan["beam"], plan["loads"]
    t_wall = time.perf_counter()
    times = output_times(0.0, t_end, dt_out)
    q = plan["q0"].copy()
    lam_prev = np.zeros(len(loads.node) + 1)
    Q, E, steps, iters = [], [], 0, 0
    for t in times:
        lam = np.zeros_like(lam_prev)
        ek.load_factors(float(t), loads.profile, loads.par, lam)
        st = solve_static(beam, loads, q0=q, start=lam_prev, target=lam)
        q, lam_prev = st.q, lam
        Q.append(q)
        E.append((0.0, st.strain_energy, np.nan, np.nan))
        steps += len(st.fractions) - 1
        iters += st.iterations
        if progress is not None:
            progress(float(t))
    Q = np.array(Q)
    return ExactSolution(
        time=times,
        q=Q,
        v=np.zeros_like(Q),
        energy=np.array(E),
        message=f"static equilibrium at {len(times)} times: {steps} load steps, {iters} Newton iterations",
        nstep=steps,
        niter=iters,
        wall_time=time.perf_counter() - t_wall,
        method="static",
    )
