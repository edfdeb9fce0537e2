"""Compiled kernels: load profiles and the right-hand sides (integrator: :mod:`.integrator`).

Everything here is numba-compiled (``cache=True``) and works on plain arrays. The body enters as
point data (quadrature points of mass ``m_k`` at body position ``r_k`` with mode shapes
``Phi_k`` (3 x n)); every body integral of the paper (eq. 23, 25, 32) is a sum over these points.

Right-hand sides (``mode``):

* 0 -- full nonlinear hybrid equations (eq. 5, 7-9) written in Kane's form
  ``sum_k m_k L_k^T a_k + K q = H`` with ``L_k = [I, -c_k~, Phi_k]``, ``c_k = r_k + Phi_k q``.
  State ``[R, e, V, w, q, p]``.
* 1 -- perturbation method: zero-order rigid equations (eq. 27, 29-30) and first-order linear
  time-varying equations (eq. 31, 35-37) integrated together. State
  ``[R0, e0, V0, w0, R1, th1, V1, w1, q1, p1]``.
* 2 -- elastic equations under a prescribed rigid rotation about a body-fixed axis through the
  body origin (Kane-Ryan-Banerjee spin-up). State ``[q, p]``. With linear modal kinematics this
  equation is linear in ``q``, so the full and the first-order equations coincide here.
* 3 -- the same prescribed motion with the exact inextensible kinematics of a planar cantilever
  (:mod:`rotaflex.floating.inextensible`). State ``[q, p]``.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from rotaflex.core.compiled import entry, inner

# load kinds / frames / profiles (keep in step with loads.py)
FORCE, TORQUE = 0, 1
BODY, INERTIAL, MATERIAL = 0, 1, 2
PROFILES = ("constant", "step", "ramp", "bang-bang", "sinusoid", "pulse")


@inner
def profile_value(kind, p, t):
    """Scalar time profile ``s(t)``; ``p = (start, duration, frequency [Hz], phase [rad])``."""
    t0, dur = p[0], p[1]
    if kind == 0:
        return 1.0
    if kind == 1:
        return 1.0 if t >= t0 else 0.0
    if kind == 2:
        if t < t0:
            return 0.0
        if t >= t0 + dur:
            return 1.0
        return (t - t0) / dur
    if kind == 3:
        if t < t0 or t >= t0 + dur:
            return 0.0
        return 1.0 if t < t0 + 0.5 * dur else -1.0
    if kind == 4:
        if t < t0 or (dur > 0.0 and t >= t0 + dur):
            return 0.0
        return np.sin(2.0 * np.pi * p[2] * (t - t0) + p[3])
    if kind == 5:
        return 1.0 if (t >= t0 and t < t0 + dur) else 0.0
    return 0.0


@inner
def spin_profile(rate, t_up, t):
    """Kane-Ryan-Banerjee spin-up: angle, rate and acceleration at time ``t``."""
    if t < t_up:
        c = 2.0 * np.pi / t_up
        ang = rate / t_up * (0.5 * t * t + (np.cos(c * t) - 1.0) / (c * c))
        om = rate / t_up * (t - np.sin(c * t) / c)
        al = rate / t_up * (1.0 - np.cos(c * t))
        return ang, om, al
    ang_up = rate / t_up * (0.5 * t_up * t_up)
    return ang_up + rate * (t - t_up), rate, 0.0


#: prescribed motion profiles (``pres[5]``; keep in step with model.Prescribed.profile)
MOTIONS = ("spin-up", "bang-bang", "versine")


@entry
def motion_profile(pres, t):
    """Angle [rad], rate [rad/s] and acceleration [rad/s^2] of the prescribed rotation.

    ``pres = (axis (3), a, b, kind, start)``: kind 0 Kane-Ryan-Banerjee spin-up to rate ``a`` in
    ``b`` seconds (:func:`spin_profile`); kind 1 rest-to-rest bang-bang slew by angle ``a`` in
    ``b`` seconds from ``start`` (constant acceleration ``4 a / b^2``, then the same
    deceleration); kind 2 versine (cycloidal) slew ``a (s - sin(2 pi s) / (2 pi))``, ``s = (t -
    start) / b``, whose acceleration is a full sine period (no jumps)."""
    kind = pres[5]
    if kind == 0.0:
        return spin_profile(pres[3], pres[4], t)
    ang, dur = pres[3], pres[4]
    tau = t - pres[6]
    if tau <= 0.0:
        return 0.0, 0.0, 0.0
    if tau >= dur:
        return ang, 0.0, 0.0
    if kind == 1.0:
        acc = 4.0 * ang / (dur * dur)
        if tau < 0.5 * dur:
            return 0.5 * acc * tau * tau, acc * tau, acc
        r = dur - tau
        return ang - 0.5 * acc * r * r, acc * r, -acc
    c = 2.0 * np.pi / dur
    return (
        ang * (tau / dur - np.sin(c * tau) / (2.0 * np.pi)),
        ang / dur * (1.0 - np.cos(c * tau)),
        ang * c / dur * np.sin(c * tau),
    )


@inner
def quat_matrix(e):
    """Active rotation matrix ``R = I + 2 e0 e~ + 2 e~ e~`` of a (normalised) quaternion."""
    n = np.sqrt(e[0] ** 2 + e[1] ** 2 + e[2] ** 2 + e[3] ** 2)
    e0, e1, e2, e3 = e[0] / n, e[1] / n, e[2] / n, e[3] / n
    A = np.empty((3, 3))
    A[0, 0] = 1.0 - 2.0 * (e2 * e2 + e3 * e3)
    A[0, 1] = 2.0 * (e1 * e2 - e0 * e3)
    A[0, 2] = 2.0 * (e1 * e3 + e0 * e2)
    A[1, 0] = 2.0 * (e1 * e2 + e0 * e3)
    A[1, 1] = 1.0 - 2.0 * (e1 * e1 + e3 * e3)
    A[1, 2] = 2.0 * (e2 * e3 - e0 * e1)
    A[2, 0] = 2.0 * (e1 * e3 - e0 * e2)
    A[2, 1] = 2.0 * (e2 * e3 + e0 * e1)
    A[2, 2] = 1.0 - 2.0 * (e1 * e1 + e2 * e2)
    return A


@inner
def quat_rate(e, w, out):
    """``de/dt = 1/2 e (x) (0, w)`` with body rates ``w`` (written into ``out[0:4]``)."""
    out[0] = 0.5 * (-e[1] * w[0] - e[2] * w[1] - e[3] * w[2])
    out[1] = 0.5 * (e[0] * w[0] + e[2] * w[2] - e[3] * w[1])
    out[2] = 0.5 * (e[0] * w[1] + e[3] * w[0] - e[1] * w[2])
    out[3] = 0.5 * (e[0] * w[2] + e[1] * w[1] - e[2] * w[0])


@inner
def cross(a, b):
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


@inner
def skew3(a):
    S = np.zeros((3, 3))
    S[0, 1], S[0, 2] = -a[2], a[1]
    S[1, 0], S[1, 2] = a[2], -a[0]
    S[2, 0], S[2, 1] = -a[1], a[0]
    return S


# ----------------------------------------------------------------------------------------
# small allocation-free helpers (also valid for n = 0 modes)
# ----------------------------------------------------------------------------------------
@njit(cache=True, inline="always", no_cpython_wrapper=True, no_cfunc_wrapper=True)
def cr(a0, a1, a2, b0, b1, b2):
    return a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0


@inner
def mvec(A, x):
    """``A @ x`` by loops (avoids a BLAS call per small product)."""
    out = np.zeros(A.shape[0])
    for i in range(A.shape[0]):
        s = 0.0
        for j in range(A.shape[1]):
            s += A[i, j] * x[j]
        out[i] = s
    return out


@inner
def mtvec(A, x):
    """``A.T @ x`` by loops."""
    out = np.zeros(A.shape[1])
    for j in range(A.shape[0]):
        xj = x[j]
        for i in range(A.shape[1]):
            out[i] += A[j, i] * xj
    return out


@inner
def outer3(a, b):
    out = np.empty((3, 3))
    for i in range(3):
        for j in range(3):
            out[i, j] = a[i] * b[j]
    return out


@inner
def phi_dot(Ph, q):
    """``Ph @ q`` for ``Ph`` (3, n) as a new (3,) array (loops: n may be 0)."""
    out = np.zeros(3)
    for a in range(3):
        s = 0.0
        for j in range(q.shape[0]):
            s += Ph[a, j] * q[j]
        out[a] = s
    return out


@inner
def sub_phiT(f, off, Ph, v):
    """``f[off:] -= Ph^T v`` for ``Ph`` (3, n)."""
    for j in range(Ph.shape[1]):
        f[off + j] -= Ph[0, j] * v[0] + Ph[1, j] * v[1] + Ph[2, j] * v[2]


@inner
def sub_mat_scaled(f, off, K, c, q):
    """``f[off:] -= c K q``."""
    n = q.shape[0]
    for i in range(n):
        s = 0.0
        for j in range(n):
            s += K[i, j] * q[j]
        f[off + i] -= c * s


@inner
def sub_mat(f, off, K, q):
    """``f[off:] -= K q``."""
    n = q.shape[0]
    for i in range(n):
        s = 0.0
        for j in range(n):
            s += K[i, j] * q[j]
        f[off + i] -= s


@inner
def sub_damping(f, off, cd, p):
    """``f[off:] -= cd * p``: modal viscous damping ``2 zeta_i omega_i p_i`` (``cd`` empty: none)."""
    for i in range(cd.shape[0]):
        f[off + i] -= cd[i] * p[i]


@inner
def contract(T, x, out):
    """``out[a, b, i] = sum_j T[a, b, i, j] x[j]`` (T: (3, 3, n, n))."""
    n = x.shape[0]
    for a in range(3):
        for b in range(3):
            for i in range(n):
                s = 0.0
                for j in range(n):
                    s += T[a, b, i, j] * x[j]
                out[a, b, i] = s


@inner
def contract3(R1, x, out):
    """``out[a, b] = sum_j R1[a, b, j] x[j]``."""
    for a in range(3):
        for b in range(3):
            s = 0.0
            for j in range(x.shape[0]):
                s += R1[a, b, j] * x[j]
            out[a, b] = s


@inner
def sub_weighted(f, off, W, T):
    """``f[off + j] -= sum_ab W[a, b] T[a, b, j]``."""
    for a in range(3):
        for b in range(3):
            wab = W[a, b]
            if wab != 0.0:
                for j in range(T.shape[2]):
                    f[off + j] -= wab * T[a, b, j]


@inner
def phi_cross(Pq, out):
    """``out[:, j] = sum m (u x Phi_j)`` from ``Pq[a, b, j] = sum m Phi_aj u_b``."""
    for j in range(Pq.shape[2]):
        out[0, j] = Pq[2, 1, j] - Pq[1, 2, j]
        out[1, j] = Pq[0, 2, j] - Pq[2, 0, j]
        out[2, j] = Pq[1, 0, j] - Pq[0, 1, j]


@inner
def geometric_terms(G, gnz, w, q, p, f, off, Smat, Sdot):
    """Centrifugal stiffening ``K_G(w) = sum_ab w_a w_b G_ab``: ``f[off:] -= K_G(w) q``;
    ``Smat[a, b] = q^T G_ab q`` and ``Sdot[a, b] = 2 p^T G_ab q`` (for the w rows)."""
    n = q.shape[0]
    for a in range(3):
        for b in range(3):
            Smat[a, b] = 0.0
            Sdot[a, b] = 0.0
            if gnz[a, b] == 0:
                continue
            ww = w[a] * w[b]
            for i in range(n):
                s = 0.0
                for j in range(n):
                    s += G[a, b, i, j] * q[j]
                f[off + i] -= ww * s
                Smat[a, b] += q[i] * s
                Sdot[a, b] += 2.0 * p[i] * s


# ----------------------------------------------------------------------------------------
# loads
# ----------------------------------------------------------------------------------------
@inner
def loads_full(t, A, q, L):
    """Generalised forces ``H = [F_v, M_w, Q]`` (body frame) of all loads, full model."""
    kind, frame, prof, par, amp, rP, PhiP, PsiP, GL, gln = L
    n = q.shape[0]
    H = np.zeros(6 + n)
    for i in range(kind.shape[0]):
        s = profile_value(prof[i], par[i], t)
        if s == 0.0:
            continue
        v = s * amp[i]
        if frame[i] == INERTIAL:
            v = mtvec(A, v)
        elif frame[i] == MATERIAL:  # turned by the small section rotation psi = Psi_P q
            v = v + cross(phi_dot(PsiP[i], q), v)
        if kind[i] == FORCE:
            c = rP[i] + phi_dot(PhiP[i], q)
            mo = cross(c, v)
            for a in range(3):
                H[a] += v[a]
                H[3 + a] += mo[a]
            sub_phiT(H, 6, PhiP[i], -v)
            # geometric stiffening from this load's axial load state (zero if switched off)
            for a in range(3):
                if v[a] != 0.0 and gln[i, a]:
                    sub_mat_scaled(H, 6, GL[i, a], v[a], q)
        else:
            for a in range(3):
                H[3 + a] += v[a]
            sub_phiT(H, 6, PsiP[i], -v)
    return H


@inner
def loads_perturbation(t, A0, th1, q1, L):
    """Zero-order rigid loads ``H0`` (6) and first-order loads ``H1`` (6 + n)."""
    kind, frame, prof, par, amp, rP, PhiP, PsiP, GL, gln = L
    n = q1.shape[0]
    H0 = np.zeros(6)
    H1 = np.zeros(6 + n)
    for i in range(kind.shape[0]):
        s = profile_value(prof[i], par[i], t)
        if s == 0.0:
            continue
        v0 = s * amp[i]
        v1 = np.zeros(3)
        if frame[i] == INERTIAL:
            v0 = mtvec(A0, v0)
            v1 = cross(v0, th1)  # (I - th1~) v0 - v0
        elif frame[i] == MATERIAL:
            v1 = cross(phi_dot(PsiP[i], q1), v0)
        if kind[i] == FORCE:
            m0 = cross(rP[i], v0)
            m1 = cross(rP[i], v1) + cross(phi_dot(PhiP[i], q1), v0)
            for a in range(3):
                H0[a] += v0[a]
                H0[3 + a] += m0[a]
                H1[a] += v1[a]
                H1[3 + a] += m1[a]
            sub_phiT(H1, 6, PhiP[i], -v0)
            for a in range(3):  # first order: zero-order load state times q1
                if v0[a] != 0.0 and gln[i, a]:
                    sub_mat_scaled(H1, 6, GL[i, a], v0[a], q1)
        else:
            for a in range(3):
                H0[3 + a] += v0[a]
                H1[3 + a] += v1[a]
            sub_phiT(H1, 6, PsiP[i], -v0)
    return H0, H1


# ----------------------------------------------------------------------------------------
# right-hand sides, written with body-integral tensors (no loop over quadrature points):
#   P[a, b, i, j] = sum m Phi_ai Phi_bj,  R1[a, b, j] = sum m Phi_aj r_b,
# so that with u = Phi q:  sum m u_a r_b = R1 . q,  sum m Phi_aj u_b = (P . q)[a, b, j].
# ----------------------------------------------------------------------------------------
@inner
def solve_lu(M, f):
    """``M x = f`` by LU; NaN where ``M`` or ``f`` is not finite (a trial state far out of range,
    which the integrator rejects), instead of an exception from inside the compiled loop."""
    if not (np.all(np.isfinite(M)) and np.all(np.isfinite(f))):
        return np.full(f.shape[0], np.nan)
    return np.linalg.solve(M, f)


@inner
def solve_spd(M, f):
    """Solve ``M x = f`` for a symmetric positive definite ``M`` (Cholesky, in place on copies)."""
    n = M.shape[0]
    Lc = M.copy()
    x = f.copy()
    for j in range(n):
        s = Lc[j, j]
        for k in range(j):
            s -= Lc[j, k] * Lc[j, k]
        if not s > 0.0:
            return solve_lu(M, f)  # not SPD (far outside the model's range): LU
        d = np.sqrt(s)
        Lc[j, j] = d
        for i in range(j + 1, n):
            s = Lc[i, j]
            for k in range(j):
                s -= Lc[i, k] * Lc[j, k]
            Lc[i, j] = s / d
    for i in range(n):
        s = x[i]
        for k in range(i):
            s -= Lc[i, k] * x[k]
        x[i] = s / Lc[i, i]
    for i in range(n - 1, -1, -1):
        s = x[i]
        for k in range(i + 1, n):
            s -= Lc[k, i] * x[k]
        x[i] = s / Lc[i, i]
    return x


@inner
def rhs_full(t, y, B, L, geo):
    mtot, S0, J0, Phibar, Pt0, Mb, Kb, P, R1, G, gnz, Minv0, Mrinv, cd = B
    n = Kb.shape[0]
    dy = np.empty_like(y)
    e = y[3:7]
    V = y[7:10]
    w = y[10:13]
    q = y[13 : 13 + n]
    p = y[13 + n :]
    A = quat_matrix(e)
    dy[0:3] = mvec(A, V)
    quat_rate(e, w, dy[3:7])
    f = loads_full(t, A, q, L)
    sub_mat(f, 6, Kb, q)
    sub_damping(f, 6, cd, p)
    Pq = np.empty((3, 3, n))
    Pp = np.empty((3, 3, n))
    contract(P, q, Pq)
    contract(P, p, Pp)
    U1 = np.empty((3, 3))
    D = np.empty((3, 3))
    contract3(R1, q, U1)  # sum m u_a r_b
    contract3(R1, p, D)  # sum m udot_a r_b
    UU = np.zeros((3, 3))
    for a in range(3):
        for b in range(3):
            s = 0.0
            s2 = 0.0
            for i in range(n):
                s += q[i] * Pq[a, b, i]  # sum m u_a u_b
                s2 += p[i] * Pq[a, b, i]  # sum m udot_a u_b
            UU[a, b] = s
            D[a, b] += s2  # D = sum m udot c^T
    S = S0 + phi_dot(Phibar, q)
    tr1 = U1[0, 0] + U1[1, 1] + U1[2, 2]
    tr2 = UU[0, 0] + UU[1, 1] + UU[2, 2]
    J = J0 - U1 - U1.T - UU
    for a in range(3):
        J[a, a] += 2.0 * tr1 + tr2
    Pt = Pt0.copy()
    X = np.empty((3, n))
    phi_cross(Pq, X)
    Pt += X
    # velocity-dependent terms: sum m L^T b with b = w x V + w x (w x c) + 2 w x udot
    wV = cross(w, V)
    ud = phi_dot(Phibar, p)
    fv = mtot * wV + cross(w, cross(w, S)) + 2.0 * cross(w, ud)
    trD = D[0, 0] + D[1, 1] + D[2, 2]
    fw = cross(S, wV) + cross(w, mvec(J, w)) + 2.0 * (trD * w - mvec(D, w))
    for a in range(3):
        f[a] -= fv[a]
        f[3 + a] -= fw[a]
    sub_phiT(f, 6, Phibar, wV)
    W = outer3(w, w)
    ww = w[0] * w[0] + w[1] * w[1] + w[2] * w[2]
    for a in range(3):
        W[a, a] -= ww
    sub_weighted(f, 6, W, R1)
    sub_weighted(f, 6, W, Pq)
    Wt = skew3(2.0 * w)
    sub_weighted(f, 6, Wt, Pp)
    M = np.zeros((6 + n, 6 + n))
    if geo:
        # foreshortening term of the Lagrangian: L_G = -1/2 q^T K_G(w) q = -1/2 w^T S(q) w adds
        # the stiffness to the q rows and the inertia change -S(q) to the w rows
        Smat = np.empty((3, 3))
        Sdot = np.empty((3, 3))
        geometric_terms(G, gnz, w, q, p, f, 6, Smat, Sdot)
        gw = mvec(Sdot, w) + cross(w, mvec(Smat, w))
        for a in range(3):
            f[3 + a] += gw[a]
            for b in range(3):
                M[3 + a, 3 + b] -= Smat[a, b]
    St = skew3(S)
    for a in range(3):
        M[a, a] = mtot
        for b in range(3):
            M[a, 3 + b] = -St[a, b]
            M[3 + a, b] = St[a, b]
            M[3 + a, 3 + b] += J[a, b]
        for j in range(n):
            M[a, 6 + j] = Phibar[a, j]
            M[6 + j, a] = Phibar[a, j]
            M[3 + a, 6 + j] = Pt[a, j]
            M[6 + j, 3 + a] = Pt[a, j]
    for i in range(n):
        for j in range(n):
            M[6 + i, 6 + j] = Mb[i, j]
    xd = solve_spd(M, f)
    dy[7:13] = xd[0:6]
    dy[13 : 13 + n] = p
    dy[13 + n :] = xd[6:]
    return dy


@inner
def zero_order_accel(t, y, B, L):
    """Zero-order rigid accelerations ``(Vdot0, wdot0)`` of eq. 27 and the load split."""
    mtot, S0, J0, Phibar, Pt0, Mb, Kb, P, R1, G, gnz, Minv0, Mrinv, cd = B
    n = Kb.shape[0]
    A0 = quat_matrix(y[3:7])
    V0, w0 = y[7:10], y[10:13]
    th1 = y[16:19]
    q1 = y[25 : 25 + n]
    H0, H1 = loads_perturbation(t, A0, th1, q1, L)
    Jw = mvec(J0, w0)
    g = np.zeros(6)
    wV = cross(w0, V0)
    wwS = cross(w0, cross(w0, S0))
    g[0:3] = mtot * wV + wwS
    g[3:6] = cross(S0, wV) + cross(w0, Jw)
    acc = mvec(Mrinv, H0 - g)
    return acc, A0, H1


@inner
def rhs_perturbation(t, y, B, L, geo):
    """Zero order + exact linearisation of :func:`rhs_full` about ``(x0(t), q = p = 0)``."""
    mtot, S0, J0, Phibar, Pt0, Mb, Kb, P, R1, G, gnz, Minv0, Mrinv, cd = B
    n = Kb.shape[0]
    dy = np.empty_like(y)
    V0, w0 = y[7:10], y[10:13]
    th1, V1, w1 = y[16:19], y[19:22], y[22:25]
    q1, p1 = y[25 : 25 + n], y[25 + n :]
    acc, A0, H1 = zero_order_accel(t, y, B, L)
    Vd0, wd0 = acc[0:3], acc[3:6]
    dy[0:3] = mvec(A0, V0)
    quat_rate(y[3:7], w0, dy[3:7])
    dy[7:13] = acc
    f = H1.copy()
    sub_mat(f, 6, Kb, q1)
    sub_damping(f, 6, cd, p1)
    Pq = np.empty((3, 3, n))
    Pp = np.empty((3, 3, n))
    contract(P, q1, Pq)
    contract(P, p1, Pp)
    U1 = np.empty((3, 3))
    dD = np.empty((3, 3))
    contract3(R1, q1, U1)
    contract3(R1, p1, dD)
    dJ = -U1 - U1.T
    tr1 = U1[0, 0] + U1[1, 1] + U1[2, 2]
    for a in range(3):
        dJ[a, a] += 2.0 * tr1
    dS = phi_dot(Phibar, q1)
    ud = phi_dot(Phibar, p1)
    wV0 = cross(w0, V0)
    dwV = cross(w1, V0) + cross(w0, V1)
    # rigid rows: linearised velocity terms and the mass-matrix change times the zero-order accel.
    fv = (
        mtot * dwV
        + cross(w1, cross(w0, S0))
        + cross(w0, cross(w1, S0))
        + cross(w0, cross(w0, dS))
        + 2.0 * cross(w0, ud)
        + cross(wd0, dS)
    )
    trD = dD[0, 0] + dD[1, 1] + dD[2, 2]
    fw = (
        cross(dS, wV0)
        + cross(S0, dwV)
        + cross(w1, mvec(J0, w0))
        + cross(w0, mvec(J0, w1))
        + cross(w0, mvec(dJ, w0))
        + 2.0 * (trD * w0 - mvec(dD, w0))
        + cross(dS, Vd0)
        + mvec(dJ, wd0)
    )
    for a in range(3):
        f[a] -= fv[a]
        f[3 + a] -= fw[a]
    # elastic rows: first-order terms and the rigid maneuver's inertial load d (eq. 28)
    W0 = outer3(w0, w0)
    dW = outer3(w1, w0) + outer3(w0, w1)
    ww = w0[0] * w0[0] + w0[1] * w0[1] + w0[2] * w0[2]
    w01 = w0[0] * w1[0] + w0[1] * w1[1] + w0[2] * w1[2]
    for a in range(3):
        W0[a, a] -= ww
        dW[a, a] -= 2.0 * w01
    sub_phiT(f, 6, Phibar, dwV + Vd0 + wV0)
    sub_phiT(f, 6, Pt0, wd0)
    X = np.empty((3, n))
    phi_cross(Pq, X)
    sub_phiT(f, 6, X, wd0)
    sub_weighted(f, 6, W0 + dW, R1)
    sub_weighted(f, 6, W0, Pq)
    sub_weighted(f, 6, skew3(2.0 * w0), Pp)
    if geo:
        Smat = np.empty((3, 3))
        Sdot = np.empty((3, 3))
        geometric_terms(G, gnz, w0, q1, p1, f, 6, Smat, Sdot)
    xd = mvec(Minv0, f)
    dy[13:16] = mvec(A0, (V1 + cross(th1, V0)))
    dy[16:19] = w1 - cross(w0, th1)
    dy[19:25] = xd[0:6]
    dy[25 : 25 + n] = p1
    dy[25 + n :] = xd[6:]
    return dy


@inner
def rhs_prescribed(t, y, B, L, geo, pres):
    mtot, S0, J0, Phibar, Pt0, Mb, Kb, P, R1, G, gnz, Minv0, Mrinv, cd = B
    n = Kb.shape[0]
    q, p = y[0:n], y[n:]
    axis = pres[0:3]
    _, om, al = motion_profile(pres, t)
    w = om * axis
    f = loads_full(t, np.eye(3), q, L)
    sub_mat(f, 6, Kb, q)
    sub_damping(f, 6, cd, p)
    if geo:
        Smat = np.empty((3, 3))
        Sdot = np.empty((3, 3))
        geometric_terms(G, gnz, w, q, p, f, 6, Smat, Sdot)
    Pq = np.empty((3, 3, n))
    Pp = np.empty((3, 3, n))
    contract(P, q, Pq)
    contract(P, p, Pp)
    # sum m Phi^T (alpha x c + w x (w x c) + 2 w x udot)
    W = skew3(al * axis) + outer3(w, w)
    ww = w[0] * w[0] + w[1] * w[1] + w[2] * w[2]
    for a in range(3):
        W[a, a] -= ww
    sub_weighted(f, 6, W, R1)
    sub_weighted(f, 6, W, Pq)
    sub_weighted(f, 6, skew3(2.0 * w), Pp)
    dy = np.empty_like(y)
    dy[0:n] = p
    dy[n:] = solve_lu(Mb, f[6:])
    return dy


@inner
def rhs_inextensible(t, y, kin, pres):
    """Prescribed frame motion with the exact inextensible kinematics of a planar cantilever
    (:mod:`rotaflex.floating.inextensible`): ``M(q) qddot = -K(q) - sum m J^T c``, where
    ``J = Phi + e_x du/dq`` and ``c = alpha x r + w x (w x r) + 2 w x J p + e_x p^T u_qq p``.
    A slope ``|v'| >= 1`` has no inextensible curve: the state is returned as NaN, which the
    integrator reports as a failure."""
    m, X, Phi, Dp, wp, pend, D1, D2, wq, ei = kin
    n = Phi.shape[2]
    q, p = y[0:n], y[n:]
    axis = pres[0:3]
    _, om, al = motion_profile(pres, t)
    w = om * axis
    W = skew3(al * axis) + outer3(w, w)
    ww = w[0] * w[0] + w[1] * w[1] + w[2] * w[2]
    for a in range(3):
        W[a, a] -= ww
    dy = np.empty_like(y)
    dy[0:n] = p
    # cumulative shortening u, its gradient g = du/dq and h = p^T (d2u/dq2) p along the panels
    npan = Dp.shape[0]
    cu = np.zeros(npan + 1)
    cg = np.zeros((npan + 1, n))
    ch = np.zeros(npan + 1)
    slope = Dp @ q
    slope_rate = Dp @ p
    bend_slope = D1 @ q
    if not (np.max(np.abs(slope)) < 1.0 and np.max(np.abs(bend_slope)) < 1.0):
        dy[n:] = np.nan  # folded (or non-finite): no inextensible curve has this deflection
        return dy
    for k in range(npan):
        s1 = slope[k]
        sp = slope_rate[k]
        c2 = 1.0 - s1 * s1
        c = np.sqrt(c2)
        cu[k + 1] = cu[k] + wp[k] * (c - 1.0)
        f1 = -wp[k] * s1 / c
        for i in range(n):
            cg[k + 1, i] = cg[k, i] + f1 * Dp[k, i]
        ch[k + 1] = ch[k] - wp[k] * sp * sp / (c2 * c)
    M = np.zeros((n, n))
    f = np.zeros(n)
    J = np.empty((3, n))
    r = np.empty(3)
    Jp = np.empty(3)
    for k in range(m.shape[0]):
        e = pend[k]
        for a in range(3):
            acc = X[k, a]
            accp = 0.0
            for i in range(n):
                J[a, i] = Phi[k, a, i]
                acc += Phi[k, a, i] * q[i]
                accp += Phi[k, a, i] * p[i]
            r[a] = acc
            Jp[a] = accp
        r[0] += cu[e]
        for i in range(n):
            J[0, i] += cg[e, i]
            Jp[0] += cg[e, i] * p[i]
        c0 = W[0, 0] * r[0] + W[0, 1] * r[1] + W[0, 2] * r[2] + 2.0 * (w[1] * Jp[2] - w[2] * Jp[1]) + ch[e]
        c1 = W[1, 0] * r[0] + W[1, 1] * r[1] + W[1, 2] * r[2] + 2.0 * (w[2] * Jp[0] - w[0] * Jp[2])
        c2_ = W[2, 0] * r[0] + W[2, 1] * r[1] + W[2, 2] * r[2] + 2.0 * (w[0] * Jp[1] - w[1] * Jp[0])
        mk = m[k]
        for i in range(n):
            f[i] -= mk * (J[0, i] * c0 + J[1, i] * c1 + J[2, i] * c2_)
            for j in range(n):
                M[i, j] += mk * (J[0, i] * J[0, j] + J[1, i] * J[1, j] + J[2, i] * J[2, j])
    # exact bending: U = EI/2 int v''^2 / (1 - v'^2)
    curvature = D2 @ q
    for k in range(wq.shape[0]):
        v1 = bend_slope[k]
        v2 = curvature[k]
        c2 = 1.0 - v1 * v1
        a2 = ei[0] * wq[k] * v2 / c2
        a1 = ei[0] * wq[k] * v2 * v2 * v1 / (c2 * c2)
        for i in range(n):
            f[i] -= a2 * D2[k, i] + a1 * D1[k, i]
    dy[n:] = solve_lu(M, f)
    return dy


# ----------------------------------------------------------------------------------------
# right-hand sides callable from Python (equation checks, linearisation); the integrator loops
# call the @inner kernels above, so a run compiles no Python wrapper for them (whose unboxing
# of the body and load tuples was a good part of the first-run compilation)
# ----------------------------------------------------------------------------------------
@entry
def rhs_full_py(t, y, B, L, geo):
    """:func:`rhs_full` for calls from Python."""
    return rhs_full(t, y, B, L, geo)


@entry
def rhs_perturbation_py(t, y, B, L, geo):
    """:func:`rhs_perturbation` for calls from Python."""
    return rhs_perturbation(t, y, B, L, geo)
