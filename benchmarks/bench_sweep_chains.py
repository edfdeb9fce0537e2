"""Continuation sweeps: wall and CPU time, whole up/down chains vs split ones, and the down branch.

    PYTHONPATH=src python benchmarks/bench_sweep_chains.py [--example gear|system] [--speeds 40] [-j 2]
    PYTHONPATH=src python benchmarks/bench_sweep_chains.py --base DIR [--rounds 3] [--modes split]
    PYTHONPATH=src python benchmarks/bench_sweep_chains.py --tiny

``gear``: examples/sweep/gear_dynamic_factor.toml over operation.speed_rpm 2000-22000 rpm;
``system``: examples/system/gearbox.toml with the ``steady`` verb over steady.speed_rpm
1000-5000 rpm, ``max_cycles = 50`` (docs/geared-rotor.md). Each runs twice on ``-j`` local processes: whole chains
(the down half from the top up case's state) and split ones (``split_down``: the down half from
the verb's own start at the top speed, next to the up half). Printed: wall time, CPU time of the
client process and of the workers on the cases (as the runner logs it; "n/a" for a tree whose
runner does not), the runner's breakdown (logged by ``rotaflex.sweep``), and the largest
difference of each summary scalar between the two down branches, beside the largest
cycle-to-cycle change of the cases (their distance from an exact steady state).

``--base DIR``: a second tree (``src/`` and ``examples/``, e.g. ``git archive REV | tar -x -C
DIR``) run interleaved with this one, ``--rounds`` times (A B, B A, ...), each sweep in a fresh
process; printed per mode: the median wall time of each tree and the median of the paired
ratios this/base.

``selftest``: the parallel efficiency of split chains on CPU-bound cases of a test verb.

``netcdf``: the CPU time of encoding one gear case's ``result.nc`` (a ``gear steady`` Result of
the gear example, 42 variables), xarray's own ``to_netcdf`` against rotaflex's
(:func:`rotaflex.core.io.write_netcdf`'s encoder with :func:`~rotaflex.core.io.h5_lookup_cache`),
alternated ``--rounds`` x 10 times each; and the CPU time of the whole ``Result.save`` without
figures (what a sweep writes per case).

``--tiny``: the gear example over 2 speeds on the coarse tooth mesh, whole and split chains on
``-j`` processes (checks the script runs; no second tree).

Numbers depend on the machine's load: the load average is printed beside them.
"""

from __future__ import annotations

import argparse
import logging
import os
import resource
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = {
    "gear": (ROOT / "examples/sweep/gear_dynamic_factor.toml", "operation.speed_rpm", 2000.0, 22000.0),
    "system": (ROOT / "examples/system/gearbox.toml", "steady.speed_rpm", 1000.0, 5000.0),
}

#: fixed overrides (as in docs/geared-rotor.md's measurement: 50 mesh cycles per steady state)
EXTRA = {"system": ["steady.max_cycles=50"]}
#: --tiny: overrides of the gear example (the coarse FE tooth mesh)
TINY_EXTRA = ["model.mesh_preset=coarse"]


def _config(example: str, root: Path = ROOT) -> dict:
    from rotaflex.core.config import load_toml

    path = root / EXAMPLES[example][0].relative_to(ROOT)
    cfg = dict(load_toml(path))
    if example == "system":
        cfg = {"domain": "system", "verb": "steady", **cfg}
    return cfg


def _cpu() -> float:
    """CPU time of this process [s] (its pool's workers are children of the fork server, not of
    this process: the runner reports theirs)."""
    me = resource.getrusage(resource.RUSAGE_SELF)
    return me.ru_utime + me.ru_stime


def _run(example: str, speeds: int, jobs: int, split: bool, out: Path, tree: Path = ROOT, extra: tuple = ()):
    """One sweep in a fresh process, with rotaflex and the example from ``tree`` (``extra``:
    more overrides)."""
    import multiprocessing as mp

    ctx = mp.get_context("spawn")
    q = ctx.Queue()
    p = ctx.Process(target=_child, args=(example, speeds, jobs, split, str(out), q, str(tree), list(extra)))
    p.start()
    res = q.get()
    p.join()
    return res


