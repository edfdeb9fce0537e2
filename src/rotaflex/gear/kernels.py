"""Compiled (numba) kernels of the dynamic gear-contact solver.

Everything that runs once per time step lives here: cubic-spline tooth surfaces, the
minimum-normal-distance contact search with its sliding kinematics (appendix A of the paper),
the co-rotational elastic force (eq. 4-5), the classical RK4 step and the three constraint
passes (displacement, velocity, acceleration) with the accelerated multiplier iteration of
eq. 19-24 / appendix B. :func:`run_steps` advances many steps in one call; Python only sees
the solver again for progress reports and output.

Conventions (all SI)
--------------------
* Nodes of gear A come first, then gear B; DOFs are interleaved ``[x0, y0, x1, y1, ...]`` and
  hold *absolute* positions ``x`` (the paper's absolute displacement plus the reference).
* ``phi[g]`` is the counter-clockwise rotation of disk ``g`` since t = 0; the tooth's local
  frame is rotated by ``theta0[g] + phi[g]`` from the global frame.
* Constraint rows: ``2*k + c`` is the tie of tie-node ``k`` in direction ``c``; the last row is
  the contact. ``G`` is the matrix ``[-Phi_q; s_q]`` so that the constraint force is
  ``G^T mu`` with ``mu = (lambda, p)`` and the error vector of eq. 8 changes by ``G dq``.
* The contact force ``p <= 0`` (compression); ``s > 0`` is a penetration.

Status codes returned by :func:`run_steps`: 0 ok; 1, 2, 3 = the displacement, velocity or
acceleration pass did not converge (``info`` holds time, residual, tolerance); 4 = contact
search failed.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from rotaflex.gear.kernels_direct import direct_pass

# ----------------------------------------------------------------------------- splines


@njit(cache=True)
def spline_second(p, m):
    """Second derivatives of the natural cubic spline through ``p`` (M, 2) on a uniform grid
    of the parameter in [0, 1]; written into ``m`` (M, 2)."""
    n = p.shape[0]
    h = 1.0 / (n - 1)
    cp = np.empty(n)
    for d in range(2):
        m[0, d] = 0.0
        m[n - 1, d] = 0.0
        # Thomas algorithm for m[k-1] + 4 m[k] + m[k+1] = 6 (p[k+1] - 2 p[k] + p[k-1]) / h^2
        cp[0] = 0.0
        prev_c = 0.0
        prev_d = 0.0
        for k in range(1, n - 1):
            rhs = 6.0 * (p[k + 1, d] - 2.0 * p[k, d] + p[k - 1, d]) / (h * h)
            den = 4.0 - prev_c
            cc = 1.0 / den
            dd = (rhs - prev_d) / den
            cp[k] = cc
            m[k, d] = dd
            prev_c = cc
            prev_d = dd
        for k in range(n - 3, 0, -1):
            m[k, d] -= cp[k] * m[k + 1, d]


@njit(cache=True)
def spline_eval(p, m, s, out):
    """Value, first and second derivative of the spline at parameter ``s``.

    ``out`` (3, 2) receives rows value / d/ds / d2/ds2. Outside [0, 1] the natural spline is
    continued linearly (its second derivative vanishes at the ends, so this is C2).
    """
    n = p.shape[0]
    h = 1.0 / (n - 1)
    if s <= 0.0 or s >= 1.0:
        k = 0 if s <= 0.0 else n - 2
        xe = 0.0 if s <= 0.0 else 1.0
        for d in range(2):
            a = (xe - k * h) if s >= 1.0 else 0.0
            b = h - a
            slope = (
                -m[k, d] * b * b / (2 * h)
                + m[k + 1, d] * a * a / (2 * h)
                - (p[k, d] / h - m[k, d] * h / 6)
                + (p[k + 1, d] / h - m[k + 1, d] * h / 6)
            )
            y0 = p[0, d] if s <= 0.0 else p[n - 1, d]
            out[0, d] = y0 + slope * (s - xe)
            out[1, d] = slope
            out[2, d] = 0.0
        return
    k = int(s / h)
    if k > n - 2:
        k = n - 2
    a = s - k * h  # x - x_k
    b = h - a  # x_{k+1} - x
    for d in range(2):
        mk = m[k, d]
        mk1 = m[k + 1, d]
        c0 = p[k, d] / h - mk * h / 6
        c1 = p[k + 1, d] / h - mk1 * h / 6
        out[0, d] = mk * b**3 / (6 * h) + mk1 * a**3 / (6 * h) + c0 * b + c1 * a
        out[1, d] = -mk * b * b / (2 * h) + mk1 * a * a / (2 * h) - c0 + c1
        out[2, d] = (mk * b + mk1 * a) / h


# ----------------------------------------------------------------------------- contact search


@njit(cache=True)
def _project(p, m, x0, x1, t0, t1, s, buf):
    """Parameter ``s`` of the spline point whose offset from (x0, x1) is normal to (t0, t1)."""
    for _ in range(40):
        spline_eval(p, m, s, buf)
        f = (buf[0, 0] - x0) * t0 + (buf[0, 1] - x1) * t1
        df = buf[1, 0] * t0 + buf[1, 1] * t1
        if df == 0.0:
            return s, False
        ds = -f / df
        if ds > 0.2:
            ds = 0.2
        elif ds < -0.2:
            ds = -0.2
        s += ds
        if abs(ds) < 1e-14:
            return s, True
    return s, abs(ds) < 1e-9


@njit(cache=True)
def _normal_fn(pq, mq, ps, ms, sig, a, b, bq, bs):
    """F(a) = P_S'(b(a)) . n_Q(a) with b(a) the normal projection of P_Q(a) on S."""
    spline_eval(pq, mq, a, bq)
    ln = math.hypot(bq[1, 0], bq[1, 1])
    t0 = bq[1, 0] / ln
    t1 = bq[1, 1] / ln
    b, ok = _project(ps, ms, bq[0, 0], bq[0, 1], t0, t1, b, bs)
    spline_eval(ps, ms, b, bs)
    n0 = -sig * t1
    n1 = sig * t0
    lb = math.hypot(bs[1, 0], bs[1, 1])
    return (bs[1, 0] * n0 + bs[1, 1] * n1) / lb, b, ok


