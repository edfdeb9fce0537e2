"""Compiled fixed-step RK4 of the travelling-window elastic-tooth model (:mod:`~.window`).

State vector ``y = [theta (n), omega (n), eta (W 2 m), eta' (W 2 m)]``: the chain's angles and
speeds, then the modal coordinates of the ``W`` window slots (pinion tooth, wheel tooth; ``m``
modes each). Tooth pair ``n`` lives in slot ``n mod W``; ``n_hi`` (the newest pair in the
window) changes only between steps, when the pinion has rolled a base pitch further; the slot
of the pair that left is then zeroed for the pair that enters.

Tables are sampled on a uniform LoA grid ``s0 + i ds`` and interpolated linearly.

Compilation (cold cache, measured with a fresh NUMBA_CACHE_DIR, CPU time on the 2-core machine):
the kernels are compiled with ``error_model="numpy"`` (no zero-division checks: every divisor
is a validated positive model constant; ~12 % less to compile), write rows element by element
and run the RK4 stages in a loop with one RHS call site (docs/gear-steady-state.md, "First run").
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from rotaflex.core.compiled import entry, inner
from rotaflex.gear.kernels.chain import chain_rhs, rk4_stage, rk4_update

__all__ = ["WindowArgs", "run_window_rk4"]


class WindowArgs(NamedTuple):
    """Pinion/wheel chain nodes, base radii [m], base pitch [m], path start/end [m], window
    entry position [m], window size, modes per tooth, table origin and step [m], residual
    stiffness [N/m], gap [m], participations (n_s, m) [1/sqrt(kg)],
    fillet stress per newton [Pa/N] of both gears, modal circular frequencies (m,) of both
    gears [rad/s], tooth damping ratio, mesh damping [N s/m] and the deflection over which it
    grows to its full value [m], lateral (bearing) chain nodes of pinion and wheel (< 0: none)."""

    ip: int
    iw: int
    rb1: float
    rb2: float
    pb: float
    s_start: float
    s_end: float
    s_low: float
    window: int
    n_modes: int
    s0: float
    ds: float
    k_res: np.ndarray
    gap: np.ndarray
    a1: np.ndarray
    a2: np.ndarray
    fillet1: np.ndarray
    fillet2: np.ndarray
    omega1: np.ndarray
    omega2: np.ndarray
    zeta: float
    c_mesh: float
    damping_onset: float
    iy1: int
    iy2: int


@inner(error_model="numpy")
def _cell(win, s):
    x = (s - win.s0) / win.ds
    n = win.k_res.shape[0]
    j = int(math.floor(x))
    if j < 0:
        j = 0
    if j > n - 2:
        j = n - 2
    return j, x - j


@inner(error_model="numpy")
def _lin(tab, j, u, ds):
    return tab[j] + u * (tab[j + 1] - tab[j]), (tab[j + 1] - tab[j]) / ds


@inner(error_model="numpy")
def _pairs(y, n_chain, n_hi, win, gen, rec):
    """Pair forces; modal generalised forces into ``gen`` (zeroed here). ``rec`` (length 8):
    total force, pinion and wheel fillet stress maxima, pairs in contact, parametric power,
    mesh dissipation, contact potential (tooth dissipation, slot 7, is added by ``_rhs``)."""
    m = win.n_modes
    W = win.window
    ip, iw = win.ip, win.iw
    base = 2 * n_chain
    nm2 = W * 2 * m
    for i in range(nm2):
        gen[i] = 0.0
    for i in range(8):
        rec[i] = 0.0
    th1, th2 = y[ip], y[iw]
    om1, om2 = y[n_chain + ip], y[n_chain + iw]
    x = win.rb1 * th1 - win.rb2 * th2
    xd = win.rb1 * om1 - win.rb2 * om2
    if win.iy1 >= 0:
        x += y[win.iy1]
        xd += y[n_chain + win.iy1]
    if win.iy2 >= 0:
        x -= y[win.iy2]
        xd -= y[n_chain + win.iy2]
    sd = win.rb1 * om1
    u_roll = win.rb1 * th1 + win.s_start
    s_min, s_max = win.s0, win.s0 + win.ds * (win.k_res.shape[0] - 1)
    dmax = 0.0
    for j in range(W):
        n = n_hi - j
        s = u_roll - n * win.pb
        if s < s_min or s > s_max:
            continue
        slot = ((n % W) + W) % W
        c, u = _cell(win, s)
        k, dk = _lin(win.k_res, c, u, win.ds)
        g, dg = _lin(win.gap, c, u, win.ds)
        defl = 0.0
        dpar = dg
        for gear in range(2):
            tab = win.a1 if gear == 0 else win.a2
            o = base + (slot * 2 + gear) * m
            for kk in range(m):
                a = tab[c, kk] + u * (tab[c + 1, kk] - tab[c, kk])
                da = (tab[c + 1, kk] - tab[c, kk]) / win.ds
                eta = y[o + kk]
                defl += a * eta
                dpar += da * eta
        delta = x - g - defl
        if delta <= 0.0:
            continue
        fs = k * delta
        if delta > dmax:
            dmax = delta
        for gear in range(2):
            tab = win.a1 if gear == 0 else win.a2
            o = (slot * 2 + gear) * m
            for kk in range(m):
                gen[o + kk] += (tab[c, kk] + u * (tab[c + 1, kk] - tab[c, kk])) * fs
        f = fs
        rec[0] += f
        f1 = (win.fillet1[c] + u * (win.fillet1[c + 1] - win.fillet1[c])) * f
        f2 = (win.fillet2[c] + u * (win.fillet2[c + 1] - win.fillet2[c])) * f
        if f1 > rec[1]:
            rec[1] = f1
        if f2 > rec[2]:
            rec[2] = f2
        rec[3] += 1.0
        rec[4] += sd * (0.5 * dk * delta * delta - k * delta * dpar)
        rec[6] += 0.5 * k * delta * delta
    if dmax > 0.0:
        # one mesh dashpot between the base circles while any pair touches (the lumped model's
        # c_m), growing over the first damping_onset of deflection: no force step at first touch;
        # it damps vibration, not the kinematic approach of a profile rolling through the mesh
        cm = win.c_mesh
        if dmax < win.damping_onset:
            cm *= dmax / win.damping_onset
        rec[0] += cm * xd
        rec[5] = cm * xd * xd


@inner(error_model="numpy")
def _rhs(t, y, dy, n_hi, chain, win, gen, rec):
    n = chain.jinv.shape[0]
    _pairs(y, n, n_hi, win, gen, rec)
    th, om = y[:n], y[n : 2 * n]
    chain_rhs(t, th, om, dy[:n], dy[n : 2 * n], chain, rec[0], win.ip, win.iw, win.rb1, win.rb2, win.iy1, win.iy2)
    m = win.n_modes
    nm2 = win.window * 2 * m
    base = 2 * n
    for slot in range(win.window):
        for gear in range(2):
            om_t = win.omega1 if gear == 0 else win.omega2
            o = (slot * 2 + gear) * m
            for kk in range(m):
                w = om_t[kk]
                eta = y[base + o + kk]
                deta = y[base + nm2 + o + kk]
                dy[base + o + kk] = deta
                dy[base + nm2 + o + kk] = gen[o + kk] - 2.0 * win.zeta * w * deta - w * w * eta
                rec[7] += 2.0 * win.zeta * w * deta * deta


@inner(error_model="numpy")
def _modal_energy(y, n_chain, win, slot):
    m = win.n_modes
    nm2 = win.window * 2 * m
    e = 0.0
    for gear in range(2):
        om_t = win.omega1 if gear == 0 else win.omega2
        o = 2 * n_chain + (slot * 2 + gear) * m
        for kk in range(m):
            e += 0.5 * (y[o + nm2 + kk] ** 2 + (om_t[kk] * y[o + kk]) ** 2)
    return e


@entry(error_model="numpy")
def run_window_rk4(y, n_hi0, t0, dt, n_steps, chain, win):
    """Advance ``n_steps`` RK4 steps of ``dt`` [s] from ``y`` (updated in place).

    The parametric work and the dissipated energy are integrated with the same RK4 stages as
    the state (an augmented ODE), so the energy balance converges with the solution.

    Returns
    -------
    (t, y_rec, rec, work, n_hi, dropped)
        Times (n_steps + 1), chain states, per-step records (total force [N], fillet stress
        maxima [Pa], pairs in contact, parametric power [W], mesh dissipation [W], contact
        potential [J], tooth modal energy [J]), cumulative parametric work and dissipated
        energy [J] (n_steps + 1, 2), the final newest pair and the modal energy dropped with
        teeth leaving the window [J].
    """
    n = chain.jinv.shape[0]
    size = y.shape[0]
    m = win.n_modes
    nm2 = win.window * 2 * m
    t_rec = np.empty(n_steps + 1)
    y_rec = np.empty((n_steps + 1, 2 * n))
    rec_out = np.empty((n_steps + 1, 7))
    work = np.zeros((n_steps + 1, 2))
    gen = np.empty(max(nm2, 1))
    rec = np.empty(8)
    k = np.empty((4, size))
    p = np.empty(4)
    d = np.empty(4)
    yt = np.empty(size)
    n_hi = n_hi0
    dropped = 0.0
    w_par = 0.0
    w_diss = 0.0
    t = t0
    for step in range(n_steps + 1):
        _rhs(t, y, k[0], n_hi, chain, win, gen, rec)
        t_rec[step] = t
        for i in range(2 * n):  # not ``y_rec[step, :] = ...``: see kernels.chain.run_rk4
            y_rec[step, i] = y[i]
        for i in range(6):
            rec_out[step, i] = rec[i]
        et = rec[6]
        for slot in range(win.window):
            et += _modal_energy(y, n, win, slot)
        rec_out[step, 6] = et
        work[step, 0] = w_par
        work[step, 1] = w_diss
        if step == n_steps:
            break
        # stage 1 is the record's RHS call above; stages 2-4 in a loop with one RHS call site
        p[0], d[0] = rec[4], rec[5] + rec[7]
        for s in range(3):
            ts = t + rk4_stage(s, y, k[s], dt, yt)
            _rhs(ts, yt, k[s + 1], n_hi, chain, win, gen, rec)
            p[s + 1], d[s + 1] = rec[4], rec[5] + rec[7]
        rk4_update(y, k[0], k[1], k[2], k[3], dt)
        w_par += dt / 6.0 * (p[0] + 2.0 * p[1] + 2.0 * p[2] + p[3])
        w_diss += dt / 6.0 * (d[0] + 2.0 * d[1] + 2.0 * d[2] + d[3])
        t = t0 + (step + 1) * dt
        # travel the window: pairs that have rolled past s_low + W pb free their slots
        u_roll = win.rb1 * y[win.ip] + win.s_start
        nh = int(math.floor((u_roll - win.s_low) / win.pb))
        while nh > n_hi:
            n_hi += 1
            slot = ((n_hi % win.window) + win.window) % win.window
            dropped += _modal_energy(y, n, win, slot)
            for gear in range(2):
                o = 2 * n + (slot * 2 + gear) * m
                for kk in range(m):
                    y[o + kk] = 0.0
                    y[o + nm2 + kk] = 0.0
    return t_rec, y_rec, rec_out, work, n_hi, dropped
