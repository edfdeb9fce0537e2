"""Compiled fixed-step RK4 for the torsional gear-train model (:mod:`rotaflex.gear.models.chain`).

The train is a chain of ``n <= 4`` rigid inertias (motor, pinion, wheel, load, rigid shafts
merged beforehand) joined by linear torsional springs/dampers; the mesh joins chain nodes
``ip`` (pinion) and ``iw`` (wheel). Angles are positive in each body's own sense of rotation.
The mesh phase is ``phi = z1 theta_ip / (2 pi) + phi0`` (mesh cycles), the mesh tables are
piecewise cubics on a uniform phase grid of ``m`` cells: for cell j and local ``u`` in [0, 1),
``y = c[0, j] + c[1, j] u + c[2, j] u^2 + c[3, j] u^3``.

Optional lateral nodes ``iy1``, ``iy2`` (< 0: none) carry the displacements of the pinion and
wheel centres along the line of action (bearing compliance): they are chain entries with a
mass instead of an inertia, no shaft to their neighbours, a spring and dashpot to ground
(``kg``, ``cg``) and nominal speed 0.

Mesh deflection and force (one-sided, optional back side after a backlash ``b``)::

    delta = rb1 theta_ip - rb2 theta_iw + y1 - y2 - e(phi),   delta' = d delta / dt
    F = k(phi) delta + c_m delta'            delta > 0        (drive side)
    F = k(phi) (delta + b) + c_m delta'      delta < -b       (back side, if b >= 0)
    F = 0                                    otherwise       (contact loss)

Compilation (cold cache, measured with a fresh NUMBA_CACHE_DIR, CPU time on the 2-core machine):
the kernels are compiled with ``error_model="numpy"`` (no zero-division checks: every divisor
is a validated positive model constant; ~12 % less to compile), write rows element by element
and run the RK4 stages in a loop with one RHS call site (docs/gear-steady-state.md, "First run").
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from rotaflex.core.compiled import entry, inner

__all__ = ["ChainArgs", "MeshArgs", "chain_rhs", "rk4_stage", "rk4_update", "run_rk4"]


class ChainArgs(NamedTuple):
    """The inertia chain: 1/J [1/(kg m^2)], shaft stiffness [N m/rad] and damping [N m s/rad]
    between neighbours, applied torque [N m], motor slope [N m s/rad] about the nominal speed
    [rad/s], prescribed-speed flags, the torque ramp time [s] (0: none), and each node's
    stiffness and damping to ground (bearings of the lateral nodes) [N/m], [N s/m]."""

    jinv: np.ndarray
    ks: np.ndarray
    cs: np.ndarray
    torque: np.ndarray
    slope: np.ndarray
    nominal: np.ndarray
    presc: np.ndarray
    ramp_time: float
    kg: np.ndarray
    cg: np.ndarray


class MeshArgs(NamedTuple):
    """The mesh: pinion and wheel node indices, base radii [m], pinion teeth, phase offset
    [cycles], stiffness [N/m] and unloaded-TE [m] cubic coefficients, damping [N s/m], backlash
    [m] (negative: no back-side contact), lateral node indices of pinion and wheel (< 0: none)."""

    ip: int
    iw: int
    rb1: float
    rb2: float
    z1: float
    phi0: float
    kc: np.ndarray
    ec: np.ndarray
    c_m: float
    backlash: float
    iy1: int
    iy2: int


@inner(error_model="numpy")
def _table(c, phi):
    """Value and phase derivative of the periodic table at phase ``phi`` [cycles]."""
    m = c.shape[1]
    x = (phi - np.floor(phi)) * m
    j = int(x)
    if j >= m:
        j = m - 1
    u = x - j
    y = c[0, j] + u * (c[1, j] + u * (c[2, j] + u * c[3, j]))
    dy = m * (c[1, j] + u * (2.0 * c[2, j] + 3.0 * u * c[3, j]))
    return y, dy


@inner(error_model="numpy")
def _mesh(mesh, th, om):
    """Mesh force F [N], deflection delta [m], its rate [m/s] and contact state (1, 0, -1)."""
    ip, iw, rb1, rb2, z1, phi0, kc, ec, c_m, backlash, iy1, iy2 = mesh
    phi = z1 * th[ip] / (2.0 * np.pi) + phi0
    dphi = z1 * om[ip] / (2.0 * np.pi)
    k, _ = _table(kc, phi)
    e, de = _table(ec, phi)
    delta = rb1 * th[ip] - rb2 * th[iw] - e
    ddelta = rb1 * om[ip] - rb2 * om[iw] - de * dphi
    if iy1 >= 0:
        delta += th[iy1]
        ddelta += om[iy1]
    if iy2 >= 0:
        delta -= th[iy2]
        ddelta -= om[iy2]
    if delta > 0.0:
        return k * delta + c_m * ddelta, delta, ddelta, 1
    if backlash >= 0.0 and delta < -backlash:
        return k * (delta + backlash) + c_m * ddelta, delta, ddelta, -1
    return 0.0, delta, ddelta, 0


@inner(error_model="numpy")
def chain_rhs(t, th, om, out_th, out_om, chain, f, ip, iw, rb1, rb2, iy1, iy2):
    """The chain's equations of motion, written once for both steady kernels.

    ``out_th = om`` and ``out_om`` = the nodes' accelerations at time ``t`` [s] under the
    applied torques (ramped over ``chain.ramp_time``), the motor slope, the shafts, the
    supports to ground and the mesh force ``f`` [N] acting at the pinion node ``ip`` (``-r_b1
    f``), the wheel node ``iw`` (``+r_b2 f``) and the lateral nodes ``iy1`` (``-f``) and ``iy2``
    (``+f``; < 0: none). Speed-prescribed nodes get zero acceleration.
    """
    jinv, ks, cs, torque, slope, nominal, presc, ramp_time, kg, cg = chain
    n = th.shape[0]
    scale = 1.0
    if ramp_time > 0.0 and t < ramp_time:
        scale = t / ramp_time
    for i in range(n):
        out_th[i] = om[i]
        if presc[i]:
            out_om[i] = 0.0
            continue
        q = scale * torque[i] + slope[i] * (nominal[i] - om[i]) - kg[i] * th[i] - cg[i] * om[i]
        if i > 0:
            q -= ks[i - 1] * (th[i] - th[i - 1]) + cs[i - 1] * (om[i] - om[i - 1])
        if i < n - 1:
            q -= ks[i] * (th[i] - th[i + 1]) + cs[i] * (om[i] - om[i + 1])
        if i == ip:
            q -= rb1 * f
        if i == iw:
            q += rb2 * f
        if i == iy1:
            q -= f
        if i == iy2:
            q += f
        out_om[i] = q * jinv[i]


@inner(error_model="numpy")
def rk4_stage(s, y, k, dt, out):
    """The point of RK4 stage ``s + 1`` after stage ``s`` (0, 1, 2) gave the slope ``k``:
    ``out = y + h k`` with ``h = dt / 2, dt / 2, dt``; returns ``h`` [s] (the stage's time is
    ``t + h``). Both steady kernels run their four stages in a loop with one call of their RHS,
    so that LLVM inlines the RHS once instead of four times (a third of the cold compilation)."""
    h = dt if s == 2 else 0.5 * dt
    for i in range(y.shape[0]):
        out[i] = y[i] + h * k[i]
    return h


@inner(error_model="numpy")
def rk4_update(y, k1, k2, k3, k4, dt):
    """The RK4 step ``y += dt / 6 (k1 + 2 k2 + 2 k3 + k4)`` in place."""
    for i in range(y.shape[0]):
        y[i] += dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])


@inner(error_model="numpy")
def _rhs(t, y, dy, chain, mesh):
    """``dy/dt`` of the chain state ``y = [theta (n), omega (n)]`` with the mesh spring."""
    n = y.shape[0] // 2
    th, om = y[:n], y[n:]
    f, _, _, _ = _mesh(mesh, th, om)
    chain_rhs(t, th, om, dy[:n], dy[n:], chain, f, mesh.ip, mesh.iw, mesh.rb1, mesh.rb2, mesh.iy1, mesh.iy2)


@entry(error_model="numpy")
def run_rk4(th, om, t0, dt, n_steps, record_every, chain, mesh):
    """Advance ``n_steps`` RK4 steps of size ``dt`` [s] from (th, om) at time t0 [s].

    ``th``/``om`` are updated in place. Every ``record_every`` steps (and at the start) the
    time, angles, speeds, mesh force, deflection and its rate are stored.

    Returns
    -------
    (t, theta, omega, force, delta, ddelta)
        Recorded histories, ``n_steps // record_every + 1`` rows.
    """
    n = th.shape[0]
    n_rec = n_steps // record_every + 1
    t_rec = np.empty(n_rec)
    th_rec = np.empty((n_rec, n))
    om_rec = np.empty((n_rec, n))
    f_rec = np.empty(n_rec)
    d_rec = np.empty(n_rec)
    dd_rec = np.empty(n_rec)
    # element loops, not slice assignments: numba's row assignment ``a[r, :] = b`` compiles its
    # shape-mismatch message formatting, ~4.7 s of a cold compilation (measured) for nothing
    y = np.empty(2 * n)
    for i in range(n):
        y[i] = th[i]
        y[n + i] = om[i]
    k = np.empty((4, 2 * n))
    yt = np.empty(2 * n)
    r = 0
    t = t0
    for step in range(n_steps + 1):
        if step % record_every == 0:
            f, d, dd, _ = _mesh(mesh, y[:n], y[n:])
            t_rec[r] = t
            for i in range(n):
                th_rec[r, i] = y[i]
                om_rec[r, i] = y[n + i]
            f_rec[r] = f
            d_rec[r] = d
            dd_rec[r] = dd
            r += 1
        if step == n_steps:
            break
        ts, ys = t, y
        for s in range(4):
            _rhs(ts, ys, k[s], chain, mesh)
            if s < 3:
                ts, ys = t + rk4_stage(s, y, k[s], dt, yt), yt
        rk4_update(y, k[0], k[1], k[2], k[3], dt)
        t = t0 + (step + 1) * dt
    for i in range(n):
        th[i] = y[i]
        om[i] = y[n + i]
    return t_rec, th_rec, om_rec, f_rec, d_rec, dd_rec
