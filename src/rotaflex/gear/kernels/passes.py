"""Constraint passes (compiled): the operator ``C = G W G^T`` of the ties and the contact rows,
the accelerated multiplier iteration of eq. 19-24 / appendix B (:func:`iterate_pass`) and the
direct solve (:func:`direct_solve`), for any number of contact pairs.

Constraint rows ``2*k + c`` are the ties of tie node ``k`` (disk-frame components), then row
``2*nt + j`` is the contact of pair ``j``. The solution of the equations of motion over a pass is
affine in the multipliers, so the error after a change ``dmu`` is ``e + C dmu`` with
``W = c1 M^-1 - c2 M^-1 K M^-1`` ((c1, c2) = (dt^2/2, dt^4/24) positions, (dt, dt^3/6)
velocities, (1, 0) accelerations). ``ccol[j]`` is the column of C of contact row ``j``.

Direct solve: the tie block ``C_t = C_0 + sum_g (c1 / J_g) b_g b_g^T`` has a constant part
``C_0 = c1 M_t^-1 - c2 M_t^-1 K_tt M_t^-1`` factored once per pass type (banded Cholesky after a
reverse Cuthill-McKee ordering, :func:`factor_tie_blocks`); the disk terms ``b_g`` enter through
the Woodbury identity (2 x 2) and the contact rows through their Schur complement. Unilateral
contact by active set: a row whose error with its force released is above ``tol`` (and which may
carry force in this pass) is made active; with several pairs, a row whose solved force would be
tensile is released and the active rows solved again. For one contact row this is the exact
solution of the linear complementarity problem.
"""

from __future__ import annotations

import numpy as np

from rotaflex.core.compiled import entry, inner


@entry
def k_local_product(g, m, rot, zk):
    """zk += K R^T M^-1 g (local frame) for a sparse g (only its non-zero nodes are visited);
    ``m`` the :class:`~rotaflex.gear.kernels.arrays.ModelArrays` (K in 2 x 2 blocks, applied
    as its transpose, which equals K to round-off: each ``zk`` entry gets its terms in the order
    of the rows)."""
    minv, gid, kptr, kcol, kblk = m.minv, m.gid, m.kptr, m.kcol, m.kblk
    nn = minv.shape[0]
    z2 = zk.reshape((nn, 2))
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
        for b in range(kptr[i], kptr[i + 1]):
            j = kcol[b]
            z2[j, 0] += kblk[b, 0] * l0
            z2[j, 1] += kblk[b, 1] * l0
        for b in range(kptr[i], kptr[i + 1]):
            j = kcol[b]
            z2[j, 0] += kblk[b, 2] * l1
            z2[j, 1] += kblk[b, 3] * l1


@inner(_nrt=False)
def respond(g, gth, c1, c2, m, rot, zk, tx, tth, scale):
    """tx += scale * (c1 M^-1 g - c2 M^-1 R K R^T M^-1 g), tth += scale * c1 gth / J.

    This is the exact response of the RK4 step to a constant generalized force (G^T dmu)
    for c1, c2 = (dt^2/2, dt^4/24) on positions and (dt, dt^3/6) on velocities.
    """
    minv, gid, jd = m.minv, m.gid, m.inertia
    nn = minv.shape[0]
    if c2 != 0.0:
        k_local_product(g, m, rot, zk)
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


@inner(_nrt=False)
def tie_row_sums(c1, c2, m_arr, bvec, rs):
    """Row sums of |C| over the tie block (for the infinity norm of appendix B)."""
    minv, tie_node, tie_gear, jd = m_arr.minv, m_arr.tie_node, m_arr.tie_gear, m_arr.inertia
    tb_ptr, tb_j, tb_b = m_arr.tb_ptr, m_arr.tb_j, m_arr.tb_b
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
        r0 = c1 * m + c1 * abs(bvec[k, 0]) * sb
        r1 = c1 * m + c1 * abs(bvec[k, 1]) * sb
        if c2 != 0.0:
            for q in range(tb_ptr[k], tb_ptr[k + 1]):
                f = c2 * m * minv[tie_node[tb_j[q]]]
                r0 += f * (abs(tb_b[q, 0]) + abs(tb_b[q, 1]))
                r1 += f * (abs(tb_b[q, 2]) + abs(tb_b[q, 3]))
        rs[2 * k] = r0
        rs[2 * k + 1] = r1


