"""Compiled Newton iteration of one Lie-group generalized-alpha step of the 3-D exact beam.

The equations, the iteration matrix and the update are those of
:mod:`rotaflex.floating.exact_solve3d` (its ``_Equations.residual`` and ``_times_tangent`` are
the same formulas in numpy, kept as the reference the tests compare with):

    r = M vd + [f_int - f_ext]  (translations),   W x J W + R^T (m_int - m_ext)  (rotations),
    A = M + gamma' C_gyro + beta' ((R^T K R + (R^T m)~) T),

``K`` the analytic static tangent (spatial spins, :func:`rotaflex.floating.exact_kernels3d.internal`
and the load stiffness of :func:`~rotaflex.floating.exact_kernels3d.external`), its rotation rows
and columns turned into section axes by the nodes' ``R``, ``T`` the right Jacobians of the
exponential map of the step's material rotation increments. Why compiled: in numpy the block
products, cross products and quaternion matrices of one iteration cost about nine times the
element kernel (docs/floating.md, 3-D cost).

DOF layout as :mod:`~rotaflex.floating.exact_kernels3d`: state 7 per block, increments 6 per
block (rotations material in the time step).
"""

from __future__ import annotations

import numpy as np

from rotaflex.core.compiled import entry, inner
from rotaflex.floating.exact_kernels3d import _jr, _mtv, advance_material, external, internal
from rotaflex.floating.kernels import cross, quat_matrix


