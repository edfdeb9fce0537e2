"""Sweep throughput: parallel efficiency on 8 equal cases and the overhead per case.

    PYTHONPATH=src python benchmarks/bench_sweep.py [--case-seconds 1.0] [--no-dask] [--tiny]

Cases are the selftest helper burning CPU (``work`` matrix products; calibrated so that one
case takes about ``--case-seconds`` in this process). Reported:

* efficiency = T_1 / (2 * T_2) for 8 equal cases, T_1 on one worker process and T_2 on two
  (pool start-up excluded, then included), and on a 2-worker Dask LocalCluster;
* overhead per case = wall time per case of a sweep of trivial cases (client-side writing of
  result.nc / summary.json / case.json included), serially and on 2 processes.

Numbers depend on the machine's load: the load average is printed beside them.
``--tiny``: 2 cases of about 0.05 s and 4 trivial ones, Dask included (checks the script runs).
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from pathlib import Path


def _cases(work: int, count: int, **extra):
    from rotaflex.sweep import grid_cases

    return grid_cases({"x": 1.0, "y": 0.5, "work": work, **extra}, {"x": [float(i + 1) for i in range(count)]})


def _timed(executor, cases, root: Path, tag: str) -> float:
    from rotaflex.sweep import run_sweep
    from rotaflex.sweep._selftest_case import run_case

    t0 = time.perf_counter()
    res = run_sweep(run_case, cases, executor, out_dir=root / tag, figures=False)
    dt = time.perf_counter() - t0
    assert res.n_failed == 0 and res.n_computed == len(cases), res.summary_text()
    _timed.case_times[tag] = [r.wall_time for r in res.records]
    return dt


_timed.case_times = {}


def _explain(tag: str, total: float, workers: int) -> str:
    """Mean case time on the worker, and the time not spent in cases (machinery overhead)."""
    times = _timed.case_times[tag]
    busy = sum(times) / workers
    return f"[mean case {sum(times) / len(times):.2f} s on its worker; not in cases {total - busy:+.2f} s]"


def _calibrate(seconds: float, probe: int = 400) -> int:
    """``work`` for one case of about ``seconds`` on a single-threaded worker process (from the
    time of a case of ``probe`` work)."""
    from rotaflex.sweep import process_pool
    from rotaflex.sweep._selftest_case import run_case
    from rotaflex.sweep._worker import execute_case

    pool = process_pool(1)
    try:
        pool.submit(execute_case, run_case, {"work": 20}).result()
        out = pool.submit(execute_case, run_case, {"work": probe}).result()
    finally:
        pool.shutdown()
    return max(1, int(seconds * probe / out.wall_time))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--case-seconds", type=float, default=1.0)
    ap.add_argument("--no-dask", action="store_true")
    ap.add_argument("--tiny", action="store_true", help="2 short cases, 4 trivial ones (checks it runs)")
    args = ap.parse_args()
    n_equal, n_trivial = (2, 4) if args.tiny else (8, 40)
    if args.tiny:
        args.case_seconds = 0.05

    from rotaflex.sweep import process_pool

    print(f"cores: {os.cpu_count()}, load average before: {os.getloadavg()}")
    work = _calibrate(args.case_seconds, 40 if args.tiny else 400)
    print(f"case size: work={work} (about {args.case_seconds:g} s each on one worker process)")
    root = Path(tempfile.mkdtemp(prefix="bench_sweep_"))
    eight = _cases(work, n_equal)

    t_inproc = _timed("serial", eight, root, "serial")
    pool = process_pool(1)
    try:  # reference: one worker process, single-threaded BLAS like the parallel workers
        t_serial = _timed(pool, _cases(work, n_equal, n=19), root, "pool1")
    finally:
        pool.shutdown()
    t0 = time.perf_counter()
    pool = process_pool(2)
    t_start = time.perf_counter() - t0
    try:
        t_pool = _timed(pool, eight, root, "pool2")
    finally:
        pool.shutdown()
    t_pool_cold = _timed(2, _cases(work, n_equal, n=17), root, "pool2cold")
    print(f"{n_equal} equal cases, in this process        : {t_inproc:7.2f} s  (multi-threaded BLAS)")
    print(
        f"{n_equal} equal cases, 1 worker process       : {t_serial:7.2f} s  (reference) "
        + _explain("pool1", t_serial, 1)
    )
    print(
        f"{n_equal} equal cases, 2 processes (warm pool): {t_pool:7.2f} s  efficiency "
        f"{t_serial / (2 * t_pool):6.1%} " + _explain("pool2", t_pool, 2)
    )
    print(
        f"{n_equal} equal cases, 2 processes, pool started inside (warm pool start {t_start:.2f} s): "
        f"{t_pool_cold:7.2f} s  "
        f"efficiency {t_serial / (2 * t_pool_cold):6.1%} " + _explain("pool2cold", t_pool_cold, 2)
    )

    trivial = _cases(0, n_trivial)
    t_triv_serial = _timed("serial", trivial, root, "triv_serial")
    pool = process_pool(2)
    try:
        t_triv_pool = _timed(pool, _cases(0, n_trivial, n=17), root, "triv_pool")
    finally:
        pool.shutdown()
    print(f"overhead per case, serial (write only): {1e3 * t_triv_serial / n_trivial:7.1f} ms")
    print(f"overhead per case, 2 processes        : {1e3 * t_triv_pool / n_trivial:7.1f} ms")

    if not args.no_dask:
        try:
            import distributed  # noqa: F401
        except ImportError:
            if args.tiny:  # the test environment (rotaflex[test]) has Dask: its part must run
                raise SystemExit("dask: not installed (pip install 'rotaflex[dask]'); --tiny runs it") from None
            print("dask: not installed (pip install 'rotaflex[dask]'), skipped")
        else:
            from rotaflex.sweep.backends import dask_executor

            t0 = time.perf_counter()
            # what `--scheduler dask-local -j 2` does
            with dask_executor("dask-local", n_workers=2) as ex:
                t_start = time.perf_counter() - t0
                t_triv_dask = _timed(ex, _cases(0, n_trivial, n=18), root, "triv_dask")  # warms up
                t_dask = _timed(ex, _cases(work, n_equal, n=18), root, "dask")
            print(
                f"{n_equal} equal cases, Dask LocalCluster 2 workers (start {t_start:.2f} s excluded): "
                f"{t_dask:7.2f} s  efficiency {t_serial / (2 * t_dask):6.1%} " + _explain("dask", t_dask, 2)
            )
            print(f"overhead per case, Dask 2 workers     : {1e3 * t_triv_dask / n_trivial:7.1f} ms")
    print(f"load average after: {os.getloadavg()}")
    print(
        "A mean case time above the 1-process reference means the workers did not get a full "
        "core each (CPU shared with other jobs): efficiency is then bounded by the free CPU, "
        "and 'not in cases' is the sweep machinery's own share."
    )


if __name__ == "__main__":
    main()