def _child(example, speeds, jobs, split, out, q, tree=str(ROOT), extra=()) -> None:
    import sys

    sys.path.insert(0, str(Path(tree) / "src"))  # before rotaflex is imported here or by the pool
    from rotaflex.sweep import sweep_config

    lines: list[str] = []

    class Keep(logging.Handler):
        def emit(self, record):
            lines.append(record.getMessage())

    log = logging.getLogger("rotaflex.sweep")
    log.setLevel(logging.INFO)
    log.addHandler(Keep())
    _, key, lo, hi = EXAMPLES[example]
    t0, c0 = time.perf_counter(), _cpu()
    res = sweep_config(
        _config(example, Path(tree)),
        [f"{key}={lo:g}:{hi:g}:{speeds}", *EXTRA.get(example, []), *extra],
        out,
        jobs,
        continuation=key,
        split_down=split,
        figures=True,
    )
    wall = time.perf_counter() - t0
    cpu = _cpu() - c0  # the pool's workers exited at its shutdown: their CPU is in RUSAGE_CHILDREN
    ds = res.dataset
    down = {k: ds[k].sel(direction="down").values.astype(float) for k in ds.data_vars if ds[k].dtype.kind == "f"}
    breakdown = next((s for s in lines if s.startswith("wall time:")), "")
    busy = sum(r.wall_time for r in res.records)
    q.put((wall, cpu, res.n_failed, breakdown, busy, down, _worker_cpu(breakdown)))


def _worker_cpu(breakdown: str) -> float:
    """The workers' CPU time on the cases from the runner's breakdown (NaN if not logged)."""
    import re

    m = re.search(r"\(([0-9.]+) s CPU on cases", breakdown)
    return float(m.group(1)) if m else float("nan")


def _compare(args, root: Path) -> None:
    """This tree and ``args.base`` interleaved: per mode, median walls and paired ratios."""
    import statistics

    trees = {"this": ROOT, "base": Path(args.base).resolve()}
    walls: dict[tuple[str, str], list[float]] = {}
    for r in range(args.rounds):
        for mode in args.modes.split(","):
            order = ["this", "base"] if r % 2 == 0 else ["base", "this"]
            for tag in order:
                load = os.getloadavg()[0]
                out = root / f"{tag}-{mode}-{r}"
                wall, cpu, failed, breakdown, busy, _, wcpu = _run(
                    args.example, args.speeds, args.jobs, mode == "split", out, trees[tag]
                )
                walls.setdefault((tag, mode), []).append(wall)
                print(
                    f"  round {r} {mode:5s} {tag}: {wall:6.1f} s wall, client CPU {cpu:5.1f} s, workers' CPU "
                    f"{wcpu:5.1f} s, sum of case times {busy:5.1f} s, {failed} failed (load {load:.1f})\n"
                    f"         {breakdown}",
                    flush=True,
                )
    for mode in args.modes.split(","):
        a, b = walls[("this", mode)], walls[("base", mode)]
        ratio = statistics.median(x / y for x, y in zip(a, b, strict=True))
        print(
            f"  {mode}: median wall this {statistics.median(a):.1f} s, base {statistics.median(b):.1f} s, "
            f"median paired ratio this/base {ratio:.2f} ({len(a)} rounds)"
        )


def _efficiency(values: int, work: int, root: Path) -> None:
    """Parallel efficiency T_1 / (2 T_2) of split chains (one chain per worker) on selftest cases
        burning CPU (``work`` 150 x 150 matrix products per case), pool start-up included (the fork
    server itself is started by an untimed warm-up sweep first)."""
    import functools

    from rotaflex.sweep import grid_cases, run_sweep
    from rotaflex.sweep.continuation import chain_cases, run_link

    grid = grid_cases({"x": 1.0, "y": 0.5, "work": work}, {"x": [float(i + 1) for i in range(values)]})
    fn = functools.partial(run_link, "rotaflex.sweep._selftest_case:run_chain")
    # warm-up: this process's fork server starts (and imports its preload) once, untimed
    warm, warm_chains = chain_cases(grid[:2], "x")
    run_sweep(fn, warm, 2, figures=False, chains=warm_chains)
    times = {}
    for tag, split, jobs in (("whole, 1 process", False, 1), ("whole, 2", False, 2), ("split, 2", True, 2)):
        cases, chains = chain_cases(grid, "x", split=split)
        load = os.getloadavg()[0]
        t0 = time.perf_counter()
        res = run_sweep(fn, cases, jobs, out_dir=root / tag.replace(", ", "_"), figures=False, chains=chains)
        times[tag] = time.perf_counter() - t0
        busy = sum(r.wall_time for r in res.records)
        assert res.n_failed == 0, res.summary_text()
        print(f"  {tag:17s}: {times[tag]:6.2f} s wall, sum of case times {busy:6.2f} s (load {load:.1f})")
    t1 = times["whole, 1 process"]
    for tag in ("whole, 2", "split, 2"):
        print(f"  efficiency {tag:9s} T_1 / (2 T_2) = {t1 / (2 * times[tag]):.0%}")


