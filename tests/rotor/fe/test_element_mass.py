"""An element's added mass (a liquid seal's M) enters every analysis through ``Rotor.MKC``: modal,
Campbell, unbalance response and FRF against the closed-form rigid rotor with the seal."""

import numpy as np
import pytest

from rotaflex.rotor.fe import Bearing, Disk, Rotor, Shaft
from rotaflex.rotor.fe.bearings.liquid_seal import LiquidSeal, element
from rotaflex.rotor.fe.frf import frf
from rotaflex.rotor.fe.modal import campbell, modal
from rotaflex.rotor.fe.response import unbalance_response

# a pump neck ring: R = 50 mm, L = 40 mm, Cr = 0.25 mm, 2 MPa, water
SEAL = LiquidSeal(
    radius=0.05,
    length=0.04,
    clearance=0.25e-3,
    inlet_pressure=2.1e6,
    outlet_pressure=1e5,
    density=1000.0,
    viscosity=1e-3,
)
KB, CB = 2e7, 4e3  # both supports together [N/m, N s/m]


def rigid_rotor(seal=True) -> Rotor:
    """A 1e5 x steel-stiff shaft (its flexibility changes the response near resonance by 7e-7),
    the seal at mid-span: in z = x + i y the translation is one complex DOF, the tilt decoupled
    by symmetry."""
    brg = [
        Bearing(node=0, kxx=KB / 2, kyy=KB / 2, cxx=CB / 2, cyy=CB / 2),
        Bearing(node=2, kxx=KB / 2, kyy=KB / 2, cxx=CB / 2, cyy=CB / 2),
    ]
    if seal:
        brg.append(Bearing(node=1, liquid_seal=SEAL, name="ring"))
    return Rotor(
        shaft=(Shaft(outer_diameter=0.1, length=0.4, elements=2, E=2e16, G=8e15),),
        disk=(Disk(node=1, mass=60.0, Id=0.6, Ip=1.0),),
        bearing=tuple(brg),
    )


def impedance(rotor: Rotor, w: float, s, with_mass: bool = True):
    """m s^2 + (c_b + C - i c) s + (k_b + K - i k) of the translation z = x + i y at spin w
    (force of the seal on the rotor -(K - i k) z - (C - i c) z' - M z'')."""
    K, k, C, c, M, _ = element(SEAL, "s").constants(w)
    m = rotor.mass + (M if with_mass else 0.0)
    return m * s**2 + (CB + C - 1j * c) * s + (KB + K - 1j * k)


def forward_root(rotor: Rotor, w: float, with_mass: bool = True) -> complex:
    K, k, C, c, M, _ = element(SEAL, "s").constants(w)
    m = rotor.mass + (M if with_mass else 0.0)
    r = np.roots([m, CB + C - 1j * c, KB + K - 1j * k])
    return r[np.argmax(r.imag)]


def test_seal_mass_is_assembled_in_MKC():
    rotor = rigid_rotor()
    w = np.array([0.0, 300.0, 1000.0])
    M = rotor.MKC(w)[0]
    for j, s in enumerate(w):
        Ms = element(SEAL, "s").constants(s)[4]
        assert Ms > 1.0  # a few kg: a test that can fail
        i = 4 * 1  # node 1, x
        assert M[j, i, i] - rotor.M[i, i] == pytest.approx(Ms, rel=1e-12)
        assert M[j, i + 1, i + 1] - rotor.M[i + 1, i + 1] == pytest.approx(Ms, rel=1e-12)


@pytest.mark.parametrize("w", [0.0, 300.0])
def test_modal_frequency_with_seal_mass(w):
    """modal(): the forward translation root of (m + M) s^2 + ... (at w = 0 and no seal
    damping/cross-coupling it would be sqrt(k/(m + M)))."""
    rotor = rigid_rotor()
    lam = modal(rotor, w).eigenvalue[0]
    ref = forward_root(rotor, w)
    got = lam[np.argmin(np.abs(lam - ref))]
    assert got == pytest.approx(ref, rel=1e-5)
    assert abs(forward_root(rotor, w, with_mass=False) - got) > 1e-2 * abs(got)  # M moves it by ~5 %


def test_campbell_frequency_with_seal_mass():
    rotor = rigid_rotor()
    speeds = np.array([100.0, 300.0, 600.0])
    lam = campbell(rotor, speeds, n_modes=4).modes.eigenvalue
    for j, w in enumerate(speeds):
        ref = forward_root(rotor, w)
        got = lam[j][np.argmin(np.abs(lam[j] - ref))]
        assert got == pytest.approx(ref, rel=1e-5)
        assert abs(forward_root(rotor, w, with_mass=False) - got) > 1e-2 * abs(got)


def test_unbalance_response_peak_with_seal_mass():
    """Forward unbalance u w^2 at the disk: z = u w^2 / impedance(i w), the seal's coefficients at
    each spin speed; around the peak the amplitude matches and the peak moves to the massive root."""
    rotor = rigid_rotor()
    u = 1e-4  # kg m
    speeds = np.linspace(400.0, 700.0, 31)
    Q = unbalance_response(rotor, speeds, [(1, u, 0.0)]).Q[:, 4]
    ref = np.array([u * w**2 / impedance(rotor, w, 1j * w) for w in speeds])
    assert Q == pytest.approx(ref, rel=1e-5)
    bare = np.array([u * w**2 / impedance(rotor, w, 1j * w, with_mass=False) for w in speeds])
    assert np.max(np.abs(Q - bare)) > 0.1 * np.max(np.abs(Q))


def test_frf_with_seal_mass():
    rotor = rigid_rotor()
    w, freq = 300.0, np.array([200.0, 450.0, 800.0])
    H = frf(rotor, freq, w, [4, 5], [4, 5]).H  # receptance, forces at x and y of the disk
    # a forward force f_x = 1, f_y = -i excites z = x + i y with 2 / impedance; the backward part is zero
    z = (H[:, 0, 0] - 1j * H[:, 0, 1]) + 1j * (H[:, 1, 0] - 1j * H[:, 1, 1])
    ref = np.array([2.0 / impedance(rotor, w, 1j * f) for f in freq])
    assert z == pytest.approx(ref, rel=1e-5)
