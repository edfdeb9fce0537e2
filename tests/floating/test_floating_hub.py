"""Hub + appendage bodies, rest-to-rest slews and modal damping against closed forms.

Hub-beam frequency equation (derived here, not taken from the code). A rigid hub of mass m_h and
inertia I_h (about its centre) carries a uniform Euler-Bernoulli beam (EI, rho A, length L)
clamped at radius r; planar motion, small amplitude. With Y(x, t) the absolute transverse
displacement of the beam at distance x from its root, hub translation y_h and rotation theta:

    T = 1/2 m_h y_h'^2 + 1/2 I_h theta'^2 + 1/2 int rho A Y'^2 dx,   U = 1/2 int EI Y''^2 dx,
    Y(0) = y_h + r theta,  dY/dx(0) = theta.

Hamilton's principle gives the beam equation EI Y'''' + rho A Y.. = 0, a free tip
(Y''(L) = Y'''(L) = 0) and, from the boundary terms at the root,

    m_h y_h..  + EI Y'''(0) = 0,
    I_h theta.. - EI Y''(0) + r EI Y'''(0) = 0.

With Y = (a1 cos bx + a2 sin bx + a3 cosh bx + a4 sinh bx) e^{i w t}, w^2 = b^4 EI / (rho A),
the six conditions are linear in (a1..a4, y_h, theta); their determinant vanishes at the
unconstrained (free-hub) frequencies. A hub that cannot translate (m_h -> inf, y_h = 0) gives
the classic hub-beam equation; the constrained frequencies (hub held) are the cantilever's,
cos bL cosh bL = -1.
"""

import json
import tomllib
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

from rotaflex.core.errors import InputError
from rotaflex.floating.body import rigid_body, with_damping
from rotaflex.floating.hub import beam_appendage, free_frequencies, hub_body, slew_torque
from rotaflex.floating.model import Initial, Prescribed, Settings
from rotaflex.floating.solve import simulate

E, RHO, W, T_, L = 70e9, 2700.0, 0.1, 0.005, 2.0
EI, RA = E * W * T_**3 / 12.0, RHO * W * T_
EXAMPLE = Path(__file__).parents[2] / "examples" / "floating" / "hub_appendage_slew.toml"


def _hub_beam_matrix(b, m_h, i_h, r):
    """Rows of the six root/tip/hub conditions in (a1, a2, a3, a4, y_h, theta)."""
    w2 = b**4 * EI / RA
    c, s, ch, sh = np.cos(b * L), np.sin(b * L), np.cosh(b * L), np.sinh(b * L)
    d0 = [np.array([1.0, 0, 1, 0]), b * np.array([0, 1.0, 0, 1]), b**2 * np.array([-1.0, 0, 1, 0])]
    d0.append(b**3 * np.array([0, -1.0, 0, 1]))
    rows = [
        [*d0[0], -1.0, -r],  # Y(0) = y_h + r theta
        [*d0[1], 0.0, -1.0],  # Y'(0) = theta
        [*(b**2 * np.array([-c, -s, ch, sh])), 0.0, 0.0],  # Y''(L) = 0
        [*(b**3 * np.array([s, -c, sh, ch])), 0.0, 0.0],  # Y'''(L) = 0
        [*(EI * d0[3]), -w2 * m_h, 0.0],  # -w^2 m_h y_h + EI Y'''(0) = 0
        [*(-EI * d0[2] + r * EI * d0[3]), 0.0, -w2 * i_h],  # -w^2 I_h theta - EI Y''(0) + r EI Y'''(0) = 0
    ]
    return np.array(rows)


def _roots(det, n, b_max):
    """First ``n`` sign changes of ``det(b)`` on (0, b_max], refined by brentq."""
    bs = np.linspace(1e-3, b_max, 3000)
    v = np.array([det(b) for b in bs])
    out = []
    for i in np.nonzero(np.sign(v[:-1]) != np.sign(v[1:]))[0]:
        out.append(brentq(det, bs[i], bs[i + 1], xtol=1e-14))
        if len(out) == n:
            break
    return np.array(out)


def _freq(b):
    return b**2 * np.sqrt(EI / RA)


