"""Forced response and nonlinear steady state: against each other, energy balance, continuation."""

from __future__ import annotations

import numpy as np
import pytest

from rotaflex.system.model import Gearbox
from rotaflex.system.response import forced_response
from rotaflex.system.steady import SteadySettings, steady_state


def _quiet(make, **kw):
    cfg = make(drive="constant_speed", **kw)
    cfg["load"]["damping"] = 2.0  # N m s/rad: damps the load's twist mode
    return cfg


def test_reduced_response_matches_full_solve(make):
    box = Gearbox.from_mapping(_quiet(make, te=(2e-6, 5e-7)))
    sp = np.linspace(50.0, 700.0, 40)
    full = forced_response(box, sp, harmonics=2, probes=[(0, 3)], cutoff=None)
    red = forced_response(box, sp, harmonics=2, probes=[(0, 3)])
    for key in ("dte", "mesh_force", "bearing_force", "orbit"):
        a, b = getattr(red, key), getattr(full, key)
        assert np.max(np.abs(a - b)) < 1e-3 * np.max(np.abs(b)), key


def test_linear_response_equals_time_domain_at_small_te(make):
    """Mean mesh stiffness, a 10 nm TE sine (no contact loss): the time-domain steady state's
    first mesh harmonic of DTE and mesh force equals the frequency-domain response."""
    box = Gearbox.from_mapping(_quiet(make, te=(1e-8,)))
    speed = 300.0
    lin = forced_response(box, [speed], harmonics=1, excitation="unloaded_te", cutoff=None)
    st = steady_state(box, speed, SteadySettings(stiffness="mean", tol=1e-6, min_cycles=30, max_cycles=3000))
    assert st.period == 1
    assert st.contact_loss[0] == 0.0
    spc = st.steps_per_cycle
    n = (st.time.size - 1) // spc * spc

    def h1(x):
        return 2 * np.abs(np.fft.rfft(x[-n - 1 : -1])[n // spc]) / n

    assert h1(st.dte[:, 0]) == pytest.approx(abs(lin.dte[0, 0, 0]), rel=2e-3)
    assert h1(st.force[:, 0]) == pytest.approx(abs(lin.mesh_force[0, 0, 0]), rel=2e-3)
    assert np.mean(st.force[:, 0]) == pytest.approx(st.static_force[0], rel=1e-6)


def test_energy_balance_converges(make):
    """E(t) - E(0) = int P dt: the residual falls with the step (RK4 + trapezoidal power)."""
    box = Gearbox.from_mapping(_quiet(make, te=(3e-6, 1e-6), k_harmonics=(8e7, 3e7)))
    errs = []
    for spc in (64, 128):
        st = steady_state(box, 300.0, SteadySettings(steps_per_cycle=spc, min_cycles=10, max_cycles=10, eval_cycles=2))
        errs.append(st.energy_error)
    assert errs[1] < 1e-3
    assert errs[1] < errs[0] / 3


def test_energy_balance_with_a_stepped_table_converges_at_second_order(make):
    """Contact-pattern table (piecewise linear, stiffness steps of 2.5e8 N/m over one cell): the
    steps fall on table points, each RK4 step stays in one cell and the work of the explicit time
    dependence is integrated from each step's one-sided power limits. Before, the power at a
    grid point took the next cell's dk/dphi and the balance stalled at ~1e-2."""
    cfg = _quiet(make, source="contact_pattern", k_pair=2.5e8, unloaded_te_pp=5e-6)
    for k in ("k_mean", "k_harmonics", "te_harmonics"):
        cfg["gear_mesh"][0].pop(k, None)
    box = Gearbox.from_mapping(cfg)
    assert box.meshes[0].gear.table.interpolation == "linear"
    errs = []
    for spc in (256, 512):
        st = steady_state(box, 300.0, SteadySettings(steps_per_cycle=spc, min_cycles=6, max_cycles=6, eval_cycles=2))
        errs.append(st.energy_error)
    assert errs[1] < 3e-4
    assert errs[1] < errs[0] / 3  # second order: the residual falls ~4x per halved step


def test_contact_loss_and_restart_from_final_state(make):
    """Near the mesh mode a 2 um TE separates the flanks; restarting from a run's final state
    continues that run exactly (20 + 10 cycles, then 20 more = one run of 40 + 10 cycles)."""
    from rotaflex.system.modal import modal

    box = Gearbox.from_mapping(_quiet(make, te=(2e-6,)))
    m = modal(box, 300.0, 30)
    k = int(np.argmax(m.mesh_energy[0]))
    assert m.mesh_energy[0, k] > 0.3  # the mesh mode
    speed = 0.95 * m.wn[0, k] / 20  # mesh frequency just below it (20 pinion teeth)

    def run(cycles, state=None):
        s = SteadySettings(steps_per_cycle=96, min_cycles=cycles, max_cycles=cycles, check_every=cycles, eval_cycles=10)
        return steady_state(box, speed, s, state)

    a = run(20)
    assert a.contact_loss[0] > 0.05
    b = run(10, {"q": a.final_q, "qdot": a.final_qdot, "phase": a.final_phase})
    c = run(40)
    np.testing.assert_allclose(b.force[:, 0], c.force[:, 0], atol=1e-9 * c.static_force[0])


def test_steady_result_saves_and_offers_final_state(make, tmp_path):
    from rotaflex.core.result import load_result
    from rotaflex.system.case import run_steady

    cfg = _quiet(make, te=(2e-6,))
    cfg["steady"] = {"speed_rpm": 2800.0, "min_cycles": 10, "max_cycles": 10, "eval_cycles": 3}
    res = run_steady(cfg)
    res.save(tmp_path / "s", figures=False)
    back = load_result(tmp_path / "s" / "result.nc")
    a, b = res.final_state(), back.final_state()
    np.testing.assert_allclose(b["q"], a["q"], rtol=0, atol=0)
    assert set(back.plot()) == {"system", "time_series"}
    s = back.summary()
    assert s["mesh_frequency"]["unit"] == "Hz" and s["dynamic_factor"]["value"] > 1.0
