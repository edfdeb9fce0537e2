import json
import math
import sys

import numpy as np
import pytest
import xarray as xr

from rotaflex.core.errors import InputError
from rotaflex.core.result import load_result
from rotaflex.sweep import grid_cases, run_sweep
from rotaflex.sweep._selftest_case import run_case
from rotaflex.sweep.backends import executor_for
from rotaflex.sweep.figures import generic_figures

BASE = {"x": 1.0, "y": 0.0, "n": 16, "sleep": 0.0}


def _grid(**extra):
    return grid_cases({**BASE, **extra}, {"x": [0.5, 1.0, 1.5], "y": [1.0, 2.0]})


def test_serial_sweep_values_files_and_closed_form(tmp_path):
    res = run_sweep(run_case, _grid(), "serial", out_dir=tmp_path)
    assert res.n_cases == 6 and res.n_failed == 0 and res.n_computed == 6
    ds = xr.open_dataset(tmp_path / "sweep.nc", engine="h5netcdf").load()
    assert list(ds["a"].dims) == ["x", "y"]
    x, y = np.meshgrid(ds["x"].values, ds["y"].values, indexing="ij")
    np.testing.assert_allclose(ds["a"].values, x**2 + y, rtol=0, atol=1e-15)
    np.testing.assert_allclose(ds["b"].values, 16 * np.sin(x), rtol=1e-15)
    assert ds["a"].attrs["units"] == "m" and ds.attrs["n_failed"] == 0
    assert (ds["status"].values == "success").all()
    rows = (tmp_path / "summary.csv").read_text().splitlines()
    assert len(rows) == 7 and "a [m]" in rows[0].split(",")
    for rec in res.records:
        case_dir = tmp_path / "cases" / rec.id
        back = load_result(case_dir / "result.nc")
        t = back.dataset["time"].values
        expected = rec.params["x"] * np.sin(2 * np.pi * rec.params["y"] * t)
        np.testing.assert_allclose(back.dataset["signal"].values, expected, rtol=0, atol=1e-15)
        info = json.loads((case_dir / "case.json").read_text())
        assert info["state"] == "done" and info["config"]["x"] == rec.params["x"]
    assert (tmp_path / "figures" / "summary_vs_x.png").exists()


def test_generic_figure_plots_the_dataset_values(tmp_path):
    res = run_sweep(run_case, _grid(), "serial")
    figs = generic_figures(res.dataset)
    fig = figs["summary_vs_x"]
    ax = next(a for a in fig.axes if a.get_ylabel() == "a [m]")
    lines = ax.get_lines()
    assert len(lines) == 2  # one per y value
    np.testing.assert_array_equal(lines[1].get_ydata(), res.dataset["a"].isel(y=1).values)
    np.testing.assert_array_equal(lines[1].get_xdata(), res.dataset["x"].values)


def _compare_sweeps(dir_a, dir_b):
    a = xr.open_dataset(dir_a / "sweep.nc", engine="h5netcdf").load()
    b = xr.open_dataset(dir_b / "sweep.nc", engine="h5netcdf").load()
    for name in ("a", "b", "signal_max", "status", "case_id"):
        np.testing.assert_array_equal(a[name].values, b[name].values)
    for cid in a["case_id"].values.ravel():
        ra = load_result(dir_a / "cases" / cid / "result.nc").dataset
        rb = load_result(dir_b / "cases" / cid / "result.nc").dataset
        np.testing.assert_array_equal(ra["signal"].values, rb["signal"].values)


def test_process_pool_identical_to_serial(tmp_path):
    cases = _grid()
    run_sweep(run_case, cases, "serial", out_dir=tmp_path / "serial", figures=False)
    res = run_sweep(run_case, cases, 2, out_dir=tmp_path / "pool", figures=False)
    assert res.n_failed == 0
    assert len({r.worker for r in res.records}) >= 1
    _compare_sweeps(tmp_path / "serial", tmp_path / "pool")


def test_failing_cases_are_recorded_and_the_sweep_goes_on(tmp_path):
    cases = grid_cases({**BASE, "fail": False}, {"fail": [False, True], "x": [1.0, 2.0]})
    res = run_sweep(run_case, cases, "serial", out_dir=tmp_path)
    assert res.n_failed == 2 and res.n_computed == 4
    for rec in res.failed:
        assert rec.status == "error" and "asked to fail" in rec.error
        text = (tmp_path / "cases" / rec.id / "error.txt").read_text()
        assert "RuntimeError" in text and "Traceback" in text
        assert not (tmp_path / "cases" / rec.id / "result.nc").exists()
    ds = res.dataset
    assert math.isnan(float(ds["a"].sel(fail=True, x=1.0))) and float(ds["a"].sel(fail=False, x=2.0)) == 4.0
    assert json.loads((tmp_path / "sweep.json").read_text())["n_failed"] == 2
    # a re-run reuses the successes and tries the failed cases again
    again = run_sweep(run_case, cases, "serial", out_dir=tmp_path)
    assert (again.n_reused, again.n_computed, again.n_failed) == (2, 2, 2)


