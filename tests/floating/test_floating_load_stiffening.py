"""Geometric stiffness from the axial load state of applied forces."""

import numpy as np

from rotaflex.floating import Initial, Load, Prescribed, Settings, uniform_beam
from rotaflex.floating.solve import simulate

L, RA, EI = 2.0, 1.0, 10.0


def test_clamped_cantilever_buckles_at_euler_load():
    # Euler: P_cr = pi^2 EI / (4 L^2) for a cantilever under a compressive tip load. K_b is per
    # unit modal mass and GL integrates N phi'^2 over the same mass-normalised modes, so the
    # critical load of K_b - P GL comes out in newtons. Ritz with the unloaded modes converges
    # from above (measured 5.8e-3, 9.4e-4, 1.3e-4, 1.6e-5 relative for 2, 4, 8, 16 modes).
    from scipy.linalg import eigh

    exact = np.pi**2 * EI / (4 * L**2)
    errs = []
    for n in (4, 8, 16):
        b = uniform_beam(L, RA, EI, n, support="cantilever")
        GL = b.load_geometric([L, 0.0, 0.0], clamped=True)[0]  # per unit pull along +x
        errs.append(eigh(b.stiffness, GL, eigvals_only=True)[0] / exact - 1)
    assert all(e > 0 for e in errs) and errs[0] > errs[1] > errs[2]
    assert errs[-1] < 3e-5
    assert np.log2(errs[1] / errs[2]) > 2.5  # observed order ~3


def test_opposite_end_forces_give_uniform_tension():
    # +P at the tip and -P at the root: no resultant, no inertia relief, N = P everywhere
    b = uniform_beam(L, RA, EI, 4)
    G = b.load_geometric([L / 2, 0.0, 0.0])[0] - b.load_geometric([-L / 2, 0.0, 0.0])[0]
    x = np.linspace(-L / 2, L / 2, 20001)
    _, Psi = b.shape_fn(np.column_stack([x, 0 * x, 0 * x]))
    d = Psi[:, 2, :]  # slopes v'
    ref = np.trapezoid(d[:, :, None] * d[:, None, :], x, axis=0)
    np.testing.assert_allclose(G, ref, atol=1e-6 * np.abs(ref).max())


def test_compressive_load_lowers_the_simulated_frequency():
    # clamped cantilever (prescribed frame at rest), tip compression 0.5 P_cr: the first-mode
    # oscillation follows omega^2 = eig(K_b - P GL), not omega_1 of the unloaded beam
    b = uniform_beam(L, RA, EI, 4, support="cantilever")
    P = 0.5 * np.pi**2 * EI / (4 * L**2)
    ld = Load(kind="force", vector=(-P, 0.0, 0.0), point=(L, 0.0, 0.0))
    GL = b.load_geometric([L, 0.0, 0.0], clamped=True)[0]
    from scipy.linalg import eigh

    w2, V = eigh(b.stiffness + (-P) * GL)
    q0 = 1e-3 * V[:, 0]  # start in the loaded first mode
    pres = Prescribed(axis=(0.0, 0.0, 1.0), rate=0.0, spin_up_time=1.0)
    T = 2 * np.pi / np.sqrt(w2[0])
    st = Settings(t_end=float(5 * T), dt_out=float(T / 200), rtol=1e-10, atol=1e-14)
    sol = simulate(b, [ld], Initial(modal_displacement=tuple(q0)), st, "full", pres)
    proj = sol.q @ V[:, 0]
    np.testing.assert_allclose(proj, 1e-3 * np.cos(np.sqrt(w2[0]) * sol.time), atol=1e-8)
    assert np.sqrt(w2[0]) < 0.75 * np.sqrt(b.stiffness[0, 0])  # clearly softened
    st_off = Settings(t_end=st.t_end, dt_out=st.dt_out, rtol=1e-10, atol=1e-14,
                      geometric_stiffness=False)
    off = simulate(b, [ld], Initial(modal_displacement=tuple(q0)), st_off, "full", pres)
    assert np.abs(off.q @ V[:, 0] - proj).max() > 1e-4  # the option matters
