"""Time integration, energy balance and steady state of the travelling-window model.

Same chain, drive laws, step-size rule and steady-state procedure as the lumped torsional model
(:func:`rotaflex.gear.models.chain.steady_state`), so the two give directly comparable results;
here the step also resolves the highest tooth frequency in contact
(:attr:`WindowModel.highest_frequency`).
"""

from __future__ import annotations

import json
import math
import time
from dataclasses import dataclass

import numpy as np

from rotaflex.core.errors import DivergenceError, InputError
from rotaflex.gear.kernels.window import WindowArgs, run_window_rk4
from rotaflex.gear.models.chain import OperatingPoint, _chain, _initial_state, natural_frequencies
from rotaflex.gear.models.window import WindowModel
from rotaflex.gear.results.steady import METRIC_UNITS, Periodicity, SteadyStateResult, detect_period, steady_metrics
from rotaflex.gear.static.loaded_te import loaded_te

__all__ = ["WindowState", "cycle_steps", "simulate", "energy_balance", "steady_state"]


@dataclass
class WindowState:
    """Chain angles [rad], speeds [rad/s], nominal speeds, time [s], modal states and newest
    window pair (continuation)."""

    theta: np.ndarray
    omega: np.ndarray
    time: float
    nominal: np.ndarray
    modal: np.ndarray
    n_hi: int


def _args(model: WindowModel, ch) -> WindowArgs:
    line = model.line
    return WindowArgs(
        int(ch.ip),
        int(ch.iw),
        float(line.g1.base_radius),
        float(line.g2.base_radius),
        float(line.base_pitch),
        float(line.s_start),
        float(line.s_end),
        float(model.s_low),
        int(model.window),
        int(model.n_modes),
        float(model.s_grid[0]),
        float(model.s_grid[1] - model.s_grid[0]),
        model.k_res,
        model.gap,
        np.ascontiguousarray(model.a1),
        np.ascontiguousarray(model.a2),
        model.fillet1,
        model.fillet2,
        model.modes[0].omega.copy(),
        model.modes[1].omega.copy(),
        float(model.tooth_damping_ratio),
        float(model.system.mesh_damping),
        float(model.damping_onset),
        int(ch.iy1),
        int(ch.iy2),
    )


def _initial(model: WindowModel, op: OperatingPoint, ch) -> WindowState:
    """Static equilibrium at phase 0 (pair 0 entering): chain as the lumped model with the
    loaded table, each tooth mode at its static deflection under the loaded TE's pair loads."""
    st = _initial_state(model.system, op, ch)
    line, w, m = model.line, model.window, model.n_modes
    modal = np.zeros(2 * w * 2 * m)
    n_hi = int(math.floor((line.s_start - model.s_low) / line.base_pitch))
    if op.ramp_cycles == 0 and m:
        force = op.torque / line.g2.base_radius
        lt = loaded_te(line, np.array([line.s_start]), force)
        for s_j, f_j in zip(lt["s"][0], lt["pair_load"][0], strict=True):
            n = round((line.s_start - s_j) / line.base_pitch)
            if f_j <= 0 or not n_hi - w < n <= n_hi:
                continue
            slot = n % w
            for gear, (a, om) in enumerate(((model.a1, model.modes[0].omega), (model.a2, model.modes[1].omega))):
                a_s = np.array([np.interp(s_j, model.s_grid, a[:, k]) for k in range(m)])
                modal[(slot * 2 + gear) * m : (slot * 2 + gear + 1) * m] = a_s * f_j / om**2
    return WindowState(st.theta, st.omega, st.time, st.nominal, modal, n_hi)


def _continue_from(state: WindowState, ch) -> WindowState:
    return WindowState(
        state.theta.copy(),
        state.omega - state.nominal + ch.nominal,
        state.time,
        ch.nominal.copy(),
        state.modal.copy(),
        int(state.n_hi),
    )


