"""First-run numba compilation per verb: a fresh process with an empty NUMBA_CACHE_DIR.

For each case: the whole process time, the time spent compiling (outermost compilations), and
per kernel the number of specialisations (signatures compiled) and the compile time excluding
the kernels it compiled inside it ("self" time), largest first. Then the same command again
with the cache now warm, for the second-run time.

Run: python benchmarks/bench_compile.py [CASE ...] [--tiny]   (cases: see CASES; default all)
The printed tables are the source of the compile figures in docs/performance.md.

``--tiny`` runs the ``rotor-disk`` case with numba's usual cache (warm after the first run)
instead of an empty one: an empty cache is what this script measures, and compiling from it
takes tens of seconds per case; tiny checks that the probe, the runs and the report work.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from collections import defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: case -> rotaflex arguments ({ex}: examples/, {out}: a fresh output directory)
CASES: dict[str, list[str]] = {
    "gear-paper": ["gear", "simulate", "{ex}/gear/4000rpm.toml", "--out", "{out}", "--no-figures"],
    "gear-coarse": ["gear", "simulate", "{ex}/gear/coarse_fast.toml", "--out", "{out}", "--no-figures"],
    "gear-reduced": ["gear", "simulate", "{ex}/gear/4000rpm_reduced.toml", "--out", "{out}", "--no-figures"],
    "gear-steady": [
        "gear",
        "steady",
        "{ex}/gear/steady/torsional_dynamic_factor.toml",
        "--out",
        "{out}",
        "--no-figures",
    ],
    "floating": ["floating", "simulate", "{ex}/floating/spinup_beam.toml", "--out", "{out}", "--no-figures"],
    "rotor-disk": ["rotor", "simulate", "{ex}/rotor/disk_123_nonlinear.toml", "--out", "{out}", "--no-figures"],
}

#: runs the CLI with a listener on numba's compile events; writes the records as JSON to argv[1]
_PROBE = """
import json, sys, time, runpy
from numba.core import event
records, stack = [], []
class Listener(event.Listener):
    def on_start(self, ev):
        stack.append([time.perf_counter(), 0.0, time.process_time(), 0.0])
    def on_end(self, ev):
        t0, children, c0, cchildren = stack.pop()
        took = time.perf_counter() - t0
        cpu = time.process_time() - c0
        if stack:
            stack[-1][1] += took
            stack[-1][3] += cpu
        f = ev.data["dispatcher"].py_func
        records.append({"kernel": f.__module__ + "." + f.__qualname__, "sig": str(ev.data["args"]),
                        "total": took, "self": took - children, "cpu": cpu, "cpu_self": cpu - cchildren,
                        "outer": not stack})
event.register("numba:compile", Listener())
out = sys.argv[1]
sys.argv = ["rotaflex"] + sys.argv[2:]
code = 0
t0 = time.perf_counter()
try:
    runpy.run_module("rotaflex", run_name="__main__")
except SystemExit as exc:
    code = exc.code
with open(out, "w") as fh:
    json.dump({"records": records, "process": time.perf_counter() - t0, "code": code}, fh)
"""


def run(args: list[str], cache: Path | None) -> dict:
    """One CLI process with numba's cache in ``cache`` (None: numba's usual cache); its compile
    records and times."""
    with tempfile.TemporaryDirectory(prefix="rotaflex-compile-") as tmp:
        argv = [a.format(ex=ROOT / "examples", out=Path(tmp) / "out") for a in args]
        env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
        if cache is not None:
            env["NUMBA_CACHE_DIR"] = str(cache)
        rec = Path(tmp) / "records.json"
        t0 = time.perf_counter()
        proc = subprocess.run(
            [sys.executable, "-c", _PROBE, str(rec), *argv, "--quiet"], env=env, capture_output=True, text=True
        )
        wall = time.perf_counter() - t0
        if proc.returncode != 0 or not rec.exists():
            raise RuntimeError(f"{' '.join(argv)} failed: {proc.stderr.strip()[-500:]}")
        data = json.loads(rec.read_text())
        data["wall"] = wall
        return data


def report(name: str, cold: dict, warm: dict) -> str:
    recs = cold["records"]
    compiling = sum(r["total"] for r in recs if r["outer"])
    cpu = sum(r["cpu"] for r in recs if r["outer"])
    per: dict[str, dict] = defaultdict(lambda: {"n": 0, "self": 0.0, "cpu": 0.0, "sigs": []})
    for r in recs:
        p = per[r["kernel"]]
        p["n"] += 1
        p["self"] += r["self"]
        p["cpu"] += r["cpu_self"]
        p["sigs"].append(r["sig"])
    lines = [
        f"{name}: first run {cold['wall']:.1f} s (compiling {compiling:.1f} s wall, {cpu:.1f} s CPU: {len(recs)} "
        f"specialisations of {len(per)} kernels); second run {warm['wall']:.1f} s (compiling "
        f"{sum(r['total'] for r in warm['records'] if r['outer']):.1f} s)",
        f"  {'self [s]':>8s} {'CPU [s]':>8s} {'share':>6s} {'n':>3s}  kernel (share: of the compile CPU time)",
    ]
    for kernel, p in sorted(per.items(), key=lambda kv: -kv[1]["cpu"])[:15]:
        share = p["cpu"] / cpu if cpu else 0.0
        lines.append(f"  {p['self']:8.2f} {p['cpu']:8.2f} {share:6.0%} {p['n']:3d}  {kernel}")
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("cases", nargs="*", help="cases to run: " + ", ".join(CASES) + " (default: all)")
    ap.add_argument("--tiny", action="store_true", help="rotor-disk on the usual numba cache (checks it runs)")
    a = ap.parse_args()
    if a.tiny:
        cold = run(CASES["rotor-disk"], None)
        warm = run(CASES["rotor-disk"], None)
        print(report("rotor-disk (usual numba cache)", cold, warm))
        return
    names = a.cases or list(CASES)
    if unknown := set(names) - set(CASES):
        ap.error(f"unknown case(s) {', '.join(sorted(unknown))}; choose from {', '.join(CASES)}")
    for name in names:
        with tempfile.TemporaryDirectory(prefix="rotaflex-numba-cache-") as cache:
            cold = run(CASES[name], Path(cache))
            warm = run(CASES[name], Path(cache))
        print(report(name, cold, warm), flush=True)
    print(f"load average at the end: {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")


if __name__ == "__main__":
    main()
