"""FE rotor model features: tapered and hollow sections, tabulated and node-to-node bearings,
point masses, instability from cross-coupled stiffness (closed form)."""

import numpy as np
import pytest
import scipy.linalg as sla

from rotaflex.core.errors import InputError
from rotaflex.rotor.fe import Bearing, Disk, PointMass, Rotor, Shaft
from rotaflex.rotor.fe.elements.shaft import cowper_shear_coefficient
from rotaflex.rotor.fe.modal import campbell, modal


def _freqs(r, n):
    """Undamped non-rotating frequencies [rad/s] (symmetric problem; both planes, so pairs)."""
    return np.sqrt(sla.eigh(r.KC(0.0)[0][0], r.M, eigvals_only=True, subset_by_index=(0, n - 1)))


def _pinned(shafts):
    return Rotor(shaft=shafts, bearing=(Bearing(node=0, kxx=1e9, kyy=1e9), Bearing(position=1.0, kxx=1e9, kyy=1e9)))


def test_tapered_element_converges_to_fine_stepped_shaft():
    """A linearly tapered shaft: tapered elements and many short cylindrical steps (each with the
    local mean diameter) converge to the same frequencies."""
    d0, d1 = 0.08, 0.04
    tapered = _pinned((Shaft(outer_diameter=d0, outer_diameter_right=d1, length=1.0, elements=40),))
    n = 200
    z = (np.arange(n) + 0.5) / n
    steps = tuple(Shaft(outer_diameter=d0 + (d1 - d0) * zz, length=1.0 / n) for zz in z)
    stepped = _pinned(steps)
    wt, ws = _freqs(tapered, 6), _freqs(stepped, 6)
    assert np.allclose(wt, ws, rtol=2e-3)
    # and a single coarse tapered element per 1/10 is already close, a cylinder of the mean diameter is not
    coarse = _pinned((Shaft(outer_diameter=d0, outer_diameter_right=d1, length=1.0, elements=10),))
    mean = _pinned((Shaft(outer_diameter=(d0 + d1) / 2, length=1.0, elements=40),))
    assert np.allclose(_freqs(coarse, 2), ws[:2], rtol=5e-3)
    assert abs(_freqs(mean, 1)[0] - ws[0]) / ws[0] > 0.03


def test_hollow_section_mass_and_cowper():
    r = Rotor(shaft=(Shaft(outer_diameter=0.1, inner_diameter=0.06, length=2.0, elements=5),), free=True)
    assert r.mass == pytest.approx(7810 * np.pi / 4 * (0.1**2 - 0.06**2) * 2.0, rel=1e-12)
    # Cowper: solid circle 6(1+nu)/(7+6nu); thin tube tends to 2(1+nu)/(4+3nu)
    nu = 0.3
    assert cowper_shear_coefficient(0.0, nu) == pytest.approx(6 * 1.3 / (7 + 1.8))
    assert cowper_shear_coefficient(0.9999, nu) == pytest.approx(2 * 1.3 / (4 + 0.9), rel=1e-3)


def test_tabulated_bearing_interpolates_and_rejects_outside():
    base = dict(shaft=(Shaft(outer_diameter=0.05, length=1.0, elements=4),))
    tab = Rotor(
        **base,
        bearing=(
            Bearing(node=0, kxx=(1e6, 3e6), kyy=(1e6, 3e6), speed_rpm=(0.0, 2000.0)),
            Bearing(node=4, kxx=2e6, kyy=2e6),
        ),
    )
    const = Rotor(**base, bearing=(Bearing(node=0, kxx=2e6, kyy=2e6), Bearing(node=4, kxx=2e6, kyy=2e6)))
    w = 1000 * np.pi / 30  # the middle of the table: k = 2e6
    assert np.allclose(tab.KC(w)[0], const.KC(w)[0])
    with pytest.raises(InputError) as e:
        tab.KC(2500 * np.pi / 30)
    # the argument the caller must change, and every table concerned with its range (issue 38)
    assert e.value.field == "speed" and "bearing[0] 0..2000 rpm" in str(e.value)


def test_bearing_between_nodes_and_point_mass():
    """Two identical masses joined by a node-to-node spring: out-of-phase mode at sqrt(2 k / m)."""
    m, k = 2.0, 5e5
    r = Rotor(
        shaft=(
            Shaft(outer_diameter=0.01, length=0.1, elements=1, rho=1e-6),
            Shaft(outer_diameter=0.01, length=0.1, elements=1, rho=1e-6, E=1e3, G=4e2),
        ),
        point_mass=(PointMass(node=0, mass=m), PointMass(node=2, mass=m)),
        disk=(
            Disk(node=1, mass=1e-9, Id=1e-9, Ip=0.0),
            Disk(node=0, mass=0, Id=1e-6, Ip=0),
            Disk(node=2, mass=0, Id=1e-6, Ip=0),
        ),
        bearing=(Bearing(node=0, to_node=2, kxx=k, kyy=k),),
        free=True,
    )
    w = modal(r, 0.0).wn[0]
    assert np.min(np.abs(w - np.sqrt(2 * k / m))) / np.sqrt(2 * k / m) < 1e-3


def test_cross_coupling_instability_closed_form():
    """Jeffcott with cross-coupled stiffness q (kxy = q, kyx = -q): forward whirl eigenvalue
    m s^2 + c s + k - i q = 0 (with this sign convention); unstable when q > c sqrt(k/m)."""
    m, k, c = 10.0, 1e6, 100.0
    thr = c * np.sqrt(k / m)

    def rotor(q):
        b = dict(kxx=k / 2, kyy=k / 2, kxy=q / 2, kyx=-q / 2, cxx=c / 2, cyy=c / 2)
        return Rotor(
            shaft=(Shaft(outer_diameter=0.05, length=0.2, E=2e15, G=8e14, rho=1e-6),),
            disk=(Disk(node=0, mass=m / 2, Id=1.0, Ip=0.5), Disk(node=1, mass=m / 2, Id=1.0, Ip=0.5)),
            bearing=(Bearing(node=0, **b), Bearing(node=1, **b)),
        )

    for q, stable in ((0.5 * thr, True), (2.0 * thr, False)):
        md = modal(rotor(q), 0.0)
        roots = np.roots([m, c, k - 1j * q]), np.roots([m, c, k + 1j * q])
        exact = np.concatenate(roots)
        exact = exact[exact.imag > 0]
        for s in exact:
            j = np.argmin(np.abs(md.eigenvalue[0] - s))
            assert abs(md.eigenvalue[0, j] - s) / abs(s) < 1e-6
            # the forward root is the one that loses stability
            assert (md.log_dec[0, j] > 0) == (stable or md.whirl[0, j] == "backward")
    c2 = campbell(rotor(2.0 * thr), np.linspace(0.0, 100.0, 5), 2)
    assert c2.unstable and c2.unstable[0]["speed"] == 0.0