def _netcdf(rounds: int, root: Path) -> None:
    """CPU time per encoding of one gear case's result.nc: xarray's own vs rotaflex's."""
    import statistics

    from rotaflex.core.io import _netcdf_bytes, h5_lookup_cache
    from rotaflex.sweep._worker import run_target
    from rotaflex.sweep.study import plan_study

    study = plan_study(_config("gear"), ["operation.speed_rpm=2000:22000:4"], None, False)
    result = run_target(study.target, study.cases[2].data)
    ds = result.dataset

    def ours() -> bytes:
        with h5_lookup_cache():
            return _netcdf_bytes(ds)

    def theirs() -> bytes:
        return ds.to_netcdf(engine="h5netcdf")

    times: dict[str, list[float]] = {"xarray": [], "rotaflex": [], "save": []}
    ours(), theirs()  # imports, first-use caches

    def save() -> None:
        result.save(root / "case", figures=False)

    for _ in range(rounds * 10):
        for tag, fn in (("xarray", theirs), ("rotaflex", ours), ("save", save)):
            c0 = time.process_time()
            fn()
            times[tag].append(time.process_time() - c0)
    nvar = len(ds.variables)
    print(f"netcdf: one gear steady result, {nvar} variables, {ds.nbytes / 1e3:.0f} kB (load {os.getloadavg()[0]:.1f})")
    for tag, ts in times.items():
        print(f"  {tag:8s}: median {1e3 * statistics.median(ts):6.1f} ms CPU, min {1e3 * min(ts):6.1f} ms")
    ratio = statistics.median(a / b for a, b in zip(times["rotaflex"], times["xarray"], strict=True))
    print(f"  median paired ratio rotaflex/xarray: {ratio:.2f}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--example", choices=[*sorted(EXAMPLES), "selftest", "netcdf"], default="gear")
    ap.add_argument("--speeds", type=int, default=40)
    ap.add_argument("-j", "--jobs", type=int, default=2)
    ap.add_argument("--work", type=int, default=300, help="selftest: matrix products per case")
    ap.add_argument("--base", help="a second tree (src/, examples/) to run interleaved with this one")
    ap.add_argument("--rounds", type=int, default=3, help="--base, netcdf: rounds of paired runs")
    ap.add_argument("--modes", default="whole,split", help="--base: modes to run (whole, split)")
    ap.add_argument("--tiny", action="store_true", help="gear example, 2 speeds, coarse mesh (checks it runs)")
    args = ap.parse_args()
    extra = ()
    if args.tiny:
        args.example, args.speeds, args.base, extra = "gear", 2, None, TINY_EXTRA
    root = Path(tempfile.mkdtemp(prefix="bench_chains_"))
    if args.base:
        print(f"{args.example}: {args.speeds} speeds up and down, -j {args.jobs}, this tree vs {args.base}")
        _compare(args, root)
        return
    if args.example == "netcdf":
        _netcdf(args.rounds, root)
        return
    if args.example == "selftest":
        print(f"selftest: {args.speeds} values up and down ({2 * args.speeds} cases), work {args.work}")
        _efficiency(args.speeds, args.work, root)
        return
    print(f"{args.example}: {args.speeds} speeds up and down ({2 * args.speeds} cases), -j {args.jobs}")
    runs = {}
    for split in (False, True):
        tag = "split" if split else "whole"
        load = os.getloadavg()[0]
        wall, cpu, failed, breakdown, busy, down, wcpu = _run(
            args.example, args.speeds, args.jobs, split, root / tag, extra=extra
        )
        runs[tag] = down
        print(
            f"  {tag:5s}: {wall:6.1f} s wall, client CPU {cpu:5.1f} s, workers' CPU {wcpu:5.1f} s, sum of case "
            f"times {busy:6.1f} s, {failed} failed (load {load:.1f})\n         {breakdown}"
        )
    a, b = runs["whole"], runs["split"]
    change = np.nanmax(np.abs(a.get("change", np.array([np.nan]))))
    print(f"  down branch, whole vs split (largest case cycle-to-cycle change {change:.2e}):")
    for k in sorted(a):
        if k in b and a[k].shape == b[k].shape:
            d = np.nanmax(np.abs(a[k] - b[k])) if np.isfinite(a[k]).any() else float("nan")
            scale = np.nanmax(np.abs(a[k])) if np.isfinite(a[k]).any() else float("nan")
            print(f"    {k:28s} max |diff| {d:.3e}  (max |value| {scale:.3e})")


if __name__ == "__main__":
    main()
