"""Compiled kernels of the 3-D geometrically exact (Simo-Reissner) beam.

Kinematics (Simo 1985; Simo & Vu-Quoc 1986): every node carries its inertial position ``x``
[m] and the rotation ``R`` of its cross-section (section axes ``e1`` along the beam, ``e2``,
``e3`` the principal axes), stored as a unit quaternion (scalar first, ``R = I + 2 e0 e~ +
2 e~ e~``, the convention of :mod:`rotaflex.rotation`). Increments are spatial: a Newton or time
step moves ``x <- x + dx`` and turns ``R <- exp(dth~) R`` (multiplicative update; the
quaternion is multiplied by ``exp(dth / 2)`` and renormalised).

Element (2 nodes, Crisfield & Jelenic 1999, Proc. R. Soc. A 455, 1125-1147, their objective
interpolation specialised to 2 nodes): the rotation between the nodes is interpolated through
their relative rotation vector ``psi = log(R_a^T R_b)``: ``R(s) = R_a exp(s psi~ / L0)``, so the
material curvature ``K = psi / L0`` is constant on the element, and the strains are evaluated at
the middle (one-point, reduced integration, which removes shear locking) with
``R_m = R_a exp(psi~ / 2)``::

    Gamma = R_m^T x' - e1 - Gamma0,     K = psi / L0 - K0,     x' = (x_b - x_a) / L0,

``N = C_N Gamma``, ``M = C_M K`` (material components, ``C_N = diag(EA, GA2, GA3)``,
``C_M = diag(GJ, EI2, EI3)``) and the strain energy ``L0 / 2 (Gamma.N + K.M)``. The
interpolation depends only on relative rotations: it is objective (rigid rotations leave the
strains unchanged) and path-independent (the strains depend on the current nodal rotations only,
not on the increments that led there), unlike the incremental rotation-vector interpolation of
Simo & Vu-Quoc (1986). ``Gamma0``, ``K0``: the strains of the reference (curved) configuration,
so it is stress-free.

Internal force (virtual work with spatial spins ``dth``): ``n = R_m N`` (spatial force),
``d psi = Jr(psi)^-1 R_b^T (dth_b - dth_a)``, ``dth_m = dth_a + R_m Jr(psi/2) d psi / 2``
(``Jr``: right Jacobian of the exponential map). The tangent (:func:`_element_tangent`) is the
analytic derivative of that force under the same spatial spins, material and geometric parts
together (the derivatives of ``Jr`` and ``Jr^-1`` included), so Newton keeps its quadratic
rate; it is not symmetric away from equilibrium (each node's rotation block differs from its
transpose by ``-m~``, ``m`` the node's moment: the spins do not commute). The central
difference of the force under the same multiplicative perturbations (``want_k = 2``, steps
1e-6 L0 and 1e-6 rad, agreeing to ~1e-10 relative) checks it and was the tangent before:
the analytic one costs about a tenth of that (docs/floating.md).

Material damping (Kelvin-Voigt, ``eta`` [s]): ``N = C_N (Gamma + eta Gamma')``,
``M = C_M (K + eta K')``, the strain rates the same maps as the variations applied to the
nodes' velocities (translational, spatial angular ``R W``); the tangent adds the damping matrix
and the rates' change with the configuration (:func:`_rate_maps`).

DOF layout: state ``q`` 7 numbers per node ``(x, y, z, e0, e1, e2, e3)`` then the reference
frame's 7; increments 6 per node ``(dx, dy, dz, dth_x, dth_y, dth_z)`` then the frame's 6.
"""

from __future__ import annotations

import numpy as np

from rotaflex.core.compiled import entry, inner
from rotaflex.floating.kernels import cross, quat_matrix, skew3

#: finite-difference steps of the element tangent: translation (times L0) and rotation [rad]
FD_STEP = 1e-6


