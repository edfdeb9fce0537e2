"""Attitude output: Euler angles unwrapped from the integrator's steps, not from output samples."""

import numpy as np
import pytest

from rotaflex.floating import Initial, Load, Settings, uniform_beam
from rotaflex.floating.result import build_result
from rotaflex.floating.solve import simulate


def _run(body, loads, initial, dt_out, method="full", t_end=6.0):
    s = Settings(t_end=t_end, dt_out=dt_out, rtol=1e-9, atol=1e-11)
    return simulate(body, loads, initial, s, method)


def test_free_spin_angle_is_rate_times_time_for_any_output_interval():
    # free-free beam spinning at 10 rad/s about z: q = 0 stays an equilibrium, so the z angle is
    # exactly 10 t; the samples at dt_out = 0.5 are 5 rad apart (more than pi: sample unwrapping
    # would alias to 0, -1.28, -2.57, ...)
    b = uniform_beam(4.0, 2.0, 40.0, 4)
    ini = Initial(angular_velocity=(0.0, 0.0, 10.0))
    for dt_out in (0.5, 0.01):
        sol = _run(b, (), ini, dt_out)
        z = sol.euler_123[:, 2]
        np.testing.assert_allclose(z, 10.0 * sol.time, rtol=0, atol=1e-7)
        np.testing.assert_allclose(sol.euler_123[:, :2], 0.0, atol=1e-9)
    np.testing.assert_allclose(_run(b, (), ini, 0.5).euler_123[:3, 2], [0.0, 5.0, 10.0], atol=1e-7)


@pytest.mark.parametrize("method", ["full", "perturbation"])
def test_torque_pulse_angle_independent_of_output_interval(method):
    # torque pulse about z at the centre: rigid closed form theta = tau/J (t^2/2) during the
    # pulse and a constant rate after; elastic coupling changes J only at second order
    L, rho_a, tau, t1 = 4.0, 2.0, 100.0, 1.0
    b = uniform_beam(L, rho_a, 4000.0, 4, section_radius=0.0)
    J = rho_a * L**3 / 12.0
    ld = Load(kind="torque", vector=(0.0, 0.0, tau), profile="pulse", duration=t1)
    coarse = _run(b, [ld], Initial(), 0.5, method, t_end=4.0)
    fine = _run(b, [ld], Initial(), 0.01, method, t_end=4.0)
    np.testing.assert_allclose(coarse.euler_123, fine.euler_123[::50], rtol=0, atol=1e-8)
    t = coarse.time
    a = tau / J
    exact = np.where(t < t1, 0.5 * a * t**2, 0.5 * a * t1**2 + a * t1 * (t - t1))
    # theta(4 s) = 32.8 rad, 4.7 rad between samples after the pulse
    assert exact[-1] > 6 * np.pi
    np.testing.assert_allclose(coarse.euler_123[:, 2], exact, rtol=2e-4, atol=1e-6)


def test_result_carries_quaternion_matrix_and_stepwise_euler():
    b = uniform_beam(4.0, 2.0, 40.0, 3)
    ini = Initial(angular_velocity=(0.0, 0.0, 10.0))
    sols = [_run(b, (), ini, 0.5, m, t_end=2.0) for m in ("full", "perturbation")]
    res = build_result(b, sols, {"tip": (2.0, 0.0, 0.0)})
    ds = res.dataset
    A = ds["rotation_matrix"].sel(solution="full").values
    th = 10.0 * ds["time"].values
    np.testing.assert_allclose(A[:, 0, 0], np.cos(th), atol=1e-7)
    np.testing.assert_allclose(A[:, 1, 0], np.sin(th), atol=1e-7)
    np.testing.assert_allclose(ds["zero_order_euler_123"].values[:, 2], th, atol=1e-7)
    fin = res.summary()["perturbation.final_euler_123"]["value"]
    assert abs(fin[2] - 20.0) < 1e-6


def test_section_radius_default_is_a_line_beam_and_small_values_run():
    b = uniform_beam(4.0, 2.0, 40.0, 3)
    assert not b.extra_inertia.any()  # a line beam carries no section inertia
    ld = Load(kind="torque", vector=(0.0, 0.0, 1.0), profile="pulse", duration=0.5)
    for r, spatial in ((0.0, False), (1e-9, False), (1e-4, True)):
        bb = uniform_beam(4.0, 2.0, 40.0, 2, spatial=spatial, section_radius=r)
        sol = _run(bb, [ld], Initial(), 0.1, t_end=1.0)
        assert sol.status == "success" and np.isfinite(sol.euler_123).all()
        # w_x never moves: the spin about the beam's own axis is not excited by a z torque
        assert np.abs(sol.angular_velocity[:, 0]).max() < 1e-9


def test_planar_attitude_figure_does_not_draw_round_off():
    import matplotlib

    matplotlib.use("Agg")
    b = uniform_beam(4.0, 2.0, 40.0, 3)
    ld = Load(kind="torque", vector=(0.0, 0.0, 5.0), profile="bang-bang", duration=1.0)
    sols = [_run(b, [ld], Initial(), 0.05, m, t_end=1.0) for m in ("full", "perturbation")]
    figs = build_result(b, sols, {"tip": (2.0, 0.0, 0.0)}).plot()
    ax = figs["attitude"].axes[0]
    labels = [ln.get_label() for ln in ax.lines]
    assert labels == ["full z", "perturbation z", "zero order z"]
    assert "zero to round-off" in ax.get_title()


@pytest.mark.parametrize(("t_end", "times"), [(2.22, [2.0, 2.22]), (2.3, [2.0, 2.3])])
def test_run_ends_at_t_end_when_it_is_not_a_multiple_of_dt_out(tmp_path, t_end, times):
    # the torque_pulse_beam example with t_end 2.22 or 2.3 s and dt_out 0.5 s: the output grid is
    # 0, 0.5, ..., 2.0 and then t_end (before: 2.22 stopped at 2.0, 2.3 ran on to 2.5), and the
    # final angle is the one at t_end: the same as with dt_out 0.01 s, which divides t_end, and
    # the rigid closed form (tau/J) (t1^2 + 2 t1 (t - t1)) / pi after the half-sine pulse
    from pathlib import Path

    from rotaflex.core.config import load_toml
    from rotaflex.floating import run

    cfg = load_toml(Path(__file__).resolve().parents[2] / "examples" / "floating" / "torque_pulse_beam.toml")
    final = {}
    for dt_out in (0.5, 0.01):
        cfg["solver"].update(t_end=t_end, dt_out=dt_out)
        res = run(cfg)
        t = res.dataset["time"].values
        assert t[-1] == t_end
        if dt_out == 0.5:
            np.testing.assert_allclose(t[-len(times) :], times)
        final[dt_out] = res.summary()["full.final_euler_123"]["value"][2]
    assert abs(final[0.5] - final[0.01]) < 1e-8
    assert abs(final[0.5] - 12.0 * (1.0 + 2.0 * (t_end - 1.0)) / np.pi) < 1e-4
