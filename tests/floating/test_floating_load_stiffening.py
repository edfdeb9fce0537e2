"""Geometric stiffness from the axial load state of applied forces."""

import numpy as np
import pytest

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
    st_off = Settings(t_end=st.t_end, dt_out=st.dt_out, rtol=1e-10, atol=1e-14, geometric_stiffness=False)
    off = simulate(b, [ld], Initial(modal_displacement=tuple(q0)), st_off, "full", pres)
    assert np.abs(off.q @ V[:, 0] - proj).max() > 1e-4  # the option matters


def _beck_matrices(n, P):
    b = uniform_beam(L, RA, EI, n, support="cantilever")
    Phi, Psi = b.shape_fn([[L, 0.0, 0.0]])
    GL = b.load_geometric([L, 0.0, 0.0], clamped=True)[0]
    # compressive tangential tip load -P along the deformed axis: axial part -P GL, plus the
    # transverse component -P theta_tip of the turned force (non-symmetric)
    return b, b.stiffness - P * GL + P * np.outer(Phi[0, 1], Psi[0, 2])


def test_beck_column_flutter_load():
    # Beck (1952): a cantilever under a tangential (follower) compressive tip load loses
    # stability by flutter at P = 20.05 EI / L^2 (two frequencies coalesce)
    def flutter(n):
        lo, hi = 15.0, 25.0
        for _ in range(50):
            mid = 0.5 * (lo + hi)
            ev = np.linalg.eigvals(_beck_matrices(n, mid * EI / L**2)[1])
            lo, hi = (mid, hi) if np.abs(ev.imag).max() < 1e-9 * np.abs(ev).max() else (lo, mid)
        return lo

    assert flutter(6) == pytest.approx(20.05, rel=2e-3)


def test_material_follower_load_in_the_kernel():
    # the same load through the solver (frame = "material"): the small-amplitude response at
    # P = 10 EI/L^2 follows the linear non-symmetric modal model
    n, P = 4, 10.0 * EI / L**2
    b, K = _beck_matrices(n, P)
    w2, V = np.linalg.eig(K)
    k = int(np.argmin(w2.real))
    v = V[:, k].real / np.linalg.norm(V[:, k].real)
    om = np.sqrt(w2[k].real)
    pres = Prescribed(axis=(0.0, 0.0, 1.0), rate=0.0, spin_up_time=1.0)
    ld = Load(kind="force", vector=(-P, 0.0, 0.0), point=(L, 0.0, 0.0), frame="material")
    T = 2 * np.pi / om
    st = Settings(t_end=float(3 * T), dt_out=float(T / 100), rtol=1e-10, atol=1e-14)
    sol = simulate(b, [ld], Initial(modal_displacement=tuple(1e-4 * v)), st, "full", pres)
    np.testing.assert_allclose(sol.q, 1e-4 * np.outer(np.cos(om * sol.time), v), atol=1e-9)
    # the same force along the (clamped) floating frame is a dead load: 10 EI/L^2 is beyond
    # Euler's 2.47 EI/L^2, so that run buckles while the tangential follower stays bounded
    ld_b = Load(kind="force", vector=(-P, 0.0, 0.0), point=(L, 0.0, 0.0), frame="body")
    sb = simulate(b, [ld_b], Initial(modal_displacement=tuple(1e-4 * v)), st, "full", pres)
    assert sb.status == "diverged" and sol.status == "success"


