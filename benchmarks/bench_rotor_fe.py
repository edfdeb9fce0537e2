"""FE rotor timings: 20 shaft elements, 2 disks, 2 anisotropic damped bearings (prints numbers).

Run: PYTHONPATH=src OMP_NUM_THREADS=1 python benchmarks/bench_rotor_fe.py [--tiny]
(``--tiny``: the same analyses at a few speeds and frequencies, one repeat; checks the script runs.)
Targets (issue 12): modal at one speed <= 20 ms; Campbell over 50 speeds with tracking <= 0.5 s;
unbalance response at 500 speeds <= 0.5 s. ROSS is compared only if it is importable.
"""

from __future__ import annotations

import argparse
import contextlib
import functools
import importlib
import time

import numpy as np

from rotaflex.rotor.fe import Bearing, Disk, Rotor, Shaft
from rotaflex.rotor.fe.modal import campbell, modal
from rotaflex.rotor.fe.response import unbalance_response

RPM = np.pi / 30


def bench_rotor() -> Rotor:
    brg = {"kxx": 1e7, "kyy": 1.5e7, "kxy": 2e5, "kyx": -2e5, "cxx": 2e3, "cyy": 3e3}
    return Rotor(
        shaft=(Shaft(outer_diameter=0.06, length=1.2, elements=20),),
        disk=(
            Disk(node=6, width=0.05, outer_diameter=0.3, inner_diameter=0.06),
            Disk(node=14, width=0.05, outer_diameter=0.35, inner_diameter=0.06),
        ),
        bearing=(Bearing(node=0, **brg), Bearing(node=20, **brg)),
    )


@contextlib.contextmanager
def eig_on_one_thread():
    """Within the block, the modal module's ``batched_eig`` runs on one thread: one dgeev after
    another, the solve as it was before the threaded split. The replacement keeps the real
    signature (``progress`` included), so every caller works unchanged."""
    mod = importlib.import_module("rotaflex.rotor.fe.modal")  # the module (the package exports a function modal)
    threaded = mod.batched_eig
    mod.batched_eig = functools.partial(threaded, workers=1)
    try:
        yield
    finally:
        mod.batched_eig = threaded


def best(fn, repeat=5):
    ts = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        ts.append(time.perf_counter() - t0)
    return min(ts), float(np.median(ts))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tiny", action="store_true", help="a few speeds, one repeat (checks the script runs)")
    tiny = ap.parse_args().tiny
    rep = 1 if tiny else None  # None: each timing's own repeat count
    n_camp, n_unb = (4, 10) if tiny else (50, 500)
    r = bench_rotor()
    _ = r.M  # assembly once (cached)
    t_asm = best(lambda: bench_rotor().M, rep or 5)
    t_modal = best(lambda: modal(r, 5000 * RPM, 12), rep or 5)
    speeds = np.linspace(0, 10000 * RPM, n_camp)
    t_camp = best(lambda: campbell(r, speeds, 8), rep or 3)
    t_camp_r = best(lambda: campbell(r, speeds, 8, reduce=40), rep or 3)
    full, red = campbell(r, speeds, 8), campbell(r, speeds, 8, reduce=40)
    dr = float(np.nanmax(np.abs(red.modes.wd - full.modes.wd) / full.modes.wd))
    sp500 = np.linspace(10, 10000 * RPM, n_unb)
    t_unb = best(lambda: unbalance_response(r, sp500, [(6, 1e-4, 0.0)]), rep or 3)
    print(f"model: {r.n_nodes} nodes, {r.n_dof} DOF")
    print(f"build + assemble       best {t_asm[0] * 1e3:7.2f} ms  median {t_asm[1] * 1e3:7.2f} ms")
    print(f"modal at one speed     best {t_modal[0] * 1e3:7.2f} ms  median {t_modal[1] * 1e3:7.2f} ms  (target 20 ms)")
    print(f"Campbell, {n_camp} speeds    best {t_camp[0]:7.3f} s   median {t_camp[1]:7.3f} s   (target 0.5 s at 50)")
    with eig_on_one_thread():
        t_one = best(lambda: campbell(r, speeds, 8), rep or 3)
    print(f"  same, eig on one thread  best {t_one[0]:7.3f} s   median {t_one[1]:7.3f} s   (before the threaded split)")
    print(
        f"Campbell, {n_camp} speeds, 40-mode basis  best {t_camp_r[0]:7.3f} s   median {t_camp_r[1]:7.3f} s   "
        f"(max relative frequency difference to full: {dr:.1e})"
    )
    print(f"unbalance, {n_unb} speeds  best {t_unb[0]:7.3f} s   median {t_unb[1]:7.3f} s   (target 0.5 s at 500)")
    practice(r, tiny)
    try:
        import ross  # noqa: F401
    except ImportError:
        print("ROSS not importable: no comparison")


def practice(r: Rotor, tiny: bool = False) -> None:
    """Static analysis, FRF and the direct critical-speed solve vs a fine Campbell diagram
    (``tiny``: 20 frequencies, a 10-speed scan, a 20-speed Campbell diagram, one repeat)."""
    from rotaflex.rotor.fe.critical import critical_speeds
    from rotaflex.rotor.fe.frf import frf
    from rotaflex.rotor.fe.static import static_analysis

    rep = 1 if tiny else None
    n_freq, n_scan, fine_n = (20, 10, 20) if tiny else (2000, 30, 2000)
    t_static = best(lambda: static_analysis(r), rep or 5)
    w = np.linspace(1.0, 2 * np.pi * 400, n_freq)
    t_frf = best(lambda: frf(r, w, 5000 * RPM, [24, 25]), rep or 3)
    scan = np.linspace(1.0, 12000 * RPM, n_scan)
    t_crit = best(lambda: critical_speeds(r, scan, 6), rep or 3)
    cs = critical_speeds(r, scan, 6)
    t_fine = best(lambda: campbell(r, np.linspace(1.0, 12000 * RPM, fine_n), 6), 1)
    fine = campbell(r, np.linspace(1.0, 12000 * RPM, fine_n), 6).critical
    diff = max(min(abs(f["speed"] - c["speed"]) for f in fine) / c["speed"] for c in cs)
    print(f"static analysis        best {t_static[0] * 1e3:7.2f} ms  median {t_static[1] * 1e3:7.2f} ms")
    print(f"FRF, {n_freq} freq x 2 in  best {t_frf[0]:7.3f} s   median {t_frf[1]:7.3f} s")
    print(
        f"direct critical speeds ({len(cs)} roots, {n_scan}-speed scan) best {t_crit[0]:7.3f} s; "
        f"{fine_n}-speed Campbell {t_fine[0]:7.3f} s; max relative difference {diff:.1e}"
    )


if __name__ == "__main__":
    main()
