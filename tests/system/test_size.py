"""Size estimates of the system verbs against what the runs really take, and the refusals.

Memory: the peak that tracemalloc sees (numpy reports its buffers to it) for two sizes of the
same run; the difference isolates the arrays that grow with the sized count, and the estimate's
difference must bound it from above without overstating it by more than 1.6x. Counts (steps,
output points) must equal what the run produced.
"""

from __future__ import annotations

import json
import tracemalloc
from pathlib import Path

import numpy as np
import pytest

from rotaflex.core.errors import InputError
from rotaflex.core.limits import set_max_memory
from rotaflex.system import size
from rotaflex.system.assembly import free_dofs
from rotaflex.system.model import Gearbox

ROOT = Path(__file__).resolve().parents[2]


def _peak(fn, *a, **kw):
    tracemalloc.start()
    try:
        out = fn(*a, **kw)
        return tracemalloc.get_traced_memory()[1], out
    finally:
        tracemalloc.stop()


def _bounds(actual: float, estimate: float) -> None:
    assert actual <= estimate <= 1.6 * actual, (actual, estimate)


@pytest.fixture
def box(make):
    return Gearbox.from_mapping(make(te=[1e-6]))


def test_modal_memory_bounds_the_peak(box):
    from rotaflex.system.modal import modal

    n, nf = box.n_dof, free_dofs(box).size
    modal(box, 100.0, 12)  # lazy model parts (rotor matrices, mesh tables) built outside the trace
    p, m = _peak(modal, box, 100.0, 12)
    _bounds(p, size.modal_size(n, nf, len(box.rotors))["bytes"])
    assert m.shape.shape[-1] == n


def test_campbell_memory_and_points(box):
    from rotaflex.system.modal import campbell

    n, nf = box.n_dof, free_dofs(box).size
    runs = {ns: _peak(campbell, box, np.linspace(0.0, 600.0, ns), 12) for ns in (8, 40)}
    est = {ns: size.campbell_size(n, nf, 2, ns, 12, nf) for ns in runs}
    _bounds(runs[40][0] - runs[8][0], est[40]["bytes"] - est[8]["bytes"])
    assert runs[40][1].modes.wd.size == est[40]["points"]


def test_response_memory_and_points(box, monkeypatch):
    from rotaflex.system import response

    seen = {}

    def spy(*a):
        seen["args"] = a
        return size.check_response(*a)

    monkeypatch.setattr(response, "check_response", spy)
    runs, est = {}, {}
    for ns in (40, 240):
        runs[ns] = _peak(response.forced_response, box, np.linspace(10.0, 600.0, ns), harmonics=3, probes=[(0, 3)])
        est[ns] = size.response_size(*seen["args"][:6])
    _bounds(runs[240][0] - runs[40][0], est[240]["bytes"] - est[40]["bytes"])
    assert runs[240][1].mesh_force.size == est[240]["points"]


def test_steady_steps_points_and_memory(box):
    from rotaflex.system.steady import SteadySettings, steady_state

    def settings(cycles):  # tol 1e-30: never periodic, so every run goes to max_cycles
        return SteadySettings(steps_per_cycle=32, min_cycles=cycles, max_cycles=cycles, eval_cycles=3, tol=1e-30)

    steady_state(box, 300.0, settings(10))  # kernel compiled / loaded outside the trace
    runs = {c: _peak(steady_state, box, 300.0, settings(c)) for c in (20, 200)}
    est = {c: size.steady_size(c, 10, 3, 32, runs[c][1].basis_size, 1, 4) for c in runs}
    for c, (_, s) in runs.items():
        assert s.cycles * s.steps_per_cycle == est[c]["steps"]
        assert s.time.size == est[c]["points"]
    _bounds(runs[200][0] - runs[20][0], est[200]["bytes"] - est[20]["bytes"])


def test_steady_refuses_beyond_max_steps_and_accepts_when_raised(box):
    from rotaflex.system.steady import SteadySettings, steady_state

    # (40 + 2) cycles x 32 steps = 1344 steps at most
    st = SteadySettings(steps_per_cycle=32, min_cycles=40, max_cycles=40, eval_cycles=2, max_steps=1300)
    with pytest.raises(InputError) as exc:
        steady_state(box, 300.0, st)
    assert exc.value.field == "steady.max_cycles" and "1.34e+03" in str(exc.value) and "max_steps" in str(exc.value)
    s = steady_state(box, 300.0, SteadySettings(**{**st.__dict__, "max_steps": 1344}))
    assert s.cycles * s.steps_per_cycle <= 1344