@inner
def qmul(p, q):
    """Hamilton product ``p (x) q`` (``R(p q) = R(p) R(q)``)."""
    return np.array(
        [
            p[0] * q[0] - p[1] * q[1] - p[2] * q[2] - p[3] * q[3],
            p[0] * q[1] + p[1] * q[0] + p[2] * q[3] - p[3] * q[2],
            p[0] * q[2] - p[1] * q[3] + p[2] * q[0] + p[3] * q[1],
            p[0] * q[3] + p[1] * q[2] - p[2] * q[1] + p[3] * q[0],
        ]
    )


@inner
def qexp(v):
    """Unit quaternion of the rotation vector ``v`` [rad]."""
    th = np.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    s = 0.5 - th * th / 48.0 if th < 1e-6 else np.sin(0.5 * th) / th
    return np.array([np.cos(0.5 * th), s * v[0], s * v[1], s * v[2]])


@inner
def qlog(q):
    """Rotation vector [rad] (angle in [0, pi]) of a unit quaternion."""
    w, x, y, z = q[0], q[1], q[2], q[3]
    if w < 0.0:  # q and -q are the same rotation: take the short way
        w, x, y, z = -w, -x, -y, -z
    s = np.sqrt(x * x + y * y + z * z)
    f = 2.0 / w * (1.0 - s * s / (3.0 * w * w)) if s < 1e-6 else 2.0 * np.arctan2(s, w) / s
    return np.array([f * x, f * y, f * z])


@inner
def _mm(A, B):
    """``A B`` of small matrices by loops (the BLAS call of ``@`` costs more than a 3 x 12 product)."""
    C = np.zeros((A.shape[0], B.shape[1]))
    for i in range(A.shape[0]):
        for k in range(A.shape[1]):
            a = A[i, k]
            for j in range(B.shape[1]):
                C[i, j] += a * B[k, j]
    return C


@inner
def _mtm(A, B):
    """``A^T B`` of small matrices by loops."""
    C = np.zeros((A.shape[1], B.shape[1]))
    for k in range(A.shape[0]):
        for i in range(A.shape[1]):
            a = A[k, i]
            for j in range(B.shape[1]):
                C[i, j] += a * B[k, j]
    return C


@inner
def _mv(A, x):
    """``A x`` (3 x 3 times 3)."""
    return np.array(
        [
            A[0, 0] * x[0] + A[0, 1] * x[1] + A[0, 2] * x[2],
            A[1, 0] * x[0] + A[1, 1] * x[1] + A[1, 2] * x[2],
            A[2, 0] * x[0] + A[2, 1] * x[1] + A[2, 2] * x[2],
        ]
    )


@inner
def _mtv(A, x):
    """``A^T x`` (3 x 3 times 3)."""
    return np.array(
        [
            A[0, 0] * x[0] + A[1, 0] * x[1] + A[2, 0] * x[2],
            A[0, 1] * x[0] + A[1, 1] * x[1] + A[2, 1] * x[2],
            A[0, 2] * x[0] + A[1, 2] * x[1] + A[2, 2] * x[2],
        ]
    )


@inner
def _jr(v):
    """Right Jacobian of the exponential map, ``d exp(v) = exp(v) (Jr(v) dv)~``."""
    th2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2]
    th = np.sqrt(th2)
    if th < 1e-4:
        a, b = 0.5 - th2 / 24.0, 1.0 / 6.0 - th2 / 120.0
    else:
        a, b = (1.0 - np.cos(th)) / th2, (th - np.sin(th)) / (th2 * th)
    S = skew3(v)
    return np.eye(3) - a * S + b * _mm(S, S)


@inner
def _jr_inv(v):
    """Inverse of :func:`_jr`."""
    th2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2]
    th = np.sqrt(th2)
    c = 1.0 / 12.0 + th2 / 720.0 if th < 1e-4 else 1.0 / th2 - (1.0 + np.cos(th)) / (2.0 * th * np.sin(th))
    S = skew3(v)
    return np.eye(3) + 0.5 * S + c * _mm(S, S)


