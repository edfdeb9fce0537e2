"""Coaxial shaft layers: sections sharing the main shaft's nodes add their stiffness and/or mass.

Equivalence by construction (two coaxial tubes vs one tube): every matrix of a Timoshenko element
of a uniform section is E I, kappa G A, rho A or rho I times a matrix that depends on the
section only through Phi = 12 E I / (kappa G A L^2) (the shape functions). Choose each tube's
shear coefficient as kappa_i = c I_i / A_i with one constant c: then every tube, and the merged
tube with A = A1 + A2, I = I1 + I2 and kappa = c I / A, has the same Phi = 12 E / (c G L^2),
so the merged matrices are exactly the sums of the layers' (to round-off).
"""

import numpy as np
import pytest

from rotaflex.core.errors import InputError
from rotaflex.rotor.fe.modal import modal
from rotaflex.rotor.fe.model import Bearing, Disk, Rotor, Shaft

D0, D1, D2 = 0.02, 0.05, 0.08  # bore, core outer = sleeve inner, sleeve outer [m]
C = 0.8 * (np.pi / 4 * (D2**2 - D0**2)) / (np.pi / 64 * (D2**4 - D0**4))  # merged tube: kappa = 0.8


def _kappa(di, do):
    """kappa = C I / A of a tube (the construction above)."""
    return C * (np.pi / 64 * (do**4 - di**4)) / (np.pi / 4 * (do**2 - di**2))


BEARINGS = (Bearing(node=0, kxx=2e7, kyy=3e7, cxx=500.0, cyy=500.0), Bearing(node=12, kxx=2e7, kyy=3e7))
DISK = (Disk(node=6, mass=20.0, Id=0.2, Ip=0.35),)


def _core(lo, hi, n, **kw):
    return Shaft(outer_diameter=D1, inner_diameter=D0, start=lo, end=hi, elements=n, **kw)


def _layered(**sleeve):
    """Core tube in three sections, a sleeve layer on the middle one (0.3 .. 0.9 m, nodes 3 .. 9)."""
    return Rotor(
        shaft=(
            _core(0.0, 0.3, 3, shear_coefficient=0.7),
            _core(0.3, 0.9, 6, shear_coefficient=_kappa(D0, D1)),
            _core(0.9, 1.2, 3, shear_coefficient=0.7),
            Shaft(
                outer_diameter=D2,
                inner_diameter=D1,
                start=0.3,
                end=0.9,
                layer="sleeve",
                shear_coefficient=_kappa(D1, D2),
                **sleeve,
            ),
        ),
        disk=DISK,
        bearing=BEARINGS,
    )


def _merged():
    """The same rotor merged by hand: the middle section one tube D0 .. D2."""
    return Rotor(
        shaft=(
            _core(0.0, 0.3, 3, shear_coefficient=0.7),
            Shaft(outer_diameter=D2, inner_diameter=D0, start=0.3, end=0.9, elements=6, shear_coefficient=0.8),
            _core(0.9, 1.2, 3, shear_coefficient=0.7),
        ),
        disk=DISK,
        bearing=BEARINGS,
    )


def _rel(a, b):
    return np.max(np.abs(a - b)) / np.max(np.abs(b))


def test_two_coaxial_tubes_equal_one_merged_tube():
    lay, ref = _layered(), _merged()
    assert lay.n_dof == ref.n_dof == 52
    for name in ("M", "K_shaft", "G", "Kst"):
        assert _rel(getattr(lay, name), getattr(ref, name)) < 1e-12, name
    w = 5000 * np.pi / 30
    for a, b in zip(lay.KC(w), ref.KC(w), strict=True):
        assert _rel(a, b) < 1e-12
    m1, m2 = modal(lay, w, 8), modal(ref, w, 8)
    np.testing.assert_allclose(m1.eigenvalue, m2.eigenvalue, rtol=1e-11)


