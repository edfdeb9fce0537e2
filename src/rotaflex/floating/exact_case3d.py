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
be ``"dynamic"``.

``[body] type = "hub"``: beam appendages (``length``, ``e``, ``rho`` and the section of
``[[body.hub.appendages]]``, :class:`HubBeam3D`) clamped at their roots to a rigid hub that
turns about a fixed axis through its centre (a bearing). ``[slew] drive = "torque"``: the hub
is free about the slew axis, with ``body.hub.inertia`` about it (``a . diag(I) a``), driven by
the slew's torque (the rigid body's inertia about the axis times the profile's acceleration)
and any ``[[loads]]`` torque on the hub (``|point| <= body.hub.radius``; its component along
the axis); :func:`rotaflex.floating.exact_solve3d.simulate_hub3d`. ``drive = "motion"`` or
``[prescribed]``: the hub follows the motion. Points are positions in hub axes on an
appendage's axis (the planar and modal hub's convention).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from rotaflex.core.errors import InputError
from rotaflex.floating.exact_beam3d import ExactBeam3D, PointLoads3D, arc3d, assemble3d, straight3d
from rotaflex.floating.exact_case import POISSON, SHEAR_COEFFICIENT, STIFF_RATIO


def _refuse_unsupported(case, exact):
    """The parts of a floating case the 3-D exact body does not run yet."""
    cfg = case.body
    if cfg.type not in ("beam", "hub") or cfg.type == "beam" and cfg.beam.support != "cantilever":
        where = "body.type" if cfg.type != "beam" else "body.beam.support"
        got = cfg.type if cfg.type != "beam" else cfg.beam.support
        raise InputError(where, got, "a 'beam' with support = 'cantilever', or a 'hub', for body.exact.dimension = 3")
    torque_hub = cfg.type == "hub" and case.prescribed is None and case.slew is not None and case.slew.drive == "torque"
    if cfg.damping_ratio > 0 and torque_hub:
        raise InputError(
            "body.damping_ratio",
            cfg.damping_ratio,
            "0 for a torque-driven 3-D hub (material damping runs on a prescribed frame or motion)",
        )
    if case.slew is not None and case.slew.drive != "motion" and cfg.type != "hub":
        raise InputError(
            "slew.drive",
            case.slew.drive,
            "'motion' for a 3-D beam (the root follows the slew; a torque turns a [body.hub])",
        )
    if cfg.type == "hub" and case.prescribed is None and (case.slew is None or case.slew.drive != "torque"):
        raise InputError(
            "slew", "<missing>", "a [slew] (drive = 'torque': the hub turns about its axis) or [prescribed] motion"
        )
    if case.prescribed is not None and exact.analysis != "dynamic":
        raise InputError("body.exact.analysis", exact.analysis, "'dynamic' with a prescribed motion (inertia)")
    if cfg.type == "hub" and exact.analysis != "dynamic":
        raise InputError("body.exact.analysis", exact.analysis, "'dynamic' for a 3-D hub (it turns freely)")
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
        raise InputError("initial", "<table>", "the defaults with body.exact.dimension = 3 (the body starts at rest)")


def build(case) -> tuple[ExactBeam3D, PointLoads3D]:
    """The 3-D exact beam of a case and its loads."""
    exact = case.body.exact
    _refuse_unsupported(case, exact)
    if case.body.type == "hub":
        beam = _hub_beam(case.body.hub, exact)
        return beam, _hub_loads(case, beam)[0]
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


@dataclass(frozen=True)
class HubBeam3D(ExactBeam3D):
    """Straight appendages clamped at their roots to a rigid hub of radius ``hub_radius`` [m]
    (:func:`_hub_beam`); points are positions in the undeformed hub axes."""

    hub_radius: float = 0.0


