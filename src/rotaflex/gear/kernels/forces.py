"""Forces of the paper's scheme at a state (compiled): co-rotational elastic force, external
torques, the accelerations at an RK4 stage for given multipliers, kinetic energy and relative
normal velocity. Conventions (SI, DOF order, frames, constraint rows) as in
:mod:`rotaflex.gear.kernels.rk4`, whose step loop calls these.
"""

from __future__ import annotations

import math

from rotaflex.core.compiled import entry, inner
from rotaflex.gear.kernels.contact import flank_weights, smooth_weights
from rotaflex.gear.kernels.passes import gt_apply


@inner
def _row_sum(kcol, kblk, b0, b1, u, f0, f1):
    """Row sums of one node's blocks ``b0 <= b < b1`` added to (f0, f1), terms in column order."""
    for b in range(b0, b1):
        j = kcol[b]
        u0 = u[j, 0]
        u1 = u[j, 1]
        f0 += kblk[b, 0] * u0
        f0 += kblk[b, 1] * u1
        f1 += kblk[b, 2] * u0
        f1 += kblk[b, 3] * u1
    return f0, f1


@entry
def block_product(kptr, kcol, kblk, u, f):
    """f = K u by 2 x 2 node blocks (``u, f`` (N, 2)), both rows of a node in one sweep.

    Node ``i`` and node ``i + h + 1`` (h = N // 2) are summed side by side: two independent
    chains of additions keep the core busy where one waits on the latency of the last one (15 %
    of the product). Each row still adds its terms in column order, so ``f`` is the same to
    the last bit as one row after the other. Rows: ``len(kptr) - 1`` (of ``f``); ``u`` has a row
    per node column.
    """
    nn = kptr.shape[0] - 1
    h = nn // 2
    for i in range(h + 1):
        if i >= nn:
            break
        a0 = kptr[i]
        a1 = kptr[i + 1]
        f0 = 0.0
        f1 = 0.0
        r = i + h + 1
        if r < nn:
            c0 = kptr[r]
            c1 = kptr[r + 1]
            n2 = min(a1 - a0, c1 - c0)
            g0 = 0.0
            g1 = 0.0
            for t in range(n2):
                b = a0 + t
                c = c0 + t
                j = kcol[b]
                k = kcol[c]
                u0 = u[j, 0]
                u1 = u[j, 1]
                v0 = u[k, 0]
                v1 = u[k, 1]
                f0 += kblk[b, 0] * u0
                g0 += kblk[c, 0] * v0
                f0 += kblk[b, 1] * u1
                g0 += kblk[c, 1] * v1
                f1 += kblk[b, 2] * u0
                g1 += kblk[c, 2] * v0
                f1 += kblk[b, 3] * u1
                g1 += kblk[c, 3] * v1
            g0, g1 = _row_sum(kcol, kblk, c0 + n2, c1, u, g0, g1)
            f[r, 0] = g0
            f[r, 1] = g1
            a0 += n2
        f0, f1 = _row_sum(kcol, kblk, a0, a1, u, f0, f1)
        f[i, 0] = f0
        f[i, 1] = f1


