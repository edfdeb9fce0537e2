"""Case files written by the workers: the done-marker protocol and the netCDF they write."""

import json
import os
import pickle
from concurrent.futures import Executor, Future, ThreadPoolExecutor
from pathlib import Path

import numpy as np
import write_fault_case
import xarray as xr
from h5py import File as H5File

from rotaflex.core.io import WriteFailed, h5_lookup_cache, write_netcdf
from rotaflex.core.result import Result
from rotaflex.sweep import grid_cases, run_sweep
from rotaflex.sweep._selftest_case import run_case
from rotaflex.sweep._worker import WriteTo, execute_case
from rotaflex.sweep.backends import _Backend
from rotaflex.sweep.runner import _read_done

BASE = {"x": 1.0, "y": 0.0, "n": 16, "sleep": 0.0}


def _faulty_cases(tmp_path, fault):
    """Three cases; the second fails as ``fault`` while its files are written (flag set)."""
    flag = tmp_path / "fault-on"
    flag.touch()
    cases = grid_cases({**BASE, "fault": "", "fault_flag": str(flag)}, {"x": [1.0, 2.0, 3.0]})
    bad = dict(cases[1].data, fault=fault)
    cases[1] = type(cases[1])(cases[1].id, cases[1].params, bad)
    return cases, flag


def _check_not_done_then_resumed(tmp_path, cases, flag, res, error_word):
    out = tmp_path / "out"
    bad = out / "cases" / cases[1].id
    assert [r.ok for r in res.records] == [True, False, True]
    assert error_word in res.records[1].error
    # not done: its marker says error, and no result.nc was swapped into its directory
    assert json.loads((bad / "case.json").read_text())["state"] == "error"
    assert not (bad / "result.nc").exists()
    assert _read_done(cases[1], bad) is None
    flag.unlink()
    res2 = run_sweep(write_fault_case.run_case, cases, 1, out_dir=out, figures=False)
    assert res2.n_failed == 0 and res2.n_computed == 1 and res2.n_reused == 2
    assert res2.records[1].computed
    assert _read_done(cases[1], bad) is not None
    # the working directory of the killed write is gone (its owner is dead)
    assert not [p for p in (out / "cases").iterdir() if p.name.startswith(".")]
    np.testing.assert_allclose(res2.dataset["a"].values, [1.0, 4.0, 9.0])


def test_case_whose_worker_raised_while_writing_is_not_done_and_rerun(tmp_path):
    cases, flag = _faulty_cases(tmp_path, "raise")
    res = run_sweep(write_fault_case.run_case, cases, 1, out_dir=tmp_path / "out", figures=False)
    _check_not_done_then_resumed(tmp_path, cases, flag, res, "write_extra asked to fail")


def test_case_whose_worker_died_while_writing_is_not_done_and_rerun(tmp_path):
    cases, flag = _faulty_cases(tmp_path, "kill")
    res = run_sweep(write_fault_case.run_case, cases, 1, out_dir=tmp_path / "out", figures=False, max_retries=0)
    assert res.records[1].attempts >= 1
    _check_not_done_then_resumed(tmp_path, cases, flag, res, "WorkerDied")


def test_files_written_by_a_worker_without_the_marker_are_recomputed(tmp_path):
    # as if the client was killed after the worker wrote the case and before its case.json
    case = grid_cases(BASE, {"x": [2.0]})[0]
    case_dir = tmp_path / "cases" / case.id
    outcome = execute_case(run_case, case.data, write_to=WriteTo(str(case_dir)))
    assert outcome.written and outcome.result.summary()["a"]["value"] == 4.0
    assert (case_dir / "result.nc").exists() and not (case_dir / "case.json").exists()
    assert _read_done(case, case_dir) is None
    res = run_sweep(run_case, [case], 1, out_dir=tmp_path, figures=False)
    assert res.n_computed == 1 and json.loads((case_dir / "case.json").read_text())["state"] == "done"


class InlineRemote(Executor):
    """Runs calls at once in this process, but is not a local executor to the runner (as a Dask
    executor, whose workers may not share the file system)."""

    def __init__(self):
        self.calls = []

    def submit(self, fn, /, *args, **kwargs):
        self.calls.append(kwargs)
        fut = Future()
        fut.set_result(fn(*args, **kwargs))
        return fut


def test_non_local_executor_sends_results_back_and_the_client_writes(tmp_path):
    ex = InlineRemote()
    assert not _Backend(ex, case_files=(tmp_path, False)).workers_write
    assert _Backend("serial", case_files=(tmp_path, False)).workers_write
    assert not _Backend("serial").workers_write  # no output directory
    with ThreadPoolExecutor(2) as pool:  # one chain on two workers: the client writes
        assert not _Backend(pool, case_files=(tmp_path, False), streams=1).workers_write
        assert _Backend(pool, case_files=(tmp_path, False), streams=2).workers_write
    cases = grid_cases(BASE, {"x": [1.0, 2.0]})
    res = run_sweep(run_case, cases, ex, out_dir=tmp_path / "out", figures=False)
    assert res.n_failed == 0 and all("write_to" not in kw for kw in ex.calls)
    for c in cases:
        assert _read_done(c, tmp_path / "out" / "cases" / c.id) is not None


def test_write_failed_pickles_with_its_message():
    err = WriteFailed("result.nc", OSError(28, "No space left on device"), "the earlier result in x is intact")
    back = pickle.loads(pickle.dumps(err))
    assert type(back) is WriteFailed and str(back) == str(err) and back.cause.errno == 28


