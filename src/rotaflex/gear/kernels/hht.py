"""Compiled kernels of the large-step method: Craig-Bampton teeth + HHT-alpha (see
:mod:`rotaflex.gear.models.reduced` for the model and the equations).

Per gear g the unknowns are the reduced tooth coordinates ``z`` (first the disk-frame
displacements of the working-flank nodes, then fixed-interface modal amplitudes) and the disk
angle ``phi``; the ties are satisfied exactly by construction. Arrays are padded to a common
size ``n`` (``nr[g]`` used entries). Contact pairs are given by two flank ids each (``pairs``);
the flank nodes of all flanks are numbered consecutively in a compact position array.
"""

from __future__ import annotations

import math

import numpy as np

from rotaflex.core.compiled import entry, inner
from rotaflex.gear.kernels.arrays import HHTScratch
from rotaflex.gear.kernels.contact import contact_geometry
from rotaflex.gear.kernels.forces import ramp_torque

#: columns of the per-record output array written by :func:`run_hht`
RECORD_COLUMNS = (
    "time",
    "phi_A",
    "phi_B",
    "omega_A",
    "omega_B",
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
    "force_peak",
    "torque_A",
    "torque_B",
    "contact_case",
    "normal_velocity",
    "tie_residual",
    "impacts",
)


@inner
def chol_solve(low, r, out):
    """Solve L L^T out = r (dense lower factor ``low``; only the leading len(r) block)."""
    n = r.shape[0]
    for i in range(n):
        acc = r[i]
        for j in range(i):
            acc -= low[i, j] * out[j]
        out[i] = acc / low[i, i]
    for i in range(n - 1, -1, -1):
        acc = out[i]
        for j in range(i + 1, n):
            acc -= low[j, i] * out[j]
        out[i] = acc / low[i, i]


@inner
def flank_positions(z, phi, fl_map, fl_gear, fl_start, fl_len, fl_xref, cen, theta0, xf):
    """Absolute positions of all flank nodes (compact numbering) into ``xf`` (2 * nf,).

    ``fl_map[k]`` is the index in ``z`` of the x displacement of flank node k (y: + 1), or -1
    for a tied node (no displacement)."""
    for f in range(fl_gear.shape[0]):
        g = fl_gear[f]
        c = math.cos(theta0[g] + phi[g])
        s = math.sin(theta0[g] + phi[g])
        for j in range(fl_len[f]):
            k = fl_start[f] + j
            q = fl_map[k]
            u0 = fl_xref[k, 0] + (z[g, q] if q >= 0 else 0.0)
            u1 = fl_xref[k, 1] + (z[g, q + 1] if q >= 0 else 0.0)
            xf[2 * k] = cen[g, 0] + c * u0 - s * u1
            xf[2 * k + 1] = cen[g, 1] + s * u0 + c * u1