@inner(_nrt=False)
def accel_poly(n_acc, eps1, coef, buf):
    """Coefficients of A_n as a polynomial in C_1 (eq. B.4-B.8) and the optimal b (eq. 24);
    ``buf`` (3, size) work rows.

    The products run over the non-zero coefficients only (degree of C_k is 2^(k-1), of A_k
    2^(k-1) - 1): the terms left out are exact zeros."""
    size = coef.shape[0]
    cc = buf[0]
    ca = buf[1]
    tmp = buf[2]
    cc[:] = 0.0
    ca[:] = 0.0
    cc[1] = 1.0
    ca[0] = 1.0
    dc = 1  # degree of C
    da = 0  # degree of A
    om = 1.0
    ep = eps1
    for _ in range(2, n_acc + 1):
        bk = ep + om
        # A <- (bk - C) A
        tmp[:] = 0.0
        for i in range(da + 1):
            if ca[i] == 0.0:
                continue
            tmp[i] += bk * ca[i]
            for j in range(min(size - i, dc + 1)):
                tmp[i + j] -= cc[j] * ca[i]
        for i in range(size):
            ca[i] = tmp[i]
        da = min(size - 1, da + dc)
        # C <- C (bk - C)
        tmp[:] = 0.0
        for i in range(dc + 1):
            if cc[i] == 0.0:
                continue
            tmp[i] += bk * cc[i]
            for j in range(min(size - i, dc + 1)):
                tmp[i + j] -= cc[j] * cc[i]
        for i in range(size):
            cc[i] = tmp[i]
        dc = min(size - 1, 2 * dc)
        ep, om = ep * om, bk * bk / 4.0
    for i in range(size):
        coef[i] = ca[i]
    return 2.0 / (om + ep)


@entry
def gt_apply(dmu, tie_node, tie_gear, bvec, rot, cnod, cw, cn, g, gth):
    """G^T dmu (x part into ``g``, disk part into ``gth``) with ``npair`` contact rows."""
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
    for jp in range(cnod.shape[0]):
        p = dmu[2 * nt + jp]
        if p == 0.0:
            continue
        for j in range(cnod.shape[2]):
            i = cnod[jp, 0, j]
            g[2 * i] += cw[jp, 0, j] * cn[jp, 0] * p
            g[2 * i + 1] += cw[jp, 0, j] * cn[jp, 1] * p
            i = cnod[jp, 1, j]
            g[2 * i] -= cw[jp, 1, j] * cn[jp, 0] * p
            g[2 * i + 1] -= cw[jp, 1, j] * cn[jp, 1] * p