@inner
def strains(xa, qa, xb, qb, L0, gam0, kap0):
    """``(Gamma, K, psi, R_m, x')`` of one element (see the module docstring)."""
    qc = np.array([qa[0], -qa[1], -qa[2], -qa[3]])
    psi = qlog(qmul(qc, qb))
    Rm = quat_matrix(qmul(qa, qexp(0.5 * psi)))
    xp = (xb - xa) / L0
    gam = _mtv(Rm, xp)
    gam[0] -= 1.0
    return gam - gam0, psi / L0 - kap0, psi, Rm, xp


@inner
def _dcoef(th):
    """``a'/th, b'/th, c'/th`` [-]: the derivatives of the scalar coefficients of :func:`_jr`
    (``a, b``) and :func:`_jr_inv` (``c``) divided by the angle (``d f(|v|) / dv = f'/th v``);
    Taylor series below 0.1 rad, where the closed forms cancel (error < 1e-9 either side)."""
    t2 = th * th
    if th < 0.1:
        da = -1.0 / 12.0 + t2 / 180.0 - t2 * t2 / 6720.0 + t2 * t2 * t2 / 453600.0
        db = -1.0 / 60.0 + t2 / 1260.0 - t2 * t2 / 60480.0 + t2 * t2 * t2 / 4989600.0
        dc = 1.0 / 360.0 + t2 / 7560.0 + t2 * t2 / 201600.0 + t2 * t2 * t2 / 5987520.0
        return da, db, dc
    s, c = np.sin(th), np.cos(th)
    da = (th * s - 2.0 * (1.0 - c)) / (t2 * t2)
    db = (th * (1.0 - c) - 3.0 * (th - s)) / (t2 * t2 * th)
    sh = np.sin(0.5 * th)
    dc = -2.0 / (t2 * t2) + 1.0 / (4.0 * t2 * sh * sh) + np.cos(0.5 * th) / (2.0 * t2 * th * sh)
    return da, db, dc


@inner
def _d_jr_t(u, w):
    """``d (Jr(u)^T w) / du`` (3, 3) at fixed ``w`` (``Jr(u)^T w = w + a u x w + b u x (u x w)``)."""
    th2 = u[0] * u[0] + u[1] * u[1] + u[2] * u[2]
    th = np.sqrt(th2)
    if th < 1e-4:
        a, b = 0.5 - th2 / 24.0, 1.0 / 6.0 - th2 / 120.0
    else:
        a, b = (1.0 - np.cos(th)) / th2, (th - np.sin(th)) / (th2 * th)
    da, db, _ = _dcoef(th)
    uw = cross(u, w)
    uuw = cross(u, uw)
    D = -a * skew3(w) + b * np.dot(u, w) * np.eye(3)
    for i in range(3):
        for j in range(3):
            D[i, j] += da * uw[i] * u[j] + db * uuw[i] * u[j] + b * (u[i] * w[j] - 2.0 * w[i] * u[j])
    return D


@inner
def _d_jr_inv_t(u, h):
    """``d (Jr(u)^-T h) / du`` (3, 3) at fixed ``h`` (``Jr^-T h = h - u x h / 2 + c u x (u x h)``)."""
    th2 = u[0] * u[0] + u[1] * u[1] + u[2] * u[2]
    th = np.sqrt(th2)
    c = 1.0 / 12.0 + th2 / 720.0 if th < 1e-4 else 1.0 / th2 - (1.0 + np.cos(th)) / (2.0 * th * np.sin(th))
    _, _, dc = _dcoef(th)
    uuh = cross(u, cross(u, h))
    D = 0.5 * skew3(h) + c * np.dot(u, h) * np.eye(3)
    for i in range(3):
        for j in range(3):
            D[i, j] += dc * uuh[i] * u[j] + c * (u[i] * h[j] - 2.0 * h[i] * u[j])
    return D


