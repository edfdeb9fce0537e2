"""FE rotor verification against closed forms, an exact Timoshenko solution and published numbers."""

import numpy as np
import pytest
import scipy.linalg as sla

from rotaflex.rotor.fe import Bearing, Disk, Rotor, Shaft
from rotaflex.rotor.fe.elements.shaft import plane_matrices
from rotaflex.rotor.fe.modal import campbell, modal
from rotaflex.rotor.fe.response import api684_required_margin, peaks, unbalance_response
from rotaflex.rotor.fe.transient import transient
from rotaflex.rotor.fe.ucs import ucs_map

RPM = np.pi / 30


def friswell_591(c=0.0, n=6, ky=1e6):
    return Rotor(
        shaft=(Shaft(outer_diameter=0.05, length=1.5, elements=n),),
        disk=(
            Disk(position=0.5, width=0.07, outer_diameter=0.28, inner_diameter=0.05),
            Disk(position=1.0, width=0.07, outer_diameter=0.35, inner_diameter=0.05),
        ),
        bearing=(Bearing(node=0, kxx=1e6, kyy=ky, cxx=c, cyy=c), Bearing(node=n, kxx=1e6, kyy=ky, cxx=c, cyy=c)),
    )


def test_timoshenko_element_matches_closed_form():
    """Quadrature matrices = the closed-form Timoshenko matrices (Przemieniecki; Friswell et al. 2010)."""
    L, d, E, G, rho, kap = 0.3, 0.08, 2e11, 7.7e10, 7800.0, 0.9
    A, I = np.pi * d**2 / 4, np.pi * d**4 / 64
    phi = 12 * E * I / (kap * G * A * L**2)
    Mt, Mr, K = (x[0] for x in plane_matrices(L, d, 0, d, 0, E, G, rho, kap))
    Kc = (
        E
        * I
        / (L**3 * (1 + phi))
        * np.array(
            [
                [12, 6 * L, -12, 6 * L],
                [6 * L, (4 + phi) * L**2, -6 * L, (2 - phi) * L**2],
                [-12, -6 * L, 12, -6 * L],
                [6 * L, (2 - phi) * L**2, -6 * L, (4 + phi) * L**2],
            ]
        )
    )
    a, b, c_ = 312 + 588 * phi + 280 * phi**2, (44 + 77 * phi + 35 * phi**2) * L, 108 + 252 * phi + 140 * phi**2
    e, f, g = (26 + 63 * phi + 35 * phi**2) * L, (8 + 14 * phi + 7 * phi**2) * L**2, (6 + 14 * phi + 7 * phi**2) * L**2
    Mtc = (
        rho
        * A
        * L
        / (840 * (1 + phi) ** 2)
        * np.array([[a, b, c_, -e], [b, f, e, -g], [c_, e, a, -b], [-e, -g, -b, f]])
    )
    h, p, q = (3 - 15 * phi) * L, (4 + 5 * phi + 10 * phi**2) * L**2, (-1 - 5 * phi + 5 * phi**2) * L**2
    Mrc = (
        rho
        * I
        / (30 * (1 + phi) ** 2 * L)
        * np.array([[36, h, -36, h], [h, p, -h, q], [-36, -h, 36, -h], [h, q, -h, p]])
    )
    for mine, ref in ((K, Kc), (Mt, Mtc), (Mr, Mrc)):
        assert np.max(np.abs(mine - ref)) < 1e-11 * np.max(np.abs(ref))


def test_global_matrices_structure():
    r = friswell_591()
    assert np.allclose(r.M, r.M.T, atol=1e-14) and np.allclose(r.G, -r.G.T, atol=1e-14)
    K = r.KC(0.0)[0][0]
    assert np.allclose(K, K.T)
    assert r.mass == pytest.approx(
        7810 * np.pi / 4 * (0.05**2 * 1.5 + (0.28**2 + 0.35**2 - 2 * 0.05**2) * 0.07), rel=1e-12
    )


def test_friswell_example_5_9_1_vs_ross_documentation():
    """The book's Example 5.9.1 model (6 elements). Reference: the ROSS documentation's output for
    this model (petrobras/ross docs, 'Example 3 - Isotropic Bearings, asymmetrical rotor'), an
    independent Timoshenko FE code: 0 rpm 86.658, 274.313, 716.786 rad/s; 4000 rpm 85.389,
    87.796, 251.785, 294.713, 600.179, 827.075 rad/s."""
    r = friswell_591()
    w0 = modal(r, 0.0, 6).wn[0]
    assert np.allclose(w0[::2], [86.65811435, 274.31285391, 716.78631221], rtol=1e-6)
    w4 = modal(r, 4000 * RPM, 6)
    assert np.allclose(
        w4.wn[0], [85.389467, 87.7958637, 251.78460413, 294.71333087, 600.17936195, 827.07536193], rtol=1e-6
    )
    # the lower of each pair is the backward whirl, from the orbit sense
    assert list(w4.whirl[0]) == ["backward", "forward"] * 3


