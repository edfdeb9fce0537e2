"""Compiled kernels: load profiles, the three right-hand sides and a Dormand-Prince integrator.

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
"""

from __future__ import annotations

import numpy as np
from numba import njit

# load kinds / frames / profiles (keep in step with loads.py)
FORCE, TORQUE = 0, 1
BODY, INERTIAL = 0, 1
PROFILES = ("constant", "step", "ramp", "bang-bang", "sinusoid", "pulse")


@njit(cache=True)
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


@njit(cache=True)
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


@njit(cache=True)
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


@njit(cache=True)
def quat_rate(e, w, out):
    """``de/dt = 1/2 e (x) (0, w)`` with body rates ``w`` (written into ``out[0:4]``)."""
    out[0] = 0.5 * (-e[1] * w[0] - e[2] * w[1] - e[3] * w[2])
    out[1] = 0.5 * (e[0] * w[0] + e[2] * w[2] - e[3] * w[1])
    out[2] = 0.5 * (e[0] * w[1] + e[3] * w[0] - e[1] * w[2])
    out[3] = 0.5 * (e[0] * w[2] + e[1] * w[1] - e[2] * w[0])


@njit(cache=True)
def cross(a, b):
    return np.array(
        [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
    )


@njit(cache=True)
def skew3(a):
    S = np.zeros((3, 3))
    S[0, 1], S[0, 2] = -a[2], a[1]
    S[1, 0], S[1, 2] = a[2], -a[0]
    S[2, 0], S[2, 1] = -a[1], a[0]
    return S


# ----------------------------------------------------------------------------------------
# loads
# ----------------------------------------------------------------------------------------
@njit(cache=True)
def loads_full(t, A, q, L):
    """Generalised forces ``H = [F_v, M_w, Q]`` (body frame) of all loads, full model."""
    kind, frame, prof, par, amp, rP, PhiP, PsiP = L
    n = q.shape[0]
    H = np.zeros(6 + n)
    for i in range(kind.shape[0]):
        s = profile_value(prof[i], par[i], t)
        if s == 0.0:
            continue
        v = s * amp[i]
        if frame[i] == INERTIAL:
            v = A.T @ v
        if kind[i] == FORCE:
            c = rP[i] + PhiP[i] @ q
            mo = cross(c, v)
            for a in range(3):
                H[a] += v[a]
                H[3 + a] += mo[a]
            H[6:] += PhiP[i].T @ v
        else:
            for a in range(3):
                H[3 + a] += v[a]
            H[6:] += PsiP[i].T @ v
    return H


@njit(cache=True)
def loads_perturbation(t, A0, th1, q1, L):
    """Zero-order rigid loads ``H0`` (6) and first-order loads ``H1`` (6 + n)."""
    kind, frame, prof, par, amp, rP, PhiP, PsiP = L
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
            v0 = A0.T @ v0
            v1 = cross(v0, th1)  # (I - th1~) v0 - v0
        if kind[i] == FORCE:
            m0 = cross(rP[i], v0)
            m1 = cross(rP[i], v1) + cross(PhiP[i] @ q1, v0)
            for a in range(3):
                H0[a] += v0[a]
                H0[3 + a] += m0[a]
                H1[a] += v1[a]
                H1[3 + a] += m1[a]
            H1[6:] += PhiP[i].T @ v0
        else:
            for a in range(3):
                H0[3 + a] += v0[a]
                H1[3 + a] += v1[a]
            H1[6:] += PsiP[i].T @ v0
    return H0, H1


# ----------------------------------------------------------------------------------------
# right-hand sides
# ----------------------------------------------------------------------------------------
@njit(cache=True, inline="always")
def cr(a0, a1, a2, b0, b1, b2):
    return a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0


@njit(cache=True, inline="always")
def mv(Phi, k, q):
    """``Phi[k] @ q`` as a tuple of three floats (no allocation)."""
    s0 = 0.0
    s1 = 0.0
    s2 = 0.0
    for j in range(q.shape[0]):
        s0 += Phi[k, 0, j] * q[j]
        s1 += Phi[k, 1, j] * q[j]
        s2 += Phi[k, 2, j] * q[j]
    return s0, s1, s2


@njit(cache=True, inline="always")
def sub_phit(f, off, mk, Phi, k, b0, b1, b2):
    """``f[off:] -= mk Phi[k]^T b``."""
    for j in range(Phi.shape[2]):
        f[off + j] -= mk * (Phi[k, 0, j] * b0 + Phi[k, 1, j] * b1 + Phi[k, 2, j] * b2)


@njit(cache=True)
def mass_matrix(q, B):
    """Full mass matrix ``M(q)`` of eq. 22 by quadrature over the body points."""
    m, r, Phi, Phibar, Mb, Kb, KGw, Minv0, Mrinv, S0, J0, mtot, Je = B
    n = q.shape[0]
    M = np.zeros((6 + n, 6 + n))
    S = np.zeros(3)
    J = Je.copy()
    Pt = np.zeros((3, n))
    for k in range(m.shape[0]):
        u0, u1, u2 = mv(Phi, k, q)
        c0, c1, c2 = r[k, 0] + u0, r[k, 1] + u1, r[k, 2] + u2
        mk = m[k]
        S[0] += mk * c0
        S[1] += mk * c1
        S[2] += mk * c2
        cc = c0 * c0 + c1 * c1 + c2 * c2
        J[0, 0] += mk * (cc - c0 * c0)
        J[1, 1] += mk * (cc - c1 * c1)
        J[2, 2] += mk * (cc - c2 * c2)
        J[0, 1] -= mk * c0 * c1
        J[0, 2] -= mk * c0 * c2
        J[1, 2] -= mk * c1 * c2
        for j in range(n):  # Phi~ = sum m c~ Phi
            Pt[0, j] += mk * (c1 * Phi[k, 2, j] - c2 * Phi[k, 1, j])
            Pt[1, j] += mk * (c2 * Phi[k, 0, j] - c0 * Phi[k, 2, j])
            Pt[2, j] += mk * (c0 * Phi[k, 1, j] - c1 * Phi[k, 0, j])
    J[1, 0], J[2, 0], J[2, 1] = J[0, 1], J[0, 2], J[1, 2]
    St = skew3(S)
    for a in range(3):
        M[a, a] = mtot
    M[0:3, 3:6] = -St
    M[3:6, 0:3] = St
    M[3:6, 3:6] = J
    M[0:3, 6:] = Phibar
    M[6:, 0:3] = Phibar.T
    M[3:6, 6:] = Pt
    M[6:, 3:6] = Pt.T
    M[6:, 6:] = Mb
    return M


@njit(cache=True)
def rhs_full(t, y, B, L, geo):
    m, r, Phi, Phibar, Mb, Kb, KGw, Minv0, Mrinv, S0, J0, mtot, Je = B
    n = Kb.shape[0]
    dy = np.empty_like(y)
    e = y[3:7]
    V = y[7:10]
    w = y[10:13]
    q = y[13 : 13 + n]
    p = y[13 + n :]
    A = quat_matrix(e)
    dy[0:3] = A @ V
    quat_rate(e, w, dy[3:7])
    f = loads_full(t, A, q, L)
    f[6:] -= Kb @ q
    sg = 0.0
    if geo:
        # foreshortening term of the Lagrangian: L_G = -1/2 (w_y^2 + w_z^2) q^T K_Gw q; it adds
        # the stiffness to the q rows and J_G = -s diag(0, 1, 1) (s = q^T K_Gw q) to the w rows
        kq = KGw @ q
        sg = q @ kq
        f[6:] -= (w[1] * w[1] + w[2] * w[2]) * kq
        sd = 2.0 * (p @ kq)
        f[4] += sd * w[1] - sg * w[0] * w[2]
        f[5] += sd * w[2] + sg * w[0] * w[1]
    f[3:6] -= cross(w, Je @ w)
    x0, x1, x2 = w[0], w[1], w[2]
    wv0, wv1, wv2 = cr(x0, x1, x2, V[0], V[1], V[2])
    for k in range(m.shape[0]):
        mk = m[k]
        u0, u1, u2 = mv(Phi, k, q)
        d0, d1, d2 = mv(Phi, k, p)
        c0, c1, c2 = r[k, 0] + u0, r[k, 1] + u1, r[k, 2] + u2
        a0, a1, a2 = cr(x0, x1, x2, c0, c1, c2)
        a0, a1, a2 = cr(x0, x1, x2, a0, a1, a2)
        g0, g1, g2 = cr(x0, x1, x2, d0, d1, d2)
        b0 = wv0 + a0 + 2.0 * g0
        b1 = wv1 + a1 + 2.0 * g1
        b2 = wv2 + a2 + 2.0 * g2
        h0, h1, h2 = cr(c0, c1, c2, b0, b1, b2)
        f[0] -= mk * b0
        f[1] -= mk * b1
        f[2] -= mk * b2
        f[3] -= mk * h0
        f[4] -= mk * h1
        f[5] -= mk * h2
        sub_phit(f, 6, mk, Phi, k, b0, b1, b2)
    M = mass_matrix(q, B)
    M[4, 4] -= sg
    M[5, 5] -= sg
    xd = np.linalg.solve(M, f)
    dy[7:13] = xd[0:6]
    dy[13 : 13 + n] = p
    dy[13 + n :] = xd[6:]
    return dy


@njit(cache=True)
def zero_order_accel(t, y, B, L):
    """Zero-order rigid accelerations ``(Vdot0, wdot0)`` of eq. 27 and the load split."""
    m, r, Phi, Phibar, Mb, Kb, KGw, Minv0, Mrinv, S0, J0, mtot, Je = B
    n = Kb.shape[0]
    A0 = quat_matrix(y[3:7])
    V0, w0 = y[7:10], y[10:13]
    th1 = y[16:19]
    q1 = y[25 : 25 + n]
    H0, H1 = loads_perturbation(t, A0, th1, q1, L)
    Jw = J0 @ w0
    g = np.zeros(6)
    wV = cross(w0, V0)
    wwS = cross(w0, cross(w0, S0))
    g[0:3] = mtot * wV + wwS
    g[3:6] = cross(S0, wV) + cross(w0, Jw)
    acc = Mrinv @ (H0 - g)
    return acc, A0, H1


@njit(cache=True)
def rhs_perturbation(t, y, B, L, geo):
    m, r, Phi, Phibar, Mb, Kb, KGw, Minv0, Mrinv, S0, J0, mtot, Je = B
    n = Kb.shape[0]
    dy = np.empty_like(y)
    V0, w0 = y[7:10], y[10:13]
    th1, V1, w1 = y[16:19], y[19:22], y[22:25]
    q1, p1 = y[25 : 25 + n], y[25 + n :]
    acc, A0, H1 = zero_order_accel(t, y, B, L)
    dy[0:3] = A0 @ V0
    quat_rate(y[3:7], w0, dy[3:7])
    dy[7:13] = acc
    # first order: f = H1 + d - (linear velocity/stiffness terms); d_3 = -sum m Phi^T a0_k
    f = H1.copy()
    f[6:] -= Kb @ q1
    if geo:
        f[6:] -= (w0[1] * w0[1] + w0[2] * w0[2]) * (KGw @ q1)
    f[3:6] -= cross(w1, Je @ w0) + cross(w0, Je @ w1)
    o0, o1, o2 = w0[0], w0[1], w0[2]
    s0, s1, s2 = w1[0], w1[1], w1[2]
    al0, al1, al2 = acc[3], acc[4], acc[5]
    t0, t1, t2 = cr(o0, o1, o2, V0[0], V0[1], V0[2])
    base0, base1, base2 = t0 + acc[0], t1 + acc[1], t2 + acc[2]
    a_, b_, c_ = cr(s0, s1, s2, V0[0], V0[1], V0[2])
    d_, e_, f_ = cr(o0, o1, o2, V1[0], V1[1], V1[2])
    g00, g01, g02 = a_ + d_, b_ + e_, c_ + f_
    for k in range(m.shape[0]):
        mk = m[k]
        r0, r1, r2 = r[k, 0], r[k, 1], r[k, 2]
        u0, u1, u2 = mv(Phi, k, q1)
        v0, v1, v2 = mv(Phi, k, p1)
        # a0 = Vd0 + w0 x V0 + wd0 x r + w0 x (w0 x r)
        x0, x1, x2 = cr(al0, al1, al2, r0, r1, r2)
        wr0, wr1, wr2 = cr(o0, o1, o2, r0, r1, r2)
        y0_, y1_, y2_ = cr(o0, o1, o2, wr0, wr1, wr2)
        a00, a01, a02 = base0 + x0 + y0_, base1 + x1 + y1_, base2 + x2 + y2_
        # g = w1 x V0 + w0 x V1 + wd0 x u + w1 x (w0 x r) + w0 x (w1 x r) + w0 x (w0 x u) + 2 w0 x v
        h0, h1, h2 = cr(al0, al1, al2, u0, u1, u2)
        i0, i1, i2 = cr(s0, s1, s2, wr0, wr1, wr2)
        j0, j1, j2 = cr(s0, s1, s2, r0, r1, r2)
        j0, j1, j2 = cr(o0, o1, o2, j0, j1, j2)
        k0, k1, k2 = cr(o0, o1, o2, u0, u1, u2)
        k0, k1, k2 = cr(o0, o1, o2, k0, k1, k2)
        l0, l1, l2 = cr(o0, o1, o2, v0, v1, v2)
        gg0 = g00 + h0 + i0 + j0 + k0 + 2.0 * l0
        gg1 = g01 + h1 + i1 + j1 + k1 + 2.0 * l1
        gg2 = g02 + h2 + i2 + j2 + k2 + 2.0 * l2
        p0_, p1_, p2_ = cr(r0, r1, r2, gg0, gg1, gg2)
        q0_, q1_, q2_ = cr(u0, u1, u2, a00, a01, a02)
        f[0] -= mk * gg0
        f[1] -= mk * gg1
        f[2] -= mk * gg2
        f[3] -= mk * (p0_ + q0_)
        f[4] -= mk * (p1_ + q1_)
        f[5] -= mk * (p2_ + q2_)
        sub_phit(f, 6, mk, Phi, k, gg0 + a00, gg1 + a01, gg2 + a02)
    xd = Minv0 @ f
    dy[13:16] = A0 @ (V1 + cross(th1, V0))
    dy[16:19] = w1 - cross(w0, th1)
    dy[19:25] = xd[0:6]
    dy[25 : 25 + n] = p1
    dy[25 + n :] = xd[6:]
    return dy


@njit(cache=True)
def rhs_prescribed(t, y, B, L, geo, axis, rate, t_up):
    m, r, Phi, Phibar, Mb, Kb, KGw, Minv0, Mrinv, S0, J0, mtot, Je = B
    n = Kb.shape[0]
    q, p = y[0:n], y[n:]
    _, om, al = spin_profile(rate, t_up, t)
    x0, x1, x2 = om * axis[0], om * axis[1], om * axis[2]
    z0, z1, z2 = al * axis[0], al * axis[1], al * axis[2]
    A = np.eye(3)
    f = np.zeros(6 + n)
    f[6:] = loads_full(t, A, q, L)[6:] - Kb @ q
    if geo:
        f[6:] -= (x1 * x1 + x2 * x2) * (KGw @ q)
    for k in range(m.shape[0]):
        u0, u1, u2 = mv(Phi, k, q)
        d0, d1, d2 = mv(Phi, k, p)
        c0, c1, c2 = r[k, 0] + u0, r[k, 1] + u1, r[k, 2] + u2
        a0, a1, a2 = cr(z0, z1, z2, c0, c1, c2)
        b0, b1, b2 = cr(x0, x1, x2, c0, c1, c2)
        b0, b1, b2 = cr(x0, x1, x2, b0, b1, b2)
        g0, g1, g2 = cr(x0, x1, x2, d0, d1, d2)
        sub_phit(f, 6, m[k], Phi, k, a0 + b0 + 2.0 * g0, a1 + b1 + 2.0 * g1, a2 + b2 + 2.0 * g2)
    dy = np.empty_like(y)
    dy[0:n] = p
    dy[n:] = np.linalg.solve(Mb, f[6:])
    return dy


@njit(cache=True)
def rhs(mode, t, y, B, L, geo, pres):
    if mode == 0:
        return rhs_full(t, y, B, L, geo)
    if mode == 1:
        return rhs_perturbation(t, y, B, L, geo)
    return rhs_prescribed(t, y, B, L, geo, pres[0:3], pres[3], pres[4])


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


@njit(cache=True)
def integrate(
    mode, y0, t_out, breaks, rtol, atol, max_steps, limit, n_lim0, n_lim1, B, L, geo, pres
):
    """Integrate ``rhs(mode, ...)`` from ``t_out[0]``; return states at ``t_out``.

    Returns ``(Y, status, t_stop, nfev, nstep)``; status 0 ok, 1 step budget exhausted,
    2 step size underflow / non-finite state, 3 ``|y[n_lim0:n_lim1]|`` exceeded ``limit``
    (divergence guard). Rows after a failure are NaN.
    """
    nt = t_out.shape[0]
    ny = y0.shape[0]
    Y = np.full((nt, ny), np.nan)
    Y[0] = y0
    y = y0.copy()
    t = t_out[0]
    K = np.zeros((7, ny))
    K[0] = rhs(mode, t, y, B, L, geo, pres)
    nfev = 1
    span = t_out[-1] - t_out[0]
    h = 1e-4 * span
    nstep = 0
    i_out = 1
    i_brk = 0
    while i_brk < breaks.shape[0] and breaks[i_brk] <= t:
        i_brk += 1
    status = 0
    while i_out < nt:
        t_target = t_out[i_out]
        if i_brk < breaks.shape[0] and breaks[i_brk] < t_target:
            t_target = breaks[i_brk]
        hit = False
        if t + h >= t_target - 1e-12 * span:
            h_try = t_target - t
            hit = True
        else:
            h_try = h
        for s in range(1, 7):
            ys = y.copy()
            for j in range(s):
                if _A[s, j] != 0.0:
                    ys += h_try * _A[s, j] * K[j]
            ts = t + _C[s] * h_try
            if hit and _C[s] == 1.0:
                ts = t_target - 1e-13 * span  # stay left of a load jump at t_target
            K[s] = rhs(mode, ts, ys, B, L, geo, pres)
        nfev += 6
        y_new = ys  # stage 7 evaluates at the 5th-order solution (FSAL)
        err = np.zeros(ny)
        for j in range(7):
            if _E[j] != 0.0:
                err += _E[j] * K[j]
        err *= h_try
        sc = atol + rtol * np.maximum(np.abs(y), np.abs(y_new))
        en = np.sqrt(np.mean((err / sc) ** 2))
        if not np.isfinite(en):
            en = 1e10
        nstep += 1
        if en <= 1.0:
            t = t_target if hit else t + h_try
            y = y_new
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
                    K[0] = rhs(mode, t, y, B, L, geo, pres)  # restart after a load jump
                    nfev += 1
                while i_out < nt and abs(t - t_out[i_out]) <= 1e-12 * span:
                    Y[i_out] = y
                    i_out += 1
                while i_brk < breaks.shape[0] and breaks[i_brk] <= t + 1e-12 * span:
                    i_brk += 1
            if n_lim1 > n_lim0 and np.max(np.abs(y[n_lim0:n_lim1])) > limit:
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
    return Y, status, t, nfev, nstep
