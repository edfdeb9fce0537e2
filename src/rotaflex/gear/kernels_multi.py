"""Compiled kernels of the gear-contact solver with several simultaneous contact pairs.

Generalises the contact part of :mod:`rotaflex.gear.kernels` (one contact row) to ``npair``
unilateral contact rows, each with its own contact search, sliding terms and multiplier, in
the paper's scheme (RK4 with constant multipliers, three passes per step, accelerated
iteration of eq. 19-24 / appendix B on the affine map ``e + C dmu``). The tie part, splines,
contact search, sliding terms, elastic force and RK4 responses are the single-pair kernels,
reused unchanged; the single-pair solver :func:`rotaflex.gear.kernels.run_steps` is untouched.

Layout
------
* Constraint rows ``2*k + c`` are the ties (as in the single-pair kernel), then row
  ``2*nt + j`` is the contact of pair ``j``.
* Per-pair arrays carry a leading pair index: ``flank (npair, 2, nfl)``, ``nedge (npair, 2)``,
  ``cres (npair, 8)``, ``cnod (npair, 2, 3)``, ``cw (npair, 2, 3)``, ``ccol (npair, nc)``
  (column of C of each contact row).
* ``torque_mode`` 0: Fig. 7 ramps on both disks (as the single-pair model); 1: constant tau_0.

Status codes as in :mod:`rotaflex.gear.kernels` (0 ok, 1-3 pass not converged, 4 search).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from rotaflex.gear.kernels import (
    accel_poly,
    contact_geometry,
    elastic_force,
    flank_weights,
    k_local_product,
    kinetic_energy,
    ramp_torque,
    respond,
    sample_flank,
    set_rotation,
    sliding_terms,
    spline_eval,
    spline_second,
    tie_row_sums,
    tie_vectors,
)

#: global columns of the per-record output
GLOBAL_COLUMNS = (
    "time",
    "phi_A",
    "phi_B",
    "omega_A",
    "omega_B",
    "kinetic_energy",
    "strain_energy",
    "external_work",
    "velocity_pass_loss",
    "res_disp",
    "res_vel",
    "res_acc",
    "iter_disp",
    "iter_vel",
    "iter_acc",
    "torque_A",
    "torque_B",
    "tie_residual",
    "impacts",
)
#: per-pair columns of the per-record output
PAIR_COLUMNS = (
    "force",
    "force_disp",
    "force_vel",
    "gap",
    "cpA_x",
    "cpA_y",
    "cpB_x",
    "cpB_y",
    "param_a",
    "param_b",
    "force_peak",
    "contact_case",
    "normal_velocity",
)


@njit(cache=True)
def torque_of(g, phi_g, rsgn_g, tpar, mode):
    """External torque on disk ``g`` (counter-clockwise positive): ramp of Fig. 7 or constant."""
    if mode == 1:
        return tpar[0]
    return ramp_torque(rsgn_g * phi_g, tpar[0], tpar[1], tpar[2])


@njit(cache=True)
def gt_apply_m(dmu, tie_node, tie_gear, bvec, rot, cnod, cw, cn, g, gth):
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
        for j in range(3):
            i = cnod[jp, 0, j]
            g[2 * i] += cw[jp, 0, j] * cn[jp, 0] * p
            g[2 * i + 1] += cw[jp, 0, j] * cn[jp, 1] * p
            i = cnod[jp, 1, j]
            g[2 * i] -= cw[jp, 1, j] * cn[jp, 0] * p
            g[2 * i + 1] -= cw[jp, 1, j] * cn[jp, 1] * p


@njit(cache=True)
def contact_columns_m(c1, c2, minv, gid, rot, indptr, indices, data, tie_node, cnod, cw, cn, g, zk, ccol):
    """Columns of C = G W G^T of every contact row (W = c1 M^-1 - c2 M^-1 K_g M^-1)."""
    nt = tie_node.shape[0]
    npair = cnod.shape[0]
    for jp in range(npair):
        for side in range(2):
            sgn = 1.0 if side == 0 else -1.0
            for j in range(3):
                i = cnod[jp, side, j]
                g[2 * i] += sgn * cw[jp, side, j] * cn[jp, 0]
                g[2 * i + 1] += sgn * cw[jp, side, j] * cn[jp, 1]
        if c2 != 0.0:
            k_local_product(g, minv, gid, rot, indptr, indices, data, zk)
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
                for j in range(3):
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
            for j in range(3):
                i = cnod[jp, side, j]
                g[2 * i] = 0.0
                g[2 * i + 1] = 0.0
        if c2 != 0.0:
            zk[:] = 0.0


@njit(cache=True)
def c_matvec_m(z, out, act, c1, c2, minv, tie_node, tie_gear, jd, bvec, tb_i, tb_j, tb_b, ccol, yl, kz):
    """out = C' z: tie block (structured) + the active contact rows/columns (``act`` mask)."""
    nt = tie_node.shape[0]
    ic = 2 * nt
    npair = ccol.shape[0]
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


