"""The RK4 stage loop of the paper's scheme (compiled): co-rotational elastic force, external
torques, accelerations at a stage, and :func:`run_steps`, which advances many steps with the
three constraint passes (displacement, velocity, acceleration) per step for any number of
contact pairs (one tooth per gear = one pair).

Conventions (all SI)
--------------------
* Nodes of gear A come first, then gear B; DOFs are interleaved ``[x0, y0, x1, y1, ...]`` and
  hold *absolute* positions ``x`` (the paper's absolute displacement plus the reference).
* ``phi[g]`` is the counter-clockwise rotation of disk ``g`` since t = 0; the tooth's local
  frame is rotated by ``theta0[g] + phi[g]`` from the global frame.
* Constraint rows: ``2*k + c`` is the tie of tie-node ``k`` in direction ``c``; row
  ``2*nt + j`` is the contact of pair ``j``. ``G`` is the matrix ``[-Phi_q; s_q]`` so that the
  constraint force is ``G^T mu`` and the error vector of eq. 8 changes by ``G dq``.
* A contact force ``p <= 0`` (compression); a gap ``s > 0`` is a penetration.

Status codes returned by :func:`run_steps`: 0 ok; 1, 2, 3 = the displacement, velocity or
acceleration pass did not converge (``info`` holds time, residual, tolerance); 4 = contact
search failed.
"""

from __future__ import annotations

import numpy as np

from rotaflex.core.compiled import entry, inner
from rotaflex.gear.kernels.arrays import StepScratch
from rotaflex.gear.kernels.contact import (
    sample_flank,
    sample_smooth,
    search_pairs,
    sliding_terms,
    spline_second,
)
from rotaflex.gear.kernels.forces import (
    accelerations,
    elastic_force,
    kinetic_energy,
    normal_velocity,
    set_rotation,
    tie_vectors,
    torque_of,
)
from rotaflex.gear.kernels.passes import (
    contact_columns,
    gt_apply,
    k_local_product,
    respond,
    solve_pass,
)

#: global columns of the per-record output ``Records.out``
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
#: per-pair columns of the per-record output ``Records.outp``
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


@inner
def new_scratch(m, s, mpts):
    """Work arrays of :func:`run_steps` for the model ``m`` and state ``s``."""
    npair = s.cres.shape[0]
    nw = s.cnod.shape[2]
    nd = 2 * m.xloc.shape[0]
    nt = m.tie_node.shape[0]
    nc = 2 * nt + npair
    nsm = nw if nw != 3 else 0  # outside the call: numba rejects control flow among many keywords
    return StepScratch(
        rot=np.empty((2, 2)),
        bvec=np.empty((nt, 2)),
        rx=np.empty((nt, 2)),
        wbuf=np.empty(nd),
        fglob=np.empty(nd),
        fc=np.zeros(nd),
        tel=np.empty(2),
        fth=np.zeros(2),
        gsc=np.zeros(nd),
        gth=np.zeros(2),
        zk=np.zeros(nd),
        xs=np.empty(nd),
        vs=np.empty(nd),
        ak=np.empty(nd),
        xsum=np.empty(nd),
        asum=np.empty(nd),
        ps=np.empty(2),
        os_=np.empty(2),
        alk=np.empty(2),
        psum=np.empty(2),
        osum=np.empty(2),
        phi_t=np.empty(2),
        pa=np.empty((npair, mpts, 2)),
        ma=np.empty((npair, mpts, 2)),
        pb=np.empty((npair, mpts, 2)),
        mb=np.empty((npair, mpts, 2)),
        va=np.empty((mpts, 2)),
        mva=np.empty((mpts, 2)),
        vb=np.empty((mpts, 2)),
        mvb=np.empty((mpts, 2)),
        cn=np.empty((npair, 2)),
        cn_s=np.empty((npair, 2)),
        cnod_t=np.empty((npair, 2, nw), np.int64),
        cw_t=np.empty((npair, 2, nw)),
        ct=np.zeros((npair, 4)),
        zero4=np.zeros((npair, 4)),
        rate1=np.zeros(4),
        ccol=np.zeros((npair, nc)),
        e0=np.zeros(nc),
        mu0=np.zeros(nc),
        dmu=np.zeros(nc),
        pbar=np.zeros(npair),
        sh_pred=np.zeros(npair),
        vtgt=np.zeros(npair),
        work=np.zeros((13, nc)),
        stats=np.zeros(2),
        poly=np.zeros((4, 33)),
        actm=np.zeros((2, npair), np.bool_),
        fl_nodes=np.empty(3, np.int64),
        fl_w=np.empty(3),
        sm_w=np.empty(nsm),
    )