@inner
def _strain_maps(Rm, psi, T, dx, L0):
    """(3, 12) maps of the element's increments ``(dx_a, dth_a, dx_b, dth_b)`` (spatial spins)
    to ``dpsi``, ``dth_m``, ``d(x_b - x_a)`` and ``dGamma`` (see :func:`_element_tangent`)."""
    Dpsi, Dm, Ddx = np.zeros((3, 12)), np.zeros((3, 12)), np.zeros((3, 12))
    A = 0.5 * _mm(_mm(Rm, _jr(0.5 * psi)), T)
    for i in range(3):
        Ddx[i, i], Ddx[i, 6 + i] = -1.0, 1.0
        Dm[i, 3 + i] = 1.0
        for j in range(3):
            Dpsi[i, 3 + j], Dpsi[i, 9 + j] = -T[i, j], T[i, j]
            Dm[i, 3 + j] -= A[i, j]
            Dm[i, 9 + j] += A[i, j]
    Dgam = _mtm(Rm, Ddx + _mm(skew3(dx), Dm)) / L0
    return Dpsi, Dm, Ddx, Dgam


@inner
def _rate_maps(Rm, psi, Rb, T, dx, Dpsi, Dm, Ddx, ve):
    """(3, 12) derivatives of the strain rates ``L0 Gamma' = R_m^T (x'_b - x'_a + (x_b - x_a)~
    w_m)`` and ``L0 K' = T (w_b - w_a)`` with the element's increments at fixed translational
    velocities and material angular velocities (``w = R W``: ``dw = -w~ dth``); ``w_m = w_a +
    A (w_b - w_a)``, ``A = R_m Jr(psi/2) T / 2``, the spin of the middle section.
    ``Jr(u) x = Jr(-u)^T x`` gives the derivatives of the untransposed Jacobians."""
    wa, wb = ve[3:6], ve[9:12]
    u = wb - wa
    Du = np.zeros((3, 12))
    Swa, Swb, Su = skew3(wa), skew3(wb), skew3(u)
    for i in range(3):
        for j in range(3):
            Du[i, 3 + j], Du[i, 9 + j] = Swa[i, j], -Swb[i, j]
    x1 = _mtv(Rb, u)
    tmp = Du.copy()
    for i in range(3):
        for j in range(3):
            tmp[i, 9 + j] += Su[i, j]
    Dx1 = _mtm(Rb, tmp)
    y1 = _mv(_jr_inv(psi), x1)  # = T u: L0 K'
    Dy1 = -_mm(_d_jr_inv_t(-psi, x1), Dpsi) + _mm(_jr_inv(psi), Dx1)
    jh = _jr(0.5 * psi)
    z1 = _mv(jh, y1)
    Dz1 = -0.5 * _mm(_d_jr_t(-0.5 * psi, y1), Dpsi) + _mm(jh, Dy1)
    Rz = _mv(Rm, z1)
    # w_m and its derivative: dw_a + (-(R_m z1)~ dth_m + R_m dz1) / 2
    wm = wa + 0.5 * Rz
    Dwm = 0.5 * (_mm(Rm, Dz1) - _mm(skew3(Rz), Dm))
    for i in range(3):
        for j in range(3):
            Dwm[i, 3 + j] -= Swa[i, j]
    g = np.zeros(3)
    for i in range(3):
        g[i] = ve[6 + i] - ve[i]
    g += cross(dx, wm)
    # d(R_m^T g) = R_m^T (g~ dth_m + d(dx)~ w_m + dx~ dw_m), d(dx)~ w_m = -w_m~ d(dx)
    Dgd = _mtm(Rm, _mm(skew3(g), Dm) - _mm(skew3(wm), Ddx) + _mm(skew3(dx), Dwm))
    return Dgd, Dy1


