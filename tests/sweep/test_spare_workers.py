"""Workers a sweep would leave idle: one continuation chain on two processes (a pool of its own
writes the case files), and the sweep figures drawn by the client and the workers at once."""

import logging
import re
from concurrent.futures import Future
from concurrent.futures.process import BrokenProcessPool

import matplotlib.image as mpimg
import numpy as np
import xarray as xr

from rotaflex.sweep import run_sweep, sweep_config
from rotaflex.sweep.backends import _Backend, _n_workers, process_pool
from rotaflex.sweep.figures import DOMAIN_PART, draw_sweep_figures, split_parts

CHAIN = {"domain": "selftest", "verb": "chain", "x": 1.0, "y": 0.0}


def _chain_sweep(tmp_path, monkeypatch, name, jobs, **extra):
    from rotaflex.core import domains

    monkeypatch.setitem(domains.COMMANDS, "selftest", {"chain": "rotaflex.sweep._selftest_case:run_chain"})
    return sweep_config({**CHAIN, **extra}, ["x=1,2,3,4"], tmp_path / name, jobs, continuation="x", figures=False)


def test_one_chain_on_two_processes_has_a_writer_pool(tmp_path):
    backend = _Backend(2, case_files=(tmp_path, False), streams=1)
    try:
        assert backend.writer is not None and not backend.workers_write
        assert _n_workers(backend.executor) == 1 and _n_workers(backend.writer) == 1  # computes, writes
    finally:
        backend.shutdown()
    backend = _Backend(2, case_files=(tmp_path, False), streams=2)  # a chain per worker
    try:
        assert backend.writer is None and backend.workers_write
    finally:
        backend.shutdown()


def test_one_chain_written_by_the_spare_worker_equals_serial(tmp_path, monkeypatch, selftest_domain, caplog):
    """Running sums of x = 1, 2, 3, 4 up then down: 1, 3, 6, 10, then 14, 17, 19, 20; the same
    result files as a serial run, also when the first case kills its computing worker once."""
    caplog.set_level(logging.INFO, logger="rotaflex.sweep")
    kill = tmp_path / "killed-once"
    res = _chain_sweep(tmp_path, monkeypatch, "pool", 2, kill_once=str(kill))
    assert res.n_failed == 0 and kill.exists()
    ds = res.dataset
    np.testing.assert_array_equal(ds["running_sum"].sel(direction="up").values, [1.0, 3.0, 6.0, 10.0])
    np.testing.assert_array_equal(ds["running_sum"].sel(direction="down").values, [20.0, 19.0, 17.0, 14.0])
    line = next(r.getMessage() for r in caplog.records if r.getMessage().startswith("wall time:"))
    # some cases were written by the writer pool (the client writes when it is busy)
    assert float(re.search(r"the workers spent ([0-9.]+) s writing", line).group(1)) > 0
    ref = _chain_sweep(tmp_path, monkeypatch, "serial", "serial", kill_once=str(kill))  # exists: no kill
    assert ref.n_failed == 0
    for rec in res.records:
        with (
            xr.open_dataset(tmp_path / "pool" / "cases" / rec.id / "result.nc") as a,
            xr.open_dataset(tmp_path / "serial" / "cases" / rec.id / "result.nc") as b,
        ):
            xr.testing.assert_identical(a.drop_attrs(), b.drop_attrs())
        assert (tmp_path / "pool" / "cases" / rec.id / "case.json").exists()


def test_split_parts_balances_the_pages():
    """Two 10-panel pages and two small parts on the client and one worker that pays 5 for its
    first figure: the client takes a big page first, the worker the other, the small ones go
    where the load is least."""
    costs = {DOMAIN_PART: 3.0, "a": 10.0, "b": 10.0, "d": 3.0}
    client, worker = split_parts(costs, 1)
    assert sorted(client + worker) == sorted(costs)
    load = [sum(costs[p] for p in client), 5.0 + sum(costs[p] for p in worker)]
    assert max(load) - min(load) <= 3.0  # no move of a small part would balance it better
    assert split_parts(costs, 0) == [sorted(costs, key=lambda p: -costs[p])]


def _dataset(tmp_path):
    res = run_sweep(
        __import__("rotaflex.sweep._selftest_case", fromlist=["run_case"]).run_case,
        [{"x": float(x), "y": 0.5} for x in range(1, 5)],
        "serial",
        figures=False,
    )
    return res.dataset


def _pixels(paths):
    return {p.name: mpimg.imread(p) for p in paths}


def test_figures_drawn_by_the_workers_equal_one_process(tmp_path):
    ds = _dataset(tmp_path)
    alone = draw_sweep_figures(ds, "selftest", tmp_path / "alone")
    pool = process_pool(2)
    try:
        shared = draw_sweep_figures(ds, "selftest", tmp_path / "shared", [(pool, 2)])
    finally:
        pool.shutdown()
    assert [p.name for p in shared] == [p.name for p in alone] and len(alone) >= 2
    a, b = _pixels(alone), _pixels(shared)
    for name in a:
        np.testing.assert_array_equal(a[name], b[name], err_msg=name)


class _BrokenPool:
    """An executor whose every task fails as a died worker does."""

    def submit(self, *args, **kwargs):
        fut = Future()
        fut.set_exception(BrokenProcessPool("gone"))
        return fut


def test_figures_of_a_failed_worker_are_drawn_here(tmp_path):
    ds = _dataset(tmp_path)
    alone = draw_sweep_figures(ds, "selftest", tmp_path / "alone")
    again = draw_sweep_figures(ds, "selftest", tmp_path / "again", [(_BrokenPool(), 2)])
    assert [p.name for p in again] == [p.name for p in alone]
    assert all(p.exists() for p in again)


def test_a_writer_pool_that_breaks_leaves_the_writing_to_the_client(tmp_path, monkeypatch, selftest_domain, caplog):
    """Every write task fails as a died writer process does: the client writes those cases
    itself, every case is done, and the sums are those of the closed form."""
    monkeypatch.setattr(_Backend, "submit_write", lambda self, case, outcome: _BrokenPool().submit())
    caplog.set_level(logging.WARNING, logger="rotaflex.sweep")
    res = _chain_sweep(tmp_path, monkeypatch, "broken", 2)
    assert res.n_failed == 0
    np.testing.assert_array_equal(res.dataset["running_sum"].sel(direction="up").values, [1.0, 3.0, 6.0, 10.0])
    assert all((tmp_path / "broken" / "cases" / r.id / "result.nc").exists() for r in res.records)
    assert any("writing the cases here" in r.getMessage() for r in caplog.records)
