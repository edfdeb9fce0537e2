"""Start-up of the command line: whole-process times of a few verbs and what each one imports.

For each verb: wall and CPU time of the whole process (median of --repeats fresh processes),
the solver time the verb itself reports (``wall_time`` in summary.json, when it has one), and
whether it loaded the heavy modules it may not need (numba, sympy, scipy.integrate,
matplotlib, dask.distributed). ``--importtime VERB`` prints the slowest imports of one verb
(``python -X importtime``).

Targets (issue 25): ``--help`` <= 0.2 s, ``rotor campbell`` on the Friswell example <= 1 s,
the rotor disk's first solve <= 0.1 s as reported, numba not imported by verbs that compile
nothing. Bytecode is cached as an installed package's is (PYTHONDONTWRITEBYTECODE is unset).

Run: python benchmarks/bench_startup.py [--tree DIR] [--repeats N] [--importtime campbell]
(``benchmarks/compare.py`` uses these functions to compare two revisions.)
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: verb name -> rotaflex arguments; {ex} is the tree's examples/ directory, {out} a fresh output directory
VERBS: dict[str, list[str]] = {
    "help": ["--help"],
    "campbell": ["rotor", "campbell", "{ex}/rotor/fe_friswell_5_9_1.toml", "--out", "{out}"],
    "campbell-nofig": ["rotor", "campbell", "{ex}/rotor/fe_friswell_5_9_1.toml", "--out", "{out}", "--no-figures"],
    "disk": ["rotor", "simulate", "{ex}/rotor/disk_123_nonlinear.toml", "--out", "{out}"],
}

#: modules a verb should load only if it uses them
HEAVY = ("numba", "sympy", "scipy.integrate", "matplotlib", "distributed", "dask", "dask.array", "xarray")

#: run the CLI, then print the heavy modules it left in sys.modules (as JSON on the last stderr line)
_PROBE = (
    "import json, sys, runpy\n"
    "sys.argv = ['rotaflex'] + sys.argv[1:]\n"
    "try:\n"
    "    runpy.run_module('rotaflex', run_name='__main__')\n"
    "except SystemExit:\n"
    "    pass\n"
    "sys.stderr.write('\\n' + json.dumps([m for m in {heavy!r} if m in sys.modules]) + '\\n')\n"
)


def environment(tree: Path) -> dict[str, str]:
    """The environment of a CLI process running the rotaflex of ``tree`` (its src/ first)."""
    env = dict(os.environ)
    env["PYTHONPATH"] = str(tree / "src")
    env.pop("PYTHONDONTWRITEBYTECODE", None)  # as installed: bytecode cached after the first run
    env.setdefault("ROTAFLEX_BLAS_THREADS", "1")
    return env


def expand(args: list[str], tree: Path, out: Path) -> list[str]:
    """``args`` with {ex} and {out} filled in."""
    return [a.format(ex=tree / "examples", out=out) for a in args]


def run_process(args: list[str], tree: Path, *, probe: bool = False) -> dict[str, float]:
    """One fresh ``python -m rotaflex ARGS`` process of ``tree``.

    Returns wall time [s], CPU time (user + system of the child) [s], the solver time the
    verb reported in summary.json [s] if it wrote one, and with ``probe`` the heavy modules
    it imported (1.0 per module loaded, 0.0 if not).
    """
    with tempfile.TemporaryDirectory(prefix="rotaflex-bench-") as tmp:
        out = Path(tmp) / "out"
        argv = expand(args, tree, out)
        head = ["-c", _PROBE.format(heavy=HEAVY)] if probe else ["-m", "rotaflex"]
        cmd = [sys.executable, *head, *argv]
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        t0 = time.perf_counter()
        proc = subprocess.run(cmd, cwd=tree, env=environment(tree), capture_output=True, text=True)
        wall = time.perf_counter() - t0
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        if proc.returncode != 0:
            raise RuntimeError(f"{' '.join(argv)} failed in {tree} ({proc.returncode}): {proc.stderr.strip()[-500:]}")
        res = {"wall": wall, "cpu": (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)}
        summary = out / "summary.json"
        if summary.exists():
            reported = json.loads(summary.read_text()).get("wall_time", {}).get("value")
            if reported is not None:
                res["reported"] = float(reported)
        if probe:
            loaded = json.loads(proc.stderr.strip().splitlines()[-1])
            res.update({f"imports {m}": float(m in loaded) for m in HEAVY})
        return res


def importtime(args: list[str], tree: Path, top: int = 25) -> str:
    """The ``top`` slowest cumulative imports of one CLI process (``-X importtime``)."""
    with tempfile.TemporaryDirectory(prefix="rotaflex-bench-") as tmp:
        argv = expand(args, tree, Path(tmp) / "out")
        proc = subprocess.run(
            [sys.executable, "-X", "importtime", "-m", "rotaflex", *argv],
            cwd=tree,
            env=environment(tree),
            capture_output=True,
            text=True,
        )
    rows = []
    for line in proc.stderr.splitlines():
        if line.startswith("import time:") and "|" in line:
            _, cumulative, name = line.split("|")
            if cumulative.strip().isdigit():
                rows.append((int(cumulative), name.rstrip()))
    rows.sort(reverse=True)
    return "\n".join(f"  {us / 1e3:8.1f} ms  {name}" for us, name in rows[:top])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--tree", type=Path, default=ROOT, help="repository checkout to measure (default: this one)")
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--importtime", choices=list(VERBS), help="print the slowest imports of this verb and stop")
    a = ap.parse_args()
    tree = a.tree.resolve()
    if a.importtime:
        print(importtime(VERBS[a.importtime], tree))
        return
    for name, args in VERBS.items():
        run_process(args, tree)  # warm-up: bytecode, OS file cache, cached rotor equations
        runs = [run_process(args, tree) for _ in range(a.repeats)]
        loaded = run_process(args, tree, probe=True)
        wall = statistics.median(r["wall"] for r in runs)
        cpu = statistics.median(r["cpu"] for r in runs)
        text = f"{name:14s} process {wall:6.3f} s wall, {cpu:6.3f} s CPU (median of {a.repeats})"
        if "reported" in runs[0]:
            text += f"; solver as reported {statistics.median(r['reported'] for r in runs):6.3f} s"
        heavy = [m for m in HEAVY if loaded[f"imports {m}"]]
        print(text + "\n               imports: " + (", ".join(heavy) or "none of " + ", ".join(HEAVY)))
    print(f"load average during the run: {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")


if __name__ == "__main__":
    main()