@inner
def _element_state(xa, qa, xb, qb, L0, gam0, kap0, cn, cm, ve, eta):
    """The stress resultants and their lever arms of one element (see the module docstring):
    ``gam, kap, psi, R_m, N, M, n, v, R_b, T, h, p``. With ``eta`` > 0 [s] the stresses are
    Kelvin-Voigt, ``N = C_N (Gamma + eta Gamma')``, ``M = C_M (K + eta K')``, the strain rates
    the strain maps times the element's velocities ``ve`` (12,) (``x'_a``, spatial angular
    velocity ``w_a``, then b's)."""
    gam, kap, psi, Rm, xp = strains(xa, qa, xb, qb, L0, gam0, kap0)
    Rb = quat_matrix(qb)
    T = _mm(_jr_inv(psi), Rb.T)
    N = cn * gam
    M = cm * kap
    if eta > 0.0:
        Dpsi, _, _, Dgam = _strain_maps(Rm, psi, T, xb - xa, L0)
        for i in range(3):
            gd, kd = 0.0, 0.0
            for j in range(12):
                gd += Dgam[i, j] * ve[j]
                kd += Dpsi[i, j] * ve[j]
            N[i] += eta * cn[i] * gd
            M[i] += eta * cm[i] * kd / L0
    n = _mv(Rm, N)
    v = L0 * cross(n, xp)
    h = 0.5 * _mtv(_jr(0.5 * psi), _mtv(Rm, v)) + M
    p = _mtv(T, h)
    return gam, kap, psi, Rm, N, M, n, v, Rb, T, h, p


@inner
def _element_force(xa, qa, xb, qb, L0, gam0, kap0, cn, cm, ve, eta, fe):
    """Element internal force ``fe`` (12,): forces and moments on a, then b; returns the
    (elastic) strain energy [J]."""
    gam, kap, _, _, _, _, n, v, _, _, _, p = _element_state(xa, qa, xb, qb, L0, gam0, kap0, cn, cm, ve, eta)
    for i in range(3):
        fe[i] = -n[i]
        fe[3 + i] = v[i] - p[i]
        fe[6 + i] = n[i]
        fe[9 + i] = p[i]
    return 0.5 * L0 * (np.dot(gam, cn * gam) + np.dot(kap, cm * kap))


@inner
def _element_tangent(xa, qa, xb, qb, L0, gam0, kap0, cn, cm, ve, eta, kv, Ke):
    """Element tangent ``Ke`` (12, 12) = ``d fe / d(dx_a, dth_a, dx_b, dth_b)`` of
    :func:`_element_force` (spatial spins, ``R <- exp(dth~) R``), analytic.

    Each quantity of the force is differentiated in turn, as a (3, 12) map of the element's
    increments (``D_*``): ``dpsi = T (dth_b - dth_a)``, ``dth_m = dth_a + R_m Jr(psi/2) dpsi / 2``,
    ``dGamma = R_m^T (d(x_b - x_a) + (x_b - x_a)~ dth_m) / L0``, ``dK = dpsi / L0``,
    ``dn = -n~ dth_m + R_m C_N dGamma``, ``dv = -(x_b - x_a)~ dn + n~ d(x_b - x_a)``,
    ``d(R_m^T v) = R_m^T (dv + v~ dth_m)``, ``dh = d(Jr(psi/2)^T)/dpsi . dpsi / 4 +
    Jr(psi/2)^T d(R_m^T v) / 2 + C_M dK``, ``dp = -p~ dth_b + R_b d(Jr^-T(psi))/dpsi . dpsi +
    T^T dh``. The products of the stiffnesses with the strain maps are the material part, the
    rest the geometric part. Not symmetric away from equilibrium: the rotation block of each
    node differs from its transpose by ``-m~`` (``m`` the node's moment in ``fe``; the spins do
    not commute), so the assembled tangent is symmetric where the moments balance.

    Damped (``eta`` > 0): the geometric part with the total stresses, the material part times
    ``1 + eta kv`` (``kv`` = d velocity / d increment of the integrator: the damping matrix
    ``eta`` times the material part) and the change of the strain rates with the configuration at
    fixed velocities (translational, material angular; :func:`_rate_maps`): the derivative of
    the damped force along the integrator's path (without it Newton diverged on stiff, strongly
    damped shear modes)."""
    _, _, psi, Rm, _, _, n, v, Rb, T, h, p = _element_state(xa, qa, xb, qb, L0, gam0, kap0, cn, cm, ve, eta)
    dx = xb - xa
    Dpsi, Dm, Ddx, Dgam = _strain_maps(Rm, psi, T, dx, L0)
    fac = 1.0 + eta * kv
    Dn = _mm(Rm, (fac * cn).reshape(3, 1) * Dgam) - _mm(skew3(n), Dm)
    Dkd = np.zeros((3, 12))
    if eta > 0.0:
        Dgd, Dkd = _rate_maps(Rm, psi, Rb, T, dx, Dpsi, Dm, Ddx, ve)
        Dn += _mm(Rm, (eta * cn / L0).reshape(3, 1) * Dgd)
    Dv = _mm(skew3(n), Ddx) - _mm(skew3(dx), Dn)
    w = _mtv(Rm, v)
    Dw = _mtm(Rm, Dv + _mm(skew3(v), Dm))
    Dh = 0.25 * _mm(_d_jr_t(0.5 * psi, w), Dpsi) + 0.5 * _mtm(_jr(0.5 * psi), Dw)
    Dh += (fac * cm / L0).reshape(3, 1) * Dpsi
    if eta > 0.0:
        Dh += (eta * cm / L0).reshape(3, 1) * Dkd
    Dp = _mm(_mm(Rb, _d_jr_inv_t(psi, h)), Dpsi) + _mtm(T, Dh)
    P = skew3(p)
    for i in range(3):
        for j in range(3):
            Dp[i, 9 + j] -= P[i, j]
    for i in range(3):
        for j in range(12):
            Ke[i, j] = -Dn[i, j]
            Ke[3 + i, j] = Dv[i, j] - Dp[i, j]
            Ke[6 + i, j] = Dn[i, j]
            Ke[9 + i, j] = Dp[i, j]