@njit(cache=True)
def iterate_pass_m(
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
    tb_i,
    tb_j,
    tb_b,
    ccol,
    work,
    stats,
):
    """Multiplier / contact-force iteration of eq. 19-21 with ``npair`` unilateral rows.

    Each contact row is active when (mode 1) its force is compressive or it penetrates, or
    (modes 2, 3) it was loaded in the previous pass (``pbar[j] < 0``) and it approaches or is
    loaded; each contact force is projected on p <= 0 after every update. The scaling
    ``||C'||_inf`` and the eigenvalue bound (tie block: exact; contact rows: Gershgorin) are
    recomputed when the active set changes. On return ``work[0]`` holds C (mu - mu_start).
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
    kz = work[6]
    y[:] = 0.0
    coef = np.zeros(33)
    act = np.zeros(npair, np.bool_)
    allact = np.ones(npair, np.bool_)
    tie_row_sums(c1, c2, minv, tie_node, tie_gear, jd, bvec, np.zeros((2, 2)), tb_i, tb_j, tb_b, rs)
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
            bbar = accel_poly(n_acc, eps1, coef)
            deg = 0
            for j in range(33):
                if coef[j] != 0.0:
                    deg = j
            last_mask = mask
        for r in range(nc):
            d[r] = coef[deg] * e[r]
        for j in range(deg - 1, -1, -1):
            c_matvec_m(d, t1, act, c1, c2, minv, tie_node, tie_gear, jd, bvec, tb_i, tb_j, tb_b, ccol, yl, kz)
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
        c_matvec_m(d, t1, allact, c1, c2, minv, tie_node, tie_gear, jd, bvec, tb_i, tb_j, tb_b, ccol, yl, kz)
        for r in range(nc):
            y[r] += t1[r]
    stats[0] = res
    stats[1] = max_iter
    return res, max_iter, False


@njit(cache=True)
def accelerations_m(
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
    tmode,
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
):
    """Accelerations at a (stage) state for multipliers ``mu``; returns the strain energy.

    As :func:`rotaflex.gear.kernels.accelerations`, with every contact point and normal
    advanced from the step start (``ct[j]`` = a, b, n_x, n_y) by its rates over ``tau_off``.
    """
    set_rotation(phi, theta0, rot)
    tie_vectors(x, cen, tie_node, tie_gear, rot, bvec, rx)
    nodes = np.empty(3, np.int64)
    w = np.empty(3)
    for jp in range(ct.shape[0]):
        n0 = ct[jp, 2] + rates[jp, 2] * tau_off
        n1 = ct[jp, 3] + rates[jp, 3] * tau_off
        ln = math.hypot(n0, n1)
        cn_s[jp, 0] = n0 / ln
        cn_s[jp, 1] = n1 / ln
        for side in range(2):
            flank_weights(flank[jp, side], nedge[jp, side], ct[jp, side] + rates[jp, side] * tau_off, nodes, w)
            for j in range(3):
                cnod[jp, side, j] = nodes[j]
                cw[jp, side, j] = w[j]
    fc[:] = 0.0
    fth[:] = 0.0
    gt_apply_m(mu, tie_node, tie_gear, bvec, rot, cnod, cw, cn_s, fc, fth)
    energy = elastic_force(x, xloc, gid, cen, rot, indptr, indices, data, wbuf, floc, fglob, tel)
    nn = xloc.shape[0]
    for i in range(nn):
        a[2 * i] = minv[i] * (fglob[2 * i] + fc[2 * i])
        a[2 * i + 1] = minv[i] * (fglob[2 * i + 1] + fc[2 * i + 1])
    for g in range(2):
        tau = torque_of(g, phi[g], rsgn[g], tpar, tmode)
        alp[g] = (tau + tel[g] + fth[g]) / jd[g]
    return energy


@njit(cache=True)
def _transfer(dmu, mi_tie_node, mi_tie_gear, bvec, rot, cnod, cw, cn, gsc, gth):
    gsc[:] = 0.0
    gth[:] = 0.0
    gt_apply_m(dmu, mi_tie_node, mi_tie_gear, bvec, rot, cnod, cw, cn, gsc, gth)


@njit(cache=True)
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


@njit(cache=True)
def pair_contact(x, flank, nedge, sig, mpts, pa, ma, pb, mb, cres, cnod, cw, mode):
    """``contact_geometry`` of one pair; ``mode`` 0 = minimum-distance search, 1 / 2 = the
    tip-corner projection of :func:`corner_contact`. Returns False on failure."""
    if mode == 0:
        return contact_geometry(x, flank, nedge, sig, mpts, pa, ma, pb, mb, cres, cnod, cw)
    sample_flank(x, flank[0], nedge[0], pa)
    sample_flank(x, flank[1], nedge[1], pb)
    spline_second(pa, ma)
    spline_second(pb, mb)
    corner_contact(pa, ma, pb, mb, sig[0], sig[1], mode, cres[0], cres[1], cres)
    nodes = np.empty(3, np.int64)
    w = np.empty(3)
    for side in range(2):
        flank_weights(flank[side], nedge[side], cres[side], nodes, w)
        for j in range(3):
            cnod[side, j] = nodes[j]
            cw[side, j] = w[j]
    return True


@njit(cache=True)
def search_pairs(
    x,
    phi0,
    rsgn0,
    mi_flank,
    mi_nedge,
    mf_sig,
    mpts,
    mf_psi,
    mf_wtab,
    lo,
    hi,
    corners,
    pa,
    ma,
    pb,
    mb,
    cres,
    cnod,
    cw,
    spair,
):
    """Contact search of every pair whose nominal contact angle ``psi_j + rsgn0 phi0`` lies in
    the mesh window [lo, hi]. A pair entering the window is warm-started from ``mf_wtab``
    (involute contact parameters on a uniform grid of the contact angle over [0, theta_s]);
    before the start of contact (psi < 0) the tip corner of B is projected on A, after its end
    (psi > theta_s) the tip corner of A on B (:func:`corner_contact`), in between the
    minimum-distance search of the single-pair model (``corners`` False: always the search);
    a pair outside it is not searched: gap 1 m, case -1, zero-weight contact row.
    Returns False if a search failed."""
    npair = cres.shape[0]
    nw = mf_wtab.shape[0]
    for jp in range(npair):
        psi = mf_psi[jp] + rsgn0 * phi0
        if psi >= lo and psi <= hi:
            if spair[jp, 5] == 0.0:
                z = (min(max(psi, 0.0), mf_wtab[nw - 1, 2]) / mf_wtab[nw - 1, 2]) * (nw - 1)
                k = min(int(z), nw - 2)
                f = z - k
                cres[jp, 0] = (1 - f) * mf_wtab[k, 0] + f * mf_wtab[k + 1, 0]
                cres[jp, 1] = (1 - f) * mf_wtab[k, 1] + f * mf_wtab[k + 1, 1]
            mode = 0
            if corners and psi < 0.0:
                mode = 1
            elif corners and psi > mf_wtab[nw - 1, 2]:
                mode = 2
            if not pair_contact(
                x,
                mi_flank[jp],
                mi_nedge[jp],
                mf_sig,
                mpts,
                pa[jp],
                ma[jp],
                pb[jp],
                mb[jp],
                cres[jp],
                cnod[jp],
                cw[jp],
                mode,
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
                for j in range(3):
                    cnod[jp, side, j] = mi_flank[jp, side, j]
                    cw[jp, side, j] = 0.0
    return True


@njit(cache=True)
def run_steps_m(
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
    mf_psi,
    mf_wtab,
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
    spair,
    rates,
    out,
    outp,
    out_mu,
    info,
):
    """Advance ``n_steps`` RK4 steps with three constraint passes and ``npair`` contacts.

    ``rates`` (npair, 4) holds the contact-parameter rates (da/dt, db/dt, dn/dt) of each pair; it
    is state, carried across calls like ``x`` and ``v`` (a run split into calls is bit-identical
    to one call).

    ``par`` = (dt, tau0, theta_2, theta_s, tol1, tol2, tol3, eps_tie1, eps_tie2, eps_tie3, lo,
    hi, corners) with [lo, hi] the window of nominal contact angles in which a pair is searched (see
    :func:`search_pairs`; ``mf_psi`` initial contact angles, ``mf_wtab`` warm-start table);
    ``ipar`` = (n_accel, max_iter, n_points, rec_row, initialise, torque_mode). ``sc`` =
    (t, W_ext, D_vel, E_el, -, -, res1, res2, res3, it1, it2, it3, -, -, n_impacts, tie_res,
    -, -, tau_A, tau_B); ``spair[j]`` = (s after pass 1, s_dot after pass 2, p_bar, p_hat,
    peak force since the last record, in-mesh flag). Global records go to ``out``, per-pair records to
    ``outp[row, j]`` (see GLOBAL_COLUMNS / PAIR_COLUMNS). Returns (status, next row).
    """
    dt = par[0]
    tpar = par[1:4]
    tol1 = par[4]
    tol2 = par[5]
    tol3 = par[6]
    n_acc = ipar[0]
    max_iter = ipar[1]
    mpts = ipar[2]
    row = ipar[3]
    tmode = ipar[5]
    npair = cres.shape[0]
    nn = mf_xloc.shape[0]
    nd = 2 * nn
    nt = mi_tie_node.shape[0]
    nc = 2 * nt + npair
    ic = 2 * nt
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
    pa = np.empty((npair, mpts, 2))
    ma = np.empty((npair, mpts, 2))
    pb = np.empty((npair, mpts, 2))
    mb = np.empty((npair, mpts, 2))
    va = np.empty((mpts, 2))
    mva = np.empty((mpts, 2))
    vb = np.empty((mpts, 2))
    mvb = np.empty((mpts, 2))
    cn = np.empty((npair, 2))
    cn_s = np.empty((npair, 2))
    cnod_t = np.empty((npair, 2, 3), np.int64)
    cw_t = np.empty((npair, 2, 3))
    ct = np.zeros((npair, 4))
    zero4 = np.zeros((npair, 4))
    rate1 = np.zeros(4)
    ccol = np.zeros((npair, nc))
    e0 = np.zeros(nc)
    mu0 = np.zeros(nc)
    dmu = np.zeros(nc)
    pbar = np.zeros(npair)
    work = np.zeros((7, nc))
    stats = np.zeros(2)
    c11 = dt * dt / 2.0
    c12 = dt**4 / 24.0
    c21 = dt
    c22 = dt**3 / 6.0
    lo = par[10]
    hi = par[11]
    corners = par[12] != 0.0
    init = ipar[4] == 1
    if init:
        if not search_pairs(
            x,
            phi[0],
            mf_rsgn[0],
            mi_flank,
            mi_nedge,
            mf_sig,
            mpts,
            mf_psi,
            mf_wtab,
            lo,
            hi,
            corners,
            pa,
            ma,
            pb,
            mb,
            cres,
            cnod,
            cw,
            spair,
        ):
            info[0] = sc[0]
            return 4, row
    for jp in range(npair):
        cn[jp, 0] = cres[jp, 3]
        cn[jp, 1] = cres[jp, 4]
    for step in range(n_steps + (1 if init else 0)):
        t = sc[0]
        initial = init and step == 0
        if not initial:
            for jp in range(npair):
                ct[jp, 0] = cres[jp, 0]
                ct[jp, 1] = cres[jp, 1]
                ct[jp, 2] = cn[jp, 0]
                ct[jp, 3] = cn[jp, 1]
            phi_t[0] = phi[0]
            phi_t[1] = phi[1]
            tau_old0 = torque_of(0, phi[0], mf_rsgn[0], tpar, tmode)
            tau_old1 = torque_of(1, phi[1], mf_rsgn[1], tpar, tmode)
            # ---- classical RK4 with the multipliers held constant
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
                accelerations_m(
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
                    tmode,
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
            # ---- contact search of every pair at the predicted state
            if not search_pairs(
                x,
                phi[0],
                mf_rsgn[0],
                mi_flank,
                mi_nedge,
                mf_sig,
                mpts,
                mf_psi,
                mf_wtab,
                lo,
                hi,
                corners,
                pa,
                ma,
                pb,
                mb,
                cres,
                cnod,
                cw,
                spair,
            ):
                info[0] = t
                return 4, row
            for jp in range(npair):
                cn[jp, 0] = cres[jp, 3]
                cn[jp, 1] = cres[jp, 4]
            set_rotation(phi, mf_theta0, rot)
            tie_vectors(x, mf_cen, mi_tie_node, mi_tie_gear, rot, bvec, rx)
            # ---- pass 1: displacements
            for k in range(nt):
                i = mi_tie_node[k]
                e0[2 * k] = -(rx[k, 0] - mf_xloc[i, 0])
                e0[2 * k + 1] = -(rx[k, 1] - mf_xloc[i, 1])
            for jp in range(npair):
                e0[ic + jp] = -cres[jp, 2]
            contact_columns_m(
                c11, c12, mf_minv, mi_gid, rot, mi_indptr, mi_indices, mf_data, mi_tie_node, cnod, cw, cn, gsc, zk, ccol
            )
            mu0[:] = mu
            res, its, ok = iterate_pass_m(
                1,
                e0,
                mu,
                pbar,
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
            for jp in range(npair):
                spair[jp, 0] = e0[ic + jp] + work[0, ic + jp]
            for r in range(nc):
                dmu[r] = mu[r] - mu0[r]
            _transfer(dmu, mi_tie_node, mi_tie_gear, bvec, rot, cnod, cw, cn, gsc, gth)
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
            for jp in range(npair):
                pbar[jp] = mu[ic + jp]
                spair[jp, 2] = pbar[jp]
            set_rotation(phi, mf_theta0, rot)
            tie_vectors(x, mf_cen, mi_tie_node, mi_tie_gear, rot, bvec, rx)
            # ---- pass 2: velocities
            ke0 = kinetic_energy(v, om, mf_minv, mf_jd)
            for k in range(nt):
                i = mi_tie_node[k]
                g = mi_tie_gear[k]
                cc = rot[g, 0]
                ss = rot[g, 1]
                e0[2 * k] = -(cc * v[2 * i] + ss * v[2 * i + 1]) + bvec[k, 0] * om[g]
                e0[2 * k + 1] = -(-ss * v[2 * i] + cc * v[2 * i + 1]) + bvec[k, 1] * om[g]
            for jp in range(npair):
                sh = 0.0
                for j in range(3):
                    i = cnod[jp, 0, j]
                    sh += cw[jp, 0, j] * (cn[jp, 0] * v[2 * i] + cn[jp, 1] * v[2 * i + 1])
                    i = cnod[jp, 1, j]
                    sh -= cw[jp, 1, j] * (cn[jp, 0] * v[2 * i] + cn[jp, 1] * v[2 * i + 1])
                e0[ic + jp] = sh
                if pbar[jp] < 0.0 and sh > tol2 and mu0[ic + jp] == 0.0:
                    sc[14] += 1.0
            contact_columns_m(
                c21, c22, mf_minv, mi_gid, rot, mi_indptr, mi_indices, mf_data, mi_tie_node, cnod, cw, cn, gsc, zk, ccol
            )
            mu0[:] = mu
            res, its, ok = iterate_pass_m(
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
            for jp in range(npair):
                spair[jp, 1] = e0[ic + jp] + work[0, ic + jp]
                spair[jp, 3] = mu[ic + jp]
            for r in range(nc):
                dmu[r] = mu[r] - mu0[r]
            _transfer(dmu, mi_tie_node, mi_tie_gear, bvec, rot, cnod, cw, cn, gsc, gth)
            respond(gsc, gth, c21, c22, mf_minv, mi_gid, rot, mf_jd, mi_indptr, mi_indices, mf_data, zk, v, om, 1.0)
            zk[:] = 0.0
            gsc[:] = 0.0
            sc[2] += ke0 - kinetic_energy(v, om, mf_minv, mf_jd)
            tau_new0 = torque_of(0, phi[0], mf_rsgn[0], tpar, tmode)
            tau_new1 = torque_of(1, phi[1], mf_rsgn[1], tpar, tmode)
            sc[1] += 0.5 * (tau_old0 + tau_new0) * (phi[0] - phi_t[0])
            sc[1] += 0.5 * (tau_old1 + tau_new1) * (phi[1] - phi_t[1])
            sc[18] = tau_new0
            sc[19] = tau_new1
        else:
            for jp in range(npair):
                pbar[jp] = -1.0 if cres[jp, 2] <= 0.0 else 0.0
        # ---- pass 3: accelerations
        for jp in range(npair):
            ct[jp, 0] = cres[jp, 0]
            ct[jp, 1] = cres[jp, 1]
            ct[jp, 2] = cn[jp, 0]
            ct[jp, 3] = cn[jp, 1]
        eel = accelerations_m(
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
            tmode,
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
            e0[2 * k] = -al0 + bvec[k, 0] * alp[g] + om[g] ** 2 * rx[k, 0] - 2 * om[g] * vl1
            e0[2 * k + 1] = -al1 + bvec[k, 1] * alp[g] + om[g] ** 2 * rx[k, 1] + 2 * om[g] * vl0
        for jp in range(npair):
            if spair[jp, 5] == 0.0:
                e0[ic + jp] = 0.0
                for q in range(4):
                    rates[jp, q] = 0.0
                continue
            sample_flank(v, mi_flank[jp, 0], mi_nedge[jp, 0], va)
            sample_flank(v, mi_flank[jp, 1], mi_nedge[jp, 1], vb)
            spline_second(va, mva)
            spline_second(vb, mvb)
            hs, _ad, _bd = sliding_terms(
                pa[jp], ma[jp], va, mva, pb[jp], mb[jp], vb, mvb, mf_sig[0], mf_sig[1], cres[jp], rate1
            )
            for q in range(4):
                rates[jp, q] = rate1[q]
            sa = hs
            for j in range(3):
                i = cnod[jp, 0, j]
                sa += cw[jp, 0, j] * (cn[jp, 0] * a[2 * i] + cn[jp, 1] * a[2 * i + 1])
                i = cnod[jp, 1, j]
                sa -= cw[jp, 1, j] * (cn[jp, 0] * a[2 * i] + cn[jp, 1] * a[2 * i + 1])
            e0[ic + jp] = sa
        contact_columns_m(
            1.0, 0.0, mf_minv, mi_gid, rot, mi_indptr, mi_indices, mf_data, mi_tie_node, cnod, cw, cn, gsc, zk, ccol
        )
        mu0[:] = mu
        res, its, ok = iterate_pass_m(
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
            dmu[r] = mu[r] - mu0[r]
        _transfer(dmu, mi_tie_node, mi_tie_gear, bvec, rot, cnod, cw, cn, gsc, gth)
        for i in range(nn):
            a[2 * i] += mf_minv[i] * gsc[2 * i]
            a[2 * i + 1] += mf_minv[i] * gsc[2 * i + 1]
        for g in range(2):
            alp[g] += gth[g] / mf_jd[g]
        gsc[:] = 0.0
        sc[0] = t
        sc[3] = eel
        for jp in range(npair):
            force = -mu[ic + jp]
            if force > spair[jp, 4]:
                spair[jp, 4] = force
            if initial:
                spair[jp, 0] = -cres[jp, 2]
        tr = 0.0
        for k in range(nt):
            i = mi_tie_node[k]
            tr = max(tr, max(abs(rx[k, 0] - mf_xloc[i, 0]), abs(rx[k, 1] - mf_xloc[i, 1])))
        sc[15] = max(sc[15], tr)
        # ---- record
        if (not initial) and ((step + (0 if init else 1)) % rec_every == 0) and row < out.shape[0]:
            out[row, 0] = t
            out[row, 1] = phi[0]
            out[row, 2] = phi[1]
            out[row, 3] = om[0]
            out[row, 4] = om[1]
            out[row, 5] = kinetic_energy(v, om, mf_minv, mf_jd)
            out[row, 6] = eel
            out[row, 7] = sc[1]
            out[row, 8] = sc[2]
            out[row, 9] = sc[6]
            out[row, 10] = sc[7]
            out[row, 11] = sc[8]
            out[row, 12] = sc[9]
            out[row, 13] = sc[10]
            out[row, 14] = sc[11]
            out[row, 15] = sc[18]
            out[row, 16] = sc[19]
            out[row, 17] = sc[15]
            out[row, 18] = sc[14]
            for jp in range(npair):
                outp[row, jp, 0] = -mu[ic + jp]
                outp[row, jp, 1] = -spair[jp, 2]
                outp[row, jp, 2] = -spair[jp, 3]
                outp[row, jp, 3] = -spair[jp, 0]
                for side in range(2):
                    px = 0.0
                    py = 0.0
                    for j in range(3):
                        i = cnod[jp, side, j]
                        px += cw[jp, side, j] * x[2 * i]
                        py += cw[jp, side, j] * x[2 * i + 1]
                    outp[row, jp, 4 + 2 * side] = px
                    outp[row, jp, 5 + 2 * side] = py
                outp[row, jp, 8] = cres[jp, 0]
                outp[row, jp, 9] = cres[jp, 1]
                outp[row, jp, 10] = spair[jp, 4]
                outp[row, jp, 11] = cres[jp, 5]
                outp[row, jp, 12] = spair[jp, 1]
                spair[jp, 4] = 0.0
            for r in range(ic):
                out_mu[row, r] = mu[r]
            row += 1
            for q in (6, 7, 8, 9, 10, 11, 15):
                sc[q] = 0.0
    return 0, row
