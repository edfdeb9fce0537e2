"""Floating modal model vs the converged geometrically exact planar reference
(``rotaflex.floating.reference``: discrete Kirchhoff elastica, RK4, refined and extrapolated).

The reference is itself checked first (observed order 2 in the link length, extrapolated error
< 1e-4, time-step error negligible), so a model error above the reference error is the
model's. Tolerances are the measured model errors (docs/floating.md, "Verification against a
geometrically exact reference") with ~30 % margin; they are far above the reference error
(3.5e-5 for the torque pulse with 128..1024 links), so the test measures the model, not the
reference.
"""

import numpy as np
import pytest

from rotaflex.floating.reference import PlanarCase, converged, modal_counterpart, simulate, tip_deflection

T_END, DT_OUT = 2.0, 0.05


def _errors(case, n0=64, levels=4, ref=None, **kw):
    """Converged reference and the modal model's max tip error relative to the peak, with
    (True) and without (False) geometric stiffness."""
    ref = ref or converged(case, T_END, DT_OUT, n0=n0, levels=levels, check_dt=False)
    scale = np.abs(ref.tip).max()
    out = {}
    for geo in (False, True):
        u, th = modal_counterpart(case, T_END, DT_OUT, geometric=geo, **kw)
        out[geo] = np.abs(u - ref.tip).max() / scale
    return ref, out


SOFT_PUSH = PlanarCase(4.0, 2.0, 1.0, force=0.2)


@pytest.fixture(scope="module")
def soft_push():
    # EI 1, 0.2 N half-sine end push (fixed direction): 64..512 links
    return converged(SOFT_PUSH, T_END, DT_OUT, n0=64, levels=4, check_dt=False)


def test_reference_converges_at_second_order_below_1e4(soft_push):
    case, ref = SOFT_PUSH, soft_push
    assert 1.8 < ref.order < 2.2  # the discrete elastica is second order in ds
    assert ref.error < 1e-4  # measured 7.5e-6
    # time step: halving the RK4 step (at 128 links) changes the tip by round-off only
    a = simulate(case, 128, T_END, DT_OUT)
    b = simulate(case, 128, T_END, DT_OUT, dt_factor=0.5)
    ua = tip_deflection(case, *a[1:], a[0])[0]
    ub = tip_deflection(case, *b[1:], b[0])[0]
    assert np.abs(ua - ub).max() / np.abs(ua).max() < 1e-8


def test_soft_beam_end_force_model_error(soft_push):
    # EI 1, 0.2 N (tip 0.056 m, 1.4 % of L): measured model error 1.71e-3 (on) / 2.02e-3 (off),
    # reference error 7.5e-6; at 0.02 N (linear range) the model error is 2.1e-4
    ref, err = _errors(SOFT_PUSH, ref=soft_push)
    assert ref.error < 1e-4
    assert err[True] < 2.5e-3
    assert err[True] < err[False]


def test_soft_beam_torque_pulse_beyond_the_linear_range():
    # EI 1, 0.5 N m torque about z at the centre, 1 s half-sine (tip 67 mm, 1.7 % of L): the
    # model is off by 1.9e-2 with or without geometric stiffness and with 10 or 20 modes -- the
    # geometric nonlinearity the fixed-mode model lacks (at 0.05 N m it is 5e-4: next test).
    # Reference from 32..256 links (1/8 of the cost of 64..512): order 1.90, error estimate
    # 1.16e-3 (64..512: 2.1e-4; 128..1024 in the slow test below: 3.5e-5); the model error is
    # 1.885e-2 against it (1.89e-2 against the tight one), at least 6e-3 inside the band, so a
    # reference good to 2e-3 decides the band with a factor 3 to spare
    ref, large = _errors(PlanarCase(4.0, 2.0, 1.0, torque=0.5), n0=32)
    assert ref.error < 2e-3  # measured 1.16e-3
    assert 1e-2 < large[True] < 2.5e-2


@pytest.mark.slow  # ~30 s: the 1024-link chain alone takes 25 s
def test_soft_beam_torque_pulse_against_the_tight_reference():
    # one level finer (128..1024 links): raw differences 2.9e-3, 7.3e-4, 1.9e-4 (orders 1.97,
    # 1.93); the order-2 extrapolants from 64..1024 change by 8.8e-4, 2.0e-4, 2.8e-5, so the
    # extrapolated reference is good to 3.5e-5, 500x below the 1.9e-2 model error it judges
    case = PlanarCase(4.0, 2.0, 1.0, torque=0.5)
    ref = converged(case, T_END, DT_OUT, n0=128, levels=4, check_dt=False)
    assert 1.8 < ref.order < 2.2
    assert ref.error < 1e-4  # measured 3.5e-5
    _, err = _errors(case, ref=ref)
    assert 1.5e-2 < err[True] < 2.5e-2  # measured 1.89e-2 (off 1.78e-2)


