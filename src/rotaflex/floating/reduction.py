"""First-order coefficient matrices from the compiled kernel and the paper's eq. 32 / 42 forms.

The first-order equations are implemented in :func:`rotaflex.floating.kernels.rhs_perturbation`
as ``M^_0 x1' = f(x1, q1)`` with ``f = H1 + d - G x1 - K^ q1`` (linear).
:func:`first_order_matrices`
extracts ``M^_0``, ``G`` (coefficient of ``x1 = [V1, w1, p1]``), ``K^`` (coefficient of ``q1``) and
``d`` column by column, so they can be compared matrix by matrix with the printed equations.
"""

from __future__ import annotations

import numpy as np

from rotaflex.floating.body import Body, gamma, integrals, m_tilde, phi_hat, skew


def first_order_matrices(body: Body, V0, w0, Vd0, wd0) -> dict[str, np.ndarray]:
    """Kernel's first-order matrices at a zero-order state (no loads).

    ``Vd0, wd0`` are imposed through an equivalent zero-order load so that the zero-order
    equations give exactly these accelerations.
    """
    from rotaflex.floating import kernels
    from rotaflex.floating.solve import pack_body, pack_loads

    n = body.n_modes
    B = pack_body(body)
    I0 = integrals(body)
    Mr = I0["M"][:6, :6]
    S0, J = I0["S"], I0["J"]
    V0, w0, Vd0, wd0 = (np.asarray(v, float) for v in (V0, w0, Vd0, wd0))
    # loads that produce (Vd0, wd0): H0 = Mr a + gyroscopic terms; applied as body force + torque
    g = np.concatenate(
        [
            I0["m"] * np.cross(w0, V0) + np.cross(w0, np.cross(w0, S0)),
            np.cross(S0, np.cross(w0, V0)) + np.cross(w0, J @ w0),
        ]
    )
    H0 = Mr @ np.concatenate([Vd0, wd0]) + g
    from rotaflex.floating.model import Load

    loads = [
        Load(kind="force", vector=tuple(H0[:3]), point=(0.0, 0.0, 0.0)),
        Load(kind="torque", vector=tuple(H0[3:]), point=(0.0, 0.0, 0.0)),
    ]
    L = pack_loads(body, loads) if _has_rotation_shapes(body) else None
    if L is None:  # torque on the frame only (no modal torque term)
        L = pack_loads(body, loads[:1])
        lst = list(L)
        lst[0] = np.array([0, 1])
        lst[1] = np.array([0, 0])
        lst[2] = np.array([0, 0])
        lst[3] = np.zeros((2, 4))
        lst[4] = np.vstack([H0[:3], H0[3:]])
        lst[5] = np.zeros((2, 3))
        lst[6] = np.zeros((2, 3, n))
        lst[7] = np.zeros((2, 3, n))
        L = tuple(lst)
    else:  # remove the modal part of the frame torque: it is part of H1, not of G/K
        lst = list(L)
        lst[7] = np.zeros_like(lst[7])
        lst[6] = np.zeros_like(lst[6])
        L = tuple(lst)

    M0 = I0["M"]

    def force(x1, q1):
        y = np.zeros(25 + 2 * n)
        y[3] = 1.0
        y[7:10], y[10:13] = V0, w0
        y[19:25] = x1[:6]
        y[25 + n :] = x1[6:]
        y[25 : 25 + n] = q1
        dy = kernels.rhs_perturbation_py(0.0, y, B, L, False)
        acc = dy[7:13]
        xd1 = np.concatenate([dy[19:25], dy[25 + n :]])
        return M0 @ xd1, acc

    f0, acc = force(np.zeros(6 + n), np.zeros(n))
    G = np.zeros((6 + n, 6 + n))
    K = np.zeros((6 + n, n))
    for j in range(6 + n):
        e = np.zeros(6 + n)
        e[j] = 1.0
        G[:, j] = -(force(e, np.zeros(n))[0] - f0)
    for j in range(n):
        e = np.zeros(n)
        e[j] = 1.0
        K[:, j] = -(force(np.zeros(6 + n), e)[0] - f0)
    return {"M0": M0, "G": G, "K": K, "d": f0, "acc0": acc}


def _has_rotation_shapes(body: Body) -> bool:
    return bool(np.all(np.isfinite(body.shape_fn(body.points[:1])[1])))


def paper_matrices(body: Body, V0, w0, Vd0, wd0) -> dict[str, np.ndarray]:
    """Eq. 32a-g and 28b as printed (with ``Phi^`` of eq. 32d), same ordering as the kernel."""
    V0, w0, Vd0, wd0 = (np.asarray(v, float) for v in (V0, w0, Vd0, wd0))
    I0 = integrals(body)
    n = body.n_modes
    Pb, Pt, Mb = I0["Phibar"], I0["Phitilde"], I0["Mb"]
    W, Vt, Wd, Vdt = skew(w0), skew(V0), skew(wd0), skew(Vd0)
    ph, phd = phi_hat(body, w0), phi_hat(body, wd0)
    G = np.zeros((6 + n, 6 + n))
    G[:3, 6:] = W @ Pb
    G[3:6, 6:] = Vt.T @ Pb + ph
    G[6:, :3] = Pb.T @ W
    G[6:, 3:6] = Pb.T @ Vt.T + ph.T
    G[6:, 6:] = 2.0 * gamma(body, w0)
    # total coefficient of x1 in eq. 31: (G0 M^0 + G~) x1 + G1 M^0 x0 (the last is linear in x1)
    M0 = I0["M"]
    G0 = np.zeros((6 + n, 6 + n))
    G0[:3, :3], G0[3:6, :3], G0[3:6, 3:6] = W, Vt, W
    h = M0 @ np.concatenate([V0, w0, np.zeros(n)])
    G1 = np.zeros((6 + n, 6 + n))
    G1[:3, 3:6] = -skew(h[:3])
    G1[3:6, :3] = -skew(h[:3])
    G1[3:6, 3:6] = -skew(h[3:6])
    G_total = G0 @ M0 + G + G1
    K = np.zeros((6 + n, n))
    K[:3] = (Wd + W @ W) @ Pb
    K[3:6] = (-Vdt - W @ Vt + Vt @ W) @ Pb + phd + W @ ph
    K[6:] = body.stiffness + gamma(body, wd0) + m_tilde(body, w0)
    d3 = -Pb.T @ (Vd0 + W @ V0) - Pt.T @ wd0 + 0.5 * ph.T @ w0
    return {
        "G": G_total,
        "G_tilde": G,
        "K": K,
        "d3": d3,
        "Mb": Mb,
        "Phibar": Pb,
        "Phitilde": Pt,
        "Phihat": ph,
    }