@njit(cache=True)
def contact_search(pa, ma, pb, mb, sig_a, sig_b, a0, b0, res):
    """Pair of minimum normal distance between spline surfaces A and B.

    Parameters
    ----------
    pa, ma, pb, mb : (M, 2) arrays
        Spline data points and second derivatives of the two tooth surfaces (root -> tip).
    sig_a, sig_b : float
        +1 if the outward normal of the tooth is the tangent turned +90 deg, else -1.
    a0, b0 : float
        Warm start (previous contact parameters).
    res : (8,) array
        Output: a, b, h (signed normal separation, > 0 = gap), n_x, n_y (unit normal pointing
        from A into B), case (0 interior, 1 tip corner of B, 2 tip corner of A), q (0 if the
        normal is A's, 1 if B's), ok flag.
    """
    bq = np.empty((3, 2))
    bs = np.empty((3, 2))
    # ---- interior common-normal point: secant iteration on F(a) = 0
    a = a0
    b = b0
    f0, b, ok0 = _normal_fn(pa, ma, pb, mb, sig_a, a, b, bq, bs)
    a1 = a + 1e-3
    f1, b1, ok1 = _normal_fn(pa, ma, pb, mb, sig_a, a1, b, bq, bs)
    conv = False
    for _ in range(60):
        if f1 == f0:
            conv = abs(f1) < 1e-13
            break
        a2 = a1 - f1 * (a1 - a) / (f1 - f0)
        if a2 > 1.6:
            a2 = 1.6
        elif a2 < -0.6:
            a2 = -0.6
        a, f0 = a1, f1
        a1 = a2
        f1, b1, ok1 = _normal_fn(pa, ma, pb, mb, sig_a, a1, b1, bq, bs)
        if abs(a1 - a) < 1e-13:
            conv = True
            break
    if not conv:
        # robust fallback: scan for sign changes, bisect the one nearest the warm start
        na = 200
        prev_f = 0.0
        prev_a = -0.6
        bb = b0
        found = False
        best = 1e300
        lo0 = 0.0
        hi0 = 0.0
        flo0 = 0.0
        blo0 = b0
        prev_b = b0
        for i in range(na + 1):
            aa = -0.6 + 2.2 * i / na
            ff, bb, okk = _normal_fn(pa, ma, pb, mb, sig_a, aa, bb, bq, bs)
            if i > 0 and ff * prev_f <= 0.0:
                dist = abs(0.5 * (prev_a + aa) - a0)
                if dist < best:
                    best = dist
                    lo0, hi0, flo0, blo0 = prev_a, aa, prev_f, prev_b
                    found = True
            prev_f = ff
            prev_a = aa
            prev_b = bb
        if found:
            lo, hi, flo = lo0, hi0, flo0
            bb = blo0
            for _ in range(200):
                mid = 0.5 * (lo + hi)
                fm, bb, okk = _normal_fn(pa, ma, pb, mb, sig_a, mid, bb, bq, bs)
                if fm * flo <= 0.0:
                    hi = mid
                else:
                    lo, flo = mid, fm
                if hi - lo < 1e-14:
                    break
            a1 = 0.5 * (lo + hi)
            f1, b1, ok1 = _normal_fn(pa, ma, pb, mb, sig_a, a1, bb, bq, bs)
        if not found:
            # no common normal (e.g. a straight flank against a corner): corner contact of B
            a1 = min(max(a0, 0.0), 1.0)
            b1 = 2.0
    a = a1
    b = b1
    case = 0
    if a > 1.0 and b > 1.0:
        case = 1 if (b - 1.0) > (a - 1.0) else 2
    elif b > 1.0:
        case = 1
    elif a > 1.0:
        case = 2
    ok = True
    if case == 0:
        a = min(max(a, 0.0), 1.0)
        b = min(max(b, 0.0), 1.0)
        spline_eval(pa, ma, a, bq)
        spline_eval(pb, mb, b, bs)
        ln = math.hypot(bq[1, 0], bq[1, 1])
        n0 = -sig_a * bq[1, 1] / ln
        n1 = sig_a * bq[1, 0] / ln
        q = 0
    elif case == 1:
        # tip corner of B on the flank of A: project the corner on A
        spline_eval(pb, mb, 1.0, bs)
        cx, cy = bs[0, 0], bs[0, 1]
        b = 1.0
        for _ in range(40):
            spline_eval(pa, ma, a, bq)
            dx = cx - bq[0, 0]
            dy = cy - bq[0, 1]
            f = dx * bq[1, 0] + dy * bq[1, 1]
            df = -(bq[1, 0] ** 2 + bq[1, 1] ** 2) + dx * bq[2, 0] + dy * bq[2, 1]
            da = -f / df
            a += da
            if abs(da) < 1e-14:
                break
        a = min(max(a, 0.0), 1.0)
        spline_eval(pa, ma, a, bq)
        ln = math.hypot(bq[1, 0], bq[1, 1])
        n0 = -sig_a * bq[1, 1] / ln
        n1 = sig_a * bq[1, 0] / ln
        q = 0
    else:
        # tip corner of A on the flank of B: the normal is B's (reversed)
        spline_eval(pa, ma, 1.0, bq)
        cx, cy = bq[0, 0], bq[0, 1]
        a = 1.0
        for _ in range(40):
            spline_eval(pb, mb, b, bs)
            dx = cx - bs[0, 0]
            dy = cy - bs[0, 1]
            f = dx * bs[1, 0] + dy * bs[1, 1]
            df = -(bs[1, 0] ** 2 + bs[1, 1] ** 2) + dx * bs[2, 0] + dy * bs[2, 1]
            db = -f / df
            b += db
            if abs(db) < 1e-14:
                break
        b = min(max(b, 0.0), 1.0)
        spline_eval(pb, mb, b, bs)
        lb = math.hypot(bs[1, 0], bs[1, 1])
        n0 = sig_b * bs[1, 1] / lb
        n1 = -sig_b * bs[1, 0] / lb
        q = 1
    spline_eval(pa, ma, a, bq)
    spline_eval(pb, mb, b, bs)
    h = (bs[0, 0] - bq[0, 0]) * n0 + (bs[0, 1] - bq[0, 1]) * n1
    res[0] = a
    res[1] = b
    res[2] = h
    res[3] = n0
    res[4] = n1
    res[5] = case
    res[6] = q
    res[7] = 1.0 if ok else 0.0


@njit(cache=True)
def _cross(ax, ay, bx, by):
    return ax * by - ay * bx


@njit(cache=True)
def sliding_terms(pa, ma, va, mva, pb, mb, vb, mvb, sig_a, sig_b, res, rates):
    """Velocity-independent part of the relative normal acceleration (appendix A).

    With the contact pair of ``res`` (from :func:`contact_search`), returns ``h_s`` such that
    ``s_ddot = n . (a_A - a_B) + h_s`` where a_A, a_B are the material accelerations of the
    contact points, and the contact-parameter rates (da/dt, db/dt). ``va, vb`` are spline data of
    the surface velocities (material velocities of the spline data points).

    Derivation: the pair keeps (P_S - P_Q) . t_Q = 0 and (interior case) P_S' . n_Q = 0, Q being
    the surface that provides the normal; differentiating both in time gives the parameter
    rates; then ``h_ddot = (A_S - A_Q).n_Q + (V_S' b' - V_Q' a').n_Q + (V_S - V_Q).n_Q'``.
    """
    a = res[0]
    b = res[1]
    case = int(res[5])
    q = int(res[6])
    h = res[2]
    eq = np.empty((3, 2))
    es = np.empty((3, 2))
    evq = np.empty((3, 2))
    evs = np.empty((3, 2))
    if q == 0:
        spline_eval(pa, ma, a, eq)
        spline_eval(va, mva, a, evq)
        spline_eval(pb, mb, b, es)
        spline_eval(vb, mvb, b, evs)
        sig = sig_a
        aq = a
    else:
        spline_eval(pb, mb, b, eq)
        spline_eval(vb, mvb, b, evq)
        spline_eval(pa, ma, a, es)
        spline_eval(va, mva, a, evs)
        sig = sig_b
        aq = b
    _ = aq
    lq = math.hypot(eq[1, 0], eq[1, 1])
    t0 = eq[1, 0] / lq
    t1 = eq[1, 1] / lq
    n0 = -sig * t1
    n1 = sig * t0
    # material rate of the tangent at fixed parameter, and its parameter derivative
    vq_t = evq[1, 0] * t0 + evq[1, 1] * t1
    tdot0 = (evq[1, 0] - vq_t * t0) / lq
    tdot1 = (evq[1, 1] - vq_t * t1) / lq
    pq2_t = eq[2, 0] * t0 + eq[2, 1] * t1
    tp0 = (eq[2, 0] - pq2_t * t0) / lq
    tp1 = (eq[2, 1] - pq2_t * t1) / lq
    # n = sig * J t  (J = +90 deg rotation): J(x, y) = (-y, x)
    ndot0 = -sig * tdot1
    ndot1 = sig * tdot0
    np0 = -sig * tp1
    np1 = sig * tp0
    dv0 = evs[0, 0] - evq[0, 0]
    dv1 = evs[0, 1] - evq[0, 1]
    # T-equation: a'(-|P_Q'| + h n.t') + b'(P_S'.t) = (V_Q - V_S).t - h n.tdot
    a11 = -lq + h * (n0 * tp0 + n1 * tp1)
    a12 = es[1, 0] * t0 + es[1, 1] * t1
    r1 = -(dv0 * t0 + dv1 * t1) - h * (n0 * tdot0 + n1 * tdot1)
    is_interior = (q == 0 and case == 0) or (q == 1 and case == 0)
    if case == 0 and is_interior:
        # F-equation: a'(P_S'.n') + b'(P_S''.n) = -V_S'.n - P_S'.ndot
        a21 = es[1, 0] * np0 + es[1, 1] * np1
        a22 = es[2, 0] * n0 + es[2, 1] * n1
        r2 = -(evs[1, 0] * n0 + evs[1, 1] * n1) - (es[1, 0] * ndot0 + es[1, 1] * ndot1)
        det = a11 * a22 - a12 * a21
        ad = (r1 * a22 - a12 * r2) / det
        bd = (a11 * r2 - a21 * r1) / det
    else:
        bd = 0.0
        ad = r1 / a11
    nd0 = ndot0 + np0 * ad
    nd1 = ndot1 + np1 * ad
    hdd_v = (evs[1, 0] * bd - evq[1, 0] * ad) * n0 + (evs[1, 1] * bd - evq[1, 1] * ad) * n1
    hdd_v += dv0 * nd0 + dv1 * nd1
    # s = -h, and the acceleration part (A_S - A_Q).n_Q = -(a_A - a_B).n with n from A to B
    if q == 0:
        rates[0] = ad
        rates[1] = bd
        rates[2] = nd0
        rates[3] = nd1
        return -hdd_v, ad, bd
    rates[0] = bd
    rates[1] = ad
    rates[2] = -nd0
    rates[3] = -nd1
    return -hdd_v, bd, ad


# ----------------------------------------------------------------------------- FE helpers