@inner
def _element_tangent_fd(xa, qa, xb, qb, L0, gam0, kap0, cn, cm, ve, eta, Ke):
    """Element tangent ``Ke`` (12, 12) by central differences of :func:`_element_force` under
    the multiplicative perturbations of its 12 DOFs (steps ``FD_STEP`` L0 and ``FD_STEP`` rad):
    the check of :func:`_element_tangent` (at fixed spatial velocities ``ve``: no ``kv`` term)."""
    fp, fm = np.zeros(12), np.zeros(12)
    for j in range(12):
        h = FD_STEP * (L0 if j % 6 < 3 else 1.0)
        if j < 6:
            xp_, qp_ = _perturbed(xa, qa, j, h)
            xm_, qm_ = _perturbed(xa, qa, j, -h)
            _element_force(xp_, qp_, xb, qb, L0, gam0, kap0, cn, cm, ve, eta, fp)
            _element_force(xm_, qm_, xb, qb, L0, gam0, kap0, cn, cm, ve, eta, fm)
        else:
            xp_, qp_ = _perturbed(xb, qb, j - 6, h)
            xm_, qm_ = _perturbed(xb, qb, j - 6, -h)
            _element_force(xa, qa, xp_, qp_, L0, gam0, kap0, cn, cm, ve, eta, fp)
            _element_force(xa, qa, xm_, qm_, L0, gam0, kap0, cn, cm, ve, eta, fm)
        for i in range(12):
            Ke[i, j] = (fp[i] - fm[i]) / (2.0 * h)


@inner
def _perturbed(x, q, j, h):
    """Node state moved by ``h`` along its local increment ``j`` (0-2 translation, 3-5 spin)."""
    xn, qn = x.copy(), q.copy()
    if j < 3:
        xn[j] += h
    else:
        w = np.zeros(3)
        w[j - 3] = h
        qn = qmul(qexp(w), q)
    return xn, qn