@inner(_nrt=False)
def contact_columns(c1, c2, m, rot, cnod, cw, cn, g, zk, ccol):
    """Columns of C = G W G^T of every contact row (W = c1 M^-1 - c2 M^-1 K_g M^-1)."""
    minv, gid, tie_node = m.minv, m.gid, m.tie_node
    nt = tie_node.shape[0]
    npair = cnod.shape[0]
    for jp in range(npair):
        for side in range(2):
            sgn = 1.0 if side == 0 else -1.0
            for j in range(cnod.shape[2]):
                i = cnod[jp, side, j]
                g[2 * i] += sgn * cw[jp, side, j] * cn[jp, 0]
                g[2 * i + 1] += sgn * cw[jp, side, j] * cn[jp, 1]
        if c2 != 0.0:
            k_local_product(g, m, rot, zk)
        for k in range(nt):
            i = tie_node[k]
            gg = gid[i]
            c = rot[gg, 0]
            s = rot[gg, 1]
            gl0 = c * g[2 * i] + s * g[2 * i + 1]
            gl1 = -s * g[2 * i] + c * g[2 * i + 1]
            ccol[jp, 2 * k] = -minv[i] * (c1 * gl0 - c2 * zk[2 * i])
            ccol[jp, 2 * k + 1] = -minv[i] * (c1 * gl1 - c2 * zk[2 * i + 1])
        for kp in range(npair):
            acc = 0.0
            for side in range(2):
                sgn = 1.0 if side == 0 else -1.0
                for j in range(cnod.shape[2]):
                    i = cnod[kp, side, j]
                    gg = gid[i]
                    c = rot[gg, 0]
                    s = rot[gg, 1]
                    z0 = zk[2 * i]
                    z1 = zk[2 * i + 1]
                    w0 = minv[i] * (c1 * g[2 * i] - c2 * (c * z0 - s * z1))
                    w1 = minv[i] * (c1 * g[2 * i + 1] - c2 * (s * z0 + c * z1))
                    acc += sgn * cw[kp, side, j] * (cn[kp, 0] * w0 + cn[kp, 1] * w1)
            ccol[jp, 2 * nt + kp] = acc
        for side in range(2):
            for j in range(cnod.shape[2]):
                i = cnod[jp, side, j]
                g[2 * i] = 0.0
                g[2 * i + 1] = 0.0
        if c2 != 0.0:
            zk[:] = 0.0


@inner(_nrt=False)
def c_matvec(z, out, act, c1, c2, m_arr, bvec, ccol, yl):
    """out = C' z: tie block (structured) + the active contact rows/columns (``act`` mask);
    ``m_arr`` the :class:`~rotaflex.gear.kernels.arrays.ModelArrays` of the pair."""
    minv, tie_node, tie_gear, jd = m_arr.minv, m_arr.tie_node, m_arr.tie_gear, m_arr.inertia
    tb_ptr, tb_j, tb_b = m_arr.tb_ptr, m_arr.tb_j, m_arr.tb_b
    nt = tie_node.shape[0]
    ic = 2 * nt
    npair = ccol.shape[0]
    y2 = yl[:ic].reshape((nt, 2))
    # one sweep for the diagonal part, the disk sums and M_t^-1 z, then one per row with the
    # tie-block product summed in registers; the same operations per entry, in the same order,
    # as the tie block written term by term
    sg0 = 0.0
    sg1 = 0.0
    for k in range(nt):
        m = minv[tie_node[k]]
        z0 = z[2 * k]
        z1 = z[2 * k + 1]
        out[2 * k] = c1 * m * z0
        out[2 * k + 1] = c1 * m * z1
        d = bvec[k, 0] * z0 + bvec[k, 1] * z1
        if tie_gear[k] == 0:
            sg0 += d
        else:
            sg1 += d
        y2[k, 0] = m * z0
        y2[k, 1] = m * z1
    s0 = sg0 / jd[0]
    s1 = sg1 / jd[1]
    for k in range(nt):
        sgv = s0 if tie_gear[k] == 0 else s1
        o0 = out[2 * k] + c1 * bvec[k, 0] * sgv
        o1 = out[2 * k + 1] + c1 * bvec[k, 1] * sgv
        if c2 != 0.0:
            k0 = 0.0
            k1 = 0.0
            for q in range(tb_ptr[k], tb_ptr[k + 1]):
                j = tb_j[q]
                k0 += tb_b[q, 0] * y2[j, 0] + tb_b[q, 1] * y2[j, 1]
                k1 += tb_b[q, 2] * y2[j, 0] + tb_b[q, 3] * y2[j, 1]
            m = minv[tie_node[k]]
            o0 -= c2 * m * k0
            o1 -= c2 * m * k1
        out[2 * k] = o0
        out[2 * k + 1] = o1
    for jp in range(npair):
        if not act[jp]:
            out[ic + jp] = 0.0
            continue
        zc = z[ic + jp]
        acc = 0.0
        for r in range(ic):
            out[r] += ccol[jp, r] * zc
            acc += ccol[jp, r] * z[r]
        for kp in range(npair):
            if act[kp]:
                acc += ccol[jp, ic + kp] * z[ic + kp]
        out[ic + jp] = acc


