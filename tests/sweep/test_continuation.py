"""Continuation sweeps of a domain verb (``verb = "steady"``, ``--continuation``) through the CLI.

The torsional gear model with the analytic single/double-contact mesh (pair stiffness 1.2e8 N/m,
2 um triangular unloaded TE, damping ratio 0.05) loses contact near its mesh resonance; the
softening makes the response two-valued below resonance: sweeping up stays on the low branch
(flanks in contact), sweeping down from above resonance stays on the high branch (contact loss)
down to 10000 rpm. Far above resonance there is one branch and both directions agree.
"""

import json
import math
import shutil
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

from rotaflex.cli import app
from rotaflex.gear.pair.geometry import GearGeometry, contact_ratio

runner = CliRunner()
ROOT = Path(__file__).resolve().parents[2]

SPEEDS = "10000,11000,12000,15000,17000,20000,21000"
BASE = """domain = "gear"
verb = "steady"
[mesh]
source = "contact_pattern"
pair_stiffness = 1.2e8
unloaded_te_pp = 2e-6
damping_ratio = 0.05
table_points = 400
[train]
inertia = [2.965e-4, 2.965e-4]
drive = "motor"
motor_slope = 0.5
[operation]
torque = 22.25
[steady]
eval_cycles = 10
max_cycles = 300
"""
ARGS = ["--vary", f"operation.speed_rpm={SPEEDS}", "--continuation", "operation.speed_rpm"]
# serial: a case computes in ~0.06 s, a worker pool would only add its start-up; the chains on
# other executors: test_dask_local_runs_the_same_chains_as_serial (gear) and
# test_chain_order_state_passing_and_a_killed_worker (process pool)
SERIAL = ["-j", "0"]


def _linear_resonance_rpm() -> float:
    """Mesh-mode resonance from the model data, independently of the code: both gears free
    (motor drive, rigid shafts), k_mean of the analytic table = k_pair (1 + share of the cycle
    with two pairs, sampled on the 400-point table), m_red = J1 J2 / (J1 r_b2^2 + J2 r_b1^2)."""
    g = GearGeometry(module=3.175e-3, teeth=28, face_width=6.35e-3)
    eps = contact_ratio(g, g)
    n = 400
    k_mean = 1.2e8 * (1 + math.ceil((eps - 1) * n) / n)
    j, rb = 2.965e-4, g.base_radius
    m_red = j * j / (j * rb**2 + j * rb**2)
    f_n = math.sqrt(k_mean / m_red) / (2 * math.pi)
    return 60 * f_n / 28