@entry
def internal(q, v, conn, L0, gam0, kap0, stiff, eta, kv, f, K, want_k):
    """Internal force ``f`` (n,) and tangent ``K`` (n, n) of all elements; returns the (elastic)
    strain energy [J].

    Parameters
    ----------
    q : (7 nb,) state (positions [m], quaternions).
    v : (6 nb,) velocities: inertial translation [m/s], material angular velocity ``W``
        [rad/s] (``R' = R W~``); used only when ``eta`` > 0.
    conn : (ne, 2) int64 element nodes; ``L0`` (ne,) reference lengths [m]; ``gam0``, ``kap0``
        (ne, 3) reference strains [-], [1/m].
    stiff : (ne, 6) ``EA, GA2, GA3`` [N] and ``GJ, EI2, EI3`` [N m^2].
    eta : float, Kelvin-Voigt time constant [s] (stresses ``C (strain + eta strain')``; 0 elastic).
    kv : float, d velocity / d increment of the integrator (``gamma / (beta h)``), for the
        damping part of the tangent.
    f, K : outputs in increment layout (6 per node), zeroed here; ``K`` only when ``want_k``.
    want_k : 0 (or False) no tangent, 1 (or True) the analytic tangent
        (:func:`_element_tangent`), 2 its central-difference check (:func:`_element_tangent_fd`).
    """
    f[:] = 0.0
    if want_k:
        K[:, :] = 0.0
    fe, Ke, ve = np.zeros(12), np.zeros((12, 12)), np.zeros(12)
    energy = 0.0
    for e in range(conn.shape[0]):
        a, b, le = conn[e, 0], conn[e, 1], L0[e]
        xa, qa = q[7 * a : 7 * a + 3], q[7 * a + 3 : 7 * a + 7]
        xb, qb = q[7 * b : 7 * b + 3], q[7 * b + 3 : 7 * b + 7]
        cn, cm = stiff[e, 0:3], stiff[e, 3:6]
        if eta > 0.0:
            # the spatial angular velocities w = R W of the two nodes
            wa = _mv(quat_matrix(qa), v[6 * a + 3 : 6 * a + 6])
            wb = _mv(quat_matrix(qb), v[6 * b + 3 : 6 * b + 6])
            for i in range(3):
                ve[i], ve[3 + i] = v[6 * a + i], wa[i]
                ve[6 + i], ve[9 + i] = v[6 * b + i], wb[i]
        energy += _element_force(xa, qa, xb, qb, le, gam0[e], kap0[e], cn, cm, ve, eta, fe)
        for i in range(6):
            f[6 * a + i] += fe[i]
            f[6 * b + i] += fe[6 + i]
        if not want_k:
            continue
        if int(want_k) == 2:
            _element_tangent_fd(xa, qa, xb, qb, le, gam0[e], kap0[e], cn, cm, ve, eta, Ke)
        else:
            _element_tangent(xa, qa, xb, qb, le, gam0[e], kap0[e], cn, cm, ve, eta, kv, Ke)
        for i in range(12):
            r = 6 * a + i if i < 6 else 6 * b + i - 6
            for j in range(12):
                K[r, 6 * a + j if j < 6 else 6 * b + j - 6] += Ke[i, j]
    return energy


@entry
def external(q, lam, node, kind, frame, amp, ref_block, dist, f, K, want_k):
    """Applied loads ``f`` (n,) scaled by ``lam`` and their load stiffness (``K -= d f / d q``).

    Parameters
    ----------
    node : (nl,) int64 node (or the frame's block) the load acts on.
    kind : (nl,) 0 force, 1 moment.
    frame : (nl,) 0 the reference frame (turns with block ``ref_block``), 1 inertial (fixed
        direction), 2 material (follows the node's section rotation: a follower load).
    amp : (nl, 3) force [N] or moment [N m] in its frame (material loads: in section axes).
    dist : (ne, 6) ``a, b, L0, wx, wy, wz``: a load fixed in space [N/m] on the element
        (consistent nodal forces ``w L0 / 2``), scaled by ``lam[-1]``.
    """
    f[:] = 0.0
    for i in range(node.shape[0]):
        d = 6 * node[i] + 3 * kind[i]
        s = lam[i]
        if frame[i] == 1:
            for k in range(3):
                f[d + k] += s * amp[i, k]
            continue
        blk = node[i] if frame[i] == 2 else ref_block
        R = quat_matrix(q[7 * blk + 3 : 7 * blk + 7])
        w = s * (R @ amp[i])
        for k in range(3):
            f[d + k] += w[k]
        if want_k:
            # d(R a) = dth x (R a) = -(R a)~ dth: the load turns with the rotation of block blk
            W = skew3(w)
            for k in range(3):
                for m in range(3):
                    K[d + k, 6 * blk + 3 + m] += W[k, m]
    sd = lam[lam.shape[0] - 1]
    for e in range(dist.shape[0]):
        a, b = int(dist[e, 0]), int(dist[e, 1])
        h = 0.5 * dist[e, 2] * sd
        for k in range(3):
            f[6 * a + k] += h * dist[e, 3 + k]
            f[6 * b + k] += h * dist[e, 3 + k]