@njit(cache=True)
def flank_weights(flank, nedge, s, nodes, w):
    """Nodes and quadratic edge shape functions of flank parameter ``s`` in [0, 1]."""
    z = min(max(s, 0.0), 1.0) * nedge
    k = int(z)
    if k > nedge - 1:
        k = nedge - 1
    xi = 2.0 * (z - k) - 1.0
    nodes[0] = flank[2 * k]
    nodes[1] = flank[2 * k + 1]
    nodes[2] = flank[2 * k + 2]
    w[0] = 0.5 * xi * (xi - 1.0)
    w[1] = 1.0 - xi * xi
    w[2] = 0.5 * xi * (xi + 1.0)


@njit(cache=True)
def sample_flank(x, flank, nedge, out):
    """Surface data points: the FE flank edge (quadratic) evaluated at M uniform parameters."""
    mpts = out.shape[0]
    nodes = np.empty(3, np.int64)
    w = np.empty(3)
    for k in range(mpts):
        flank_weights(flank, nedge, k / (mpts - 1), nodes, w)
        for d in range(2):
            out[k, d] = w[0] * x[2 * nodes[0] + d] + w[1] * x[2 * nodes[1] + d] + w[2] * x[2 * nodes[2] + d]


@njit(cache=True)
def elastic_force(x, xloc, gid, cen, rot, indptr, indices, data, wbuf, floc, fglob, tel):
    """Co-rotational elastic force (eq. 4-5) and strain energy.

    ``w = R^T (x - c) - X`` (exact co-rotational form), ``f = -R K w`` on the nodes, and the
    disk torque ``sum f_loc . J (X + w)`` = -dE/dphi, which makes the force conservative.
    """
    nn = xloc.shape[0]
    for i in range(nn):
        g = gid[i]
        c = rot[g, 0]
        s = rot[g, 1]
        dx = x[2 * i] - cen[g, 0]
        dy = x[2 * i + 1] - cen[g, 1]
        wbuf[2 * i] = c * dx + s * dy - xloc[i, 0]
        wbuf[2 * i + 1] = -s * dx + c * dy - xloc[i, 1]
    nd = 2 * nn
    energy = 0.0
    for r in range(nd):
        acc = 0.0
        for j in range(indptr[r], indptr[r + 1]):
            acc += data[j] * wbuf[indices[j]]
        floc[r] = acc
        energy += 0.5 * acc * wbuf[r]
    tel[0] = 0.0
    tel[1] = 0.0
    for i in range(nn):
        g = gid[i]
        c = rot[g, 0]
        s = rot[g, 1]
        f0 = floc[2 * i]
        f1 = floc[2 * i + 1]
        fglob[2 * i] = -(c * f0 - s * f1)
        fglob[2 * i + 1] = -(s * f0 + c * f1)
        # J (X + w) = (-(Y + w_y), X + w_x)
        tel[g] += f0 * (-(xloc[i, 1] + wbuf[2 * i + 1])) + f1 * (xloc[i, 0] + wbuf[2 * i])
    return energy


@njit(cache=True)
def ramp_torque(theta, tau0, th2, ths):
    """Torque of Fig. 7: 0 -> tau0 over [0, th2], tau0, tau0 -> 0 over [ths - th2, ths]."""
    if theta <= 0.0 or theta >= ths:
        return 0.0
    f = 1.0
    if theta < th2:
        f = theta / th2
    if theta > ths - th2:
        f = min(f, (ths - theta) / th2)
    return tau0 * f


# ----------------------------------------------------------------------------- model helpers


@njit(cache=True)
def set_rotation(phi, theta0, rot):
    for g in range(2):
        ang = theta0[g] + phi[g]
        rot[g, 0] = math.cos(ang)
        rot[g, 1] = math.sin(ang)


@njit(cache=True)
def tie_vectors(x, cen, tie_node, tie_gear, rot, bvec, rx):
    """Disk-frame tie quantities of every tie node k (constraint ``R^T (x_k - c) - X_k = 0``).

    ``rx[k] = R^T (x_k - c)`` (current position in the disk frame) and
    ``bvec[k] = J rx[k]``, the derivative of ``-Phi_k`` with respect to the disk angle.
    """
    for k in range(tie_node.shape[0]):
        i = tie_node[k]
        g = tie_gear[k]
        c = rot[g, 0]
        s = rot[g, 1]
        dx = x[2 * i] - cen[g, 0]
        dy = x[2 * i + 1] - cen[g, 1]
        r0 = c * dx + s * dy
        r1 = -s * dx + c * dy
        rx[k, 0] = r0
        rx[k, 1] = r1
        bvec[k, 0] = -r1
        bvec[k, 1] = r0


@njit(cache=True)
def contact_geometry(x, flank, nedge, sig, mpts, pa, ma, pb, mb, cres, cnod, cw):
    """Sample both flanks at ``x``, build the splines, search the contact pair, and store the
    contact row (nodes ``cnod`` and weights ``cw`` of each side). Returns False on failure."""
    sample_flank(x, flank[0], nedge[0], pa)
    sample_flank(x, flank[1], nedge[1], pb)
    spline_second(pa, ma)
    spline_second(pb, mb)
    a0 = cres[0]
    b0 = cres[1]
    contact_search(pa, ma, pb, mb, sig[0], sig[1], a0, b0, cres)
    if cres[7] == 0.0:
        return False
    nodes = np.empty(3, np.int64)
    w = np.empty(3)
    flank_weights(flank[0], nedge[0], cres[0], nodes, w)
    for j in range(3):
        cnod[0, j] = nodes[j]
        cw[0, j] = w[j]
    flank_weights(flank[1], nedge[1], cres[1], nodes, w)
    for j in range(3):
        cnod[1, j] = nodes[j]
        cw[1, j] = w[j]
    return True


@njit(cache=True)
def smooth_weights(tab, s, w):
    """Weights ``w`` (n_flank,) of the flank nodes at parameter ``s`` of the smoothed surface:
    linear interpolation in the table ``tab`` (NT, n_flank) of a uniform parameter grid."""
    nt = tab.shape[0]
    z = min(max(s, 0.0), 1.0) * (nt - 1)
    i = min(int(z), nt - 2)
    f = z - i
    for n in range(tab.shape[1]):
        w[n] = (1.0 - f) * tab[i, n] + f * tab[i + 1, n]


@njit(cache=True)
def sample_smooth(x, flank, tab, mloc, theta, omega, vel, out):
    """Smoothed surface data: ``out[k] = sum_n tab[row_k, n] x_n + omega J R(theta) mloc[k]``
    at the M spline parameters k / (M - 1) (``row_k = k (NT - 1) / (M - 1)``).

    With ``vel = False`` (``x`` the node positions; ``omega J`` replaced by the identity) this is
    the surface; with ``vel = True``, velocities and the disk speed it is the surface velocity (see
    :func:`contact_geometry_smooth`). ``mloc`` (M, 2) is the misfit of the smoothed undeformed
    flank, in the tooth frame.
    """
    mpts = out.shape[0]
    nt = tab.shape[0]
    step = (nt - 1) // (mpts - 1)
    c = math.cos(theta)
    s = math.sin(theta)
    for k in range(mpts):
        r = k * step
        p0 = 0.0
        p1 = 0.0
        for n in range(flank.shape[0]):
            i = flank[n]
            p0 += tab[r, n] * x[2 * i]
            p1 += tab[r, n] * x[2 * i + 1]
        m0 = c * mloc[k, 0] - s * mloc[k, 1]
        m1 = s * mloc[k, 0] + c * mloc[k, 1]
        if not vel:
            out[k, 0] = p0 + m0
            out[k, 1] = p1 + m1
        else:
            out[k, 0] = p0 - omega * m1
            out[k, 1] = p1 + omega * m0


@njit(cache=True)
def contact_geometry_smooth(x, phi, flank, nedge, sig, mpts, pa, ma, pb, mb, cres, cnod, cw, theta0, tab, mloc):
    """:func:`contact_geometry` on the smoothed flank surfaces.

    The surface of tooth g is ``P(s) = X_ref(s) + sum_n T_n(s) (x_n - X_ref,n)``: the FE
    flank's reference shape plus the least-squares cubic-spline fit of the displacement of its
    nodes (``tab[g]`` = T on a parameter grid, ``mloc[g]`` = the reference misfit
    ``X_ref(s) - sum_n T_n(s) X_ref,n``). The constraint row is the exact derivative of the gap
    of that surface: the contact force is spread over the flank nodes with the weights T(a)
    (``cnod`` = all flank nodes, ``cw`` = T at the contact parameters). ``cnod.shape[1] == 3``
    selects the paper's surfaces and 3-node force (:func:`contact_geometry`).
    """
    if cnod.shape[1] == 3:
        return contact_geometry(x, flank, nedge, sig, mpts, pa, ma, pb, mb, cres, cnod, cw)
    sample_smooth(x, flank[0], tab[0], mloc[0], theta0[0] + phi[0], 1.0, False, pa)
    sample_smooth(x, flank[1], tab[1], mloc[1], theta0[1] + phi[1], 1.0, False, pb)
    spline_second(pa, ma)
    spline_second(pb, mb)
    contact_search(pa, ma, pb, mb, sig[0], sig[1], cres[0], cres[1], cres)
    if cres[7] == 0.0:
        return False
    w = np.empty(cnod.shape[1])
    for side in range(2):
        smooth_weights(tab[side], cres[side], w)
        for n in range(cnod.shape[1]):
            cnod[side, n] = flank[side, n]
            cw[side, n] = w[n]
    return True