@inner
def evaluate(
    z,
    zd,
    phi,
    phid,
    p,
    nr,
    fl_map,
    mr,
    kr,
    gr,
    cx,
    fl_gear,
    fl_start,
    fl_len,
    fl_xref,
    cen,
    theta0,
    sig,
    pairs,
    mpts,
    rsgn,
    tpar,
    xf,
    flid,
    nedge2,
    pa,
    ma,
    pb,
    mb,
    cres,
    cnod,
    cw,
    grow,
    sgap,
    fz,
    fphi,
    tau,
    ok,
):
    """Contact search of every pair, constraint gradients and the force vectors F(q, qd, p).

    ``grow`` (npair, 2, n + 1): gradient of the penetration ``s`` of each pair with respect to
    (z, phi) of each gear; ``sgap`` (npair,) the penetration (``-gap``). ``fz``, ``fphi``:
    K z + gyroscopic/centrifugal terms - contact forces, and the disk terms - external torque.
    Returns the strain energy.
    """
    flank_positions(z, phi, fl_map, fl_gear, fl_start, fl_len, fl_xref, cen, theta0, xf)
    npair = pairs.shape[0]
    ng = z.shape[0]
    grow[:] = 0.0
    ok[0] = 1
    for k in range(npair):
        fa = pairs[k, 0]
        fb = pairs[k, 1]
        for side in range(2):
            f = fa if side == 0 else fb
            nedge2[side] = (fl_len[f] - 1) // 2
            for j in range(fl_len[f]):
                flid[side, j] = fl_start[f] + j
        sg = np.empty(2)
        sg[0] = sig[fa]
        sg[1] = sig[fb]
        if not contact_geometry(xf, flid, nedge2, sg, mpts, pa, ma, pb, mb, cres[k], cnod[k], cw[k]):
            ok[0] = 0
            return 0.0
        n0 = cres[k, 3]
        n1 = cres[k, 4]
        sgap[k] = -cres[k, 2]
        for side in range(2):
            f = fa if side == 0 else fb
            g = fl_gear[f]
            sgn = 1.0 if side == 0 else -1.0
            c = math.cos(theta0[g] + phi[g])
            s = math.sin(theta0[g] + phi[g])
            for j in range(3):
                kk = cnod[k, side, j]
                q = fl_map[kk]
                wx = sgn * cw[k, side, j] * n0
                wy = sgn * cw[k, side, j] * n1
                lx = c * wx + s * wy
                ly = -s * wx + c * wy
                u0 = fl_xref[kk, 0]
                u1 = fl_xref[kk, 1]
                if q >= 0:
                    grow[k, g, q] += lx
                    grow[k, g, q + 1] += ly
                    u0 += z[g, q]
                    u1 += z[g, q + 1]
                grow[k, g, nr[g]] += lx * (-u1) + ly * u0
    energy = 0.0
    for g in range(ng):
        n = nr[g]
        sc = 0.0
        sm = 0.0
        for i in range(n):
            acc = 0.0
            accm = 0.0
            accg = 0.0
            for j in range(n):
                acc += kr[g, i, j] * z[g, j]
                accm += mr[g, i, j] * z[g, j]
                accg += gr[g, i, j] * zd[g, j]
            energy += 0.5 * acc * z[g, i]
            fz[g, i] = acc + 2.0 * phid[g] * accg - phid[g] ** 2 * (cx[g, i] + accm)
            sc += cx[g, i] * zd[g, i]
            sm += accm * zd[g, i]
        u = tpar[3 + g]  # gear-ratio factor: u tau(u theta), exact for u = 1
        tau[g] = u * ramp_torque(u * rsgn[g] * phi[g], tpar[0], tpar[1], tpar[2])
        fphi[g] = phid[g] * (2.0 * sc + 2.0 * sm) - tau[g]
        for k in range(npair):
            for i in range(n):
                fz[g, i] -= p[k] * grow[k, g, i]
            fphi[g] -= p[k] * grow[k, g, n]
    return energy


@inner
def mass_product(z, za, phia, nr, mr, gr, hx, cx, ix, jd, mz, mphi):
    """(M(q) a): z part ``mz`` and disk part ``mphi``."""
    for g in range(z.shape[0]):
        n = nr[g]
        cz = 0.0
        zmz = 0.0
        coup = 0.0
        for i in range(n):
            accm = 0.0
            accg = 0.0
            accmz = 0.0
            for j in range(n):
                accm += mr[g, i, j] * za[g, j]
                accg += gr[g, i, j] * z[g, j]
                accmz += mr[g, i, j] * z[g, j]
            hz = hx[g, i] + accg
            mz[g, i] = accm + hz * phia[g]
            coup += hz * za[g, i]
            cz += cx[g, i] * z[g, i]
            zmz += accmz * z[g, i]
        mphi[g] = coup + (jd[g] + ix[g] + 2.0 * cz + zmz) * phia[g]