@pytest.mark.slow
def test_soft_beam_small_torque_pulse_in_the_linear_range():
    # 0.05 N m (tip 6.7 mm): measured model error 5.4e-4
    ref, small = _errors(PlanarCase(4.0, 2.0, 1.0, torque=0.05))
    assert ref.error < 1e-3
    assert small[True] < 1e-3


ISSUE13 = PlanarCase(1.0, 1.0, 10.0, torque=1.0)


def test_issue_torque_pulse_angle():
    # issue 13: free-free unit beam (L 1 m, rho_a 1 kg/m, J = 1/12), 1 N m torque pulse as a 1 s
    # half-sine: theta(2 s) = (tau/J) * 3 t1^2/pi = 36/pi = 11.459 rad, whatever dt_out
    exact = 36.0 / np.pi
    for dt_out in (0.5, 0.01):
        _, th = modal_counterpart(ISSUE13, T_END, dt_out, n_modes=4)
        assert abs(th[-1] - exact) < 1e-4


@pytest.mark.slow  # ~6 s CPU: the stiff short chain needs ~70x the steps of the soft beam's
def test_reference_mean_axis_angle_of_the_issue_torque_pulse():
    # the geometrically exact reference's mean-axis angle agrees once converged: lumped masses
    # give the chain J (1 + 2/n^2), so 64 links alone are 5.6e-3 low; extrapolated from 32 and 64
    case, exact = ISSUE13, 36.0 / np.pi
    ang = {}
    for n in (32, 64):
        t, nodes, m, x0 = simulate(case, n, T_END, 0.01)
        ang[n] = tip_deflection(case, nodes, m, x0, t)[1][-1]
    assert abs(ang[64] - exact) > 1e-3
    assert abs(ang[64] + (ang[64] - ang[32]) / 3.0 - exact) < 1e-4


# EI 100, 1 s half-sine loads on the 4 m free-free beam (the body spins up to 3-3.7 rad/s): the
# reference from 64, 128, 256 links (~6 s) is enough here. Its conservative error estimate (change
# of the extrapolant) is 9e-5 for the end force and 1.5e-3 for the torque, 10-150 times below the
# model errors it judges; against the 128..1024-link references of benchmarks/reference_floating.py
# (8.6e-5) the model errors are the same to 2 digits (force 1.49e-2 / 1.53e-1, torque 1.32e-2 /
# 1.10e-1 with / without geometric stiffness).
STIFF = dict(n0=64, levels=3)


def test_stiff_beam_end_force_model_error():
    # EI 100, 20 N end force in a fixed direction (tip 0.161 m, 4 % of L). Reference from 32, 64,
    # 128 links (4.9 s CPU; 64..256 took 17.6 s): order 1.81, error estimate 1.1e-3; model error
    # on 1.492e-2, off 1.533e-1 (against 64..256, error 9.1e-5: 1.489e-2 and 1.532e-1, the same
    # to 3 digits). The coarser chain is just short of the asymptotic range (order 1.81 instead
    # of 1.98), hence the wider order bound; second order itself is checked on the soft beam.
    # The model-error band stays 2.7 x the reference error away from the measured value.
    ref, err = _errors(PlanarCase(4.0, 2.0, 100.0, force=20.0), n0=32, levels=3)
    assert 1.7 < ref.order < 2.2 and ref.error < 2e-3
    assert 1.2e-2 < err[True] < 1.8e-2  # the geometric stiffness of the load state makes it 10x smaller
    assert err[False] > 0.12


@pytest.mark.slow  # 18.7 s CPU (64..256 links of the stiff beam); the end-force twin above runs by default
def test_stiff_beam_torque_pulse_model_error():
    # EI 100, 50 N m torque about z at the centre (tip 43 mm, 1.1 % of L); measured on 1.331e-2,
    # off 1.107e-1, reference order 1.98, error estimate 1.5e-3 (tight reference: 1.32e-2, 1.10e-1)
    ref, err = _errors(PlanarCase(4.0, 2.0, 100.0, torque=50.0), **STIFF)
    assert 1.8 < ref.order < 2.2 and ref.error < 3e-3
    assert 1.0e-2 < err[True] < 1.7e-2
    assert err[False] > 8e-2


SPINUP = PlanarCase(10.0, 1.2, 1.4e4, support="clamped-spin", rate=6.0, spin_up_time=15.0)


def _spinup_errors(t_end: float):
    """Reference (16, 32, 64 links) and the modal model's max tip errors over ``t_end``: the
    inextensible kinematics relative to the peak, the linear one in metres."""
    ref = converged(SPINUP, t_end, 0.05, n0=16, levels=3, check_dt=False)
    ext, _ = modal_counterpart(SPINUP, t_end, 0.05, n_modes=6, kinematics="inextensible")
    lin, _ = modal_counterpart(SPINUP, t_end, 0.05, n_modes=6)
    peak = np.abs(ref.tip).max()
    return ref, peak, np.abs(ext - ref.tip).max() / peak, np.abs(lin - ref.tip).max()