def jeffcott(m=10.0, k=1e6, c=200.0):
    # pure translation mode of a symmetric rigid rotor: mass at the two bearings, a stiff light shaft
    return Rotor(
        shaft=(Shaft(outer_diameter=0.05, length=0.2, elements=1, E=2e15, G=8e14, rho=1e-6),),
        disk=(Disk(node=0, mass=m / 2, Id=1.0, Ip=0.5), Disk(node=1, mass=m / 2, Id=1.0, Ip=0.5)),
        bearing=(
            Bearing(node=0, kxx=k / 2, kyy=k / 2, cxx=c / 2, cyy=c / 2),
            Bearing(node=1, kxx=k / 2, kyy=k / 2, cxx=c / 2, cyy=c / 2),
        ),
    )


def test_jeffcott_critical_speed_and_unbalance_closed_form():
    m, k, c, u = 10.0, 1e6, 200.0, 1e-4
    r = jeffcott(m, k, c)
    md = modal(r, 0.0)
    wn = np.sqrt(k / m)
    j = np.argmin(np.abs(md.wn[0] - wn))
    assert md.wn[0, j] == pytest.approx(wn, rel=1e-6)
    assert md.damping_ratio[0, j] == pytest.approx(c / (2 * np.sqrt(k * m)), rel=1e-5)
    W = np.linspace(50, 600, 111)
    res = unbalance_response(r, W, [(0, u / 2, 0.0), (1, u / 2, 0.0)])
    X, Y = res.at(0)
    exact = u * W**2 / (k - m * W**2 + 1j * c * W)
    assert np.max(np.abs(X - exact) / np.abs(exact)) < 1e-6
    assert np.allclose(Y, -1j * X)  # circular forward orbit
    Xn = unbalance_response(r, [wn], [(0, u / 2, 0.0), (1, u / 2, 0.0)]).at(0)[0][0]
    assert np.angle(Xn) == pytest.approx(-np.pi / 2, abs=1e-6)  # 90 deg lag at the undamped natural frequency
    # half-power amplification factor of a light damped oscillator: AF ~ 1 / (2 zeta)
    Wf = np.linspace(200, 450, 5001)
    amp = np.abs(unbalance_response(r, Wf, [(0, u / 2, 0.0), (1, u / 2, 0.0)]).at(0)[0])
    pk = peaks(Wf, amp, operating_speed=2 * wn)
    zeta = c / (2 * np.sqrt(k * m))
    assert len(pk) == 1 and pk[0]["af"] == pytest.approx(1 / (2 * zeta), rel=0.02)
    assert pk[0]["sm_percent"] == pytest.approx(100 * abs(2 * wn - pk[0]["speed"]) / (2 * wn))
    # API 684 required margin by hand: AF = 1/(2 zeta) = 15.81 -> 17 (1 - 1/(15.81 - 1.5)) = 15.81 %
    # below the operating speed, 10 + 15.81 = 25.81 % above it
    af = pk[0]["af"]
    assert pk[0]["sm_required_percent"] == pytest.approx(17 * (1 - 1 / (af - 1.5)))
    assert pk[0]["sm_required_percent"] == pytest.approx(15.8, abs=0.3) and pk[0]["sm_ok"] == 1.0
    close = peaks(Wf, amp, operating_speed=1.1 * wn)[0]  # 9.1 % < 15.8 %
    assert close["sm_percent"] == pytest.approx(9.1, abs=0.2) and close["sm_ok"] == 0.0
    above = peaks(Wf, amp, operating_speed=0.8 * wn)[0]  # critical above: 25 % < 25.8 %
    assert above["sm_required_percent"] == pytest.approx(25.8, abs=0.3) and above["sm_ok"] == 0.0
    assert peaks(Wf, amp, operating_speed=0.75 * wn)[0]["sm_ok"] == 1.0  # 33 % > 25.8 %


def test_api684_required_margin_hand_values():
    assert api684_required_margin(2.4, below=True) == 0.0  # AF < 2.5: no margin required
    assert api684_required_margin(2.5, below=True) == pytest.approx(0.0)  # 17 (1 - 1/1) = 0
    assert api684_required_margin(3.5, below=True) == pytest.approx(8.5)  # 17 (1 - 1/2)
    assert api684_required_margin(3.5, below=False) == pytest.approx(18.5)
    assert api684_required_margin(100.0, below=True) == 16.0  # capped
    assert api684_required_margin(100.0, below=False) == 26.0


