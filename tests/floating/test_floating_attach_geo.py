"""Attachment modes for end loads; geometric stiffness of FE and user bodies."""

import numpy as np
import pytest
import sympy as sp

from rotaflex.core.errors import InputError
from rotaflex.floating.beam import uniform_beam
from rotaflex.floating.body import integrals, m_tilde, point_body
from rotaflex.floating.fe import frame_body, straight_beam_nodes
from rotaflex.floating.model import Initial, Settings
from rotaflex.floating.solve import geometric_stiffness, invariants, simulate

L, RA, EI = 4.0, 2.0, 40.0


def exact_tip_flexibility():
    """Inertia-relief tip deflection of a free-free uniform beam under a unit tip force, derived
    symbolically: EI w'''' = q with q = -rho_a (a0 + alpha (x - L/2)), free ends, mean axes."""
    x, c0, c1 = sp.symbols("x c0 c1")
    Ls, ra, ei = sp.Rational(4), sp.Rational(2), sp.Rational(40)
    m, Jc = ra * Ls, ra * Ls**3 / 12
    q = -ra * (1 / m + (Ls / 2) / Jc * (x - Ls / 2))
    V = sp.integrate(q, (x, 0, x))
    M = sp.integrate(V, (x, 0, x))
    w = sp.integrate(sp.integrate(M / ei, (x, 0, x)), (x, 0, x)) + c0 + c1 * x
    sol = sp.solve([sp.integrate(w, (x, 0, Ls)), sp.integrate(w * (x - Ls / 2), (x, 0, Ls))])
    return float(w.subs(sol).subs(x, Ls))


def modal_static_tip(body):
    Phi, _ = body.shape_fn([[L / 2, 0.0, 0.0]])
    return float(Phi[0, 1] @ np.linalg.solve(body.stiffness, Phi[0, 1]))


def test_attachment_mode_gives_exact_end_load_deflection():
    exact = exact_tip_flexibility()
    assert exact == pytest.approx(L**3 / (105 * EI), rel=1e-12)  # hand value 1/105
    err_plain, err_att = [], []
    for n in (1, 2, 4, 8):
        err_plain.append(abs(modal_static_tip(uniform_beam(L, RA, EI, n)) / exact - 1))
        b = uniform_beam(L, RA, EI, n, attachment_points=[(L / 2, 0.0, 0.0)])
        err_att.append(abs(modal_static_tip(b) / exact - 1))
        Ib = integrals(b)  # still mass-orthonormal, mean axes
        assert np.abs(Ib["Mb"] - np.eye(b.n_modes)).max() < 1e-8
        assert np.abs(Ib["Phibar"]).max() < 1e-10 and np.abs(Ib["Phitilde"]).max() < 1e-10
        # the elastic frequencies are unchanged
        ref = uniform_beam(L, RA, EI, n).frequencies
        assert np.allclose(b.frequencies[:n], ref, rtol=1e-8)
    print("end-load static error, modes 1/2/4/8: plain", err_plain, "with attachment", err_att)
    assert err_plain[-1] > 1e-3  # 8 modes alone: 0.2 % (converges like n^-3)
    assert max(err_att) < 1e-8


def test_fe_attachment_mode():
    r = 0.01
    A, I2 = np.pi * r**2, np.pi * r**4 / 4
    E, rho = EI / I2, RA / A
    nodes = straight_beam_nodes(L, 16, start=(-L / 2, 0.0, 0.0))
    kw = dict(e=E, g=0.4 * E, rho=rho, area=A, iy=I2, iz=I2, j=2 * I2, n_modes=4)
    exact = exact_tip_flexibility()
    plain = frame_body(nodes, **kw)
    att = frame_body(nodes, **kw, attachment_points=[(L / 2, 0.0, 0.0)])
    e_plain = abs(modal_static_tip(plain) / exact - 1)
    e_att = abs(modal_static_tip(att) / exact - 1)
    print(f"FE end-load static error: plain {e_plain:.2e}, with attachment {e_att:.2e}")
    assert e_plain > 1e-2 and e_att < 1e-4
    assert np.abs(integrals(att)["Mb"] - np.eye(att.n_modes)).max() < 1e-9
    assert np.allclose(att.frequencies[:4], plain.frequencies, rtol=1e-8)
    with pytest.raises(InputError, match="attachment_points"):
        frame_body(nodes, **kw, attachment_points=[(L, 1.0, 0.0)])


