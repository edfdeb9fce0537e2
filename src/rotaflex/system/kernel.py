"""Compiled fixed-step RK4 of the reduced gearbox equations with one-sided gear meshes.

Reduced coordinates eta (``q = P eta``, ``P^T M P = I``)::

    eta'' = f - K eta - D eta' - sum_j g_j F_j
    delta_j = g_j . eta - e_j(phi_j),  phi_j = phi0_j + nu_j t   (prescribed mesh phase, cycles)
    F_j = k_j(phi_j) delta_j + c_j delta_j'          delta_j > 0           (drive flank)
    F_j = k_j(phi_j) (delta_j + b_j) + c_j delta_j'  delta_j < -b_j, b_j >= 0 (back flank)
    F_j = 0                                          otherwise             (contact loss)

Tables are piecewise cubics on a uniform phase grid (``MeshTable.coefficients``). Each step
records the DTE (twist part ``t_j . eta``), delta, F, the energy
``E = eta'^2/2 + eta.Ks eta/2 - eta.f + sum V_j`` (``V_j = k (delta [+ b])^2 / 2`` in contact)
and the power ``P`` of everything not in E (damping, non-symmetric stiffness, the explicit time
dependence of k and e), so that ``E(t) - E(0) = int P dt`` checks the integration.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from rotaflex.core.compiled import entry, inner


class Reduced(NamedTuple):
    """Reduced model arrays: K (r, r), D (r, r), Ks (symmetric part of K), Ka (skew part; (0, 0) when K is symmetric),
    Ds (symmetric part of D), f (r,) [N-ish, reduced], g (nm, r), t (nm, r) twist part of g."""

    K: np.ndarray
    D: np.ndarray
    Ks: np.ndarray
    Ka: np.ndarray
    Ds: np.ndarray
    f: np.ndarray
    g: np.ndarray
    t: np.ndarray


class Meshes(NamedTuple):
    """Per mesh: stiffness and TE cubic coefficients (nm, 4, n), phase rate nu [cycles/s], phase
    at t = 0 [cycles], damping c [N s/m], backlash b [m] (< 0: no back contact), mean stiffness
    [N/m] and a flag ``varying`` (0: use the mean stiffness)."""

    ck: np.ndarray
    ce: np.ndarray
    nu: np.ndarray
    phase0: np.ndarray
    c: np.ndarray
    b: np.ndarray
    kmean: np.ndarray
    varying: np.ndarray


@inner
def _table(c, j, phase, side):
    """Value and phase derivative of table j at ``phase`` [cycles]. ``side`` +1 / -1: at a grid
    point (to 1e-6 of a cell) take the cell after / before it, i.e. the one-sided limits of the
    derivative, which jumps there for piecewise-linear tables; 0: the cell containing phase."""
    n = c.shape[2]
    x = (phase - np.floor(phase)) * n
    i = int(x)
    if i >= n:
        i = n - 1
    u = x - i
    if side != 0:
        xr = np.floor(x + 0.5)
        if abs(x - xr) < 1e-6:
            if side > 0:
                i, u = int(xr) % n, 0.0
            else:
                i, u = (int(xr) - 1) % n, 1.0
    y = c[j, 0, i] + u * (c[j, 1, i] + u * (c[j, 2, i] + u * c[j, 3, i]))
    dy = n * (c[j, 1, i] + u * (2.0 * c[j, 2, i] + 3.0 * u * c[j, 3, i]))
    return y, dy


@inner
def _mesh(ms, j, t, gx, gv, side):
    """Force, deflection, and the energy/power terms of mesh j at time t (gx = g.eta, gv = g.eta');
    ``side``: which one-sided derivative of the tables at a grid point (:func:`_table`)."""
    ph = ms.phase0[j] + ms.nu[j] * t
    e, de = _table(ms.ce, j, ph, side)
    if ms.varying[j] > 0:
        k, dk = _table(ms.ck, j, ph, side)
    else:
        k, dk = ms.kmean[j], 0.0
    d = gx - e
    dd = gv - de * ms.nu[j]
    s = 0.0
    on = False
    if d > 0.0:
        s, on = d, True
    elif ms.b[j] >= 0.0 and d < -ms.b[j]:
        s, on = d + ms.b[j], True
    if not on:
        return 0.0, d, 0.0, 0.0
    F = k * s + ms.c[j] * dd
    V = 0.5 * k * s * s
    # explicit time dependence of V = k(phi(t)) s^2/2 with e(phi(t)) inside s, and the damper
    P = 0.5 * dk * ms.nu[j] * s * s - k * s * de * ms.nu[j] - ms.c[j] * dd * gv
    return F, d, V, P


@inner
def _accel(rd, ms, t, x, v, a, kx, dv, side):
    """Acceleration ``a`` at (t, x, v); also stores ``kx = K x`` and ``dv = D v`` for
    :func:`_record` at the same state (one pass over K and D per state, not two). ``side``: the
    table cell at a grid point (:func:`_table`): +1 at a step's start, -1 at its end, so that
    every stage of a step sees the same cell of piecewise-linear tables."""
    r = x.size
    for i in range(r):
        sk = 0.0
        sd = 0.0
        for k in range(r):
            sk += rd.K[i, k] * x[k]
            sd += rd.D[i, k] * v[k]
        kx[i] = sk
        dv[i] = sd
        a[i] = rd.f[i] - sk - sd
    for j in range(ms.nu.size):
        gx = 0.0
        gv = 0.0
        for i in range(r):
            gx += rd.g[j, i] * x[i]
            gv += rd.g[j, i] * v[i]
        F, _, _, _ = _mesh(ms, j, t, gx, gv, side)
        if F != 0.0:
            for i in range(r):
                a[i] -= rd.g[j, i] * F


@inner
def _record(rd, ms, t, x, v, kx, dv, out_dte, out_d, out_F, out_E, out_P, s):
    """Energy and power at (t, x, v) with ``kx = K x``, ``dv = D v`` from :func:`_accel`:
    ``x.Ks x = x.K x`` and ``v.Ds v = v.D v`` (skew parts drop out of quadratic forms); the
    skew stiffness' power ``v.Ka x`` needs its own product, skipped when Ka is empty (symmetric K)."""
    r = x.size
    E = 0.0
    P = 0.0
    skew = rd.Ka.shape[0] > 0
    Pleft = 0.0
    for i in range(r):
        E += 0.5 * v[i] * v[i] + 0.5 * x[i] * kx[i] - x[i] * rd.f[i]
        P -= v[i] * dv[i]
        if skew:
            ax = 0.0
            for k in range(r):
                ax += rd.Ka[i, k] * x[k]
            P -= v[i] * ax
    Pmesh = 0.0
    for j in range(ms.nu.size):
        gx = 0.0
        gv = 0.0
        tx = 0.0
        for i in range(r):
            gx += rd.g[j, i] * x[i]
            gv += rd.g[j, i] * v[i]
            tx += rd.t[j, i] * x[i]
        F, d, V, Pm = _mesh(ms, j, t, gx, gv, np.int64(1))
        Pl = Pm
        ph = ms.phase0[j] + ms.nu[j] * t
        xg = (ph - np.floor(ph)) * ms.ck.shape[2]
        if abs(xg - np.floor(xg + 0.5)) < 1e-6:  # on a table point: the limit from before differs
            Pl = _mesh(ms, j, t, gx, gv, np.int64(-1))[3]
        out_dte[s, j] = tx
        out_d[s, j] = d
        out_F[s, j] = F
        E += V
        Pmesh += Pm
        Pleft += Pl
    out_E[s] = E
    # power entering the step that starts here (right limit) and ending the one before (left)
    out_P[s, 0] = P + Pmesh
    out_P[s, 1] = P + Pleft


@entry
def run_rk4(rd, ms, x, v, t0, dt, n_steps, out_x, out_v, out_dte, out_d, out_F, out_E, out_P):
    """Advance (x, v) in place by ``n_steps`` RK4 steps from t0; record n_steps + 1 samples."""
    r = x.size
    k1x = np.empty(r)
    k1v = np.empty(r)
    k2x = np.empty(r)
    k2v = np.empty(r)
    k3x = np.empty(r)
    k3v = np.empty(r)
    k4x = np.empty(r)
    k4v = np.empty(r)
    xs = np.empty(r)
    vs = np.empty(r)
    kx = np.empty(r)
    dv = np.empty(r)
    kw = np.empty(r)
    dw = np.empty(r)
    # integer constants passed as np.int64: numba compiles a callee once per literal value it is
    # called with (_accel, _mesh and _table were compiled three times, _record twice; a cold
    # `system steady` of gearbox.toml took 14.4 s CPU, now 10.8 s; results bit-identical)
    _accel(rd, ms, t0, x, v, k1v, kx, dv, np.int64(1))
    _record(rd, ms, t0, x, v, kx, dv, out_dte, out_d, out_F, out_E, out_P, np.int64(0))
    out_x[0] = x
    out_v[0] = v
    for s in range(n_steps):
        t = t0 + s * dt
        k1x[:] = v  # k1v: the acceleration computed with the last record
        for i in range(r):
            xs[i] = x[i] + 0.5 * dt * k1x[i]
            vs[i] = v[i] + 0.5 * dt * k1v[i]
        k2x[:] = vs
        _accel(rd, ms, t + 0.5 * dt, xs, vs, k2v, kw, dw, np.int64(0))
        for i in range(r):
            xs[i] = x[i] + 0.5 * dt * k2x[i]
            vs[i] = v[i] + 0.5 * dt * k2v[i]
        k3x[:] = vs
        _accel(rd, ms, t + 0.5 * dt, xs, vs, k3v, kw, dw, np.int64(0))
        for i in range(r):
            xs[i] = x[i] + dt * k3x[i]
            vs[i] = v[i] + dt * k3v[i]
        k4x[:] = vs
        _accel(rd, ms, t + dt, xs, vs, k4v, kw, dw, np.int64(-1))
        for i in range(r):
            x[i] += dt / 6.0 * (k1x[i] + 2.0 * k2x[i] + 2.0 * k3x[i] + k4x[i])
            v[i] += dt / 6.0 * (k1v[i] + 2.0 * k2v[i] + 2.0 * k3v[i] + k4v[i])
        # the next step's k1 and this sample's energy terms from one pass over K and D
        _accel(rd, ms, t + dt, x, v, k1v, kx, dv, np.int64(1))
        _record(rd, ms, t + dt, x, v, kx, dv, out_dte, out_d, out_F, out_E, out_P, s + 1)
        out_x[s + 1] = x
        out_v[s + 1] = v