def _ss_beam_frequencies(n_el, L=1.0, d=0.1, E=2.1e11, G=8.1e10, rho=7800.0, kap=0.9):
    r = Rotor(
        shaft=(Shaft(outer_diameter=d, length=L, elements=n_el, E=E, G=G, rho=rho, shear_coefficient=kap),), free=True
    )
    K = r.KC(0.0)[0][0]
    # pinned ends: remove x, y at both end nodes (constraint elimination, no penalty)
    fixed = {0, 1, r.n_dof - 4, r.n_dof - 3}
    keep = [i for i in range(r.n_dof) if i not in fixed]
    w2 = sla.eigh(K[np.ix_(keep, keep)], r.M[np.ix_(keep, keep)], eigvals_only=True)
    return np.sqrt(w2[::2])  # x-z and y-z planes are identical


def _ss_timoshenko_exact(n, L=1.0, d=0.1, E=2.1e11, G=8.1e10, rho=7800.0, kap=0.9):
    """Exact simply supported Timoshenko frequency (lower root of the frequency equation)."""
    A, I = np.pi * d**2 / 4, np.pi * d**4 / 64
    a = n * np.pi / L
    c4 = rho**2 * I / (kap * G)
    c2 = -(rho * A + rho * I * a**2 * (1 + E / (kap * G)))
    c0 = E * I * a**4
    return np.sqrt((-c2 - np.sqrt(c2**2 - 4 * c4 * c0)) / (2 * c4))


def test_simply_supported_timoshenko_beam_and_convergence_order():
    exact = np.array([_ss_timoshenko_exact(n) for n in (1, 2, 3)])
    w = _ss_beam_frequencies(64)[:3]
    assert np.max(np.abs(w - exact) / exact) < 2e-4
    # shear matters here (d/L = 0.1): Euler-Bernoulli would be > 1 % off for mode 3
    eb = (3 * np.pi) ** 2 * np.sqrt(2.1e11 * np.pi * 0.1**4 / 64 / (7800 * np.pi * 0.01 / 4))
    assert abs(eb - exact[2]) / exact[2] > 0.05
    errs = [abs(_ss_beam_frequencies(n)[2] - exact[2]) / exact[2] for n in (8, 16, 32)]
    orders = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    # observed O(h^2): the element's shear strain is constant per element, so the coupling of
    # rotary inertia with shear (the omega^4 term of the exact equation) converges at second order
    assert np.all((orders > 1.9) & (orders < 2.3)), orders


def test_rigid_rotor_gyroscopic_quartic():
    """Rigid rotor (m, Id, Ip at the centre) on unequal springs at -a, +b: forward/backward whirl
    frequencies are the positive roots of the quartic
    (k1 + k2 - m w^2)(k1 a^2 + k2 b^2 - Id w^2 +/- Ip Omega w) - (k2 b - k1 a)^2 = 0."""
    m, Id, Ip, k1, k2, a, b = 20.0, 0.5, 0.6, 1e6, 2e6, 0.3, 0.2
    r = Rotor(
        shaft=(
            Shaft(outer_diameter=0.1, start=-a, end=0.0, E=1e16, G=4e15, rho=1e-6),
            Shaft(outer_diameter=0.1, length=b, E=1e16, G=4e15, rho=1e-6),
        ),
        disk=(
            Disk(node=1, mass=m, Id=Id, Ip=Ip),
            Disk(node=0, mass=1e-6, Id=1e-6, Ip=0.0),
            Disk(node=2, mass=1e-6, Id=1e-6, Ip=0.0),
        ),
        bearing=(Bearing(node=0, kxx=k1, kyy=k1), Bearing(node=2, kxx=k2, kyy=k2)),
    )
    W = 300.0
    md = modal(r, W, 4)
    got = {"forward": [], "backward": []}
    for w, s in zip(md.wn[0], md.whirl[0], strict=True):
        got[str(s)].append(w)
    for sense, sgn in (("forward", 1), ("backward", -1)):
        K11, K22, K12 = k1 + k2, k1 * a**2 + k2 * b**2, k2 * b - k1 * a
        # (K11 - m w^2)(K22 - Id w^2 + s Ip W w) - K12^2, expanded in powers of w
        poly = np.polymul([-m, 0, K11], [-Id, sgn * Ip * W, K22])
        poly[-1] -= K12**2
        roots = np.sort([z.real for z in np.roots(poly) if abs(z.imag) < 1e-6 and z.real > 0])
        assert np.allclose(np.sort(got[sense]), roots, rtol=1e-5), (sense, got[sense], roots)


