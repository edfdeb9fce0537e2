"""Compare the working tree with a git revision on the same benchmarks: interleaved, paired.

The revision is checked out into a temporary worktree (``git worktree add --detach``, removed
afterwards). Every benchmark is one fresh process (``python -m rotaflex ...``) run with each
tree's own src/ and examples/; after one discarded warm-up per tree (bytecode, numba cache,
the rotor equation cache, OS file cache), the two trees alternate N times (A B, B A, A B, ...)
so that load drifting over the run hits both alike. Printed per metric: the median of each
tree, and the median of the N paired ratios working/REV (< 1: the working tree is faster).

Metrics of a process: ``wall`` and ``cpu`` (user + system of the child) [s], and ``reported``:
the solver time the verb wrote in summary.json (``wall_time``), when it writes one. On a
loaded machine wall time is noisy; CPU time less so; the paired ratio is the number to quote.

Run: python benchmarks/compare.py REV [-n 7] [--bench help,campbell,disk]
     python benchmarks/compare.py 9eff67c --cmd "spinup=floating simulate {ex}/floating/spinup_beam.toml --out {out}"
     python benchmarks/compare.py --tiny
(``{ex}``: the tree's examples/, ``{out}``: a fresh output directory. ``--tiny``: no revision is
checked out; the working tree is paired with itself on ``help``, one repeat (checks the script
runs; the ratio is then ~1 by construction).)
"""

from __future__ import annotations

import argparse
import os
import shlex
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_startup import VERBS, run_process  # noqa: E402 - a sibling script, not a package

ROOT = Path(__file__).resolve().parents[1]

#: benchmarks run by default (``--bench`` chooses others from :data:`BENCHMARKS`)
DEFAULT = ("help", "campbell", "disk")
#: name -> rotaflex arguments; {ex} = the tree's examples/, {out} = a fresh output directory
BENCHMARKS: dict[str, list[str]] = {
    **VERBS,
    "campbell-nofig": [*VERBS["campbell"], "--no-figures"],
    "disk-nofig": [*VERBS["disk"], "--no-figures"],
    "rotor-modal": ["rotor", "modal", "{ex}/rotor/fe_friswell_5_9_1.toml", "--out", "{out}", "--no-figures"],
    "gear-coarse": ["gear", "simulate", "{ex}/gear/coarse_fast.toml", "--out", "{out}", "--no-figures"],
    "gear-paper": ["gear", "simulate", "{ex}/gear/4000rpm.toml", "--out", "{out}", "--no-figures"],
    "gear-reduced": ["gear", "simulate", "{ex}/gear/4000rpm_reduced.toml", "--out", "{out}", "--no-figures"],
    "floating-spinup": ["floating", "simulate", "{ex}/floating/spinup_beam.toml", "--out", "{out}", "--no-figures"],
}


def worktree(rev: str, where: Path) -> Path:
    """Check ``rev`` out (detached) into a new worktree under ``where``."""
    path = where / f"rev-{rev.replace('/', '_')}"
    subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", "-q", str(path), rev], check=True)
    return path


def remove_worktree(path: Path) -> None:
    subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(path)], check=False)
    subprocess.run(["git", "-C", str(ROOT), "worktree", "prune"], check=False)


def paired(a: list[float], b: list[float]) -> float:
    """Median of the paired ratios a_i / b_i."""
    return statistics.median(x / y for x, y in zip(a, b, strict=True) if y > 0)


def measure(benches: dict[str, list[str]], trees: dict[str, Path], repeats: int, say) -> dict:
    """``{bench: {tree: [metrics dict per repeat]}}``, the trees alternating within each repeat."""
    names = list(trees)
    runs: dict = {b: {t: [] for t in names} for b in benches}
    for args in benches.values():
        for t in names:
            run_process(args, trees[t])  # warm-up, discarded
    for i in range(repeats):
        order = names if i % 2 == 0 else names[::-1]
        for b, args in benches.items():
            for t in order:
                runs[b][t].append(run_process(args, trees[t]))
        say(f"repeat {i + 1}/{repeats} done (load {os.getloadavg()[0]:.1f})")
    return runs


def table(runs: dict, names: list[str]) -> str:
    a, b = names
    lines = [f"{'benchmark':16s} {'metric':9s} {a + ' [s]':>14s} {b + ' [s]':>14s} {'paired ratio':>13s}"]
    for bench, by_tree in runs.items():
        for metric in by_tree[a][0]:
            if metric not in by_tree[b][0]:
                continue
            xa = [r[metric] for r in by_tree[a]]
            xb = [r[metric] for r in by_tree[b]]
            lines.append(
                f"{bench:16s} {metric:9s} {statistics.median(xa):14.3f} {statistics.median(xb):14.3f} "
                f"{paired(xa, xb):13.2f}"
            )
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("rev", nargs="?", help="git revision to compare the working tree with (e.g. main, 9eff67c)")
    ap.add_argument("-n", "--repeats", type=int, default=7, help="paired repeats per benchmark (default 7)")
    ap.add_argument("--bench", default=",".join(DEFAULT), help="comma-separated: " + ", ".join(BENCHMARKS))
    ap.add_argument(
        "--cmd", action="append", default=[], metavar="NAME=ARGS", help="an extra benchmark: rotaflex arguments"
    )
    ap.add_argument("--tiny", action="store_true", help="the working tree against itself on help, 1 repeat")
    a = ap.parse_args()
    if a.tiny:
        runs = measure({"help": BENCHMARKS["help"]}, {"working": ROOT, "again": ROOT}, 1, lambda m: None)
        print("--tiny: the working tree paired with itself, 1 repeat")
        print(table(runs, ["working", "again"]))
        return
    if a.rev is None:
        ap.error("REV is required (or --tiny)")
    benches = {}
    for name in filter(None, a.bench.split(",")):
        if name not in BENCHMARKS:
            ap.error(f"unknown benchmark {name!r}; choose from {', '.join(BENCHMARKS)}")
        benches[name] = BENCHMARKS[name]
    for spec in a.cmd:
        name, _, args = spec.partition("=")
        benches[name] = shlex.split(args)

    def say(m):
        print(m, file=sys.stderr, flush=True)

    rev = subprocess.run(
        ["git", "-C", str(ROOT), "rev-parse", "--short", a.rev], check=True, capture_output=True, text=True
    ).stdout.strip()
    head = subprocess.run(
        ["git", "-C", str(ROOT), "describe", "--always", "--dirty"], check=True, capture_output=True, text=True
    ).stdout.strip()
    with tempfile.TemporaryDirectory(prefix="rotaflex-compare-") as tmp:
        other = worktree(rev, Path(tmp))
        try:
            trees = {"working": ROOT, rev: other}
            runs = measure(benches, trees, a.repeats, say)
        finally:
            remove_worktree(other)
    print(f"working tree {head} vs {rev}: {a.repeats} paired fresh processes per benchmark, interleaved")
    print(table(runs, ["working", rev]))
    print(f"ratio = median over repeats of working/{rev} (< 1: working tree faster); {os.cpu_count()} cores")


if __name__ == "__main__":
    main()