@inner(_nrt=False)
def hold_contact(s, w):
    """Contact parameters and normal of the current state into ``w.ct`` (rates start there)."""
    for jp in range(s.cres.shape[0]):
        w.ct[jp, 0] = s.cres[jp, 0]
        w.ct[jp, 1] = s.cres[jp, 1]
        w.ct[jp, 2] = w.cn[jp, 0]
        w.ct[jp, 3] = w.cn[jp, 1]


@inner(_nrt=False)
def _stage(x, phi, mu, tau_off, rates, m, tpar, tmode, w, a, alp):
    """:func:`accelerations` at a stage state with the step-start contact ``w.ct`` advanced by
    ``rates`` over ``tau_off``; stage contact rows in ``w.cnod_t, w.cw_t``."""
    return accelerations(
        x,
        phi,
        mu,
        tau_off,
        w.ct,
        rates,
        m,
        tpar,
        tmode,
        w.cnod_t,
        w.cw_t,
        w.rot,
        w.bvec,
        w.rx,
        w.wbuf,
        w.fglob,
        w.tel,
        w.fc,
        w.fth,
        w.cn_s,
        w.fl_nodes,
        w.fl_w,
        w.sm_w,
        a,
        alp,
    )


@inner(_nrt=False)
def rk4_predict(dt, m, tpar, tmode, s, w):
    """Classical RK4 step of the state ``s`` with the multipliers ``s.mu`` held over the step
    (k1 = the stored consistent acceleration of the step start)."""
    x, v, a, phi, om, alp = s.x, s.v, s.a, s.phi, s.om, s.alp
    xs, vs, ak, xsum, asum = w.xs, w.vs, w.ak, w.xsum, w.asum
    ps, os_, alk, psum, osum = w.ps, w.os_, w.alk, w.psum, w.osum
    nd = x.shape[0]
    for q in range(nd):
        xsum[q] = v[q]
        asum[q] = a[q]
    for g in range(2):
        psum[g] = om[g]
        osum[g] = alp[g]
    for stage in range(3):
        hh = 0.5 * dt if stage < 2 else dt
        wgt = 2.0 if stage < 2 else 1.0
        if stage == 0:
            for q in range(nd):
                xs[q] = x[q] + hh * v[q]
                vs[q] = v[q] + hh * a[q]
            for g in range(2):
                ps[g] = phi[g] + hh * om[g]
                os_[g] = om[g] + hh * alp[g]
        else:
            for q in range(nd):
                xs[q] = x[q] + hh * vs[q]
                vs[q] = v[q] + hh * ak[q]
            for g in range(2):
                ps[g] = phi[g] + hh * os_[g]
                os_[g] = om[g] + hh * alk[g]
        _stage(xs, ps, s.mu, hh, s.rates, m, tpar, tmode, w, ak, alk)
        for q in range(nd):
            xsum[q] += wgt * vs[q]
            asum[q] += wgt * ak[q]
        for g in range(2):
            psum[g] += wgt * os_[g]
            osum[g] += wgt * alk[g]
    for q in range(nd):
        x[q] += dt / 6.0 * xsum[q]
        v[q] += dt / 6.0 * asum[q]
    for g in range(2):
        phi[g] += dt / 6.0 * psum[g]
        om[g] += dt / 6.0 * osum[g]


@inner(_nrt=False)
def _pass_change(m, s, w):
    """``w.gsc, w.gth`` = G^T (mu - mu0) of the pass just solved (contact rows of ``s``)."""
    nc = s.mu.shape[0]
    for q in range(nc):
        w.dmu[q] = s.mu[q] - w.mu0[q]
    w.gsc[:] = 0.0
    w.gth[:] = 0.0
    gt_apply(w.dmu, m.tie_node, m.tie_gear, w.bvec, w.rot, s.cnod, s.cw, w.cn, w.gsc, w.gth)


