"""Large-rotation disk on the FE shaft: equations vs a sympy Lagrange derivation, Jacobi
integral conservation, small-amplitude agreement with the linear model."""

import numpy as np
import sympy as sp

from rotaflex.rotor.fe import Bearing, Disk, Rotor, Shaft
from rotaflex.rotor.fe.elements.large_disk import LargeRotationDisk
from rotaflex.rotor.fe.transient import transient


def test_remainder_matches_sympy_lagrange():
    t = sp.symbols("t")
    Id, Ip, W0, al = sp.symbols("I_d I_p Omega_0 alpha", positive=True)
    ax, ay = sp.Function("a_x")(t), sp.Function("a_y")(t)
    W = W0 + al * t
    # body rates of the x-y'-z'' sequence with the spin last (independent of the module's text)
    Rx = sp.Matrix([[1, 0, 0], [0, sp.cos(ax), -sp.sin(ax)], [0, sp.sin(ax), sp.cos(ax)]])
    Ry = sp.Matrix([[sp.cos(ay), 0, sp.sin(ay)], [0, 1, 0], [-sp.sin(ay), 0, sp.cos(ay)]])
    # angular velocity in the tilted (non-spinning) frame: R^T R' off-diagonals of R = Rx Ry
    R = Rx * Ry
    Om = (R.T * R.diff(t)).applyfunc(sp.simplify)
    w = sp.Matrix([Om[2, 1], Om[0, 2], Om[1, 0]]) + sp.Matrix([0, 0, W])
    T = sp.Rational(1, 2) * (Id * (w[0] ** 2 + w[1] ** 2) + Ip * w[2] ** 2)
    eqs = [sp.diff(T.diff(q.diff(t)), t) - T.diff(q) for q in (ax, ay)]
    # linear model's disk terms: Id q'' + Omega G q' + Omega' Kst q
    lin = [Id * ax.diff(t, 2) + Ip * W * ay.diff(t) + Ip * al * ay, Id * ay.diff(t, 2) - Ip * W * ax.diff(t)]
    rng = np.random.default_rng(1)
    el = LargeRotationDisk(0, 0.3, 0.5)
    for _ in range(5):
        x, y, vx, vy, accx, accy, tt = rng.uniform(-0.8, 0.8, 7)
        subs = {Id: 0.3, Ip: 0.5, W0: 120.0, al: 35.0}
        vals = {ax.diff(t, 2): accx, ay.diff(t, 2): accy, ax.diff(t): vx, ay.diff(t): vy, ax: x, ay: y, t: tt}
        ref = [float((e - li).subs(subs).subs(vals)) for e, li in zip(eqs, lin, strict=True)]
        q, v = np.array([0, 0, x, y]), np.array([0, 0, vx, vy])
        h = el.force(q, v, 120.0 + 35.0 * tt, 35.0)
        mine = [el.mass_increment(q) * accx + h[2], h[3]]
        assert np.allclose(mine, ref, rtol=1e-10, atol=1e-10)


def _overhung():
    return Rotor(
        shaft=(Shaft(outer_diameter=0.04, length=0.6, elements=6),),
        disk=(Disk(node=6, mass=5.0, Id=0.05, Ip=0.09),),
        bearing=(Bearing(node=0, kxx=1e7, kyy=1e7), Bearing(node=3, kxx=1e7, kyy=1e7)),
    )


def test_jacobi_integral_conserved_at_large_tilt():
    r = _overhung()
    K = r.KC(300.0)[0][0]
    q0 = np.zeros(r.n_dof)
    q0[6 * 4 + 3] = 0.4  # 0.4 rad disk tilt: far from linear
    tr = transient(
        r, 0.05, speed_start=300.0, q0=q0, method="modal", n_modes=6, n_output=101, rtol=1e-10, large_rotation=[6]
    )
    el = LargeRotationDisk(6, 0.05, 0.09)
    dM = np.array([el.mass_increment(q[24:28]) for q in tr.q])
    E = (
        0.5 * np.einsum("ti,ij,tj->t", tr.v, r.M, tr.v)
        + 0.5 * dM * tr.v[:, 26] ** 2
        + 0.5 * np.einsum("ti,ij,tj->t", tr.q, K, tr.q)
    )
    assert np.max(np.abs(E - E[0])) / E[0] < 1e-6
    lin = transient(r, 0.05, speed_start=300.0, q0=q0, method="modal", n_modes=6, n_output=101, rtol=1e-10)
    assert np.max(np.abs(lin.q[:, 27] - tr.q[:, 27])) > 1e-3  # the large-rotation terms matter here


def test_small_tilt_matches_linear_model():
    r = _overhung()
    q0 = np.zeros(r.n_dof)
    q0[27] = 1e-4
    a = transient(
        r,
        0.02,
        speed_start=300.0,
        speed_end=400.0,
        q0=q0,
        method="modal",
        n_modes=6,
        n_output=101,
        rtol=1e-10,
        large_rotation=[6],
    )
    b = transient(
        r, 0.02, speed_start=300.0, speed_end=400.0, q0=q0, method="modal", n_modes=6, n_output=101, rtol=1e-10
    )
    assert np.max(np.abs(a.q - b.q)) < 1e-6 * np.max(np.abs(b.q))  # differences are O(tilt^2) ~ 1e-8
