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

import math

import numpy as np
from numba import njit

from rotaflex.gear.kernels.contact import (
    flank_weights,
    sample_flank,
    sample_smooth,
    search_pairs,
    sliding_terms,
    smooth_weights,
    spline_second,
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
def kinetic_energy(v, om, minv, jd):
    e = 0.5 * (jd[0] * om[0] ** 2 + jd[1] * om[1] ** 2)
    for i in range(minv.shape[0]):
        e += 0.5 * (v[2 * i] ** 2 + v[2 * i + 1] ** 2) / minv[i]
    return e


@njit(cache=True)
def torque_of(g, phi_g, rsgn_g, tpar, mode):
    """External torque on disk ``g`` (counter-clockwise positive): ramp of Fig. 7 or constant.

    ``tpar`` = (tau0, theta_2, theta_s, u_0, u_1): disk ``g`` gets ``u_g tau(u_g theta_g)``, the
    driver's ramp in the driver's rotation ``u_g theta_g`` scaled by the gear ratio ``u_g``
    (1 for the driver, z_driven / z_driver for the driven gear; u = 1 multiplies exactly).
    """
    u = tpar[3] if g == 0 else tpar[4]
    if mode == 1:
        return u * tpar[0]
    return u * ramp_torque(u * rsgn_g * phi_g, tpar[0], tpar[1], tpar[2])


@njit(cache=True)
def accelerations(
    x,
    phi,
    mu,
    tau_off,
    ct,
    rates,
    m,
    tpar,
    tmode,
    cnod,
    cw,
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

    The constraint force is ``G(q)^T mu`` with the Jacobian at the stage state: tie forces
    ``-R(phi) lambda`` turn with the disk; each contact force follows its contact point, whose
    parameters and normal at the step start (``ct[j]`` = a, b, n_x, n_y) advance with their
    rates (``rates[j]`` = da/dt, db/dt, dn_x/dt, dn_y/dt, appendix A) over ``tau_off`` seconds.
    ``m`` is the :class:`~rotaflex.gear.kernels.arrays.ModelArrays`; ``tpar`` = (tau0, theta_2,
    theta_s, u_A, u_B).
    """
    set_rotation(phi, m.theta0, rot)
    tie_vectors(x, m.centres, m.tie_node, m.tie_gear, rot, bvec, rx)
    nw = cnod.shape[2]
    nodes = np.empty(3, np.int64)
    w = np.empty(3)
    ws = np.empty(nw if nw != 3 else 0)
    for jp in range(ct.shape[0]):
        n0 = ct[jp, 2] + rates[jp, 2] * tau_off
        n1 = ct[jp, 3] + rates[jp, 3] * tau_off
        ln = math.hypot(n0, n1)
        cn_s[jp, 0] = n0 / ln
        cn_s[jp, 1] = n1 / ln
        for side in range(2):
            s = ct[jp, side] + rates[jp, side] * tau_off
            if nw == 3:
                flank_weights(m.flank[jp, side], m.nedge[jp, side], s, nodes, w)
                for j in range(3):
                    cnod[jp, side, j] = nodes[j]
                    cw[jp, side, j] = w[j]
            else:
                smooth_weights(m.tab[jp, side], s, ws)
                for j in range(nw):
                    cnod[jp, side, j] = m.flank[jp, side, j]
                    cw[jp, side, j] = ws[j]
    fc[:] = 0.0
    fth[:] = 0.0
    gt_apply(mu, m.tie_node, m.tie_gear, bvec, rot, cnod, cw, cn_s, fc, fth)
    energy = elastic_force(x, m.xloc, m.gid, m.centres, rot, m.indptr, m.indices, m.data, wbuf, floc, fglob, tel)
    nn = m.xloc.shape[0]
    for i in range(nn):
        a[2 * i] = m.minv[i] * (fglob[2 * i] + fc[2 * i])
        a[2 * i + 1] = m.minv[i] * (fglob[2 * i + 1] + fc[2 * i + 1])
    for g in range(2):
        tau = torque_of(g, phi[g], m.rsgn[g], tpar, tmode)
        alp[g] = (tau + tel[g] + fth[g]) / m.inertia[g]
    return energy


@njit(cache=True)
def _normal_velocity(v, cnod, cw, cn, jp):
    """Relative normal velocity of the contact row of pair ``jp`` (> 0: approaching)."""
    sh = 0.0
    for j in range(cnod.shape[2]):
        i = cnod[jp, 0, j]
        sh += cw[jp, 0, j] * (cn[jp, 0] * v[2 * i] + cn[jp, 1] * v[2 * i + 1])
        i = cnod[jp, 1, j]
        sh -= cw[jp, 1, j] * (cn[jp, 0] * v[2 * i] + cn[jp, 1] * v[2 * i + 1])
    return sh


@njit(cache=True)
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
    dt = p.dt
    tpar = (p.tau0, p.theta_2, p.theta_s, p.gain[0], p.gain[1])
    rest = p.restitution
    tol1 = p.tol_disp
    tol2 = p.tol_vel
    tol3 = p.tol_acc
    n_acc = p.n_accel
    max_iter = p.max_iter
    mpts = p.n_points
    tmode = p.torque_mode
    direct = p.direct
    x = s.x
    v = s.v
    a = s.a
    phi = s.phi
    om = s.om
    alp = s.alp
    mu = s.mu
    cres = s.cres
    cnod = s.cnod
    cw = s.cw
    sc = s.sc
    spair = s.spair
    rates = s.rates
    out = r.out
    outp = r.outp
    out_mu = r.out_mu
    info = r.info
    minv = m.minv
    jd = m.inertia
    npair = cres.shape[0]
    nw = cnod.shape[2]
    nn = m.xloc.shape[0]
    nd = 2 * nn
    nt = m.tie_node.shape[0]
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
    cnod_t = np.empty((npair, 2, nw), np.int64)
    cw_t = np.empty((npair, 2, nw))
    ct = np.zeros((npair, 4))
    zero4 = np.zeros((npair, 4))
    rate1 = np.zeros(4)
    ccol = np.zeros((npair, nc))
    e0 = np.zeros(nc)
    mu0 = np.zeros(nc)
    dmu = np.zeros(nc)
    pbar = np.zeros(npair)
    sh_pred = np.zeros(npair)
    vtgt = np.zeros(npair)
    work = np.zeros((13, nc))
    stats = np.zeros(2)
    c11 = dt * dt / 2.0
    c12 = dt**4 / 24.0
    c21 = dt
    c22 = dt**3 / 6.0
    lo = p.window_lo
    hi = p.window_hi
    corners = p.corners
    if init:
        if not search_pairs(x, phi, m, mpts, lo, hi, corners, pa, ma, pb, mb, cres, cnod, cw, spair):
            info[0] = sc[0]
            return 4, row
    for jp in range(npair):
        cn[jp, 0] = cres[jp, 3]
        cn[jp, 1] = cres[jp, 4]
    for step in range(n_steps + (1 if init else 0)):
        t = sc[0]
        initial = init and step == 0
        closing = False
        if not initial:
            # ---- constraint Jacobian of the step start, multipliers mu held over the step
            for jp in range(npair):
                ct[jp, 0] = cres[jp, 0]
                ct[jp, 1] = cres[jp, 1]
                ct[jp, 2] = cn[jp, 0]
                ct[jp, 3] = cn[jp, 1]
            phi_t[0] = phi[0]
            phi_t[1] = phi[1]
            tau_old0 = torque_of(0, phi[0], m.rsgn[0], tpar, tmode)
            tau_old1 = torque_of(1, phi[1], m.rsgn[1], tpar, tmode)
            # ---- classical RK4 (k1 = stored consistent acceleration of the step start)
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
                accelerations(
                    xs,
                    ps,
                    mu,
                    hh,
                    ct,
                    rates,
                    m,
                    tpar,
                    tmode,
                    cnod_t,
                    cw_t,
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
            t = t + dt
            # ---- contact search of every pair at the predicted state
            if not search_pairs(x, phi, m, mpts, lo, hi, corners, pa, ma, pb, mb, cres, cnod, cw, spair):
                info[0] = t
                return 4, row
            for jp in range(npair):
                cn[jp, 0] = cres[jp, 3]
                cn[jp, 1] = cres[jp, 4]
                # approach velocity of the predicted state (before the passes): impact reference
                sh_pred[jp] = _normal_velocity(v, cnod, cw, cn, jp)
            ke_pred = kinetic_energy(v, om, minv, jd)
            for q in range(nd):
                xsum[q] = x[q]  # predicted state (strain energy of a closing step)
            psum[0] = phi[0]
            psum[1] = phi[1]
            set_rotation(phi, m.theta0, rot)
            tie_vectors(x, m.centres, m.tie_node, m.tie_gear, rot, bvec, rx)
            # ---- pass 1: displacement constraints (eq. 8, 19)
            for k in range(nt):
                i = m.tie_node[k]
                e0[2 * k] = -(rx[k, 0] - m.xloc[i, 0])
                e0[2 * k + 1] = -(rx[k, 1] - m.xloc[i, 1])
            for jp in range(npair):
                e0[ic + jp] = -cres[jp, 2]
            contact_columns(
                c11, c12, minv, m.gid, rot, m.indptr, m.indices, m.data, m.tie_node, cnod, cw, cn, gsc, zk, ccol
            )
            mu0[:] = mu
            res, its, ok = solve_pass(
                direct, p, 1, e0, mu, pbar, c11, c12, p.eps_disp, tol1, n_acc, max_iter, m, bvec, ccol, work, stats
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
            for q in range(nc):
                dmu[q] = mu[q] - mu0[q]
            gsc[:] = 0.0
            gth[:] = 0.0
            gt_apply(dmu, m.tie_node, m.tie_gear, bvec, rot, cnod, cw, cn, gsc, gth)
            # RK4 positions and velocities with the new multipliers (affine response)
            k_local_product(gsc, minv, m.gid, rot, m.indptr, m.indices, m.data, zk)
            for i in range(nn):
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
                phi[g] += c11 * gth[g] / jd[g]
                om[g] += c21 * gth[g] / jd[g]
            gsc[:] = 0.0
            for jp in range(npair):
                pbar[jp] = mu[ic + jp]
                spair[jp, 2] = pbar[jp]
                if pbar[jp] < 0.0 and mu0[ic + jp] == 0.0:
                    closing = True
            set_rotation(phi, m.theta0, rot)
            tie_vectors(x, m.centres, m.tie_node, m.tie_gear, rot, bvec, rx)
            # ---- pass 2: velocity constraints (eq. 15, 20, 22)
            ke0 = kinetic_energy(v, om, minv, jd)
            if closing:
                # a contact closes: the displacement pass stops the penetration with a force
                # held over the step, i.e. it takes part in the impact; its change of kinetic
                # + strain energy is counted in D (strain part added after pass 3)
                set_rotation(psum, m.theta0, rot)
                se_pred = elastic_force(
                    xsum, m.xloc, m.gid, m.centres, rot, m.indptr, m.indices, m.data, wbuf, floc, fglob, tel
                )
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
                sh = _normal_velocity(v, cnod, cw, cn, jp)
                vtgt[jp] = 0.0
                if pbar[jp] < 0.0 and sh > tol2 and mu0[ic + jp] == 0.0:
                    sc[14] += 1.0
                if rest > 0.0 and pbar[jp] < 0.0 and sh_pred[jp] > tol2 and mu0[ic + jp] == 0.0:
                    # Newton impact law: target -e x (approach velocity before the
                    # displacement pass, which already removes part of it) instead of 0
                    vtgt[jp] = -rest * sh_pred[jp]
                e0[ic + jp] = sh - vtgt[jp]
            contact_columns(
                c21, c22, minv, m.gid, rot, m.indptr, m.indices, m.data, m.tie_node, cnod, cw, cn, gsc, zk, ccol
            )
            mu0[:] = mu
            res, its, ok = solve_pass(
                direct, p, 2, e0, mu, pbar, c21, c22, p.eps_vel, tol2, n_acc, max_iter, m, bvec, ccol, work, stats
            )
            if not ok:
                info[0] = t
                info[1] = res
                info[2] = tol2
                return 2, row
            sc[7] = max(sc[7], res)
            sc[10] = max(sc[10], its)
            for jp in range(npair):
                spair[jp, 1] = e0[ic + jp] + work[0, ic + jp] + vtgt[jp]
                spair[jp, 3] = mu[ic + jp]
            for q in range(nc):
                dmu[q] = mu[q] - mu0[q]
            gsc[:] = 0.0
            gth[:] = 0.0
            gt_apply(dmu, m.tie_node, m.tie_gear, bvec, rot, cnod, cw, cn, gsc, gth)
            respond(gsc, gth, c21, c22, minv, m.gid, rot, jd, m.indptr, m.indices, m.data, zk, v, om, 1.0)
            zk[:] = 0.0
            gsc[:] = 0.0
            sc[2] += ke0 - kinetic_energy(v, om, minv, jd)
            # external work (trapezoidal in the disk angles)
            tau_new0 = torque_of(0, phi[0], m.rsgn[0], tpar, tmode)
            tau_new1 = torque_of(1, phi[1], m.rsgn[1], tpar, tmode)
            sc[1] += 0.5 * (tau_old0 + tau_new0) * (phi[0] - phi_t[0])
            sc[1] += 0.5 * (tau_old1 + tau_new1) * (phi[1] - phi_t[1])
            sc[18] = tau_new0
            sc[19] = tau_new1
        else:
            for jp in range(npair):
                pbar[jp] = -1.0 if cres[jp, 2] <= 0.0 else 0.0
        # ---- pass 3: acceleration constraints (eq. 17, 21, 23)
        for jp in range(npair):
            ct[jp, 0] = cres[jp, 0]
            ct[jp, 1] = cres[jp, 1]
            ct[jp, 2] = cn[jp, 0]
            ct[jp, 3] = cn[jp, 1]
        eel = accelerations(
            x,
            phi,
            mu,
            0.0,
            ct,
            zero4,
            m,
            tpar,
            tmode,
            cnod,
            cw,
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
        # sliding terms of the relative normal acceleration (appendix A)
        for jp in range(npair):
            if spair[jp, 5] == 0.0:
                e0[ic + jp] = 0.0
                for q in range(4):
                    rates[jp, q] = 0.0
                continue
            if nw == 3:
                sample_flank(v, m.flank[jp, 0], m.nedge[jp, 0], va)
                sample_flank(v, m.flank[jp, 1], m.nedge[jp, 1], vb)
            else:
                sample_smooth(v, m.flank[jp, 0], m.tab[jp, 0], m.mloc[jp, 0], m.theta0[0] + phi[0], om[0], True, va)
                sample_smooth(v, m.flank[jp, 1], m.tab[jp, 1], m.mloc[jp, 1], m.theta0[1] + phi[1], om[1], True, vb)
            spline_second(va, mva)
            spline_second(vb, mvb)
            hs, _ad, _bd = sliding_terms(
                pa[jp], ma[jp], va, mva, pb[jp], mb[jp], vb, mvb, m.sig[0], m.sig[1], cres[jp], rate1
            )
            for q in range(4):
                rates[jp, q] = rate1[q]
            sa = hs
            for j in range(nw):
                i = cnod[jp, 0, j]
                sa += cw[jp, 0, j] * (cn[jp, 0] * a[2 * i] + cn[jp, 1] * a[2 * i + 1])
                i = cnod[jp, 1, j]
                sa -= cw[jp, 1, j] * (cn[jp, 0] * a[2 * i] + cn[jp, 1] * a[2 * i + 1])
            e0[ic + jp] = sa
        contact_columns(
            1.0, 0.0, minv, m.gid, rot, m.indptr, m.indices, m.data, m.tie_node, cnod, cw, cn, gsc, zk, ccol
        )
        mu0[:] = mu
        res, its, ok = solve_pass(
            direct, p, 3, e0, mu, pbar, 1.0, 0.0, p.eps_acc, tol3, n_acc, max_iter, m, bvec, ccol, work, stats
        )
        if not ok:
            info[0] = t
            info[1] = res
            info[2] = tol3
            return 3, row
        sc[8] = max(sc[8], res)
        sc[11] = max(sc[11], its)
        for q in range(nc):
            dmu[q] = mu[q] - mu0[q]
        gsc[:] = 0.0
        gth[:] = 0.0
        gt_apply(dmu, m.tie_node, m.tie_gear, bvec, rot, cnod, cw, cn, gsc, gth)
        for i in range(nn):
            a[2 * i] += minv[i] * gsc[2 * i]
            a[2 * i + 1] += minv[i] * gsc[2 * i + 1]
        for g in range(2):
            alp[g] += gth[g] / jd[g]
        gsc[:] = 0.0
        sc[0] = t
        sc[3] = eel
        if closing:
            sc[2] -= eel  # strain energy after the displacement pass (positions unchanged since)
        for jp in range(npair):
            force = -mu[ic + jp]
            if force > spair[jp, 4]:
                spair[jp, 4] = force
            if initial:
                spair[jp, 0] = -cres[jp, 2]
        tr = 0.0
        for k in range(nt):
            i = m.tie_node[k]
            tr = max(tr, max(abs(rx[k, 0] - m.xloc[i, 0]), abs(rx[k, 1] - m.xloc[i, 1])))
        sc[15] = max(sc[15], tr)
        # ---- record
        if (not initial) and ((step + (0 if init else 1)) % rec_every == 0) and row < out.shape[0]:
            out[row, 0] = t
            out[row, 1] = phi[0]
            out[row, 2] = phi[1]
            out[row, 3] = om[0]
            out[row, 4] = om[1]
            out[row, 5] = kinetic_energy(v, om, minv, jd)
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
                    for j in range(nw):
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
                out_mu[row, q] = mu[q]
            row += 1
            for q in (6, 7, 8, 9, 10, 11, 15):
                sc[q] = 0.0
    return 0, row
