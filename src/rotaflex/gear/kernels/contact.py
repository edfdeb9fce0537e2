"""Contact surfaces and contact search (compiled): cubic splines through the flank points, the
minimum-normal-distance search with its tip-corner branches, the sliding terms of the relative
normal acceleration (appendix A of the paper), the optional smoothed surfaces, and the search of
every contact pair of a step (:func:`search_pairs`).

Arrays of a pair carry the gear index first (``flank[g]``, ``nedge[g]``, ``sig[g]``), so gear A
and gear B may have different flank discretisations (flank ids padded to a common length, the
used part given by ``nedge[g]``). The contact result ``cres`` of a pair is
``(a, b, gap s, n_x, n_y, case, branch, ok)``; ``s > 0`` is a penetration.
"""

from __future__ import annotations

import math

import numpy as np

from rotaflex.core.compiled import entry, inner


@entry
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


@entry
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


@inner
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


@inner
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


#: largest change of the flank parameter of A accepted from the secant iteration in one search
#: (the contact point moves by ~1e-5 of the flank per step; the paper's runs stay far below)
MAX_SEARCH_JUMP = 0.5


@entry
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
    if conv and abs(a1 - a0) > MAX_SEARCH_JUMP:
        # a common normal far from the warm start (the secant can leave the flank and meet a
        # spurious root beyond the tip, e.g. near the start of contact of a small pinion):
        # take the root nearest the warm start, or the corner contact, as below
        conv = False
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


@inner
def _cross(ax, ay, bx, by):
    return ax * by - ay * bx


@entry
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


@entry
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


@entry
def sample_flank(x, flank, nedge, out):
    """Surface data points: the FE flank edge (quadratic) evaluated at M uniform parameters."""
    mpts = out.shape[0]
    nodes = np.empty(3, np.int64)
    w = np.empty(3)
    for k in range(mpts):
        flank_weights(flank, nedge, k / (mpts - 1), nodes, w)
        for d in range(2):
            out[k, d] = w[0] * x[2 * nodes[0] + d] + w[1] * x[2 * nodes[1] + d] + w[2] * x[2 * nodes[2] + d]


@entry
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


@entry
def smooth_weights(tab, s, w):
    """Weights ``w`` (n_flank,) of the flank nodes at parameter ``s`` of the smoothed surface:
    linear interpolation in the table ``tab`` (NT, n_flank) of a uniform parameter grid."""
    nt = tab.shape[0]
    z = min(max(s, 0.0), 1.0) * (nt - 1)
    i = min(int(z), nt - 2)
    f = z - i
    for n in range(tab.shape[1]):
        w[n] = (1.0 - f) * tab[i, n] + f * tab[i + 1, n]


@entry
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


@inner
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
    sample_smooth(x, flank[0], tab[0], mloc[0], theta0[0] + phi[0], 1.0, np.bool_(False), pa)
    sample_smooth(x, flank[1], tab[1], mloc[1], theta0[1] + phi[1], 1.0, np.bool_(False), pb)
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


@inner
def corner_contact(pa, ma, pb, mb, sig_a, sig_b, which, a0, b0, res):
    """Tip-corner contact outside the path of contact (same output as ``contact_search``).

    ``which`` 1: the tip corner of B projected on A's flank, A's normal (before the start of
    contact, where the common normal of the splines lies beyond B's tip); 2: the tip corner of
    A projected on B, B's normal reversed (after the end of contact). These are the corner
    branches of :func:`rotaflex.gear.kernels.contact_search`, used directly because the
    common-normal iteration can converge to a distant pair before the teeth meet.
    """
    bq = np.empty((3, 2))
    bs = np.empty((3, 2))
    if which == 1:
        spline_eval(pb, mb, 1.0, bs)
        cx, cy = bs[0, 0], bs[0, 1]
        a = a0
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
        spline_eval(pa, ma, 1.0, bq)
        cx, cy = bq[0, 0], bq[0, 1]
        a = 1.0
        b = b0
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
    res[0] = a
    res[1] = b
    res[2] = (bs[0, 0] - bq[0, 0]) * n0 + (bs[0, 1] - bq[0, 1]) * n1
    res[3] = n0
    res[4] = n1
    res[5] = which
    res[6] = q
    res[7] = 1.0


