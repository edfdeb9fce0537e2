"""`gear steady` speed sweeps: one continuation path, model data built once per process."""

import pytest

from rotaflex.core.errors import InputError
from rotaflex.gear.cases import steady
from rotaflex.gear.solvers.steady_driver import continuation

#: the lumped model with the analytic mesh table: milliseconds a steady state
BASE = {
    "mesh_stiffness": {"source": "contact_pattern", "unloaded_te_pp": 2e-6},
    "operation": {"torque": 22.25},
    "steady": {"tol": 1e-3, "min_cycles": 10},
}
SPEEDS = [6000.0, 9000.0, 12000.0]


def _at(speed: float, **tables) -> dict:
    return {**BASE, **tables, "operation": {**BASE["operation"], "speed_rpm": speed}}


def test_in_process_sweep_equals_the_case_by_case_continuation():
    """The `[sweep]` table and `rotaflex sweep --continuation operation.speed_rpm` (one case per
    speed, each from the last case's final_state() handed over as data) give the same numbers
    to the last bit: up through the speeds, then down from the top state."""
    sweep = steady.run_torsional({**BASE, "sweep": {"speeds_rpm": SPEEDS}}).dataset
    order = [("up", j) for j in range(3)] + [("down", j) for j in (2, 1, 0)]
    state, kv = None, {}
    for direction, j in order:
        res = steady.run_torsional(_at(SPEEDS[j]), initial_state=state)
        state = res.final_state()
        kv[direction, j] = float(res.dataset["dynamic_factor"])
    for (direction, j), value in kv.items():
        assert sweep["dynamic_factor"].sel(direction=direction).values[j] == value
    # a softening resonance is not in this range: both legs agree, so the check above is not
    # only about the order; the down leg starts from the top state, not from statics
    assert sweep["cycles_run"].sel(direction="down").values[2] <= sweep["cycles_run"].sel(direction="up").values[2]


def test_model_is_built_once_per_sweep_and_keyed_by_content(monkeypatch):
    """Cases that differ only in the speed (or [steady]) share one model; the cache key is the
    config's content (two separately parsed equal configs hit it), and a change the model
    depends on (the torque) builds a new one."""
    steady._built_model.cache_clear()
    calls = []
    build = steady.build_system
    monkeypatch.setattr(steady, "build_system", lambda cfg: calls.append(cfg) or build(cfg))
    state = None
    for rpm in (6000.0, 6500.0, 7000.0):
        state = steady.run_torsional(_at(rpm), initial_state=state).final_state()
    assert len(calls) == 1
    a = steady._checked(_at(6000.0, steady={"tol": 1e-2}))
    b = steady._checked(_at(8000.0))
    assert a is not b and steady.build_model(a)[2] is steady.build_model(b)[2]
    steady.run_torsional({**BASE, "operation": {"torque": 30.0, "speed_rpm": 6000.0}})
    assert len(calls) == 2


def test_pair_data_is_shared_across_speeds_and_methods():
    """The FE pair data depends on the pair only: a case at another speed, with another method
    or other [steady] settings gets the same object."""
    a = steady._checked({"model": {"method": "elastic_teeth"}, "operation": {"speed_rpm": 4000.0}})
    b = steady._checked({"operation": {"speed_rpm": 9000.0}, "steady": {"eval_cycles": 5}})
    assert steady.pair_data(a) is steady.pair_data(b)
    c = steady._checked({"gear": {"face_width": 8e-3}})
    assert steady.pair_data(c) is not steady.pair_data(a)


def test_continuation_checks_speeds_before_running():
    ran = []

    def point(rpm, state):
        ran.append(rpm)
        return None, state

    with pytest.raises(InputError, match="speeds_rpm"):
        continuation(point, [3000.0, 2000.0])
    with pytest.raises(InputError, match="directions"):
        continuation(point, [2000.0, 3000.0], ("up", "sideways"))
    assert ran == []
    list(continuation(point, [1000.0, 2000.0, 3000.0]))
    assert ran == [1000.0, 2000.0, 3000.0, 3000.0, 2000.0, 1000.0]


def test_progress_lines_for_a_long_run(monkeypatch, capsys):
    """Past a few seconds `gear steady` reports progress (one line per update off a terminal):
    mesh cycles for one point, speeds for a sweep."""
    monkeypatch.setattr(steady.LateProgress, "AFTER", 0.0)
    steady.run_torsional(_at(9000.0), progress=True)
    err = capsys.readouterr().err
    assert "gear steady:" in err and "mesh cycle" in err
    steady.run_torsional({**BASE, "sweep": {"speeds_rpm": SPEEDS[:2]}}, progress=True)
    lines = [s for s in capsys.readouterr().err.splitlines() if s.startswith("gear steady:")]
    assert lines and "(4/4 speed)" in lines[-1]
    steady.run_torsional(_at(9000.0), progress=False)
    assert "gear steady:" not in capsys.readouterr().err