def _hub_beam(h, exact) -> HubBeam3D:
    """The appendages of ``[body.hub]`` as 3-D exact beams clamped to the hub.

    Each is straight from ``root`` along ``direction`` with the section axes of the modal
    appendage (:func:`rotaflex.floating.hub._frame_to`: ``e2`` in the plane with hub z, so
    ``thickness`` is the in-plane and ``width`` the out-of-plane dimension): ``EI3 = E I`` in
    plane, ``EI2 = E I`` out of plane, ``EA = E A``, ``GA = 5/6 E A / 2.6``, ``GJ = E (I2 + I3)
    / 2.6`` (``ea``, ``ga``, ``gj`` of ``[body.exact]`` override), rotary inertia ``rho (I2 +
    I3, I2, I3)`` per length."""
    from rotaflex.floating.hub import _frame_to, section

    for key in ("bend_radius", "rho_i"):
        if getattr(exact, key) is not None:
            raise InputError(f"body.exact.{key}", getattr(exact, key), "unset for a 3-D hub (straight appendages)")
    pieces, rho_i = [], []
    for i, a in enumerate(h.appendages):
        where = f"body.hub.appendages[{i}]"
        if a.file is not None:
            raise InputError(
                f"{where}.file", a.file, "a beam appendage (length, e, rho, section) for body.model = 'exact'"
            )
        for key in ("length", "e", "rho"):
            if getattr(a, key) is None:
                raise InputError(f"{where}.{key}", "<missing>", "a number > 0 for a beam appendage")
        area, i_in, i_out = section(a.width, a.thickness, a.area, a.second_moment, where)
        shear = a.e / (2.0 * (1.0 + POISSON))
        sec = dict(
            ea=exact.ea or a.e * area,
            ga=exact.ga or SHEAR_COEFFICIENT * shear * area,
            gj=exact.gj or shear * (i_in + i_out),
            ei2=a.e * i_out,
            ei3=a.e * i_in,
            rho_a=a.rho * area,
        )
        frame = _frame_to(a.direction, where)
        pieces.append(straight3d(a.length, exact.elements, start=a.root, frame=frame, **sec))
        rho_i += [(a.rho * (i_in + i_out), a.rho * i_out, a.rho * i_in)] * exact.elements
    if not pieces:
        raise InputError("body.hub.appendages", [], "at least one beam appendage for body.model = 'exact'")
    b = assemble3d(pieces, [True] * len(pieces))
    fields = {f.name: getattr(b, f.name) for f in dataclasses.fields(b)}
    fields["rho_i"] = np.array(rho_i, dtype=float)
    return HubBeam3D(**fields, hub_radius=float(h.radius))


def _on_hub(beam: HubBeam3D, point) -> bool:
    """A point within the hub radius (the modal hub's rule)."""
    return float(np.linalg.norm(point)) <= beam.hub_radius * (1 + 1e-12) + 1e-12


def _hub_loads(case, beam: HubBeam3D, axis=None):
    """Loads on the appendages (:class:`PointLoads3D`, points in hub axes) and the torques on
    the hub about the unit ``axis`` (their component along it, whatever their frame: the hub
    turns about it, ``R_F a = a``; the bearing carries the rest) as ``(amps, profiles, pars)``."""
    from rotaflex.floating.kernels import PROFILES

    pts, kinds, frames, vecs, profs, pars, hub_t = [], [], [], [], [], [], []
    for i, ld in enumerate(case.loads):
        prof, par = PROFILES.index(ld.profile), (ld.start, ld.duration, ld.frequency, ld.phase)
        v = np.asarray(ld.vector, dtype=float)
        if _on_hub(beam, ld.point):
            if ld.kind != "torque":
                raise InputError(
                    f"loads[{i}].kind",
                    ld.kind,
                    "'torque' on the 3-D hub (its bearing carries forces) or a point off it",
                )
            if axis is not None:
                hub_t.append((float(np.dot(axis, v)), prof, par))
            continue
        beam.locate(ld.point, f"loads[{i}].point")
        pts.append(np.asarray(ld.point, dtype=float))
        kinds.append(ld.kind)
        frames.append(ld.frame)
        vecs.append(v)
        profs.append(prof)
        pars.append(par)
    g = np.asarray(case.body.exact.gravity, dtype=float)
    loads = PointLoads3D.build(beam, pts, kinds, frames, vecs, profs, pars, distributed=beam.rho_a[:, None] * g)
    return loads, hub_t