def test_memory_refusals_name_the_key(box):
    from rotaflex.system.modal import campbell, modal
    from rotaflex.system.response import forced_response

    n = box.n_dof  # the system matrices alone: 8 n^2 (8 + 2 rotors) bytes, ~0.4 MB here
    cases = [
        ("100kB", lambda: modal(box, 0.0, 4), "modal.n_modes"),
        ("100kB", lambda: forced_response(box, [100.0]), "rotor[0].shaft[0].elements"),
        ("2MB", lambda: campbell(box, np.linspace(0.0, 600.0, 2000), 4), "campbell.n_speeds"),
        ("2MB", lambda: forced_response(box, np.linspace(10.0, 600.0, 100000)), "response.n_speeds"),
    ]
    try:
        for limit, run, field in cases:
            set_max_memory(limit)
            with pytest.raises(InputError) as exc:
                run()
            assert exc.value.field == field and "--max-memory" in str(exc.value), (field, n)
    finally:
        set_max_memory(None)


def test_clamp_modes():
    assert size.clamp_modes(12, 70, "modal.n_modes") == (12, "")
    n, note = size.clamp_modes(100, 70, "modal.n_modes")
    assert n == 70 and "modal.n_modes = 100 clamped to 70" in note


def _cli(*args):
    from typer.testing import CliRunner

    from rotaflex.cli import app

    return CliRunner().invoke(app, [*args, "-q", "--no-figures"])


def _case(tmp_path, **tables):
    """The example gearbox's model tables with the given analysis tables (flat key = number)."""
    text = (ROOT / "examples/system/gearbox.toml").read_text()
    text = text[: text.index("[modal]")]
    for name, table in tables.items():
        text += f"[{name}]\n" + "".join(f"{k} = {v!r}\n" for k, v in table.items())
    path = tmp_path / "case.toml"
    path.write_text(text)
    return path


def _one_line(r, key):
    lines = [ln for ln in r.output.strip().splitlines() if ln]
    assert r.exit_code == 2 and len(lines) == 1 and key in lines[0], r.output


@pytest.mark.parametrize(
    ("verb", "tables", "limit", "key"),
    [
        ("steady", {"steady": {"speed_rpm": 3000.0, "max_cycles": 10**6}}, None, "steady.max_cycles"),
        ("steady", {"steady": {"speed_rpm": 3000.0, "steps_per_cycle": 100000}}, None, "steady.steps_per_cycle"),
        ("response", {"response": {"n_speeds": 100000, "harmonics": 50}}, None, "response.n_speeds"),
        ("campbell", {"campbell": {"n_speeds": 2000, "n_modes": 200}}, "1MB", "campbell.n_speeds"),
        ("modal", {}, "100kB", "modal.n_modes"),
    ],
)
def test_cli_refusals_exit_2_one_line(tmp_path, monkeypatch, verb, tables, limit, key):
    monkeypatch.setenv("ROTAFLEX_MAX_MEMORY", "8GiB")  # the CLI exports --max-memory: undone after the test
    extra = ["--max-memory", limit] if limit else []
    try:
        r = _cli(*extra, "system", verb, str(_case(tmp_path, **tables)), "--out", str(tmp_path / "o"))
    finally:
        set_max_memory(None)
    _one_line(r, key)
    assert not (tmp_path / "o").exists()


def test_cli_modal_clamps_n_modes_with_a_note(tmp_path):
    path = _case(tmp_path, modal={"speed_rpm": 3000.0, "n_modes": 200})
    r = _cli("system", "modal", str(path), "--out", str(tmp_path / "o"))
    assert r.exit_code == 0, r.output
    s = json.loads((tmp_path / "o" / "summary.json").read_text())
    nf = free_dofs(Gearbox.from_toml(path)).size
    assert nf < 200 and f"modal.n_modes = 200 clamped to {nf}" in s["note"]["value"]
    assert f"mode_{nf - 1}_frequency_hz" in s and f"mode_{nf}_frequency_hz" not in s