@njit(cache=True)
def gt_apply(dmu, tie_node, tie_gear, bvec, rot, cnod, cw, cn, g, gth):
    """g (x part) and gth (disk part) of G^T dmu, added into the given arrays.

    Tie multipliers are disk-frame components, so the tie force on node k is ``-R lambda_k``.
    """
    nt = tie_node.shape[0]
    for k in range(nt):
        i = tie_node[k]
        gg = tie_gear[k]
        c = rot[gg, 0]
        s = rot[gg, 1]
        l0 = dmu[2 * k]
        l1 = dmu[2 * k + 1]
        g[2 * i] -= c * l0 - s * l1
        g[2 * i + 1] -= s * l0 + c * l1
        gth[gg] += bvec[k, 0] * l0 + bvec[k, 1] * l1
    p = dmu[2 * nt]
    if p != 0.0:
        for j in range(cnod.shape[1]):
            i = cnod[0, j]
            g[2 * i] += cw[0, j] * cn[0] * p
            g[2 * i + 1] += cw[0, j] * cn[1] * p
            i = cnod[1, j]
            g[2 * i] -= cw[1, j] * cn[0] * p
            g[2 * i + 1] -= cw[1, j] * cn[1] * p


@njit(cache=True)
def k_local_product(g, minv, gid, rot, indptr, indices, data, zk):
    """zk = K R^T M^-1 g (local frame) for a sparse g (only its non-zero nodes are visited)."""
    nn = minv.shape[0]
    for i in range(nn):
        g0 = g[2 * i]
        g1 = g[2 * i + 1]
        if g0 == 0.0 and g1 == 0.0:
            continue
        gg = gid[i]
        c = rot[gg, 0]
        s = rot[gg, 1]
        l0 = (c * g0 + s * g1) * minv[i]
        l1 = (-s * g0 + c * g1) * minv[i]
        for d in range(2):
            r = 2 * i + d
            val = l0 if d == 0 else l1
            for j in range(indptr[r], indptr[r + 1]):
                zk[indices[j]] += data[j] * val


@njit(cache=True)
def respond(g, gth, c1, c2, minv, gid, rot, jd, indptr, indices, data, zk, tx, tth, scale):
    """tx += scale * (c1 M^-1 g - c2 M^-1 R K R^T M^-1 g), tth += scale * c1 gth / J.

    This is the exact response of the RK4 step to a constant generalized force (G^T dmu)
    for c1, c2 = (dt^2/2, dt^4/24) on positions and (dt, dt^3/6) on velocities.
    """
    nn = minv.shape[0]
    if c2 != 0.0:
        k_local_product(g, minv, gid, rot, indptr, indices, data, zk)
    for i in range(nn):
        gg = gid[i]
        c = rot[gg, 0]
        s = rot[gg, 1]
        z0 = zk[2 * i]
        z1 = zk[2 * i + 1]
        tx[2 * i] += scale * minv[i] * (c1 * g[2 * i] - c2 * (c * z0 - s * z1))
        tx[2 * i + 1] += scale * minv[i] * (c1 * g[2 * i + 1] - c2 * (s * z0 + c * z1))
    for gg in range(2):
        tth[gg] += scale * c1 * gth[gg] / jd[gg]


@njit(cache=True)
def contact_column(c1, c2, minv, gid, rot, indptr, indices, data, tie_node, cnod, cw, cn, g, zk, ccol):
    """Column of C = G W G^T belonging to the contact row (W = c1 M^-1 - c2 M^-1 K_g M^-1)."""
    nt = tie_node.shape[0]
    for side in range(2):
        sgn = 1.0 if side == 0 else -1.0
        for j in range(cnod.shape[1]):
            i = cnod[side, j]
            g[2 * i] += sgn * cw[side, j] * cn[0]
            g[2 * i + 1] += sgn * cw[side, j] * cn[1]
    if c2 != 0.0:
        k_local_product(g, minv, gid, rot, indptr, indices, data, zk)
    for k in range(nt):
        i = tie_node[k]
        gg = gid[i]
        c = rot[gg, 0]
        s = rot[gg, 1]
        # disk-frame components: -(c1 M^-1 R^T g - c2 M^-1 K R^T M^-1 g)
        gl0 = c * g[2 * i] + s * g[2 * i + 1]
        gl1 = -s * g[2 * i] + c * g[2 * i + 1]
        ccol[2 * k] = -minv[i] * (c1 * gl0 - c2 * zk[2 * i])
        ccol[2 * k + 1] = -minv[i] * (c1 * gl1 - c2 * zk[2 * i + 1])
    acc = 0.0
    for side in range(2):
        sgn = 1.0 if side == 0 else -1.0
        for j in range(cnod.shape[1]):
            i = cnod[side, j]
            gg = gid[i]
            c = rot[gg, 0]
            s = rot[gg, 1]
            z0 = zk[2 * i]
            z1 = zk[2 * i + 1]
            w0 = minv[i] * (c1 * g[2 * i] - c2 * (c * z0 - s * z1))
            w1 = minv[i] * (c1 * g[2 * i + 1] - c2 * (s * z0 + c * z1))
            acc += sgn * cw[side, j] * (cn[0] * w0 + cn[1] * w1)
    ccol[2 * nt] = acc
    # clear the scratch vectors
    for side in range(2):
        for j in range(cnod.shape[1]):
            i = cnod[side, j]
            g[2 * i] = 0.0
            g[2 * i + 1] = 0.0
    if c2 != 0.0:
        zk[:] = 0.0


@njit(cache=True)
def c_matvec(z, out, act, c1, c2, minv, tie_node, tie_gear, jd, bvec, rot, tb_i, tb_j, tb_b, ccol, yl, kz):
    """out = C' z with the structured C = G W G^T (ties: diagonal + disk rank-1 + local
    stiffness coupling of the tie nodes; contact: explicit column). ``act`` masks the contact."""
    nt = tie_node.shape[0]
    ic = 2 * nt
    sg0 = 0.0
    sg1 = 0.0
    for k in range(nt):
        m = minv[tie_node[k]]
        out[2 * k] = c1 * m * z[2 * k]
        out[2 * k + 1] = c1 * m * z[2 * k + 1]
        d = bvec[k, 0] * z[2 * k] + bvec[k, 1] * z[2 * k + 1]
        if tie_gear[k] == 0:
            sg0 += d
        else:
            sg1 += d
    for k in range(nt):
        sgv = sg0 / jd[0] if tie_gear[k] == 0 else sg1 / jd[1]
        out[2 * k] += c1 * bvec[k, 0] * sgv
        out[2 * k + 1] += c1 * bvec[k, 1] * sgv
    if c2 != 0.0:
        # ties are written in the disk frame, so the stiffness coupling needs no rotation
        for k in range(nt):
            m = minv[tie_node[k]]
            yl[2 * k] = m * z[2 * k]
            yl[2 * k + 1] = m * z[2 * k + 1]
            kz[2 * k] = 0.0
            kz[2 * k + 1] = 0.0
        for q in range(tb_i.shape[0]):
            i = tb_i[q]
            j = tb_j[q]
            kz[2 * i] += tb_b[q, 0, 0] * yl[2 * j] + tb_b[q, 0, 1] * yl[2 * j + 1]
            kz[2 * i + 1] += tb_b[q, 1, 0] * yl[2 * j] + tb_b[q, 1, 1] * yl[2 * j + 1]
        for k in range(nt):
            m = minv[tie_node[k]]
            out[2 * k] -= c2 * m * kz[2 * k]
            out[2 * k + 1] -= c2 * m * kz[2 * k + 1]
    if act:
        zc = z[ic]
        acc = 0.0
        for r in range(ic):
            out[r] += ccol[r] * zc
            acc += ccol[r] * z[r]
        out[ic] = acc + ccol[ic] * zc
    else:
        out[ic] = 0.0