@inner(_nrt=False)
def _columns(c1, c2, m, s, w):
    contact_columns(c1, c2, m, w.rot, s.cnod, s.cw, w.cn, w.gsc, w.zk, w.ccol)


@inner(_nrt=False)
def _copy(src, dst):
    """dst[:] = src element by element (an array-to-array slice assignment needs numba's
    reference counting, which the pass kernels are compiled without)."""
    for q in range(src.shape[0]):
        dst[q] = src[q]


@inner(_nrt=False)
def _fail(r, t, res, tol):
    r.info[0] = t
    r.info[1] = res
    r.info[2] = tol


@inner(_nrt=True)
def _search_all(s, m, p, w):
    """Contact search of every pair at the state ``s.x, s.phi`` (results into ``s.cres, s.cnod,
    s.cw, s.spair``); False when a search fails."""
    return search_pairs(
        s.x,
        s.phi,
        m,
        p.n_points,
        p.window_lo,
        p.window_hi,
        p.corners,
        w.pa,
        w.ma,
        w.pb,
        w.mb,
        s.cres,
        s.cnod,
        s.cw,
        s.spair,
    )


@inner(_nrt=False)
def predicted_contact(t, p, m, s, w, r):
    """Contact search of every pair at the predicted state; approach velocities ``w.sh_pred``,
    predicted positions kept in ``w.xsum, w.psum``. Returns (ok, kinetic energy)."""
    if not _search_all(s, m, p, w):
        r.info[0] = t
        return False, 0.0
    for jp in range(s.cres.shape[0]):
        w.cn[jp, 0] = s.cres[jp, 3]
        w.cn[jp, 1] = s.cres[jp, 4]
        # approach velocity of the predicted state (before the passes): impact reference
        w.sh_pred[jp] = normal_velocity(s.v, s.cnod, s.cw, w.cn, jp)
    ke_pred = kinetic_energy(s.v, s.om, m.minv, m.inertia)
    for q in range(s.x.shape[0]):
        w.xsum[q] = s.x[q]  # predicted state (strain energy of a closing step)
    w.psum[0] = s.phi[0]
    w.psum[1] = s.phi[1]
    return True, ke_pred


@inner(_nrt=False)
def displacement_pass(t, p, m, s, w, r):
    """Pass 1: displacement constraints (eq. 8, 19), then the affine RK4 response of positions
    and velocities to the new multipliers. Returns (status, closing): status 1 if the pass did
    not converge; ``closing`` when a contact closes in this step."""
    x, v, phi, om, mu, sc, spair = s.x, s.v, s.phi, s.om, s.mu, s.sc, s.spair
    minv, jd = m.minv, m.inertia
    dt = p.dt
    c11 = dt * dt / 2.0
    c12 = dt**4 / 24.0
    c21 = dt
    c22 = dt**3 / 6.0
    nt = m.tie_node.shape[0]
    ic = 2 * nt
    npair = s.cres.shape[0]
    e0, rot, zk, gsc = w.e0, w.rot, w.zk, w.gsc
    set_rotation(phi, m.theta0, rot)
    tie_vectors(x, m.centres, m.tie_node, m.tie_gear, rot, w.bvec, w.rx)
    for k in range(nt):
        i = m.tie_node[k]
        e0[2 * k] = -(w.rx[k, 0] - m.xloc[i, 0])
        e0[2 * k + 1] = -(w.rx[k, 1] - m.xloc[i, 1])
    for jp in range(npair):
        e0[ic + jp] = -s.cres[jp, 2]
    _columns(c11, c12, m, s, w)
    _copy(mu, w.mu0)
    res, its, ok = solve_pass(
        p,
        np.int64(1),
        e0,
        mu,
        w.pbar,
        c11,
        c12,
        p.eps_disp,
        p.tol_disp,
        p.n_accel,
        p.max_iter,
        m,
        w.bvec,
        w.ccol,
        w.work,
        w.stats,
        w.poly,
        w.actm,
    )
    if not ok:
        _fail(r, t, res, p.tol_disp)
        return 1, False
    sc[6] = max(sc[6], res)
    sc[9] = max(sc[9], its)
    for jp in range(npair):
        spair[jp, 0] = e0[ic + jp] + w.work[0, ic + jp]
    _pass_change(m, s, w)
    # RK4 positions and velocities with the new multipliers (affine response)
    k_local_product(gsc, m, rot, zk)
    for i in range(minv.shape[0]):
        gg = m.gid[i]
        cc = rot[gg, 0]
        ss = rot[gg, 1]
        kx = cc * zk[2 * i] - ss * zk[2 * i + 1]
        ky = ss * zk[2 * i] + cc * zk[2 * i + 1]
        x[2 * i] += minv[i] * (c11 * gsc[2 * i] - c12 * kx)
        x[2 * i + 1] += minv[i] * (c11 * gsc[2 * i + 1] - c12 * ky)
        v[2 * i] += minv[i] * (c21 * gsc[2 * i] - c22 * kx)
        v[2 * i + 1] += minv[i] * (c21 * gsc[2 * i + 1] - c22 * ky)
    zk[:] = 0.0
    for g in range(2):
        phi[g] += c11 * w.gth[g] / jd[g]
        om[g] += c21 * w.gth[g] / jd[g]
    gsc[:] = 0.0
    closing = False
    for jp in range(npair):
        w.pbar[jp] = mu[ic + jp]
        spair[jp, 2] = w.pbar[jp]
        if w.pbar[jp] < 0.0 and w.mu0[ic + jp] == 0.0:
            closing = True
    return 0, closing


