"""Compiled Dormand-Prince 5(4) integrator of the floating-body right-hand sides.

Attitude from the state and Euler 1-2-3 angles unwrapped after every accepted step (never from
output samples), step control landing on output times and load breakpoints, divergence guard.
Each right-hand side of :mod:`rotaflex.floating.kernels` (``mode`` 0 full, 1 perturbation, 2
prescribed, 3 inextensible) has its own compiled loop (:data:`LOOPS`), chosen once per run in
Python: a run compiles only the loop and right-hand side it uses, and no evaluation branches on
the mode. A run can be advanced in chunks (progress output) with the same steps as in one call.
"""

from __future__ import annotations

import numpy as np

from rotaflex.core.compiled import entry, inner
from rotaflex.floating.kernels import (
    motion_profile,
    quat_matrix,
    rhs_full,
    rhs_inextensible,
    rhs_perturbation,
    rhs_prescribed,
)

# ----------------------------------------------------------------------------------------
# attitude from the state, and Euler 1-2-3 angles unwrapped step by step (never from samples)
# ----------------------------------------------------------------------------------------
#: largest attitude change [rad] accepted in one integrator step, so that the per-step Euler
#: unwrapping below is unambiguous whatever rtol and dt_out are
MAX_STEP_ROTATION = 0.5


@inner
def attitude_zero_order(mode, t, y, pres):
    """Unit quaternion (scalar first) of the rigid part of state ``y`` at time ``t``: the
    prescribed rotation (``mode`` >= 2), else the normalised ``y[3:7]`` (the attitude of the full
    method, the zero-order attitude ``e0`` of the perturbation method)."""
    e = np.empty(4)
    if mode >= 2:
        ang = motion_profile(pres, t)[0]
        e[0] = np.cos(0.5 * ang)
        for i in range(3):
            e[i + 1] = np.sin(0.5 * ang) * pres[i]
        return e
    n = np.sqrt(y[3] ** 2 + y[4] ** 2 + y[5] ** 2 + y[6] ** 2)
    e[0], e[1], e[2], e[3] = y[3] / n, y[4] / n, y[5] / n, y[6] / n
    return e


@inner
def attitude(mode, t, y, pres):
    """Unit attitude quaternion (scalar first) of state ``y`` at time ``t`` (two functions, not
    a flag: numba compiled one specialisation per literal flag value)."""
    e0 = attitude_zero_order(mode, t, y, pres)
    if mode != 1:
        return e0
    # perturbation: e0 (x) exp(theta_1)
    a0, a1, a2, a3 = e0[0], e0[1], e0[2], e0[3]
    t1, t2, t3 = y[16], y[17], y[18]
    ang = np.sqrt(t1 * t1 + t2 * t2 + t3 * t3)
    c = np.cos(0.5 * ang)
    sc = 0.5 if ang < 1e-8 else np.sin(0.5 * ang) / ang
    b0, b1, b2, b3 = c, sc * t1, sc * t2, sc * t3
    e = np.empty(4)
    e[0] = a0 * b0 - a1 * b1 - a2 * b2 - a3 * b3
    e[1] = a0 * b1 + b0 * a1 + a2 * b3 - a3 * b2
    e[2] = a0 * b2 + b0 * a2 + a3 * b1 - a1 * b3
    e[3] = a0 * b3 + b0 * a3 + a1 * b2 - a2 * b1
    return e


@inner
def euler123(e, prev, out):
    """Euler 1-2-3 angles (``R = Rx(a) Ry(b) Rz(c)``) of ``e`` on the branch nearest ``prev``."""
    A = quat_matrix(e)
    s = min(1.0, max(-1.0, A[0, 2]))
    raw0 = np.arctan2(-A[1, 2], A[2, 2])
    raw1 = np.arcsin(s)
    raw2 = np.arctan2(-A[0, 1], A[0, 0])
    tau = 2.0 * np.pi
    out[0] = raw0 + tau * np.round((prev[0] - raw0) / tau)
    out[1] = raw1 + tau * np.round((prev[1] - raw1) / tau)
    out[2] = raw2 + tau * np.round((prev[2] - raw2) / tau)


@inner
def step_rotation(ea, eb):
    """Rotation angle [rad] between unit quaternions ``ea`` and ``eb``."""
    d = abs(ea[0] * eb[0] + ea[1] * eb[1] + ea[2] * eb[2] + ea[3] * eb[3])
    return 2.0 * np.arccos(min(1.0, d))


