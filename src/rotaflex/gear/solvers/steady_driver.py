"""The one steady-state driver of the gear models: run until periodic, evaluate the last cycles.

Both steady methods (``lumped``: :func:`rotaflex.gear.models.chain.steady_state`;
``elastic_teeth``: :func:`rotaflex.gear.solvers.window_run.steady_state`) hand this driver a
:class:`SteadyMethod` (how to start, how many steps per mesh cycle, how to run a block of
cycles, what to add to the dataset) and get the same procedure, tolerances, metrics and
dataset layout. The chain's energy terms that both energy balances share are
methods of :class:`rotaflex.gear.models.chain.Chain`.
"""

from __future__ import annotations

import json
import time
from typing import Any, Protocol

import numpy as np

from rotaflex.core.errors import InputError
from rotaflex.gear.results.steady import METRIC_UNITS, Periodicity, SteadyStateResult, detect_period, steady_metrics

__all__ = ["DIRECTIONS", "LateProgress", "SteadyMethod", "continuation", "periodicity", "run_steady", "sweep_steady"]

#: the legs of a continuation, in run order (as ``rotaflex sweep --continuation``)
DIRECTIONS = ("up", "down")


class SteadyMethod(Protocol):
    """What a steady method gives the driver.

    ``system`` is the TorsionalSystem (teeth, base radii, mesh table for the scales),
    ``chain`` the chain arrays of the operating point, ``keep`` the history keys kept
    between blocks (must include ``time``, ``force`` [N] and ``dte`` [m]), ``attrs`` extra
    dataset attributes.
    """

    system: Any
    chain: Any
    keep: tuple[str, ...]
    attrs: dict

    def start(self, state):
        """Initial state (static equilibrium) when ``state`` is None, else ``state`` moved to
        the operating point's nominal speeds."""

    def steps_per_cycle(self, steps: int, points_per_period: int) -> int:
        """RK4 steps per mesh cycle."""

    def run(self, state, n_cycles: int, spc: int) -> dict:
        """Advance ``state`` in place by ``n_cycles`` mesh cycles; every step recorded."""

    def annotate(self, ds, buf: dict, sl: slice) -> None:
        """Add the method's own variables (evaluated cycles ``buf[...][sl]``) to ``ds``."""


def periodicity(buf: dict, spc: int, tol: float, max_period: int, f_static: float, k_mean: float) -> Periodicity:
    """Period at which both the mesh force (scale ``f_static``) and the DTE (scale the static
    deflection ``f_static / k_mean``) repeat within ``tol``; the force alone is blind while the
    flanks are apart (F = 0 in both cycles)."""
    pf = detect_period(buf["force"], spc, tol, max_period=max_period, scale=f_static)
    pd = detect_period(buf["dte"], spc, tol, max_period=max_period, scale=f_static / k_mean)
    changes = tuple(max(a, b) for a, b in zip(pf.changes, pd.changes, strict=True))
    for p, c in enumerate(changes, start=1):
        if c <= tol:
            return Periodicity(p, c, changes)
    return Periodicity(0, min(changes), changes)


def _run_blocks(
    method: SteadyMethod, st, spc, *, tol, min_cycles, target, fixed, eval_cycles, max_period, f_static, progress
):
    """Blocks of ``eval_cycles`` cycles until periodic (or ``target`` cycles); the last
    ``max(eval_cycles, 2 max_period)`` cycles kept; ``progress(done, target)`` after each."""
    k_mean = method.system.mesh.mean_stiffness
    keep = max(eval_cycles, 2 * max_period)
    done, buf, per = 0, None, None
    while done < target:
        block = min(eval_cycles, target - done)
        h = method.run(st, block, spc)
        done += block
        if progress is not None:
            progress(done, target)
        rows = {k: h[k][:-1] for k in method.keep}  # drop the next cycle's first sample
        buf = rows if buf is None else {k: np.concatenate([buf[k], rows[k]])[-keep * spc :] for k in rows}
        if not fixed and done >= min_cycles:
            per = periodicity(buf, spc, tol, max_period, f_static, k_mean)
            if per.period:
                break
    if per is None or fixed:
        per = periodicity(buf, spc, tol, max_period, f_static, k_mean)
    return done, buf, per


