"""Bodies: hand-derivable integrals, FE free-free frequencies, bad input."""

import numpy as np
import pytest

from rotaflex.core.errors import InputError
from rotaflex.floating.beam import uniform_beam
from rotaflex.floating.body import gamma, integrals, m_tilde, point_body
from rotaflex.floating.fe import frame_body, straight_beam_nodes

BETA_FF = np.array([4.7300, 7.8532, 10.9956])  # free-free beta L (issue / textbooks)


def test_uniform_beam_integrals_match_hand_values():
    L, rho_a, ei = 2.0, 1.5, 30.0
    b = uniform_beam(L, rho_a, ei, 6, section_radius=0.01)
    ig = integrals(b)
    assert ig["m"] == pytest.approx(rho_a * L, rel=1e-13)
    assert np.abs(ig["S"]).max() < 1e-13
    jt = rho_a * L**3 / 12.0
    je = rho_a * L * 0.01**2
    assert np.allclose(np.diag(ig["J"]), [je / 2, jt + je / 4, jt + je / 4], rtol=1e-12)
    assert np.abs(ig["Phibar"]).max() < 1e-12  # mean axes: int rho phi = 0
    assert np.abs(ig["Phitilde"]).max() < 1e-12  # mean axes: int rho x phi = 0
    assert np.abs(ig["Mb"] - np.eye(6)).max() < 1e-12
    om = BETA_FF**2 * np.sqrt(ei / (rho_a * L**4))
    assert np.allclose(np.sqrt(np.diag(b.stiffness))[:3], om, rtol=1e-4)
    # free end value of a mass-normalised free-free mode: 2 / sqrt(rho_a L)
    Phi, Psi = b.shape_fn([[L / 2, 0.0, 0.0]])
    assert np.allclose(np.abs(Phi[0, 1]), 2.0 / np.sqrt(rho_a * L), rtol=1e-10)
    # planar modes: Gamma(w) = 0 and M~(w_z) = -w_z^2 M_b (eq. 40)
    assert np.abs(gamma(b, [0.3, 0.2, 1.1])).max() < 1e-13
    assert np.allclose(m_tilde(b, [0, 0, 1.7]), -(1.7**2) * np.eye(6), atol=1e-12)


def test_spatial_beam_gamma_couples_planes():
    b = uniform_beam(2.0, 1.0, 20.0, 2, spatial=True)  # ei_z = ei: pairs y1, z1, y2, z2
    G = gamma(b, [0.7, 0.0, 0.0])
    # Phi_y^T w~ Phi_z with w = w_x e_x: (e_y . (e_x x e_z)) w_x = -w_x (mass-normalised)
    iy, iz = b.mode_labels.index("bend_y1"), b.mode_labels.index("bend_z1")
    assert G[iy, iz] == pytest.approx(-0.7, abs=1e-12)
    assert G[iz, iy] == pytest.approx(0.7, abs=1e-12)


def test_cantilever_southwell_coefficient():
    # rotating cantilever, hub radius 0: omega^2 = omega_1^2 + 1.1933 Omega^2 (Southwell)
    b = uniform_beam(10.0, 1.2, 1.4e4, 4, support="cantilever")
    assert b.geometric[1, 1][0, 0] == pytest.approx(1.1933, abs=2e-4)
    assert b.frequencies[0] == pytest.approx(1.8751**2 * np.sqrt(1.4e4 / (1.2 * 1e4)), rel=1e-4)


def test_fe_free_free_frequencies_within_0p1_percent():
    L, r = 10.0, 0.01
    A, I2 = np.pi * r**2, np.pi * r**4 / 4
    E, rho = 2.1e11, 7800.0
    b = frame_body(straight_beam_nodes(L, 30), e=E, g=8e10, rho=rho, area=A, iy=I2, iz=I2, j=2 * I2, n_modes=6)
    ref = BETA_FF**2 * np.sqrt(E * I2 / (rho * A * L**4))
    got = np.sqrt(np.diag(b.stiffness))[::2]  # equal stiffness: each bending frequency twice
    err = np.abs(got / ref - 1.0)
    assert err.max() < 1e-3
    Ib = integrals(b)
    assert np.abs(Ib["Phibar"]).max() < 1e-10 and np.abs(Ib["Phitilde"]).max() < 1e-10


def test_point_body_roundtrip_and_bad_input():
    b = uniform_beam(2.0, 1.0, 20.0, 3)
    shapes = np.transpose(b.shapes, (2, 0, 1))
    pb = point_body(b.masses, b.points, shapes, frequencies=np.sqrt(np.diag(b.stiffness)))
    assert np.allclose(
        integrals(pb)["M"],
        integrals(b)["M"] - np.diag([0, 0, 0, *np.diag(b.extra_inertia), 0, 0, 0]),
        atol=1e-12,
    )
    with pytest.raises(InputError, match="mass > 0"):
        point_body(-b.masses, b.points, shapes, frequencies=[1, 2, 3])
    with pytest.raises(InputError, match="mass-orthonormal"):
        point_body(b.masses, b.points, 2 * shapes, frequencies=[1, 2, 3])
    with pytest.raises(InputError, match="at least one elastic mode"):
        point_body(b.masses, b.points, shapes[:0], frequencies=[])
    with pytest.raises(InputError, match="frequency > 0"):
        point_body(b.masses, b.points, shapes, frequencies=[1, -2, 3])
    with pytest.raises(InputError, match="node"):
        pb.shape_fn([[0.123, 0.0, 0.0]])
    with pytest.raises(InputError, match="beam axis"):
        b.shape_fn([[1.5, 0.0, 0.0]])
    with pytest.raises(InputError, match="body.beam.ei"):
        uniform_beam(2.0, 1.0, 0.0, 3)
    with pytest.raises(InputError, match="body.beam.n_modes"):
        uniform_beam(2.0, 1.0, 1.0, 0)
