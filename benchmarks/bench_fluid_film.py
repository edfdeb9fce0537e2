"""Fluid-film bearing timings (prints numbers; nothing asserted).

Run: PYTHONPATH=src OMP_NUM_THREADS=1 python benchmarks/bench_fluid_film.py [--tiny]
(``--tiny``: 4-speed tables, a 4-speed Campbell diagram, one repeat; checks the script runs.)
Targets (issue 23): finite-length coefficients at one speed <= 20 ms; a 50-speed table <= 0.5 s;
the 20-element rotor of bench_rotor_fe.py on two fluid-film bearings: Campbell over 50 speeds <= 1 s.
"""

from __future__ import annotations

import argparse
import dataclasses
import time

import numpy as np
from bench_rotor_fe import bench_rotor, eig_on_one_thread

from rotaflex.rotor.fe import Bearing
from rotaflex.rotor.fe.bearings import FluidFilm, coefficients_from_reaction
from rotaflex.rotor.fe.modal import campbell

RPM = np.pi / 30
#: repeats of every timing; --tiny sets 1
REPEAT: int | None = None


def best(fn, repeat=5):
    """(best wall, median wall, best CPU time of this process) [s]; on a shared machine the CPU
    time is the steadier figure (run with OMP_NUM_THREADS=1 so that CPU ~ wall when idle)."""
    ts, cs = [], []
    for _ in range(REPEAT or repeat):
        t0, c0 = time.perf_counter(), time.process_time()
        fn()
        ts.append(time.perf_counter() - t0)
        cs.append(time.process_time() - c0)
    return min(ts), float(np.median(ts)), min(cs)


def film(load: float, **kw) -> FluidFilm:
    """D = 60 mm, L/D = 0.5, c = 60 um, 0.02 Pa s (the bearings of examples/rotor/fe_fluid_film.toml)."""
    return FluidFilm(
        diameter=0.06,
        length=0.03,
        clearance=60e-6,
        viscosity=0.02,
        load=(0.0, -load),
        speed_rpm=(500.0, 12000.0),
        **kw,
    )


def row(label: str, t, ms: bool = False, target: str = "") -> None:
    """One printed line: best and median wall time, best CPU time."""
    f, u = (1e3, "ms") if ms else (1.0, "s ")
    best_, med, cpu = (x * f for x in t)
    print(f"{label:<50s} best {best_:7.3f} {u}  median {med:7.3f} {u}  CPU {cpu:7.3f} {u}  {target}")


def main() -> None:
    global REPEAT
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tiny", action="store_true", help="4-speed tables and Campbell, one repeat (checks it runs)")
    tiny = ap.parse_args().tiny
    n_table, n_camp = (4, 4) if tiny else (50, 50)
    REPEAT = 1 if tiny else None
    ff = film(419.0, n_speeds=n_table)
    one = best(lambda: coefficients_from_reaction(ff, (0.0, 419.0), [3000 * RPM]), 10)
    table = best(lambda: coefficients_from_reaction(ff, (0.0, 419.0)), 3)
    t = coefficients_from_reaction(ff, (0.0, 419.0))
    print(f"grid {ff.n_theta} x {ff.n_z} (half solved: {ff.n_theta * ff.n_z // 2} unknowns), L/D = 0.5")
    row("finite, one speed (equilibrium + 8 coefficients)", one, True, "(target 20 ms)")
    row(f"finite, {n_table}-speed table", table, False, "(target 0.5 s)")
    print(f"   eccentricity ratio {t.eccentricity[0]:.3f} .. {t.eccentricity[-1]:.3f}, ", end="")
    print(f"S {t.sommerfeld[0]:.3g} .. {t.sommerfeld[-1]:.3g}")
    short = best(lambda: coefficients_from_reaction(dataclasses.replace(ff, model="short"), (0.0, 419.0)), 3)
    row(f"short, {n_table}-speed table", short, True)
    tp = dataclasses.replace(ff, type="tilting_pad", clearance=80e-6, preload=0.2, n_speeds=min(20, n_table))
    row(
        f"tilting pad (4 pads), {tp.n_speeds}-speed table",
        best(lambda: coefficients_from_reaction(tp, (0.0, 419.0)), 3),
    )

    base = bench_rotor()

    def build():
        brg = (
            Bearing(node=0, fluid_film=film(419.0, n_speeds=n_table)),
            Bearing(node=20, fluid_film=film(458.0, n_speeds=n_table)),
        )
        return dataclasses.replace(base, bearing=brg)

    rotor = build()
    speeds = np.linspace(500, 12000, n_camp) * RPM
    print(f"rotor {rotor.n_dof} DOF on 2 fluid-film bearings:")
    row("   build (2 coefficient tables)", best(build, 3))
    row(f"   Campbell, {n_camp} speeds", best(lambda: campbell(rotor, speeds, 8), 3))
    with eig_on_one_thread():  # the solve as it was: one dgeev after another
        row(f"   Campbell, {n_camp} speeds, eig on one thread", best(lambda: campbell(rotor, speeds, 8), 3))
        before = campbell(rotor, speeds, 8).modes.eigenvalue
    same = np.array_equal(before, campbell(rotor, speeds, 8).modes.eigenvalue, equal_nan=True)
    print(f"   eigenvalues threaded == one thread (bitwise): {same}")
    row("   build + Campbell", best(lambda: campbell(build(), speeds, 8), 3), False, "(target 1 s)")
    row(f"   Campbell, {n_camp} speeds, 40-mode basis", best(lambda: campbell(rotor, speeds, 8, reduce=40), 3))
    row("   build + Campbell, 40-mode basis", best(lambda: campbell(build(), speeds, 8, reduce=40), 3), False, "(1 s)")
    for red in (None, 40):
        c = campbell(rotor, speeds, 8, reduce=red)
        onset = ", ".join(f"mode {u['mode']} at {u['speed'] / RPM:.1f} rpm" for u in c.unstable) or "none"
        print(f"   instability onset ({'full' if red is None else '40-mode basis'}): {onset}")


if __name__ == "__main__":
    main()