@inner(_nrt=False)
def velocity_pass(t, p, m, s, w, r, ke_pred, closing):
    """Pass 2: velocity constraints (eq. 15, 20, 22) with Newton's impact law; the kinetic
    energy it removes (and, for a closing contact, the displacement pass's change of kinetic +
    predicted strain energy) goes to ``sc[2]``. Returns 2 if the pass did not converge, else 0."""
    x, v, phi, om, mu, sc, spair = s.x, s.v, s.phi, s.om, s.mu, s.sc, s.spair
    minv, jd = m.minv, m.inertia
    dt = p.dt
    tol2 = p.tol_vel
    c21 = dt
    c22 = dt**3 / 6.0
    nt = m.tie_node.shape[0]
    ic = 2 * nt
    npair = s.cres.shape[0]
    e0, rot, bvec = w.e0, w.rot, w.bvec
    set_rotation(phi, m.theta0, rot)
    tie_vectors(x, m.centres, m.tie_node, m.tie_gear, rot, bvec, w.rx)
    ke0 = kinetic_energy(v, om, minv, jd)
    if closing:
        # a contact closes: the displacement pass stops the penetration with a force held
        # over the step, i.e. it takes part in the impact; its change of kinetic + strain
        # energy is counted in D (strain part added after pass 3)
        set_rotation(w.psum, m.theta0, rot)
        se_pred = elastic_force(w.xsum, rot, m, w.wbuf, w.fglob, w.tel)
        set_rotation(phi, m.theta0, rot)
        sc[2] += ke_pred + se_pred - ke0
    for k in range(nt):
        i = m.tie_node[k]
        g = m.tie_gear[k]
        cc = rot[g, 0]
        ss = rot[g, 1]
        e0[2 * k] = -(cc * v[2 * i] + ss * v[2 * i + 1]) + bvec[k, 0] * om[g]
        e0[2 * k + 1] = -(-ss * v[2 * i] + cc * v[2 * i + 1]) + bvec[k, 1] * om[g]
    for jp in range(npair):
        sh = normal_velocity(v, s.cnod, s.cw, w.cn, jp)
        w.vtgt[jp] = 0.0
        if w.pbar[jp] < 0.0 and sh > tol2 and w.mu0[ic + jp] == 0.0:
            sc[14] += 1.0
        if p.restitution > 0.0 and w.pbar[jp] < 0.0 and w.sh_pred[jp] > tol2 and w.mu0[ic + jp] == 0.0:
            # Newton impact law: target -e x (approach velocity before the displacement
            # pass, which already removes part of it) instead of 0
            w.vtgt[jp] = -p.restitution * w.sh_pred[jp]
        e0[ic + jp] = sh - w.vtgt[jp]
    _columns(c21, c22, m, s, w)
    _copy(mu, w.mu0)
    res, its, ok = solve_pass(
        p,
        np.int64(2),
        e0,
        mu,
        w.pbar,
        c21,
        c22,
        p.eps_vel,
        tol2,
        p.n_accel,
        p.max_iter,
        m,
        bvec,
        w.ccol,
        w.work,
        w.stats,
        w.poly,
        w.actm,
    )
    if not ok:
        _fail(r, t, res, tol2)
        return 2
    sc[7] = max(sc[7], res)
    sc[10] = max(sc[10], its)
    for jp in range(npair):
        spair[jp, 1] = e0[ic + jp] + w.work[0, ic + jp] + w.vtgt[jp]
        spair[jp, 3] = mu[ic + jp]
    _pass_change(m, s, w)
    respond(w.gsc, w.gth, c21, c22, m, rot, w.zk, v, om, 1.0)
    w.zk[:] = 0.0
    w.gsc[:] = 0.0
    sc[2] += ke0 - kinetic_energy(v, om, minv, jd)
    return 0


