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

    PYTHONPATH=src python benchmarks/bench_gear.py [--coarse] [--span DEG] [--rpm RPM] [--tiny]

``--tiny``: the coarse mesh over 0.2 deg (a few hundred steps), a short warm-up and 5 repetitions
in the step split, one reduced-method time step; checks the script runs.
"""

from __future__ import annotations

import argparse
import math
import time
import timeit

import numpy as np
from numba import njit

from rotaflex.core.units import rpm_to_rad_s
from rotaflex.gear.kernels import forces, rk4
from rotaflex.gear.models import fe_pair as dynamics
from rotaflex.gear.pair import paper
from rotaflex.gear.pair.geometry import contact_angles
from rotaflex.gear.pair.tooth_mesh import COARSE, DEFAULT, build_tooth_mesh


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--coarse", action="store_true")
    ap.add_argument("--span", type=float, default=None, help="rotation span [deg]")
    ap.add_argument("--rpm", type=float, default=4000.0)
    ap.add_argument("--tiny", action="store_true", help="coarse mesh, 0.2 deg, few repetitions (checks it runs)")
    args = ap.parse_args()
    if args.tiny:
        args.coarse, args.span = True, args.span or 0.2
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
    print(f"  peak contact force {r['force_peak'].max():.1f} N")
    step_split(model, th2, ths, rpm, *((200, 5) if args.tiny else ()))
    compare(model, out, rpm, th2, ths, span, n_reduced=1 if args.tiny else None)
    unequal(args.span or 2.0)


@njit(cache=True)
def _restore(s, snap):
    """Copy the saved state ``snap`` into ``s`` (both :class:`State`)."""
    for dst, src in ((s.x, snap.x), (s.v, snap.v), (s.a, snap.a), (s.mu, snap.mu), (s.sc, snap.sc)):
        dst[:] = src
    for dst, src in ((s.phi, snap.phi), (s.om, snap.om), (s.alp, snap.alp)):
        dst[:] = src
    s.cres[:] = snap.cres
    s.cnod[:] = snap.cnod
    s.cw[:] = snap.cw
    s.spair[:] = snap.spair
    s.rates[:] = snap.rates


@njit(cache=True)
def _pieces(nrep, upto, p, tpar, m, s, w, r, snap):
    """``nrep`` times: restore the saved state, then run the pieces of one step up to ``upto``
    (0 restore only, 1 RK4 stages, 2 contact search, 3 displacement pass, 4 velocity pass,
    5 acceleration pass and step close)."""
    for _ in range(nrep):
        _restore(s, snap)
        for jp in range(s.cres.shape[0]):
            w.cn[jp, 0] = s.cres[jp, 3]
            w.cn[jp, 1] = s.cres[jp, 4]
        if upto == 0:
            continue
        t = s.sc[0]
        rk4.hold_contact(s, w)
        rk4.rk4_predict(p.dt, m, tpar, p.torque_mode, s, w)
        if upto == 1:
            continue
        t += p.dt
        _, ke_pred = rk4.predicted_contact(t, p, m, s, w, r)
        if upto == 2:
            continue
        _, closing = rk4.displacement_pass(t, p, m, s, w, r)
        if upto == 3:
            continue
        rk4.velocity_pass(t, p, m, s, w, r, ke_pred, closing)
        if upto == 4:
            continue
        _, eel = rk4.acceleration_pass(t, p, tpar, p.torque_mode, m, s, w, r)
        rk4.close_step(t, eel, closing, False, m, s, w)


@njit(cache=True)
def _scratch(m, s, n_points):
    """The solver's work arrays (built by a kernel: ``new_scratch`` is not callable from Python)."""
    return rk4.new_scratch(m, s, n_points)


@njit(cache=True)
def _products(nrep, m, x, w):
    """``nrep`` elastic-force evaluations (rotation + stiffness product + torques)."""
    forces.set_rotation(np.zeros(2), m.theta0, w.rot)
    e = 0.0
    for _ in range(nrep):
        e += forces.elastic_force(x, w.rot, m, w.wbuf, w.fglob, w.tel)
    return e


@njit(cache=True)
def _bare_product(nrep, indptr, indices, data, u, out):
    """``nrep`` plain CSR products out = K u (the floor of one stiffness product)."""
    for _ in range(nrep):
        for r in range(out.shape[0]):
            acc = 0.0
            for j in range(indptr[r], indptr[r + 1]):
                acc += data[j] * u[indices[j]]
            out[r] = acc


