"""Attachment shapes for applied moments (``moment_points`` / ``attach_at_loads`` with torques)."""

import numpy as np
import pytest
import sympy as sp

from rotaflex.floating.beam import uniform_beam
from rotaflex.floating.body import integrals
from rotaflex.floating.case import BodyConfig, build_body, from_mapping
from rotaflex.floating.fe import frame_body, straight_beam_nodes
from rotaflex.floating.model import Load

L, RA, EI = 4.0, 2.0, 40.0


def exact_moment_flexibility(a_frac):
    """Tip deflection of a free-free beam under a unit moment at x = a (x in [0, L]), inertia
    relief (no resultant force: q = -rho_a x_c / J_c), mean axes; derived symbolically."""
    x, c0, c1 = sp.symbols("x c0 c1")
    Ls, ra, ei = sp.Rational(4), sp.Rational(2), sp.Rational(40)
    a = a_frac * Ls
    Jc = ra * Ls**3 / 12
    q = -ra * (x - Ls / 2) / Jc
    V = sp.integrate(q, (x, 0, x))
    M = sp.integrate(V, (x, 0, x))
    # w = relief part + couple part -(x - a)^2 / (2 EI) for x > a, integrated piecewise
    w_left = sp.integrate(sp.integrate(M / ei, (x, 0, x)), (x, 0, x)) + c0 + c1 * x
    w_right = w_left - (x - a) ** 2 / (2 * ei)
    cond = [
        sp.integrate(w_left, (x, 0, a)) + sp.integrate(w_right, (x, a, Ls)),
        sp.integrate(w_left * (x - Ls / 2), (x, 0, a)) + sp.integrate(w_right * (x - Ls / 2), (x, a, Ls)),
    ]
    sol = sp.solve(cond, [c0, c1])
    return float(w_right.subs(sol).subs(x, Ls))


def modal_tip_under_moment(body, a):
    Phi, _ = body.shape_fn([[L / 2, 0.0, 0.0]])
    _, Psi = body.shape_fn([[a, 0.0, 0.0]])
    return float(Phi[0, 1] @ np.linalg.solve(body.stiffness, Psi[0, 2]))


@pytest.mark.parametrize("a_frac", [sp.Rational(1, 2), sp.Rational(7, 8)])
def test_moment_attachment_gives_exact_static_tip_deflection(a_frac):
    exact = exact_moment_flexibility(a_frac)
    a = float(a_frac) * L - L / 2
    plain = [abs(modal_tip_under_moment(uniform_beam(L, RA, EI, n), a) / exact - 1) for n in (2, 8)]
    att = []
    for n in (1, 2, 8):
        b = uniform_beam(L, RA, EI, n, moment_points=[(a, 0.0, 0.0)])
        att.append(abs(modal_tip_under_moment(b, a) / exact - 1))
        Ib = integrals(b)  # still mass-orthonormal and in mean axes
        assert np.abs(Ib["Mb"] - np.eye(b.n_modes)).max() < 1e-8
        assert np.abs(Ib["Phibar"]).max() < 1e-10 and np.abs(Ib["Phitilde"]).max() < 1e-10
        # elastic frequencies unchanged (to the Gauss mass quadrature across the curvature jump)
        assert np.allclose(b.frequencies[:n], uniform_beam(L, RA, EI, n).frequencies, rtol=1e-7)
    print(f"moment at {float(a_frac)} L: plain 2/8 modes {plain}, attachment 1/2/8 {att}")
    assert plain[-1] > 1e-4  # modes alone converge slowly
    assert max(att) < 1e-8


def test_fe_moment_attachment():
    r = 0.01
    A, I2 = np.pi * r**2, np.pi * r**4 / 4
    nodes = straight_beam_nodes(L, 16, start=(-L / 2, 0.0, 0.0))
    kw = dict(e=EI / I2, g=0.4 * EI / I2, rho=RA / A, area=A, iy=I2, iz=I2, j=2 * I2, n_modes=4)
    exact = exact_moment_flexibility(sp.Rational(1, 2))
    plain = frame_body(nodes, **kw)
    att = frame_body(nodes, **kw, moment_points=[(0.0, 0.0, 0.0)])
    e_plain = abs(modal_tip_under_moment(plain, 0.0) / exact - 1)
    e_att = abs(modal_tip_under_moment(att, 0.0) / exact - 1)
    print(f"FE moment static error: plain {e_plain:.2e}, with attachment {e_att:.2e}")
    assert e_plain > 1e-3 and e_att < 1e-4  # FE discretisation error of 16 elements remains


