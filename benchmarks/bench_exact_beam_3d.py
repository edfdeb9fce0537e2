"""Cost of the 3-D exact beam on a prescribed slew, beside the planar exact beam.

The case is ``examples/floating/arm_slew_3d_exact.toml`` (1 m aluminium strip clamped to a
frame slewed 90 deg in 1 s by a versine profile) with ``--elements`` elements (default 20) over
``--t-end`` seconds (default 10): the oblique axis of the example on the 3-D beam, and the same
slew about z on the 3-D and on the planar exact beam (the in-plane case, which both solve: the
script also prints their largest tip difference relative to the peak). Each run goes once
untimed over 0.1 s (compile, warm caches), then timed; printed: wall time, steps, Newton
iterations, milliseconds per step. One BLAS thread (as the CLI). ``--tiny``: 4 elements over
0.2 s (a test runs it that way).

Run: PYTHONPATH=src python benchmarks/bench_exact_beam_3d.py [--tiny] [--t-end S] [--elements N]
"""

from __future__ import annotations

import argparse
import copy
import json
import sys
import time
import tomllib
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
CASE = ROOT / "examples" / "floating" / "arm_slew_3d_exact.toml"


def config(dimension: int, axis, t_end: float, elements: int) -> dict:
    cfg = tomllib.loads(CASE.read_text())
    cfg.pop("domain")
    ex = cfg["body"]["exact"]
    ex.update(dimension=dimension, elements=elements)
    if dimension == 2:  # the planar body has one bending stiffness and no torsion
        for key in ("gj",):
            ex.pop(key)
        cfg["body"]["beam"].pop("ei_z")
    cfg["slew"]["axis"] = list(axis)
    cfg["solver"]["t_end"] = t_end
    return cfg


def timed(cfg: dict):
    from rotaflex.floating.case import run_case

    warm = copy.deepcopy(cfg)
    warm["solver"]["t_end"] = warm["solver"]["dt_out"] = 0.1
    run_case(warm)
    t0 = time.perf_counter()
    res = run_case(cfg)
    return res, time.perf_counter() - t0


def main(argv=None) -> dict:
    from rotaflex.core.threads import limit_blas_threads

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tiny", action="store_true", help="4 elements over 0.2 s")
    ap.add_argument("--t-end", type=float, default=10.0)
    ap.add_argument("--elements", type=int, default=20)
    args = ap.parse_args(argv)
    if args.tiny:
        args.t_end, args.elements = 0.2, 4
    runs = {"3d_oblique": (3, (0.0, 0.6, 0.8)), "3d_z": (3, (0.0, 0.0, 1.0)), "2d_z": (2, (0.0, 0.0, 1.0))}
    rows, tips = {}, {}
    with limit_blas_threads():
        for name, (dim, axis) in runs.items():
            res, wall = timed(config(dim, axis, args.t_end, args.elements))
            ds = res.dataset.isel(solution=0)
            tips[name] = ds["point_deflection"].sel(point="tip").values
            msg = str(res.dataset.attrs["message"])  # "exact: <method>: N steps, M Newton iterations"
            steps = int(msg.rsplit(": ", 1)[1].split(" steps")[0])
            rows[name] = {"wall_s": wall, "message": msg, "ms_per_step": 1e3 * wall / steps}
            print(f"{name}: {wall:.2f} s, {1e3 * wall / steps:.2f} ms/step ({msg})", flush=True)
    peak = float(np.abs(tips["2d_z"]).max())
    diff = float(np.abs(tips["3d_z"] - tips["2d_z"]).max() / peak)
    print(f"in-plane slew: |3-D - planar| / peak tip deflection = {diff:.3g} (peak {peak:.4g} m)")
    out = {"t_end": args.t_end, "elements": args.elements, "runs": rows, "planar_difference": diff}
    print(json.dumps(out))
    return out


if __name__ == "__main__":
    sys.exit(0 if main() else 1)