def run_steady(
    method: SteadyMethod,
    op,
    *,
    tol: float = 1e-4,
    min_cycles: int = 20,
    max_cycles: int = 400,
    eval_cycles: int = 10,
    fixed_cycles: int | None = None,
    max_period: int = 4,
    steps_per_cycle: int = 100,
    points_per_period: int = 40,
    state=None,
    config: dict | None = None,
    progress=None,
):
    """Run until periodic, then evaluate the last ``eval_cycles`` mesh cycles.

    Periodicity: the cycle-to-cycle changes (:func:`~rotaflex.gear.results.steady.cycle_change`)
    of the mesh force (``scale`` = static mesh force ``T_out / r_b2``) and of the DTE (``scale``
    = static deflection ``F_static / k_mean``) at a period of 1 ... ``max_period`` cycles must
    both fall below ``tol``; checked after each block of ``eval_cycles`` cycles once
    ``min_cycles`` have run. ``fixed_cycles`` runs exactly that many cycles instead. Either way
    ``status = "not_periodic"`` (with the change in the message) when the tolerance is not met.
    ``progress``: optional ``progress(cycles done, cycles at most)``, called after each block.

    Returns
    -------
    (SteadyStateResult, state)
        The result (histories of the evaluated cycles, metrics, natural frequencies) and the
        final state for continuation.
    """
    import xarray as xr

    from rotaflex.gear.models.chain import natural_frequencies

    if fixed_cycles is not None and fixed_cycles < max(eval_cycles, 2):
        raise InputError("fixed_cycles", fixed_cycles, f">= {max(eval_cycles, 2)}")
    t0 = time.perf_counter()
    sys = method.system
    st = method.start(state)
    spc = method.steps_per_cycle(steps_per_cycle, points_per_period)
    f_static = op.torque / sys.base_radius[1]
    done, buf, per = _run_blocks(
        method,
        st,
        spc,
        tol=tol,
        min_cycles=min_cycles,
        target=fixed_cycles if fixed_cycles is not None else max_cycles,
        fixed=fixed_cycles is not None,
        eval_cycles=eval_cycles,
        max_period=max_period,
        f_static=f_static,
        progress=progress,
    )
    n_eval = eval_cycles
    if per.period > 1:
        n_eval = max(per.period, eval_cycles // per.period * per.period)
    sl = slice(len(buf["time"]) - n_eval * spc, None)
    peak = buf["force_no_te_rate"][sl] if "force_no_te_rate" in buf else None
    met = steady_metrics(buf["dte"][sl], buf["force"][sl], f_static, spc, n_eval, peak_force=peak)
    nf = natural_frequencies(sys, op)
    status = "success" if per.period else "not_periodic"
    msg = (
        f"periodic with period {per.period} mesh cycle(s) after {done} cycles, change {per.change:.2e} <= {tol:g}"
        if per.period
        else f"not periodic after {done} mesh cycles: smallest cycle-to-cycle change "
        f"{per.change:.2e} > tol {tol:g} (periods 1-{max_period})"
    )
    ds = xr.Dataset(
        coords={"time": ("time", buf["time"][sl], {"units": "s"}), "mode": ("mode", np.arange(len(nf["frequency"])))}
    )
    ds["dte"] = ("time", buf["dte"][sl], {"units": "m", "long_name": "dynamic transmission error"})
    ds["mesh_force"] = ("time", buf["force"][sl], {"units": "N", "long_name": "mesh force"})
    for k, v in met.items():
        ds[k] = ((), v, {"units": METRIC_UNITS[k]})
    method.annotate(ds, buf, sl)
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
        **method.attrs,
        config=json.dumps(config or {}),
    )
    return SteadyStateResult(ds), st


