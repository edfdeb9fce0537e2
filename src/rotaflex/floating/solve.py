"""Solvers: full nonlinear hybrid equations, perturbation method, prescribed spin-up.

:func:`simulate` packs a :class:`~rotaflex.floating.body.Body`, loads and settings into arrays,
runs the compiled integrator of :mod:`rotaflex.floating.kernels` and post-processes the states
into a :class:`Solution` (plain arrays, SI units). :mod:`rotaflex.floating.result` turns one or
more solutions into a ``FloatingResult``.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field

import numpy as np

from rotaflex.core.errors import InputError
from rotaflex.floating.body import Body, skew
from rotaflex.floating.model import Initial, Load, Prescribed, Settings

log = logging.getLogger(__name__)

METHODS = ("full", "perturbation")
_PROFILES = {"constant": 0, "step": 1, "ramp": 2, "bang-bang": 3, "sinusoid": 4, "pulse": 5}


@dataclass
class Solution:
    """States of one solver run at the output times (all SI)."""

    method: str
    time: np.ndarray
    position: np.ndarray  # (T, 3) inertial origin position R_o
    quaternion: np.ndarray  # (T, 4)
    velocity: np.ndarray  # (T, 3) body frame
    angular_velocity: np.ndarray  # (T, 3) body frame
    q: np.ndarray  # (T, n)
    p: np.ndarray  # (T, n)
    status: str = "success"
    message: str = ""
    nfev: int = 0
    nstep: int = 0
    wall_time: float = 0.0
    parts: dict = field(default_factory=dict)  # perturbation: zero/first-order pieces
    geometric: bool = False
    kinematics: str = "linear"
    min_stiffness: np.ndarray | None = None  # (T,) min eigenvalue of the effective stiffness
    euler_123: np.ndarray | None = None  # (T, 3) Euler 1-2-3 angles unwrapped step by step


def pack_body(body: Body):
    """Body-integral tensors for the kernels (see :mod:`rotaflex.floating.kernels`)."""
    from rotaflex.floating.body import integrals

    m = np.asarray(body.masses, dtype=float)
    r = np.asarray(body.points, dtype=float)
    Phi = np.asarray(body.shapes, dtype=float)
    I0 = integrals(body)
    M0 = I0["M"].copy()
    J = I0["J"].copy()
    if body.planar and J[0, 0] < 1e-9 * J[2, 2]:
        # a planar line beam: the rotation about its axis has (almost) no inertia but is decoupled
        # from in-plane motion (in-plane loads are enforced in simulate), so w_x stays exactly 0
        # whatever inertia the kernel uses for it; J_zz keeps the mass matrix well conditioned
        J[0, 0] = M0[3, 3] = J[2, 2]
    ev = np.linalg.eigvalsh(M0[:6, :6])
    if ev.min() <= 1e-14 * ev.max():
        beam = body.name.startswith("uniform")
        raise InputError(
            "body.beam.section_radius" if beam else "body",
            f"rigid-body mass matrix eigenvalues min {ev.min():.3g}, max {ev.max():.3g}",
            "a radius > 0 for a spatial beam (a line beam has no inertia about its axis)"
            if beam
            else "a mass distribution with a non-singular inertia tensor (e.g. collinear point "
            "masses need rotary inertia about their line)",
        )
    P = np.einsum("k,kai,kbj->abij", m, Phi, Phi)
    R1 = np.einsum("k,kaj,kb->abj", m, Phi, r)
    G = geometric_tensor(body)
    gnz = (np.abs(G).reshape(3, 3, -1).max(axis=2, initial=0.0) > 0).astype(np.int64)
    c = np.ascontiguousarray
    return (
        float(I0["m"]),
        I0["S"].copy(),
        c(J),
        c(I0["Phibar"]),
        c(I0["Phitilde"]),
        c(I0["Mb"]),
        c(np.asarray(body.stiffness, dtype=float)),
        c(P),
        c(R1),
        c(G),
        gnz,
        np.linalg.inv(M0),
        np.linalg.inv(M0[:6, :6]),
        modal_damping(body),
    )


def modal_damping(body: Body) -> np.ndarray:
    """Modal damping coefficients ``2 zeta_i omega_i`` [1/s] of mass-normalised modes (empty
    array without damping, so the kernels do no work for it)."""
    if body.damping is None or body.n_modes == 0:
        return np.zeros(0)
    return 2.0 * np.asarray(body.damping, dtype=float) * np.sqrt(np.clip(np.diag(body.stiffness), 0.0, None))


def geometric_tensor(body: Body) -> np.ndarray:
    """Unit geometric stiffness ``G[a, b]`` (3, 3, n, n): ``K_G(w) = sum_ab w_a w_b G[a, b]``."""
    n = body.n_modes
    if body.geometric is None:
        return np.zeros((3, 3, n, n))
    return np.asarray(body.geometric, dtype=float)


def geometric_stiffness(body: Body, w) -> np.ndarray:
    """``K_G(w)`` (..., n, n) for angular velocities ``w`` (..., 3) [1/s^2]."""
    return np.einsum("...a,...b,abij->...ij", w, w, geometric_tensor(body))


def pack_loads(
    body: Body,
    loads: tuple[Load, ...] | list[Load],
    geometric: bool = False,
    clamped: bool = False,
):
    """Load arrays for the kernels; ``geometric``: with the geometric stiffness of each force's
    axial load state (``clamped``: prescribed frame motion, the root carries the load)."""
    n = body.n_modes
    nl = len(loads)
    kind = np.zeros(nl, dtype=np.int64)
    frame = np.zeros(nl, dtype=np.int64)
    prof = np.zeros(nl, dtype=np.int64)
    par = np.zeros((nl, 4))
    amp = np.zeros((nl, 3))
    rP = np.zeros((nl, 3))
    PhiP = np.zeros((nl, 3, n))
    PsiP = np.zeros((nl, 3, n))
    GL = np.zeros((nl, 3, n, n))
    for i, ld in enumerate(loads):
        kind[i] = 0 if ld.kind == "force" else 1
        frame[i] = {"body": 0, "inertial": 1, "material": 2}[ld.frame]
        prof[i] = _PROFILES[ld.profile]
        par[i] = (ld.start, ld.duration, ld.frequency, ld.phase)
        amp[i] = ld.vector
        rP[i] = ld.point
        try:
            Phi_i, Psi_i = body.shape_fn(np.array([ld.point]))
        except InputError as exc:
            raise InputError(f"loads[{i}].point", list(ld.point), exc.allowed) from None
        PhiP[i], PsiP[i] = Phi_i[0], Psi_i[0]
        if geometric and ld.kind == "force" and body.load_geometric is not None:
            GL[i] = body.load_geometric(ld.point, clamped)
        if ld.frame == "material" and not np.all(np.isfinite(PsiP[i])):
            raise InputError(
                f"loads[{i}].frame",
                "material",
                "'body' or 'inertial' (this body has no rotation shapes to turn the load with)",
            )
        if ld.kind == "torque" and not np.all(np.isfinite(PsiP[i])):
            raise InputError(
                f"loads[{i}].kind",
                "torque",
                "a force (this body has no rotation shapes for point torques)",
            )
    gln = (np.abs(GL).reshape(nl, 3, n * n).max(axis=2, initial=0.0) > 0).astype(np.int64)
    return kind, frame, prof, par, amp, rP, PhiP, PsiP, GL, gln


def output_times(t_start: float, t_end: float, dt_out: float) -> np.ndarray:
    """Output times [s]: ``t_start, t_start + dt_out, ...`` and ``t_end`` last (a shorter final
    interval when ``t_end - t_start`` is not a multiple of ``dt_out``; a grid point within
    1e-9 ``dt_out`` of ``t_end`` is moved onto it), so a run always ends exactly at ``t_end``.

    Examples
    --------
    >>> output_times(0.0, 2.22, 0.5).tolist()
    [0.0, 0.5, 1.0, 1.5, 2.0, 2.22]
    """
    span = t_end - t_start
    n = max(1, int(np.floor(span / dt_out + 1e-9)))
    t = t_start + dt_out * np.arange(n + 1)
    if t_end - t[-1] > 1e-9 * dt_out:
        return np.append(t, t_end)
    t[-1] = t_end
    return t


def _breaks(loads, prescribed, t_end, t_start=0.0):
    b = [t for ld in loads for t in ld.breakpoints()]
    if prescribed is not None:
        b += prescribed.breakpoints()
    return np.array(sorted({t for t in b if t_start < t < t_end}), dtype=float)


def _check_inextensible(body: Body, loads, settings: Settings, clamped: bool) -> None:
    """The exact inextensible kinematics exists for planar cantilever beams in a prescribed frame."""
    if body.inextensible is None:
        raise InputError(
            "solver.kinematics",
            "inextensible",
            "'linear' for this body (the inextensible kinematics needs a planar cantilever beam: "
            "body.beam.support = 'cantilever', not spatial)",
        )
    if not clamped:
        raise InputError(
            "solver.kinematics", "inextensible", "'linear' without [prescribed] motion (the root must be clamped)"
        )
    if len(loads):
        raise InputError(
            "loads",
            [ld.kind for ld in loads],
            "no loads with solver.kinematics = 'inextensible' (prescribed motion only)",
        )
    if settings.geometric_stiffness:
        raise InputError(
            "solver.geometric_stiffness",
            True,
            "unset or false with solver.kinematics = 'inextensible' (the exact kinematics contains "
            "the centrifugal stiffening; adding it would count it twice)",
        )
    if body.damping is not None and np.any(np.asarray(body.damping) > 0):
        raise InputError(
            "body.damping_ratio",
            body.damping.tolist(),
            "0 with solver.kinematics = 'inextensible' (modal damping is a linear-kinematics option)",
        )


def use_geometric(body: Body, settings: Settings, clamped: bool = False) -> bool:
    """Whether the run uses the centrifugal (and load) geometric stiffness.

    Default (``solver.geometric_stiffness`` unset): on when the body provides it, except for a
    free-floating body whose modes are clamped to its frame (a cantilever beam not under
    prescribed motion): its tensor holds the tension of a rotation about the clamped root, while
    the free body turns about its centre of mass and the root accelerates; measured on a
    cantilever with a root torque, the mismatch made the equations unstable (real Jacobian
    eigenvalue +4.3e3 1/s, run stopped at t = 0.018 s with 2 modes, 0.0005 s with 6).
    """
    if settings.kinematics == "inextensible":
        return False
    if settings.geometric_stiffness is None:
        return body.geometric is not None and (clamped or body.frame.startswith("mean axes"))
    if settings.geometric_stiffness and body.geometric is None:
        raise InputError(
            "solver.geometric_stiffness",
            True,
            "false for this body (centrifugal stiffening needs beam or FE bodies, or point bodies "
            "with body.points.geometric)",
        )
    return bool(settings.geometric_stiffness)


def _require_in_plane(loads, initial: Initial) -> None:
    """A planar line beam moves in the body x-y plane only: refuse anything out of plane."""
    allowed = "in-plane input for a planar line beam (set body.beam.section_radius > 0 or "
    for i, ld in enumerate(loads):
        if ld.kind == "force" and ld.vector[2] != 0.0:
            raise InputError(f"loads[{i}].vector", list(ld.vector), allowed + "use z = 0)")
        if ld.kind == "torque" and (ld.vector[0] != 0.0 or ld.vector[1] != 0.0):
            raise InputError(f"loads[{i}].vector", list(ld.vector), allowed + "torque about z)")
    w, v, e = initial.angular_velocity, initial.velocity, initial.quaternion
    if w[0] != 0.0 or w[1] != 0.0:
        raise InputError("initial.angular_velocity", list(w), allowed + "rotate about z)")
    if v[2] != 0.0:
        raise InputError("initial.velocity", list(v), allowed + "use z = 0)")
    if e[1] != 0.0 or e[2] != 0.0:
        raise InputError("initial.quaternion", list(e), allowed + "rotate about z)")


def _initial_modal(vals, n, name):
    if len(vals) == 0:
        return np.zeros(n)
    if len(vals) != n:
        raise InputError(f"initial.{name}", list(vals), f"{n} values (one per mode) or none")
    return np.asarray(vals, dtype=float)


def check_inputs(body: Body, loads, initial: Initial, settings: Settings, method: str, clamped: bool = False):
    """Every check :func:`simulate` makes before integrating; returns the packed
    ``(geometric flag, body tensors, load arrays)``.

    Raises
    ------
    InputError
        Bad input (one line naming field, value and what is allowed).
    """
    if method not in METHODS:
        raise InputError("solver.method", method, "one of " + ", ".join(METHODS))
    if settings.kinematics == "inextensible":
        _check_inextensible(body, loads, settings, clamped)
    geo = use_geometric(body, settings, clamped)
    B = pack_body(body)
    Lp = pack_loads(body, list(loads), geo, clamped)
    if body.planar and B[2][0, 0] > body.extra_inertia[0, 0] * (1 + 1e-12):
        _require_in_plane(loads, initial)
    _initial_modal(initial.modal_displacement, body.n_modes, "modal_displacement")
    _initial_modal(initial.modal_velocity, body.n_modes, "modal_velocity")
    return geo, B, Lp


def estimate_steps(body: Body, settings: Settings, method: str = "full", prescribed: Prescribed | None = None):
    """Integrator steps a run needs at least, estimated before it starts: ``(steps, omega_max)``.

    The explicit step is bounded by the fastest mode ``omega_max`` [rad/s] of the linearised body
    (unconstrained frequencies for free-floating runs, clamped ones under prescribed motion):
    ``steps >= omega_max t_end``, one step per radian of that mode's phase. Measured on seven
    runs (benchmarks and examples, rtol 1e-6 to 1e-10): 1.3 to 8 steps per radian, so a run whose
    estimate exceeds the budget would use it up.
    """
    if body.n_modes == 0:
        return 0.0, 0.0
    if prescribed is None and method in METHODS:
        from rotaflex.floating.hub import free_frequencies

        w = float(free_frequencies(body).max(initial=0.0))
    else:
        w = float(body.frequencies.max(initial=0.0))
    return w * settings.t_end, w


def check_step_budget(body: Body, settings: Settings, method: str = "full", prescribed: Prescribed | None = None):
    """Refuse a run whose estimated steps (:func:`estimate_steps`) exceed ``solver.max_steps``."""
    from rotaflex.core.limits import require

    steps, w = estimate_steps(body, settings, method, prescribed)
    require(
        "solver.max_steps",
        settings.max_steps,
        steps,
        settings.max_steps,
        f"integration steps (t_end = {settings.t_end:g} s, fastest mode {w:.4g} rad/s: at least one step per radian)",
        f"raise solver.max_steps above {steps:.3g}, or shorten solver.t_end, or use fewer modes",
    )


def run_mode(method: str, prescribed: Prescribed | None, settings: Settings) -> int:
    """The integrator mode (:data:`rotaflex.floating.integrator.MODES`) of a run: 0 full, 1
    perturbation, 2 prescribed motion, 3 prescribed motion with inextensible kinematics."""
    if prescribed is not None:
        return 3 if settings.kinematics == "inextensible" else 2
    return 0 if method == "full" else 1


def simulate(
    body: Body,
    loads=(),
    initial: Initial | None = None,
    settings: Settings | None = None,
    method: str = "full",
    prescribed: Prescribed | None = None,
    *,
    t_start: float = 0.0,
    progress=None,
) -> Solution:
    """Simulate a floating flexible body.

    Parameters
    ----------
    body : Body
    loads : sequence of Load
    initial : Initial, optional
        Initial state (default: at rest at the origin, identity attitude).
    settings : Settings, optional
    method : {"full", "perturbation"}
        "full": nonlinear hybrid equations (eq. 5, 7-9), the reference. "perturbation": zero-order
        rigid (eq. 27, 29-30) plus first-order linear time-varying equations (eq. 31, 35-37), total
        = zero order + first order. With ``prescribed`` motion both reduce to the same linear
        elastic equation (the rigid motion is given).
    prescribed : Prescribed, optional
        Prescribed rotation about a body-fixed axis (Kane-Ryan-Banerjee spin-up); then only the
        elastic coordinates are integrated and ``initial`` rigid values are ignored.
    t_start : float
        Start time [s] of the run (``initial`` holds at ``t_start``; output times from
        :func:`output_times`: every ``settings.dt_out``, and always ``settings.t_end`` last).
        Used for sampled-data control loops.
    progress : callable, optional
        ``progress(t)`` with the simulated time [s] reached, called about 100 times during the run.

    Returns
    -------
    Solution

    A run that stops early (step budget, step-size underflow, divergence guard) returns its
    samples up to the stop (later rows NaN) with ``status`` ``"failed"`` or ``"diverged"`` and a
    ``message`` saying why in words.
    """
    from rotaflex.floating import integrator

    initial = initial or Initial()
    settings = settings or Settings()
    n = body.n_modes
    geo, B, Lp = check_inputs(body, loads, initial, settings, method, prescribed is not None)
    t_out = output_times(t_start, settings.t_end, settings.dt_out)
    q0 = _initial_modal(initial.modal_displacement, n, "modal_displacement")
    p0 = _initial_modal(initial.modal_velocity, n, "modal_velocity")
    e0 = np.asarray(initial.quaternion, float) / np.linalg.norm(initial.quaternion)
    rigid0 = np.concatenate([initial.position, e0, initial.velocity, initial.angular_velocity])
    pres = np.zeros(7)
    mode = run_mode(method, prescribed, settings)
    if prescribed is not None:
        pres = prescribed.packed()
        y0 = np.concatenate([q0, p0])
        lim = (0, n)
    elif mode == 0:
        y0 = np.concatenate([rigid0, q0, p0])
        lim = (13, 13 + n)
    else:
        y0 = np.concatenate([rigid0, np.zeros(12), q0, p0])
        lim = (25, 25 + n)
    phimax = float(np.abs(body.shapes).max(initial=0.0))
    q_limit = 10.0 * body.length / max(phimax, 1e-300)
    breaks = _breaks(loads, prescribed, t_out[-1], t_start)
    if mode == 3:  # the inextensible kinematics arrays take the place of the body tensors
        B = (np.asarray(body.masses, float), np.asarray(body.points, float), np.asarray(body.shapes, float))
        B = B + tuple(body.inextensible.packed())
    run = integrator.LOOPS[mode]  # the one compiled loop (and right-hand side) this run uses
    t0 = time.perf_counter()
    Y, EUL, y, K0, att, cnt, hs = integrator.start(y0, t_out, breaks)
    # in chunks of output rows when progress is shown (the carried state makes this identical
    # to one call); one call otherwise
    n_chunks = min(100, len(t_out) - 1) if progress is not None else 1
    ends = np.unique(np.linspace(1, len(t_out), n_chunks + 1).round().astype(np.int64))[1:]
    n_lim = np.array(lim, dtype=np.int64)
    st = 0
    for i_end in ends:
        st = run(
            mode, t_out, i_end, Y, EUL, y, K0, att, cnt, hs, breaks, settings.rtol, settings.atol,
            settings.max_steps, q_limit, n_lim, B, Lp, geo, pres,
        )  # fmt: skip
        if progress is not None:
            progress(float(hs[1]))
        if st != 0:
            break
    nfev, nstep, t_stop = int(cnt[0]), int(cnt[1]), float(hs[1])
    wall = time.perf_counter() - t0
    sol = _unpack(mode, method, t_out, Y, n, prescribed, pres)
    sol.euler_123 = EUL[:, :3]
    if mode == 1:
        sol.parts["euler0"] = EUL[:, 3:]
    sol.nfev, sol.nstep, sol.wall_time, sol.geometric = int(nfev), int(nstep), wall, geo
    sol.kinematics = "inextensible" if mode == 3 else "linear"
    # the inextensible model's linearisation is K_b + M~(w) + K_G: judge its stability by that
    sol.min_stiffness = min_effective_stiffness(body, sol.angular_velocity, geo or mode == 3)
    ok = np.isfinite(sol.min_stiffness)
    neg = np.nonzero(ok & (sol.min_stiffness < 0))[0]
    notes = []
    if st in (1, 2):
        # stopped early: keep the samples computed so far (later rows are NaN) and say why
        sol.status = "failed"
        why = (
            f"the step budget solver.max_steps = {settings.max_steps} was used up"
            if st == 1
            else "the step size fell below 1e-14 of the time span (stiff or non-finite state"
            + (", or a slope |v'| >= 1 that no inextensible curve has)" if mode == 3 else ")")
        )
        notes.append(
            f"time integration stopped early at t = {t_stop:.6g} s of {t_out[-1]:.6g} s because "
            f"{why}; the output keeps the samples before that time"
        )
        log.warning("floating %s: %s", method, notes[0])
    if neg.size:
        notes.append(
            f"effective elastic stiffness K_b + M~(w){' + K_G' if geo else ''} is indefinite from "
            f"t = {t_out[neg[0]]:.4g} s (min eigenvalue {np.nanmin(sol.min_stiffness):.4g} "
            "1/s^2): "
            "centrifugal softening makes the linear modal model unstable"
            + ("" if geo or body.geometric is None else "; set solver.geometric_stiffness = true")
        )
    notes += _range_notes(body, sol)
    unstiffened = settings.geometric_stiffness is not False and settings.kinematics == "linear"
    if unstiffened and body.load_geometric is None and any(ld.kind == "force" for ld in loads):
        notes.append(
            "note: forces do not stiffen this body (point or file data carry no stress state; "
            "only a given centrifugal geometric tensor acts): use a beam or FE frame body for load stiffening"
        )
    if sol.status == "success" and sol.kinematics == "linear" and _max_deflection(body, sol.q) > body.length:
        sol.status = "diverged"
        if st != 3:  # a stop by the divergence guard is reported once, below
            log.warning("floating %s: %s", method, notes[-1])
    if st == 3:
        sol.status = "diverged"
        notes.insert(
            0,
            f"response diverged at t = {t_stop:.4g} s (|q| > {q_limit:.3g}, i.e. deflections > 10 x body size)",
        )
        log.warning("floating %s: %s", method, notes[0])
    sol.message = "; ".join(notes) if notes else f"{nstep} steps, {nfev} evaluations"
    return sol


#: elastic deflection [fraction of the body size] above which the linear model is out of range
LINEAR_RANGE = 0.1
#: slope |v'| above which a modal v(s) field resolves the inextensible curve poorly
STEEP_SLOPE = 0.8


def _max_deflection(body: Body, q: np.ndarray) -> float:
    """Largest elastic deflection [m] of any mass point over the finite rows of ``q`` (T, n)."""
    q = q[np.isfinite(q).all(axis=1)]
    if q.size == 0 or body.n_modes == 0:
        return 0.0
    S = body.shapes.reshape(-1, body.n_modes)
    out = 0.0
    for i in range(0, len(q), 256):  # blocks keep the (T, N, 3) deflections small
        u = (q[i : i + 256] @ S.T).reshape(-1, body.masses.size, 3)
        out = max(out, float(np.sqrt((u * u).sum(axis=-1)).max()))
    return out


def _range_notes(body: Body, sol: Solution) -> list[str]:
    """Plain-words notes when a run left the range where its kinematics is accurate."""
    if body.n_modes == 0:
        return []
    if sol.kinematics == "inextensible":
        q = sol.q[np.isfinite(sol.q).all(axis=1)]
        slope = float(np.abs(q @ body.inextensible.slopes.T).max(initial=0.0))
        if slope > STEEP_SLOPE:
            return [
                f"the slope |v'| reached {slope:.3g} (the beam turns by {np.degrees(np.arcsin(min(slope, 1.0))):.0f}"
                " deg): a modal v(s) field resolves such shapes poorly; check the result with more modes"
            ]
        return []
    defl = _max_deflection(body, sol.q)
    if defl <= LINEAR_RANGE * body.length:
        return []
    return [
        f"the elastic deflection reached {defl:.3g} m, {defl / body.length:.0%} of the body size "
        f"{body.length:g} m: "
        + (
            "more than the body itself, so the result is not a small-deflection solution; "
            if defl > body.length
            else ""
        )
        + "the linear floating-frame model is accurate to ~1e-3 only below ~1 % (docs/floating.md, limits)"
    ]


def _quat_from_rotvec(th):
    ang = np.linalg.norm(th, axis=-1, keepdims=True)
    half = 0.5 * ang
    scale = 0.5 * np.sinc(half / np.pi)
    return np.concatenate([np.cos(half), scale * th], axis=-1)


def _unpack(mode, method, t, Y, n, prescribed, pres) -> Solution:
    from rotaflex.rotation.quaternion import quaternion_product

    nt = len(t)
    if mode >= 2:
        ax = pres[:3]
        from rotaflex.floating.kernels import motion_profile

        prof = np.array([motion_profile(pres, tt) for tt in t])
        ang, om = prof[:, 0], prof[:, 1]
        quat = np.concatenate([np.cos(0.5 * ang)[:, None], np.sin(0.5 * ang)[:, None] * ax[None]], 1)
        return Solution(
            "prescribed",
            t,
            np.zeros((nt, 3)),
            quat,
            np.zeros((nt, 3)),
            om[:, None] * ax[None],
            Y[:, :n],
            Y[:, n:],
        )
    if mode == 0:
        e = Y[:, 3:7] / np.linalg.norm(Y[:, 3:7], axis=1, keepdims=True)
        return Solution("full", t, Y[:, 0:3], e, Y[:, 7:10], Y[:, 10:13], Y[:, 13 : 13 + n], Y[:, 13 + n :])
    e0 = Y[:, 3:7] / np.linalg.norm(Y[:, 3:7], axis=1, keepdims=True)
    th1 = Y[:, 16:19]
    e = quaternion_product(e0, _quat_from_rotvec(th1))
    parts = {
        "R0": Y[:, 0:3],
        "e0": e0,
        "V0": Y[:, 7:10],
        "w0": Y[:, 10:13],
        "R1": Y[:, 13:16],
        "th1": th1,
        "V1": Y[:, 19:22],
        "w1": Y[:, 22:25],
    }
    return Solution(
        "perturbation",
        t,
        Y[:, 0:3] + Y[:, 13:16],
        e,
        Y[:, 7:10] + Y[:, 19:22],
        Y[:, 10:13] + Y[:, 22:25],
        Y[:, 25 : 25 + n],
        Y[:, 25 + n :],
        parts=parts,
    )


def min_effective_stiffness(body: Body, w: np.ndarray, geo: bool) -> np.ndarray:
    """Smallest eigenvalue of ``K_b + M~(w) (+ K_G(w))`` at each time [1/s^2]."""
    if body.n_modes == 0:
        return np.full(len(w), np.inf)
    W = skew(w)
    WW = W @ W  # (T, 3, 3)
    PP = np.einsum("k,kai,kbj->abij", body.masses, body.shapes, body.shapes)  # (3, 3, n, n)
    Keff = body.stiffness[None] + np.einsum("tab,abij->tij", WW, PP)
    if geo and body.geometric is not None:
        Keff = Keff + geometric_stiffness(body, w)
    out = np.full(len(w), np.nan)
    ok = np.all(np.isfinite(Keff), axis=(1, 2))  # rows after an early stop are NaN
    out[ok] = np.linalg.eigvalsh(0.5 * (Keff[ok] + np.swapaxes(Keff[ok], 1, 2)))[:, 0]
    return out


# ----------------------------------------------------------------------------------------
# post-processing: points, momenta, energy
# ----------------------------------------------------------------------------------------
def rotation_matrices(quat: np.ndarray) -> np.ndarray:
    from rotaflex.rotation.quaternion import quaternion_to_matrix

    return quaternion_to_matrix(quat / np.linalg.norm(quat, axis=-1, keepdims=True))


def point_motion(body: Body, sol: Solution, points: np.ndarray):
    """Inertial positions (T, P, 3) and body-frame elastic deflections (T, P, 3) of points."""
    Phi, _ = body.shape_fn(points)
    u = np.einsum("paj,tj->tpa", Phi, sol.q)
    if sol.kinematics == "inextensible":
        u[:, :, 0] += body.inextensible.shortening(np.asarray(points, float)[:, 0], sol.q)
    A = rotation_matrices(sol.quaternion)
    pos = sol.position[:, None, :] + np.einsum("tab,tpb->tpa", A, points[None] + u)
    return pos, u


def invariants(body: Body, sol: Solution):
    """Inertial linear momentum (T, 3), angular momentum about the inertial origin (T, 3),
    total energy (T,) [J] (kinetic + modal strain) and centre-of-mass position (T, 3)."""
    A = rotation_matrices(sol.quaternion)
    c = body.points[None] + np.einsum("kaj,tj->tka", body.shapes, sol.q)
    ud = np.einsum("kaj,tj->tka", body.shapes, sol.p)
    inext = sol.kinematics == "inextensible"
    if inext:
        c[:, :, 0] += body.inextensible.shortening(body.points[:, 0], sol.q)
        ud[:, :, 0] += body.inextensible.shortening_rate(body.points[:, 0], sol.q, sol.p)
    vb = sol.velocity[:, None, :] + np.cross(sol.angular_velocity[:, None, :], c) + ud
    m = body.masses
    Pb = np.einsum("k,tka->ta", m, vb)
    Hb = np.einsum("k,tka->ta", m, np.cross(c, vb)) + sol.angular_velocity @ body.extra_inertia.T
    T = 0.5 * np.einsum("k,tka,tka->t", m, vb, vb) + 0.5 * np.einsum(
        "ta,ab,tb->t", sol.angular_velocity, body.extra_inertia, sol.angular_velocity
    )
    if sol.geometric and body.geometric is not None and sol.method == "full":
        # L_G = -1/2 w^T S(q) w with S_ab = q^T G_ab q
        Sm = np.einsum("ti,abij,tj->tab", sol.q, body.geometric, sol.q)
        w = sol.angular_velocity
        Hb = Hb - np.einsum("tab,tb->ta", Sm, w)
        T = T - 0.5 * np.einsum("ta,tab,tb->t", w, Sm, w)
    P = np.einsum("tab,tb->ta", A, Pb)
    H = np.cross(sol.position, P) + np.einsum("tab,tb->ta", A, Hb)
    U = (
        body.inextensible.bending_energy(sol.q)
        if inext
        else 0.5 * np.einsum("ti,ij,tj->t", sol.q, body.stiffness, sol.q)
    )
    cm = sol.position + np.einsum("tab,tb->ta", A, np.einsum("k,tka->ta", m, c)) / m.sum()
    return P, H, T + U, cm