def test_rerun_computes_only_missing_cases(tmp_path):
    cases = _grid()
    run_sweep(run_case, cases, "serial", out_dir=tmp_path, figures=False)
    stamps = {c.id: (tmp_path / "cases" / c.id / "result.nc").stat().st_mtime_ns for c in cases}
    # as if interrupted: two cases never finished, one finished writing result.nc but not its marker
    import shutil

    shutil.rmtree(tmp_path / "cases" / cases[1].id)
    shutil.rmtree(tmp_path / "cases" / cases[4].id)
    (tmp_path / "cases" / cases[5].id / "case.json").unlink()
    seen = []
    res = run_sweep(
        run_case,
        cases,
        "serial",
        out_dir=tmp_path,
        figures=False,
        progress=lambda rec, done, total: seen.append(rec.id),
    )
    assert sorted(seen) == sorted([cases[1].id, cases[4].id, cases[5].id])
    assert res.n_computed == 3 and res.n_reused == 3 and res.n_failed == 0
    for i in (0, 2, 3):
        assert (tmp_path / "cases" / cases[i].id / "result.nc").stat().st_mtime_ns == stamps[cases[i].id]
    np.testing.assert_allclose(res.dataset["a"].values.ravel(), [c.params["x"] ** 2 + c.params["y"] for c in cases])


def test_killed_worker_case_is_retried_and_nothing_is_lost(tmp_path):
    marker = tmp_path / "killed-once"
    cases = grid_cases({**BASE, "sleep": 0.2, "kill_once": ""}, {"x": [0.5, 1.0, 1.5, 2.0, 2.5, 3.0]})
    # the fourth case kills its worker the first time it runs
    data = dict(cases[3].data, kill_once=str(marker))
    cases[3] = type(cases[3])(cases[3].id, cases[3].params, data)
    res = run_sweep(run_case, cases, 2, out_dir=tmp_path / "out", figures=False)
    assert marker.exists()
    assert res.n_failed == 0 and res.n_cases == 6
    assert res.records[3].attempts >= 2
    for c in cases:
        assert (tmp_path / "out" / "cases" / c.id / "result.nc").exists()
    np.testing.assert_allclose(res.dataset["a"].values, np.array([0.5, 1.0, 1.5, 2.0, 2.5, 3.0]) ** 2)


def test_case_that_always_kills_its_worker_fails_alone(tmp_path):
    cases = grid_cases({**BASE, "kill_always": False}, {"x": [1.0, 2.0, 3.0], "kill_always": [False]})
    bad = dict(cases[1].data, kill_always=True)
    cases[1] = type(cases[1])(cases[1].id, cases[1].params, bad)
    res = run_sweep(run_case, cases, 2, out_dir=tmp_path, max_retries=1, figures=False)
    assert [r.ok for r in res.records] == [True, False, True]
    assert "WorkerDied" in res.records[1].error and res.records[1].attempts >= 2
    assert (tmp_path / "cases" / cases[1].id / "error.txt").exists()


def test_list_of_cases_gives_a_case_dimension():
    res = run_sweep(run_case, [{"x": 2.0, "y": 1.0}, {"x": 1.0, "y": 3.0}], "serial")
    ds = res.dataset
    assert ds["a"].dims == ("case",) and ds.attrs["layout"] == "list"
    np.testing.assert_array_equal(ds["a"].values, [5.0, 4.0])
    np.testing.assert_array_equal(ds["x"].values, [2.0, 1.0])


def not_a_result(data):
    return {"value": data["x"]}


def test_case_function_returning_a_non_result_is_an_error():
    res = run_sweep(not_a_result, [{"x": 1.0}], "serial")
    assert res.n_failed == 1 and "not a Result" in res.records[0].error


def test_missing_dask_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)
    with pytest.raises(InputError) as err:
        with executor_for(2, "tcp://127.0.0.1:1"):
            pass
    assert "rotaflex[dask]" in str(err.value)


def test_bad_executor_arguments():
    with pytest.raises(InputError):
        with executor_for(-1, None):
            pass
    with pytest.raises(TypeError):
        run_sweep(run_case, [{"x": 1.0}], executor="threads")
