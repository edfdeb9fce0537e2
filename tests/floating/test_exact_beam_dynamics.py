"""Dynamics of the planar geometrically exact beam: energy, time-step order, frequency, spin-up.

Independent references: conservation of energy and the work-energy balance (exact for the
continuous equations); the observed order of generalized-alpha (2, Chung & Hulbert 1993); the
first clamped-free Euler-Bernoulli frequency ``1.8751^2 sqrt(EI / rho A L^4)``; the
Kane-Ryan-Banerjee spin-up against the discrete-elastica reference
(:mod:`rotaflex.floating.reference`, a second formulation: lumped masses, RK4), Richardson
extrapolated from 16 and 32 links.
"""

from __future__ import annotations

import numpy as np
import pytest

from rotaflex.core.errors import InputError
from rotaflex.floating import reference as ref
from rotaflex.floating.exact_beam import PointLoads, cantilever
from rotaflex.floating.exact_solve import alpha_coefficients, simulate_exact, time_grid
from rotaflex.floating.model import Prescribed

W1 = 1.8751040687**2  # first clamped-free eigenvalue (beta L)^2
T1 = 2 * np.pi / W1  # period for EI = rho A = L = 1 [s]


def unit_beam(n=8, ea=1e4):
    return cantilever(1.0, n, ea=ea, ga=ea, ei=1.0, rho_a=1.0)


def no_loads(b):
    return PointLoads.build(b, [], [], [], [])


def swing_velocity(b, amp):
    """Nodes moving in the static tip-load shape (mostly mode 1): v = amp (3 s^2 - s^3) / 2."""
    n = b.n_nodes
    s = b.nodes[:, 0]
    v = np.zeros(b.n_dof)
    v[1 : 3 * n : 3] = amp * (3 * s**2 - s**3) / 2
    v[2 : 3 * n : 3] = amp * (6 * s - 3 * s**2) / 2
    return v


def test_alpha_coefficients_of_chung_hulbert():
    assert alpha_coefficients(1.0) == pytest.approx((0.5, 0.5, 0.25, 0.5))
    am, af, beta, gamma = alpha_coefficients(0.0)
    assert (am, af, gamma, beta) == pytest.approx((-1.0, 0.0, 1.5, 1.0))
    with pytest.raises(InputError, match=r"body\.exact\.rho_inf"):
        alpha_coefficients(1.5)


def test_time_grid_steps_onto_outputs_and_breakpoints():
    t, out = time_grid(1.0, 0.3, 0.07, breaks=[0.45])
    assert t[0] == 0.0 and t[-1] == 1.0
    assert 0.45 in t and np.all(np.diff(t) <= 0.07 + 1e-12)
    assert t[out].tolist() == pytest.approx([0.0, 0.3, 0.6, 0.9, 1.0])


def test_rho_one_keeps_the_energy_of_a_large_free_vibration():
    # tip swinging up to ~25 % of L: trapezoidal rule (rho_inf = 1); the energy error is O(h^2)
    b = unit_beam()
    v0 = swing_velocity(b, 1.0)
    drift = []
    for k in (100, 200, 400):
        s = simulate_exact(b, no_loads(b), t_end=3 * T1, dt_out=T1 / 20, time_step=T1 / k, rho_inf=1.0, v0=v0)
        assert s.status == "success"
        e = s.energy[:, 0] + s.energy[:, 1]
        drift.append(np.abs(e - e[0]).max() / e[0])
        assert np.abs(s.q[:, 3 * 8 + 1]).max() > 0.2  # large deflection indeed
    assert drift[-1] < 2e-4
    assert drift[0] / drift[-1] > 8  # ~ order 2 over two halvings


def test_numerical_damping_grows_as_rho_inf_falls():
    # generalized-alpha damps the step-resolved mode little and the unresolved ones strongly;
    # for a nonlinear beam the energy is not monotone step by step (fluctuations ~1e-4 of it)
    b = unit_beam()
    loss = {}
    for rho in (0.9, 0.6):
        s = simulate_exact(
            b, no_loads(b), t_end=3 * T1, dt_out=T1 / 20, time_step=T1 / 50, rho_inf=rho, v0=swing_velocity(b, 1.0)
        )
        e = s.energy[:, 0] + s.energy[:, 1]
        loss[rho] = (e[0] - e[-1]) / e[0]
        assert np.abs(e - e[0]).max() < 5e-3 * e[0]
    assert 0 < loss[0.9] < loss[0.6]


def test_energy_balance_with_the_work_of_a_tip_force_converges_at_order_two():
    b = unit_beam()
    loads = PointLoads.build(
        b, [(1.0, 0.0)], ["force"], ["inertial"], [(0.0, -2.0)], profiles=[4], pars=[(0.0, 0.0, 0.5 / T1, 0.0)]
    )
    rel = []
    for k in (50, 100, 200):
        s = simulate_exact(b, loads, t_end=1.5 * T1, dt_out=T1 / 10, time_step=T1 / k, rho_inf=0.9)
        rel.append(np.abs(s.balance).max() / np.abs(s.energy[:, 2]).max())
    order = np.log2(np.array(rel[:-1]) / rel[1:])
    assert np.all((order > 1.8) & (order < 2.2)), order
    assert rel[-1] < 1e-4


