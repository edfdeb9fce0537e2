"""Bearing coefficient tables: interpolation (linear, pchip), extrapolation policy, the
out-of-range message, and coefficients of either sign."""

import numpy as np
import pytest
from scipy.interpolate import PchipInterpolator

from rotaflex.core.errors import InputError
from rotaflex.core.units import rpm_to_rad_s
from rotaflex.rotor.fe.case_config import parse
from rotaflex.rotor.fe.modal import modal
from rotaflex.rotor.fe.model import Bearing, Rotor, Shaft

RPM = np.pi / 30
SPEEDS = (0.0, 1500.0, 2000.0, 4000.0, 4500.0, 8000.0)  # uneven steps [rpm]
KXX = (1.0e7, 1.6e7, 1.7e7, 1.7e7, 2.6e7, 3.0e7)  # flat stretch: pchip keeps it flat
KXY = (0.0, 2.0e6, -1.0e6, -3.0e6, 4.0e6, 1.0e6)  # sign changes and local extrema
CYY = (3.0e3, 2.5e3, 2.4e3, 1.0e3, 0.9e3, 0.2e3)  # decreasing


def _rotor(**table):
    return Rotor(
        shaft=(Shaft(outer_diameter=0.05, length=1.0, elements=4),),
        bearing=(
            Bearing(node=0, kxx=KXX, kyy=KXX, kxy=KXY, cxx=CYY, cyy=CYY, speed_rpm=SPEEDS, **table),
            Bearing(node=4, kxx=2e7, kyy=2e7),
        ),
    )


def _block(rotor, speeds):
    K, C = rotor.KC(speeds)
    return K[:, :2, :2] - rotor.K_shaft[:2, :2], C[:, :2, :2]


def test_pchip_matches_scipy_pchip_interpolator():
    rotor = _rotor(interpolation="pchip")
    w = np.linspace(0.0, 8000.0, 1601) * RPM
    k, c = _block(rotor, w)
    x = np.asarray(SPEEDS) * RPM
    for got, table in ((k[:, 0, 0], KXX), (k[:, 0, 1], KXY), (c[:, 1, 1], CYY)):
        ref = PchipInterpolator(x, np.asarray(table))(w)
        assert np.max(np.abs(got - ref)) <= 1e-12 * np.max(np.abs(table))
    # monotone between monotone data: the flat stretch stays flat, no overshoot above the table
    flat = (w >= 2000 * RPM) & (w <= 4000 * RPM)
    assert np.all(k[flat, 0, 0] == pytest.approx(1.7e7, rel=1e-14)) and k[:, 0, 0].max() <= 3.0e7 * (1 + 1e-14)


def test_linear_default_is_numpys_interp_bitwise():
    """The default (linear) gives exactly what the previous np.interp code gave: results unchanged."""
    rotor = _rotor()
    w = np.concatenate([np.linspace(0.0, 8000.0, 997), SPEEDS]) * RPM
    k, _ = _block(rotor, w)
    # the table's speeds converted as the config reader converts them (rotaflex.core.units)
    assert np.array_equal(k[:, 0, 1], np.interp(w, rpm_to_rad_s(np.asarray(SPEEDS)), KXY))


@pytest.mark.parametrize("interpolation", ["linear", "pchip"])
def test_extrapolation_hold_and_linear(interpolation):
    x = np.asarray(SPEEDS) * RPM
    w = np.array([9000.0, 12000.0]) * RPM
    hold = _block(_rotor(interpolation=interpolation, extrapolation="hold"), w)[0][:, 0, 1]
    np.testing.assert_array_equal(hold, [KXY[-1]] * 2)
    line = _block(_rotor(interpolation=interpolation, extrapolation="linear"), w)[0][:, 0, 1]
    if interpolation == "linear":
        slope = (KXY[-1] - KXY[-2]) / (x[-1] - x[-2])
    else:
        slope = PchipInterpolator(x, np.asarray(KXY)).derivative()(x[-1])
    np.testing.assert_allclose(line, KXY[-1] + slope * (w - x[-1]), rtol=1e-12)


def _config(analysis, table):
    tab = {"speed_rpm": [1000, 3000], "kxx": [1e7, 2e7], "kyy": [1e7, 2e7]}
    return {
        "shaft": [{"outer_diameter": 0.05, "length": 1.0, "elements": 4}],
        "bearing": {
            "left": {"node": 0, **tab},
            "middle": {"node": 2, "kxx": 1e5, "kyy": 1e5},
            "right": {"node": 4, **tab, "speed_rpm": [500, 2500]},
        },
        analysis: table,
    }


@pytest.mark.parametrize(
    "analysis, table",
    [
        ("campbell", {"speed_rpm": [0, 5000]}),
        ("unbalance", {"speed_rpm": [1200, 5000], "mass": [{"node": 2, "magnitude": 1e-4}]}),
        ("modal", {"speed_rpm": [600, 2000, 4000]}),
        ("frf", {"speed_rpm": 4000}),
    ],
)
def test_out_of_range_names_the_analysis_key_and_every_table(analysis, table):
    with pytest.raises(InputError) as e:
        parse(_config(analysis, table), analysis)
    assert e.value.field == f"{analysis}.speed_rpm"
    text = str(e.value)
    assert "bearing.left 1000..3000 rpm" in text and "bearing.right 500..2500 rpm" in text
    assert "middle" not in text  # constant: no table
    assert 'extrapolation = "hold"' in text


def test_hold_extrapolation_lets_the_analysis_run():
    cfg = _config("campbell", {"speed_rpm": [0, 5000]})
    for name in ("left", "right"):
        cfg["bearing"][name]["extrapolation"] = "hold"
    rotor, _ = parse(cfg, "campbell")
    K = rotor.KC(5000 * RPM)[0][0] - rotor.K_shaft
    assert K[0, 0] == 2e7 and K[16, 16] == 2e7  # both tables held at their last value


def test_negative_direct_coefficients_accepted_and_instability_reported():
    base = dict(shaft=(Shaft(outer_diameter=0.05, length=1.0, elements=4),))
    supports = (Bearing(node=0, kxx=2e7, kyy=2e7), Bearing(node=4, kxx=2e7, kyy=2e7))
    plain = Rotor(**base, bearing=supports)
    # a seal of negative direct stiffness: adding a negative semi-definite stiffness to a
    # non-rotating undamped system lowers no natural frequency (Rayleigh quotient), strictly
    # those of the modes that move node 2 (the first pair; the second pair has a node there)
    seal = Rotor(**base, bearing=(*supports, Bearing(node=2, kxx=-5e5, kyy=-5e5)))
    w0, w1 = modal(plain, 0.0, 4).wn[0], modal(seal, 0.0, 4).wn[0]
    assert np.all(w1 <= w0 * (1 + 1e-12)) and np.all(w1[:2] < w0[:2])
    # negative direct damping: the modal damping phi^T C phi of the modes that move node 2 is
    # negative, so those modes grow and are reported unstable; positive damping: stable
    neg = modal(Rotor(**base, bearing=(*supports, Bearing(node=2, cxx=-50.0, cyy=-50.0))), 0.0, 4)
    pos = modal(Rotor(**base, bearing=(*supports, Bearing(node=2, cxx=50.0, cyy=50.0))), 0.0, 4)
    assert neg.unstable[0, :2].all() and not pos.unstable.any()
    np.testing.assert_allclose(neg.log_dec[0, :2], -pos.log_dec[0, :2], rtol=1e-3)