@inner
def kinetic(z, zd, phid, nr, mr, gr, hx, cx, ix, jd):
    """Kinetic energy 1/2 qd^T M(q) qd."""
    mz = np.empty_like(z)
    mphi = np.empty(z.shape[0])
    mass_product(z, zd, phid, nr, mr, gr, hx, cx, ix, jd, mz, mphi)
    e = 0.0
    for g in range(z.shape[0]):
        for i in range(nr[g]):
            e += 0.5 * zd[g, i] * mz[g, i]
        e += 0.5 * phid[g] * mphi[g]
    return e


@inner
def small_solve(a, b, n):
    """Solve the leading n x n system a x = b in place (Gauss, partial pivoting); returns b."""
    for c in range(n):
        piv = c
        for r in range(c + 1, n):
            if abs(a[r, c]) > abs(a[piv, c]):
                piv = r
        if piv != c:
            for j in range(n):
                a[c, j], a[piv, j] = a[piv, j], a[c, j]
            b[c], b[piv] = b[piv], b[c]
        for r in range(c + 1, n):
            f = a[r, c] / a[c, c]
            for j in range(c, n):
                a[r, j] -= f * a[c, j]
            b[r] -= f * b[c]
    for c in range(n - 1, -1, -1):
        acc = b[c]
        for j in range(c + 1, n):
            acc -= a[c, j] * b[j]
        b[c] = acc / a[c, c]
    return b


@inner
def new_hht_scratch(hm, hs, mpts):
    """Work arrays of :func:`run_hht` for the model ``hm`` and state ``hs``."""
    ng = hs.z.shape[0]
    n = hs.z.shape[1]
    npair = hm.pairs.shape[0]
    nf = hm.fl_xref.shape[0]
    maxfl = 0
    for f in range(hm.fl_len.shape[0]):
        maxfl = max(maxfl, hm.fl_len[f])
    return HHTScratch(
        xf=np.empty(2 * nf),
        flid=np.zeros((2, maxfl), np.int64),
        nedge2=np.zeros(2, np.int64),
        pa=np.empty((mpts, 2)),
        ma=np.empty((mpts, 2)),
        pb=np.empty((mpts, 2)),
        mb=np.empty((mpts, 2)),
        grow=np.zeros((npair, ng, n + 1)),
        sgap=np.zeros(npair),
        fz=np.zeros((ng, n)),
        fphi=np.zeros(ng),
        tau=np.zeros(ng),
        taun=np.zeros(ng),
        ok=np.zeros(1, np.int64),
        zn=np.empty((ng, n)),
        zdn=np.empty((ng, n)),
        zan=np.empty((ng, n)),
        phin=np.empty(ng),
        phidn=np.empty(ng),
        phian=np.empty(ng),
        mz=np.zeros((ng, n)),
        mphi=np.zeros(ng),
        rhs=np.zeros(n + 1),
        y=np.zeros((ng, n + 1)),
        wcol=np.zeros((npair, ng, n + 1)),
        amat=np.zeros((npair, npair)),
        bvec=np.zeros(npair),
        dp=np.zeros(npair),
        act=np.zeros(npair, np.bool_),
        act_old=np.zeros(npair, np.bool_),
    )


@inner
def _evaluate_state(hm, hs, w, tpar, mpts, fz, fphi):
    """:func:`evaluate` at the current iterate of ``hs``; F into ``fz, fphi``."""
    return evaluate(
        hs.z,
        hs.zd,
        hs.phi,
        hs.phid,
        hs.p,
        hm.nr,
        hm.fl_map,
        hm.mr,
        hm.kr,
        hm.gr,
        hm.cx,
        hm.fl_gear,
        hm.fl_start,
        hm.fl_len,
        hm.fl_xref,
        hm.centres,
        hm.theta0,
        hm.sig,
        hm.pairs,
        mpts,
        hm.rsgn,
        tpar,
        w.xf,
        w.flid,
        w.nedge2,
        w.pa,
        w.ma,
        w.pb,
        w.mb,
        hs.cres,
        hs.cnod,
        hs.cw,
        w.grow,
        w.sgap,
        fz,
        fphi,
        w.tau,
        w.ok,
    )


