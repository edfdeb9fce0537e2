"""Geared rotor system timings (printed, never asserted): two FE rotors of 20 elements each and
one mesh (the example gearbox refined): Campbell over 50 speeds, linear TE response at 500
speeds, nonlinear steady state per speed (50 mesh cycles), each with its accuracy against the
unreduced solve, and the 40-speed up/down continuation sweep of nonlinear steady states (at
most 50 mesh cycles each, contact-pattern mesh) on 2 local workers with ``--split-down``: wall
time, CPU time of the whole process tree (client, fork server, workers; polled with psutil),
the runner's breakdown (starting workers, running cases, of which the client writing case
files, combining), the sum of the cases' own times and the load average before and after. One
BLAS thread (set before numpy loads).

Run: python benchmarks/bench_geared_rotor.py [--sweep-only] [--speeds 40] [-j 2] [--whole] [--tiny]
(``--tiny``: 5 Campbell speeds, 10 response speeds, 20-cycle steady states, one repeat, and the
sweep over 2 speeds with 20-30 cycles each; checks the script runs.)
"""

from __future__ import annotations

import contextlib
import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from rotaflex.core.config import load_toml  # noqa: E402
from rotaflex.system.modal import campbell  # noqa: E402
from rotaflex.system.model import MODEL_KEYS, Gearbox  # noqa: E402
from rotaflex.system.response import forced_response  # noqa: E402
from rotaflex.system.steady import SteadySettings, steady_state  # noqa: E402

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "system" / "gearbox.toml"
RPM = np.pi / 30
#: repeats of every timing (--tiny: 1)
REPEAT: int | None = None


def config(source: str = "harmonic") -> dict:
    """The example gearbox's config with 20 elements per shaft (gear at node 10, bearings at 2
    and 18)."""
    cfg = load_toml(EXAMPLE)
    for r in cfg["rotor"]:
        r["shaft"][0]["elements"] = 20
        for b, node in zip(r["bearing"], (2, 18), strict=True):
            b["node"] = node
    m = cfg["gear_mesh"][0]
    m.update(pinion_node=10, wheel_node=10)
    if source == "harmonic":
        m.update(source="harmonic", k_mean=3.9e8, k_harmonics=[6e7, 2e7], te_harmonics=[2e-6, 5e-7])
    cfg["load"]["node"] = 20
    for probe in cfg["response"]["probes"]:
        probe["node"] = 10
    return cfg


def model(source: str = "harmonic") -> Gearbox:
    """:func:`config` built."""
    return Gearbox.from_mapping({k: v for k, v in config(source).items() if k in MODEL_KEYS})


def timed(fn, *a, repeat=3, **kw):
    """Best of ``repeat`` runs: CPU time of this process (what a loaded machine does not inflate;
    one BLAS thread) and wall time, printed together."""
    best, wall, out = np.inf, np.inf, None
    for _ in range(REPEAT or repeat):
        t0, c0 = time.perf_counter(), time.process_time()
        out = fn(*a, **kw)
        best = min(best, time.process_time() - c0)
        wall = min(wall, time.perf_counter() - t0)
    print(f"  [{getattr(fn, '__name__', fn)}: cpu {best:.3f} s, wall {wall:.3f} s]")
    return best, out


def _sweep_child(out: str, speeds: int, jobs: int, split: bool, q, cycles: tuple[int, int] = (20, 40)) -> None:
    """One continuation sweep in a fresh process; puts (wall, breakdown, case times, failed)."""
    import logging

    from rotaflex.sweep import sweep_config

    lines: list[str] = []

    class Keep(logging.Handler):
        def emit(self, record):
            lines.append(record.getMessage())

    log = logging.getLogger("rotaflex.sweep")
    log.setLevel(logging.INFO)
    log.addHandler(Keep())
    cfg = {"domain": "system", "verb": "steady", **config("contact_pattern")}
    cfg["steady"] = {"speed_rpm": 1000.0, "min_cycles": cycles[0], "max_cycles": cycles[1], "eval_cycles": 10}
    t0 = time.perf_counter()
    res = sweep_config(
        cfg, [f"steady.speed_rpm=1000:5000:{speeds}"], out, jobs, continuation="steady.speed_rpm", split_down=split
    )
    wall = time.perf_counter() - t0
    breakdown = next((ln for ln in lines if ln.startswith("wall time:")), "")
    times = [r.wall_time for r in res.records]
    cycles = res.dataset["cycles"].values if "cycles" in res.dataset else np.array([np.nan])
    q.put((wall, breakdown, times, res.n_failed, float(np.nanmax(cycles))))


