"""Compiled equations of Newton's iteration in a Lie-group generalized-alpha step of the 3-D exact beam.

The residual and the iteration matrix of :func:`rotaflex.floating.exact_solve3d.simulate_exact3d`
and ``simulate_hub3d`` (the iteration itself is ``exact_solve3d._newton``; ``_Equations.residual``
and ``_times_tangent`` there are the same formulas in numpy, kept as the tests' reference):

    r = M vd + [f_int - f_ext]  (translations),   W x J W + R^T (m_int - m_ext)  (rotations),
    A = M + gamma' C_gyro + beta' ((R^T K R + (R^T m)~) T),

``K`` the analytic static tangent (spatial spins, :func:`rotaflex.floating.exact_kernels3d.internal`
and the load stiffness of :func:`~rotaflex.floating.exact_kernels3d.external`), its rotation rows
and columns turned into section axes by the nodes' ``R``, ``T`` the right Jacobians of the
exponential map of the step's material rotation increments. Why compiled: in numpy the block
products, cross products and quaternion matrices of an iteration took about three times the
element kernels' time (the profile in docs/floating.md, 3-D cost).

Why two small kernels called from Python between the element kernels, not the whole Newton
iteration in one kernel: a kernel that calls the element kernels compiles their call tree again.
Measured (20 elements, the 2 s slew of ``benchmarks/bench_exact_beam_3d.py``, three alternating
pairs): the iteration in one kernel 2.2-2.6 ms per step against 2.6-3.0 ms here, for 17 s CPU
more at a cold start (13 s of them the element kernels again, 3.5 s numba's dense solve).
"""

from __future__ import annotations

import numpy as np

from rotaflex.core.compiled import entry
from rotaflex.floating.exact_kernels3d import _jr, _mtv
from rotaflex.floating.kernels import cross, quat_matrix


@entry
def dynamic_residual(q1, v1, vd1, M, jd, f, fe, free, r, m):
    """Equations of motion ``r`` (n,) at the state ``q1`` (7 per block), velocities ``v1`` and
    their rates ``vd1`` (6 per block, rotations material) from the internal ``f`` and external
    ``fe`` forces (spatial); ``M`` (n, n) the mass matrix, ``jd`` its diagonal; fills ``m``
    (nb, 3): the blocks' moments ``R^T (m_int - m_ext)`` in section axes. Returns the largest
    ``|r|`` on the DOFs ``free`` (int64 indices; 0 if none, NaN if one is NaN)."""
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
    # NaN if any is (as numpy's max): a diverged state must not pass the tolerance test
    res, bad = 0.0, False
    for i in range(free.shape[0]):
        a = abs(r[free[i]])
        if np.isnan(a):
            bad = True
        elif a > res:
            res = a
    return np.nan if bad else res


@entry
def iteration_matrix(q1, v1, dq, M, jd, K, m, gp, bp, rows, A):
    """``A = M + gp C_gyro + bp ((R^T K R + (R^T m)~) T)`` (n, n) at ``q1, v1`` for the step's
    increments ``dq`` (``gp``, ``bp``: gamma', beta' of the integrator; ``m`` from
    :func:`dynamic_residual`); ``K`` (the spatial tangent) is overwritten by the bracket.
    Only the rows and columns ``rows`` (int64, increasing) are written, into ``A`` (nr, nr):
    the free DOFs' block, or all."""
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
    # the gyroscopic blocks C = W~ J - (J W)~ on the rotation diagonal
    C = np.zeros((nb, 3, 3))
    for b in range(nb):
        c = 6 * b + 3
        w = v1[c : c + 3]
        J = jd[c : c + 3]
        jw = J * w
        C[b, 0, 1], C[b, 0, 2], C[b, 1, 2] = -w[2] * J[1] + jw[2], w[1] * J[2] - jw[1], -w[0] * J[2] + jw[0]
        C[b, 1, 0], C[b, 2, 0], C[b, 2, 1] = w[2] * J[0] - jw[2], -w[1] * J[0] + jw[1], w[0] * J[1] - jw[0]
    nr = rows.shape[0]
    for ii in range(nr):
        i = rows[ii]
        for jj in range(nr):
            j = rows[jj]
            if i // 6 == j // 6 and i % 6 >= 3 and j % 6 >= 3:
                A[ii, jj] = M[i, j] + gp * C[i // 6, i % 6 - 3, j % 6 - 3] + bp * K[i, j]
            else:
                A[ii, jj] = M[i, j] + bp * K[i, j]
