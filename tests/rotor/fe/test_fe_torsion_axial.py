"""Torsional and axial modes vs closed forms."""

import numpy as np

from rotaflex.rotor.fe import Disk, Rotor, Shaft
from rotaflex.rotor.fe.torsion_axial import axial_modes, torsional_modes


def test_free_free_uniform_shaft_exact_and_second_order():
    L, E, G, rho = 1.2, 2e11, 8e10, 7800.0
    exact_t = np.arange(1, 4) * np.pi / L * np.sqrt(G / rho)
    exact_a = np.arange(1, 4) * np.pi / L * np.sqrt(E / rho)
    errs = []
    for n in (10, 20, 40):
        r = Rotor(
            shaft=(Shaft(outer_diameter=0.05, inner_diameter=0.02, length=L, elements=n, E=E, G=G, rho=rho),), free=True
        )
        wt, wa = torsional_modes(r, 4)[0], axial_modes(r, 4)[0]
        assert abs(wt[0]) < 1e-6 * wt[1] and abs(wa[0]) < 1e-6 * wa[1]  # rigid-body modes
        errs.append(np.abs(wt[1:] - exact_t) / exact_t)
        assert np.allclose(wa[1:] / exact_a, wt[1:] / exact_t, rtol=1e-9)  # same equation, scaled
    orders = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all((orders > 1.9) & (orders < 2.1))
    # leading error term of linear elements with consistent mass: (k h)^2 / 24, k h = n pi / N
    lead = (np.arange(1, 4) * np.pi / 40) ** 2 / 24
    assert np.allclose(errs[-1], lead, rtol=0.03)


def test_two_disks_on_a_light_shaft():
    """Two inertias on a torsional spring GJ/L: omega = sqrt(k (1/I1 + 1/I2))."""
    G, d, L, I1, I2 = 8e10, 0.03, 0.5, 0.2, 0.05
    r = Rotor(
        shaft=(Shaft(outer_diameter=d, length=L, elements=1, G=G, rho=1e-6),),
        disk=(Disk(node=0, mass=1.0, Id=0.1, Ip=I1), Disk(node=1, mass=1.0, Id=0.1, Ip=I2)),
        free=True,
    )
    k = G * np.pi * d**4 / 32 / L
    w = torsional_modes(r, 2)[0][1]
    assert abs(w - np.sqrt(k * (1 / I1 + 1 / I2))) / w < 1e-6