@inner(_nrt=False)
def _external_work(tpar, tmode, m, s, w, tau_old0, tau_old1):
    """Trapezoidal external work over the step (disk angles ``w.phi_t`` -> ``s.phi``)."""
    phi, sc = s.phi, s.sc
    tau_new0 = torque_of(np.int64(0), phi[0], m.rsgn[0], tpar, tmode)
    tau_new1 = torque_of(np.int64(1), phi[1], m.rsgn[1], tpar, tmode)
    sc[1] += 0.5 * (tau_old0 + tau_new0) * (phi[0] - w.phi_t[0])
    sc[1] += 0.5 * (tau_old1 + tau_new1) * (phi[1] - w.phi_t[1])
    sc[18] = tau_new0
    sc[19] = tau_new1


@inner(_nrt=True)
def acceleration_errors(m, s, w):
    """Error vector of pass 3: tie rows (-Phi_ddot) and each pair's relative normal acceleration
    with the sliding terms of appendix A (whose contact-parameter rates go to ``s.rates``)."""
    v, a, phi, om, alp = s.v, s.a, s.phi, s.om, s.alp
    cres, cnod, cw, rates = s.cres, s.cnod, s.cw, s.rates
    e0, rot, bvec, rx, cn = w.e0, w.rot, w.bvec, w.rx, w.cn
    nt = m.tie_node.shape[0]
    ic = 2 * nt
    nw = cnod.shape[2]
    for k in range(nt):
        i = m.tie_node[k]
        g = m.tie_gear[k]
        cc = rot[g, 0]
        ss = rot[g, 1]
        al0 = cc * a[2 * i] + ss * a[2 * i + 1]
        al1 = -ss * a[2 * i] + cc * a[2 * i + 1]
        vl0 = cc * v[2 * i] + ss * v[2 * i + 1]
        vl1 = -ss * v[2 * i] + cc * v[2 * i + 1]
        # -Phi_ddot = -R^T a + b alpha + omega^2 R^T (x - c) + 2 omega J R^T v
        e0[2 * k] = -al0 + bvec[k, 0] * alp[g] + om[g] ** 2 * rx[k, 0] - 2 * om[g] * vl1
        e0[2 * k + 1] = -al1 + bvec[k, 1] * alp[g] + om[g] ** 2 * rx[k, 1] + 2 * om[g] * vl0
    for jp in range(cres.shape[0]):
        if s.spair[jp, 5] == 0.0:
            e0[ic + jp] = 0.0
            for q in range(4):
                rates[jp, q] = 0.0
            continue
        if nw == 3:
            sample_flank(v, m.flank[jp, 0], m.nedge[jp, 0], w.va)
            sample_flank(v, m.flank[jp, 1], m.nedge[jp, 1], w.vb)
        else:
            sample_smooth(
                v, m.flank[jp, 0], m.tab[jp, 0], m.mloc[jp, 0], m.theta0[0] + phi[0], om[0], np.bool_(True), w.va
            )
            sample_smooth(
                v, m.flank[jp, 1], m.tab[jp, 1], m.mloc[jp, 1], m.theta0[1] + phi[1], om[1], np.bool_(True), w.vb
            )
        spline_second(w.va, w.mva)
        spline_second(w.vb, w.mvb)
        hs, _ad, _bd = sliding_terms(
            w.pa[jp], w.ma[jp], w.va, w.mva, w.pb[jp], w.mb[jp], w.vb, w.mvb, m.sig[0], m.sig[1], cres[jp], w.rate1
        )
        for q in range(4):
            rates[jp, q] = w.rate1[q]
        sa = hs
        for j in range(nw):
            i = cnod[jp, 0, j]
            sa += cw[jp, 0, j] * (cn[jp, 0] * a[2 * i] + cn[jp, 1] * a[2 * i + 1])
            i = cnod[jp, 1, j]
            sa -= cw[jp, 1, j] * (cn[jp, 0] * a[2 * i] + cn[jp, 1] * a[2 * i + 1])
        e0[ic + jp] = sa


