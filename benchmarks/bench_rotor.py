"""Rotor timings (printed, never asserted): derivation/compile cold and cached, a 10 s nonlinear
run at rtol 1e-9, and `rotaflex reproduce rotor` end to end.

Run: python benchmarks/bench_rotor.py
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time

from rotaflex.rotor import symbolic
from rotaflex.rotor.case import run_case

SPECS = {
    "euler 123 nonlinear": symbolic.EOMSpec(),
    "euler 313 nonlinear": symbolic.EOMSpec(sequence="313", spin_index=2),
    "quaternion spherical nonlinear": symbolic.EOMSpec(parameterisation="quaternion_spherical"),
    "free body euler 321": symbolic.EOMSpec(sequence="321", spin_index=None),
}


def main() -> None:
    with tempfile.TemporaryDirectory() as cache:
        os.environ["ROTAFLEX_CACHE_DIR"] = cache
        print("derive + compile one parameterisation (target <= 2 s cold, <= 0.1 s cached)")
        for name, spec in SPECS.items():
            t0 = time.perf_counter()
            symbolic.compiled(spec, use_cache=False)
            cold = time.perf_counter() - t0
            symbolic._LOADED.clear()
            t0 = time.perf_counter()
            symbolic.compiled(spec)
            warm = time.perf_counter() - t0
            print(f"  {name:34s} cold {cold:6.3f} s   from disk cache {warm * 1e3:6.2f} ms")
        print("10 s of nonlinear rotor-disk motion, DOP853, rtol 1e-9 (target <= 0.5 s)")
        for name, form in (("euler 123", {"sequence": "123"}), ("euler 313", {"sequence": "313"})):
            cfg = {"formulation": form, "solver": {"t_end": 10.0, "rtol": 1e-9, "atol": 1e-12}}
            run_case(cfg)  # warm the in-memory cache
            best = min(_timed(run_case, cfg) for _ in range(3))
            print(f"  {name:34s} {best:6.3f} s")
        with tempfile.TemporaryDirectory() as out:
            t0 = time.perf_counter()
            subprocess.run(
                [sys.executable, "-m", "rotaflex", "reproduce", "rotor", "--out", out, "-q"],
                check=True,
                capture_output=True,
            )
            print(
                f"rotaflex reproduce rotor (cold cache, new process; target <= 30 s): {time.perf_counter() - t0:.2f} s"
            )


def _timed(fn, *args) -> float:
    t0 = time.perf_counter()
    fn(*args)
    return time.perf_counter() - t0


if __name__ == "__main__":
    main()