@inner
def _dynamic_residual(q1, v1, vd1, M, jd, f, fe, r, m):
    """Equations of motion ``r`` (n,) from the internal ``f`` and external ``fe`` forces
    (spatial); ``m`` (nb, 3): the blocks' moments ``R^T (m_int - m_ext)`` in section axes."""
    n = r.shape[0]
    for i in range(n):
        s = 0.0
        for j in range(n):
            s += M[i, j] * vd1[j]
        r[i] = s
    g = np.zeros(3)
    for b in range(n // 6):
        o = 6 * b
        for k in range(3):
            r[o + k] += f[o + k] - fe[o + k]
            g[k] = f[o + 3 + k] - fe[o + 3 + k]
        mb = _mtv(quat_matrix(q1[7 * b + 3 : 7 * b + 7]), g)
        w = v1[o + 3 : o + 6]
        gyro = cross(w, jd[o + 3 : o + 6] * w)
        for k in range(3):
            m[b, k] = mb[k]
            r[o + 3 + k] += gyro[k] + mb[k]


@inner
def _iteration_matrix(q1, v1, dq, M, jd, K, m, gp, bp, A):
    """``A = M + gp C_gyro + bp ((R^T K R + (R^T m)~) T)`` (n, n); ``K`` (spatial tangent) is
    overwritten by the bracket."""
    n = K.shape[0]
    nb = n // 6
    x = np.zeros(3)
    for b in range(nb):  # columns: K R_b on the rotation columns
        R = quat_matrix(q1[7 * b + 3 : 7 * b + 7])
        c = 6 * b + 3
        for i in range(n):
            for k in range(3):
                x[k] = K[i, c + k]
            for col in range(3):
                K[i, c + col] = x[0] * R[0, col] + x[1] * R[1, col] + x[2] * R[2, col]
        for j in range(n):  # rows: R_b^T K on the rotation rows
            for k in range(3):
                x[k] = K[c + k, j]
            for row in range(3):
                K[c + row, j] = R[0, row] * x[0] + R[1, row] * x[1] + R[2, row] * x[2]
    for b in range(nb):
        c = 6 * b + 3
        # (R^T m)~: d(R^T m) / dTheta at fixed m
        K[c, c + 1] -= m[b, 2]
        K[c, c + 2] += m[b, 1]
        K[c + 1, c] += m[b, 2]
        K[c + 1, c + 2] -= m[b, 0]
        K[c + 2, c] -= m[b, 1]
        K[c + 2, c + 1] += m[b, 0]
        # times the tangent operator: the rotation columns times Jr(dTheta_b)
        T = _jr(dq[c : c + 3])
        for i in range(n):
            for k in range(3):
                x[k] = K[i, c + k]
            for col in range(3):
                K[i, c + col] = x[0] * T[0, col] + x[1] * T[1, col] + x[2] * T[2, col]
    for i in range(n):
        for j in range(n):
            A[i, j] = M[i, j] + bp * K[i, j]
    for b in range(nb):
        c = 6 * b + 3
        w = v1[c : c + 3]
        J = jd[c : c + 3]
        jw = J * w
        # C = W~ J - (J W)~
        C = np.zeros((3, 3))
        C[0, 1], C[0, 2], C[1, 2] = -w[2] * J[1] + jw[2], w[1] * J[2] - jw[1], -w[0] * J[2] + jw[0]
        C[1, 0], C[2, 0], C[2, 1] = w[2] * J[0] - jw[2], -w[1] * J[0] + jw[1], w[0] * J[1] - jw[0]
        for i in range(3):
            for j in range(3):
                A[c + i, c + j] = M[c + i, c + j] + gp * C[i, j] + bp * K[c + i, c + j]


@entry
def equations(q1, v1, vd1, dq, M, jd, beam, loads, lam, coef, want_k, r, A):
    """Residual ``r`` (n,) of the equations of motion at ``q1, v1, vd1`` and, with ``want_k``,
    the iteration matrix ``A`` (n, n) for the step's increments ``dq`` (the hub solver's use).

    ``beam``: ``(conn, L0, gam0, kap0, stiff)``; ``loads``: ``(node, kind, frame, amp, ref_block,
    dist)`` (:func:`rotaflex.floating.exact_kernels3d.internal`, ``external``); ``lam`` the
    load factors; ``coef``: ``(eta [s], kv, gamma', beta')``."""
    conn, L0, gam0, kap0, stiff = beam
    node, kind, frame, amp, ref_block, dist = loads
    eta, kv, gp, bp = coef
    n = r.shape[0]
    f, fe = np.zeros(n), np.zeros(n)
    K = np.zeros((n, n)) if want_k else np.zeros((1, 1))
    internal(q1, v1, conn, L0, gam0, kap0, stiff, eta, kv, f, K, 1 if want_k else 0)
    external(q1, lam, node, kind, frame, amp, ref_block, dist, fe, K, want_k)
    m = np.zeros((n // 6, 3))
    _dynamic_residual(q1, v1, vd1, M, jd, f, fe, r, m)
    if want_k:
        _iteration_matrix(q1, v1, dq, M, jd, K, m, gp, bp, A)


@entry
def newton_step(q, q1, dq, v1, vd1, a1, free, M, jd, beam, loads, lam, coef, r):
    """Newton's iteration of one Lie-group generalized-alpha step (prescribed frame): from the
    predictor ``dq, v1, vd1, a1`` (the eliminated DOFs already imposed) to the converged step,
    all updated in place, ``q1 = q (+) dq``, ``r`` the final residual (its eliminated rows: the
    clamps' reaction).

    ``free`` (nf,) int64 unknown DOFs; ``beam``, ``loads``, ``lam`` as :func:`equations`;
    ``coef``: ``(eta, kv, gamma', beta', (1 - af) / (1 - am), force tolerance [N], position step
    tolerance [m], max_iter)``. Converged when, from the second iteration, the largest free
    residual is within the force tolerance or the last correction of the positions within the
    step tolerance. Returns ``(converged, iterations, residual)``."""
    conn, L0, gam0, kap0, stiff = beam
    node, kind, frame, amp, ref_block, dist = loads
    eta, kv, gp, bp, c, tol, step_tol, max_iter = coef
    n, nf = q.shape[0] // 7 * 6, free.shape[0]
    f, fe = np.zeros(n), np.zeros(n)
    K, A, Af, rhs = np.zeros((n, n)), np.zeros((n, n)), np.zeros((nf, nf)), np.zeros(nf)
    m = np.zeros((n // 6, 3))
    step = np.inf
    res = np.inf
    for it in range(1, int(max_iter) + 1):
        advance_material(q1, q, dq)
        # the residual alone first: the tangent only when another iteration follows
        internal(q1, v1, conn, L0, gam0, kap0, stiff, eta, kv, f, K, 0)
        external(q1, lam, node, kind, frame, amp, ref_block, dist, fe, K, False)
        _dynamic_residual(q1, v1, vd1, M, jd, f, fe, r, m)
        res = 0.0
        for i in range(nf):
            res = max(res, abs(r[free[i]]))
        if not np.isfinite(res):
            return False, it, res
        if it > 1 and (res <= tol or step <= step_tol):
            return True, it, res
        internal(q1, v1, conn, L0, gam0, kap0, stiff, eta, kv, f, K, 1)
        external(q1, lam, node, kind, frame, amp, ref_block, dist, fe, K, True)
        _iteration_matrix(q1, v1, dq, M, jd, K, m, gp, bp, A)
        for i in range(nf):
            rhs[i] = -r[free[i]]
            for j in range(nf):
                Af[i, j] = A[free[i], free[j]]
        d = np.linalg.solve(Af, rhs)
        step = 0.0
        for i in range(nf):
            k = free[i]
            vd1[k] += d[i]
            a1[k] += c * d[i]
            v1[k] += gp * d[i]
            dq[k] += bp * d[i]
            step = max(step, abs(d[i]))
        step *= bp
    return False, int(max_iter), res