def _det_scaled(b, m_h, i_h, r, pinned=False):
    A = _hub_beam_matrix(b, m_h, i_h, r)
    if pinned:  # y_h = 0: drop its column and the hub force equation
        A = np.delete(np.delete(A, 4, axis=1), 4, axis=0)
    A = A / np.linalg.norm(A, axis=1, keepdims=True)  # rows of very different size (cosh, EI)
    return np.linalg.det(A)


def test_constrained_frequencies_are_the_cantilever_roots():
    app = beam_appendage(L, E, RHO, 5, width=W, thickness=T_)
    body = hub_body(50.0, 5.0, [(app, (0.5, 0.0, 0.0), (1.0, 0.0, 0.0))], radius=0.5)
    bl = [brentq(lambda x: np.cos(x) * np.cosh(x) + 1.0, k * np.pi + 0.1, (k + 1) * np.pi - 0.1) for k in range(5)]
    exact = _freq(np.array(bl) / L)
    assert np.allclose(body.frequencies, exact, rtol=1e-10)
    assert abs(body.mass - (50.0 + RA * L)) < 1e-9


@pytest.mark.parametrize(("m_h", "r"), [(50.0, 0.5), (20.0, 0.0)])
def test_unconstrained_frequencies_of_the_free_hub(m_h, r):
    """Free-floating hub: the closed-form roots (hub translating and rotating) vs the model's
    (6 + n) eigenproblem with 10 clamped modes (Ritz: converges from above)."""
    app = beam_appendage(L, E, RHO, 10, width=W, thickness=T_)
    body = hub_body(m_h, [5.0, 5.0, 5.0], [(app, (r, 0.0, 0.0), (1.0, 0.0, 0.0))], radius=r)
    exact = _freq(_roots(lambda b: _det_scaled(b, m_h, 5.0, r), 3, 12.0 / L))
    got = free_frequencies(body)[:3]
    rel = (got - exact) / exact
    assert np.all(rel > -1e-9), rel  # Rayleigh-Ritz: upper bounds
    assert np.all(rel < 2e-4), rel
    # more constraint, higher frequency: clamped > free-hub first frequency < ... interlacing
    assert exact[0] > body.frequencies[0]


def test_unconstrained_frequencies_of_a_pinned_hub():
    """Classic hub-beam (hub rotates about a fixed axis): the model with a hub 1e6 times heavier
    than the beam against the closed form without hub translation."""
    app = beam_appendage(L, E, RHO, 10, width=W, thickness=T_)
    body = hub_body(2.7e6, 5.0, [(app, (0.5, 0.0, 0.0), (1.0, 0.0, 0.0))], radius=0.5)
    exact = _freq(_roots(lambda b: _det_scaled(b, 0.0, 5.0, 0.5, pinned=True), 2, 12.0 / L))
    got = free_frequencies(body)[:2]
    assert np.allclose(got, exact, rtol=2e-4), (got, exact)


@pytest.mark.parametrize("profile", ["bang-bang", "versine"])
def test_rest_to_rest_slew_of_a_rigid_body_ends_at_rest_at_the_target(profile):
    body = hub_body(10.0, [2.0, 3.0, 4.0])  # no appendages: a rigid body
    assert body.rigid
    angle = np.radians(90.0)
    ld = slew_torque(body, angle, 10.0, profile, axis=(0.0, 0.0, 1.0), start=1.0)
    assert abs(ld.vector[2] - 4.0 * (4 * angle / 100 if profile == "bang-bang" else 2 * np.pi * angle / 100)) < 1e-12
    sol = simulate(body, [ld], settings=Settings(t_end=12.0, dt_out=0.5, rtol=1e-10, atol=1e-12), method="full")
    assert sol.status == "success"
    assert abs(sol.euler_123[-1, 2] - angle) < 1e-8
    assert np.abs(sol.angular_velocity[-1]).max() < 1e-9
    assert np.abs(sol.euler_123[sol.time <= 1.0, 2]).max() == 0.0  # nothing before the start