@inner
def _step_start(hm, hs, w, tpar):
    """Keep the state of the step start (``w.zn`` ...) and its external torques."""
    z, zd, za, phi, phid, phia = hs.z, hs.zd, hs.za, hs.phi, hs.phid, hs.phia
    for g in range(z.shape[0]):
        for i in range(z.shape[1]):
            w.zn[g, i] = z[g, i]
            w.zdn[g, i] = zd[g, i]
            w.zan[g, i] = za[g, i]
        w.phin[g] = phi[g]
        w.phidn[g] = phid[g]
        w.phian[g] = phia[g]
        w.taun[g] = tpar[3 + g] * ramp_torque(tpar[3 + g] * hm.rsgn[g] * phi[g], tpar[0], tpar[1], tpar[2])
    for k in range(hs.p.shape[0]):
        w.act_old[k] = hs.p[k] < 0.0


@inner
def _newmark(hm, hs, w, h, beta, gam):
    """Positions and velocities of the iterate from its accelerations (Newmark formulas)."""
    z, zd, za, phi, phid, phia = hs.z, hs.zd, hs.za, hs.phi, hs.phid, hs.phia
    zn, zdn, zan = w.zn, w.zdn, w.zan
    for g in range(z.shape[0]):
        for i in range(hm.nr[g]):
            z[g, i] = zn[g, i] + h * zdn[g, i] + h * h * ((0.5 - beta) * zan[g, i] + beta * za[g, i])
            zd[g, i] = zdn[g, i] + h * ((1.0 - gam) * zan[g, i] + gam * za[g, i])
        phi[g] = w.phin[g] + h * w.phidn[g] + h * h * ((0.5 - beta) * w.phian[g] + beta * phia[g])
        phid[g] = w.phidn[g] + h * ((1.0 - gam) * w.phian[g] + gam * phia[g])


@inner
def _contact_schur(hm, hs, w, alpha, bh2):
    """One Newton correction's linear solves: ``w.y`` = S^-1 (residual), ``w.wcol`` = S^-1 of
    each gradient, then the Schur system of the contact pairs with the active set
    p = min(0, p - c s); the force change into ``w.dp``."""
    nr, grow, y, wcol, amat, bvec, dp, act = hm.nr, w.grow, w.y, w.wcol, w.amat, w.bvec, w.dp, w.act
    p = hs.p
    ng = hs.z.shape[0]
    npair = p.shape[0]
    mass_product(hs.z, hs.za, hs.phia, nr, hm.mr, hm.gr, hm.hx, hm.cx, hm.ix, hm.inertia, w.mz, w.mphi)
    for g in range(ng):
        m = nr[g]
        for i in range(m):
            w.rhs[i] = w.mz[g, i] / (1.0 + alpha) + w.fz[g, i] - alpha / (1.0 + alpha) * hs.fz[g, i]
        w.rhs[m] = w.mphi[g] / (1.0 + alpha) + w.fphi[g] - alpha / (1.0 + alpha) * hs.fphi[g]
        chol_solve(hm.sfac[g], w.rhs[: m + 1], y[g, : m + 1])
        for k in range(npair):
            chol_solve(hm.sfac[g], grow[k, g, : m + 1], wcol[k, g, : m + 1])
    for k in range(npair):
        gy = 0.0
        for g in range(ng):
            for i in range(nr[g] + 1):
                gy += grow[k, g, i] * y[g, i]
        for l in range(npair):
            acc = 0.0
            for g in range(ng):
                for i in range(nr[g] + 1):
                    acc += grow[k, g, i] * wcol[l, g, i]
            amat[k, l] = acc
        bvec[k] = gy - w.sgap[k] / bh2
    for k in range(npair):
        ck = 1.0 / (bh2 * amat[k, k])
        act[k] = p[k] - ck * w.sgap[k] < 0.0
    na = 0
    idx = np.empty(npair, np.int64)
    for k in range(npair):
        if act[k]:
            idx[na] = k
            na += 1
        else:
            dp[k] = -p[k]
    if na > 0:
        asub = np.empty((na, na))
        bsub = np.empty(na)
        for r in range(na):
            k = idx[r]
            bsub[r] = bvec[k]
            for l in range(npair):
                if not act[l]:
                    bsub[r] -= amat[k, l] * dp[l]
            for c in range(na):
                asub[r, c] = amat[k, idx[c]]
        small_solve(asub, bsub, na)
        for r in range(na):
            dp[idx[r]] = bsub[r]