def _hub_drive(case, body, beam: HubBeam3D):
    """The :class:`~rotaflex.floating.exact_solve3d.HubDrive` of a torque slew: the slew axis,
    the hub's inertia about it, the torques on the hub. The slew's torque (the planar case's
    ``J theta_ref''``, :func:`rotaflex.floating.hub.slew_torque`, with ``J`` about the centre
    of mass of a free body) is rescaled to ``J`` about the bearing axis through the hub centre,
    the torque that turns the rigid body on its bearing along the profile."""
    from rotaflex.floating.body import integrals
    from rotaflex.floating.exact_solve3d import HubDrive
    from rotaflex.floating.hub import slew_inertia

    ax = np.asarray(case.slew.axis, dtype=float)
    ax = ax / np.linalg.norm(ax)
    j_hub = float(ax**2 @ np.asarray(case.body.hub.inertia, dtype=float))
    if not j_hub > 0:
        raise InputError("body.hub.inertia", list(case.body.hub.inertia), "a moment > 0 about the slew axis [kg m^2]")
    _, hub_t = _hub_loads(case, beam, ax)
    # the slew's torque is the last load (rotaflex.floating.case._with_slew)
    scale = float(ax @ integrals(body)["J"] @ ax) / slew_inertia(body, ax)
    hub_t[-1] = (hub_t[-1][0] * scale, *hub_t[-1][1:])
    return HubDrive(
        axis=ax,
        inertia=j_hub,
        torque=np.array([t[0] for t in hub_t]),
        profile=np.array([t[1] for t in hub_t], dtype=np.int64),
        par=np.array([t[2] for t in hub_t], dtype=float).reshape(-1, 4),
    )


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
    points(beam, case.outputs)
    exact = case.body.exact
    w1 = first_frequency(body)
    h = exact.time_step or min(case.solver.dt_out, 2 * np.pi / w1 / STEPS_PER_PERIOD)
    if exact.analysis != "static":
        check_step_budget(case, h)
    q0 = beam.reference_state()
    frame = "prescribed" if case.prescribed is not None else "fixed"
    plan = {"beam": beam, "frame": frame, "loads": loads, "q0": q0, "h": h, "w1": w1, "exact": exact}
    if isinstance(beam, HubBeam3D) and case.prescribed is None:
        plan.update(frame="free", hub=_hub_drive(case, body, beam))
    return plan


def run(case, plan, progress=None):
    """The 3-D solutions of a checked case: ``exact`` (Lie-group generalized-alpha,
    :func:`rotaflex.floating.exact_solve3d.simulate_exact3d`) and/or ``static``."""
    from rotaflex.floating.exact_case import quasi_static
    from rotaflex.floating.exact_solve3d import simulate_exact3d, simulate_hub3d
    from rotaflex.floating.solve import _breaks

    exact = plan["exact"]
    sols = []
    if plan["frame"] == "free":
        sol = simulate_hub3d(
            plan["beam"],
            plan["loads"],
            plan["hub"],
            t_end=case.solver.t_end,
            dt_out=case.solver.dt_out,
            time_step=plan["h"],
            rho_inf=exact.rho_inf,
            breakpoints=_breaks(case.loads, None, case.solver.t_end),
            progress=progress,
        )
        return [sol]
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
        if isinstance(plan["beam"], HubBeam3D):
            _add_hub_energy(sols[-1], plan["beam"], case.body.hub.inertia)
    if exact.analysis != "dynamic":
        sols.append(quasi_static(plan, case.solver.t_end, case.solver.dt_out, progress))
    return sols


def _add_hub_energy(sol, beam: HubBeam3D, inertia) -> None:
    """A hub that follows a prescribed motion: its kinetic energy ``w . I w / 2`` (``w`` the
    frame's angular velocity, ``I`` the principal moments ``inertia`` [kg m^2]) into the kinetic
    energy and, as the work the drive spent on it (from rest), into the drive's work (the
    planar hub's accounting, where the hub is part of the mass matrix)."""
    w = sol.v.reshape(len(sol.v), -1, 6)[:, beam.n_nodes, 3:]
    e_hub = 0.5 * np.einsum("tk,k,tk->t", w, np.asarray(inertia, dtype=float), w)
    sol.energy[:, 0] += e_hub
    sol.energy[:, 3] += e_hub - e_hub[0]


def points(beam: ExactBeam3D, outputs: dict) -> dict:
    """The output points at their reference positions (for the result): material points
    ``[s, 0, 0]`` of a beam, positions on an appendage axis (hub axes) of a hub."""
    if not isinstance(beam, HubBeam3D):
        return {name: material_point(beam, pt, f"outputs.{name}") for name, pt in outputs.items()}
    out = {}
    for name, pt in outputs.items():
        p = np.asarray(pt, dtype=float)
        if _on_hub(beam, p):
            raise InputError(
                f"outputs.{name}", list(pt), "a point on an appendage axis (the hub's motion: hub_angle, quaternion)"
            )
        beam.locate(p, f"outputs.{name}")
        out[name] = p
    return out