@inner(_nrt=False)
def iterate_pass(mode, e0, mu, pbar, c1, c2, eps_tie, tol, n_acc, max_iter, m_arr, bvec, ccol, work, stats, poly, actm):
    """Multiplier / contact-force iteration of eq. 19-21 with ``npair`` unilateral rows.

    Each contact row is active when (mode 1) its force is compressive or it penetrates, or
    (modes 2, 3) it was loaded in the previous pass (``pbar[j] < 0``) and it approaches or is
    loaded; each contact force is projected on p <= 0 after every update. The scaling
    ``||C'||_inf`` and the eigenvalue bound (tie block: exact; contact rows: Gershgorin) are
    recomputed when the active set changes. On return ``work[0]`` holds C (mu - mu_start).
    ``poly`` (4, 33) and ``actm`` (2, npair) are work arrays (no allocation in the step).
    Returns (residual, iterations, converged).
    """
    nc = e0.shape[0]
    npair = ccol.shape[0]
    ic = nc - npair
    y = work[0]
    e = work[1]
    d = work[2]
    t1 = work[3]
    rs = work[4]
    yl = work[5]
    y[:] = 0.0
    coef = poly[0]
    act = actm[0]
    allact = actm[1]
    allact[:] = True
    tie_row_sums(c1, c2, m_arr, bvec, rs)
    last_mask = -1
    nrm = 1.0
    bbar = 1.0
    deg = 0
    res = 0.0
    for it in range(max_iter + 1):
        for r in range(ic):
            e[r] = e0[r] + y[r]
        mask = 0
        for jp in range(npair):
            sval = e0[ic + jp] + y[ic + jp]
            p = mu[ic + jp]
            if mode == 1:
                a_ = (p < 0.0) or (sval > 0.0)
            else:
                a_ = (pbar[jp] < 0.0) and ((sval > 0.0) or (p < 0.0))
            act[jp] = a_
            e[ic + jp] = sval if a_ else 0.0
            if a_:
                mask += 1 << jp
        res = 0.0
        for r in range(nc):
            if abs(e[r]) > res:
                res = abs(e[r])
        if res <= tol:
            stats[0] = res
            stats[1] = it
            return res, it, True
        if it == max_iter:
            break
        if mask != last_mask:
            nrm = 0.0
            for r in range(ic):
                v = rs[r]
                for jp in range(npair):
                    if act[jp]:
                        v += abs(ccol[jp, r])
                if v > nrm:
                    nrm = v
            epsa = eps_tie
            for jp in range(npair):
                if not act[jp]:
                    continue
                crow = 0.0
                for r in range(ic):
                    crow += abs(ccol[jp, r])
                for kp in range(npair):
                    if act[kp] and kp != jp:
                        crow += abs(ccol[jp, ic + kp])
                diag = ccol[jp, ic + jp]
                if crow + abs(diag) > nrm:
                    nrm = crow + abs(diag)
                ec = diag - crow
                if ec < 0.05 * diag:
                    ec = 0.05 * diag
                if ec < epsa:
                    epsa = ec
            eps1 = epsa / nrm
            if eps1 > 0.999:
                eps1 = 0.999
            if eps1 < 1e-9:
                eps1 = 1e-9
            bbar = accel_poly(n_acc, eps1, coef, poly[1:])
            deg = 0
            for j in range(33):
                if coef[j] != 0.0:
                    deg = j
            last_mask = mask
        for r in range(nc):
            d[r] = coef[deg] * e[r]
        for j in range(deg - 1, -1, -1):
            c_matvec(d, t1, act, c1, c2, m_arr, bvec, ccol, yl)
            for r in range(nc):
                d[r] = t1[r] / nrm + coef[j] * e[r]
        for r in range(nc):
            d[r] = -bbar * d[r] / nrm
        for jp in range(npair):
            p = mu[ic + jp]
            newp = min(0.0, p + d[ic + jp])
            d[ic + jp] = newp - p
        for r in range(nc):
            mu[r] += d[r]
        c_matvec(d, t1, allact, c1, c2, m_arr, bvec, ccol, yl)
        for r in range(nc):
            y[r] += t1[r]
    stats[0] = res
    stats[1] = max_iter
    return res, max_iter, False