def test_prescribed_slew_profiles_are_rest_to_rest():
    """Angle, rate and acceleration of the prescribed profiles: the rate is the derivative of the
    angle, the acceleration that of the rate (central differences), rest at both ends."""
    from rotaflex.floating.kernels import motion_profile

    for profile in ("bang-bang", "versine"):
        pres = Prescribed(profile=profile, angle=1.3, duration=4.0, start=0.5).packed()
        t = np.linspace(0.0, 5.0, 2001)
        a, w, al = np.array([motion_profile(pres, tt) for tt in t]).T
        dt = t[1] - t[0]
        assert np.allclose(np.gradient(a, dt)[1:-1], w[1:-1], atol=2e-3)
        near_jump = np.zeros(len(t), dtype=bool)  # bang-bang: compare away from the jumps
        for j in np.nonzero(np.abs(np.diff(al)) > 0.1)[0]:
            near_jump[max(0, j - 1) : j + 3] = True
        assert np.allclose(np.gradient(w, dt)[~near_jump], al[~near_jump], atol=2e-3)
        assert a[0] == 0.0 and abs(a[-1] - 1.3) < 1e-15 and w[-1] == 0.0 and al[-1] == 0.0


@pytest.mark.parametrize("zeta", [0.01, 0.05])
def test_damped_mode_decays_at_its_ratio(zeta):
    """Hub held at rest (prescribed, zero slew), first appendage mode displaced: successive peaks
    fall by the logarithmic decrement 2 pi zeta / sqrt(1 - zeta^2)."""
    app = beam_appendage(L, E, RHO, 3, width=W, thickness=T_)
    body = with_damping(hub_body(50.0, 5.0, [(app, (0.5, 0.0, 0.0), (1.0, 0.0, 0.0))], radius=0.5), zeta)
    w1 = body.frequencies[0]
    period = 2 * np.pi / (w1 * np.sqrt(1 - zeta**2))
    st = Settings(t_end=4 * period, dt_out=period / 400, rtol=1e-10, atol=1e-13)
    sol = simulate(
        body,
        [],
        Initial(modal_displacement=(0.01, 0.0, 0.0)),
        st,
        prescribed=Prescribed(profile="bang-bang", angle=0.0, duration=1.0),
    )
    q = sol.q[:, 0]
    peaks = [i for i in range(1, len(q) - 1) if q[i] > q[i - 1] and q[i] >= q[i + 1]]
    # refine each peak by a parabola through three samples
    vals = []
    for i in peaks:
        y0, y1, y2 = q[i - 1 : i + 2]
        vals.append(y1 - 0.125 * (y2 - y0) ** 2 / (y2 - 2 * y1 + y0))
    dec = np.log(np.array(vals[:-1]) / np.array(vals[1:]))
    assert len(dec) >= 2
    assert np.allclose(dec, 2 * np.pi * zeta / np.sqrt(1 - zeta**2), rtol=1e-4), dec


def test_hub_slew_example_reports_residual_vibration():
    from rotaflex.floating.case import resolve_paths, run_case

    cfg = tomllib.loads(EXAMPLE.read_text())
    cfg.pop("domain")
    cfg["solver"]["t_end"] = 14.0
    cfg["solver"]["dt_out"] = 0.05
    res = run_case(resolve_paths(cfg, EXAMPLE.parent))
    s = res.summary()
    assert res.status == "success"
    assert abs(s["full.slew_angle_deg"]["value"] - 90.0) < 0.01  # open-loop torque: near the target
    assert s["full.final_euler_123_deg"]["value"][2] == pytest.approx(np.degrees(s["full.final_euler_123"]["value"][2]))
    amp = s["full.tip.residual_amplitude"]["value"]
    assert 0 < amp < s["full.tip.max_deflection"]["value"]
    assert "settling_time" in json.dumps(s)


def test_bad_hub_input_names_the_field():
    from rotaflex.floating.case import validate_config

    cfg = tomllib.loads(EXAMPLE.read_text())
    cfg.pop("domain")
    bad = json.loads(json.dumps(cfg))
    del bad["body"]["hub"]["appendages"][0]["thickness"]
    with pytest.raises(InputError, match=r"body\.hub\.appendages\[0\]\.width"):
        validate_config(bad)
    bad = json.loads(json.dumps(cfg))
    bad["slew"]["drive"] = "motion"
    bad["prescribed"] = {"rate": 1.0}
    with pytest.raises(InputError, match="slew.drive"):
        validate_config(bad)
    bad = json.loads(json.dumps(cfg))
    bad["outputs"]["tip"] = [3.5, 0.0, 0.0]
    with pytest.raises(InputError, match="outputs.tip"):
        validate_config(bad)
    with pytest.raises(InputError, match="body.hub.inertia"):
        hub_body(1.0, [10.0, 1.0, 1.0])
    assert rigid_body(1.0, [1.0, 1.0, 1.0]).rigid