def test_ucs_matches_campbell_forward_crossings():
    r = friswell_591()
    c = campbell(r, np.linspace(0, 4000 * RPM, 81), 6)
    fw = [x["speed"] for x in c.critical if x["whirl"] == "forward" and x["harmonic"] == 1]
    u = ucs_map(r, [1e6], 2)[0]
    assert np.allclose(fw[:2], u, rtol=2e-3)  # Campbell crossing is linearly interpolated


def test_campbell_tracking_keeps_whirl_through_crossing():
    r = friswell_591()
    c = campbell(r, np.linspace(50 * RPM, 4000 * RPM, 40), 6)
    ff = c.modes.forward_fraction
    # every tracked mode keeps one whirl sense along the speed range (no label swaps)
    assert np.all((ff > 0.5).all(0) | (ff < 0.5).all(0))
    assert c.mac_min[1:].min() > 0.9


def test_transient_matches_steady_unbalance_both_methods():
    r = friswell_591(c=3e3, ky=1.2e6)
    W = 200.0
    Q = unbalance_response(r, [W], [(2, 1e-4, 0.3)]).Q[0]
    for method, tol in (("modal", 1e-6), ("direct", 1e-3)):
        tr = transient(
            r,
            0.2,
            speed_start=W,
            unbalance=[(2, 1e-4, 0.3)],
            method=method,
            n_output=401,
            q0=Q.real,
            v0=(1j * W * Q).real,
            n_modes=28,
            steps_per_output=8,
        )
        ex = (Q[None, :] * np.exp(1j * W * tr.time[:, None])).real
        assert np.max(np.abs(tr.q[:, 8] - ex[:, 8])) / abs(Q[8]) < tol, method


def test_energy_conserved_undamped_gyroscopic_free_vibration():
    r = friswell_591()
    q0 = np.zeros(r.n_dof)
    q0[8] = 1e-3
    tr = transient(r, 0.1, speed_start=300.0, q0=q0, method="modal", n_modes=8, n_output=101, rtol=1e-10)
    K = r.KC(300.0)[0][0]
    E = 0.5 * np.einsum("ti,ij,tj->t", tr.v, r.M, tr.v) + 0.5 * np.einsum("ti,ij,tj->t", tr.q, K, tr.q)
    assert np.max(np.abs(E - E[0])) / E[0] < 1e-6


def test_runup_peak_lags_the_critical_speed():
    r = friswell_591(c=3e3)
    crit = ucs_map(r, [1e6], 1)[0, 0]
    tr = transient(
        r,
        2.0,
        speed_start=0.5 * crit,
        speed_end=1.5 * crit,
        unbalance=[(4, 1e-4, 0.0)],
        method="modal",
        n_modes=12,
        n_output=4001,
    )
    amp = np.hypot(tr.q[:, 16], tr.q[:, 17])
    w_peak = tr.speed[np.argmax(amp)]
    assert crit < w_peak < 1.2 * crit  # an accelerating rotor peaks after the steady critical


def test_nonlinear_force_plugin_equals_linear_spring():
    """A callable force -k_extra x at a node must give the same motion as a bearing with k_extra."""
    r0, r1 = friswell_591(c=3e3), friswell_591(c=3e3)
    r1 = Rotor(shaft=r0.shaft, disk=r0.disk, bearing=(*r0.bearing, Bearing(node=3, kxx=5e5, kyy=5e5)))

    def spring(t, q, v):
        f = np.zeros_like(q)
        f[12:14] = -5e5 * q[12:14]
        return f

    q0 = np.zeros(r0.n_dof)
    q0[8] = 1e-4
    a = transient(r0, 0.05, speed_start=200.0, q0=q0, force=spring, method="direct", n_output=101)
    b = transient(r1, 0.05, speed_start=200.0, q0=q0, method="direct", n_output=101)
    assert np.max(np.abs(a.q - b.q)) < 1e-6 * np.max(np.abs(b.q))


def test_campbell_reduced_basis_converges_to_full():
    """The reduced basis (undamped modes) approaches the full solution as it grows."""
    r = friswell_591(c=3e3, ky=1.3e6, n=12)
    sp = np.linspace(0, 4000 * RPM, 12)
    wf = np.sort(campbell(r, sp, 6).modes.wd, 1)  # sorted: labels may differ at the degenerate 0 rpm
    errs = [np.max(np.abs(np.sort(campbell(r, sp, 6, reduce=m).modes.wd, 1) - wf) / wf) for m in (16, 24, 36)]
    assert errs[0] > errs[1] > errs[2] and errs[2] < 2e-3, errs
