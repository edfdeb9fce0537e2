"""First-run numba compilation of ``floating simulate`` for every example, with a fresh cache each.

For each ``examples/floating/*.toml``: one CLI process with an empty ``NUMBA_CACHE_DIR``; printed
are the process wall time, its CPU time (user + system, the figure that means something on a
shared machine), the time spent compiling (outermost compilations, numba's own compile events),
and the number of specialisations (signatures compiled) and kernels, plus the right-hand-side
kernels that were compiled. ``--src`` measures another tree (e.g. an extracted older revision).

Run: PYTHONPATH=src python benchmarks/bench_floating_compile.py [NAME ...] [--src DIR] [--tiny]

``--tiny`` runs ``torque_pulse_beam`` with numba's usual cache (warm after the first run)
instead of an empty one: an empty cache is what this script measures, and compiling from it
takes tens of seconds per example; tiny checks that the probe, the run and the table work.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
from bench_compile import _PROBE  # noqa: E402 - the compile-event probe shared with bench_compile


def cold_run(toml: Path, src: Path, empty_cache: bool = True) -> dict:
    """One ``floating simulate`` process on an empty numba cache (``empty_cache=False``: numba's
    usual cache): times and compile records."""
    with tempfile.TemporaryDirectory(prefix="rotaflex-floating-compile-") as tmp:
        rec = Path(tmp) / "records.json"
        argv = ["floating", "simulate", str(toml), "--out", str(Path(tmp) / "out"), "--no-figures", "--quiet"]
        env = {**os.environ, "PYTHONPATH": str(src)}
        if empty_cache:
            env["NUMBA_CACHE_DIR"] = str(Path(tmp) / "numba")
            Path(env["NUMBA_CACHE_DIR"]).mkdir()
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        t0 = time.perf_counter()
        proc = subprocess.run([sys.executable, "-c", _PROBE, str(rec), *argv], env=env, capture_output=True, text=True)
        wall = time.perf_counter() - t0
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        if proc.returncode != 0 or not rec.exists():
            raise RuntimeError(f"{toml.name} failed: {proc.stderr.strip()[-500:]}")
        data = json.loads(rec.read_text())
    recs = data["records"]
    return {
        "wall": wall,
        "cpu": (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime),
        "compiling": sum(r["total"] for r in recs if r["outer"]),
        "specialisations": len(recs),
        "kernels": len({r["kernel"] for r in recs}),
        "rhs": sorted({r["kernel"].rsplit(".", 1)[-1] for r in recs if "rhs" in r["kernel"]}),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("names", nargs="*", help="example names without .toml (default: all)")
    ap.add_argument("--src", type=Path, default=ROOT / "src", help="the tree to measure (default: this src/)")
    ap.add_argument("--tiny", action="store_true", help="torque_pulse_beam on the usual numba cache (checks it runs)")
    a = ap.parse_args()
    tomls = sorted((ROOT / "examples" / "floating").glob("*.toml"))
    if a.tiny:
        tomls = [t for t in tomls if t.stem == "torque_pulse_beam"]
    elif a.names:
        tomls = [t for t in tomls if t.stem in a.names]
    print(f"{'example':32s} {'wall [s]':>9s} {'CPU [s]':>8s} {'compiling [s]':>14s} {'spec.':>6s} {'kernels':>8s}  rhs")
    for toml in tomls:
        r = cold_run(toml, a.src, empty_cache=not a.tiny)
        print(
            f"{toml.stem:32s} {r['wall']:9.1f} {r['cpu']:8.1f} {r['compiling']:14.1f} {r['specialisations']:6d} "
            f"{r['kernels']:8d}  {', '.join(r['rhs'])}",
            flush=True,
        )
    print(f"load average at the end: {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")


if __name__ == "__main__":
    main()