def cycle_steps(model: WindowModel, op: OperatingPoint, steps: int = 100, points_per_period: int = 40) -> int:
    """RK4 steps per mesh cycle: ``steps`` at least, ``points_per_period`` per period of the
    highest chain mode, 12 per period of the highest tooth frequency in contact."""
    sys = model.system
    f_mesh = op.omega * sys.teeth[0] / (2 * np.pi)
    f_chain = float(np.max(natural_frequencies(sys, op)["frequency"], initial=0.0))
    need = max(points_per_period * f_chain, 12.0 * model.highest_frequency) / f_mesh
    return int(max(steps, math.ceil(need)))


def _run(model, op, ch, st: WindowState, n_cycles: int, spc: int) -> dict:
    """Advance ``n_cycles`` mesh cycles in place; every step recorded."""
    sys = model.system
    t_mesh = 2 * np.pi / (op.omega * sys.teeth[0])
    y = np.concatenate([st.theta, st.omega, st.modal])
    ramp = op.ramp_cycles * t_mesh
    chain = ch.args(ramp)
    t, yr, rec, work, n_hi, dropped = run_window_rk4(
        y, st.n_hi, st.time, t_mesh / spc, n_cycles * spc, chain, _args(model, ch)
    )
    n = len(ch.inertia)
    st.theta, st.omega, st.modal = y[:n].copy(), y[n : 2 * n].copy(), y[2 * n :].copy()
    st.time, st.n_hi = float(t[-1]), int(n_hi)
    if not np.all(np.isfinite(y)):
        bad = int(np.argmax(~np.all(np.isfinite(yr), axis=1)))
        raise DivergenceError(
            "elastic-tooth model (RK4)", t[bad], f"non-finite state after step {bad}; raise steady.steps_per_cycle"
        )
    rb1, rb2 = model.line.g1.base_radius, model.line.g2.base_radius
    th, om = yr[:, :n], yr[:, n:]
    return {
        "time": t,
        "theta": th,
        "omega": om,
        "force": rec[:, 0],
        "fillet_stress": rec[:, 1:3],
        "n_contact": rec[:, 3],
        "parametric_work": work[:, 0],
        "dissipated": work[:, 1],
        "elastic_energy": rec[:, 6],
        "dropped": dropped,
        "dte": rb1 * th[:, ch.ip] - rb2 * th[:, ch.iw],
    }


def simulate(
    model: WindowModel,
    op: OperatingPoint,
    n_cycles: int,
    *,
    steps_per_cycle: int = 100,
    points_per_period: int = 40,
    state: WindowState | None = None,
) -> dict:
    """Integrate ``n_cycles`` mesh cycles from static equilibrium (or ``state``).

    Returns
    -------
    dict
        ``time`` [s], ``theta``, ``omega`` (chain nodes), ``force`` (total mesh force) [N],
        ``dte`` [m], ``fillet_stress`` (pinion, wheel maxima) [Pa], ``n_contact``, the power
        and energy records of :func:`energy_balance`, ``spc``, ``state``, ``names``.
    """
    ch = _chain(model.system, op)
    st = _initial(model, op, ch) if state is None else _continue_from(state, ch)
    spc = cycle_steps(model, op, steps_per_cycle, points_per_period)
    h = _run(model, op, ch, st, n_cycles, spc)
    h.update(spc=spc, state=st, names=ch.names)
    return h


