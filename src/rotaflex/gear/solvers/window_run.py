"""Time integration, energy balance and steady state of the travelling-window model.

Same chain, drive laws, step-size rule and steady-state procedure as the lumped torsional model
(both through :func:`rotaflex.gear.solvers.steady_loop.run_steady`), so the two give directly comparable results;
here the step also resolves the highest tooth frequency in contact
(:attr:`WindowModel.highest_frequency`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from rotaflex.core.errors import DivergenceError
from rotaflex.gear.kernels.window import WindowArgs, run_window_rk4
from rotaflex.gear.models.chain import OperatingPoint, build_chain, initial_state, natural_frequencies
from rotaflex.gear.models.window import WindowModel
from rotaflex.gear.solvers.steady_loop import run_steady
from rotaflex.gear.static.loaded_te import loaded_te

__all__ = ["WindowState", "WindowSteady", "cycle_steps", "simulate", "energy_balance", "steady_state"]


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
    st = initial_state(model.system, op, ch)
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
    ch = build_chain(model.system, op)
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

    ch = build_chain(model.system, op)
    th, om, t = hist["theta"], hist["omega"], hist["time"]
    free = ~ch.presc
    e = 0.5 * np.sum(ch.inertia[free] * om[:, free] ** 2, axis=1) + hist["elastic_energy"]
    e, diss = ch.add_strain_and_dissipation(th, om, e, np.zeros(len(t)))
    rb1 = model.line.g1.base_radius
    p_in = ch.drive_power(op, model.system.teeth[0], th, om, t, hist["force"], rb1)
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


@dataclass
class WindowSteady:
    """The window model as a :class:`~rotaflex.gear.solvers.steady_loop.SteadyMethod`."""

    model: WindowModel
    op: OperatingPoint
    keep: tuple = ("time", "force", "dte", "fillet_stress", "n_contact")
    attrs: dict = field(default_factory=lambda: {"method": "elastic_teeth"})

    def __post_init__(self):
        self.system = self.model.system
        self.chain = build_chain(self.system, self.op)

    def start(self, state: WindowState | None) -> WindowState:
        return _initial(self.model, self.op, self.chain) if state is None else _continue_from(state, self.chain)

    def steps_per_cycle(self, steps: int, points_per_period: int) -> int:
        return cycle_steps(self.model, self.op, steps, points_per_period)

    def run(self, state: WindowState, n_cycles: int, spc: int) -> dict:
        return _run(self.model, self.op, self.chain, state, n_cycles, spc)

    def annotate(self, ds, buf: dict, sl: slice) -> None:
        """Fillet stress histories and maxima, pairs in contact."""
        ds.coords["gear"] = ("gear", ["pinion", "wheel"])
        ds["fillet_stress"] = (
            ("time", "gear"),
            buf["fillet_stress"][sl],
            {"units": "Pa", "long_name": "tension-side fillet stress (quasi-static, most loaded tooth)"},
        )
        ds["pairs_in_contact"] = ("time", buf["n_contact"][sl], {"units": "1"})
        for i, name in enumerate(("pinion", "wheel")):
            ds[f"fillet_stress_max_{name}"] = (
                (),
                float(buf["fillet_stress"][sl, i].max()),
                {"units": "Pa", "long_name": f"largest tension-side fillet stress of the {name}"},
            )


def steady_state(model: WindowModel, op: OperatingPoint, *, state: WindowState | None = None, **kw):
    """Run until periodic, then evaluate the last ``eval_cycles`` mesh cycles.

    The procedure, tolerances, keywords and metrics of
    :func:`rotaflex.gear.solvers.steady_loop.run_steady` (as the lumped model), plus
    ``fillet_stress_max_pinion`` / ``_wheel`` [Pa] (quasi-static: the FE tooth's stress per
    newton times the pair's spring force) and the ``pairs_in_contact`` history.

    Returns
    -------
    (SteadyStateResult, WindowState)
    """
    return run_steady(WindowSteady(model, op), op, state=state, **kw)