def planar_eq42(body: Body, Vx0, Vy0, thd0, Vyd0, thdd0) -> dict[str, np.ndarray]:
    """Coefficients of the planar first-order elastic equation eq. 42 (beam along x, modes in y).

    Returns the coefficient vectors/matrices of ``Vdot_y1`` (``phibar``), ``thetaddot_1``
    (``phibar_b``), ``V_x1`` (``thetadot0 phibar``), ``thetadot_1`` (``V_x0 phibar``), ``q1``
    (``K_b - thetadot0^2 M_b``), ``p1`` (0) and the forcing ``d_3`` of eq. 41.
    """
    m, x, phi = body.masses, body.points[:, 0], body.shapes[:, 1, :]
    pb = m @ phi
    pbb = (m * x) @ phi
    return {
        "Vy1_dot": pb,
        "theta1_ddot": pbb,
        "Vx1": thd0 * pb,
        "theta1_dot": Vx0 * pb,
        "q1": body.stiffness - thd0**2 * np.eye(body.n_modes),
        "p1": np.zeros((body.n_modes,) * 2),
        "d3": -pb * (Vyd0 + thd0 * Vx0) - thdd0 * pbb,
    }


def planar_inertial_to_body(zero: dict, first: dict) -> dict[str, np.ndarray]:
    """Body-frame velocities of a planar motion from inertial ones (eq. 29, 35 and 43).

    ``zero``: ``th``, ``thd``, ``thdd`` [rad, rad/s, rad/s^2], ``Rd``, ``Rdd`` (2,) [m/s, m/s^2];
    ``first``: the same first-order quantities plus ``qd``, ``qdd`` (n,). ``V = R(theta)^T Rdot``
    linearised about the zero-order motion gives ``V_0``, ``Vdot_0`` and the first-order
    velocity vector ``x1 = (V_1, w_1, p_1)`` and its time derivative in the kernel's layout.
    """
    c, s = np.cos(zero["th"]), np.sin(zero["th"])
    w0 = zero["thd"]
    (rx, ry), (rxx, ryy) = zero["Rd"], zero["Rdd"]
    V0 = np.array([c * rx + s * ry, -s * rx + c * ry])
    Vd0 = np.array([c * rxx + s * ryy + w0 * V0[1], -s * rxx + c * ryy - w0 * V0[0]])
    th1, thd1 = first["th"], first["thd"]
    (ax, ay), (axx, ayy) = first["Rd"], first["Rdd"]
    V1 = np.array([c * ax + s * ay + th1 * V0[1], -s * ax + c * ay - th1 * V0[0]])  # eq. 43
    Vd1 = np.array(
        [
            c * axx + s * ayy + w0 * (-s * ax + c * ay) + thd1 * V0[1] + th1 * Vd0[1],
            -s * axx + c * ayy - w0 * (c * ax + s * ay) - thd1 * V0[0] - th1 * Vd0[0],
        ]
    )
    x1 = np.concatenate([V1, [0.0, 0.0, 0.0, thd1], first["qd"]])
    x1d = np.concatenate([Vd1, [0.0, 0.0, 0.0, first["thdd"]], first["qdd"]])
    return {"V0": np.append(V0, 0.0), "Vd0": np.append(Vd0, 0.0), "x1": x1, "x1d": x1d}


def planar_eq44_residual(body: Body, zero: dict, first: dict) -> np.ndarray:
    """Left minus right side of eq. 44 (no external load Q_1), beam along x, modes in y.

    Read with the dots the scan lost restored: ``phibar (-s R''_x1 + c R''_y1) + phibar_b
    theta''_1 + M_b q''_1 - phibar (c R''_x0 + s R''_y0) theta_1 + (K_b - theta'_0^2 M_b) q_1
    = -phibar_b theta''_0 + phibar (s R''_x0 - c R''_y0)``. The theta_1 term is the one
    obtained by substituting eq. 43 into eq. 42 (docs/floating.md); the print's sign pattern
    there could not be read from the scan.
    """
    m, x, phi = body.masses, body.points[:, 0], body.shapes[:, 1, :]
    pb, pbb = m @ phi, (m * x) @ phi
    c, s = np.cos(zero["th"]), np.sin(zero["th"])
    (rxx, ryy), (axx, ayy) = zero["Rdd"], first["Rdd"]
    lhs = (
        pb * (-s * axx + c * ayy)
        + pbb * first["thdd"]
        + first["qdd"]
        - pb * (c * rxx + s * ryy) * first["th"]
        + (body.stiffness - zero["thd"] ** 2 * np.eye(body.n_modes)) @ first["q"]
    )
    rhs = -pbb * zero["thdd"] + pb * (s * rxx - c * ryy)
    return lhs - rhs