def _modal_tip(body, a):
    Phi, _ = body.shape_fn([[L / 2, 0.0, 0.0]])
    _, Psi = body.shape_fn([[a, 0.0, 0.0]])
    w2, V = np.linalg.eigh(body.stiffness)
    return np.sqrt(w2), V.T @ Psi[0, 2], V.T @ Phi[0, 1]


def _pulse_tip_history(body, a, t, T=1.0, shape="rect"):
    """Linear mean-axes modal response of the tip to a unit moment pulse of length T at a, in
    closed form per mode (``rect``: 1 on [0, T); ``halfsine``: sin(pi t / T) on [0, T)). The
    rigid rotation is left out, which isolates the modal truncation error."""
    w, f, g = _modal_tip(body, a)
    tt = t[:, None]
    if shape == "rect":
        c = np.where(tt < T, 1 - np.cos(w * tt), np.cos(w * (tt - T)) - np.cos(w * tt)) / w**2
    else:
        om = np.pi / T
        A = 1.0 / (w**2 - om**2)

        def on(x):  # q, dq/dt of q'' + w^2 q = sin(om x), q(0) = q'(0) = 0
            return A * (np.sin(om * x) - om / w * np.sin(w * x)), A * om * (np.cos(om * x) - np.cos(w * x))

        q_in, _ = on(tt)
        qT, vT = on(T)
        q_out = qT * np.cos(w * (tt - T)) + vT / w * np.sin(w * (tt - T))
        c = np.where(tt < T, q_in, q_out)
    return (c * (f * g)).sum(axis=1)


@pytest.fixture(scope="module")
def beam300():
    # the 300-mode reference beam, built once for the two pulse tests below
    return uniform_beam(L, RA, EI, 300)


def test_ten_modes_with_moment_shape_as_accurate_as_forty_modes(beam300):
    # half-sine torque pulse (1 s) at the centre: the modes above the 10th respond
    # quasi-statically, which is exactly what the moment attachment shape carries
    t = np.linspace(0.0, 4.0, 2001)
    ref = _pulse_tip_history(beam300, 0.0, t, shape="halfsine")
    scale = np.abs(ref).max()

    def err(body):
        return np.abs(_pulse_tip_history(body, 0.0, t, shape="halfsine") - ref).max() / scale

    e10, e40 = err(uniform_beam(L, RA, EI, 10)), err(uniform_beam(L, RA, EI, 40))
    e10a = err(uniform_beam(L, RA, EI, 10, moment_points=[(0.0, 0.0, 0.0)]))
    print(f"half-sine pulse, tip history: 10 modes {e10:.2e}, 40 modes {e40:.2e}, 10 + moment shape {e10a:.2e}")
    assert e10 > 10 * e40  # the modal series alone converges slowly for a moment
    # measured 1.2e-4 vs 1.1e-4: what remains is the small oscillation of modes 11+ set off by
    # the slope jumps of the half-sine at 0 and T (amplitude ~ (pi/T)/omega_j), not static
    assert e10a <= 1.25 * e40 and e10a < 0.05 * e10


def test_rectangular_pulse_peak_deflection_improves_tenfold(beam300):
    # with a jump in the load, the oscillation of the truncated high modes right after the jump
    # cannot be represented by any 10-dimensional basis; the peak deflection still improves 10x
    t = np.linspace(0.0, 4.0, 4001)
    ref = np.abs(_pulse_tip_history(beam300, 0.0, t)).max()

    def err(body):
        return abs(np.abs(_pulse_tip_history(body, 0.0, t)).max() / ref - 1)

    e10 = err(uniform_beam(L, RA, EI, 10))
    e10a = err(uniform_beam(L, RA, EI, 10, moment_points=[(0.0, 0.0, 0.0)]))
    print(f"rectangular pulse, peak tip deflection: 10 modes {e10:.2e}, 10 + moment {e10a:.2e}")
    assert e10a < 0.2 * e10


def test_attach_at_loads_adds_moment_shapes_for_torques():
    cfg = from_mapping(
        BodyConfig,
        {"type": "beam", "attach_at_loads": True, "beam": {"length": L, "rho_a": RA, "ei": EI, "n_modes": 3}},
    )
    b = build_body(cfg, [Load(kind="torque", vector=(0.0, 0.0, 1.0))])
    assert b.n_modes == 4 and any(lab.startswith("attach") for lab in b.mode_labels)
