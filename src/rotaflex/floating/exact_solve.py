"""Dynamics of the planar geometrically exact beam: generalized-alpha with clamp multipliers.

Equations (inertial coordinates, :mod:`rotaflex.floating.exact_beam`)::

    M q'' + f_int(q, q') - f_ext(q, t) + G(q)^T lam = 0,     g(q) = 0 (root clamps)

with a constant mass ``M`` (planar Reissner beam: translation and rotary inertia, plus the hub)
and the root clamps ``g`` tying each root node to the reference frame. The reference frame
(``X, Y, phi``) is fixed, follows a prescribed rotation (:class:`~rotaflex.floating.model.Prescribed`
profiles) or is a free rigid hub.

Integrator: generalized-alpha (Chung & Hulbert 1993, J. Appl. Mech. 60, 371-375) in the form of
Arnold & Bruls (2007, Multibody Syst. Dyn. 18, 185-202), which keeps equilibrium and the
constraints exactly at the step end (index-3 constraints, second order). Its one parameter is
the spectral radius at infinite frequency ``rho_inf`` in [0, 1]: 1 is the trapezoidal rule (no
numerical damping, energy kept to O(h^2) over the run), smaller values damp the unresolved
high frequencies (the stiff axial and shear modes) while the resolved ones keep second order.
Fixed step ``h`` onto every load/motion breakpoint and output time; a step whose Newton
iteration fails is retried in 2, 4, ... sub-steps.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass

import numpy as np

from rotaflex.core.errors import InputError
from rotaflex.floating import exact_kernels as ek
from rotaflex.floating.exact_beam import ExactBeam, PointLoads

log = logging.getLogger(__name__)

#: frame motions: held at its start value, rotation prescribed about z, free rigid hub
FRAMES = ("fixed", "prescribed", "free")


def alpha_coefficients(rho_inf: float) -> tuple[float, float, float, float]:
    """``(alpha_m, alpha_f, beta, gamma)`` of generalized-alpha for ``rho_inf`` (Chung & Hulbert
    1993, eq. 25 and 17-18: second order, high-frequency dissipation maximal for that radius)."""
    if not 0.0 <= rho_inf <= 1.0:
        raise InputError("body.exact.rho_inf", rho_inf, "a number from 0 to 1")
    am = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0)
    af = rho_inf / (rho_inf + 1.0)
    gamma = 0.5 + af - am
    return am, af, 0.25 * (gamma + 0.5) ** 2, gamma


def time_grid(t_end: float, dt_out: float, h: float, breaks=(), t_start: float = 0.0):
    """Step end times (start first) and a mask of the output times: every interval between the
    output times and breakpoints cut into equal steps no longer than ``h``."""
    from rotaflex.floating.solve import output_times

    out = output_times(t_start, t_end, dt_out)
    knots = np.unique(np.concatenate([out, [b for b in breaks if t_start < b < t_end]]))
    n = np.maximum(1, np.ceil((np.diff(knots) / h) * (1.0 - 1e-12)).astype(int))
    times = [knots[:1]] + [knots[i] + (knots[i + 1] - knots[i]) * np.arange(1, n[i] + 1) / n[i] for i in range(len(n))]
    times = np.concatenate(times)
    times[np.searchsorted(times, knots)] = knots  # exact knots despite round-off
    is_out = np.isin(times, out)
    return times, is_out


@dataclass
class ExactSolution:
    """States at the output times (SI): ``q``, ``v`` (T, n) in the DOF order of
    :class:`~rotaflex.floating.exact_beam.ExactBeam`; ``energy`` (T, 4): kinetic, strain, work of
    the applied loads, work of the drive (fixed and prescribed DOFs) [J]."""

    time: np.ndarray
    q: np.ndarray
    v: np.ndarray
    energy: np.ndarray
    status: str = "success"
    message: str = ""
    nstep: int = 0
    niter: int = 0
    wall_time: float = 0.0
    method: str = "exact"

    @property
    def balance(self) -> np.ndarray:
        """``E - E(0) - W_loads - W_drive`` (T,) [J]: zero for an exact integration of an
        undamped body."""
        e = self.energy[:, 0] + self.energy[:, 1]
        return e - e[0] - self.energy[:, 2] - self.energy[:, 3]


def initial_acceleration(beam: ExactBeam, loads: PointLoads, q, v, fixed, qdd_fixed, t=0.0):
    """``q''`` (n,) and clamp multipliers at the start: ``[M G^T; G 0] [q''; lam] = [f; -G' v]``
    with the driven DOFs' accelerations given (``qdd_fixed`` where ``fixed``)."""
    n = beam.n_dof
    clamp = beam.clamp_table()
    nc = 3 * len(clamp)
    lam = np.zeros(len(loads.node) + 1)
    ek.load_factors(t, loads.profile, loads.par, lam)
    fe, fi, Kd = np.zeros(n), np.zeros(n), np.zeros((1, 1))
    ek.external(
        q, lam, loads.node, loads.kind, loads.frame, loads.amp, loads.ref, beam.frame_dof + 2, loads.dist, fe, Kd, False
    )
    kap0 = np.zeros(len(beam.conn))
    ek.internal(q, v, beam.conn, beam.reference_lengths(), kap0, beam.stiffness, 0.0, 0.0, fi, Kd, False)
    g, G = np.zeros(nc), np.zeros((nc, n))
    if nc:
        ek.constraints(q, clamp, g, G)
    # the velocity-squared part of g'' for each clamp: + phi'^2 R(phi) r on the translations
    gdd = np.zeros(nc)
    phi, w = q[beam.frame_dof + 2], v[beam.frame_dof + 2]
    c, s = np.cos(phi), np.sin(phi)
    for i, (_, _, rx, ry, _, _) in enumerate(clamp):
        gdd[3 * i : 3 * i + 2] = w * w * np.array([c * rx - s * ry, s * rx + c * ry])
    M = beam.mass_matrix()
    free = np.flatnonzero(~fixed)
    rhs = fe - fi - M[:, fixed] @ qdd_fixed[fixed]
    A = np.zeros((len(free) + nc, len(free) + nc))
    A[: len(free), : len(free)] = M[np.ix_(free, free)]
    A[: len(free), len(free) :] = G[:, free].T
    A[len(free) :, : len(free)] = G[:, free]
    b = np.concatenate([rhs[free], -gdd - G[:, fixed] @ qdd_fixed[fixed]])
    x = np.linalg.lstsq(A, b, rcond=None)[0] if nc else np.linalg.solve(A, b)
    qdd = qdd_fixed.copy()
    qdd[free] = x[: len(free)]
    return qdd, x[len(free) :]


def simulate_exact(
    beam: ExactBeam,
    loads: PointLoads,
    *,
    t_end: float,
    dt_out: float,
    time_step: float,
    rho_inf: float = 0.9,
    eta: float = 0.0,
    frame: str = "fixed",
    prescribed: np.ndarray | None = None,
    q0: np.ndarray | None = None,
    v0: np.ndarray | None = None,
    breakpoints=(),
    max_steps: int = 2_000_000,
    newton_tol: float = 1e-10,
    progress=None,
) -> ExactSolution:
    """Integrate the beam from ``q0, v0`` (default: undeformed at rest) to ``t_end`` [s].

    Parameters
    ----------
    time_step : float
        Largest step ``h`` [s]; intervals between output times and breakpoints are cut into
        equal steps no longer than it.
    rho_inf : float
        Spectral radius at infinite frequency of generalized-alpha (1: no numerical damping).
    eta : float
        Kelvin-Voigt material damping time constant [s] (``2 zeta / omega`` damps the mode of
        frequency ``omega`` with ratio ``zeta``, higher modes more).
    frame : {"fixed", "prescribed", "free"}
        The reference frame is held, rotates by ``prescribed`` (packed
        :meth:`~rotaflex.floating.model.Prescribed.packed`), or is the free hub.
    newton_tol : float
        Newton stops when the largest correction is below ``newton_tol * max(L, 1)``.
    progress : callable, optional
        Called with the simulated time [s] after each chunk (about 1/50 of the run).
    """
    if frame not in FRAMES:
        raise ValueError(f"frame {frame!r} not in {FRAMES}")
    if frame == "free" and (beam.hub_mass <= 0 or beam.hub_inertia <= 0):
        raise InputError("body.hub.mass", beam.hub_mass, "a hub with mass and inertia > 0 for a free frame")
    t_wall = time.perf_counter()
    n = beam.n_dof
    d = beam.frame_dof
    q = beam.reference_state() if q0 is None else np.array(q0, dtype=float)
    v = np.zeros(n) if v0 is None else np.array(v0, dtype=float)
    fixed = np.zeros(n, dtype=bool)
    if frame != "free":
        fixed[d:] = True
    pres = np.full(7, -1.0) if prescribed is None or frame != "prescribed" else np.asarray(prescribed, dtype=float)
    hold = q.copy()
    qdd_fixed = np.zeros(n)
    if pres[5] >= 0:
        fixed[d + 2] = False  # driven by the profile, not held
        ang, om, al = ek.motion_profile(pres, 0.0)
        q[d + 2] = hold[d + 2] + ang
        v[d + 2] = om
        qdd_fixed[d + 2] = al
    driven = fixed.copy()
    if pres[5] >= 0:
        driven[d + 2] = True
    qdd, mult = initial_acceleration(beam, loads, q, v, driven, qdd_fixed)
    times, is_out = time_grid(t_end, dt_out, time_step, breakpoints)
    if len(times) - 1 > max_steps:
        from rotaflex.core.limits import require

        require(
            "solver.max_steps",
            max_steps,
            len(times) - 1,
            max_steps,
            f"generalized-alpha steps (t_end = {t_end:g} s, time_step = {time_step:.4g} s)",
            "raise solver.max_steps, or a longer body.exact.time_step, or a shorter solver.t_end",
        )
    am, af, beta, gamma = alpha_coefficients(rho_inf)
    coef = (am, af, beta, gamma, newton_tol * max(beam.length, 1.0), 25.0)
    L0 = beam.reference_lengths()
    bm = (beam.conn, L0, np.zeros(len(L0)), beam.stiffness, float(eta))
    ld = (loads.node, loads.kind, loads.frame, loads.amp, loads.ref, loads.profile, loads.par, loads.dist, d + 2)
    M = beam.mass_matrix()
    clamp = beam.clamp_table()
    a = qdd.copy()
    works = np.zeros(2)
    chunks = np.unique(np.linspace(0, len(times) - 1, min(51, len(times))).astype(int))
    parts, status, nstep, niter = [], 0, 0, 0
    for c0, c1 in zip(chunks[:-1], chunks[1:], strict=True):
        mask = is_out[c0 : c1 + 1].copy()
        if c0 > 0:
            mask[0] = False  # written by the chunk before
        status, Q, V, E, st, it = ek.integrate(
            q, v, qdd, a, mult, works, times[c0 : c1 + 1], mask, M, bm, ld, clamp, fixed, hold, pres, coef, 8
        )
        parts.append((Q, V, E))
        nstep += st
        niter += it
        if status:
            break
        if progress is not None:
            progress(float(times[c1]))
    Q = np.vstack([p[0] for p in parts])
    V = np.vstack([p[1] for p in parts])
    E = np.vstack([p[2] for p in parts])
    t_out = times[is_out]
    if len(Q) < len(t_out):  # stopped early: the rest of the outputs are NaN
        pad = np.full((len(t_out) - len(Q), n), np.nan)
        Q, V = np.vstack([Q, pad]), np.vstack([V, pad])
        E = np.vstack([E, np.full((len(pad), 4), np.nan)])
    msg = f"generalized-alpha (rho_inf = {rho_inf:g}): {nstep} steps, {niter} Newton iterations"
    if status:
        ok = np.isfinite(E[:, 0])
        t_fail = t_out[ok][-1] if ok.any() else 0.0
        msg = (
            f"generalized-alpha: Newton did not converge after t = {t_fail:.6g} s even with 256 sub-steps "
            "(a load the beam cannot carry, or a time_step far too long)"
        )
    log.info(msg)
    return ExactSolution(
        time=t_out,
        q=Q,
        v=V,
        energy=E,
        status="success" if status == 0 else "failed",
        message=msg,
        nstep=nstep,
        niter=niter,
        wall_time=time.perf_counter() - t_wall,
    )
