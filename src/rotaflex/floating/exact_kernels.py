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
from rotaflex.floating.kernels import motion_profile, profile_value


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


@inner
def _prescribe(q, v, qdd, fixed, hold, fdof, pres, t):
    """Fixed DOFs at their held values; with ``pres[5] >= 0`` the frame angle DOF ``fdof + 2``
    follows :func:`rotaflex.floating.kernels.motion_profile`."""
    for i in range(q.shape[0]):
        if fixed[i]:
            q[i], v[i], qdd[i] = hold[i], 0.0, 0.0
    if pres[5] >= 0.0:
        ang, om, al = motion_profile(pres, t)
        q[fdof + 2], v[fdof + 2], qdd[fdof + 2] = hold[fdof + 2] + ang, om, al


@entry
def load_factors(t, prof, par, lam):
    """Profile values ``lam`` (nl + 1,) of the loads at ``t``; the last (distributed load) is 1."""
    _loads_at(t, prof, par, lam)


@inner
def _loads_at(t, prof, par, lam):
    for i in range(prof.shape[0]):
        lam[i] = profile_value(prof[i], par[i], t)
    lam[lam.shape[0] - 1] = 1.0


@inner
def _step(q, v, qdd, a, t1, h, M, beam, loads, clamp, fixed, hold, pres, coef, work):
    """One generalized-alpha step to ``t1`` (Arnold & Bruls 2007 form of Chung & Hulbert 1993):
    equilibrium ``M q'' + f_int(q, q') - f_ext(q, t) + G^T lam = 0``, ``g(q) = 0`` at ``t1``;
    the acceleration-like ``a`` carries the algorithmic damping. Returns (converged, iterations).
    """
    conn, L0, kap0, stiff, eta = beam
    node, kind, frame, amp, ref, prof, par, dist, ref_dof = loads
    am, af, beta, gamma, tol, max_iter = coef
    f, K, fe, Ke, g, G, lam, mult, A, rhs = work
    n = q.shape[0]
    nc = g.shape[0]
    fdof = n - 3
    bp = (1.0 - am) / (beta * h * h * (1.0 - af))
    gp = gamma / (beta * h)
    qdd_n = qdd.copy()
    # predictor: constant velocity, no acceleration term (extrapolating with the start
    # acceleration threw a section of tiny rotary inertia under a step moment by radians and
    # Newton then settled on a spurious high-energy branch); v, q'' and a consistent with it
    q += h * v
    a_new = (-h * h * (0.5 - beta) * a) / (beta * h * h)
    v += h * ((1.0 - gamma) * a + gamma * a_new)
    qdd[:] = ((1.0 - am) * a_new + am * a - af * qdd) / (1.0 - af)
    _prescribe(q, v, qdd, fixed, hold, fdof, pres, t1)
    _loads_at(t1, prof, par, lam)
    mult[:] = 0.0
    for it in range(1, int(max_iter) + 1):
        internal(q, v, conn, L0, kap0, stiff, eta, gp, f, K, True)
        external(q, lam, node, kind, frame, amp, ref, ref_dof, dist, fe, Ke, True)
        if nc:
            constraints(q, clamp, g, G)
        for i in range(n):
            r = f[i] - fe[i]
            for j in range(n):
                r += M[i, j] * qdd[j]
                A[i, j] = bp * M[i, j] + K[i, j] + Ke[i, j]
            for k in range(nc):
                r += G[k, i] * mult[k]
                A[i, n + k] = G[k, i]
                A[n + k, i] = G[k, i]
            rhs[i] = -r
        for k in range(nc):
            rhs[n + k] = -g[k]
            for j in range(nc):
                A[n + k, n + j] = 0.0
        for i in range(n):
            if fixed[i] or (pres[5] >= 0.0 and i == fdof + 2):
                for j in range(n + nc):
                    A[i, j] = 0.0
                    A[j, i] = 0.0
                A[i, i] = 1.0
                rhs[i] = 0.0
        dx = np.linalg.solve(A, rhs)
        step = 0.0
        for i in range(n):
            q[i] += dx[i]
            v[i] += gp * dx[i]
            qdd[i] += bp * dx[i]
            step = max(step, abs(dx[i]))
        for k in range(nc):
            mult[k] += dx[n + k]
        if not np.isfinite(step):
            return False, it
        if step <= tol:
            a[:] = ((1.0 - af) * qdd + af * qdd_n - am * a) / (1.0 - am)
            return True, it
    return False, int(max_iter)


@inner
def _drive_force(q, qdd, M, G, mult, fe, fi, driven, R):
    """Force the drive applies on the driven DOFs: ``M q'' + f_int - f_ext + G^T lam`` there."""
    n = q.shape[0]
    for i in range(n):
        R[i] = 0.0
        if not driven[i]:
            continue
        r = fi[i] - fe[i]
        for j in range(n):
            r += M[i, j] * qdd[j]
        for k in range(G.shape[0]):
            r += G[k, i] * mult[k]
        R[i] = r