@njit(cache=True)
def tie_row_sums(c1, c2, minv, tie_node, tie_gear, jd, bvec, rot, tb_i, tb_j, tb_b, rs):
    """Row sums of |C| over the tie block (for the infinity norm of appendix B)."""
    nt = tie_node.shape[0]
    sb0 = 0.0
    sb1 = 0.0
    for k in range(nt):
        a = abs(bvec[k, 0]) + abs(bvec[k, 1])
        if tie_gear[k] == 0:
            sb0 += a
        else:
            sb1 += a
    for k in range(nt):
        m = minv[tie_node[k]]
        sb = sb0 / jd[0] if tie_gear[k] == 0 else sb1 / jd[1]
        rs[2 * k] = c1 * m + c1 * abs(bvec[k, 0]) * sb
        rs[2 * k + 1] = c1 * m + c1 * abs(bvec[k, 1]) * sb
    if c2 != 0.0:
        for q in range(tb_i.shape[0]):
            i = tb_i[q]
            j = tb_j[q]
            f = c2 * minv[tie_node[i]] * minv[tie_node[j]]
            rs[2 * i] += f * (abs(tb_b[q, 0, 0]) + abs(tb_b[q, 0, 1]))
            rs[2 * i + 1] += f * (abs(tb_b[q, 1, 0]) + abs(tb_b[q, 1, 1]))


@njit(cache=True)
def accel_poly(n_acc, eps1, coef):
    """Coefficients of A_n as a polynomial in C_1 (eq. B.4-B.8) and the optimal b (eq. 24)."""
    size = coef.shape[0]
    cc = np.zeros(size)
    ca = np.zeros(size)
    cc[1] = 1.0
    ca[0] = 1.0
    om = 1.0
    ep = eps1
    tmp = np.zeros(size)
    for _ in range(2, n_acc + 1):
        bk = ep + om
        # A <- (bk - C) A
        tmp[:] = 0.0
        for i in range(size):
            if ca[i] == 0.0:
                continue
            tmp[i] += bk * ca[i]
            for j in range(size - i):
                tmp[i + j] -= cc[j] * ca[i]
        ca[:] = tmp
        # C <- C (bk - C)
        tmp[:] = 0.0
        for i in range(size):
            if cc[i] == 0.0:
                continue
            tmp[i] += bk * cc[i]
            for j in range(size - i):
                tmp[i + j] -= cc[j] * cc[i]
        cc[:] = tmp
        ep, om = ep * om, bk * bk / 4.0
    coef[:] = ca
    return 2.0 / (om + ep)


@njit(cache=True)
def iterate_pass(
    mode,
    e0,
    mu,
    pbar,
    c1,
    c2,
    eps_tie,
    tol,
    n_acc,
    max_iter,
    minv,
    tie_node,
    tie_gear,
    jd,
    bvec,
    rot,
    tb_i,
    tb_j,
    tb_b,
    ccol,
    work,
    stats,
):
    """The multiplier / contact-force iteration of eq. 19-21 for one pass.

    mode 1: displacement (contact error eq. 6); 2: velocity (eq. 22); 3: acceleration (eq. 23).
    ``e0`` is the error vector at the starting multipliers ``mu`` (updated in place); the
    solution of the equations of motion is affine in the multipliers with matrix C, so the
    error after a change dmu is e0 + C dmu. Returns (residual, iterations, converged,
    C dmu at the contact row).
    """
    nc = e0.shape[0]
    ic = nc - 1
    y = work[0]
    e = work[1]
    d = work[2]
    t1 = work[3]
    rs = work[4]
    yl = work[5]
    kz = work[6]
    y[:] = 0.0
    coef = np.zeros(33)
    tie_row_sums(c1, c2, minv, tie_node, tie_gear, jd, bvec, rot, tb_i, tb_j, tb_b, rs)
    last_act = -1
    nrm = 1.0
    bbar = 1.0
    deg = 0
    res = 0.0
    for it in range(max_iter + 1):
        for r in range(ic):
            e[r] = e0[r] + y[r]
        sval = e0[ic] + y[ic]
        p = mu[ic]
        if mode == 1:
            act = (p < 0.0) or (sval > 0.0)
        else:
            act = (pbar < 0.0) and ((sval > 0.0) or (p < 0.0))
        e[ic] = sval if act else 0.0
        res = 0.0
        for r in range(nc):
            if abs(e[r]) > res:
                res = abs(e[r])
        if res <= tol:
            stats[0] = res
            stats[1] = it
            return res, it, True, y[ic]
        if it == max_iter:
            break
        ia = 1 if act else 0
        if ia != last_act:
            nrm = 0.0
            for r in range(ic):
                v = rs[r] + (abs(ccol[r]) if act else 0.0)
                if v > nrm:
                    nrm = v
            epsa = eps_tie
            if act:
                crow = 0.0
                for r in range(ic):
                    crow += abs(ccol[r])
                if crow + abs(ccol[ic]) > nrm:
                    nrm = crow + abs(ccol[ic])
                ec = ccol[ic] - crow
                if ec < 0.05 * ccol[ic]:
                    ec = 0.05 * ccol[ic]
                if ec < epsa:
                    epsa = ec
            eps1 = epsa / nrm
            if eps1 > 0.999:
                eps1 = 0.999
            if eps1 < 1e-9:
                eps1 = 1e-9
            bbar = accel_poly(n_acc, eps1, coef)
            deg = 0
            for j in range(33):
                if coef[j] != 0.0:
                    deg = j
            last_act = ia
        # d = A_n(C_1) e by Horner
        for r in range(nc):
            d[r] = coef[deg] * e[r]
        for j in range(deg - 1, -1, -1):
            c_matvec(
                d,
                t1,
                act,
                c1,
                c2,
                minv,
                tie_node,
                tie_gear,
                jd,
                bvec,
                rot,
                tb_i,
                tb_j,
                tb_b,
                ccol,
                yl,
                kz,
            )
            for r in range(nc):
                d[r] = t1[r] / nrm + coef[j] * e[r]
        for r in range(nc):
            d[r] = -bbar * d[r] / nrm
        newp = min(0.0, p + d[ic])
        d[ic] = newp - p
        for r in range(nc):
            mu[r] += d[r]
        c_matvec(
            d,
            t1,
            True,
            c1,
            c2,
            minv,
            tie_node,
            tie_gear,
            jd,
            bvec,
            rot,
            tb_i,
            tb_j,
            tb_b,
            ccol,
            yl,
            kz,
        )
        for r in range(nc):
            y[r] += t1[r]
    stats[0] = res
    stats[1] = max_iter
    return res, max_iter, False, y[ic]


@njit(cache=True)
def direct_solve(
    mode,
    e0,
    mu,
    pbar,
    c1,
    c2,
    tol,
    max_ref,
    lb,
    perm,
    minv,
    tie_node,
    tie_gear,
    jd,
    bvec,
    rot,
    tb_i,
    tb_j,
    tb_b,
    ccol,
    work,
    stats,
):
    """Direct multiplier solve of one pass (:mod:`rotaflex.gear.kernels_direct`), checked.

    After the exact solve the error ``e0 + C dmu`` is re-evaluated with the structured
    :func:`c_matvec` and, if above ``tol``, refined (at most ``max_ref`` times). Same return
    values as :func:`iterate_pass` (iterations = number of solves).
    """
    nc = e0.shape[0]
    ic = nc - 1
    e = work[1]
    dmu = work[2]
    t1 = work[3]
    y = work[4]
    y[:] = 0.0
    buf = work[7:13]
    res = 0.0
    for it in range(max_ref + 1):
        for r in range(nc):
            e[r] = e0[r] + y[r]
        direct_pass(mode, e, mu, pbar, lb, perm, tie_gear, bvec, ccol, tol, dmu, buf)
        for r in range(nc):
            mu[r] += dmu[r]
        c_matvec(
            dmu, t1, True, c1, c2, minv, tie_node, tie_gear, jd, bvec, rot, tb_i, tb_j, tb_b, ccol, work[5], work[6]
        )
        for r in range(nc):
            y[r] += t1[r]
        res = 0.0
        for r in range(ic):
            res = max(res, abs(e0[r] + y[r]))
        sval = e0[ic] + y[ic]
        p = mu[ic]
        if mode == 1:
            act = (p < 0.0) or (sval > 0.0)
        else:
            act = (pbar < 0.0) and ((sval > 0.0) or (p < 0.0))
        if act:
            res = max(res, abs(sval))
        if res <= tol:
            stats[0] = res
            stats[1] = it + 1
            return res, it + 1, True, y[ic]
    stats[0] = res
    stats[1] = max_ref + 1
    return res, max_ref + 1, False, y[ic]


