"""Compiled kernels of the planar geometrically exact (Reissner) beam.

Kinematics (Reissner 1972; Simo & Vu-Quoc 1986, planar case): every node carries its inertial
position ``(x, y)`` [m] and the inertial angle ``theta`` [rad] of its cross-section. An element
from node ``a`` to node ``b`` with reference length ``L0`` interpolates all three linearly and
is integrated with one point (its middle), which removes shear locking of the linear element
(reduced integration). At that point, with ``t = (cos th, sin th)``, ``n = (-sin th, cos th)``,
``th = (th_a + th_b) / 2`` and ``x' = (x_b - x_a) / L0``, the exact strains are

    eps = x' . t - 1 (axial),   gam = x' . n (shear),   kap = (th_b - th_a) / L0 - kap0,

the section forces ``N = EA (eps + eta eps')``, ``Q = GA (gam + eta gam')``,
``M = EI (kap + eta kap')`` (``eta`` [s]: Kelvin-Voigt material damping, 0 for an elastic beam)
and the strain energy ``L0 / 2 (EA eps^2 + GA gam^2 + EI kap^2)``.

DOF vector ``q``: the nodes' ``(x, y, theta)`` one after the other, then any extra DOFs (the
hub's ``(X, Y, phi)``). Matrices are dense: the planar beams of the floating cases have at most a
few hundred elements, where a dense LU (LAPACK through numba) is faster than a sparse one.
"""

from __future__ import annotations

import numpy as np

from rotaflex.core.compiled import entry, inner


@inner
def _element(q, a, b, L0, kap0):
    """Strains and kinematic quantities of one element at its middle."""
    xa, ya, tha = q[3 * a], q[3 * a + 1], q[3 * a + 2]
    xb, yb, thb = q[3 * b], q[3 * b + 1], q[3 * b + 2]
    dx, dy = (xb - xa) / L0, (yb - ya) / L0
    th = 0.5 * (tha + thb)
    c, s = np.cos(th), np.sin(th)
    xt = dx * c + dy * s  # x' . t
    xn = -dx * s + dy * c  # x' . n
    return dx, dy, c, s, xt, xn, xt - 1.0, xn, (thb - tha) / L0 - kap0


@inner
def _b_rows(c, s, xt, xn, L0, B):
    """Strain-displacement rows ``B`` (3, 6) of (eps, gam, kap) on (xa, ya, tha, xb, yb, thb)."""
    B[:, :] = 0.0
    # d eps = dx' . t + (x' . n) d th,   d gam = dx' . n - (x' . t) d th
    B[0, 0], B[0, 1], B[0, 3], B[0, 4] = -c / L0, -s / L0, c / L0, s / L0
    B[0, 2] = B[0, 5] = 0.5 * xn
    B[1, 0], B[1, 1], B[1, 3], B[1, 4] = s / L0, -c / L0, -s / L0, c / L0
    B[1, 2] = B[1, 5] = -0.5 * xt
    B[2, 2], B[2, 5] = -1.0 / L0, 1.0 / L0


@entry
def internal(q, v, conn, L0, kap0, stiff, eta, kv, f, K, want_k):
    """Internal force ``f`` (n,) and tangent ``K`` (n, n) [N, N m, N/m, ...] of all elements;
    returns the strain energy [J].

    Parameters
    ----------
    q, v : (n,) positions/angles and their rates.
    conn : (ne, 2) int64 element nodes ``a, b``.
    L0, kap0 : (ne,) reference lengths [m] and curvatures [1/m].
    stiff : (ne, 3) ``EA, GA, EI`` [N, N, N m^2].
    eta : float, Kelvin-Voigt time constant [s] (stress ``D (strain + eta strain')``).
    kv : float, ``d v / d q`` of the integrator (``gamma / (beta h)``), for the damping tangent.
    f, K : outputs (zeroed here); ``K`` only when ``want_k``.
    """
    f[:] = 0.0
    if want_k:
        K[:, :] = 0.0
    B = np.zeros((3, 6))
    dofs = np.zeros(6, dtype=np.int64)
    energy = 0.0
    for e in range(conn.shape[0]):
        a, b, le = conn[e, 0], conn[e, 1], L0[e]
        _, _, c, s, xt, xn, eps, gam, kap = _element(q, a, b, le, kap0[e])
        for j in range(3):
            dofs[j] = 3 * a + j
            dofs[3 + j] = 3 * b + j
        _b_rows(c, s, xt, xn, le, B)
        ea, ga, ei = stiff[e, 0], stiff[e, 1], stiff[e, 2]
        energy += 0.5 * le * (ea * eps * eps + ga * gam * gam + ei * kap * kap)
        rate0 = rate1 = rate2 = 0.0
        if eta > 0.0:
            for j in range(6):
                vj = v[dofs[j]]
                rate0 += B[0, j] * vj
                rate1 += B[1, j] * vj
                rate2 += B[2, j] * vj
        N = ea * (eps + eta * rate0)
        Q = ga * (gam + eta * rate1)
        M = ei * (kap + eta * rate2)
        for j in range(6):
            f[dofs[j]] += le * (N * B[0, j] + Q * B[1, j] + M * B[2, j])
        if not want_k:
            continue
        fac = 1.0 + eta * kv
        for i in range(6):
            for j in range(6):
                K[dofs[i], dofs[j]] += (
                    le * fac * (ea * B[0, i] * B[0, j] + ga * B[1, i] * B[1, j] + ei * B[2, i] * B[2, j])
                )
        # geometric part: N d2eps + Q d2gam; g = N n - Q t couples dx' with d th
        gx, gy = -N * s - Q * c, N * c - Q * s
        h = -(N * xt + Q * xn)
        for ti in (2, 5):
            for k, sign in ((0, -1.0), (3, 1.0)):
                K[dofs[k], dofs[ti]] += 0.5 * sign * gx
                K[dofs[k + 1], dofs[ti]] += 0.5 * sign * gy
                K[dofs[ti], dofs[k]] += 0.5 * sign * gx
                K[dofs[ti], dofs[k + 1]] += 0.5 * sign * gy
            for tj in (2, 5):
                K[dofs[ti], dofs[tj]] += 0.25 * le * h
    return energy


