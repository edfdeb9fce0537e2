"""Gas labyrinth seal: leakage, zero cross-coupling without swirl, the linearised coefficients against a
nonlinear solution of the same bulk-flow equations on a circumferential grid, bad input."""

import numpy as np
import pytest
from scipy.optimize import root

from rotaflex.core.errors import InputError
from rotaflex.rotor.fe.bearings.labyrinth import Labyrinth, LabyrinthElement, element, tooth_flow
from rotaflex.rotor.fe.model import Rotor

# the see-through seal geometry of Childs & Scharrer's test rig (R = 75.5 mm, 3.175 mm pitch and depth)
SEAL = dict(
    teeth=8,
    pitch=3.175e-3,
    tooth_height=3.175e-3,
    tooth_width=0.15e-3,
    clearance=0.1e-3,
    radius=0.0755,
    inlet_pressure=7e5,
    outlet_pressure=1e5,
    inlet_temperature=300.0,
)


def test_no_speed_no_preswirl_no_cross_coupling():
    el = element(Labyrinth(**SEAL, preswirl=0.0), "lab")
    K, C = el.coefficients(np.array([0.0]), np.array([200.0]))
    assert K[0, 0, 1] == 0.0 and C[0, 0, 1] == 0.0
    assert C[0, 0, 0] > 0  # the cavities' squeeze still damps
    # with speed, cross-coupling appears and grows with the inlet swirl
    ks = [element(Labyrinth(**SEAL, preswirl=p), "lab").coefficients([1000.0])[0][0, 0, 1] for p in (-0.3, 0, 0.5)]
    assert ks[0] < ks[1] < ks[2] and ks[2] > 0


def test_single_tooth_leakage_is_the_isentropic_orifice():
    """Neumann's tooth flow = the isentropic orifice with C_d = mu_1 as the pressure drop vanishes, and
    mu_1 -> pi / (pi + 2), Kirchhoff's free-streamline contraction of a slot. Expanding both in
    delta = 1 - P_d / P_u (sympy): Neumann / orifice = 1 + (3 / gamma - 1) delta / 4 + O(delta^2), so
    Neumann's formula leaks 0.29 % more at P_d/P_u = 0.99 and 3.1 % more at 0.9 (measured) for air."""
    rt, g, cr = 287.0 * 300.0, 1.4, 1e-4

    def orifice(pu, pd, cd):
        r = pd / pu
        return cd * cr * pu * np.sqrt(2 * g / ((g - 1) * rt) * (r ** (2 / g) - r ** ((g + 1) / g)))

    pu = 5e5
    for r in (0.9999, 0.999, 0.99):
        pd = r * pu
        s = (pu / pd) ** ((g - 1) / g) - 1
        mu1 = np.pi / (np.pi + 2 - 5 * s + 2 * s**2)
        excess = tooth_flow(pu, pd, cr, rt, g) / orifice(pu, pd, mu1) - 1
        assert excess == pytest.approx((3 / g - 1) * (1 - r) / 4, rel=20 * (1 - r))
    pd = pu * (1 - 1e-9)
    assert tooth_flow(pu, pd, cr, rt, g) == pytest.approx(orifice(pu, pd, np.pi / (np.pi + 2)), rel=1e-6)


def test_leakage_passes_every_tooth_and_meets_the_outlet():
    """7 -> 3 bar: the same flow through every tooth, the last cavity meets the outlet; 7 -> 1 bar: the last
    tooth chokes at the critical ratio 0.528 and the last cavity stays above the outlet (reported)."""
    el = element(Labyrinth(**{**SEAL, "outlet_pressure": 3e5}), "lab")
    m, p, choked = el.leak
    assert not choked and p[0] == 7e5 and p[-1] == pytest.approx(3e5, rel=1e-9)
    flows = [tooth_flow(p[k], p[k + 1], 1e-4, el.rt, 1.4, el.mu2[k]) for k in range(8)]
    np.testing.assert_allclose(flows, m, rtol=1e-9)
    m, p, choked = element(Labyrinth(**SEAL), "lab").leak
    assert choked and p[-1] / p[-2] == pytest.approx((2 / 2.4) ** 3.5, rel=1e-9) and p[-1] > 1e5