@njit(cache=True)
def solve_pass(
    direct,
    lb,
    perm,
    mode,
    e0,
    mu,
    pbar,
    c1,
    c2,
    eps_tie,
    tol,
    n_acc,
    max_iter,
    minv,
    tie_node,
    tie_gear,
    jd,
    bvec,
    rot,
    tb_i,
    tb_j,
    tb_b,
    ccol,
    work,
    stats,
):
    """Dispatch one pass to the iteration of eq. 19-24 or to the direct solve."""
    if direct:
        return direct_solve(
            mode,
            e0,
            mu,
            pbar,
            c1,
            c2,
            tol,
            3,
            lb,
            perm,
            minv,
            tie_node,
            tie_gear,
            jd,
            bvec,
            rot,
            tb_i,
            tb_j,
            tb_b,
            ccol,
            work,
            stats,
        )
    return iterate_pass(
        mode,
        e0,
        mu,
        pbar,
        c1,
        c2,
        eps_tie,
        tol,
        n_acc,
        max_iter,
        minv,
        tie_node,
        tie_gear,
        jd,
        bvec,
        rot,
        tb_i,
        tb_j,
        tb_b,
        ccol,
        work,
        stats,
    )


# ----------------------------------------------------------------------------- time stepping


@njit(cache=True)
def accelerations(
    x,
    phi,
    mu,
    tau_off,
    ct,
    rates,
    flank,
    nedge,
    cnod,
    cw,
    xloc,
    gid,
    cen,
    theta0,
    jd,
    minv,
    indptr,
    indices,
    data,
    tie_node,
    tie_gear,
    rsgn,
    tpar,
    rot,
    bvec,
    rx,
    wbuf,
    floc,
    fglob,
    tel,
    fc,
    fth,
    cn_s,
    a,
    alp,
    tab,
):
    """Accelerations at a (stage) state for given multipliers ``mu``; returns strain energy.

    The constraint force is ``G(q)^T mu`` with the Jacobian at the stage state: tie forces
    ``-R(phi) lambda`` turn with the disk; the contact force follows the contact point, whose
    parameters and normal at the step start (``ct`` = a, b, n_x, n_y) advance with their
    rates (``rates`` = da/dt, db/dt, dn_x/dt, dn_y/dt, appendix A) over ``tau_off`` seconds.
    ``tpar`` = (tau0, theta_2, theta_s).
    """
    set_rotation(phi, theta0, rot)
    tie_vectors(x, cen, tie_node, tie_gear, rot, bvec, rx)
    n0 = ct[2] + rates[2] * tau_off
    n1 = ct[3] + rates[3] * tau_off
    ln = math.hypot(n0, n1)
    cn_s[0] = n0 / ln
    cn_s[1] = n1 / ln
    if cnod.shape[1] == 3:
        nodes = np.empty(3, np.int64)
        w = np.empty(3)
        flank_weights(flank[0], nedge[0], ct[0] + rates[0] * tau_off, nodes, w)
        for j in range(3):
            cnod[0, j] = nodes[j]
            cw[0, j] = w[j]
        flank_weights(flank[1], nedge[1], ct[1] + rates[1] * tau_off, nodes, w)
        for j in range(3):
            cnod[1, j] = nodes[j]
            cw[1, j] = w[j]
    else:
        ws = np.empty(cnod.shape[1])
        for side in range(2):
            smooth_weights(tab[side], ct[side] + rates[side] * tau_off, ws)
            for j in range(cnod.shape[1]):
                cnod[side, j] = flank[side, j]
                cw[side, j] = ws[j]
    fc[:] = 0.0
    fth[:] = 0.0
    gt_apply(mu, tie_node, tie_gear, bvec, rot, cnod, cw, cn_s, fc, fth)
    energy = elastic_force(x, xloc, gid, cen, rot, indptr, indices, data, wbuf, floc, fglob, tel)
    nn = xloc.shape[0]
    for i in range(nn):
        a[2 * i] = minv[i] * (fglob[2 * i] + fc[2 * i])
        a[2 * i + 1] = minv[i] * (fglob[2 * i + 1] + fc[2 * i + 1])
    for g in range(2):
        tau = ramp_torque(rsgn[g] * phi[g], tpar[0], tpar[1], tpar[2])
        alp[g] = (tau + tel[g] + fth[g]) / jd[g]
    return energy


@njit(cache=True)
def kinetic_energy(v, om, minv, jd):
    e = 0.5 * (jd[0] * om[0] ** 2 + jd[1] * om[1] ** 2)
    for i in range(minv.shape[0]):
        e += 0.5 * (v[2 * i] ** 2 + v[2 * i + 1] ** 2) / minv[i]
    return e