# ------------------------------------------------------------------- FE frame bodies
def _fe_and_analytic(ne, n_modes=6):
    from rotaflex.floating.fe import frame_body, straight_beam_nodes

    r = 0.004
    A, I2 = np.pi * r**2, np.pi * r**4 / 4
    nodes = straight_beam_nodes(L, ne, start=(-L / 2, 0.0, 0.0))
    fe = frame_body(nodes, e=7e10, g=2.6e10, rho=2700.0, area=A, iy=I2, iz=I2, j=2 * I2, n_modes=n_modes)
    beam = uniform_beam(L, 2700.0 * A, 7e10 * I2, n_modes // 2, spatial=True, section_radius=r)
    return fe, beam


def test_fe_end_force_stiffening_matches_the_analytic_beam():
    """Free-free beam pushed axially at one end (inertia relief: N(x) = -P (x - x0) / L): the
    load-induced shift of eig(K_b - P G_x) of the FE frame converges to the analytic beam's.
    Measured shift errors (max over 6 modes) 3.8e-3, 1.8e-4, 1.5e-4 for 8, 16, 32 elements; the
    1e-4 floor is the FE modes' rotary inertia (Rayleigh beam) against Euler-Bernoulli modes."""
    P = 10.0  # push: body-frame force -P along x at the +x end
    errs = []
    for ne in (8, 32):
        fe, beam = _fe_and_analytic(ne)
        shifts = []
        for b in (fe, beam):
            loaded = np.linalg.eigvalsh(b.stiffness - P * b.load_geometric([L / 2, 0.0, 0.0])[0])
            shifts.append(loaded - np.linalg.eigvalsh(b.stiffness))
        # a strong effect: the push lowers the first bending eigenvalue by over 10 %
        assert shifts[1][0] < -0.1 * beam.stiffness[0, 0]
        errs.append(np.abs(shifts[0] / shifts[1] - 1).max())
    assert errs[1] < 5e-4 and errs[1] < errs[0] / 5, errs


def test_fe_opposite_end_forces_give_uniform_tension():
    fe, _ = _fe_and_analytic(16)
    G = fe.load_geometric([L / 2, 0.0, 0.0])[0] - fe.load_geometric([-L / 2, 0.0, 0.0])[0]
    # +1 N at one end, -1 N at the other: no inertia relief, uniform unit tension, as the beam
    _, beam = _fe_and_analytic(16)
    Gb = beam.load_geometric([L / 2, 0.0, 0.0])[0] - beam.load_geometric([-L / 2, 0.0, 0.0])[0]
    ef = np.linalg.eigvalsh(fe.stiffness + 5.0 * G)
    eb = np.linalg.eigvalsh(beam.stiffness + 5.0 * Gb)
    np.testing.assert_allclose(ef, eb, rtol=1e-3)  # measured 1.1e-4
    # lateral unit forces at the end cause no axial force in a straight beam
    assert np.abs(fe.load_geometric([L / 2, 0.0, 0.0])[1:]).max() < 1e-9 * np.abs(G).max()


def test_fe_pushed_beam_simulation_feels_the_load():
    """The audit case: an FE frame pushed along its axis: with geometric stiffness the first
    mode oscillates at the loaded frequency sqrt(eig(K_b - P G)) in both methods."""
    fe, _ = _fe_and_analytic(16, n_modes=2)
    P = 10.0
    w_loaded = np.sqrt(np.linalg.eigvalsh(fe.stiffness - P * fe.load_geometric([L / 2, 0.0, 0.0])[0]))
    load = Load(kind="force", vector=(-P, 0.0, 0.0), point=(L / 2, 0.0, 0.0), frame="body")
    period = 2 * np.pi / w_loaded[0]
    ini = Initial(modal_displacement=(1e-3, 0.0))
    out = {}
    for geo in (True, False):
        st = Settings(t_end=3 * period, dt_out=period / 200, rtol=1e-10, atol=1e-13, geometric_stiffness=geo)
        for method in ("full", "perturbation"):
            s = simulate(fe, [load], ini, st, method)
            q = s.q[:, 0]
            # zero crossings of mode 1 give its period
            t = s.time
            up = np.where((q[:-1] < 0) & (q[1:] >= 0))[0]
            tc = t[up] - q[up] * (t[up + 1] - t[up]) / (q[up + 1] - q[up])
            out[geo, method] = np.mean(np.diff(tc))
    for method in ("full", "perturbation"):
        assert out[True, method] == pytest.approx(period, rel=1e-5)  # measured 6e-9, 3e-12
        assert abs(out[False, method] / period - 1) > 0.05