def sweep(speeds: int = 40, jobs: int = 2, split: bool = True, cycles: tuple[int, int] = (20, 40)) -> None:
    """The up/down continuation sweep in a spawned process; CPU of its whole process tree
    (``cycles``: the fewest and most mesh cycles per steady state)."""
    import multiprocessing as mp
    import queue
    import tempfile

    import psutil

    out = Path(tempfile.mkdtemp(prefix="bench_geared_sweep_")) / "sweep"
    ctx = mp.get_context("spawn")
    q = ctx.Queue()
    load0 = os.getloadavg()
    p = ctx.Process(target=_sweep_child, args=(str(out), speeds, jobs, split, q, cycles))
    p.start()
    root = psutil.Process(p.pid)
    cpu: dict[int, float] = {}
    res = None
    while res is None:
        try:
            for proc in [root, *root.children(recursive=True)]:
                with contextlib.suppress(psutil.Error):
                    t = proc.cpu_times()
                    cpu[proc.pid] = t.user + t.system
        except psutil.Error:
            pass
        try:
            res = q.get(timeout=0.1)
        except queue.Empty:
            if not p.is_alive():
                raise RuntimeError("the sweep process died") from None
    p.join()
    wall, breakdown, times, failed, cycles = res
    load1 = os.getloadavg()
    tag = "split" if split else "whole"
    print(
        f"sweep {speeds} speeds up/down ({2 * speeds} steady states, <= {cycles:.0f} mesh cycles each), -j {jobs}, "
        f"{tag} chains: {wall:.1f} s wall (target <= 60 s), {sum(cpu.values()):.1f} s CPU all processes "
        f"({cpu.get(p.pid, np.nan):.1f} s of it the client), "
        f"{failed} failed; load average {load0[0]:.1f} before, {load1[0]:.1f} after\n"
        f"  cases: sum {np.nansum(times):.1f} s, median {np.nanmedian(times):.2f} s, max {np.nanmax(times):.2f} s "
        f"(wall in the case function)\n  runner: {breakdown}"
    )


def main() -> None:
    import argparse

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sweep-only", action="store_true")
    ap.add_argument("--no-sweep", action="store_true")
    ap.add_argument("--speeds", type=int, default=40)
    ap.add_argument("-j", "--jobs", type=int, default=2)
    ap.add_argument("--whole", action="store_true", help="whole up/down chains instead of --split-down")
    ap.add_argument("--tiny", action="store_true", help="few speeds and cycles, one repeat (checks it runs)")
    args = ap.parse_args()
    global REPEAT
    REPEAT = 1 if args.tiny else None
    if not args.sweep_only:
        solvers(args.tiny)
    if not args.no_sweep:
        speeds = 2 if args.tiny else args.speeds
        sweep(speeds, args.jobs, not args.whole, (20, 30) if args.tiny else (20, 40))


def solvers(tiny: bool = False) -> None:
    box = model()
    n_camp, n_resp, cycles = (5, 10, 20) if tiny else (50, 500, 40)
    print(f"model: 2 rotors x 20 elements, {box.n_dof} DOFs, one mesh")
    sp = np.linspace(0.0, 6000.0, n_camp) * RPM
    t, c = timed(campbell, box, sp, 16)
    tf, cf = timed(campbell, box, sp, 16, reduce=False, repeat=1)
    d = np.max(np.abs(np.sort(c.modes.wd, 1) - np.sort(cf.modes.wd, 1)) / np.sort(cf.modes.wd, 1))
    print(
        f"campbell {n_camp} speeds x 16 modes: {t:.3f} s reduced (target <= 1 s), {tf:.3f} s all DOFs; "
        f"max relative frequency difference {d:.1e}"
    )
    sp = np.linspace(100.0, 6000.0, n_resp) * RPM
    t, r = timed(forced_response, box, sp, harmonics=3, probes=[(0, 10), (1, 10)])
    tf, rf = timed(forced_response, box, sp, harmonics=3, probes=[(0, 10), (1, 10)], cutoff=None, repeat=1)
    errs = {
        k: np.max(np.abs(getattr(r, k) - getattr(rf, k))) / np.max(np.abs(getattr(rf, k)))
        for k in ("dte", "mesh_force", "bearing_force")
    }
    print(
        f"TE response {n_resp} speeds x 3 harmonics: {t:.3f} s reduced (target <= 1 s), {tf:.3f} s all DOFs; "
        "max difference / peak: " + ", ".join(f"{k} {v:.1e}" for k, v in errs.items())
    )
    st = SteadySettings(min_cycles=cycles, max_cycles=cycles, check_every=cycles, eval_cycles=10)
    steady_state(box, 300.0, st)  # compile / load the kernel cache
    for source in ("harmonic", "contact_pattern"):
        b = model(source)
        t, s = timed(steady_state, b, 300.0, st)
        print(
            f"steady state, {source} mesh, {cycles + 10} mesh cycles at 2865 rpm: {t:.3f} s (target <= 0.5 s); "
            f"{s.steps_per_cycle} steps/cycle, basis {s.basis_size}, energy balance error {s.energy_error:.1e}"
        )


if __name__ == "__main__":
    main()