def test_mass_only_and_stiffness_only_layers():
    core = Rotor(
        shaft=(
            _core(0.0, 0.3, 3, shear_coefficient=0.7),
            _core(0.3, 0.9, 6, shear_coefficient=_kappa(D0, D1)),
            _core(0.9, 1.2, 3, shear_coefficient=0.7),
        ),
        disk=DISK,
        bearing=BEARINGS,
    )
    full, mass_only, stiff_only = _layered(), _layered(stiffness=False), _layered(mass=False)
    # a mass-only layer leaves the stiffness of the core alone (bitwise) and adds all its inertia
    assert np.array_equal(mass_only.K_shaft, core.K_shaft)
    assert np.array_equal(mass_only.M, full.M) and np.array_equal(mass_only.G, full.G)
    rho = 7810.0  # steel (materials.py)
    sleeve = rho * np.pi / 4 * (D2**2 - D1**2) * 0.6
    assert mass_only.mass - core.mass == pytest.approx(sleeve, rel=1e-13)
    # tilt inertia about z = 0: the element's shape functions hold rigid motions exactly, so
    # R^T M R = int rho A z^2 dz + int rho I dz over the sleeve (0.3 .. 0.9 m)
    R = np.zeros(core.n_dof)
    R[0::4], R[3::4] = core.nodes, 1.0  # x = z theta_y
    area, inertia = np.pi / 4 * (D2**2 - D1**2), np.pi / 64 * (D2**4 - D1**4)
    tilt = rho * area * (0.9**3 - 0.3**3) / 3 + rho * inertia * 0.6
    assert R @ (mass_only.M - core.M) @ R == pytest.approx(tilt, rel=1e-12)
    # a stiffness-only layer leaves the inertia alone and adds all its stiffness
    assert (
        np.array_equal(stiff_only.M, core.M)
        and np.array_equal(stiff_only.G, core.G)
        and np.array_equal(stiff_only.K_shaft, full.K_shaft)
    )
    # the added mass lowers and the added stiffness raises the first forward frequency
    f = [modal(r, 0.0, 1).wn[0, 0] for r in (core, mass_only, stiff_only)]
    assert f[1] < f[0] < f[2]


def test_layer_from_toml_tables():
    data = {
        "shaft": [
            {"outer_diameter": D1, "length": 0.6, "elements": 6},
            {
                "outer_diameter": 0.12,
                "inner_diameter": D1,
                "start": 0.2,
                "end": 0.4,
                "layer": "impeller",
                "stiffness": False,
            },
        ],
        "bearing": {"left": {"node": 0, "kxx": 1e7, "kyy": 1e7}, "right": {"node": 6, "kxx": 1e7, "kyy": 1e7}},
    }
    r = Rotor.from_mapping(data)
    assert r.n_nodes == 7 and list(r.layer_elements["index"]) == [2, 3]


@pytest.mark.parametrize(
    "layer, field",
    [
        ({"start": 0.25, "end": 0.4}, "shaft[1].start"),  # not a node
        ({"start": 0.2, "end": 0.45}, "shaft[1].end"),
        ({"end": 0.4}, "shaft[1].start"),  # a layer does not chain after the previous section
        ({"start": 0.2, "end": 0.4, "elements": 3}, "shaft[1].elements"),  # spans 2 main elements
        ({"start": 0.2, "end": 0.4, "rigid": True}, "shaft[1].rigid"),
    ],
)
def test_layer_bad_input_names_the_key(layer, field):
    with pytest.raises(InputError) as e:
        Rotor(
            shaft=(
                Shaft(outer_diameter=D1, length=0.6, elements=6),
                Shaft(outer_diameter=0.1, inner_diameter=D1, layer="hub", **layer),
            ),
            bearing=(Bearing(node=0, kxx=1e7, kyy=1e7), Bearing(node=6, kxx=1e7, kyy=1e7)),
        )
    assert e.value.field == field


def test_static_diagrams_carry_the_layers_weight():
    """Equilibrium: the bearings carry the whole weight (layers included), and at the right end
    (a bearing at the last node) the shear equals that reaction and the moment closes to zero
    once the layers' distributed weight is in the diagrams."""
    from rotaflex.rotor.fe.static import static_analysis

    rotor = _layered(stiffness=False)
    s = static_analysis(rotor)
    weight = rotor.mass * 9.80665
    assert s.reactions[:, 1].sum() == pytest.approx(weight, rel=1e-12)
    assert np.max(np.abs(s.shear[-1] + s.reactions[1])) < 1e-9 * weight
    assert np.max(np.abs(s.moment[-1])) < 1e-9 * weight
    assert s.load_total[1] == pytest.approx(-weight, rel=1e-12)  # the applied load: every layer's weight