@pytest.fixture(scope="module")
def swept(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("cont")
    cfg = tmp / "base.toml"
    cfg.write_text(BASE)
    out = tmp / "out"
    res = runner.invoke(app, ["sweep", str(cfg), "--out", str(out), *ARGS, *SERIAL])
    return cfg, out, res


def test_direction_dimension_and_all_cases_ok(swept):
    _, out, res = swept
    assert res.exit_code == 0, res.output
    with xr.open_dataset(out / "sweep.nc") as ds:
        assert list(ds["direction"].values) == ["up", "down"]
        assert ds["dynamic_factor"].dims == ("operation_speed_rpm", "direction")
        assert (ds["status"].values == "success").all()
        assert ds.attrs["verb"] == "steady" and ds.attrs["continuation"] == "operation.speed_rpm"
    assert (out / "figures" / "gear_steady_sweep.png").stat().st_size > 10_000


def test_hysteresis_below_resonance_and_agreement_far_above(swept):
    _, out, _ = swept
    with xr.open_dataset(out / "sweep.nc") as ds:
        kv = ds["dynamic_factor"]
        low = kv.sel(operation_speed_rpm=10000.0)
        # two branches: contact kept going up, contact loss going down (threshold: 1.0 in K_v,
        # i.e. the dynamic mesh force differs by a whole static load)
        assert float(low.sel(direction="down") - low.sel(direction="up")) > 1.0
        assert float(ds["contact_loss_fraction"].sel(operation_speed_rpm=10000.0, direction="up")) < 0.05
        assert float(ds["contact_loss_fraction"].sel(operation_speed_rpm=10000.0, direction="down")) > 0.3
        # 20000 rpm is reached from 17000 going up and from 21000 going down: one branch there
        far = kv.sel(operation_speed_rpm=20000.0)
        assert abs(float(far.sel(direction="up") - far.sel(direction="down"))) < 1e-2


def test_resonance_marked_where_the_linear_model_predicts(swept):
    _, out, _ = swept
    expected = _linear_resonance_rpm()
    with xr.open_dataset(out / "sweep.nc") as ds:
        got = np.unique(ds["resonance_speed"].values)
        f_n = np.unique(ds["mesh_natural_frequency"].values)
    assert got.size == 1 and f_n.size == 1
    assert got[0] == pytest.approx(expected, rel=1e-6)
    assert 60 * f_n[0] / 28 == pytest.approx(expected, rel=1e-6)


def test_resume_continues_the_chain_from_the_saved_state(swept, tmp_path):
    cfg, out, _ = swept
    copy = tmp_path / "out"
    shutil.copytree(out, copy)
    with xr.open_dataset(out / "sweep.nc") as ds:
        before = ds["dynamic_factor"].values.copy()
        ids = ds["case_id"]
        # drop the last three cases of the down leg (down at 12000, 11000, 10000)
        dropped = [str(ids.sel(operation_speed_rpm=s, direction="down").item()) for s in (12000.0, 11000.0, 10000.0)]
    for cid in dropped:
        shutil.rmtree(copy / "cases" / cid)
    res = runner.invoke(app, ["sweep", str(cfg), "--out", str(copy), *ARGS, *SERIAL, "--no-figures"])
    assert res.exit_code == 0, res.output
    assert "3 computed, 11 reused" in res.output
    with xr.open_dataset(copy / "sweep.nc") as ds:
        after = ds["dynamic_factor"].values
    # recomputed from the saved final state of down at 15000: the same (deterministic) branch
    np.testing.assert_allclose(after, before, rtol=1e-9)
    info = json.loads((copy / "cases" / dropped[-1] / "case.json").read_text())
    assert info["params"]["direction"] == "down"


def test_example_sweep_file_plans(tmp_path):
    from rotaflex.core.config import load_toml
    from rotaflex.sweep import plan_study

    st = plan_study(
        load_toml(ROOT / "examples" / "sweep" / "gear_dynamic_factor.toml"),
        ["operation.speed_rpm=2000:22000:40"],
        "operation.speed_rpm",
    )
    assert st.verb == "steady" and len(st.cases) == 80 and len(st.chains) == 1


def test_verb_schema_validates_every_case_up_front(tmp_path):
    cfg = tmp_path / "bad.toml"
    cfg.write_text(BASE.replace("max_cycles = 300", "max_cycles = 300\nmin_cycles = 20"))
    res = runner.invoke(
        app, ["sweep", str(cfg), "--out", str(tmp_path / "o"), "--vary", "steady.max_cycles=100,10", "-j", "0"]
    )
    assert res.exit_code == 2
    assert "steady.min_cycles" in res.output and "steady.max_cycles=10" in res.output
    assert not (tmp_path / "o" / "cases").exists()


def test_continuation_needs_a_continuable_verb_and_a_swept_key(tmp_path):
    cfg = tmp_path / "c.toml"
    cfg.write_text(BASE)
    res = runner.invoke(
        app,
        ["sweep", str(cfg), "--out", str(tmp_path / "o"), "--vary", "operation.torque=10,20"]
        + ["--continuation", "operation.speed_rpm"],
    )
    assert res.exit_code == 2 and "--continuation" in res.output
    bad_verb = tmp_path / "v.toml"
    bad_verb.write_text(BASE.replace('verb = "steady"', 'verb = "nope"'))
    res = runner.invoke(app, ["sweep", str(bad_verb), "--out", str(tmp_path / "o2"), "--vary", "operation.torque=1,2"])
    assert res.exit_code == 2 and "verb" in res.output and "'steady'" in res.output


def test_dask_local_runs_the_same_chains_as_serial(swept, tmp_path):
    """The chain order (and so every number) does not depend on the executor: the whole
    two-branch sweep of the fixture (serial) again on a local Dask cluster (one worker: the
    sweep is one chain, a second worker would only idle)."""
    pytest.importorskip("distributed")
    cfg, out, _ = swept
    dask = tmp_path / "dask"
    res = runner.invoke(
        app, ["sweep", str(cfg), "--out", str(dask), *ARGS, "--scheduler", "dask-local", "-j", "1", "--no-figures"]
    )
    assert res.exit_code == 0, res.output
    assert "14 computed, 0 reused" in res.output
    with xr.open_dataset(out / "sweep.nc") as a, xr.open_dataset(dask / "sweep.nc") as b:
        assert b["dynamic_factor"].shape == (7, 2)
        np.testing.assert_array_equal(b["dynamic_factor"].values, a["dynamic_factor"].values)
        np.testing.assert_array_equal(b["case_id"].values, a["case_id"].values)

    def workers(d):
        return {json.loads(p.read_text())["worker"] for p in (d / "cases").glob("*/case.json")}

    assert len(workers(dask)) == 1 and workers(dask).isdisjoint(workers(out))  # ran on the Dask worker


def test_unreadable_saved_state_restarts_the_chain(tmp_path, monkeypatch, selftest_domain):
    """A case whose saved state cannot be read runs again from the state before it, and the
    missing case after it follows; the finished cases after those are reused (issue 32). The
    test verb's state is the running sum of x (a restart from a wrong state would change it)."""
    from rotaflex.core import domains

    monkeypatch.setitem(domains.COMMANDS, "selftest", {"chain": "rotaflex.sweep._selftest_case:run_chain"})
    cfg = tmp_path / "c.toml"
    cfg.write_text('domain = "selftest"\nverb = "chain"\nx = 1.0\n')
    args = ["sweep", str(cfg), "--out", str(tmp_path / "o"), "--vary", "x=1,2,3", "--continuation", "x"]
    args += ["-j", "0", "--no-figures"]
    res = runner.invoke(app, args)
    assert res.exit_code == 0, res.output
    with xr.open_dataset(tmp_path / "o" / "sweep.nc") as ds:
        before = ds["running_sum"].values.copy()
        last_up = str(ds["case_id"].sel(x=3.0, direction="up").item())
        first_down = str(ds["case_id"].sel(x=3.0, direction="down").item())
    shutil.rmtree(tmp_path / "o" / "cases" / first_down)
    (tmp_path / "o" / "cases" / last_up / "result.nc").write_bytes(b"not a netCDF file")
    res = runner.invoke(app, args)
    assert res.exit_code == 0, res.output
    assert "2 computed, 4 reused" in res.output, res.output[-300:]
    with xr.open_dataset(tmp_path / "o" / "sweep.nc") as ds:
        np.testing.assert_array_equal(ds["running_sum"].values, before)
        np.testing.assert_array_equal(ds["running_sum"].sel(direction="down").sortby("x").values, [12.0, 11.0, 9.0])


def test_single_run_of_the_verb_reads_a_sweep_base_file(tmp_path):
    cfg = tmp_path / "c.toml"
    cfg.write_text(BASE.replace("[operation]", "[operation]\nspeed_rpm = 21000.0"))
    res = runner.invoke(app, ["gear", "steady", str(cfg), "--out", str(tmp_path / "one"), "--no-figures"])
    assert res.exit_code == 0, res.output
    res = runner.invoke(app, ["gear", "static", str(cfg), "--out", str(tmp_path / "two"), "--no-figures"])
    assert res.exit_code == 2 and "verb" in res.output


def test_chain_order_state_passing_and_a_killed_worker(tmp_path, monkeypatch, selftest_domain):
    """A continuable test verb whose state is the running sum of x: up 1, 2, 3 then down 3, 2, 1
    gives 1, 3, 6, 9, 11, 12 in each of two parallel chains (y = 0, 1), also when the first case
    to run kills its worker process once (local pool rebuilt, case retried)."""
    from rotaflex.core import domains

    monkeypatch.setitem(domains.COMMANDS, "selftest", {"chain": "rotaflex.sweep._selftest_case:run_chain"})
    cfg = tmp_path / "c.toml"
    kill = tmp_path / "killed-once"
    cfg.write_text(f'domain = "selftest"\nverb = "chain"\nx = 1.0\ny = 0.0\nkill_once = "{kill}"\n')
    args = ["--vary", "x=3,1,2", "--vary", "y=0,1", "--continuation", "x", "-j", "2", "--no-figures"]
    res = runner.invoke(app, ["sweep", str(cfg), "--out", str(tmp_path / "o"), *args])
    assert res.exit_code == 0, res.output
    assert kill.exists()
    with xr.open_dataset(tmp_path / "o" / "sweep.nc") as ds:
        for y in (0, 1):
            one = ds.sel(y=y)
            up = one["running_sum"].sel(direction="up").sortby("x").values
            down = one["running_sum"].sel(direction="down").sortby("x").values
            np.testing.assert_array_equal(up, [1.0, 3.0, 6.0])
            np.testing.assert_array_equal(down, [12.0, 11.0, 9.0])
            np.testing.assert_array_equal(one["position"].sel(direction="down").sortby("x").values, [6, 5, 4])
        assert int(ds["attempts"].max()) >= 2


def test_a_failing_case_stops_its_chain(tmp_path, monkeypatch, selftest_domain):
    from rotaflex.core import domains

    monkeypatch.setitem(domains.COMMANDS, "selftest", {"chain": "rotaflex.sweep._selftest_case:run_chain"})
    cfg = tmp_path / "c.toml"
    cfg.write_text('domain = "selftest"\nverb = "chain"\nx = 1.0\nfail = false\n')
    args = ["--vary", "x=1,2,3", "--vary", "fail=false,true", "--continuation", "x", "-j", "0", "--no-figures"]
    res = runner.invoke(app, ["sweep", str(cfg), "--out", str(tmp_path / "o"), *args])
    assert res.exit_code == 1
    with xr.open_dataset(tmp_path / "o" / "sweep.nc") as ds:
        by_fail = {str(ds["fail"].values[i]).lower(): ds.isel(fail=i) for i in range(ds.sizes["fail"])}
        assert (by_fail["false"]["status"].values == "success").all()
        errors = [str(e) for e in by_fail["true"]["error"].values.ravel()]
    # the chain's first case (x = 1, up) raises; the 5 after it are not run
    assert sum(e.startswith("RuntimeError") for e in errors) == 1
    assert sum(e.startswith("ContinuationStopped") for e in errors) == 5


def test_split_down_chains_keep_the_up_half_and_start_down_cold():
    from rotaflex.sweep.continuation import chain_cases
    from rotaflex.sweep.spec import grid_cases

    grid = grid_cases({"a": {"x": 1.0, "y": 0.0}}, {"a.x": [1.0, 2.0, 3.0], "a.y": [0.0, 1.0]})
    whole_cases, whole = chain_cases(grid, "a.x")
    split_cases, split = chain_cases(grid, "a.x", split=True)
    assert len(whole) == 2 and len(split) == 4
    by_id = {c.id: c for c in split_cases}
    for up, down in zip(split[::2], split[1::2], strict=True):
        assert [by_id[i].params["direction"] for i in up] == ["up"] * 3
        assert [by_id[i].params["a.x"] for i in down] == [3.0, 2.0, 1.0]
        assert by_id[down[0]].data["continuation"]["after"] is None  # its own start at the top
    # the up halves are the same cases (same ids and hashes): a split re-run reuses them
    assert [ch[:3] for ch in whole] == split[::2]
    # the first down case differs from the whole chain's (it does not start from the top state)
    assert {ch[3] for ch in whole}.isdisjoint({ch[0] for ch in split[1::2]})


def test_split_down_follows_the_same_down_branch_from_a_single_branch_top(swept, tmp_path):
    """At 21000 rpm (far above resonance) there is one branch: the down half started from its own
    run there follows the same branch as from the up half's last state, hysteresis included."""
    cfg, out, _ = swept
    res = runner.invoke(
        app, ["sweep", str(cfg), "--out", str(tmp_path / "s"), *ARGS, *SERIAL, "--split-down", "--no-figures"]
    )
    assert res.exit_code == 0, res.output
    with xr.open_dataset(out / "sweep.nc") as a, xr.open_dataset(tmp_path / "s" / "sweep.nc") as b:
        np.testing.assert_array_equal(b["dynamic_factor"].sel(direction="up"), a["dynamic_factor"].sel(direction="up"))
        down_a, down_b = (d["dynamic_factor"].sel(direction="down").values for d in (a, b))
        # steady-state tolerance scale: the two runs reach the same periodic orbit from different
        # starts, so they differ by about the cycle-to-cycle change they stop at
        np.testing.assert_allclose(down_b, down_a, atol=1e-2)
        low = b["dynamic_factor"].sel(operation_speed_rpm=10000.0)
        assert float(low.sel(direction="down") - low.sel(direction="up")) > 1.0


def test_split_down_needs_a_continuation(tmp_path):
    cfg = tmp_path / "c.toml"
    cfg.write_text(BASE)
    res = runner.invoke(
        app, ["sweep", str(cfg), "--out", str(tmp_path / "o"), "--vary", "operation.torque=10,20", "--split-down"]
    )
    assert res.exit_code == 2 and "--split-down" in res.output