@entry
def elastic_force(x, rot, m, wbuf, fglob, tel):
    """Co-rotational elastic force (eq. 4-5) and strain energy.

    ``w = R^T (x - c) - X`` (exact co-rotational form), ``f = -R K w`` on the nodes, and the
    disk torque ``sum f_loc . J (X + w)`` = -dE/dphi, which makes the force conservative.
    ``m`` is the :class:`~rotaflex.gear.kernels.arrays.ModelArrays`; K is applied by 2 x 2
    node blocks (:func:`block_product`, into ``fglob`` as scratch), then energy, global force
    and torques node by node.
    """
    xloc, gid, cen = m.xloc, m.gid, m.centres
    nn = xloc.shape[0]
    for i in range(nn):
        g = gid[i]
        c = rot[g, 0]
        s = rot[g, 1]
        dx = x[2 * i] - cen[g, 0]
        dy = x[2 * i + 1] - cen[g, 1]
        wbuf[2 * i] = c * dx + s * dy - xloc[i, 0]
        wbuf[2 * i + 1] = -s * dx + c * dy - xloc[i, 1]
    block_product(m.kptr, m.kcol, m.kblk, wbuf.reshape((nn, 2)), fglob.reshape((nn, 2)))
    energy = 0.0
    tel[0] = 0.0
    tel[1] = 0.0
    for i in range(nn):
        f0 = fglob[2 * i]
        f1 = fglob[2 * i + 1]
        energy += 0.5 * f0 * wbuf[2 * i]
        energy += 0.5 * f1 * wbuf[2 * i + 1]
        g = gid[i]
        c = rot[g, 0]
        s = rot[g, 1]
        fglob[2 * i] = -(c * f0 - s * f1)
        fglob[2 * i + 1] = -(s * f0 + c * f1)
        # J (X + w) = (-(Y + w_y), X + w_x)
        tel[g] += f0 * (-(xloc[i, 1] + wbuf[2 * i + 1])) + f1 * (xloc[i, 0] + wbuf[2 * i])
    return energy


@entry
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


@entry
def set_rotation(phi, theta0, rot):
    for g in range(2):
        ang = theta0[g] + phi[g]
        rot[g, 0] = math.cos(ang)
        rot[g, 1] = math.sin(ang)


@inner(_nrt=False)
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


@entry
def kinetic_energy(v, om, minv, jd):
    e = 0.5 * (jd[0] * om[0] ** 2 + jd[1] * om[1] ** 2)
    for i in range(minv.shape[0]):
        e += 0.5 * (v[2 * i] ** 2 + v[2 * i + 1] ** 2) / minv[i]
    return e


@inner(_nrt=False)
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


@inner(_nrt=False)
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
    fglob,
    tel,
    fc,
    fth,
    cn_s,
    nodes,
    w,
    ws,
    a,
    alp,
):
    """Accelerations at a (stage) state for multipliers ``mu``; returns the strain energy.

    The constraint force is ``G(q)^T mu`` with the Jacobian at the stage state: tie forces
    ``-R(phi) lambda`` turn with the disk; each contact force follows its contact point, whose
    parameters and normal at the step start (``ct[j]`` = a, b, n_x, n_y) advance with their
    rates (``rates[j]`` = da/dt, db/dt, dn_x/dt, dn_y/dt, appendix A) over ``tau_off`` seconds.
    ``m`` is the :class:`~rotaflex.gear.kernels.arrays.ModelArrays`; ``tpar`` = (tau0, theta_2,
    theta_s, u_A, u_B); ``nodes, w, ws`` scratch of the contact weights (3,), (3,), (nw,).
    """
    set_rotation(phi, m.theta0, rot)
    tie_vectors(x, m.centres, m.tie_node, m.tie_gear, rot, bvec, rx)
    nw = cnod.shape[2]
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
    energy = elastic_force(x, rot, m, wbuf, fglob, tel)
    nn = m.xloc.shape[0]
    for i in range(nn):
        a[2 * i] = m.minv[i] * (fglob[2 * i] + fc[2 * i])
        a[2 * i + 1] = m.minv[i] * (fglob[2 * i + 1] + fc[2 * i + 1])
    for g in range(2):
        tau = torque_of(g, phi[g], m.rsgn[g], tpar, tmode)
        alp[g] = (tau + tel[g] + fth[g]) / m.inertia[g]
    return energy


@inner(_nrt=False)
def normal_velocity(v, cnod, cw, cn, jp):
    """Relative normal velocity of the contact row of pair ``jp`` (> 0: approaching)."""
    sh = 0.0
    for j in range(cnod.shape[2]):
        i = cnod[jp, 0, j]
        sh += cw[jp, 0, j] * (cn[jp, 0] * v[2 * i] + cn[jp, 1] * v[2 * i + 1])
        i = cnod[jp, 1, j]
        sh -= cw[jp, 1, j] * (cn[jp, 0] * v[2 * i] + cn[jp, 1] * v[2 * i + 1])
    return sh
