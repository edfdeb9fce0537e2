"""Pedestal supports: a mass on springs and dampers to ground between a bearing and ground.

Two-mass closed form: a rigid symmetric rotor (mass m1) on two identical bearings (k1, c1 each)
on two identical pedestals (m2, k2, c2 each). Its bounce motion (rotor translation, both
pedestals in phase) is the two-mass chain with M = diag(m1, 2 m2), C and K of the springs
2 k1 (rotor-pedestals) and 2 k2 (pedestals-ground), in each direction; the eigenvalues s are
the roots of the quartic (m1 s^2 + 2 c1 s + 2 k1)(2 m2 s^2 + 2 (c1 + c2) s + 2 (k1 + k2))
- (2 c1 s + 2 k1)^2 = 0.
"""

import numpy as np
import pytest

from rotaflex.core.errors import InputError
from rotaflex.rotor.fe.case_config import parse
from rotaflex.rotor.fe.modal import modal
from rotaflex.rotor.fe.model import Bearing, Pedestal, Rotor, Shaft

K1, C1 = 2e7, 3e3
PED = {"x": (40.0, 5e7, 2e3), "y": (40.0, 8e7, 1e3)}  # mass, stiffness, damping per direction


def _rotor():
    ped = Pedestal(mass=40.0, kxx=5e7, kyy=8e7, cxx=2e3, cyy=1e3)
    return Rotor(
        shaft=(Shaft(outer_diameter=0.1, length=0.8, elements=4, rigid=True),),
        bearing=(
            Bearing(node=0, kxx=K1, kyy=K1, cxx=C1, cyy=C1, pedestal=ped),
            Bearing(node=4, kxx=K1, kyy=K1, cxx=C1, cyy=C1, pedestal=ped),
        ),
    )


def _quartic(m1, m2, k1, c1, k2, c2):
    a = np.polymul([m1, 2 * c1, 2 * k1], [2 * m2, 2 * (c1 + c2), 2 * (k1 + k2)])
    b = np.polymul([2 * c1, 2 * k1], [2 * c1, 2 * k1])
    s = np.roots(np.polysub(a, b))
    return np.sort_complex(s[s.imag > 0])


def test_two_mass_closed_form():
    rotor = _rotor()
    assert rotor.n_dof == 4 * 5 + 4 and rotor.n_rotor_dof == 20
    m1 = rotor.mass
    assert m1 == pytest.approx(7810 * np.pi / 4 * 0.1**2 * 0.8, rel=1e-12)  # pedestals not in it
    lam = modal(rotor, 0.0, 8).eigenvalue[0]
    for d, (m2, k2, c2) in PED.items():
        for ref in _quartic(m1, m2, K1, C1, k2, c2):
            err = np.min(np.abs(lam - ref)) / abs(ref)
            assert err < 1e-6, (d, ref, err)  # the rigid section: a stiffness penalty (errors 1e-8..3e-7)


def test_pedestal_dofs_and_matrices():
    rotor = _rotor()
    K, C = rotor.KC(1000.0)
    p = slice(20, 24)  # x, y of pedestal 0, then of pedestal 1
    np.testing.assert_array_equal(np.diag(rotor.M)[p], [40.0] * 4)
    np.testing.assert_array_equal(np.diag(K[0])[p], [K1 + 5e7, K1 + 8e7] * 2)
    np.testing.assert_array_equal(np.diag(C[0])[p], [C1 + 2e3, C1 + 1e3] * 2)
    assert K[0][0, 20] == -K1 and K[0][16, 22] == -K1 and K[0][0, 22] == 0  # bearing 1 on pedestal 1
    m = modal(rotor, 0.0, 6)
    assert m.shape.shape[-1] == 24 and set(m.whirl[0]) <= {"forward", "backward", "mixed"}


def test_pedestal_from_toml_and_bad_input():
    base = {
        "shaft": [{"outer_diameter": 0.05, "length": 1.0, "elements": 4}],
        "bearing": {
            "left": {"node": 0, "kxx": 1e7, "kyy": 1e7, "pedestal": {"mass": 30.0, "kxx": 1e8, "kyy": 1e8}},
            "right": {"node": 4, "kxx": 1e7, "kyy": 1e7},
        },
        "modal": {"speed_rpm": 1000},
    }
    rotor, _ = parse(base, "modal")
    assert rotor.n_dof == 22 and rotor.pedestals[0][0] == 0
    bad = {**base, "bearing": {**base["bearing"], "left": {**base["bearing"]["left"], "pedestal": {"kxx": 1e8}}}}
    with pytest.raises(InputError) as e:
        parse(bad, "modal")
    assert e.value.field == "bearing.left.pedestal.mass"
    # a pedestal held by nothing (no stiffness to ground): the rotor is not supported
    free = {**base, "bearing": {**base["bearing"], "left": {**base["bearing"]["left"], "pedestal": {"mass": 30.0}}}}
    with pytest.raises(InputError) as e:
        parse(free, "modal")
    assert e.value.field == "free"


def test_example_impeller_stack_runs(tmp_path):
    """The example of layers, Rayleigh damping and pedestals: its modal command runs, at the
    speeds of its [modal] table, with its 11 nodes and 2 pedestals."""
    from pathlib import Path

    from typer.testing import CliRunner

    from rotaflex.cli import app
    from rotaflex.core.result import load_result

    example = Path(__file__).resolve().parents[3] / "examples" / "rotor" / "impeller_stack_pedestal.toml"
    assert "rotaflex rotor modal examples/rotor/impeller_stack_pedestal.toml" in example.read_text()
    res = CliRunner().invoke(app, ["rotor", "modal", str(example), "--out", str(tmp_path), "-q", "--no-figures"])
    assert res.exit_code == 0, res.output
    ds = load_result(tmp_path / "result.nc").dataset
    assert list(ds["speed_rpm"].values) == [0, 6000, 9500] and ds.sizes["node"] == 11
    assert np.all(ds["log_dec"].values > 0)  # Rayleigh and bearing damping: every mode decays