def test_time_step_convergence_order_two():
    b = unit_beam()
    loads = PointLoads.build(
        b, [(1.0, 0.0)], ["force"], ["inertial"], [(0.0, -2.0)], profiles=[4], pars=[(0.0, 0.0, 0.5 / T1, 0.0)]
    )

    def tip(k):
        s = simulate_exact(b, loads, t_end=2 * T1, dt_out=T1 / 40, time_step=T1 / k, rho_inf=0.8, newton_tol=1e-13)
        return s.q[:, 3 * 8 : 3 * 8 + 2]

    fine = tip(2560)
    err = np.array([np.abs(tip(k) - fine).max() for k in (80, 160, 320)])
    order = np.log2(err[:-1] / err[1:])
    assert np.all((order > 1.7) & (order < 2.3)), order


def test_first_frequency_of_the_clamped_beam():
    # small swing (1e-4 L): the period of the exact beam is the linear clamped-free period
    # (32 elements: O(h^2) of the linear elements, measured 2.1e-5)
    b = unit_beam(32, ea=1e6)
    s = simulate_exact(
        b, no_loads(b), t_end=4 * T1, dt_out=T1 / 200, time_step=T1 / 400, rho_inf=0.9, v0=swing_velocity(b, 1e-4)
    )
    y = s.q[:, 3 * 32 + 1]
    up = np.flatnonzero((y[:-1] < 0) & (y[1:] >= 0))
    tz = s.time[up] - y[up] * (s.time[up + 1] - s.time[up]) / (y[up + 1] - y[up])
    period = np.diff(tz).mean()
    assert period == pytest.approx(T1, rel=1e-4)


def test_spin_up_follows_the_geometrically_exact_reference():
    # Kane, Ryan & Banerjee (1987) beam: L 10 m, rho A 1.2 kg/m, EI 1.4e4 N m^2, 6 rad/s in 15 s;
    # the linear modal model without stiffening diverges, the exact beam follows the reference
    L, rho_a, ei = 10.0, 1.2, 1.4e4
    n = 20
    b = cantilever(L, n, ea=3.2e5 * ei / L**2, ga=3.2e5 * ei / L**2, ei=ei, rho_a=rho_a)
    pres = Prescribed(rate=6.0, spin_up_time=15.0)
    s = simulate_exact(
        b,
        no_loads(b),
        t_end=10.0,
        dt_out=0.05,
        time_step=0.005,
        rho_inf=0.9,
        frame="prescribed",
        prescribed=pres.packed(),
    )
    phi, xt, yt = s.q[:, -1], s.q[:, 3 * n], s.q[:, 3 * n + 1]
    tip = -np.sin(phi) * xt + np.cos(phi) * yt  # along the hub frame's y
    case = ref.PlanarCase(length=L, rho_a=rho_a, ei=ei, support="clamped-spin", rate=6.0, spin_up_time=15.0)
    u = []
    for links in (16, 32):
        t, nodes, m, x0 = ref.simulate(case, links, 10.0, 0.05)
        u.append(ref.tip_deflection(case, nodes, m, x0, t)[0])
    u_ref = u[1] + (u[1] - u[0]) / 3.0
    peak = np.abs(u_ref).max()
    assert peak == pytest.approx(0.574, abs=2e-3)  # the documented peak of this beam
    assert np.abs(tip - u_ref).max() < 2e-3 * peak
    # the drive's work is the energy the beam takes up (balance within 1e-3 of it)
    e = s.energy[:, 0] + s.energy[:, 1]
    assert np.abs(s.balance).max() < 1e-3 * e.max()


def test_lumped_mass_frequencies_of_the_free_beam():
    # linearised free-free frequencies (tangent at rest) against Euler-Bernoulli's (beta L)^2:
    # 4.7300408, 7.8532046, 10.9956078, then (2k + 1) pi / 2 to < 1e-7; 40 elements: the
    # consistent mass is 8 % high at mode 10, the lumped one 1.1 % (its soft one-point stiffness
    # and its lumped inertia cancel), both within 0.35 % at mode 1
    import scipy.linalg

    from rotaflex.floating.exact_beam import assemble, residual, straight

    bl = np.array([4.7300408, 7.8532046, 10.9956078] + [(2 * k + 1) * np.pi / 2 for k in range(4, 11)])
    w_eb = bl**2 / 16.0 * np.sqrt(40.0 / 2.0)
    err = {}
    for lumped in (False, True):
        piece = straight(4.0, 40, ea=8e5, ga=8e5, ei=40.0, rho_a=2.0, start=(-2.0, 0.0))
        b = assemble([piece], [False], lumped=lumped)
        _, K, _ = residual(b, no_loads(b), b.reference_state(), 0.0)
        n = 3 * b.n_nodes
        w = np.sqrt(np.abs(scipy.linalg.eigh(K[:n, :n], b.mass_matrix()[:n, :n], eigvals_only=True)))
        err[lumped] = np.sort(w)[3:13] / w_eb - 1
    assert np.abs(err[False][0]) < 3.5e-3 and np.abs(err[True][0]) < 3.5e-3
    assert 0.07 < err[False][-1] < 0.09
    assert np.abs(err[True]).max() < 0.012