@inner
def band_solve(lb, r, out):
    """Solve L L^T out = r with the banded factor ``lb`` (n, bw + 1); ``out`` may alias ``r``."""
    n = r.shape[0]
    bw = lb.shape[1] - 1
    for i in range(n):
        acc = r[i]
        k0 = max(0, i - bw)
        for j in range(k0, i):
            acc -= lb[i, i - j] * out[j]
        out[i] = acc / lb[i, 0]
    for i in range(n - 1, -1, -1):
        acc = out[i]
        k1 = min(n - 1, i + bw)
        for j in range(i + 1, k1 + 1):
            acc -= lb[j, j - i] * out[j]
        out[i] = acc / lb[i, 0]


@inner
def tie_solve(lb, perm, bmat, r, out, tmp, y, s2):
    """out = C_t^-1 r with C_t = C_0 + B diag(c1 / J) B^T (Woodbury, B = ``bmat`` (n, 2)).

    ``y`` (2, n) must hold C_0^-1 b_g in permuted order and ``s2`` the 2 x 2 matrix
    diag(1/dcoef) + B^T C_0^-1 B (see :func:`prepare_woodbury`).
    """
    n = r.shape[0]
    for i in range(n):
        tmp[i] = r[perm[i]]
    band_solve(lb, tmp, tmp)
    q0 = 0.0
    q1 = 0.0
    for i in range(n):
        q0 += bmat[perm[i], 0] * tmp[i]
        q1 += bmat[perm[i], 1] * tmp[i]
    det = s2[0, 0] * s2[1, 1] - s2[0, 1] * s2[1, 0]
    z0 = (s2[1, 1] * q0 - s2[0, 1] * q1) / det
    z1 = (-s2[1, 0] * q0 + s2[0, 0] * q1) / det
    for i in range(n):
        out[perm[i]] = tmp[i] - y[0, i] * z0 - y[1, i] * z1


@entry
def prepare_woodbury(lb, perm, bmat, dcoef, y, s2):
    """y[g] = C_0^-1 b_g (permuted order), s2 = diag(1/dcoef) + B^T C_0^-1 B."""
    n = bmat.shape[0]
    for g in range(2):
        for i in range(n):
            y[g, i] = bmat[perm[i], g]
        band_solve(lb, y[g], y[g])
    for g in range(2):
        for h in range(2):
            acc = 0.0
            for i in range(n):
                acc += bmat[perm[i], g] * y[h, i]
            s2[g, h] = acc + (1.0 / dcoef[g] if g == h else 0.0)


