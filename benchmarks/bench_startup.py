"""Start-up of the command line: whole-process times of a few verbs and what each one imports.

For each verb: wall and CPU time of the whole process (median of --repeats fresh processes),
the solver time the verb itself reports (``wall_time`` in summary.json, when it has one), and
whether it loaded the heavy modules it may not need (numba, sympy, scipy.integrate,
matplotlib, dask, dask.distributed). ``--importtime VERB`` prints the slowest imports of one
verb (``python -X importtime``) and each package's own import time; ``--phases VERB`` splits
the process time of one verb (CLI and config, verb modules, the verb's function, result.nc,
matplotlib import, building and drawing the figures).

Targets (issue 25): ``--help`` <= 0.2 s, ``rotor campbell`` on the Friswell example <= 1 s,
the rotor disk's first solve <= 0.1 s as reported, numba not imported by verbs that compile
nothing. Bytecode is cached as an installed package's is (PYTHONDONTWRITEBYTECODE is unset).

Run: python benchmarks/bench_startup.py [--tree DIR] [--repeats N] [--importtime VERB | --phases VERB] [--tiny]
(``benchmarks/compare.py`` uses these functions to compare two revisions; ``--tiny``: the ``help``
verb only, one repeat, checks the script runs.)
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
    """The ``top`` slowest cumulative imports of one CLI process (``-X importtime``), then each
    top-level package's own import time summed (what importing it costs beyond what it imports
    from other packages; ``-X importtime`` itself adds ~20 %)."""
    with tempfile.TemporaryDirectory(prefix="rotaflex-bench-") as tmp:
        argv = expand(args, tree, Path(tmp) / "out")
        proc = subprocess.run(
            [sys.executable, "-X", "importtime", "-m", "rotaflex", *argv],
            cwd=tree,
            env=environment(tree),
            capture_output=True,
            text=True,
        )
    rows, packages = [], {}
    for line in proc.stderr.splitlines():
        if line.startswith("import time:") and "|" in line:
            own, cumulative, name = line.split("|")
            if cumulative.strip().isdigit():
                rows.append((int(cumulative), name.rstrip()))
                package = name.strip().split(".")[0]
                packages[package] = packages.get(package, 0) + int(own.split(":")[1])
    rows.sort(reverse=True)
    text = [f"  {us / 1e3:8.1f} ms  {name}" for us, name in rows[:top]]
    text.append(f"own import time by top-level package (total {sum(packages.values()) / 1e3:.0f} ms):")
    ranked = sorted(packages.items(), key=lambda kv: -kv[1])
    text += [f"  {us / 1e3:8.1f} ms  {package}" for package, us in ranked[:12]]
    return "\n".join(text)


#: run the CLI with its phases timed; print {phase: seconds} as JSON on the last stderr line
_PHASES = """
import json, sys, time, runpy
t_start = time.perf_counter()
spent = {}

def timed(name, fn):
    def wrapper(*a, **k):
        t = time.perf_counter()
        try:
            return fn(*a, **k)
        finally:
            spent[name] = spent.get(name, 0.0) + time.perf_counter() - t
    return wrapper

import rotaflex.core.domains as domains, rotaflex.core.plotting as plotting, rotaflex.core.result as result
original_command = domains.command

def command(domain, verb):
    t = time.perf_counter()
    fn = original_command(domain, verb)
    spent["verb modules"] = time.perf_counter() - t
    return timed("analysis", fn)

domains.command = command
result.Result.to_netcdf = timed("result.nc", result.Result.to_netcdf)
result.Result.save = timed("save", result.Result.save)
for name in ("figure_types", "pyplot"):  # figure_types: figures without pyplot (older trees: pyplot)
    if hasattr(plotting, name):
        setattr(plotting, name, timed("matplotlib import", getattr(plotting, name)))
plotting.save_figure = timed("draw + PNG", plotting.save_figure)
sys.argv = ["rotaflex"] + sys.argv[1:]
try:
    runpy.run_module("rotaflex", run_name="__main__")
except SystemExit:
    pass
spent["in process"] = time.perf_counter() - t_start
sys.stderr.write("\\n" + json.dumps(spent) + "\\n")
"""

#: phases printed by --phases, in order: (label, how it is computed from the probe's numbers)
PHASE_ROWS = (
    ("interpreter start and exit", lambda p, wall: wall - p["in process"]),
    (
        "CLI, config, BLAS pinning (typer, numpy, scipy.linalg; main: also pydantic)",
        lambda p, wall: p["in process"] - p["verb modules"] - p.get("analysis", 0) - p.get("save", 0),
    ),
    ("verb modules (xarray, pandas, FE modules; main: also scipy.optimize)", lambda p, wall: p["verb modules"]),
    ("the verb's function: analysis, dataset (and imports made inside)", lambda p, wall: p.get("analysis", 0.0)),
    ("result.nc (h5netcdf)", lambda p, wall: p.get("result.nc", 0.0)),
    ("figures: matplotlib import", lambda p, wall: p.get("matplotlib import", 0.0)),
    ("figures: building them", lambda p, wall: p.get("save", 0) - p.get("result.nc", 0) - _figure_io(p)),
    ("figures: draw + PNG", lambda p, wall: p.get("draw + PNG", 0.0)),
)


def _figure_io(p: dict) -> float:
    return p.get("matplotlib import", 0.0) + p.get("draw + PNG", 0.0)


def phases(args: list[str], tree: Path, repeats: int) -> str:
    """Where one verb's process time goes: the median over ``repeats`` fresh processes of each
    phase (:data:`PHASE_ROWS`; "building them" includes summary.json, a few ms)."""
    rows: dict[str, list[float]] = {label: [] for label, _ in PHASE_ROWS}
    walls = []
    for i in range(repeats + 1):  # the first one is a warm-up
        with tempfile.TemporaryDirectory(prefix="rotaflex-bench-") as tmp:
            argv = expand(args, tree, Path(tmp) / "out")
            t0 = time.perf_counter()
            proc = subprocess.run(
                [sys.executable, "-c", _PHASES, *argv], cwd=tree, env=environment(tree), capture_output=True, text=True
            )
            wall = time.perf_counter() - t0
        if proc.returncode != 0:
            raise RuntimeError(f"{' '.join(argv)} failed ({proc.returncode}): {proc.stderr.strip()[-500:]}")
        if i == 0:
            continue
        spent = json.loads(proc.stderr.strip().splitlines()[-1])
        walls.append(wall)
        for label, how in PHASE_ROWS:
            rows[label].append(how(spent, wall))
    lines = [f"  {statistics.median(v):6.3f} s  {label}" for label, v in rows.items()]
    lines.append(f"  {statistics.median(walls):6.3f} s  whole process, wall (median of {repeats})")
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--tree", type=Path, default=ROOT, help="repository checkout to measure (default: this one)")
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--importtime", choices=list(VERBS), help="print the slowest imports of this verb and stop")
    ap.add_argument("--phases", choices=list(VERBS), help="print where this verb's process time goes and stop")
    ap.add_argument("--tiny", action="store_true", help="the help verb, one repeat (checks it runs)")
    a = ap.parse_args()
    verbs = {"help": VERBS["help"]} if a.tiny else VERBS
    if a.tiny:
        a.repeats = 1
    tree = a.tree.resolve()
    if a.importtime:
        print(importtime(VERBS[a.importtime], tree))
        return
    if a.phases:
        print(phases(VERBS[a.phases], tree, a.repeats))
        return
    for name, args in verbs.items():
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
