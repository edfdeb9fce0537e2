"""Exact beam vs modal body on the same flexible-arm slew: run time and tip difference.

The case is ``examples/floating/flexible_arm_slew_exact.toml`` (hub + 1 m aluminium strip, 20
elements, versine slew by a stiff servo) over ``--t-end`` seconds (default 10) at several slew
angles; for each angle both bodies run (each once untimed to compile/warm, then timed) and the
script prints the wall time of each, the exact body's steps and Newton iterations, the largest
tip deflection / L, and the largest tip-deflection difference modal - exact relative to the
exact peak (the modal body's error where the exact beam is converged; docs/floating.md).
``--tiny`` runs one small angle over 0.5 s with 4 elements (a test runs it that way).

Run: PYTHONPATH=src python benchmarks/bench_exact_beam.py [--tiny] [--t-end S] [--angles A ...]
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
CASE = ROOT / "examples" / "floating" / "flexible_arm_slew_exact.toml"


def config(model: str, angle: float, t_end: float, elements: int, n_modes: int) -> dict:
    cfg = tomllib.loads(CASE.read_text())
    cfg.pop("domain")
    cfg = copy.deepcopy(cfg)
    cfg["body"]["model"] = model
    cfg["body"]["exact"]["elements"] = elements
    cfg["body"]["hub"]["appendages"][0]["n_modes"] = n_modes
    cfg["slew"]["angle_deg"] = angle
    cfg["solver"].update(t_end=t_end, method="full")
    return cfg


def timed(cfg: dict):
    from rotaflex.floating.case import run_case

    run_case(config_short(cfg))  # compile and warm caches outside the timing
    t0 = time.perf_counter()
    res = run_case(cfg)
    return res, time.perf_counter() - t0


def config_short(cfg: dict) -> dict:
    c = copy.deepcopy(cfg)
    c["solver"]["t_end"] = min(0.1, cfg["solver"]["t_end"])
    c["solver"]["dt_out"] = min(c["solver"]["dt_out"], c["solver"]["t_end"])
    return c


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tiny", action="store_true", help="one 1 deg slew over 0.5 s, 4 elements")
    ap.add_argument("--t-end", type=float, default=10.0)
    ap.add_argument("--angles", type=float, nargs="*", default=[1.0, 10.0, 30.0, 90.0])
    ap.add_argument("--elements", type=int, default=20)
    ap.add_argument("--modes", type=int, default=4)
    args = ap.parse_args(argv)
    if args.tiny:
        args.t_end, args.angles, args.elements = 0.5, [1.0], 4
    rows = []
    for angle in args.angles:
        out = {"angle_deg": angle}
        tips = {}
        for model in ("modal", "exact"):
            res, wall = timed(config(model, angle, args.t_end, args.elements, args.modes))
            ds = res.dataset.isel(solution=0)
            tips[model] = ds["point_deflection"].sel(point="tip").values[:, 1]
            out[f"{model}_wall_s"] = wall
            if model == "exact":
                out["exact_message"] = str(res.dataset.attrs["message"])
                out["deflection_to_length"] = float(ds["deflection_to_length"].max())
        peak = float(np.abs(tips["exact"]).max())
        out["modal_minus_exact_relative"] = float(np.abs(tips["modal"] - tips["exact"]).max() / peak)
        rows.append(out)
        print(
            f"angle {angle:6.2f} deg: modal {out['modal_wall_s']:.3f} s, exact {out['exact_wall_s']:.3f} s "
            f"({out['exact_message']}); max deflection / L {out['deflection_to_length']:.4g}; "
            f"|modal - exact| / peak {out['modal_minus_exact_relative']:.3g}",
            flush=True,
        )
    print(json.dumps({"t_end": args.t_end, "elements": args.elements, "modes": args.modes, "rows": rows}))
    return {"rows": rows}


if __name__ == "__main__":
    sys.exit(0 if main() else 1)