@inner
def _newton_update(hm, hs, w, alpha, bh2, rref):
    """Apply one Newton correction (:func:`_contact_schur`) to the accelerations and contact
    forces. Returns (residual, active set unchanged)."""
    nr, wcol, dp, act, act_old = hm.nr, w.wcol, w.dp, w.act, w.act_old
    za, phia, p = hs.za, hs.phia, hs.p
    npair = p.shape[0]
    _contact_schur(hm, hs, w, alpha, bh2)
    res = 0.0
    for g in range(hs.z.shape[0]):
        m = nr[g]
        for i in range(m + 1):
            d = -w.y[g, i]
            for k in range(npair):
                d += wcol[k, g, i] * dp[k]
            if i < m:
                za[g, i] += d
                res = max(res, bh2 * abs(d))
            else:
                phia[g] += d
                res = max(res, bh2 * abs(d) * rref)
    same = True
    for k in range(npair):
        p[k] += dp[k]
        if act[k]:
            res = max(res, abs(w.sgap[k]))
        if act[k] != act_old[k]:
            same = False
        act_old[k] = act[k]
    return res, same


@inner
def _impact_projection(hm, hs, w):
    """No approaching normal velocity at active pairs: a plastic impulse per approaching pair;
    the kinetic energy removed goes to ``hs.sc[7]``."""
    nr, grow, wcol, bvec, act = hm.nr, w.grow, w.wcol, w.bvec, w.act
    z, zd, phid, p = hs.z, hs.zd, hs.phid, hs.p
    mr, gr, hx, cx, ix, jd = hm.mr, hm.gr, hm.hx, hm.cx, hm.ix, hm.inertia
    ng = z.shape[0]
    npair = p.shape[0]
    nimp = 0
    for k in range(npair):
        sdk = 0.0
        for g in range(ng):
            for i in range(nr[g]):
                sdk += grow[k, g, i] * zd[g, i]
            sdk += grow[k, g, nr[g]] * phid[g]
        bvec[k] = sdk
        act[k] = p[k] < 0.0 and sdk > 0.0
        if act[k]:
            nimp += 1
    if nimp == 0:
        return
    ke0 = kinetic(z, zd, phid, nr, mr, gr, hx, cx, ix, jd)
    for g in range(ng):
        for k in range(npair):
            chol_solve(hm.m0fac[g], grow[k, g, : nr[g] + 1], wcol[k, g, : nr[g] + 1])
    idx = np.empty(npair, np.int64)
    na = 0
    for k in range(npair):
        if act[k]:
            idx[na] = k
            na += 1
    asub = np.empty((na, na))
    bsub = np.empty(na)
    for r in range(na):
        bsub[r] = -bvec[idx[r]]
        for c in range(na):
            acc = 0.0
            for g in range(ng):
                for i in range(nr[g] + 1):
                    acc += grow[idx[r], g, i] * wcol[idx[c], g, i]
            asub[r, c] = acc
    small_solve(asub, bsub, na)
    for r in range(na):
        k = idx[r]
        for g in range(ng):
            for i in range(nr[g]):
                zd[g, i] += wcol[k, g, i] * bsub[r]
            phid[g] += wcol[k, g, nr[g]] * bsub[r]
    hs.sc[7] += ke0 - kinetic(z, zd, phid, nr, mr, gr, hx, cx, ix, jd)


