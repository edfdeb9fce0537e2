"""``body.model = "exact"`` with ``body.exact.dimension = 3``: a case on the 3-D exact beam.

What a 3-D case may hold (the rest is refused, naming the key): ``[body] type = "beam"`` with
``[body.beam] support = "cantilever"`` (root at the origin along x, clamped to a fixed frame);
``ei`` is ``EI3`` (bending in the x-y plane, deflection along y), ``ei_z`` is ``EI2`` (deflection
along z; default ``ei``); ``[body.exact]`` adds ``gj`` (default ``(EI2 + EI3) / 2.6``: a solid
circular section, Poisson's ratio 0.3), ``ea``, ``ga`` (both directions) and ``bend_radius`` (the
beam curved in the x-y plane towards +y with that radius, a circular arc of the beam's length);
``analysis``: ``"static"`` (the equilibrium path at the output times), ``"dynamic"`` (Lie-group
generalized-alpha, :mod:`rotaflex.floating.exact_solve3d`; ``body.damping_ratio``: Kelvin-Voigt
material damping as in the planar beam) or ``"both"``.

Points (loads, outputs) are material coordinates: ``[s, 0, 0]`` is the section at arclength
``s`` from the root (for a straight beam its position; for a bent one where it sits on the arc).
Loads are 3-component forces and torques, ``frame = "inertial"`` (fixed direction),
``"material"`` (follower: given in the root's axes, turned with the section from its reference
orientation) or ``"body"`` (the reference frame at rest, the same as inertial); ``body.exact.gravity``
is a distributed load ``rho_a g`` fixed in space.

The reference frame is fixed, or turns about its origin as ``[prescribed]`` says (any axis;
spin-up, bang-bang or versine profiles) or as a ``[slew]`` with ``drive = "motion"``; the root
is clamped to it (:func:`rotaflex.floating.exact_solve3d.rigid_motion`). ``analysis`` must then
be ``"dynamic"``; a torque-driven slew needs a free hub (not in 3-D yet).
"""

from __future__ import annotations

import numpy as np

from rotaflex.core.errors import InputError
from rotaflex.floating.exact_beam3d import ExactBeam3D, PointLoads3D, arc3d, assemble3d, straight3d
from rotaflex.floating.exact_case import POISSON, STIFF_RATIO


def _refuse_unsupported(case, exact):
    """The parts of a floating case the 3-D exact body does not run yet."""
    cfg = case.body
    if cfg.type != "beam" or cfg.beam.support != "cantilever":
        where = "body.type" if cfg.type != "beam" else "body.beam.support"
        got = cfg.type if cfg.type != "beam" else cfg.beam.support
        raise InputError(where, got, "a 'beam' with support = 'cantilever' for body.exact.dimension = 3")
    if case.slew is not None and case.slew.drive != "motion":
        raise InputError(
            "slew.drive", case.slew.drive, "'motion' with body.exact.dimension = 3 (the root follows the slew)"
        )
    if case.prescribed is not None and exact.analysis != "dynamic":
        raise InputError("body.exact.analysis", exact.analysis, "'dynamic' with a prescribed motion (inertia)")
    ini = case.initial
    moved = (
        any(ini.position)
        or any(ini.velocity)
        or any(ini.angular_velocity)
        or list(ini.quaternion) != [1.0, 0.0, 0.0, 0.0]
        or len(ini.modal_displacement)
        or len(ini.modal_velocity)
    )
    if moved:
        raise InputError("initial", "<table>", "the defaults with body.exact.dimension = 3 (a clamped static beam)")


def build(case) -> tuple[ExactBeam3D, PointLoads3D]:
    """The 3-D exact beam of a case and its loads."""
    exact = case.body.exact
    _refuse_unsupported(case, exact)
    b = case.body.beam
    ei3 = b.ei
    ei2 = b.ei_z or b.ei
    ea = exact.ea or STIFF_RATIO * b.ei / b.length**2
    ga = exact.ga or STIFF_RATIO * b.ei / b.length**2
    gj = exact.gj or (ei2 + ei3) / (2.0 * (1.0 + POISSON))
    sec = dict(ea=ea, ga=ga, gj=gj, ei2=ei2, ei3=ei3, rho_a=b.rho_a)
    if exact.bend_radius is None:
        piece = straight3d(b.length, exact.elements, **sec)
    else:
        piece = arc3d(exact.bend_radius, b.length / exact.bend_radius, exact.elements, **sec)
    beam = assemble3d([piece], [True])
    return beam, _loads(case, beam)


