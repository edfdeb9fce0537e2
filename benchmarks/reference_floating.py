"""Floating modal model vs the converged geometrically exact planar reference.

Reference: ``rotaflex.floating.reference`` (discrete Kirchhoff elastica, RK4, refined in links
and time step, Richardson-extrapolated at the observed order). Cases: free-free beam L 4 m,
rho_a 2 kg/m, 1 s half-sine end force along a fixed inertial direction or torque about z at the
centre, EI 100 and 1; the Kane-Ryan-Banerjee spin-up beam (examples/floating/spinup_beam.toml)
over 20 s. Prints the reference's convergence (per-level differences, observed order, estimated
error, time-step check), the model error, and wall times.
Run: PYTHONPATH=src python benchmarks/reference_floating.py [--quick | --tiny]
(``--quick``: the EI 1 cases only; ``--tiny``: one EI 1 case and the spin-up beam over short spans
with three coarse refinement levels, 2-8 links to start; checks the script runs.)
"""

import argparse
import time

import numpy as np

from rotaflex.floating.reference import PlanarCase, converged, modal_counterpart

SPINUP = PlanarCase(10.0, 1.2, 1.4e4, support="clamped-spin", rate=6.0, spin_up_time=15.0)


def report(name, ref, model_errs, wall):
    print(f"{name}: levels {ref.levels}, max|tip| {ref.max_tip[-1]:.5e} m, reference {wall:.1f} s")
    print("  successive differences / max|tip|: " + ", ".join(f"{d:.2e}" for d in ref.differences))
    print(
        f"  observed order {ref.order:.2f}, extrapolated error estimate {ref.error:.1e}, "
        f"dt/2 change {ref.time_error:.1e}"
    )
    for k, v in model_errs.items():
        print(f"  model {k}: max |u - u_ref| / max|u_ref| = {v:.2e}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="the EI 1 cases only")
    ap.add_argument("--tiny", action="store_true", help="one case, short spans, coarse levels (checks it runs)")
    a = ap.parse_args()
    t_end, dt_out = (0.2, 0.05) if a.tiny else (2.0, 0.05)
    # tiny: three levels (the fewest that give an observed order), coarse
    levels, coarse = (3, 8) if a.tiny else (4, None)
    t_spin, spin_modes = (0.5, (4,)) if a.tiny else (20.0, (4, 8, 12))
    cases = [
        ("EI 1, 0.2 N end force", PlanarCase(4.0, 2.0, 1.0, force=0.2)),
        ("EI 1, 0.5 N m torque", PlanarCase(4.0, 2.0, 1.0, torque=0.5)),
    ][: 1 if a.tiny else 2]
    if not (a.quick or a.tiny):
        cases += [
            ("EI 100, 20 N end force", PlanarCase(4.0, 2.0, 100.0, force=20.0)),
            ("EI 100, 50 N m torque", PlanarCase(4.0, 2.0, 100.0, torque=50.0)),
        ]
    for name, c in cases:
        t0 = time.perf_counter()
        # torque pulses: one level finer (128..1024 links) to bring the estimate below 1e-4
        ref = converged(c, t_end, dt_out, n0=coarse or (128 if c.torque else 64), levels=levels)
        wall = time.perf_counter() - t0
        scale = np.abs(ref.tip).max()
        errs = {}
        for geo in (False, True):
            u, _ = modal_counterpart(c, t_end, dt_out, geometric=geo)
            errs[f"10 modes + attachment, geometric stiffness {'on' if geo else 'off'}"] = (
                np.abs(u - ref.tip).max() / scale
            )
        report(name, ref, errs, wall)
    t0 = time.perf_counter()
    ref = converged(SPINUP, t_spin, 0.05, n0=coarse // 4 if coarse else 16, levels=levels)
    wall = time.perf_counter() - t0
    errs = {}
    for nm in spin_modes:
        u, _ = modal_counterpart(SPINUP, t_spin, 0.05, n_modes=nm)
        errs[f"{nm} modes (abs. {np.abs(u - ref.tip).max():.2e} m)"] = np.abs(u - ref.tip).max() / np.abs(ref.tip).max()
    report(f"spin-up beam, {t_spin:g} s", ref, errs, wall)


if __name__ == "__main__":
    main()