@entry
def constraints(q, clamp, g, G):
    """Root clamps: node ``c`` rigidly fixed to the frame block ``d``.

    ``clamp`` (nc, 9): ``node, d, rx, ry, rz, a0, a1, a2, a3``: the node sits at ``r`` in frame
    axes and its section rotation is ``R_F R(a)``. Fills ``g`` (6 nc,): position gap and
    ``log(R_c (R_F R(a))^T)``, and ``G`` (6 nc, n), the Jacobian at ``g = 0`` (where Newton ends).
    """
    G[:, :] = 0.0
    for i in range(clamp.shape[0]):
        c, d = int(clamp[i, 0]), int(clamp[i, 1])
        qf = q[7 * d + 3 : 7 * d + 7]
        p = quat_matrix(qf) @ clamp[i, 2:5]
        qt = qmul(qf, clamp[i, 5:9])
        qc = q[7 * c + 3 : 7 * c + 7]
        rot = qlog(qmul(qc, np.array([qt[0], -qt[1], -qt[2], -qt[3]])))
        P = skew3(p)
        for k in range(3):
            r = 6 * i + k
            g[r] = q[7 * c + k] - q[7 * d + k] - p[k]
            g[r + 3] = rot[k]
            G[r, 6 * c + k] = 1.0
            G[r, 6 * d + k] = -1.0
            G[r + 3, 6 * c + 3 + k] = 1.0
            G[r + 3, 6 * d + 3 + k] = -1.0
            for m in range(3):
                G[r, 6 * d + 3 + m] = P[k, m]


@entry
def advance(q, dx):
    """Apply the increment ``dx`` (6 per block) to the state ``q`` (7 per block) in place."""
    for blk in range(dx.shape[0] // 6):
        for k in range(3):
            q[7 * blk + k] += dx[6 * blk + k]
        qn = qmul(qexp(dx[6 * blk + 3 : 6 * blk + 6]), q[7 * blk + 3 : 7 * blk + 7])
        nrm = np.sqrt(qn[0] ** 2 + qn[1] ** 2 + qn[2] ** 2 + qn[3] ** 2)
        for k in range(4):
            q[7 * blk + 3 + k] = qn[k] / nrm


@entry
def element_strains(q, conn, L0, gam0, kap0, out):
    """Strains ``out`` (ne, 6): ``Gamma`` then ``K`` of every element (reference subtracted)."""
    for e in range(conn.shape[0]):
        a, b = conn[e, 0], conn[e, 1]
        gam, kap, _, _, _ = strains(
            q[7 * a : 7 * a + 3],
            q[7 * a + 3 : 7 * a + 7],
            q[7 * b : 7 * b + 3],
            q[7 * b + 3 : 7 * b + 7],
            L0[e],
            gam0[e],
            kap0[e],
        )
        out[e, 0:3] = gam
        out[e, 3:6] = kap


@entry
def advance_material(q, q_ref, dx):
    """``q = q_ref (+) dx`` with material rotation increments (6 per block): positions
    ``x_ref + dx``, rotations ``R_ref exp(dth~)`` (the Lie-group time step's update)."""
    for blk in range(dx.shape[0] // 6):
        for k in range(3):
            q[7 * blk + k] = q_ref[7 * blk + k] + dx[6 * blk + k]
        qn = qmul(q_ref[7 * blk + 3 : 7 * blk + 7], qexp(dx[6 * blk + 3 : 6 * blk + 6]))
        nrm = np.sqrt(qn[0] ** 2 + qn[1] ** 2 + qn[2] ** 2 + qn[3] ** 2)
        for k in range(4):
            q[7 * blk + 3 + k] = qn[k] / nrm