def energy_balance(model: WindowModel, op: OperatingPoint, hist: dict) -> dict:
    """Energy bookkeeping of a :func:`simulate` history.

    ``E`` = chain kinetic + shaft strain + bearing + tooth modal + contact-spring energy; power balance
    ``dE/dt = P_drive - P_load - D_mesh - D_teeth + P_par`` (``P_par``: work of the pairs'
    position-dependent stiffness, gap and mode shapes as the mesh rolls); teeth leaving the
    window take ``dropped`` with them. The mesh and tooth terms are integrated by the kernel
    with the state's RK4 stages; the drive's work (smooth) by Simpson's rule.

    Returns
    -------
    dict
        ``energy_change``, ``work_in``, ``dissipated``, ``parametric``, ``dropped``,
        ``residual`` [J] and ``scale`` (work in + dissipated) [J].
    """
    from scipy.integrate import simpson

    ch = _chain(model.system, op)
    th, om, t = hist["theta"], hist["omega"], hist["time"]
    free = ~ch.presc
    e = 0.5 * np.sum(ch.inertia[free] * om[:, free] ** 2, axis=1) + hist["elastic_energy"]
    diss = np.zeros(len(t))
    p_in = np.zeros(len(t))
    for i in range(len(ch.inertia) - 1):
        e = e + 0.5 * ch.ks[i] * (th[:, i] - th[:, i + 1]) ** 2
        diss = diss + ch.cs[i] * (om[:, i] - om[:, i + 1]) ** 2
    e = e + 0.5 * th**2 @ ch.kg
    diss = diss + om**2 @ ch.cg
    rb1 = model.line.g1.base_radius
    ramp = op.ramp_cycles * 2 * np.pi / (op.omega * model.system.teeth[0])
    scale = np.clip(t / ramp, 0.0, 1.0) if ramp > 0 else np.ones(len(t))
    for i in range(len(ch.inertia)):
        if ch.presc[i]:
            tq = np.zeros(len(t))
            if i + 1 < len(ch.inertia):
                tq += ch.ks[i] * (th[:, i] - th[:, i + 1]) + ch.cs[i] * (om[:, i] - om[:, i + 1])
            if i == ch.ip:
                tq += rb1 * hist["force"]
            p_in += tq * om[:, i]
        else:
            p_in += (scale * ch.torque[i] + ch.slope[i] * (ch.nominal[i] - om[:, i])) * om[:, i]
    out = {
        "energy_change": float(e[-1] - e[0]),
        "work_in": float(simpson(p_in, x=t)),
        "dissipated": float(simpson(diss, x=t) + hist["dissipated"][-1] - hist["dissipated"][0]),
        "parametric": float(hist["parametric_work"][-1] - hist["parametric_work"][0]),
        "dropped": float(hist["dropped"]),
    }
    out["residual"] = out["energy_change"] - (out["work_in"] - out["dissipated"] + out["parametric"] - out["dropped"])
    out["scale"] = float(simpson(np.abs(p_in), x=t)) + out["dissipated"]
    return out


def _periodicity(buf, model, spc, tol, max_period, f_static) -> Periodicity:
    k_mean = model.system.mesh.mean_stiffness
    pf = detect_period(buf["force"], spc, tol, max_period=max_period, scale=f_static)
    pd = detect_period(buf["dte"], spc, tol, max_period=max_period, scale=f_static / k_mean)
    changes = tuple(max(a, b) for a, b in zip(pf.changes, pd.changes, strict=True))
    for p, c in enumerate(changes, start=1):
        if c <= tol:
            return Periodicity(p, c, changes)
    return Periodicity(0, min(changes), changes)


_KEEP = ("time", "force", "dte", "fillet_stress", "n_contact")


