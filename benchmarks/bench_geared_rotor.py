"""Geared rotor system timings (printed, never asserted): two FE rotors of 20 elements each and
one mesh (the example gearbox refined): Campbell over 50 speeds, linear TE response at 500
speeds, nonlinear steady state per speed (50 mesh cycles), each with its accuracy against the
unreduced solve. One BLAS thread (set before numpy loads).

Run: python benchmarks/bench_geared_rotor.py
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from rotaflex.core.config import load_toml  # noqa: E402
from rotaflex.system.modal import campbell  # noqa: E402
from rotaflex.system.model import Gearbox  # noqa: E402
from rotaflex.system.response import forced_response  # noqa: E402
from rotaflex.system.steady import SteadySettings, steady_state  # noqa: E402

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "system" / "gearbox.toml"
RPM = np.pi / 30


def model(source: str = "harmonic") -> Gearbox:
    """The example gearbox with 20 elements per shaft (gear at node 10, bearings at 2 and 18)."""
    cfg = load_toml(EXAMPLE)
    for r in cfg["rotor"]:
        r["shaft"][0]["elements"] = 20
        for b, node in zip(r["bearing"], (2, 18), strict=True):
            b["node"] = node
    m = cfg["gear_mesh"][0]
    m.update(pinion_node=10, wheel_node=10)
    if source == "harmonic":
        m.update(source="harmonic", k_mean=3.9e8, k_harmonics=[6e7, 2e7], te_harmonics=[2e-6, 5e-7])
    cfg["load"]["node"] = 20
    return Gearbox.from_mapping(cfg)


def timed(fn, *a, repeat=3, **kw):
    """Best of ``repeat`` runs: CPU time of this process (what a loaded machine does not inflate;
    one BLAS thread) and wall time, printed together."""
    best, wall, out = np.inf, np.inf, None
    for _ in range(repeat):
        t0, c0 = time.perf_counter(), time.process_time()
        out = fn(*a, **kw)
        best = min(best, time.process_time() - c0)
        wall = min(wall, time.perf_counter() - t0)
    print(f"  [{getattr(fn, '__name__', fn)}: cpu {best:.3f} s, wall {wall:.3f} s]")
    return best, out


def main() -> None:
    box = model()
    print(f"model: 2 rotors x 20 elements, {box.n_dof} DOFs, one mesh")
    sp = np.linspace(0.0, 6000.0, 50) * RPM
    t, c = timed(campbell, box, sp, 16)
    tf, cf = timed(campbell, box, sp, 16, reduce=False, repeat=1)
    d = np.max(np.abs(np.sort(c.modes.wd, 1) - np.sort(cf.modes.wd, 1)) / np.sort(cf.modes.wd, 1))
    print(
        f"campbell 50 speeds x 16 modes: {t:.3f} s reduced (target <= 1 s), {tf:.3f} s all DOFs; "
        f"max relative frequency difference {d:.1e}"
    )
    sp = np.linspace(100.0, 6000.0, 500) * RPM
    t, r = timed(forced_response, box, sp, harmonics=3, probes=[(0, 10), (1, 10)])
    tf, rf = timed(forced_response, box, sp, harmonics=3, probes=[(0, 10), (1, 10)], cutoff=None, repeat=1)
    errs = {
        k: np.max(np.abs(getattr(r, k) - getattr(rf, k))) / np.max(np.abs(getattr(rf, k)))
        for k in ("dte", "mesh_force", "bearing_force")
    }
    print(
        f"TE response 500 speeds x 3 harmonics: {t:.3f} s reduced (target <= 1 s), {tf:.3f} s all DOFs; "
        "max difference / peak: " + ", ".join(f"{k} {v:.1e}" for k, v in errs.items())
    )
    st = SteadySettings(min_cycles=40, max_cycles=40, check_every=40, eval_cycles=10)
    steady_state(box, 300.0, st)  # compile / load the kernel cache
    for source in ("harmonic", "contact_pattern"):
        b = model(source)
        t, s = timed(steady_state, b, 300.0, st)
        print(
            f"steady state, {source} mesh, 50 mesh cycles at 2865 rpm: {t:.3f} s (target <= 0.5 s); "
            f"{s.steps_per_cycle} steps/cycle, basis {s.basis_size}, energy balance error {s.energy_error:.1e}"
        )


if __name__ == "__main__":
    main()