@njit(cache=True)
def run_steps(
    n_steps,
    rec_every,
    mi_gid,
    mi_indptr,
    mi_indices,
    mi_tie_node,
    mi_tie_gear,
    mi_flank,
    mi_nedge,
    mi_tb_i,
    mi_tb_j,
    mf_xloc,
    mf_minv,
    mf_data,
    mf_cen,
    mf_theta0,
    mf_jd,
    mf_sig,
    mf_tb_b,
    mf_rsgn,
    par,
    ipar,
    x,
    v,
    a,
    phi,
    om,
    alp,
    mu,
    cres,
    cnod,
    cw,
    sc,
    out,
    out_mu,
    info,
    dfac,
    dperm,
    tab,
    mloc,
):
    """Advance ``n_steps`` RK4 steps with the three constraint passes per step.

    ``par`` = (dt, tau0, theta_2, theta_s, tol1, tol2, tol3, eps_tie1, eps_tie2, eps_tie3
    [, restitution e]);
    ``ipar`` = (n_accel, max_iter, n_points, rec_row, initialise, direct);
    with direct = 1 the passes use the exact solve of :func:`direct_solve` with the banded
    factors ``dfac`` (3, n, bw + 1) of the tie block and the row order ``dperm``. ``sc`` carries running
    scalars: (t, W_ext, D_vel, E_el, -, F_peak, res1, res2, res3, it1, it2, it3, s_final,
    shat, n_impacts, tie_res, pbar, phat, tau_A, tau_B, contact rates (4)). Records are written every
    ``rec_every`` steps into ``out`` starting at row ``ipar[3]``; returns (status, next row).
    """
    dt = par[0]
    tpar = par[1:4]
    rest = par[10] if par.shape[0] > 10 else 0.0  # coefficient of restitution e
    tol1 = par[4]
    tol2 = par[5]
    tol3 = par[6]
    n_acc = ipar[0]
    max_iter = ipar[1]
    mpts = ipar[2]
    row = ipar[3]
    nn = mf_xloc.shape[0]
    nd = 2 * nn
    nt = mi_tie_node.shape[0]
    nc = 2 * nt + 1
    ic = nc - 1
    rot = np.empty((2, 2))
    bvec = np.empty((nt, 2))
    rx = np.empty((nt, 2))
    wbuf = np.empty(nd)
    floc = np.empty(nd)
    fglob = np.empty(nd)
    fc = np.zeros(nd)
    tel = np.empty(2)
    fth = np.zeros(2)
    gsc = np.zeros(nd)
    gth = np.zeros(2)
    zk = np.zeros(nd)
    xs = np.empty(nd)
    vs = np.empty(nd)
    ak = np.empty(nd)
    xsum = np.empty(nd)
    asum = np.empty(nd)
    ps = np.empty(2)
    os_ = np.empty(2)
    alk = np.empty(2)
    psum = np.empty(2)
    osum = np.empty(2)
    phi_t = np.empty(2)
    pa = np.empty((mpts, 2))
    ma = np.empty((mpts, 2))
    pb = np.empty((mpts, 2))
    mb = np.empty((mpts, 2))
    va = np.empty((mpts, 2))
    mva = np.empty((mpts, 2))
    vb = np.empty((mpts, 2))
    mvb = np.empty((mpts, 2))
    cn = np.empty(2)
    cn_s = np.empty(2)
    nw = cnod.shape[1]
    cnod_t = np.empty((2, nw), np.int64)
    cw_t = np.empty((2, nw))
    ct = np.zeros(4)
    rates = np.zeros(4)
    for j in range(4):
        rates[j] = sc[20 + j]  # contact-parameter rates carried over from the previous call
    zero4 = np.zeros(4)
    ccol = np.zeros(nc)
    e0 = np.zeros(nc)
    mu0 = np.zeros(nc)
    work = np.zeros((13, nc))
    stats = np.zeros(2)
    c11 = dt * dt / 2.0
    c12 = dt**4 / 24.0
    c21 = dt
    c22 = dt**3 / 6.0
    cn[0] = cres[3]
    cn[1] = cres[4]
    init = ipar[4] == 1
    direct = ipar[5] == 1
    if init:
        if not contact_geometry_smooth(
            x, phi, mi_flank, mi_nedge, mf_sig, mpts, pa, ma, pb, mb, cres, cnod, cw, mf_theta0, tab, mloc
        ):
            info[0] = sc[0]
            return 4, row
        cn[0] = cres[3]
        cn[1] = cres[4]
    for step in range(n_steps + (1 if init else 0)):
        t = sc[0]
        initial = init and step == 0
        if not initial:
            # ---- constraint Jacobian of the step start, multipliers mu held over the step
            ct[0] = cres[0]
            ct[1] = cres[1]
            ct[2] = cn[0]
            ct[3] = cn[1]
            phi_t[0] = phi[0]
            phi_t[1] = phi[1]
            tau_old0 = ramp_torque(mf_rsgn[0] * phi[0], tpar[0], tpar[1], tpar[2])
            tau_old1 = ramp_torque(mf_rsgn[1] * phi[1], tpar[0], tpar[1], tpar[2])
            # ---- classical RK4 (k1 = stored consistent acceleration of the step start)
            for r in range(nd):
                xsum[r] = v[r]
                asum[r] = a[r]
            for g in range(2):
                psum[g] = om[g]
                osum[g] = alp[g]
            for stage in range(3):
                hh = 0.5 * dt if stage < 2 else dt
                wgt = 2.0 if stage < 2 else 1.0
                if stage == 0:
                    for r in range(nd):
                        xs[r] = x[r] + hh * v[r]
                        vs[r] = v[r] + hh * a[r]
                    for g in range(2):
                        ps[g] = phi[g] + hh * om[g]
                        os_[g] = om[g] + hh * alp[g]
                else:
                    for r in range(nd):
                        xs[r] = x[r] + hh * vs[r]
                        vs[r] = v[r] + hh * ak[r]
                    for g in range(2):
                        ps[g] = phi[g] + hh * os_[g]
                        os_[g] = om[g] + hh * alk[g]
                accelerations(
                    xs,
                    ps,
                    mu,
                    hh,
                    ct,
                    rates,
                    mi_flank,
                    mi_nedge,
                    cnod_t,
                    cw_t,
                    mf_xloc,
                    mi_gid,
                    mf_cen,
                    mf_theta0,
                    mf_jd,
                    mf_minv,
                    mi_indptr,
                    mi_indices,
                    mf_data,
                    mi_tie_node,
                    mi_tie_gear,
                    mf_rsgn,
                    tpar,
                    rot,
                    bvec,
                    rx,
                    wbuf,
                    floc,
                    fglob,
                    tel,
                    fc,
                    fth,
                    cn_s,
                    ak,
                    alk,
                    tab,
                )
                for r in range(nd):
                    xsum[r] += wgt * vs[r]
                    asum[r] += wgt * ak[r]
                for g in range(2):
                    psum[g] += wgt * os_[g]
                    osum[g] += wgt * alk[g]
            for r in range(nd):
                x[r] += dt / 6.0 * xsum[r]
                v[r] += dt / 6.0 * asum[r]
            for g in range(2):
                phi[g] += dt / 6.0 * psum[g]
                om[g] += dt / 6.0 * osum[g]
            t = t + dt
            # ---- contact search at the predicted state
            if not contact_geometry_smooth(
                x, phi, mi_flank, mi_nedge, mf_sig, mpts, pa, ma, pb, mb, cres, cnod, cw, mf_theta0, tab, mloc
            ):
                info[0] = t
                return 4, row
            cn[0] = cres[3]
            cn[1] = cres[4]
            # approach velocity of the predicted state (before the passes): impact reference
            sh_pred = 0.0
            for j in range(nw):
                i = cnod[0, j]
                sh_pred += cw[0, j] * (cn[0] * v[2 * i] + cn[1] * v[2 * i + 1])
                i = cnod[1, j]
                sh_pred -= cw[1, j] * (cn[0] * v[2 * i] + cn[1] * v[2 * i + 1])
            ke_pred = kinetic_energy(v, om, mf_minv, mf_jd)
            for r in range(nd):
                xsum[r] = x[r]  # predicted state (strain energy of a closing step)
            psum[0] = phi[0]
            psum[1] = phi[1]
            set_rotation(phi, mf_theta0, rot)
            tie_vectors(x, mf_cen, mi_tie_node, mi_tie_gear, rot, bvec, rx)
            # ---- pass 1: displacement constraints (eq. 8, 19)
            for k in range(nt):
                i = mi_tie_node[k]
                e0[2 * k] = -(rx[k, 0] - mf_xloc[i, 0])
                e0[2 * k + 1] = -(rx[k, 1] - mf_xloc[i, 1])
            e0[ic] = -cres[2]
            contact_column(
                c11, c12, mf_minv, mi_gid, rot, mi_indptr, mi_indices, mf_data, mi_tie_node, cnod, cw, cn, gsc, zk, ccol
            )
            mu0[:] = mu
            res, its, ok, yc = solve_pass(
                direct,
                dfac[0],
                dperm,
                1,
                e0,
                mu,
                0.0,
                c11,
                c12,
                par[7],
                tol1,
                n_acc,
                max_iter,
                mf_minv,
                mi_tie_node,
                mi_tie_gear,
                mf_jd,
                bvec,
                rot,
                mi_tb_i,
                mi_tb_j,
                mf_tb_b,
                ccol,
                work,
                stats,
            )
            if not ok:
                info[0] = t
                info[1] = res
                info[2] = tol1
                return 1, row
            sc[6] = max(sc[6], res)
            sc[9] = max(sc[9], its)
            sc[12] = e0[ic] + yc
            for r in range(nc):
                e0[r] = mu[r] - mu0[r]
            gsc[:] = 0.0
            gth[:] = 0.0
            gt_apply(e0, mi_tie_node, mi_tie_gear, bvec, rot, cnod, cw, cn, gsc, gth)
            # RK4 positions and velocities with the new multipliers (affine response)
            k_local_product(gsc, mf_minv, mi_gid, rot, mi_indptr, mi_indices, mf_data, zk)
            for i in range(nn):
                gg = mi_gid[i]
                cc = rot[gg, 0]
                ss = rot[gg, 1]
                kx = cc * zk[2 * i] - ss * zk[2 * i + 1]
                ky = ss * zk[2 * i] + cc * zk[2 * i + 1]
                x[2 * i] += mf_minv[i] * (c11 * gsc[2 * i] - c12 * kx)
                x[2 * i + 1] += mf_minv[i] * (c11 * gsc[2 * i + 1] - c12 * ky)
                v[2 * i] += mf_minv[i] * (c21 * gsc[2 * i] - c22 * kx)
                v[2 * i + 1] += mf_minv[i] * (c21 * gsc[2 * i + 1] - c22 * ky)
            zk[:] = 0.0
            for g in range(2):
                phi[g] += c11 * gth[g] / mf_jd[g]
                om[g] += c21 * gth[g] / mf_jd[g]
            gsc[:] = 0.0
            pbar = mu[ic]
            sc[16] = pbar
            set_rotation(phi, mf_theta0, rot)
            tie_vectors(x, mf_cen, mi_tie_node, mi_tie_gear, rot, bvec, rx)
            # ---- pass 2: velocity constraints (eq. 15, 20, 22)
            ke0 = kinetic_energy(v, om, mf_minv, mf_jd)
            closing = pbar < 0.0 and mu0[ic] == 0.0
            if closing:
                # a contact closes: the displacement pass stops the penetration with a force
                # held over the step, i.e. it takes part in the impact; its change of kinetic
                # + strain energy is counted in D (strain part added after pass 3)
                set_rotation(psum, mf_theta0, rot)
                se_pred = elastic_force(
                    xsum, mf_xloc, mi_gid, mf_cen, rot, mi_indptr, mi_indices, mf_data, wbuf, floc, fglob, tel
                )
                set_rotation(phi, mf_theta0, rot)
                sc[2] += ke_pred + se_pred - ke0
            for k in range(nt):
                i = mi_tie_node[k]
                g = mi_tie_gear[k]
                cc = rot[g, 0]
                ss = rot[g, 1]
                e0[2 * k] = -(cc * v[2 * i] + ss * v[2 * i + 1]) + bvec[k, 0] * om[g]
                e0[2 * k + 1] = -(-ss * v[2 * i] + cc * v[2 * i + 1]) + bvec[k, 1] * om[g]
            sh = 0.0
            for j in range(nw):
                i = cnod[0, j]
                sh += cw[0, j] * (cn[0] * v[2 * i] + cn[1] * v[2 * i + 1])
                i = cnod[1, j]
                sh -= cw[1, j] * (cn[0] * v[2 * i] + cn[1] * v[2 * i + 1])
            vtgt = 0.0
            if pbar < 0.0 and sh > tol2 and mu0[ic] == 0.0:
                sc[14] += 1.0
            if rest > 0.0 and pbar < 0.0 and sh_pred > tol2 and mu0[ic] == 0.0:
                # Newton impact law: target -e x (approach velocity before the displacement
                # pass, which already removes part of it) instead of 0
                vtgt = -rest * sh_pred
            e0[ic] = sh - vtgt
            contact_column(
                c21, c22, mf_minv, mi_gid, rot, mi_indptr, mi_indices, mf_data, mi_tie_node, cnod, cw, cn, gsc, zk, ccol
            )
            mu0[:] = mu
            res, its, ok, yc = solve_pass(
                direct,
                dfac[1],
                dperm,
                2,
                e0,
                mu,
                pbar,
                c21,
                c22,
                par[8],
                tol2,
                n_acc,
                max_iter,
                mf_minv,
                mi_tie_node,
                mi_tie_gear,
                mf_jd,
                bvec,
                rot,
                mi_tb_i,
                mi_tb_j,
                mf_tb_b,
                ccol,
                work,
                stats,
            )
            if not ok:
                info[0] = t
                info[1] = res
                info[2] = tol2
                return 2, row
            sc[7] = max(sc[7], res)
            sc[10] = max(sc[10], its)
            sc[13] = e0[ic] + yc + vtgt
            sc[17] = mu[ic]
            for r in range(nc):
                e0[r] = mu[r] - mu0[r]
            gsc[:] = 0.0
            gth[:] = 0.0
            gt_apply(e0, mi_tie_node, mi_tie_gear, bvec, rot, cnod, cw, cn, gsc, gth)
            respond(gsc, gth, c21, c22, mf_minv, mi_gid, rot, mf_jd, mi_indptr, mi_indices, mf_data, zk, v, om, 1.0)
            zk[:] = 0.0
            gsc[:] = 0.0
            sc[2] += ke0 - kinetic_energy(v, om, mf_minv, mf_jd)
            # external work (trapezoidal in the disk angles)
            tau_new0 = ramp_torque(mf_rsgn[0] * phi[0], tpar[0], tpar[1], tpar[2])
            tau_new1 = ramp_torque(mf_rsgn[1] * phi[1], tpar[0], tpar[1], tpar[2])
            sc[1] += 0.5 * (tau_old0 + tau_new0) * (phi[0] - phi_t[0])
            sc[1] += 0.5 * (tau_old1 + tau_new1) * (phi[1] - phi_t[1])
            sc[18] = tau_new0
            sc[19] = tau_new1
        else:
            pbar = -1.0 if cres[2] <= 0.0 else 0.0
            closing = False
        # ---- pass 3: acceleration constraints (eq. 17, 21, 23)
        ct[0] = cres[0]
        ct[1] = cres[1]
        ct[2] = cn[0]
        ct[3] = cn[1]
        eel = accelerations(
            x,
            phi,
            mu,
            0.0,
            ct,
            zero4,
            mi_flank,
            mi_nedge,
            cnod,
            cw,
            mf_xloc,
            mi_gid,
            mf_cen,
            mf_theta0,
            mf_jd,
            mf_minv,
            mi_indptr,
            mi_indices,
            mf_data,
            mi_tie_node,
            mi_tie_gear,
            mf_rsgn,
            tpar,
            rot,
            bvec,
            rx,
            wbuf,
            floc,
            fglob,
            tel,
            fc,
            fth,
            cn_s,
            a,
            alp,
            tab,
        )
        for k in range(nt):
            i = mi_tie_node[k]
            g = mi_tie_gear[k]
            cc = rot[g, 0]
            ss = rot[g, 1]
            al0 = cc * a[2 * i] + ss * a[2 * i + 1]
            al1 = -ss * a[2 * i] + cc * a[2 * i + 1]
            vl0 = cc * v[2 * i] + ss * v[2 * i + 1]
            vl1 = -ss * v[2 * i] + cc * v[2 * i + 1]
            # -Phi_ddot = -R^T a + b alpha + omega^2 R^T (x - c) + 2 omega J R^T v
            e0[2 * k] = -al0 + bvec[k, 0] * alp[g] + om[g] ** 2 * rx[k, 0] - 2 * om[g] * vl1
            e0[2 * k + 1] = -al1 + bvec[k, 1] * alp[g] + om[g] ** 2 * rx[k, 1] + 2 * om[g] * vl0
        # sliding terms of the relative normal acceleration (appendix A)
        if nw == 3:
            sample_flank(v, mi_flank[0], mi_nedge[0], va)
            sample_flank(v, mi_flank[1], mi_nedge[1], vb)
        else:
            sample_smooth(v, mi_flank[0], tab[0], mloc[0], mf_theta0[0] + phi[0], om[0], True, va)
            sample_smooth(v, mi_flank[1], tab[1], mloc[1], mf_theta0[1] + phi[1], om[1], True, vb)
        spline_second(va, mva)
        spline_second(vb, mvb)
        hs, _ad, _bd = sliding_terms(pa, ma, va, mva, pb, mb, vb, mvb, mf_sig[0], mf_sig[1], cres, rates)
        for j in range(4):
            sc[20 + j] = rates[j]
        sa = hs
        for j in range(nw):
            i = cnod[0, j]
            sa += cw[0, j] * (cn[0] * a[2 * i] + cn[1] * a[2 * i + 1])
            i = cnod[1, j]
            sa -= cw[1, j] * (cn[0] * a[2 * i] + cn[1] * a[2 * i + 1])
        e0[ic] = sa
        contact_column(
            1.0, 0.0, mf_minv, mi_gid, rot, mi_indptr, mi_indices, mf_data, mi_tie_node, cnod, cw, cn, gsc, zk, ccol
        )
        mu0[:] = mu
        res, its, ok, yc = solve_pass(
            direct,
            dfac[2],
            dperm,
            3,
            e0,
            mu,
            pbar,
            1.0,
            0.0,
            par[9],
            tol3,
            n_acc,
            max_iter,
            mf_minv,
            mi_tie_node,
            mi_tie_gear,
            mf_jd,
            bvec,
            rot,
            mi_tb_i,
            mi_tb_j,
            mf_tb_b,
            ccol,
            work,
            stats,
        )
        if not ok:
            info[0] = t
            info[1] = res
            info[2] = tol3
            return 3, row
        sc[8] = max(sc[8], res)
        sc[11] = max(sc[11], its)
        for r in range(nc):
            e0[r] = mu[r] - mu0[r]
        gsc[:] = 0.0
        gth[:] = 0.0
        gt_apply(e0, mi_tie_node, mi_tie_gear, bvec, rot, cnod, cw, cn, gsc, gth)
        for i in range(nn):
            a[2 * i] += mf_minv[i] * gsc[2 * i]
            a[2 * i + 1] += mf_minv[i] * gsc[2 * i + 1]
        for g in range(2):
            alp[g] += gth[g] / mf_jd[g]
        gsc[:] = 0.0
        sc[0] = t
        sc[3] = eel
        if closing:
            sc[2] -= eel  # strain energy after the displacement pass (positions unchanged since)
        force = -mu[ic]
        if force > sc[5]:
            sc[5] = force
        tr = 0.0
        for k in range(nt):
            i = mi_tie_node[k]
            tr = max(tr, max(abs(rx[k, 0] - mf_xloc[i, 0]), abs(rx[k, 1] - mf_xloc[i, 1])))
        sc[15] = max(sc[15], tr)
        if initial:
            sc[12] = -cres[2]
        # ---- record
        if (not initial) and ((step + (0 if init else 1)) % rec_every == 0) and row < out.shape[0]:
            out[row, 0] = t
            out[row, 1] = phi[0]
            out[row, 2] = phi[1]
            out[row, 3] = om[0]
            out[row, 4] = om[1]
            out[row, 5] = force
            out[row, 6] = -sc[16]
            out[row, 7] = -sc[17]
            out[row, 8] = -sc[12]
            for side in range(2):
                px = 0.0
                py = 0.0
                for j in range(nw):
                    i = cnod[side, j]
                    px += cw[side, j] * x[2 * i]
                    py += cw[side, j] * x[2 * i + 1]
                out[row, 9 + 2 * side] = px
                out[row, 10 + 2 * side] = py
            out[row, 13] = cres[0]
            out[row, 14] = cres[1]
            out[row, 15] = kinetic_energy(v, om, mf_minv, mf_jd)
            out[row, 16] = eel
            out[row, 17] = sc[1]
            out[row, 18] = sc[2]
            out[row, 19] = sc[6]
            out[row, 20] = sc[7]
            out[row, 21] = sc[8]
            out[row, 22] = sc[9]
            out[row, 23] = sc[10]
            out[row, 24] = sc[11]
            out[row, 25] = sc[5]
            out[row, 26] = sc[18]
            out[row, 27] = sc[19]
            out[row, 28] = cres[5]
            out[row, 29] = sc[13]
            out[row, 30] = sc[15]
            out[row, 31] = sc[14]
            for r in range(ic):
                out_mu[row, r] = mu[r]
            row += 1
            for q in (5, 6, 7, 8, 9, 10, 11, 15):
                sc[q] = 0.0
    return 0, row