@inner(_nrt=False)
def acceleration_pass(t, p, tpar, tmode, m, s, w, r):
    """Pass 3: consistent accelerations (eq. 17, 21, 23) of the current positions and
    velocities. Returns (status, strain energy): status 3 if the pass did not converge."""
    a, alp, mu, sc = s.a, s.alp, s.mu, s.sc
    minv, jd = m.minv, m.inertia
    hold_contact(s, w)
    eel = accelerations(
        s.x,
        s.phi,
        mu,
        0.0,
        w.ct,
        w.zero4,
        m,
        tpar,
        tmode,
        s.cnod,
        s.cw,
        w.rot,
        w.bvec,
        w.rx,
        w.wbuf,
        w.fglob,
        w.tel,
        w.fc,
        w.fth,
        w.cn_s,
        w.fl_nodes,
        w.fl_w,
        w.sm_w,
        a,
        alp,
    )
    acceleration_errors(m, s, w)
    _columns(1.0, 0.0, m, s, w)
    _copy(mu, w.mu0)
    res, its, ok = solve_pass(
        p,
        np.int64(3),
        w.e0,
        mu,
        w.pbar,
        1.0,
        0.0,
        p.eps_acc,
        p.tol_acc,
        p.n_accel,
        p.max_iter,
        m,
        w.bvec,
        w.ccol,
        w.work,
        w.stats,
        w.poly,
        w.actm,
    )
    if not ok:
        _fail(r, t, res, p.tol_acc)
        return 3, eel
    sc[8] = max(sc[8], res)
    sc[11] = max(sc[11], its)
    _pass_change(m, s, w)
    for i in range(minv.shape[0]):
        a[2 * i] += minv[i] * w.gsc[2 * i]
        a[2 * i + 1] += minv[i] * w.gsc[2 * i + 1]
    for g in range(2):
        alp[g] += w.gth[g] / jd[g]
    w.gsc[:] = 0.0
    return 0, eel


@inner(_nrt=False)
def close_step(t, eel, closing, initial, m, s, w):
    """Running scalars at the end of a step: time, strain energy, peak forces, tie residual."""
    sc, spair, mu, cres, rx = s.sc, s.spair, s.mu, s.cres, w.rx
    ic = 2 * m.tie_node.shape[0]
    sc[0] = t
    sc[3] = eel
    if closing:
        sc[2] -= eel  # strain energy after the displacement pass (positions unchanged since)
    for jp in range(cres.shape[0]):
        force = -mu[ic + jp]
        if force > spair[jp, 4]:
            spair[jp, 4] = force
        if initial:
            spair[jp, 0] = -cres[jp, 2]
    tr = 0.0
    for k in range(m.tie_node.shape[0]):
        i = m.tie_node[k]
        tr = max(tr, max(abs(rx[k, 0] - m.xloc[i, 0]), abs(rx[k, 1] - m.xloc[i, 1])))
    sc[15] = max(sc[15], tr)


