"""Rotor timings (printed, never asserted): derivation/compile cold and cached, a 10 s nonlinear
run at rtol 1e-9, and `rotaflex reproduce rotor` end to end.

Run: python benchmarks/bench_rotor.py [--tiny]
(``--tiny``: one parameterisation, 0.1 s of motion, one repeat, and ``rotaflex rotor simulate``
of the disk example in place of ``reproduce rotor``; checks the script runs.)
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from rotaflex.rotor import symbolic
from rotaflex.rotor.case import run_case

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "rotor" / "disk_123_nonlinear.toml"
SPECS = {
    "euler 123 nonlinear": symbolic.EOMSpec(),
    "euler 313 nonlinear": symbolic.EOMSpec(sequence="313", spin_index=2),
    "quaternion spherical nonlinear": symbolic.EOMSpec(parameterisation="quaternion_spherical"),
    "free body euler 321": symbolic.EOMSpec(sequence="321", spin_index=None),
}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tiny", action="store_true", help="one parameterisation, 0.1 s spans (checks it runs)")
    tiny = ap.parse_args().tiny
    specs = dict(list(SPECS.items())[:1]) if tiny else SPECS
    t_end, repeat = (0.1, 1) if tiny else (10.0, 3)
    with tempfile.TemporaryDirectory() as cache:
        os.environ["ROTAFLEX_CACHE_DIR"] = cache
        print("derive + compile one parameterisation (target <= 2 s cold, <= 0.1 s cached)")
        for name, spec in specs.items():
            t0 = time.perf_counter()
            symbolic.compiled(spec, use_cache=False)
            cold = time.perf_counter() - t0
            symbolic._LOADED.clear()
            t0 = time.perf_counter()
            symbolic.compiled(spec)
            warm = time.perf_counter() - t0
            print(f"  {name:34s} cold {cold:6.3f} s   from disk cache {warm * 1e3:6.2f} ms")
        print(f"{t_end:g} s of nonlinear rotor-disk motion, DOP853, rtol 1e-9 (target <= 0.5 s for 10 s)")
        for name, form in (("euler 123", {"sequence": "123"}), ("euler 313", {"sequence": "313"})):
            cfg = {"formulation": form, "solver": {"t_end": t_end, "rtol": 1e-9, "atol": 1e-12}}
            run_case(cfg)  # warm the in-memory cache
            best = min(_timed(run_case, cfg) for _ in range(repeat))
            print(f"  {name:34s} {best:6.3f} s")
        with tempfile.TemporaryDirectory() as out:
            if tiny:
                what = "rotor simulate (disk example)"
                args = ["rotor", "simulate", str(EXAMPLE), "--no-figures"]
            else:
                what = "reproduce rotor"
                args = ["reproduce", "rotor"]
            t0 = time.perf_counter()
            subprocess.run(
                [sys.executable, "-m", "rotaflex", *args, "--out", out, "-q"], check=True, capture_output=True
            )
            print(f"rotaflex {what} (cold cache, new process; target <= 30 s): {time.perf_counter() - t0:.2f} s")


def _timed(fn, *args) -> float:
    t0 = time.perf_counter()
    fn(*args)
    return time.perf_counter() - t0


if __name__ == "__main__":
    main()
