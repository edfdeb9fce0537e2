"""Geometrically exact planar reference for the floating beam: a discrete elastica.

The beam is N links of length ds with the mass lumped at the N + 1 nodes (end nodes half),
bending energy sum EI/(2 ds) (theta_{j+1} - theta_j)^2 over joint angles (exact large
rotations) and stiff axial springs EA (exact kinematics; EA >> loads makes it nearly
inextensible). As ds -> 0 it converges to the inextensible Euler-Bernoulli elastica (O(ds^2)).
The tip deflection is read in the mean-axis frame of the nodes (planar: centre of mass and
the rotation that zeros sum m r0 x u), the frame of the floating modal model.

Case: free-free beam L 4 m, rho_a 2 kg/m, end force 20 N along a fixed inertial direction
(y), a 1 s half-sine pulse, EI = 100 and EI = 1 (scaled force), compared with the floating modal model
(10 modes + attachment shape, geometric stiffness on / off).
Run: PYTHONPATH=src python benchmarks/reference_elastica.py
"""

import time

import numpy as np
from scipy.integrate import solve_ivp

L, RA = 4.0, 2.0
N1 = 32  # links of the coarser elastica (the finer has 2 N1)


def chain_rhs(n, ei, ea, force, t_pulse):
    ds = L / n
    m = np.full(n + 1, RA * ds)
    m[[0, -1]] *= 0.5

    def rhs(t, y):
        x = y[: 2 * (n + 1)].reshape(-1, 2)
        v = y[2 * (n + 1) :].reshape(-1, 2)
        d = np.diff(x, axis=0)
        ln = np.hypot(d[:, 0], d[:, 1])
        e = d / ln[:, None]
        f = np.zeros_like(x)
        ax = (ea * (ln - ds) / ds)[:, None] * e  # tension along each link
        f[:-1] += ax
        f[1:] -= ax
        th = np.arctan2(d[:, 1], d[:, 0])
        dth = np.angle(np.exp(1j * np.diff(th)))
        mom = ei * dth / ds  # joint moments
        # dU/dtheta_j for link j, then theta_j's gradient wrt its end nodes
        g = np.zeros(n)
        g[:-1] -= mom
        g[1:] += mom
        perp = np.column_stack([-e[:, 1], e[:, 0]]) / ln[:, None]  # dtheta/dx_end
        fb = g[:, None] * perp
        f[1:] -= fb
        f[:-1] += fb
        if t < t_pulse:  # half-sine pulse: smooth enough not to excite the truncated modes
            f[-1] += force * np.sin(np.pi * t / t_pulse)
        a = f / m[:, None]
        return np.concatenate([v.ravel(), a.ravel()])

    x0 = np.column_stack([np.linspace(-L / 2, L / 2, n + 1), np.zeros(n + 1)])
    return rhs, m, x0


def mean_axis_tip(x, m, x0):
    cm = m @ x / m.sum()
    xi = x - cm
    s = m @ (x0[:, 0] * xi[:, 1] - x0[:, 1] * xi[:, 0])
    c = m @ (x0[:, 0] * xi[:, 0] + x0[:, 1] * xi[:, 1])
    th = np.arctan2(s, c)
    R = np.array([[np.cos(th), np.sin(th)], [-np.sin(th), np.cos(th)]])  # A^T
    return (R @ xi[-1])[1], th


def reference(n, ei, force, t_end, t_out):
    ea = 2e4 * ei  # axial stretch << bending deflection
    rhs, m, x0 = chain_rhs(n, ei, ea, np.array([0.0, force]), 1.0)
    y0 = np.concatenate([x0.ravel(), np.zeros(2 * (n + 1))])
    sol = solve_ivp(rhs, (0, t_end), y0, method="DOP853", t_eval=t_out, rtol=1e-9, atol=1e-12)
    tips = [mean_axis_tip(sol.y[: 2 * (n + 1), k].reshape(-1, 2), m, x0)[0] for k in range(len(t_out))]
    return np.array(tips)


def modal(ei, force, t_end, dt, geo):
    from rotaflex.floating import Load, Settings, uniform_beam
    from rotaflex.floating.solve import point_motion, simulate

    b = uniform_beam(L, RA, ei, 10, attachment_points=[(2.0, 0.0, 0.0)])
    ld = Load(
        kind="force",
        vector=(0.0, force, 0.0),
        point=(2.0, 0.0, 0.0),
        frame="inertial",
        profile="sinusoid",
        frequency=0.5,
        duration=1.0,
    )
    s = simulate(
        b,
        [ld],
        settings=Settings(t_end=t_end, dt_out=dt, rtol=1e-10, atol=1e-13, geometric_stiffness=geo),
        method="full",
    )
    return point_motion(b, s, np.array([[2.0, 0.0, 0.0]]))[1][:, 0, 1]


if __name__ == "__main__":
    t_end, dt = 2.0, 0.05
    t = np.arange(0.0, t_end + 1e-9, dt)
    for ei, force in ((100.0, 20.0), (1.0, 0.2)):
        refs = {}
        for n in (N1, 2 * N1):
            t0 = time.perf_counter()
            refs[n] = reference(n, ei, force, t_end, t)
            print(
                f"EI {ei:g}: elastica {n} links, {time.perf_counter() - t0:.1f} s, "
                f"max |tip| {np.abs(refs[n]).max():.5e} m"
            )
        ref = refs[2 * N1] + (refs[2 * N1] - refs[N1]) / 3.0  # Richardson, O(ds^2)
        scale = np.abs(ref).max()
        print(f"  discretisation estimate ({2 * N1} vs extrapolated): {np.abs(refs[2 * N1] - ref).max() / scale:.2e}")
        for geo in (False, True):
            u = modal(ei, force, t_end, dt, geo)
            print(
                f"  modal model, geometric stiffness {'on ' if geo else 'off'}: max rel. error "
                f"{np.abs(u - ref).max() / scale:.2e} (tip {np.abs(u).max():.5e} m)"
            )