def steady_state(
    model: WindowModel,
    op: OperatingPoint,
    *,
    tol: float = 1e-4,
    min_cycles: int = 20,
    max_cycles: int = 400,
    eval_cycles: int = 10,
    fixed_cycles: int | None = None,
    max_period: int = 4,
    steps_per_cycle: int = 100,
    points_per_period: int = 40,
    state: WindowState | None = None,
    config: dict | None = None,
):
    """Run until periodic, then evaluate the last ``eval_cycles`` mesh cycles.

    The procedure, tolerances and metrics of :func:`rotaflex.gear.models.chain.steady_state`, plus
    ``fillet_stress_max_pinion`` / ``_wheel`` [Pa] (quasi-static: the FE tooth's stress per
    newton times the pair's spring force) and the ``pairs_in_contact`` history.

    Returns
    -------
    (SteadyStateResult, WindowState)
    """
    import xarray as xr

    if fixed_cycles is not None and fixed_cycles < max(eval_cycles, 2):
        raise InputError("fixed_cycles", fixed_cycles, f">= {max(eval_cycles, 2)}")
    t0 = time.perf_counter()
    sys = model.system
    ch = _chain(sys, op)
    st = _initial(model, op, ch) if state is None else _continue_from(state, ch)
    spc = cycle_steps(model, op, steps_per_cycle, points_per_period)
    f_static = op.torque / sys.base_radius[1]
    keep = max(eval_cycles, 2 * max_period)
    done, buf, per = 0, None, None
    target = fixed_cycles if fixed_cycles is not None else max_cycles
    while done < target:
        block = min(eval_cycles, target - done)
        h = _run(model, op, ch, st, block, spc)
        done += block
        rows = {k: h[k][:-1] for k in _KEEP}
        buf = rows if buf is None else {k: np.concatenate([buf[k], rows[k]])[-keep * spc :] for k in rows}
        if fixed_cycles is None and done >= min_cycles:
            per = _periodicity(buf, model, spc, tol, max_period, f_static)
            if per.period:
                break
    if per is None or fixed_cycles is not None:
        per = _periodicity(buf, model, spc, tol, max_period, f_static)
    n_eval = eval_cycles
    if per.period > 1:
        n_eval = max(per.period, eval_cycles // per.period * per.period)
    sl = slice(len(buf["time"]) - n_eval * spc, None)
    met = steady_metrics(buf["dte"][sl], buf["force"][sl], f_static, spc, n_eval)
    nf = natural_frequencies(sys, op)
    status = "success" if per.period else "not_periodic"
    msg = (
        f"periodic with period {per.period} mesh cycle(s) after {done} cycles, change {per.change:.2e} <= {tol:g}"
        if per.period
        else f"not periodic after {done} mesh cycles: smallest cycle-to-cycle change "
        f"{per.change:.2e} > tol {tol:g} (periods 1-{max_period})"
    )
    ds = xr.Dataset(
        coords={
            "time": ("time", buf["time"][sl], {"units": "s"}),
            "mode": ("mode", np.arange(len(nf["frequency"]))),
            "gear": ("gear", ["pinion", "wheel"]),
        }
    )
    ds["dte"] = ("time", buf["dte"][sl], {"units": "m", "long_name": "dynamic transmission error"})
    ds["mesh_force"] = ("time", buf["force"][sl], {"units": "N", "long_name": "mesh force"})
    ds["fillet_stress"] = (
        ("time", "gear"),
        buf["fillet_stress"][sl],
        {"units": "Pa", "long_name": "tension-side fillet stress (quasi-static, most loaded tooth)"},
    )
    ds["pairs_in_contact"] = ("time", buf["n_contact"][sl], {"units": "1"})
    for k, v in met.items():
        ds[k] = ((), v, {"units": METRIC_UNITS[k]})
    for i, name in enumerate(("pinion", "wheel")):
        ds[f"fillet_stress_max_{name}"] = (
            (),
            float(buf["fillet_stress"][sl, i].max()),
            {"units": "Pa", "long_name": f"largest tension-side fillet stress of the {name}"},
        )
    ds["change"] = ((), per.change, {"units": "1", "long_name": "cycle-to-cycle change"})
    ds["period_cycles"] = ((), per.period, {"units": "1"})
    ds["cycles_run"] = ((), done, {"units": "1"})
    ds["natural_frequency"] = ("mode", nf["frequency"], {"units": "Hz"})
    ds["mesh_energy_share"] = ("mode", nf["mesh_energy"], {"units": "1"})
    ds.attrs.update(
        status=status,
        message=msg,
        wall_time=time.perf_counter() - t0,
        samples_per_cycle=spc,
        static_force=f_static,
        speed_rpm=op.speed_rpm,
        mesh_frequency=op.omega * sys.teeth[0] / (2 * np.pi),
        method="elastic_teeth",
        config=json.dumps(config or {}),
    )
    return SteadyStateResult(ds), st
