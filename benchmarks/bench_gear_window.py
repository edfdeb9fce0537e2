"""Elastic-tooth (travelling-window) gear model: timings against the issue's targets.

The paper's 28:28 pair (tip radius 47.625 mm; FE tooth pairs of `gear static`, E = 210 GPa,
nu = 0.3), disk inertias 2.965e-4 kg m^2, torque 22.25 N m, mesh damping ratio 0.07, motor
slope 0.5 N m s/rad, rigid shafts, premature corner contact. Prints, on one core after the
compiled kernel is cached: the model build, one 50-mesh-cycle steady-state point (massless
teeth and with 2 / 4 tooth modes), a 40-speed up-and-down sweep (80 steady states) with the
lumped model's numbers beside it; then the same sweep through the command line
(``examples/sweep/gear_dynamic_factor.toml``) on 2 local workers and on 2-worker dask-local.
Targets (issue): point <= 5 s, sweep <= 3 min. Asserts nothing.

Run: PYTHONPATH=src python benchmarks/bench_gear_window.py [--no-cli] [--tiny]
(``--tiny``: the coarse tooth mesh, 0 and 2 tooth modes, 10-cycle points, one repeat, 2 speeds in
process and through the command line on 2 local workers; checks the script runs.)
"""

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from rotaflex.gear.models.chain import OperatingPoint, TorsionalSystem
from rotaflex.gear.models.mesh_stiffness import loaded_mesh_table
from rotaflex.gear.models.window import build_window_model
from rotaflex.gear.pair.geometry import GearGeometry, center_distance_no_backlash
from rotaflex.gear.pair.tooth_mesh import COARSE, build_tooth_mesh
from rotaflex.gear.solvers.steady_driver import sweep_steady
from rotaflex.gear.solvers.window_run import steady_state
from rotaflex.gear.static.loaded_te import pair_line

G = GearGeometry(module=3.175e-3, teeth=28, face_width=6.35e-3, tip_radius=0.047625, root_radius=0.04048)
TORQUE = 22.25
ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "sweep" / "gear_dynamic_factor.toml"


def main(tiny=False):
    cycles, repeat, n_speeds, modes = (10, 1, 2, (0, 2)) if tiny else (50, 3, 40, (0, 2, 4))
    t = time.perf_counter()
    mesh = build_tooth_mesh(G, **(COARSE if tiny else {}))
    line = pair_line(G, G, mesh, mesh, center_distance_no_backlash(G, G), TORQUE / G.base_radius, (210e9, 0.3) * 2)
    table = loaded_mesh_table(line, line.force)
    system = TorsionalSystem(mesh=table, base_radius=(G.base_radius,) * 2, drive="motor", motor_slope=0.5)
    models = {n: build_window_model(system, line, (mesh, mesh), (7800.0, 7800.0), n_modes=n) for n in modes}
    print(f"FE pair data + {len(models)} window models: {time.perf_counter() - t:.2f} s")
    op = OperatingPoint(10000.0, TORQUE)
    for n, model in models.items():
        steady_state(model, op, fixed_cycles=cycles)  # compile / load the cached kernel
        best = np.inf
        for _ in range(repeat):
            t = time.perf_counter()
            res, _ = steady_state(model, op, fixed_cycles=cycles)
            best = min(best, time.perf_counter() - t)
        print(
            f"n_modes {n}: {cycles}-cycle point at 10000 rpm, {res.dataset.attrs['samples_per_cycle']} steps/cycle: "
            f"{best * 1e3:.1f} ms (best of {repeat}; target 5 s at 50 cycles); "
            f"K_v {float(res.dataset.dynamic_factor):.3f}, "
            f"DTE p-p {float(res.dataset.dte_pp) * 1e6:.3f} um"
        )
    speeds = np.linspace(2000.0, 22000.0, n_speeds)
    t = time.perf_counter()
    sw = sweep_steady(models[0], TORQUE, speeds)
    wall = time.perf_counter() - t
    lumped = sweep_steady(system, TORQUE, speeds).dataset
    print(f"{n_speeds}-speed up-and-down sweep, massless teeth: {wall:.2f} s (target 180 s); {sw.message}")
    ds = sw.dataset
    print(" speed  Kv_up Kv_down  lumped_up  DTEpp_up[um] lumped  loss_up  sigma_F1max[MPa]")
    for j, s in enumerate(speeds):
        print(
            f"{s:6.0f} {ds.dynamic_factor.values[0, j]:6.3f} {ds.dynamic_factor.values[1, j]:6.3f}"
            f" {lumped.dynamic_factor.values[0, j]:9.3f} {ds.dte_pp.values[0, j] * 1e6:10.3f}"
            f" {lumped.dte_pp.values[0, j] * 1e6:7.3f} {ds.contact_loss_fraction.values[0, j]:7.3f}"
            f" {ds.fillet_stress_max_pinion.values[0, j] / 1e6:9.1f}"
        )
    return ds


def cli_sweeps(reference, tiny: bool = False) -> None:
    """The example continuation sweep through ``rotaflex sweep`` at the speeds of ``reference``,
    on 2 local processes and dask-local. ``tiny``: the coarse tooth mesh, 2 local processes only
    (``bench_sweep.py --tiny`` runs a Dask cluster), and a failed command ends with exit 1."""
    import xarray as xr

    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    n = reference.sizes["speed"]
    base = [sys.executable, "-m", "rotaflex", "sweep", str(EXAMPLE), "--vary", f"operation.speed_rpm=2000:22000:{n}"]
    base += ["--continuation", "operation.speed_rpm", "-j", "2", "--quiet"]
    runs = (("2 local workers", []), ("dask-local, 2 workers", ["--scheduler", "dask-local"]))
    if tiny:
        base += ["--vary", "model.mesh_preset=coarse"]
        runs = runs[:1]
        print("--tiny: coarse tooth mesh, 2 local workers only (no Dask cluster)")
    with tempfile.TemporaryDirectory() as tmp:
        for tag, extra in runs:
            out = Path(tmp) / tag.split()[0].replace(",", "")
            t = time.perf_counter()
            proc = subprocess.run([*base, "--out", str(out), *extra], env=env, capture_output=True, text=True)
            wall = time.perf_counter() - t
            if proc.returncode not in (0, 1):
                print(f"rotaflex sweep ({tag}) failed: {proc.stderr.strip()[-400:]}")
                if tiny:
                    sys.exit(f"rotaflex sweep ({tag}) failed")
                continue
            with xr.open_dataset(out / "sweep.nc") as ds:
                kv = ds["dynamic_factor"].squeeze(drop=True).transpose("direction", "operation_speed_rpm").values
            diff = float(np.nanmax(np.abs(kv - reference.dynamic_factor.values)))
            print(
                f"rotaflex sweep --continuation, {tag}: {wall:.1f} s for {2 * n} cases (target 180 s for 80); "
                f"max |K_v - in-process sweep| = {diff:.2e}"
            )


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--no-cli", action="store_true", help="skip the command-line sweeps")
    ap.add_argument("--tiny", action="store_true", help="coarse mesh, 2 speeds, one repeat (checks it runs)")
    a = ap.parse_args()
    ref = main(a.tiny)
    if not a.no_cli:
        cli_sweeps(ref, a.tiny)