@entry
def integrate(q, v, qdd, a, mult, works, times, is_out, M, beam, loads, clamp, fixed, hold, pres, coef, max_halvings):
    """Generalized-alpha over the step end times ``times`` (the first is the start).

    The state ``q, v, qdd`` and the acceleration-like ``a`` (equal to ``qdd`` at the very start),
    the clamp multipliers ``mult`` (3 nc,) and the works so far ``works`` (2,) [J] are updated in
    place, so a run can go on in chunks (for progress).
    Returns ``(status, Q, V, energy (nout, 4), steps, iterations)``: status 0 done, 1 a step
    failed to converge after ``max_halvings`` halvings (arrays filled up to the failure);
    energy columns: kinetic, strain, work of the applied loads, work of the drive on the fixed
    and prescribed DOFs, each [J], the works by the trapezoidal rule over each interval.
    """
    n = q.shape[0]
    nc = 3 * clamp.shape[0]
    nl = loads[0].shape[0]
    work = (
        np.zeros(n),
        np.zeros((n, n)),
        np.zeros(n),
        np.zeros((n, n)),
        np.zeros(nc),
        np.zeros((nc, n)),
        np.zeros(nl + 1),
        np.zeros(nc),
        np.zeros((n + nc, n + nc)),
        np.zeros(n + nc),
    )
    conn, L0, kap0, stiff, eta = beam
    node, kind, frame, amp, ref, prof, par, dist, ref_dof = loads
    nout = 0
    for k in range(times.shape[0]):
        if is_out[k]:
            nout += 1
    Q = np.full((nout, n), np.nan)
    V = np.full((nout, n), np.nan)
    E = np.full((nout, 4), np.nan)
    driven = fixed.copy()
    if pres[5] >= 0.0:
        driven[n - 1] = True
    fe0, fe1, fi = np.zeros(n), np.zeros(n), np.zeros(n)
    R0, R1 = np.zeros(n), np.zeros(n)
    lam = np.zeros(nl + 1)
    Kd = np.zeros((1, 1))
    G = np.zeros((nc, n))
    g = np.zeros(nc)
    w_ext = works[0]
    w_fix = works[1]
    iters = 0
    steps = 0
    j = 0
    qs, vs, qdds, as_ = q.copy(), v.copy(), qdd.copy(), a.copy()
    _loads_at(times[0], prof, par, lam)
    external(q, lam, node, kind, frame, amp, ref, ref_dof, dist, fe0, Kd, False)
    internal(q, v, conn, L0, kap0, stiff, eta, 0.0, fi, Kd, False)
    if nc:
        constraints(q, clamp, g, G)
    _drive_force(q, qdd, M, G, mult, fe0, fi, driven, R0)
    for k in range(times.shape[0]):
        if k > 0:
            q_old = q.copy()
            # the interval in 2^m equal sub-steps, m raised until every sub-step converges
            t0, t1 = times[k - 1], times[k]
            ok = False
            for m in range(max_halvings + 1):
                qs[:], vs[:], qdds[:], as_[:] = q, v, qdd, a
                nsub = 2**m
                hs = (t1 - t0) / nsub
                ok = True
                for s in range(nsub):
                    conv, it = _step(
                        qs, vs, qdds, as_, t0 + (s + 1) * hs, hs, M, beam, loads, clamp, fixed, hold, pres, coef, work
                    )
                    iters += it
                    steps += 1
                    if not conv:
                        ok = False
                        break
                if ok:
                    break
            if not ok:
                works[0], works[1] = w_ext, w_fix
                return 1, Q, V, E, steps, iters
            q[:], v[:], qdd[:], a[:] = qs, vs, qdds, as_
            _loads_at(t1, prof, par, lam)
            external(q, lam, node, kind, frame, amp, ref, ref_dof, dist, fe1, Kd, False)
            internal(q, v, conn, L0, kap0, stiff, eta, 0.0, fi, Kd, False)
            if nc:
                constraints(q, clamp, g, G)
            _drive_force(q, qdd, M, G, work[7], fe1, fi, driven, R1)
            for i in range(n):
                dq = q[i] - q_old[i]
                w_ext += 0.5 * (fe0[i] + fe1[i]) * dq
                w_fix += 0.5 * (R0[i] + R1[i]) * dq
            fe0[:] = fe1
            R0[:] = R1
            mult[:] = work[7]
        if is_out[k]:
            ekin = 0.0
            for i in range(n):
                for jj in range(n):
                    ekin += 0.5 * v[i] * M[i, jj] * v[jj]
            Q[j] = q
            V[j] = v
            E[j, 0] = ekin
            E[j, 1] = internal(q, v, conn, L0, kap0, stiff, 0.0, 0.0, fi, Kd, False)
            E[j, 2] = w_ext
            E[j, 3] = w_fix
            j += 1
    works[0], works[1] = w_ext, w_fix
    return 0, Q, V, E, steps, iters