def _nonlinear_force(el: LabyrinthElement, speed: float, ecc: float, n_theta: int, whirl: float = 0.0):
    """Force [N] on the rotor at (ecc, 0) on a circular orbit of radius ``ecc`` whirling at ``whirl``
    [rad/s]: the bulk-flow equations of every cavity solved without linearisation on a periodic grid of
    ``n_theta`` points (spectral d/dtheta), steady in the frame turning with the orbit (d/dt = -W d/dtheta)."""
    sp, z = el.spec, el.zeroth(speed)
    nc, R, L = el.nc, sp.radius, el.L
    th = 2 * np.pi * np.arange(n_theta) / n_theta
    k = np.fft.fftfreq(n_theta, 1.0 / n_theta)
    k[n_theta // 2] = 0 if n_theta % 2 == 0 else k[n_theta // 2]

    def ddt(f):
        return np.fft.ifft(1j * k * np.fft.fft(f, axis=-1), axis=-1).real

    H = sp.clearance - ecc * np.cos(th)
    depth = sp.tooth_height + H
    A, dh = depth * L, 2 * depth * L / (depth + L)
    n0, m0 = 0.079, -0.25

    def tau(rho, u):
        return 0.5 * n0 * rho * np.abs(u) * u * (rho * np.abs(u) * dh / el.mu) ** m0

    def residual(x):
        P = np.vstack(
            [
                np.full(n_theta, sp.inlet_pressure),
                x[: nc * n_theta].reshape(nc, n_theta),
                np.full(n_theta, sp.outlet_pressure),
            ]
        )
        V = np.vstack([np.full(n_theta, z.v[0]), x[nc * n_theta :].reshape(nc, n_theta)])
        mdot = np.array([tooth_flow(P[j], P[j + 1], H, el.rt, el.gamma, el.mu2[j]) for j in range(sp.teeth)])
        res = []
        for i in range(1, nc + 1):
            rho = P[i] / el.rt
            res.append((-whirl * ddt(rho * A) + ddt(rho * A * V[i]) / R + mdot[i] - mdot[i - 1]) / z.m)
        for i in range(1, nc + 1):
            rho = P[i] / el.rt
            mom = rho * A * (V[i] / R - whirl) * ddt(V[i]) + mdot[i - 1] * (V[i] - V[i - 1]) + A / R * ddt(P[i])
            mom -= L * (el.a_r * tau(rho, R * speed - V[i]) - el.a_s * tau(rho, V[i]))
            res.append(mom / (z.m * R * max(speed, 1.0)))
        return np.concatenate(res)

    x0 = np.concatenate([np.repeat(z.p[1:-1], n_theta), np.repeat(z.v[1:], n_theta)])
    sol = root(residual, x0, method="hybr", options={"xtol": 1e-13})
    assert sol.success, sol.message
    P = sol.x[: nc * n_theta].reshape(nc, n_theta)
    w = 2 * np.pi / n_theta
    return -R * L * w * np.sum(P * np.cos(th)), -R * L * w * np.sum(P * np.sin(th))


@pytest.mark.parametrize("preswirl", [0.0, 0.5])
def test_static_coefficients_match_the_nonlinear_solution(preswirl):
    """K(0) and k(0) of the perturbation solution = -F_x / e and F_y / e of the nonlinear bulk-flow
    equations solved on a circumferential grid with e = 1e-3 Cr: 8 and 16 grid points give the same force
    (the response is one harmonic) and the finite eccentricity costs ~1e-7 (measured)."""
    el = element(Labyrinth(**SEAL, preswirl=preswirl), "lab")
    speed = 1000.0
    K, _ = el.coefficients(np.array([speed]), np.array([1e-9]))
    ecc = 1e-3 * SEAL["clearance"]
    forces = [_nonlinear_force(el, speed, ecc, n) for n in (8, 16)]
    for fx, fy in forces:
        assert -fx / ecc == pytest.approx(K[0, 0, 0], rel=1e-5, abs=1e-5 * abs(K[0, 0, 1]))
        assert fy / ecc == pytest.approx(K[0, 0, 1], rel=1e-5)
    assert forces[0][1] == pytest.approx(forces[1][1], rel=1e-8)


@pytest.mark.parametrize(
    "change, key",
    [
        ({"clearance": 0.0}, "clearance"),
        ({"clearance": -1e-4}, "clearance"),
        ({"outlet_pressure": 7e5}, "outlet_pressure"),
        ({"outlet_pressure": 8e5}, "outlet_pressure"),
        ({"teeth": 1}, "teeth"),
        ({"leakage": "martin"}, "leakage"),
    ],
)
def test_bad_seal_input_names_the_key(change, key):
    data = {
        "shaft": [{"outer_diameter": 0.151, "length": 0.6, "elements": 4}],
        "bearing": {
            "de": {"node": 0, "kxx": 1e8, "kyy": 1e8},
            "nde": {"node": 4, "kxx": 1e8, "kyy": 1e8},
            "inlet": {"node": 2, "labyrinth": {**SEAL, **change}},
        },
    }
    with pytest.raises(InputError) as err:
        Rotor.from_mapping(data)
    assert err.value.field == f"bearing.inlet.labyrinth.{key}"


@pytest.mark.parametrize("whirl", [400.0, 1500.0])
def test_whirling_coefficients_match_the_nonlinear_solution(whirl):
    """K, k, C, c at a whirl frequency: the forces of forward (W) and backward (-W) circular orbits of the
    nonlinear equations (steady in the whirling frame) give K + W c = -F_x / e and W C - k = -F_y / e."""
    el = element(Labyrinth(**SEAL, preswirl=0.5), "lab")
    speed, ecc = 1000.0, 1e-3 * SEAL["clearance"]
    K, C = el.coefficients(np.array([speed]), np.array([whirl]))
    kd, kc, cd, cc = K[0, 0, 0], K[0, 0, 1], C[0, 0, 0], C[0, 0, 1]
    for w in (whirl, -whirl):
        fx, fy = _nonlinear_force(el, speed, ecc, 8, w)
        assert -fx / ecc == pytest.approx(kd + w * cc, rel=1e-5)
        assert -fy / ecc == pytest.approx(w * cd - kc, rel=1e-5)


def test_choked_seal_leaks_in_proportion_to_the_inlet_pressure():
    """Two teeth, 50 and 100 bar to 1 bar: the last tooth sits at the critical pressure ratio
    (2 / (gamma + 1))^(gamma / (gamma - 1)) = 0.528 and, every tooth flow being homogeneous of degree one
    in the pressures, the leakage doubles with the inlet pressure."""
    base = dict(teeth=2, pitch=3e-3, tooth_height=3e-3, clearance=0.2e-3, radius=0.05, inlet_temperature=300.0)
    els = [element(Labyrinth(**base, inlet_pressure=p, outlet_pressure=1e5), "lab") for p in (50e5, 100e5)]
    (m1, p1, c1), (m2, _, c2) = els[0].leak, els[1].leak
    assert c1 and c2
    assert p1[2] / p1[1] == pytest.approx((2 / 2.4) ** 3.5, rel=1e-9)
    assert m2 / m1 == pytest.approx(2.0, rel=1e-9)
    assert not element(Labyrinth(**base, inlet_pressure=1.5e5, outlet_pressure=1e5), "lab").leak[2]
    K, C = els[0].coefficients([1000.0])
    assert np.all(np.isfinite(K)) and np.all(np.isfinite(C))


@pytest.mark.parametrize(
    "change, key",
    [
        ({"sutherland_constant": -100.0}, "sutherland_constant"),  # T + S changes sign between 0 and T_in
        ({"choking": "laby3"}, "choking"),  # LABY3's choking is a property of its (vermes) tooth law
        ({"cavity_length": "land"}, "cavity_length"),
        ({"cavity_temperature": "adiabatic"}, "cavity_temperature"),
    ],
)
def test_bad_laby3_option_names_the_key(change, key):
    data = {
        "shaft": [{"outer_diameter": 0.151, "length": 0.6, "elements": 4}],
        "bearing": {
            "de": {"node": 0, "kxx": 1e8, "kyy": 1e8},
            "nde": {"node": 4, "kxx": 1e8, "kyy": 1e8},
            "inlet": {"node": 2, "labyrinth": {**SEAL, **change}},
        },
    }
    with pytest.raises(InputError) as err:
        Rotor.from_mapping(data)
    assert err.value.field == f"bearing.inlet.labyrinth.{key}"


def test_isentropic_cavities_cool_and_sutherland_follows():
    """``cavity_temperature = "isentropic"``: every cavity at T_{k-1} (P_k / P_{k-1})^((gamma-1)/gamma), so
    T_k / T_0 = (P_k / P_0)^((gamma-1)/gamma) along the seal (1e-12); the viscosity then follows
    Sutherland's law at each cavity's temperature: for air through 1.716e-5 Pa s at 273.15 K with
    S = 110.4 K, the U.S. Standard Atmosphere 1976 form 1.458e-6 T^1.5 / (T + 110.4) [Pa s]."""
    spec = {**SEAL, "outlet_pressure": 3e5, "inlet_temperature": 273.15}
    el = element(Labyrinth(**spec, cavity_temperature="isentropic", sutherland_constant=110.4, viscosity=1.716e-5), "l")
    t, p = el.temperature, el.leak[1]
    np.testing.assert_allclose(t / 273.15, (p / 7e5) ** (0.4 / 1.4), rtol=1e-12)
    assert t[-2] < 250.0
    np.testing.assert_allclose(el.viscosity(t), 1.458e-6 * t**1.5 / (t + 110.4), rtol=2e-4)
    out = el.outputs(np.array([1000.0]))
    np.testing.assert_allclose(out["cavity_temperature"].values, t[1:-1])
