"""Rayleigh damping alpha M + beta K of shaft sections and disks against the modal damping
formula: with C = alpha M + beta K the undamped modes (K phi = w^2 M phi) diagonalise C, each
mode is a damped oscillator with zeta = alpha / (2 w) + beta w / 2, and its eigenvalues are
lambda = -zeta w +- i w sqrt(1 - zeta^2) (non-rotating)."""

import numpy as np
import pytest
import scipy.linalg as sla

from rotaflex.rotor.fe.modal import modal
from rotaflex.rotor.fe.model import Bearing, Disk, Rotor, Shaft


def _shaft(alpha, beta):
    return (
        Shaft(outer_diameter=0.06, length=0.5, elements=5, rayleigh_alpha=alpha, rayleigh_beta=beta),
        Shaft(
            outer_diameter=0.08, inner_diameter=0.03, length=0.7, elements=6, rayleigh_alpha=alpha, rayleigh_beta=beta
        ),
    )


def _check(rotor, alpha, beta, n):
    K = rotor.KC(0.0)[0][0]
    w2, _ = sla.eigh(K, rotor.M)
    w = np.sqrt(np.clip(w2, 0, None))
    w = w[w > 1.0][: 2 * n : 2]  # each plane gives the same frequency: one of each pair
    zeta = alpha / (2 * w) + beta * w / 2
    ref = -zeta * w + 1j * w * np.sqrt(1 - zeta**2)
    got = modal(rotor, 0.0, 2 * n).eigenvalue[0][::2]
    np.testing.assert_allclose(got, ref, rtol=1e-9)
    return zeta


def test_free_rotor_alpha_and_beta():
    """Free-free (no bearings): K is the shaft's alone, so C = alpha M + beta K holds globally."""
    alpha, beta = 3.0, 2e-5
    rotor = Rotor(
        shaft=_shaft(alpha, beta),
        disk=(Disk(position=0.5, mass=15.0, Id=0.1, Ip=0.18, rayleigh_alpha=alpha),),
        free=True,
    )
    ref = alpha * rotor.M + beta * rotor.K_shaft
    assert np.max(np.abs(rotor.C_rayleigh - ref)) <= 1e-14 * np.max(np.abs(ref))
    zeta = _check(rotor, alpha, beta, 4)
    assert zeta[0] > 0.01 and zeta[-1] > zeta[0]  # both terms matter over these modes


def test_supported_rotor_alpha():
    """On undamped bearings C = alpha M is proportional to M whatever K is."""
    alpha = 8.0
    rotor = Rotor(
        shaft=_shaft(alpha, 0.0),
        disk=(Disk(position=0.5, mass=15.0, Id=0.1, Ip=0.18, rayleigh_alpha=alpha),),
        bearing=(Bearing(node=0, kxx=5e6, kyy=5e6), Bearing(node=11, kxx=5e6, kyy=5e6)),
    )
    _check(rotor, alpha, 0.0, 3)


def test_rayleigh_per_section_only_where_given():
    """A section without damping adds none: C is assembled from each section's own matrices."""
    one = Rotor(
        shaft=(_shaft(0.0, 1e-4)[0], _shaft(0.0, 0.0)[1]),
        free=True,
    )
    first = slice(0, 4 * 6)  # nodes 0..5 belong to the first section only (node 5 is shared)
    assert np.count_nonzero(one.C_rayleigh[4 * 6 :, 4 * 6 :]) == 0
    assert np.count_nonzero(one.C_rayleigh[first, first]) > 0
    assert one.C_rayleigh[0, 0] == pytest.approx(1e-4 * one.K_shaft[0, 0], rel=1e-14)