@inner
def _rot(phi, x, y):
    c, s = np.cos(phi), np.sin(phi)
    return c * x - s * y, s * x + c * y


@entry
def external(q, lam, node, kind, frame, amp, ref, ref_dof, dist, f, K, want_k):
    """Applied loads ``f`` (n,) scaled by ``lam`` (one factor per load) and their load stiffness
    ``K -= d f / d q`` (added to ``K``) when ``want_k``.

    Parameters
    ----------
    node : (nl,) int64 node (or DOF block) the load acts on.
    kind : (nl,) 0 force, 1 moment about z.
    frame : (nl,) 0 the reference frame of the body (rotates with DOF ``ref_dof``), 1 inertial
        (fixed direction), 2 material (follows the section angle at the node: a follower force).
    amp : (nl, 2) force (x, y) [N] in its frame, or (moment [N m], 0).
    ref : (nl,) angle of the load's frame at ``q = 0`` reference (the node's initial section
        angle for material loads) [rad].
    ref_dof : int, DOF of the reference frame's angle (-1: the frame does not rotate).
    dist : (ne, 5) ``a, b, L0, wx, wy``: a distributed load (wx, wy) [N/m] fixed in space on the
        element between nodes a and b (consistent nodal forces ``w L0 / 2``); scaled by ``lam[-1]``.
    """
    f[:] = 0.0
    for i in range(node.shape[0]):
        d = 3 * node[i]
        s = lam[i]
        if kind[i] == 1:
            f[d + 2] += s * amp[i, 0]
            continue
        if frame[i] == 1:
            f[d] += s * amp[i, 0]
            f[d + 1] += s * amp[i, 1]
            continue
        j = d + 2 if frame[i] == 2 else ref_dof
        phi = ref[i] + (q[j] if j >= 0 else 0.0)
        fx, fy = _rot(phi, amp[i, 0], amp[i, 1])
        f[d] += s * fx
        f[d + 1] += s * fy
        if want_k and j >= 0:
            # d/dphi of R(phi) F0 = (-fy, fx): a follower load is not conservative
            K[d, j] -= -s * fy
            K[d + 1, j] -= s * fx
    sd = lam[lam.shape[0] - 1]
    for e in range(dist.shape[0]):
        a, b = int(dist[e, 0]), int(dist[e, 1])
        h = 0.5 * dist[e, 2] * sd
        f[3 * a] += h * dist[e, 3]
        f[3 * a + 1] += h * dist[e, 4]
        f[3 * b] += h * dist[e, 3]
        f[3 * b + 1] += h * dist[e, 4]


@entry
def constraints(q, clamp, g, G):
    """Root clamps: node ``c`` rigidly fixed to the frame whose ``(X, Y, phi)`` are DOFs ``d..d+2``.

    ``clamp`` (nc, 6): ``node, d, rx, ry, alpha, unused``: the node sits at ``(rx, ry)`` in frame
    axes and its section angle is ``phi + alpha``. Fills ``g`` (3 nc,) and its Jacobian ``G``
    (3 nc, n).
    """
    G[:, :] = 0.0
    for i in range(clamp.shape[0]):
        c, d = int(clamp[i, 0]), int(clamp[i, 1])
        rx, ry, al = clamp[i, 2], clamp[i, 3], clamp[i, 4]
        phi = q[d + 2]
        px, py = _rot(phi, rx, ry)
        k = 3 * i
        g[k] = q[3 * c] - q[d] - px
        g[k + 1] = q[3 * c + 1] - q[d + 1] - py
        g[k + 2] = q[3 * c + 2] - phi - al
        G[k, 3 * c] = 1.0
        G[k + 1, 3 * c + 1] = 1.0
        G[k + 2, 3 * c + 2] = 1.0
        G[k, d] = -1.0
        G[k + 1, d + 1] = -1.0
        G[k + 2, d + 2] = -1.0
        G[k, d + 2] = py
        G[k + 1, d + 2] = -px