@inner
def _record_hht(row, t, energy, hm, hs, w, hr):
    """Write record ``row`` (:data:`RECORD_COLUMNS`; pair 0 in the pair columns, every pair's
    force in ``hr.outp``)."""
    nr, grow = hm.nr, w.grow
    z, zd, phi, phid, p, sc, cres, cnod, cw = hs.z, hs.zd, hs.phi, hs.phid, hs.p, hs.sc, hs.cres, hs.cnod, hs.cw
    out = hr.out
    force = -p[0]
    out[row, 0] = t
    out[row, 1] = phi[0]
    out[row, 2] = phi[1]
    out[row, 3] = phid[0]
    out[row, 4] = phid[1]
    out[row, 5] = force
    out[row, 6] = force
    out[row, 7] = force
    out[row, 8] = -w.sgap[0]
    for side in range(2):
        px = 0.0
        py = 0.0
        for j in range(3):
            kk = cnod[0, side, j]
            px += cw[0, side, j] * w.xf[2 * kk]
            py += cw[0, side, j] * w.xf[2 * kk + 1]
        out[row, 9 + 2 * side] = px
        out[row, 10 + 2 * side] = py
    out[row, 13] = cres[0, 0]
    out[row, 14] = cres[0, 1]
    out[row, 15] = kinetic(z, zd, phid, nr, hm.mr, hm.gr, hm.hx, hm.cx, hm.ix, hm.inertia)
    out[row, 16] = energy
    out[row, 17] = sc[1]
    out[row, 18] = sc[7]
    out[row, 19] = sc[3]
    out[row, 22] = sc[4]
    out[row, 25] = sc[2]
    out[row, 26] = w.tau[0]
    out[row, 27] = w.tau[1]
    out[row, 28] = cres[0, 5]
    sd = 0.0
    for g in range(z.shape[0]):
        for i in range(nr[g]):
            sd += grow[0, g, i] * zd[g, i]
        sd += grow[0, g, nr[g]] * phid[g]
    out[row, 29] = sd
    out[row, 30] = 0.0
    out[row, 31] = sc[5]
    for k in range(p.shape[0]):
        hr.outp[row, k] = -p[k]
    sc[2] = 0.0
    sc[3] = 0.0
    sc[4] = 0.0


@inner
def _close_hht_step(t, its, hs, w):
    """Running scalars at the end of a step: time, external work, peak force, impacts; F of
    the new state becomes the step start's."""
    phi, p, sc = hs.phi, hs.p, hs.sc
    sc[0] = t
    for g in range(hs.z.shape[0]):
        for i in range(hs.z.shape[1]):
            hs.fz[g, i] = w.fz[g, i]
        hs.fphi[g] = w.fphi[g]
        sc[1] += 0.5 * (w.taun[g] + w.tau[g]) * (phi[g] - w.phin[g])
    sc[2] = max(sc[2], -p[0])
    sc[3] = max(sc[3], abs(w.sgap[0]) if p[0] < 0.0 else 0.0)
    sc[4] = max(sc[4], its)
    if p[0] < 0.0 and sc[6] == 0.0:
        sc[5] += 1.0
    sc[6] = 1.0 if p[0] < 0.0 else 0.0


