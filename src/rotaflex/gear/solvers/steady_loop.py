"""The run-until-periodic loop of the gear steady methods (below every model module).

:func:`run_steady` drives a :class:`SteadyMethod` (how to start, how many steps per mesh cycle,
how to run a block of cycles, what to add to the dataset) to a periodic
steady state and evaluates its last cycles; :func:`until_periodic` is the block loop itself,
shared with the geared-rotor steady state (:func:`rotaflex.system.steady.steady_state`). This
module imports only the chain's data and linear analysis
(:mod:`rotaflex.gear.models.chain_system`), so the models (:mod:`rotaflex.gear.models.chain`,
:mod:`rotaflex.gear.solvers.window_run`) and the sweep driver
(:mod:`rotaflex.gear.solvers.steady_driver`) all import it from above.
"""

from __future__ import annotations

import json
import time
from typing import Any, Protocol

import numpy as np

from rotaflex.core.errors import InputError
from rotaflex.gear.results.steady import METRIC_UNITS, Periodicity, SteadyStateResult, detect_period, steady_metrics

__all__ = ["SteadyMethod", "periodicity", "run_steady", "until_periodic"]


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


def until_periodic(advance, check, *, block: int, min_cycles: int, max_cycles: int, whole_blocks: bool = False):
    """The loop of every steady state: run blocks of mesh cycles until periodic.

    Parameters
    ----------
    advance : callable
        ``advance(n)`` runs ``n`` more mesh cycles (and records what ``check`` reads).
    check : callable
        ``check() -> Periodicity`` of what has run so far (period 0: not periodic).
    block : int
        Mesh cycles between checks.
    min_cycles : int
        Cycles before the first check (``max_cycles + 1``: no check before the end, a run of
        exactly ``max_cycles`` cycles).
    max_cycles : int
        Cycles at most.
    whole_blocks : bool
        Run whole blocks only (the last may end past ``max_cycles``); otherwise the last block
        is cut to end at ``max_cycles`` exactly.

    Returns
    -------
    (int, Periodicity)
        Cycles run and the last check (made once more at the end if none was made).
    """
    done, per = 0, None
    while done < max_cycles:
        n = block if whole_blocks else min(block, max_cycles - done)
        advance(n)
        done += n
        if done >= min_cycles:
            per = check()
            if per.period:
                break
    if per is None:
        per = check()
    return done, per


def _run_blocks(
    method: SteadyMethod, st, spc, *, tol, min_cycles, target, fixed, eval_cycles, max_period, f_static, progress
):
    """Blocks of ``eval_cycles`` cycles until periodic (or ``target`` cycles); the last
    ``max(eval_cycles, 2 max_period)`` cycles kept; ``progress(done, target)`` after each."""
    k_mean = method.system.mesh.mean_stiffness
    keep = max(eval_cycles, 2 * max_period)
    buf, done = {}, [0]

    def advance(n):
        h = method.run(st, n, spc)
        done[0] += n
        if progress is not None:
            progress(done[0], target)
        rows = {k: h[k][:-1] for k in method.keep}  # drop the next cycle's first sample
        buf.update(rows if not buf else {k: np.concatenate([buf[k], rows[k]])[-keep * spc :] for k in rows})

    def check():
        return periodicity(buf, spc, tol, max_period, f_static, k_mean)

    first = target + 1 if fixed else min_cycles
    n_run, per = until_periodic(advance, check, block=eval_cycles, min_cycles=first, max_cycles=target)
    return n_run, buf, per


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

    # here, not at the top: the geared-rotor steady state imports this module for
    # until_periodic and should not load the chain's compiled kernels with it
    from rotaflex.gear.models.chain_system import natural_frequencies

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
