"""Fluid-film bearing timings (prints numbers; nothing asserted).

Run: PYTHONPATH=src OMP_NUM_THREADS=1 python benchmarks/bench_fluid_film.py
Targets (issue 23): finite-length coefficients at one speed <= 20 ms; a 50-speed table <= 0.5 s;
the 20-element rotor of bench_rotor_fe.py on two fluid-film bearings: Campbell over 50 speeds <= 1 s.
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np
from bench_rotor_fe import bench_rotor

from rotaflex.rotor.fe import Bearing
from rotaflex.rotor.fe.bearings import FluidFilm, coefficients_from_reaction
from rotaflex.rotor.fe.modal import campbell

RPM = np.pi / 30


def best(fn, repeat=5):
    """(best wall, median wall, best CPU time of this process) [s]; on a shared machine the CPU
    time is the steadier figure (run with OMP_NUM_THREADS=1 so that CPU ~ wall when idle)."""
    ts, cs = [], []
    for _ in range(repeat):
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


def main() -> None:
    ff = film(419.0)
    one = best(lambda: coefficients_from_reaction(ff, (0.0, 419.0), [3000 * RPM]), 10)
    table = best(lambda: coefficients_from_reaction(ff, (0.0, 419.0)), 3)
    t = coefficients_from_reaction(ff, (0.0, 419.0))
    print(f"grid {ff.n_theta} x {ff.n_z} (half solved: {ff.n_theta * ff.n_z // 2} unknowns), L/D = 0.5")
    print(f"finite, one speed (equilibrium + 8 coefficients)  best {one[0] * 1e3:6.1f} ms  median {one[1] * 1e3:6.1f} ms  CPU {one[2] * 1e3:6.1f} ms")
    print(f"finite, 50-speed table                            best {table[0]:6.3f} s   median {table[1]:6.3f} s   CPU {table[2]:6.3f} s")
    print(f"   eccentricity ratio {t.eccentricity[0]:.3f} .. {t.eccentricity[-1]:.3f}, S {t.sommerfeld[0]:.3g} .. {t.sommerfeld[-1]:.3g}")
    short = best(lambda: coefficients_from_reaction(dataclasses.replace(ff, model="short"), (0.0, 419.0)), 3)
    print(f"short, 50-speed table                             best {short[0] * 1e3:6.1f} ms  median {short[1] * 1e3:6.1f} ms  CPU {short[2] * 1e3:6.1f} ms")

    base = bench_rotor()

    def build():
        brg = (Bearing(node=0, fluid_film=film(419.0)), Bearing(node=20, fluid_film=film(458.0)))
        return dataclasses.replace(base, bearing=brg)

    rotor = build()
    speeds = np.linspace(500, 12000, 50) * RPM
    t_build = best(build, 3)
    t_camp = best(lambda: campbell(rotor, speeds, 8), 3)
    t_all = best(lambda: campbell(build(), speeds, 8), 3)
    c = campbell(rotor, speeds, 8)
    print(f"rotor {rotor.n_dof} DOF on 2 fluid-film bearings:")
    print(f"   build (2 coefficient tables)   best {t_build[0]:6.3f} s  median {t_build[1]:6.3f} s  CPU {t_build[2]:6.3f} s")
    print(f"   Campbell, 50 speeds            best {t_camp[0]:6.3f} s  median {t_camp[1]:6.3f} s  CPU {t_camp[2]:6.3f} s")
    print(f"   build + Campbell               best {t_all[0]:6.3f} s  median {t_all[1]:6.3f} s  CPU {t_all[2]:6.3f} s  (target 1 s)")
    onset = ", ".join(f"mode {u['mode']} at {u['speed'] / RPM:.0f} rpm" for u in c.unstable) or "none"
    print(f"   instability onset: {onset}")


if __name__ == "__main__":
    main()