def _rich_dataset():
    """Variables of the kinds results hold: a coordinate per dimension, a string coordinate, a
    dimension without coordinate, an empty one, scalars, integers, attributes of several types."""
    rng = np.random.default_rng(3)
    t = np.linspace(0.0, 1.0, 50)
    return xr.Dataset(
        {
            "dte": ("time", rng.normal(size=50), {"units": "m", "long_name": "transmission error"}),
            "force": (("time", "gear"), rng.normal(size=(50, 2)), {"units": "N"}),
            "state": ("chain_node", np.array([1.5, 2.5]), {"units": "rad"}),
            "modal": ("modal_dof", np.zeros(0), {"units": "1"}),
            "shape": (("mode", "dof"), rng.normal(size=(3, 4))),
            "count": ((), np.int64(7), {"units": "1"}),
            "peak": ((), 3.25, {"units": "m"}),
            "flag": ("gear", np.array([True, False])),
        },
        coords={
            "time": ("time", t, {"units": "s"}),
            "gear": ("gear", np.array(["pinion", "wheel"])),
            "chain_node": ("chain_node", np.array(["pinion", "wheel"])),
            "mode": ("mode", np.arange(3)),
        },
        attrs={"status": "success", "wall_time": 0.125, "n": 41, "config": json.dumps({"a": [1, 2]})},
    )


def _structure(path):
    """Every HDF5 object of a file: kind, dtype, shape, data and attributes (dimension-scale
    references resolved to the names they point at)."""
    out = {}
    with H5File(path, "r") as f:

        def attrs(obj):
            res = {}
            for k in obj.attrs:
                v = obj.attrs[k]
                if k == "DIMENSION_LIST":
                    v = [[f[r].name for r in refs] for refs in v]
                elif k == "REFERENCE_LIST":
                    v = sorted((f[r].name, int(i)) for r, i in v)
                res[k] = repr(v)
            return res

        def visit(name, obj):
            data = repr(obj[()]) if hasattr(obj, "dtype") else None
            kind, dtype, shape = type(obj).__name__, str(getattr(obj, "dtype", "")), getattr(obj, "shape", None)
            out[name] = (kind, dtype, shape, data, attrs(obj))

        f.visititems(visit)
        out["/"] = attrs(f)
    return out


def test_result_nc_written_the_new_way_reads_as_xarrays_own(tmp_path):
    ds = _rich_dataset()
    write_netcdf(tmp_path / "ours.nc", ds)
    res = Result(ds.copy())
    res.save(tmp_path / "case", figures=False)  # adds the provenance attributes to res.dataset
    pairs = {"ours.nc": ds, "case/result.nc": res.dataset}
    for name, source in pairs.items():
        ref = tmp_path / f"xarray-{name.replace('/', '-')}"
        source.to_netcdf(ref, engine="h5netcdf")  # xarray's own writer, no lookup cache
        for engine in ("h5netcdf", None):
            with xr.open_dataset(ref, engine=engine) as want, xr.open_dataset(tmp_path / name, engine=engine) as got:
                xr.testing.assert_identical(got.load(), want.load())
        assert _structure(tmp_path / name) == _structure(ref)
    assert res.dataset.attrs["rotaflex_version"] and res.dataset.attrs["result_kind"] == "generic"


def test_lookup_cache_restores_h5netcdf_and_nests(tmp_path):
    import h5netcdf.core
    import h5netcdf.dimensions

    before = (h5netcdf.core.BaseObject._h5ds, h5netcdf.core.Group._h5group, h5netcdf.dimensions.Dimension._h5ds)
    ds = _rich_dataset()
    with h5_lookup_cache():
        assert h5netcdf.core.BaseObject._h5ds is not before[0]
        with h5_lookup_cache():
            write_netcdf(tmp_path / "a.nc", ds)
        assert h5netcdf.core.BaseObject._h5ds is not before[0]  # the outer context still holds
    after = (h5netcdf.core.BaseObject._h5ds, h5netcdf.core.Group._h5group, h5netcdf.dimensions.Dimension._h5ds)
    assert after == before
    assert os.path.getsize(tmp_path / "a.nc") > 0


def _dask_loaded_after_a_dataset() -> bool:
    xr.Dataset({"v": ("x", np.zeros(2))}, coords={"x": [0.0, 1.0]})
    import sys

    return "dask" in sys.modules


def test_local_workers_build_datasets_without_importing_dask():
    from rotaflex.sweep.backends import process_pool

    pool = process_pool(1)
    try:
        assert pool.submit(_dask_loaded_after_a_dataset).result() is False
    finally:
        pool.shutdown()


def test_full_disk_in_a_worker_or_the_client_ends_the_sweep(tmp_path, monkeypatch):
    import pytest

    import rotaflex.core.result as result_module

    def full(path, dataset):
        raise WriteFailed(Path(path).name, OSError(28, "No space left on device"))

    monkeypatch.setattr(result_module, "write_netcdf", full)
    cases = grid_cases(BASE, {"x": [1.0, 2.0]})
    for executor in ("serial", InlineRemote()):  # the worker writes; the client writes
        out = tmp_path / type(executor).__name__
        with pytest.raises(WriteFailed, match="no space left on device while writing result.nc"):
            run_sweep(run_case, cases, executor, out_dir=out, figures=False)
        assert not list((out / "cases").glob("*/case.json"))  # nothing marked done


def test_case_figures_are_drawn_by_the_worker_that_writes_the_case(tmp_path):
    cases = grid_cases({**BASE, "y": 2.0}, {"x": [1.0, 2.0]})
    res = run_sweep(run_case, cases, 1, out_dir=tmp_path, figures=False, case_figures=True)
    assert res.n_failed == 0
    for c in cases:
        pngs = list((tmp_path / "cases" / c.id).glob("*.png"))
        assert pngs and all(p.stat().st_size > 1000 for p in pngs)
        assert json.loads((tmp_path / "cases" / c.id / "case.json").read_text())["worker"].split(":")[-1] != str(
            os.getpid()
        )