@inner
def _initial_evaluation(hm, hs, tpar, mpts):
    """F at the start state of ``hs`` (into ``hs.fz, hs.fphi``) and the consistent start
    accelerations ``M a = -F`` (contact forces zero). Returns (contact search ok, kinetic +
    strain energy [J])."""
    w = new_hht_scratch(hm, hs, mpts)
    e_strain = _evaluate_state(hm, hs, w, tpar, mpts, hs.fz, hs.fphi)
    if w.ok[0] == 0:
        return False, 0.0
    for g in range(2):
        m = hm.nr[g]
        rhs = np.empty(m + 1)
        for i in range(m):
            rhs[i] = -hs.fz[g, i]
        rhs[m] = -hs.fphi[g]
        sol = np.empty(m + 1)
        chol_solve(hm.m0fac[g], rhs, sol)
        for i in range(m):
            hs.za[g, i] = sol[i]
        hs.phia[g] = sol[m]
    ke = kinetic(hs.z, hs.zd, hs.phid, hm.nr, hm.mr, hm.gr, hm.hx, hm.cx, hm.ix, hm.inertia)
    return True, ke + e_strain


@entry
def run_hht(n_steps, rec_every, row, init, hm, hp, hs, hr):
    """Advance ``n_steps`` HHT-alpha steps (Negrut et al. 2007 form for index-3 constraints).

    ``hm`` :class:`~rotaflex.gear.kernels.arrays.HHTModel`, ``hp``
    :class:`~rotaflex.gear.kernels.arrays.HHTParams`, ``hs``
    :class:`~rotaflex.gear.kernels.arrays.HHTState` (advanced in place), ``hr``
    :class:`~rotaflex.gear.kernels.arrays.HHTRecords`; ``row`` the next free record row.
    ``hs.fz, hs.fphi`` hold F at the current state (updated). ``hs.sc`` running scalars:
    (t, W_ext, peak force since record, max |s| since record, max iterations since record,
    impacts, previous contact flag, kinetic energy removed by the impact projection).

    Impact law (as the paper's velocity pass): after each step, an active pair whose relative
    normal velocity is still approaching gets a normal impulse that makes it zero (perfectly
    plastic); the kinetic energy removed is accumulated in ``sc[7]``.
    ``init``: first call of a run: before the steps, evaluate F at the start state and make
    the start accelerations consistent (``M a = -F``, contact forces zero); the start energy
    (kinetic + strain) [J] goes to ``hr.info[3]``. (Part of this entry point rather than one of
    its own: each entry point compiles its whole tree of kernels again.)
    Returns (status, next row); status 1 = Newton iteration did not converge (``info`` =
    time, residual, tolerance), 4 = contact search failed.
    """
    info = hr.info
    h = hp.dt
    alpha = hp.alpha
    tpar = np.array([hp.tau0, hp.theta_2, hp.theta_s, hp.gain[0], hp.gain[1]])
    tol = hp.tol
    gam = 0.5 - alpha
    beta = 0.25 * (1.0 - alpha) ** 2
    bh2 = beta * h * h
    if init:
        ok, e_start = _initial_evaluation(hm, hs, tpar, hp.n_points)
        info[3] = e_start
        if not ok:
            info[0] = hs.sc[0]
            return 4, row
    w = new_hht_scratch(hm, hs, hp.n_points)
    energy = 0.0
    for step in range(n_steps):
        t = hs.sc[0]
        _step_start(hm, hs, w, tpar)
        converged = False
        res = 0.0
        its = 0
        for it in range(hp.max_iter + 1):
            its = it
            _newmark(hm, hs, w, h, beta, gam)
            energy = _evaluate_state(hm, hs, w, tpar, hp.n_points, w.fz, w.fphi)
            if w.ok[0] == 0:
                info[0] = t + h
                return 4, row
            if converged or it == hp.max_iter:
                break
            res, same = _newton_update(hm, hs, w, alpha, bh2, hp.r_ref)
            if res <= tol and same:
                converged = True
        if not converged:
            info[0] = t + h
            info[1] = res
            info[2] = tol
            return 1, row
        _impact_projection(hm, hs, w)
        t = t + h
        _close_hht_step(t, its, hs, w)
        if (step + 1) % rec_every == 0 and row < hr.out.shape[0]:
            _record_hht(row, t, energy, hm, hs, w, hr)
            row += 1
    return 0, row
