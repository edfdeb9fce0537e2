"""Invariants of the assembled matrices over random rotors (hypothesis)."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from rotaflex.rotor.fe import Bearing, Disk, Rotor, Shaft, modal

sections = st.lists(
    st.tuples(st.floats(0.02, 0.12), st.floats(0.0, 0.8), st.floats(0.6, 1.4), st.floats(0.05, 0.6), st.integers(1, 3)),
    min_size=1,
    max_size=3,
)


def _rotor(secs, free=False, k=0.0):
    shafts = tuple(
        Shaft(
            outer_diameter=d,
            inner_diameter=d * r * 0.9,
            outer_diameter_right=d * t,
            inner_diameter_right=d * t * r * 0.9,
            length=L,
            elements=n,
        )
        for d, r, t, L, n in secs
    )
    rotor = Rotor(shaft=shafts, free=True)
    if free:
        return rotor
    n = rotor.n_nodes - 1
    return Rotor(
        shaft=shafts,
        disk=(Disk(node=n // 2, mass=3.0, Id=0.02, Ip=0.035),),
        bearing=(Bearing(node=0, kxx=k, kyy=1.3 * k), Bearing(node=n, kxx=k, kyy=k)),
    )


@settings(max_examples=15, deadline=None)
@given(sections)
def test_free_shaft_matrices(secs):
    r = _rotor(secs, free=True)
    M, G, K = r.M, r.G, r.K_shaft
    assert np.allclose(M, M.T, rtol=0, atol=1e-12 * np.abs(M).max())
    assert np.allclose(G, -G.T, rtol=0, atol=1e-12 * np.abs(G).max())
    assert np.min(np.linalg.eigvalsh(M)) > 0
    ev = np.linalg.eigvalsh(K)
    # exactly the four lateral rigid-body modes (two translations, two tilts) have zero strain energy
    assert np.sum(np.abs(ev) < 1e-9 * ev.max()) == 4


@settings(max_examples=10, deadline=None)
@given(sections, st.floats(1e5, 1e8), st.floats(0.0, 2000.0))
def test_undamped_gyroscopic_modes_are_neutral(secs, k, speed):
    """No damping, symmetric stiffness: a conservative gyroscopic system, so every eigenvalue is
    imaginary (log dec 0) and each mode's whirl fraction lies in [0, 1]."""
    md = modal(_rotor(secs, k=k), speed, 8)
    assert np.all(np.abs(md.log_dec) < 1e-6)
    assert np.all((md.forward_fraction >= 0) & (md.forward_fraction <= 1))
