"""Floating-body speed: 2-D free-free beam, 10 modes, 10 s; full nonlinear vs perturbation.

Prints wall times (after a warm-up that compiles the kernels), the speed ratio, and the accuracy of
each run against a refined reference (rtol 1e-11) of the full nonlinear model.
Run: PYTHONPATH=src python benchmarks/bench_floating.py [--tiny]
(``--tiny``: 4 modes, spans of 0.5-1 s, one tolerance, one repeat; checks the script runs.)
"""

import argparse

import numpy as np

from rotaflex.floating.beam import uniform_beam
from rotaflex.floating.model import Load, Prescribed, Settings
from rotaflex.floating.solve import point_motion, simulate


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tiny", action="store_true", help="4 modes, short spans, one repeat (checks it runs)")
    tiny = ap.parse_args().tiny
    n_modes, t_end, t_push, t_spin = (4, 0.5, 0.5, 1.0) if tiny else (10, 10.0, 5.0, 20.0)
    tolerances = ((1e-6, 1e-8),) if tiny else ((1e-6, 1e-8), (1e-7, 1e-9), (1e-8, 1e-10))
    repeat, spin_modes = (1, (4,)) if tiny else (3, (4, 6, 8, 12))
    body = uniform_beam(4.0, 2.0, 40.0, n_modes)
    loads = [Load(kind="torque", vector=(0.0, 0.0, 5.0), profile="bang-bang", duration=4.0)]
    tip = np.array([[2.0, 0.0, 0.0]])
    simulate(body, loads, settings=Settings(t_end=0.1), method="full")  # compile / load cache
    simulate(body, loads, settings=Settings(t_end=0.1), method="perturbation")
    ref = simulate(body, loads, settings=Settings(t_end=t_end, rtol=1e-11, atol=1e-14), method="full")
    ref_p = simulate(body, loads, settings=Settings(t_end=t_end, rtol=1e-11, atol=1e-14), method="perturbation")
    xr = point_motion(body, ref, tip)[0]
    xrp = point_motion(body, ref_p, tip)[0]
    defl = np.abs(point_motion(body, ref, tip)[1]).max()
    print(f"max tip deflection {defl:.4e} m; perturbation model error (refined runs) {np.abs(xrp - xr).max():.3e} m")
    print(
        f"{'rtol':>8} {'method':>13} {'wall [s]':>9} {'steps':>7} "
        f"{'err vs own ref [m]':>19} {'err vs full ref [m]':>20}"
    )
    for rtol, atol in tolerances:
        walls = {}
        for m, own in (("full", xr), ("perturbation", xrp)):
            s = simulate(body, loads, settings=Settings(t_end=t_end, rtol=rtol, atol=atol), method=m)
            x = point_motion(body, s, tip)[0]
            walls[m] = s.wall_time
            print(
                f"{rtol:8.0e} {m:>13} {s.wall_time:9.3f} {s.nstep:7d} {np.abs(x - own).max():19.3e} "
                f"{np.abs(x - xr).max():20.3e}"
            )
        print(f"{'':8} speed ratio full / perturbation = {walls['full'] / walls['perturbation']:.2f}")

    # cost of the load-dependent geometric stiffness: free-free beam (10 modes + attachment shape)
    # pushed at one end by a 20 N inertial-direction pulse, geometric stiffness on vs off
    pb = uniform_beam(4.0, 2.0, 100.0, n_modes, attachment_points=[(2.0, 0.0, 0.0)])
    push = [
        Load(
            kind="force",
            vector=(0.0, 20.0, 0.0),
            point=(2.0, 0.0, 0.0),
            frame="inertial",
            profile="pulse",
            duration=1.0,
        )
    ]
    walls = {}
    for geo in (False, True):
        st = Settings(t_end=t_push, geometric_stiffness=geo)
        simulate(pb, push, settings=Settings(t_end=0.1, geometric_stiffness=geo), method="full")
        best = min(
            (simulate(pb, push, settings=st, method="full") for _ in range(repeat)),
            key=lambda s: s.wall_time,
        )
        walls[geo] = best
        u = point_motion(pb, best, tip)[1][:, 0, 1]
        print(
            f"pushed beam, geometric stiffness {'on ' if geo else 'off'}: wall {best.wall_time:.3f} s,"
            f" steps {best.nstep}, max tip deflection {np.abs(u).max():.4e} m"
        )
    print(
        f"cost of geometric stiffness (centrifugal + applied load): "
        f"{walls[True].wall_time / walls[False].wall_time:.2f} x wall time"
    )

    # cost of the inextensible kinematics: Kane-Ryan-Banerjee spin-up beam, 20 s, rtol 1e-10,
    # linear floating-frame model with geometric stiffness vs exact inextensible kinematics

    spin = Prescribed(rate=6.0, spin_up_time=15.0)
    print(f"{'modes':>5} {'linear + K_G [s]':>17} {'inextensible [s]':>17} {'ratio':>6} {'tip shift [m]':>14}")
    for nm in spin_modes:
        sb = uniform_beam(10.0, 1.2, 1.4e4, nm, support="cantilever")
        runs = {}
        for kin in ("linear", "inextensible"):
            st = Settings(t_end=t_spin, dt_out=0.05, rtol=1e-10, atol=1e-13, kinematics=kin)
            simulate(sb, [], settings=Settings(t_end=0.1, kinematics=kin), prescribed=spin)  # compile
            runs[kin] = simulate(sb, [], settings=st, prescribed=spin)
        shift = point_motion(sb, runs["inextensible"], np.array([[10.0, 0.0, 0.0]]))[1][:, 0, 0].min()
        wl, wi = runs["linear"].wall_time, runs["inextensible"].wall_time
        print(f"{nm:5d} {wl:17.3f} {wi:17.3f} {wi / wl:6.1f} {shift:14.4f}")


if __name__ == "__main__":
    main()