def continuation(point, speeds_rpm, directions=DIRECTIONS):
    """Steady states along the speeds, each from the previous one's final state.

    The loop of an in-process speed sweep, in the order of a ``rotaflex sweep --continuation``
    chain: upwards through ``speeds_rpm``, then downwards from the top state (angles and
    vibration velocities kept, mean speeds moved to the new value by the method's ``start``).

    Parameters
    ----------
    point : callable
        ``point(speed_rpm, state) -> (result, final state)``: one steady state (``state`` None:
        the method's own start).
    speeds_rpm : array_like
        Pinion speeds [rpm], ascending, > 0, at least two.
    directions : sequence of {"up", "down"}

    Returns
    -------
    iterator of (int, int, SteadyStateResult)
        Direction index, speed index, the point's result (the speeds and directions are
        checked at once, the points run as the iterator is consumed).
    """
    speeds = np.asarray(speeds_rpm, dtype=float)
    if speeds.ndim != 1 or len(speeds) < 2 or np.any(np.diff(speeds) <= 0) or speeds[0] <= 0:
        raise InputError("speeds_rpm", list(speeds), "ascending speeds > 0 (at least two)")
    for d in directions:
        if d not in DIRECTIONS:
            raise InputError("directions", d, "'up' or 'down'")
    return _legs(point, speeds, tuple(directions))


def _legs(point, speeds, directions):
    state = None
    for di, d in enumerate(directions):
        order = range(len(speeds)) if d == "up" else range(len(speeds) - 1, -1, -1)
        for j in order:
            res, state = point(float(speeds[j]), state)
            yield di, j, res


def sweep_steady(model, torque: float, speeds_rpm, *, directions=DIRECTIONS, iso=None, progress=None, **steady_kw):
    """Steady states of ``model`` at each speed with continuation, up and then down.

    Parameters
    ----------
    model : TorsionalSystem or WindowModel
        The lumped model, or the elastic-tooth window model (adds ``fillet_stress_max_pinion``
        / ``_wheel``); run by the registry's ``lumped`` or ``elastic_teeth`` method.
    torque : float
        Output torque [N m].
    speeds_rpm : array_like
        Pinion speeds [rpm], ascending, > 0.
    directions : sequence of {"up", "down"}
    iso : IsoKvInput, optional
        Adds the ISO 6336-1 method B K_v at each speed (``iso_kv``) for the figure.
    progress : callable, optional
        ``progress(points done, points)`` after each steady state.
    **steady_kw
        Keywords of :func:`run_steady` (tol, eval_cycles, ...).

    Returns
    -------
    SpeedSweepResult
        See :func:`rotaflex.gear.results.steady_sweep.sweep_dataset`.
    """
    from rotaflex.gear.models.chain import OperatingPoint, TorsionalSystem
    from rotaflex.gear.results.steady_sweep import sweep_dataset
    from rotaflex.gear.solvers.registry import METHODS

    t0 = time.perf_counter()
    lumped = isinstance(model, TorsionalSystem)
    run = METHODS["lumped" if lumped else "elastic_teeth"]
    system = model if lumped else model.system
    speeds = np.asarray(speeds_rpm, dtype=float)
    n_points, done = len(speeds) * len(directions), [0]

    def point(rpm, state):
        out = run(model, dict(steady_kw, op=OperatingPoint(speed_rpm=rpm, torque=torque), state=state))
        done[0] += 1
        if progress is not None:
            progress(done[0], n_points)
        return out

    points = continuation(point, speeds, directions)
    return sweep_dataset(points, speeds, directions, system, torque, iso=iso, started=t0)


class LateProgress:
    """A :class:`~rotaflex.core.progress.Progress` that appears only once a run has taken
    :attr:`AFTER` seconds (a run of a second or two shows nothing)."""

    #: seconds before the first progress line
    AFTER = 3.0

    def __init__(self, desc: str, enabled: bool = True):
        self.desc, self.enabled, self.done, self.bar = desc, enabled, 0, None
        self.t0 = time.perf_counter()

    def update(self, done: float, total: float, unit: str) -> None:
        self.done = done
        if self.bar is None and self.enabled and time.perf_counter() - self.t0 >= self.AFTER:
            from rotaflex.core.progress import Progress

            self.bar = Progress(total, self.desc, unit)
        if self.bar is not None:
            self.bar.update(done, total)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