@inner(_nrt=False)
def record_row(row, eel, m, s, r):
    """Write record ``row`` (:data:`GLOBAL_COLUMNS`, :data:`PAIR_COLUMNS`, tie multipliers) and
    reset the per-record maxima."""
    x, phi, om, mu, sc, spair, cres, cnod, cw = s.x, s.phi, s.om, s.mu, s.sc, s.spair, s.cres, s.cnod, s.cw
    out, outp = r.out, r.outp
    ic = 2 * m.tie_node.shape[0]
    out[row, 0] = sc[0]
    out[row, 1] = phi[0]
    out[row, 2] = phi[1]
    out[row, 3] = om[0]
    out[row, 4] = om[1]
    out[row, 5] = kinetic_energy(s.v, om, m.minv, m.inertia)
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
    for jp in range(cres.shape[0]):
        outp[row, jp, 0] = -mu[ic + jp]
        outp[row, jp, 1] = -spair[jp, 2]
        outp[row, jp, 2] = -spair[jp, 3]
        outp[row, jp, 3] = -spair[jp, 0]
        for side in range(2):
            px = 0.0
            py = 0.0
            for j in range(cnod.shape[2]):
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
    for q in range(ic):
        r.out_mu[row, q] = mu[q]
    for q in (6, 7, 8, 9, 10, 11, 15):
        sc[q] = 0.0


@entry
def run_steps(n_steps, rec_every, row, init, m, p, s, r):
    """Advance ``n_steps`` RK4 steps with the three constraint passes per step.

    Parameters
    ----------
    n_steps, rec_every : int
        Steps of this call; a record is written every ``rec_every`` steps.
    row : int
        Next free record row.
    init : bool
        First call of a run: search the contact and make the start accelerations consistent
        (pass 3 only) before the first step.
    m : ModelArrays
    p : StepParams
    s : State
        Advanced in place. ``s.sc`` = (t, W_ext, D, E_el, -, -, res1, res2, res3, it1, it2,
        it3, -, -, n_impacts, tie_res, -, -, tau_A, tau_B, ...); ``s.spair[j]`` = (gap after
        pass 1, normal velocity after pass 2, p_bar, p_hat, peak force since the last record,
        in-mesh flag).
    r : Records

    Returns (status, next record row).
    """
    tpar = (p.tau0, p.theta_2, p.theta_s, p.gain[0], p.gain[1])
    w = new_scratch(m, s, p.n_points)
    npair = s.cres.shape[0]
    if init:
        if not _search_all(s, m, p, w):
            r.info[0] = s.sc[0]
            return 4, row
    for jp in range(npair):
        w.cn[jp, 0] = s.cres[jp, 3]
        w.cn[jp, 1] = s.cres[jp, 4]
    for step in range(n_steps + (1 if init else 0)):
        initial = init and step == 0
        closing = False
        if initial:
            t = s.sc[0]
            for jp in range(npair):
                w.pbar[jp] = -1.0 if s.cres[jp, 2] <= 0.0 else 0.0
        else:
            # one step of the paper's scheme: RK4 prediction with the multipliers held, contact
            # search, displacement and velocity passes, external work (written here, not in a
            # kernel of its own: numba compiles a called kernel's whole tree again per level)
            t = s.sc[0] + p.dt
            hold_contact(s, w)
            w.phi_t[0] = s.phi[0]
            w.phi_t[1] = s.phi[1]
            tau_old0 = torque_of(np.int64(0), s.phi[0], m.rsgn[0], tpar, p.torque_mode)
            tau_old1 = torque_of(np.int64(1), s.phi[1], m.rsgn[1], tpar, p.torque_mode)
            rk4_predict(p.dt, m, tpar, p.torque_mode, s, w)
            ok, ke_pred = predicted_contact(t, p, m, s, w, r)
            if not ok:
                return 4, row
            status, closing = displacement_pass(t, p, m, s, w, r)
            if status == 0:
                status = velocity_pass(t, p, m, s, w, r, ke_pred, closing)
            if status != 0:
                return status, row
            _external_work(tpar, p.torque_mode, m, s, w, tau_old0, tau_old1)
        status, eel = acceleration_pass(t, p, tpar, p.torque_mode, m, s, w, r)
        if status != 0:
            return status, row
        close_step(t, eel, closing, initial, m, s, w)
        if (not initial) and ((step + (0 if init else 1)) % rec_every == 0) and row < r.out.shape[0]:
            record_row(row, eel, m, s, r)
            row += 1
    return 0, row