def test_spinup_beam_tip_within_1e3_of_the_reference_through_the_peak():
    # the Kane-Ryan-Banerjee spin-up beam over its first 10 s, which hold the tip's peak (0.574 m
    # at t = 6.75 s) and both maxima of the error over 20 s (next test): measured inextensible
    # 1.46e-4 of the peak (1.46e-4 over 20 s), linear 5.95e-4 m = 1.037e-3 of the peak at t = 6.8 s
    # (5.9e-4 m = 1.04e-3 over 20 s); reference order 2.000, error estimate 1.4e-5 (1.3e-4 over
    # 20 s). Half the span, half the cost (reference 15 s CPU instead of ~30 s on the loaded machine)
    ref, peak, err_ext, err_lin = _spinup_errors(10.0)
    assert 1.8 < ref.order < 2.2 and ref.error < 2e-4 and 0.55 < peak < 0.6
    assert err_ext < 1e-3  # the issue's acceptance number, relative to the peak
    assert err_ext < 3e-4  # measured 1.46e-4
    assert err_lin < 1e-3  # [m]
    assert 1e-3 < err_lin / peak < 1.1e-3 and err_lin / peak > 3 * err_ext


@pytest.mark.slow  # ~25 s; the 10 s twin above runs by default
def test_spinup_beam_tip_within_1e3_of_the_reference_over_20_s():
    # the Kane-Ryan-Banerjee spin-up beam over 20 s (peak 0.574 m at t = 6.8-7.2 s) against the
    # reference from 16, 32, 64 links (~10 s; order 2.00, error estimate 1.3e-4 of the peak; the
    # 32..256-link benchmark gives 5e-7). With the example's inextensible kinematics and 6 modes
    # the measured error is 1.46e-4 of the peak, within the issue's 1e-3; the linear model with
    # geometric stiffness is off by 5.9e-4 m = 1.04e-3 of the peak: within 1e-3 m absolute, just
    # above 1e-3 relative (converged in modes: 4 to 12 give 0.98e-3 to 1.05e-3), its own
    # O((u/L)^2) error (docs/floating.md)
    ref, peak, err_ext, err_lin = _spinup_errors(20.0)
    assert 1.8 < ref.order < 2.2 and ref.error < 2e-4 and 0.55 < peak < 0.6
    assert err_ext < 1e-3  # the issue's acceptance number, relative to the peak
    assert err_ext < 3e-4  # measured 1.46e-4 (the reference's own estimate: 1.3e-4)
    assert err_lin < 1e-3  # [m]
    assert 1e-3 < err_lin / peak < 1.1e-3 and err_lin / peak > 3 * err_ext


@pytest.mark.slow  # ~25 s
def test_spinup_beam_error_scales_with_the_square_of_the_deflection_ratio():
    # Both histories measure the same thing (the y coordinate, in the hub frame, of the material
    # point at s = L), so the 1.04e-3 relative error at rate 6 rad/s is the linear model's own:
    # the neglected O((u/L)^2) terms (foreshortening, its coupling with the hub motion). At half
    # the rate the peak ratio u/L falls from 0.057 to 0.031 and the relative error from 1.04e-3
    # to 3.2e-4: err / peak / (peak/L)^2 = 0.32 and 0.35, i.e. quadratic in the deflection
    k = {}
    for rate in (6.0, 3.0):
        case = PlanarCase(10.0, 1.2, 1.4e4, support="clamped-spin", rate=rate, spin_up_time=15.0)
        ref = converged(case, 20.0, 0.05, n0=16, levels=3, check_dt=False)
        u, _ = modal_counterpart(case, 20.0, 0.05, n_modes=8)
        peak = np.abs(ref.tip).max()
        k[rate] = np.abs(u - ref.tip).max() / peak / (peak / 10.0) ** 2
    assert 0.25 < k[6.0] < 0.4 and 0.25 < k[3.0] < 0.4
    assert abs(k[6.0] / k[3.0] - 1.0) < 0.2  # measured 0.92


def test_issue_torque_pulse_example_file():
    # examples/floating/torque_pulse_beam.toml through run(path): euler_123 at dt_out = 0.5 s
    from pathlib import Path

    from rotaflex.floating import run

    path = Path(__file__).resolve().parents[2] / "examples" / "floating" / "torque_pulse_beam.toml"
    ds = run(path).dataset
    z = ds["euler_123"].values[..., 2].ravel()
    assert abs(z[-1] - 36.0 / np.pi) < 1e-4
    assert ds["time"].values[-1] == 2.0 and len(ds["time"]) == 5
