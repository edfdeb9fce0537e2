"""Floating-body cost per right-hand-side evaluation, working tree vs a git revision.

Cost per evaluation = integrator time / number of right-hand-side evaluations (the
integrator's own work per evaluation is included; it is the same in both trees). The time is
the process CPU time of the integrator section (``--wall``: its wall time), so that other
processes on a shared machine do not count. Each round runs
one worker process per tree, alternating which goes first, and each worker reports the best of
``--repeat`` runs per case; the printed ratio is the median over rounds of the paired ratios
(revision / working tree, > 1 = the working tree is faster). Step and evaluation counts are
printed too: the comparison only means something when they are equal.

Run: PYTHONPATH=src python benchmarks/bench_floating_rhs.py [REV] [--rounds 7] [--repeat 3]
(default REV: the parent of the commit that added the inextensible kinematics, cf9d0c3^).
Without git (or with ``--worker``) it prints the working tree's numbers only.
``--tiny``: no revision, this tree only, in this process, each case over 0.2 s, one repeat
(checks the script runs).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tarfile
import tempfile
from pathlib import Path

#: case name -> (method, n_modes, t_end [s]); the spin-up cases run under prescribed motion
CASES = {
    "full, free-free beam 10 modes": ("full", 10, 4.0),
    "perturbation, same": ("perturbation", 10, 4.0),
    "prescribed spin-up, cantilever 6 modes": ("prescribed", 6, 8.0),
    "inextensible spin-up, 6 modes": ("inextensible", 6, 8.0),
}


def _run(method: str, n: int, t_end: float):
    import numpy as np

    from rotaflex.floating.beam import uniform_beam
    from rotaflex.floating.model import Load, Prescribed, Settings
    from rotaflex.floating.solve import simulate

    if method in ("prescribed", "inextensible"):
        body = uniform_beam(10.0, 1.2, 1.4e4, n, support="cantilever")
        kin = {"kinematics": "inextensible"} if method == "inextensible" else {}  # older trees: no key
        st = Settings(t_end=t_end, dt_out=0.05, rtol=1e-10, atol=1e-13, **kin)
        return simulate(body, [], settings=st, prescribed=Prescribed(rate=6.0, spin_up_time=15.0))
    body = uniform_beam(4.0, 2.0, 40.0, n)
    loads = [Load(kind="torque", vector=(0.0, 0.0, 5.0), profile="bang-bang", duration=4.0)]
    del np
    return simulate(body, loads, settings=Settings(t_end=t_end), method=method)


def worker(repeat: int, wall: bool = False, t_span: float | None = None) -> dict:
    """Best-of-``repeat`` cost per evaluation [us] of each case this tree supports (each over
    its own span, or ``t_span`` [s])."""
    if not wall:  # simulate() times its integrator section with time.perf_counter: CPU time instead
        import time
        import types

        from rotaflex.floating import solve

        solve.time = types.SimpleNamespace(perf_counter=time.process_time)
    out = {}
    for name, (method, n, t_end) in CASES.items():
        try:
            _run(method, n, 0.1)  # compile or load the cache outside the timing
        except Exception:  # noqa: BLE001 - an older tree without the option: case not compared
            continue
        best = None
        for _ in range(repeat):
            s = _run(method, n, t_span or t_end)
            if best is None or s.wall_time < best.wall_time:
                best = s
        out[name] = {"us": 1e6 * best.wall_time / best.nfev, "nfev": best.nfev, "nstep": best.nstep}
    return out


def _tree(rev: str, root: Path, dest: Path) -> Path:
    """Extract ``src/`` of ``rev`` into ``dest`` (git archive; no checkout is touched)."""
    data = subprocess.run(["git", "-C", str(root), "archive", rev, "src"], check=True, capture_output=True).stdout
    tar = dest / "src.tar"
    tar.write_bytes(data)
    with tarfile.open(tar) as t:
        t.extractall(dest, filter="data")
    return dest / "src"


def _spawn(src: Path, repeat: int, wall: bool = False) -> dict:
    env = {**os.environ, "PYTHONPATH": str(src)}
    cmd = [sys.executable, __file__, "--worker", "--repeat", str(repeat)] + (["--wall"] if wall else [])
    return json.loads(subprocess.run(cmd, env=env, check=True, capture_output=True, text=True).stdout)


def compare(
    rev: str, rounds: int, repeat: int, here: Path | None = None, keep: Path | None = None, wall: bool = False
) -> None:
    import numpy as np

    root = Path(__file__).resolve().parents[1]
    here = here or root / "src"
    with tempfile.TemporaryDirectory() as tmp:
        dest = keep or Path(tmp)
        dest.mkdir(parents=True, exist_ok=True)
        old = dest / "src" if (dest / "src").is_dir() else _tree(rev, root, dest)
        print(f"warm-up (compiles {rev} once into {dest}) ...", flush=True)
        _spawn(old, 1, wall), _spawn(here, 1, wall)
        pairs = {}
        last = {}
        for r in range(rounds):
            order = [("rev", old), ("tree", here)] if r % 2 == 0 else [("tree", here), ("rev", old)]
            res = {k: _spawn(src, repeat, wall) for k, src in order}
            for name in res["tree"]:
                if name in res["rev"]:
                    pairs.setdefault(name, []).append((res["rev"][name]["us"], res["tree"][name]["us"]))
            last = res
            ratios = {n: round(float(np.median([a / b for a, b in p])), 3) for n, p in pairs.items()}
            print(f"round {r + 1}: median ratios so far {ratios}", flush=True)
    clock = "wall" if wall else "CPU"
    print(f"cost per right-hand-side evaluation [us, {clock}], {rounds} interleaved rounds, best of {repeat} each")
    print(f"{'case':40s} {rev + ' [us]':>14s} {'tree [us]':>10s} {'ratio rev/tree':>15s}  evaluations rev / tree")
    for name, pr in pairs.items():
        a = np.array(pr)
        ratio = np.median(a[:, 0] / a[:, 1])
        counts = f"{last['rev'][name]['nfev']} / {last['tree'][name]['nfev']}"
        print(f"{name:40s} {np.median(a[:, 0]):14.3f} {np.median(a[:, 1]):10.3f} {ratio:15.3f}  {counts}")
    for name in last["tree"]:
        if name not in pairs:
            print(f"{name:40s} {'-':>14s} {last['tree'][name]['us']:10.3f} {'(new)':>15s}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("rev", nargs="?", default="cf9d0c3^")
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--worker", action="store_true", help="print this tree's numbers as JSON")
    ap.add_argument("--wall", action="store_true", help="wall time instead of the process CPU time")
    ap.add_argument("--src", type=Path, help="the tree to compare (default: this checkout's src/)")
    ap.add_argument("--keep", type=Path, help="extract REV here and reuse it next time (default: a temporary dir)")
    ap.add_argument("--tiny", action="store_true", help="this tree only, 0.2 s per case, one repeat (checks it runs)")
    a = ap.parse_args()
    if a.worker:
        print(json.dumps(worker(a.repeat, a.wall)))
        return
    if a.tiny:
        print("--tiny: no comparison; this tree only, 0.2 s per case, one repeat:")
        numbers = worker(1, a.wall, t_span=0.2)
        this_tree(numbers)
        if missing := set(CASES) - set(numbers):  # on this tree every case must run
            sys.exit(f"cases that failed on this tree: {', '.join(sorted(missing))}")
        return
    try:
        compare(a.rev, a.rounds, a.repeat, a.src, a.keep, a.wall)
    except (subprocess.CalledProcessError, FileNotFoundError) as exc:
        print(f"no comparison ({exc}); this tree only:")
        this_tree(worker(a.repeat, a.wall))


def this_tree(numbers: dict) -> None:
    """Print :func:`worker`'s numbers."""
    for name, v in numbers.items():
        print(f"{name:40s} {v['us']:8.3f} us/evaluation, {v['nfev']} evaluations")


if __name__ == "__main__":
    main()
