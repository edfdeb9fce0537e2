"""Timing of the dynamic gear-contact solver (printed, not asserted).

Runs the paper's 4000 rpm case over theta_s = 21.06 deg (about 29,000 RK4 steps, dt = 3e-8 s)
with the default mesh, then times the pieces of one step in isolation: the contact search
(spline build + minimum-normal-distance search) and the multiplier iteration (three passes).

Then compares the two faster methods with the paper_rk4 run (same case): the direct
multiplier solve (``multipliers="direct"``, same dt) and the large-step method
(``reduced_hht``: Craig-Bampton teeth + HHT-alpha) at several dt, with wall time, time per step,
speed-up and the peak / RMS difference of the contact force (reduced method: paper_rk4 force
interpolated at its times). ``--rpm 20000`` for the 20000 rpm case. Last, the cost of the
unequal drawing-pair example (examples/gear/unequal_shifted_relief.toml) over a short span.

    PYTHONPATH=src python benchmarks/bench_gear.py [--coarse] [--span DEG] [--rpm RPM]
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from rotaflex.core.units import rpm_to_rad_s
from rotaflex.gear.kernels import contact as kernels
from rotaflex.gear.kernels.rk4 import elastic_force
from rotaflex.gear.models import fe_pair as dynamics
from rotaflex.gear.pair import paper
from rotaflex.gear.pair.geometry import contact_angles
from rotaflex.gear.pair.tooth_mesh import COARSE, DEFAULT, build_tooth_mesh


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--coarse", action="store_true")
    ap.add_argument("--span", type=float, default=None, help="rotation span [deg]")
    ap.add_argument("--rpm", type=float, default=4000.0)
    args = ap.parse_args()
    g = paper.geometry()
    mesh = build_tooth_mesh(g, **(COARSE if args.coarse else DEFAULT))
    model = dynamics.build_model(g, g, mesh, mesh, **paper.material())
    ths, th2 = contact_angles(g, g)
    span = math.radians(args.span) if args.span else ths
    # warm-up (numba compile / cache load)
    dynamics.simulate(
        model, speeds=rpm_to_rad_s((4000, 4000)), torque=paper.TORQUE, theta_2=th2, theta_s=ths, span=1e-4, dt=3e-8
    )
    rpm = (args.rpm, args.rpm)
    out = dynamics.simulate(
        model,
        speeds=rpm_to_rad_s(rpm),
        torque=paper.TORQUE,
        theta_2=th2,
        theta_s=ths,
        span=span,
        dt=3e-8,
        record_every=1,
    )
    per = out.wall_time / out.steps
    k = model.stiffness
    print(
        f"mesh: {mesh.n_nodes} nodes/tooth, {mesh.n_elements} elements, K nnz {k.nnz} (both), "
        f"{len(model.tie_node)} tie nodes, RK4 limit {model.dt_limit:.3e} s"
    )
    print(
        f"{args.rpm:g} rpm over {math.degrees(span):.2f} deg: {out.steps} steps in {out.wall_time:.2f} s"
        f" = {per * 1e6:.1f} us/step"
    )
    r = out.records
    print(
        f"  mean iterations per pass (disp/vel/acc, max per record): {r['iter_disp'].mean():.2f}"
        f" / {r['iter_vel'].mean():.2f} / {r['iter_acc'].mean():.2f}"
    )
    # --- pieces in isolation, on the final state of the run
    x = model.reference_positions()
    n = 2000
    pa = np.empty((model.n_points, 2))
    ma = np.empty_like(pa)
    pb = np.empty_like(pa)
    mb = np.empty_like(pa)
    cres = np.zeros(8)
    cres[:2] = 0.3, 0.99
    cnod = np.zeros((2, 3), np.int64)
    cw = np.zeros((2, 3))
    kernels.contact_geometry(x, model.flank, model.nedge, model.sig, model.n_points, pa, ma, pb, mb, cres, cnod, cw)
    t0 = time.perf_counter()
    for _ in range(n):
        kernels.contact_geometry(x, model.flank, model.nedge, model.sig, model.n_points, pa, ma, pb, mb, cres, cnod, cw)
    t_search = (time.perf_counter() - t0) / n
    # elastic force (one of four per step)
    nd = 2 * model.n_nodes
    rot = np.array([[1.0, 0.0], [1.0, 0.0]])
    bufs = [np.zeros(nd) for _ in range(3)]
    tel = np.zeros(2)
    idx = (k.indptr.astype(np.int64), k.indices.astype(np.int64), k.data)
    elastic_force(x, model.xloc, model.gid, model.centres, rot, *idx, *bufs, tel)
    t0 = time.perf_counter()
    for _ in range(n):
        elastic_force(x, model.xloc, model.gid, model.centres, rot, *idx, *bufs, tel)
    t_force = (time.perf_counter() - t0) / n
    print(
        f"  contact search (sampling + 2 splines + search), Python-called: "
        f"{t_search * 1e6:.1f} us ({t_search / per:.1%} of a step)"
    )
    print(
        f"  elastic force (CSR matvec), Python-called: {t_force * 1e6:.1f} us; 4 per step = "
        f"{4 * t_force / per:.1%} of a step"
    )
    rest = 1.0 - (t_search + 4 * t_force) / per
    print(
        f"  remainder (multiplier iterations of the three passes, RK4 vector updates, "
        f"sliding terms, bookkeeping): {rest:.1%}"
    )
    print(f"  peak contact force {r['force_peak'].max():.1f} N")
    # the multiplier passes run inside the compiled step and are not timed separately: their
    # share is at most the remainder above; the direct-solve row below shows what replacing the
    # iteration by the exact solve changes per step.
    compare(model, out, rpm, th2, ths, span)
    unequal(args.span or 2.0)


def unequal(span_deg: float) -> None:
    """Cost of examples/gear/unequal_shifted_relief.toml (20/40 drawing pair, default mesh) over
    ``span_deg`` of the pinion, and the full run (theta_s) extrapolated per step."""
    import tomllib
    from pathlib import Path

    from rotaflex.gear.cases.simulate import prepare, run_case

    path = Path(__file__).resolve().parents[1] / "examples" / "gear" / "unequal_shifted_relief.toml"
    cfg = tomllib.loads(path.read_text())
    cfg["operation"]["span_deg"] = span_deg
    cfg["output"]["root_stress"] = False
    _, _, _, model, run = prepare(cfg)
    ds = run_case(cfg).dataset
    per = float(ds["time_per_step"])
    n_full = round(float(ds["theta_s"]) / run.span * run.n_steps)
    print(
        f"\nunequal example (20/40, x 0.25/0.1, tip reliefs; {model.n_nodes} nodes, dt {run.dt:g} s, "
        f"{cfg['operation']['driver_speed_rpm']:g} rpm): {int(ds['steps'])} steps over {span_deg:g} deg in "
        f"{float(ds['solver_wall_time']):.2f} s = {per * 1e6:.1f} us/step; full theta_s = "
        f"{math.degrees(float(ds['theta_s'])):.2f} deg: {n_full} steps, about {n_full * per:.0f} s"
    )


def compare(model, ref, rpm, th2, ths, span):
    """Rows for the direct multiplier solve and the large-step method vs paper_rk4."""
    from rotaflex.gear.models import reduced

    tr, fr = ref.records["time"], ref.records["force"]
    rows = [("paper_rk4 iterative", 3e-8, ref.steps, ref.wall_time, 0.0, 0.0, fr.max())]
    dynamics.simulate(
        model,
        speeds=rpm_to_rad_s(rpm),
        torque=paper.TORQUE,
        theta_2=th2,
        theta_s=ths,
        span=1e-4,
        dt=3e-8,
        multipliers="direct",
    )
    d = dynamics.simulate(
        model,
        speeds=rpm_to_rad_s(rpm),
        torque=paper.TORQUE,
        theta_2=th2,
        theta_s=ths,
        span=span,
        dt=3e-8,
        record_every=1,
        multipliers="direct",
    )
    df = d.records["force"] - fr
    rows.append(
        (
            "paper_rk4 direct",
            3e-8,
            d.steps,
            d.wall_time,
            np.abs(df).max(),
            np.sqrt(np.mean(df**2)),
            d.records["force"].max(),
        )
    )
    t0 = time.perf_counter()
    red = reduced.build_reduced(model, 20)
    t_build = time.perf_counter() - t0
    om = float(rpm_to_rad_s(rpm)[0])
    for dt in (2e-6, 5e-4 / om, 5e-7, 2.5e-7):
        if dt > reduced.time_step_limit(red, rpm_to_rad_s(rpm)):
            continue
        kw = dict(speeds=rpm_to_rad_s(rpm), torque=paper.TORQUE, theta_2=th2, theta_s=ths, dt=dt)
        reduced.simulate_reduced(red, span=20 * om * dt, **kw)  # compile / cache load
        o = reduced.simulate_reduced(red, span=span, **kw)
        f = o.records["force"]
        dd = f - np.interp(o.records["time"], tr, fr)
        rows.append(
            (f"reduced_hht dt={dt:.3g}", dt, o.steps, o.wall_time, np.abs(dd).max(), np.sqrt(np.mean(dd**2)), f.max())
        )
    print(f"\nmethod comparison ({rpm[0]:g} rpm; reduced model build {t_build:.3f} s, not included):")
    print(
        f"{'method':28s} {'dt [s]':>9s} {'steps':>7s} {'wall [s]':>9s} {'us/step':>8s} "
        f"{'speed-up':>8s} {'max|dF| N':>10s} {'RMS dF N':>9s} {'peak N':>8s}"
    )
    for name, dt, n, w, dmax, drms, pk in rows:
        print(
            f"{name:28s} {dt:9.3g} {n:7d} {w:9.3f} {w / n * 1e6:8.1f} "
            f"{ref.wall_time / w:8.1f} {dmax:10.3f} {drms:9.3f} {pk:8.1f}"
        )


if __name__ == "__main__":
    main()