@entry
def pair_contact(x, phi, flank, nedge, sig, mpts, pa, ma, pb, mb, cres, cnod, cw, mode, theta0, tab, mloc):
    """Contact geometry of one pair. ``mode`` 0 = minimum-distance search, 1 / 2 = the tip-corner
    projection of :func:`corner_contact`. ``cnod.shape[1] == 3``: the paper's surfaces and 3-node
    force; otherwise the smoothed surfaces of ``tab``/``mloc`` (:func:`contact_geometry_smooth`).
    Returns False on failure."""
    if mode == 0:
        return contact_geometry_smooth(
            x, phi, flank, nedge, sig, mpts, pa, ma, pb, mb, cres, cnod, cw, theta0, tab, mloc
        )
    nw = cnod.shape[1]
    if nw == 3:
        sample_flank(x, flank[0], nedge[0], pa)
        sample_flank(x, flank[1], nedge[1], pb)
    else:
        sample_smooth(x, flank[0], tab[0], mloc[0], theta0[0] + phi[0], 1.0, np.bool_(False), pa)
        sample_smooth(x, flank[1], tab[1], mloc[1], theta0[1] + phi[1], 1.0, np.bool_(False), pb)
    spline_second(pa, ma)
    spline_second(pb, mb)
    corner_contact(pa, ma, pb, mb, sig[0], sig[1], mode, cres[0], cres[1], cres)
    if nw == 3:
        nodes = np.empty(3, np.int64)
        w = np.empty(3)
        for side in range(2):
            flank_weights(flank[side], nedge[side], cres[side], nodes, w)
            for j in range(3):
                cnod[side, j] = nodes[j]
                cw[side, j] = w[j]
    else:
        ws = np.empty(nw)
        for side in range(2):
            smooth_weights(tab[side], cres[side], ws)
            for j in range(nw):
                cnod[side, j] = flank[side, j]
                cw[side, j] = ws[j]
    return True


@inner
def search_pairs(x, phi, m_arr, mpts, lo, hi, corners, pa, ma, pb, mb, cres, cnod, cw, spair):
    """Contact search of every pair whose nominal contact angle ``psi[j] + rsgn[0] phi[0]`` lies
    in the mesh window [lo, hi] (one pair, no window: ``lo, hi = -inf, inf``); the pair's data
    (flanks, warm-start table ``wtab``, smoothed surfaces) from ``m_arr``, the
    :class:`~rotaflex.gear.kernels.arrays.ModelArrays`.

    A pair entering the window is warm-started from ``wtab`` (involute contact parameters on a
    uniform grid of the contact angle over [0, theta_s]; a table of one row: no warm start, the
    previous parameters are the start). Before the start of contact (psi < 0) the tip corner of
    B is projected on A, after its end (psi > theta_s) the tip corner of A on B
    (:func:`corner_contact`), in between the minimum-distance search (``corners`` False: always
    the search). A pair outside the window is not searched: gap 1 m, case -1, zero-weight
    contact row. ``spair[j, 5]`` is set to 1 for a pair in the window, else 0.
    Returns False if a search failed."""
    flank, nedge, sig, psi0, wtab = m_arr.flank, m_arr.nedge, m_arr.sig, m_arr.psi, m_arr.wtab
    rsgn0, theta0, tab, mloc = m_arr.rsgn[0], m_arr.theta0, m_arr.tab, m_arr.mloc
    npair = cres.shape[0]
    nw = wtab.shape[0]
    for jp in range(npair):
        psi = psi0[jp] + rsgn0 * phi[0]
        if psi >= lo and psi <= hi:
            if spair[jp, 5] == 0.0 and nw > 1:
                z = (min(max(psi, 0.0), wtab[nw - 1, 2]) / wtab[nw - 1, 2]) * (nw - 1)
                k = min(int(z), nw - 2)
                f = z - k
                cres[jp, 0] = (1 - f) * wtab[k, 0] + f * wtab[k + 1, 0]
                cres[jp, 1] = (1 - f) * wtab[k, 1] + f * wtab[k + 1, 1]
            mode = 0
            if corners and psi < 0.0:
                mode = 1
            elif corners and psi > wtab[nw - 1, 2]:
                mode = 2
            if not pair_contact(
                x,
                phi,
                flank[jp],
                nedge[jp],
                sig,
                mpts,
                pa[jp],
                ma[jp],
                pb[jp],
                mb[jp],
                cres[jp],
                cnod[jp],
                cw[jp],
                mode,
                theta0,
                tab[jp],
                mloc[jp],
            ):
                return False
            spair[jp, 5] = 1.0
        else:
            spair[jp, 5] = 0.0
            cres[jp, 2] = 1.0
            cres[jp, 3] = 1.0
            cres[jp, 4] = 0.0
            cres[jp, 5] = -1.0
            for side in range(2):
                for j in range(cnod.shape[2]):
                    cnod[jp, side, j] = flank[jp, side, j]
                    cw[jp, side, j] = 0.0
    return True