# ----------------------------------------------------------------------------------------
# Dormand-Prince 5(4) with step control, landing on output times and load breakpoints
# ----------------------------------------------------------------------------------------
_C = np.array([0.0, 1 / 5, 3 / 10, 4 / 5, 8 / 9, 1.0, 1.0])
_A = np.array(
    [
        [0, 0, 0, 0, 0, 0],
        [1 / 5, 0, 0, 0, 0, 0],
        [3 / 40, 9 / 40, 0, 0, 0, 0],
        [44 / 45, -56 / 15, 32 / 9, 0, 0, 0],
        [19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729, 0, 0],
        [9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656, 0],
        [35 / 384, 0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84],
    ]
)
_B = np.array([35 / 384, 0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84, 0])
_E = np.array([71 / 57600, 0, -71 / 16695, 71 / 1920, -17253 / 339200, 22 / 525, -1 / 40])


def _make_integrate(mode: int):
    """The compiled Dormand-Prince loop over the right-hand side of ``mode``.

    One loop per right-hand side, specialised at compile time (no branch on the mode and no
    unused argument arrays on any evaluation): 0 :func:`rhs_full`, 1 :func:`rhs_perturbation`, 2
    :func:`rhs_prescribed` (``B`` = body tensors, ``L`` = loads), 3 :func:`rhs_inextensible`
    (``B`` = the inextensible-kinematics arrays; ``L`` and ``geo`` unused). The choice is made by
    bool closure constants (so the loop is cached on disk, and numba removes the branches on them
    before typing: only the chosen right-hand side is compiled). Each loop has its own name, so
    its cache index is its own and :func:`rotaflex.core.jit.cache_is_cold` sees whether *this*
    loop is compiled. A loop compiles when a run first calls it.
    """
    full, pert, presc = mode == 0, mode == 1, mode == 2

    def run(
        mode, t_out, i_end, Y, EUL, y, K0, att, cnt, hs, breaks, rtol, atol, max_steps, limit, n_lim, B, L, geo, pres
    ):
        """Advance from output row ``cnt[2] - 1`` until row ``i_end`` is written (or a stop).

        State carried between calls (updated in place, so a run in chunks is identical to one
        call): ``y`` state, ``K0`` the first stage (FSAL), ``att`` = (previous attitude quaternion,
        Euler angles, zero-order Euler angles), ``cnt`` = (nfev, nstep, i_out, i_brk), ``hs`` =
        (step size, time, 2 before the first call / 1 while ``K0`` is to be evaluated / 0). Rows
        ``Y``/``EUL`` are written as they are reached. Returns the status: 0 ok, 1 step budget
        exhausted, 2 step size underflow / non-finite state, 3 ``|y[n_lim[0]:n_lim[1]]|`` exceeded
        ``limit`` (divergence guard).
        """
        nt = t_out.shape[0]
        ny = y.shape[0]
        if hs[2] == 2.0:  # first call: row 0's Euler angles (the first stage follows below)
            att[0:4] = attitude(mode, hs[1], y, pres)
            eul, eul0 = np.zeros(3), np.zeros(3)
            euler123(att[0:4], eul, eul)
            euler123(attitude_zero_order(mode, hs[1], y, pres), eul0, eul0)
            att[4:7], att[7:10] = eul, eul0
            EUL[0, :3], EUL[0, 3:] = eul, eul0
            hs[2] = 1.0
        K = np.zeros((7, ny))
        K[0] = K0
        e_prev = att[0:4].copy()
        eul = att[4:7].copy()
        eul0 = att[7:10].copy()
        nfev, nstep, i_out, i_brk = cnt[0], cnt[1], cnt[2], cnt[3]
        h, t = hs[0], hs[1]
        pending = hs[2] != 0.0
        span = t_out[-1] - t_out[0]
        status = 0
        while i_out < min(i_end, nt):
            t_target = t_out[i_out]
            if i_brk < breaks.shape[0] and breaks[i_brk] < t_target:
                t_target = breaks[i_brk]
            hit = False
            if t + h >= t_target - 1e-12 * span:
                h_try = t_target - t
                hit = True
            else:
                h_try = h
            ys = np.empty(ny)
            # stage 0 is K0 (FSAL) unless it is pending (first step, restart after a load
            # jump): then evaluated here, so the right-hand side has one call site in the loop
            for s in range(0 if pending else 1, 7):
                for i in range(ny):
                    acc = y[i]
                    for j in range(s):
                        acc += h_try * _A[s, j] * K[j, i]
                    ys[i] = acc
                ts = t + _C[s] * h_try
                if hit and _C[s] == 1.0:
                    ts = t_target - 1e-13 * span  # stay left of a load jump at t_target
                if full:
                    K[s] = rhs_full(ts, ys, B, L, geo)
                elif pert:
                    K[s] = rhs_perturbation(ts, ys, B, L, geo)
                elif presc:
                    K[s] = rhs_prescribed(ts, ys, B, L, geo, pres)
                else:
                    K[s] = rhs_inextensible(ts, ys, B, pres)
            nfev += 7 if pending else 6
            pending = False
            y_new = ys  # stage 7 evaluates at the 5th-order solution (FSAL)
            en = 0.0
            for i in range(ny):
                er = 0.0
                for j in range(7):
                    er += _E[j] * K[j, i]
                sc = atol + rtol * max(abs(y[i]), abs(y_new[i]))
                en += (h_try * er / sc) ** 2
            en = np.sqrt(en / ny)
            if not np.isfinite(en):
                en = 1e10
            e_new = attitude(mode, t + h_try, y_new, pres)
            rot = step_rotation(e_prev, e_new)
            if not rot <= MAX_STEP_ROTATION:
                en = max(en, 2.0)
            nstep += 1
            if en <= 1.0:
                e_prev = e_new
                euler123(e_new, eul, eul)
                if mode == 1:  # zero-order attitude; it turns by less than the total per step
                    euler123(attitude_zero_order(mode, t + h_try, y_new, pres), eul0, eul0)
                else:
                    eul0[:] = eul
                t = t_target if hit else t + h_try
                y[:] = y_new
                K[0] = K[6]
                fac = 0.9 * en ** (-0.2) if en > 0 else 5.0
                if fac > 5.0:
                    fac = 5.0
                if not hit:
                    h = h_try * fac
                elif fac > 1.0:
                    h = max(h, h_try * fac)
                if hit:
                    if i_brk < breaks.shape[0] and abs(t - breaks[i_brk]) <= 1e-12 * span:
                        i_brk += 1
                        pending = True  # restart after a load jump: K0 at (t, y) next step
                    while i_out < nt and abs(t - t_out[i_out]) <= 1e-12 * span:
                        Y[i_out] = y
                        EUL[i_out, :3], EUL[i_out, 3:] = eul, eul0
                        i_out += 1
                    while i_brk < breaks.shape[0] and breaks[i_brk] <= t + 1e-12 * span:
                        i_brk += 1
                if n_lim[1] > n_lim[0] and np.max(np.abs(y[n_lim[0] : n_lim[1]])) > limit:
                    status = 3
                    break
            else:
                fac = 0.9 * en ** (-0.2)
                if fac < 0.2:
                    fac = 0.2
                h = h_try * fac
                if h < 1e-14 * span:
                    status = 2
                    break
            if nstep >= max_steps:
                status = 1
                break
        K0[:] = K[0]
        att[0:4], att[4:7], att[7:10] = e_prev, eul, eul0
        cnt[0], cnt[1], cnt[2], cnt[3] = nfev, nstep, i_out, i_brk
        hs[0], hs[1], hs[2] = h, t, 1.0 if pending else 0.0
        return status

    run.__name__ = run.__qualname__ = f"integrate_{MODES[mode]}"
    return entry(run)


