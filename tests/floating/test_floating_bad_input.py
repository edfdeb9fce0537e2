"""Floating bad input through the CLI (exit 2, one line naming the field) and early stops."""

import json
import time

import numpy as np
import pytest
from typer.testing import CliRunner

from rotaflex.cli import app
from rotaflex.core.errors import InputError
from rotaflex.floating.case import SCHEMA, FloatingCase, validate_config

POINTS = """
domain = "floating"
[body]
type = "points"
[body.points]
masses = [1.0, 1.0, 1.0, 1.0]
positions = [[-0.5, 0.0, 0.0], [0.5, 0.0, 0.0], [0.0, -0.5, 0.0], [0.0, 0.5, 0.0]]
shapes = [[[0.0, 0.0, 0.5], [0.0, 0.0, 0.5], [0.0, 0.0, -0.5], [0.0, 0.0, -0.5]]]
frequencies = [3.0]
[solver]
t_end = 0.1
dt_out = 0.01
"""

BEAM = """
domain = "floating"
[body]
type = "beam"
[body.beam]
length = 2.0
rho_a = 1.0
ei = 10.0
n_modes = 2
[[loads]]
kind = "torque"
vector = [0.0, 0.0, 1.0]
profile = "pulse"
duration = 0.05
[solver]
t_end = 0.1
dt_out = 0.01
[outputs]
tip = [1.0, 0.0, 0.0]
"""

FRAME = """
domain = "floating"
[body]
type = "frame"
[body.frame]
nodes = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]
e = 7.0e10
g = 2.6e10
rho = 2700.0
area = 1e-4
iy = 1e-9
iz = 1e-9
j = 2e-9
n_modes = 2
elements_per_segment = 4
[solver]
t_end = 0.1
dt_out = 0.01
"""

CASES = [
    (
        POINTS,
        "frequencies = [3.0]\n",
        "frequencies = [3.0]\nrotary_inertias = [[10.0, 1.0, 1.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0], "
        "[0.0, 0.0, 0.0]]\n",
        ["body.points.rotary_inertias[0]", "triangle"],
    ),
    (POINTS, "masses = [1.0, 1.0, 1.0, 1.0]", "masses = [1.0, -1.0, 1.0, 1.0]", ["body.points.masses[1]"]),
    (BEAM, "duration = 0.05", "duration = 0.0", ["loads[0].duration"]),
    (BEAM, 'profile = "pulse"', 'profile = "sinusoid"', ["loads[0].frequency"]),
    (BEAM, "n_modes = 2", "n_modes = 100000", ["body.beam.n_modes", "<= 100"]),
    (BEAM, "dt_out = 0.01", "dt_out = 1e-9", ["solver.dt_out", "output samples"]),
    (BEAM, "n_modes = 2", "n_modes = 2\nsection_radius = -0.1", ["body.beam.section_radius"]),
    (BEAM, "n_modes = 2", "n_modes = 2\nspatial = true", ["body.beam.section_radius", "spatial"]),
    (BEAM, "vector = [0.0, 0.0, 1.0]", "vector = [1.0, 0.0, 1.0]", ["loads[0].vector", "in-plane"]),
    (FRAME, "elements_per_segment = 4", "elements_per_segment = 100000", ["body.frame.elements_per_segment"]),
    (FRAME, "n_modes = 2", "n_modes = 100", ["body.frame.n_modes"]),
    (FRAME, "[1.0, 0.0, 0.0]]", "[0.0, 0.0, 0.0]]", ["body.frame.nodes"]),
]


@pytest.mark.parametrize("base, old, new, words", CASES)
def test_bad_input_exit_2_one_line(tmp_path, base, old, new, words):
    assert old in base
    path = tmp_path / "case.toml"
    path.write_text(base.replace(old, new))
    t0 = time.perf_counter()
    res = CliRunner().invoke(app, ["floating", "simulate", str(path), "--out", str(tmp_path / "o")])
    assert res.exit_code == 2, res.output
    lines = [ln for ln in res.output.strip().splitlines() if ln.strip()]
    assert len(lines) == 1, res.output
    for w in words:
        assert w in lines[0], lines[0]
    assert time.perf_counter() - t0 < 30  # refused before anything big is allocated


@pytest.mark.parametrize("base, old, new, words", CASES)
def test_validate_config_gives_the_same_error(base, old, new, words):
    import tomllib

    cfg = tomllib.loads(base.replace(old, new))
    cfg.pop("domain")
    with pytest.raises(InputError) as exc:
        validate_config(cfg)
    assert exc.value.field == words[0]


def test_validate_config_accepts_good_cases_without_running():
    import tomllib

    for base in (POINTS, BEAM, FRAME):
        cfg = tomllib.loads(base)
        cfg.pop("domain")
        cfg["solver"]["t_end"] = 1e5  # would take hours to integrate
        cfg["solver"]["dt_out"] = 1.0
        cfg["solver"]["max_steps"] = 10**12  # a budget that allows it: validation still runs nothing
        t0 = time.perf_counter()
        assert validate_config(cfg) is None
        assert time.perf_counter() - t0 < 5.0
    assert SCHEMA is FloatingCase


def test_step_budget_is_estimated_before_the_run():
    """t_end = 1e5 s with the default budget: refused up front (one line naming
    solver.max_steps, the estimate and how to raise it), not found exhausted after minutes."""
    import tomllib

    from rotaflex.floating.beam import uniform_beam
    from rotaflex.floating.hub import free_frequencies

    cfg = tomllib.loads(BEAM)
    cfg.pop("domain")
    cfg["solver"]["t_end"] = 1e5
    cfg["solver"]["dt_out"] = 1.0
    t0 = time.perf_counter()
    with pytest.raises(InputError) as err:
        validate_config(cfg)
    assert time.perf_counter() - t0 < 5.0
    e = err.value
    # the estimate: one step per radian of the fastest free-floating mode over t_end
    w = free_frequencies(uniform_beam(2.0, 1.0, 10.0, 2)).max()
    assert e.field == "solver.max_steps" and e.value == 2_000_000
    assert f"~{w * 1e5:.3g}" in e.allowed and "raise solver.max_steps" in e.allowed
    # the estimate is a lower bound: a short run of the same case needs more steps than it
    from rotaflex.floating.model import Load, Settings
    from rotaflex.floating.solve import simulate

    ld = Load(kind="torque", vector=(0.0, 0.0, 1.0), profile="pulse", duration=0.05)
    for method in ("full", "perturbation"):
        sol = simulate(uniform_beam(2.0, 1.0, 10.0, 2), [ld], settings=Settings(t_end=1.0, dt_out=0.1), method=method)
        assert sol.nstep > w * 1.0


def test_early_stop_keeps_data_and_says_why(tmp_path):
    path = tmp_path / "case.toml"
    path.write_text(BEAM.replace("dt_out = 0.01", "dt_out = 0.01\nmax_steps = 20"))
    out = tmp_path / "o"
    res = CliRunner().invoke(app, ["floating", "simulate", str(path), "--out", str(out), "--no-figures"])
    assert res.exit_code == 1, res.output
    assert "step budget" in res.output and "stopped early at t =" in res.output
    assert "residual" not in res.output
    import xarray as xr

    with xr.open_dataset(out / "result.nc") as ds:
        q = ds["modal_displacement"].sel(solution="full").values
        assert ds.attrs["status"] == "failed"
        assert q.shape[0] == 11 and 0 < int((~np.isnan(q[:, 0])).sum()) < 11
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"]["value"] == "failed"