@njit(cache=True)
def _block_products(nrep, m, u, f):
    """``nrep`` block products f = K u of the solver (no rotation, energy or torques)."""
    for _ in range(nrep):
        forces.block_product(m.kptr, m.kcol, m.kblk, u, f)


def _per_call(fn, nrep, *args) -> float:
    """Best of 5 of the CPU time per repetition [s] of ``fn(nrep, *args)`` (compiled loop; the
    thread's CPU time, so that other jobs on the machine inflate it less than wall time)."""
    fn(2, *args)
    best = math.inf
    for _ in range(5):
        t0 = time.thread_time()
        fn(nrep, *args)
        best = min(best, (time.thread_time() - t0) / nrep)
    return best


def step_split(model, th2, ths, rpm, warm_steps=6000, nrep=2000):
    """Per-step split of the paper_rk4 step on an in-mesh state (after ``warm_steps`` steps):
    the four stiffness products, the three multiplier passes (without their product),
    the contact search, and the rest (RK4 vector updates, sliding terms, bookkeeping), against
    the bare CSR product; each piece timed in a compiled loop, best of 5."""
    ki = dynamics.kernel_inputs(
        model, speeds=rpm_to_rad_s(rpm), torque=paper.TORQUE, theta_2=th2, theta_s=ths, span=1.0, dt=3e-8
    )
    m, p, s, r = ki.arrays, ki.params, ki.state, ki.rec
    status, _ = rk4.run_steps(warm_steps, 10, 0, True, m, p, s, r)
    assert status == 0
    snap = type(s)(*[a.copy() for a in s])
    w = _scratch(m, s, p.n_points)
    tpar = (p.tau0, p.theta_2, p.theta_s, p.gain[0], p.gain[1])
    cum = [_per_call(_pieces, nrep, k, p, tpar, m, s, w, r, snap) for k in range(6)]
    piece = np.diff(cum)  # stages, search, pass 1, pass 2, pass 3 + close
    prod = _per_call(_products, nrep, m, snap.x, w)
    k = model.stiffness
    u = np.ones(k.shape[0])
    csr = (k.indptr.astype(np.int64), k.indices.astype(np.int64), k.data)
    bare = _per_call(_bare_product, nrep, *csr, u, np.empty_like(u))
    bare_scipy = min(timeit.repeat(lambda: k @ u, number=200, repeat=5, timer=time.thread_time)) / 200
    blocks = _per_call(_block_products, nrep, m, np.ones((k.shape[0] // 2, 2)), np.empty((k.shape[0] // 2, 2)))
    total = cum[-1] - cum[0]
    passes = piece[2] + piece[3] + piece[4] - prod
    contact = piece[1]
    rest = total - 4 * prod - passes - contact
    us = 1e6
    print(
        f"  step split on an in-mesh state (compiled loops, best of 5): total {total * us:.1f} us = "
        f"products 4 x {prod * us:.1f} = {4 * prod * us:.1f} us + passes {passes * us:.1f} us "
        f"+ contact search {contact * us:.1f} us + rest (RK4 updates, sliding terms) {rest * us:.1f} us"
    )
    print(
        f"    passes: displacement {piece[2] * us:.1f}, velocity {piece[3] * us:.1f}, "
        f"acceleration {(piece[4] - prod) * us:.1f} us; bare CSR product K u {bare * us:.1f} us "
        f"(floor of the four products {4 * bare * us:.1f} us; step / floor {total / (4 * bare):.2f}); "
        f"scipy's CSR K @ u {bare_scipy * us:.1f} us; the solver's block product alone {blocks * us:.1f} us"
    )


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


def compare(model, ref, rpm, th2, ths, span, n_reduced=None):
    """Rows for the direct multiplier solve and the large-step method vs paper_rk4 (at most
    ``n_reduced`` time steps of the large-step method; None: all that are stable)."""
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
    t0 = time.thread_time()
    red = reduced.build_reduced(model, 20)
    t_build = time.thread_time() - t0
    om = float(rpm_to_rad_s(rpm)[0])
    stable = [dt for dt in (2e-6, 5e-4 / om, 5e-7, 2.5e-7) if dt <= reduced.time_step_limit(red, rpm_to_rad_s(rpm))]
    for dt in stable[:n_reduced]:
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