#: right-hand sides by mode (the integrator's ``mode`` argument)
MODES = ("full", "perturbation", "prescribed", "inextensible")
#: the compiled loop of each mode; a run calls exactly one of them
LOOPS = tuple(_make_integrate(m) for m in range(len(MODES)))
#: the compiled right-hand side of each mode
RHS = (rhs_full, rhs_perturbation, rhs_prescribed, rhs_inextensible)


def kernels(mode: int) -> list:
    """The numba dispatchers a run of ``mode`` calls first (for the compile announcement)."""
    return [LOOPS[mode], RHS[mode]]


def start(y0, t_out, breaks):
    """Initial carried state of :func:`_make_integrate`'s loop: ``(Y, EUL, y, K0, att, cnt, hs)``
    with row 0 of ``Y`` written. The loop's first call writes row 0 of ``EUL`` and evaluates the
    first stage ``K0`` (``hs[2] == 2``), so the right-hand sides and attitude helpers are called
    only from compiled code and need no Python wrapper."""
    nt, ny = t_out.shape[0], y0.shape[0]
    Y = np.full((nt, ny), np.nan)
    EUL = np.full((nt, 6), np.nan)
    Y[0] = y0
    t = float(t_out[0])
    i_brk = int(np.searchsorted(breaks, t, side="right"))
    cnt = np.array([0, 0, 1, i_brk], dtype=np.int64)
    hs = np.array([1e-4 * (t_out[-1] - t_out[0]), t, 2.0])
    return Y, EUL, y0.astype(float).copy(), np.zeros(ny), np.zeros(10), cnt, hs