@inner
def _factor_views(packed, tie_gear, bvec, n, buf):
    """Band factor, Woodbury vectors (copied into ``buf[4:6]``), 2 x 2 capacitance matrix and
    the current disk vectors B (n, 2) of one pass's packed factor data."""
    nb = packed.shape[1] - 2
    lb = packed[:n, :nb]
    y = buf[4:6, :n]
    for r in range(n):
        y[0, r] = packed[r, nb]
        y[1, r] = packed[r, nb + 1]
    s2 = packed[n, :4].reshape((2, 2))
    bmat = np.zeros((n, 2))
    for k in range(n // 2):
        g = tie_gear[k]
        bmat[2 * k, g] = bvec[k, 0]
        bmat[2 * k + 1, g] = bvec[k, 1]
    return lb, y, s2, bmat


@entry
def direct_pass(mode, e0, mu, pbar, packed, perm, tie_gear, bvec, ccol, tol, dmu, buf):
    """Multiplier change ``dmu`` of one pass from the factored C (unilateral contact by active set).

    Parameters
    ----------
    mode : int
        1 displacement, 2 velocity, 3 acceleration pass (contact allowed in passes 2-3 only if
        ``pbar < 0``, as in the iterative scheme).
    e0 : (nc,) array
        Error vector at the current multipliers ``mu`` (tie rows, then the contact row).
    packed, perm : factor data of this pass (see :func:`factor_tie_blocks`) and the row order.
    ccol : (nc,) array
        Contact column of C (tie part, then the diagonal entry).
    dmu : (nc,) output
    buf : (6, nc) scratch
    Returns ``(C_ref dmu)`` at the contact row. ``C_ref`` uses the reference disk vectors, so
    the caller re-evaluates the error with the exact C and repeats if needed.
    """
    nc = e0.shape[0]
    ic = nc - 1
    n = ic
    lb, y, s2, bmat = _factor_views(packed, tie_gear, bvec, n, buf)
    tmp = buf[0]
    w = buf[1]
    u = buf[2]
    rhs = buf[3]
    p0 = mu[ic]
    # tie-only solution with the contact force set to zero: dp = -p0
    dp = -p0
    for r in range(n):
        rhs[r] = e0[r] + ccol[r] * dp
    tie_solve(lb, perm, bmat, rhs[:n], w[:n], tmp[:n], y, s2)
    s0 = e0[ic] + ccol[ic] * dp
    for r in range(n):
        s0 -= ccol[r] * w[r]
    allowed = mode == 1 or pbar < 0.0
    if allowed and s0 > tol:
        # active contact: Schur complement of the contact row
        tie_solve(lb, perm, bmat, ccol[:n], u[:n], tmp[:n], y, s2)
        sig = ccol[ic]
        for r in range(n):
            sig -= ccol[r] * u[r]
        ddp = -s0 / sig
        dp += ddp
        for r in range(n):
            w[r] += u[r] * ddp
    for r in range(n):
        dmu[r] = -w[r]
    dmu[ic] = dp
    yc = ccol[ic] * dp
    for r in range(n):
        yc += ccol[r] * dmu[r]
    return yc


@inner
def direct_pass_pairs(mode, e0, mu, pbar, packed, perm, tie_gear, bvec, ccol, tol, dmu, buf):
    """:func:`direct_pass` with several contact rows (``ccol`` (npair, nc)): Schur complement
    of the active contact rows, active set by release of tensile rows."""
    npair = ccol.shape[0]
    nc = e0.shape[0]
    ic = nc - npair
    n = ic
    lb, y, s2, bmat = _factor_views(packed, tie_gear, bvec, n, buf)
    tmp = buf[0]
    w = buf[1]
    rhs = buf[3]
    dp = np.empty(npair)
    for j in range(npair):
        dp[j] = -mu[ic + j]
    for r in range(n):
        acc = e0[r]
        for j in range(npair):
            acc += ccol[j, r] * dp[j]
        rhs[r] = acc
    tie_solve(lb, perm, bmat, rhs[:n], w[:n], tmp[:n], y, s2)
    s0 = np.empty(npair)
    u = np.empty((npair, n))
    for j in range(npair):
        acc = e0[ic + j]
        for k in range(npair):
            acc += ccol[j, ic + k] * dp[k]
        for r in range(n):
            acc -= ccol[j, r] * w[r]
        s0[j] = acc
        tie_solve(lb, perm, bmat, ccol[j, :n], u[j], tmp[:n], y, s2)
    sch = np.empty((npair, npair))
    for j in range(npair):
        for k in range(npair):
            acc = ccol[j, ic + k]
            for r in range(n):
                acc -= ccol[j, r] * u[k, r]
            sch[j, k] = acc
    act = np.zeros(npair, np.bool_)
    for j in range(npair):
        act[j] = (mode == 1 or pbar[j] < 0.0) and s0[j] > tol
    ddp = np.zeros(npair)
    for _ in range(npair + 1):
        idx = np.nonzero(act)[0]
        na = idx.shape[0]
        ddp[:] = 0.0
        if na == 0:
            break
        a = np.empty((na, na))
        rr = np.empty(na)
        for p in range(na):
            rr[p] = -s0[idx[p]]
            for q in range(na):
                a[p, q] = sch[idx[p], idx[q]]
        sol = np.linalg.solve(a, rr)
        released = False
        for p in range(na):
            ddp[idx[p]] = sol[p]
            if sol[p] > 0.0:
                act[idx[p]] = False
                released = True
        if not released:
            break
    for r in range(n):
        acc = w[r]
        for j in range(npair):
            acc += u[j, r] * ddp[j]
        dmu[r] = -acc
    for j in range(npair):
        dmu[ic + j] = dp[j] + ddp[j]


@inner(_nrt=True)
def direct_solve(mode, e0, mu, pbar, c1, c2, tol, max_ref, lb, perm, m_arr, bvec, ccol, work, stats):
    """Direct multiplier solve of one pass, checked.

    After the exact solve the error ``e0 + C dmu`` is re-evaluated with the structured
    :func:`c_matvec` and, if above ``tol``, refined (at most ``max_ref`` times). Same return
    values as :func:`iterate_pass` (iterations = number of solves); ``work[0]`` holds
    C (mu - mu_start) on return.
    """
    nc = e0.shape[0]
    npair = ccol.shape[0]
    ic = nc - npair
    e = work[1]
    dmu = work[2]
    t1 = work[3]
    y = work[0]
    y[:] = 0.0
    buf = work[7:13]
    allact = np.ones(npair, np.bool_)
    res = 0.0
    for it in range(max_ref + 1):
        for r in range(nc):
            e[r] = e0[r] + y[r]
        if npair == 1:
            direct_pass(mode, e, mu, pbar[0], lb, perm, m_arr.tie_gear, bvec, ccol[0], tol, dmu, buf)
        else:
            direct_pass_pairs(mode, e, mu, pbar, lb, perm, m_arr.tie_gear, bvec, ccol, tol, dmu, buf)
        for r in range(nc):
            mu[r] += dmu[r]
        c_matvec(dmu, t1, allact, c1, c2, m_arr, bvec, ccol, work[5])
        for r in range(nc):
            y[r] += t1[r]
        res = 0.0
        for r in range(ic):
            res = max(res, abs(e0[r] + y[r]))
        for jp in range(npair):
            sval = e0[ic + jp] + y[ic + jp]
            p = mu[ic + jp]
            if mode == 1:
                act = (p < 0.0) or (sval > 0.0)
            else:
                act = (pbar[jp] < 0.0) and ((sval > 0.0) or (p < 0.0))
            if act:
                res = max(res, abs(sval))
        if res <= tol:
            stats[0] = res
            stats[1] = it + 1
            return res, it + 1, True
    stats[0] = res
    stats[1] = max_ref + 1
    return res, max_ref + 1, False


@inner(_nrt=False)
def solve_pass(
    prm, mode, e0, mu, pbar, c1, c2, eps_tie, tol, n_acc, max_iter, m_arr, bvec, ccol, work, stats, poly, actm
):
    """Pass ``mode`` (1, 2, 3) by the iteration of eq. 19-24 (``prm.dfac`` empty) or by the
    direct solve (factors ``prm.dfac[mode - 1]`` of the
    :class:`~rotaflex.gear.kernels.arrays.StepParams`); returns (residual, iterations,
    converged) and leaves C (mu - mu_start) in ``work[0]``.

    Both solvers are in the one compiled run (a branch per pass, not a specialisation each):
    a second specialisation compiled the whole step again, 35 s CPU on a cold cache.
    """
    if prm.dfac.shape[1] == 0:
        return iterate_pass(
            mode, e0, mu, pbar, c1, c2, eps_tie, tol, n_acc, max_iter, m_arr, bvec, ccol, work, stats, poly, actm
        )
    factors = prm.dfac[mode - 1]
    return direct_solve(mode, e0, mu, pbar, c1, c2, tol, 3, factors, prm.dperm, m_arr, bvec, ccol, work, stats)


def factor_tie_blocks(model, dt: float):
    """Banded Cholesky factors of C_0 for the three passes, with the Woodbury data.

    Returns ``(packed, perm, bw)``. ``packed`` (3, n + 1, bw + 3) holds per pass: rows 0..n-1,
    columns 0..bw the band ``L[i, i - k]`` (permuted order), columns bw + 1, bw + 2 the vectors
    C_0^-1 b_g of the reference disk vectors, row n the 2 x 2 matrix
    diag(J_g / c1) + B^T C_0^-1 B (first four entries). ``perm`` (n,) is the row order, ``bw``
    the lower bandwidth.
    """
    import scipy.sparse as sp
    from scipy.sparse.csgraph import reverse_cuthill_mckee

    nt = len(model.tie_node)
    n = 2 * nt
    mt = np.repeat(model.minv[model.tie_node], 2)
    ktt = np.zeros((n, n))
    for i, j, b in zip(model.tb_i, model.tb_j, model.tb_b, strict=True):
        ktt[2 * i : 2 * i + 2, 2 * j : 2 * j + 2] = b
    pattern = sp.csr_matrix((np.abs(ktt) > 0) | np.eye(n, dtype=bool))
    perm = np.asarray(reverse_cuthill_mckee(pattern, symmetric_mode=True), dtype=np.int64)
    kp = ktt[np.ix_(perm, perm)]
    rows, cols = np.nonzero(kp)
    bw = int(np.max(np.abs(rows - cols))) if len(rows) else 0
    lband = np.zeros((3, n, bw + 1))
    for p, (c1, c2) in enumerate(((dt * dt / 2, dt**4 / 24), (dt, dt**3 / 6), (1.0, 0.0))):
        c0 = c1 * np.diag(mt) - c2 * (mt[:, None] * ktt * mt[None, :])
        low = np.linalg.cholesky(c0[np.ix_(perm, perm)])
        for k in range(bw + 1):
            lband[p, k:, k] = np.diagonal(low, -k)
    # Woodbury data of the reference disk vectors b_g = J X_k (the tie positions once the ties
    # hold); the small change of b_g during a step is absorbed by the refinement of
    # :func:`direct_solve`.
    nb = bw + 1
    packed = np.zeros((3, n + 1, nb + 2))
    packed[:, :n, :nb] = lband
    bmat = np.zeros((n, 2))
    xl = model.xloc[model.tie_node]
    for k, g in enumerate(model.tie_gear):
        bmat[2 * k, g] = -xl[k, 1]
        bmat[2 * k + 1, g] = xl[k, 0]
    for p, c1 in enumerate((dt * dt / 2, dt, 1.0)):
        y = np.empty((2, n))
        s2 = np.empty((2, 2))
        prepare_woodbury(np.ascontiguousarray(lband[p]), perm, bmat, c1 / np.asarray(model.inertia, dtype=float), y, s2)
        packed[p, :n, nb] = y[0]
        packed[p, :n, nb + 1] = y[1]
        packed[p, n, :4] = s2.ravel()
    return packed, perm, bw