def _fe_beam(ne, r=0.004):
    A, I2 = np.pi * r**2, np.pi * r**4 / 4
    nodes = straight_beam_nodes(L, ne, start=(-L / 2, 0.0, 0.0))
    return frame_body(nodes, e=7e10, g=2.6e10, rho=2700.0, area=A, iy=I2, iz=I2, j=2 * I2, n_modes=6), uniform_beam(
        L, 2700.0 * A, 7e10 * I2, 3, spatial=True, section_radius=r
    )


def test_fe_geometric_stiffness_matches_analytic_beam():
    """Spin-stiffened frequencies: FE (axial force of the static centrifugal load) vs the
    analytic beam's K_Gw, for spin about z, about y and a general axis."""
    errs = []
    for ne in (20, 40):
        fb, ab = _fe_beam(ne)
        w1 = np.sqrt(ab.stiffness[0, 0])
        e = 0.0
        for w in ([0, 0, 1.0], [0, 2.0, 0], [0.5, 1.0, 3.0]):
            w = w1 * np.array(w)
            ef = np.linalg.eigvalsh(fb.stiffness + m_tilde(fb, w) + geometric_stiffness(fb, w))
            ea = np.linalg.eigvalsh(ab.stiffness + m_tilde(ab, w) + geometric_stiffness(ab, w))
            e = max(e, np.abs(ef / ea - 1).max())
            # stiffening is large here: without K_G the two would differ by much more
            assert np.abs(geometric_stiffness(ab, w)).max() > 0.3 * ab.stiffness[0, 0]
        errs.append(e)
    order = np.log2(errs[0] / errs[1])
    print(f"FE vs analytic spin-stiffened eigenvalues: {errs}, order {order:.2f}")
    assert errs[1] < 2e-3 and 1.7 < order < 2.3


def test_fe_geometric_full_model_conserves_energy_and_momentum():
    # 3-D frame tumbling freely: off-diagonal G[a, b] pairs are non-zero
    nodes = np.array([[0.0, 0, 0], [0.5, 0, 0], [1.0, 0, 0], [1.0, 0.4, 0], [1.0, 0.4, 0.5]])
    r = 0.01
    b = frame_body(
        nodes,
        e=7e10,
        g=2.6e10,
        rho=2700.0,
        area=np.pi * r**2,
        iy=np.pi * r**4 / 4,
        iz=np.pi * r**4 / 4,
        j=np.pi * r**4 / 2,
        n_modes=4,
    )
    assert np.abs(b.geometric[0, 1]).max() > 0 and np.abs(b.geometric[1, 2]).max() > 0
    ini = Initial(angular_velocity=(1.5, -2.0, 3.0), modal_displacement=(1e-3, -1e-3, 5e-4, 0.0))
    st = Settings(t_end=1.0, dt_out=0.01, rtol=1e-11, atol=1e-14, geometric_stiffness=True)
    s = simulate(b, [], ini, st, "full")
    P, H, E, _ = invariants(b, s)
    assert np.abs(H - H[0]).max() < 1e-8 * np.abs(H[0]).max()
    assert np.abs(E - E[0]).max() < 1e-8 * E[0]
    s0 = simulate(
        b, [], ini, Settings(t_end=1.0, dt_out=0.01, rtol=1e-11, atol=1e-14, geometric_stiffness=False), "full"
    )
    assert np.abs(s.q - s0.q).max() > 1e-5  # the option changes the response


def test_point_body_geometric_input():
    ab = uniform_beam(L, RA, EI, 2, spatial=True)
    shapes = np.transpose(ab.shapes, (2, 0, 1))
    f = np.sqrt(np.diag(ab.stiffness))
    pb = point_body(
        ab.masses, ab.points, shapes, frequencies=f, geometric={"yy": ab.geometric[1, 1], "zz": ab.geometric[2, 2]}
    )
    w = np.array([0.3, 1.2, -0.7])
    assert np.allclose(geometric_stiffness(pb, w), geometric_stiffness(ab, w), atol=1e-12)
    with pytest.raises(InputError, match=r"body\.points\.geometric\.ww"):
        point_body(ab.masses, ab.points, shapes, frequencies=f, geometric={"ww": np.eye(4)})
    with pytest.raises(InputError, match="symmetric"):
        point_body(ab.masses, ab.points, shapes, frequencies=f, geometric={"xy": np.triu(np.ones((4, 4)))})
    with pytest.raises(InputError, match="geometric_stiffness"):
        simulate(
            point_body(ab.masses, ab.points, shapes, frequencies=f),
            settings=Settings(t_end=0.1, geometric_stiffness=True),
        )
