"""ISO 6336-1 method B K_v against the standard's formulas evaluated by hand in its own units
(N/mm, um, kg/mm, min^-1); no published worked example is used."""

import math

import numpy as np
import pytest

from rotaflex.core.errors import InputError
from rotaflex.gear.static.iso6336_kv import IsoKvInput, cv_coefficients, iso_kv, reduced_mass_per_width

# c' = 14, c_gamma_alpha = 20 N/(mm um); m_red = 0.01 kg/mm; K_A F_t/b = 200 N/mm;
# f_pb,eff = 10 um, f_f,eff = 8 um, no relief; z1 = 28, eps = 1.6
INP = IsoKvInput(
    z1=28,
    c_single=14e9,
    c_gamma_alpha=20e9,
    m_red=10.0,
    load_per_width=2e5,
    eps_gamma=1.6,
    f_pb_eff=10e-6,
    f_f_eff=8e-6,
)


def test_resonance_speed_in_the_standards_units():
    n_e1 = 30000.0 / (math.pi * 28) * math.sqrt(20.0 / 0.01)  # min^-1
    assert INP.resonance_speed_rpm == pytest.approx(n_e1, rel=1e-12)


def test_kv_in_each_range_by_hand():
    omega_e1 = INP.resonance_speed  # rad/s
    # B_p = 14*10/200 = 0.7, B_f = 14*8/200 = 0.56, B_k = 1; N_S = 0.85 (200 N/mm >= 100)
    k = 0.32 * 0.7 + 0.34 * 0.56 + 0.23 * 1.0  # = 0.6444
    kv_main = 0.32 * 0.7 + 0.34 * 0.56 + 0.90 + 1.0  # = 2.3144
    cv7 = 0.125 * math.sin(math.pi * (1.6 - 2.0)) + 0.875
    kv_super = 0.47 * 0.7 + 0.47 * 0.56 + cv7  # = 1.348318...
    kv_mid = kv_super + (kv_main - kv_super) / 0.35 * (1.5 - 1.325)
    ratios = np.array([0.0, 0.5, 0.85, 0.9, 1.15, 1.325, 1.5, 3.0])
    want = [1.0, 0.5 * k + 1, 0.85 * k + 1, kv_main, kv_main, kv_mid, kv_super, kv_super]
    got = iso_kv(INP, ratios * omega_e1)
    assert got == pytest.approx(want, rel=1e-12)
    assert kv_mid == pytest.approx(1.831359, abs=2e-6)  # by hand on paper


def test_light_load_limit_of_main_resonance_and_relief():
    # 50 N/mm < 100: N_S = 0.5 + 0.35 sqrt(50/100)
    inp = IsoKvInput(load_per_width=5e4, c_single=14e9, tip_relief=2e-6, f_pb_eff=5e-6)
    assert inp.n_s == pytest.approx(0.5 + 0.35 * math.sqrt(0.5), rel=1e-12)
    bp, bf, bk = inp.b_factors()
    assert (bp, bf, bk) == pytest.approx((14 * 5 / 50, 0.0, abs(1 - 14 * 2 / 50)), rel=1e-12)
    omega = (inp.n_s + 1e-3) * inp.resonance_speed
    assert iso_kv(inp, omega) == pytest.approx(0.32 * bp + 0.90 * bk + 1.0, rel=1e-12)


def test_cv_table_above_contact_ratio_two():
    cv = cv_coefficients(2.2)
    assert cv["Cv2"] == pytest.approx(0.57 / 1.9)
    assert cv["Cv3"] == pytest.approx(0.15)
    assert cv["Cv4"] == pytest.approx(0.46 / 0.76)
    assert cv["Cv6"] == pytest.approx(0.12 / 0.46)
    assert cv["Cv7"] == pytest.approx(0.125 * math.sin(0.2 * math.pi) + 0.875)
    assert cv_coefficients(1.4)["Cv7"] == 0.75 and cv_coefficients(2.7)["Cv7"] == 1.0


def test_reduced_mass_of_equal_gears():
    j, rb, b = 2.965e-4, 0.0418, 6.35e-3
    assert reduced_mass_per_width((j, j), (rb, rb), b) == pytest.approx(j / (2 * rb**2) / b)
    # a much heavier wheel: m_red -> the pinion's J1 / r_b1^2
    assert reduced_mass_per_width((j, 1e6 * j), (rb, 2 * rb), b) == pytest.approx(j / rb**2 / b, rel=1e-5)


def test_bad_input():
    with pytest.raises(InputError, match="speed"):
        iso_kv(INP, [-1.0])
    with pytest.raises(InputError, match="eps_gamma"):
        cv_coefficients(1.0)