def material_point(beam: ExactBeam3D, point, where: str) -> np.ndarray:
    """Reference position [m] of the material point ``[s, 0, 0]`` (arclength ``s`` from the root)."""
    p = np.asarray(point, dtype=float)
    s = p[0]
    if np.abs(p[1:]).max() > 0 or not 0.0 <= s <= beam.length * (1 + 1e-12):
        raise InputError(where, list(point), f"[s, 0, 0] with 0 <= s <= {beam.length:g} (arclength from the root)")
    k = int(np.clip(np.searchsorted(beam.arclength, s) - 1, 0, len(beam.conn) - 1))
    a, b = beam.conn[k]
    xi = (s - beam.arclength[a]) / (beam.arclength[b] - beam.arclength[a])
    return (1 - xi) * beam.nodes[a] + xi * beam.nodes[b]


def _loads(case, beam: ExactBeam3D) -> PointLoads3D:
    from rotaflex.floating.kernels import PROFILES

    pts, kinds, frames, vecs, profs, pars = [], [], [], [], [], []
    for i, ld in enumerate(case.loads):
        pts.append(material_point(beam, ld.point, f"loads[{i}].point"))
        kinds.append(ld.kind)
        frames.append(ld.frame)
        vecs.append(np.asarray(ld.vector, dtype=float))
        profs.append(PROFILES.index(ld.profile))
        pars.append((ld.start, ld.duration, ld.frequency, ld.phase))
    g = np.asarray(case.body.exact.gravity, dtype=float)
    return PointLoads3D.build(beam, pts, kinds, frames, vecs, profs, pars, distributed=beam.rho_a[:, None] * g)


def check(case, body):
    """Build and check everything a 3-D run needs (bad input raises before any solve); the
    default time step is the planar one's (:func:`rotaflex.floating.exact_case.check`)."""
    from rotaflex.floating.exact_case import STEPS_PER_PERIOD, check_step_budget, first_frequency

    beam, loads = build(case)
    for name, pt in case.outputs.items():
        material_point(beam, pt, f"outputs.{name}")
    exact = case.body.exact
    w1 = first_frequency(body)
    h = exact.time_step or min(case.solver.dt_out, 2 * np.pi / w1 / STEPS_PER_PERIOD)
    if exact.analysis != "static":
        check_step_budget(case, h)
    q0 = beam.reference_state()
    frame = "prescribed" if case.prescribed is not None else "fixed"
    return {"beam": beam, "frame": frame, "loads": loads, "q0": q0, "h": h, "w1": w1, "exact": exact}


def run(case, plan, progress=None):
    """The 3-D solutions of a checked case: ``exact`` (Lie-group generalized-alpha,
    :func:`rotaflex.floating.exact_solve3d.simulate_exact3d`) and/or ``static``."""
    from rotaflex.floating.exact_case import quasi_static
    from rotaflex.floating.exact_solve3d import simulate_exact3d
    from rotaflex.floating.solve import _breaks

    exact = plan["exact"]
    sols = []
    if exact.analysis != "static":
        sols.append(
            simulate_exact3d(
                plan["beam"],
                plan["loads"],
                t_end=case.solver.t_end,
                dt_out=case.solver.dt_out,
                time_step=plan["h"],
                rho_inf=exact.rho_inf,
                eta=2.0 * case.body.damping_ratio / plan["w1"],
                prescribed=None if case.prescribed is None else case.prescribed.packed(),
                breakpoints=_breaks(case.loads, case.prescribed, case.solver.t_end),
                progress=progress if exact.analysis == "dynamic" else None,
            )
        )
    if exact.analysis != "dynamic":
        sols.append(quasi_static(plan, case.solver.t_end, case.solver.dt_out, progress))
    return sols


def points(beam: ExactBeam3D, outputs: dict) -> dict:
    """The output points at their reference positions (for the result)."""
    return {name: material_point(beam, pt, f"outputs.{name}") for name, pt in outputs.items()}
