"""Speed sweeps of the gear steady methods: the continuation loop and ``sweep_steady``.

Both steady methods (``lumped``: :func:`rotaflex.gear.models.chain.steady_state`;
``elastic_teeth``: :func:`rotaflex.gear.solvers.window_run.steady_state`) run one point by
:func:`~rotaflex.gear.solvers.steady_loop.run_steady` (re-exported here with
:class:`~rotaflex.gear.solvers.steady_loop.SteadyMethod`) and get the same procedure,
tolerances, metrics and dataset layout. This module sits above the models, the registry and
the sweep dataset; the loop itself sits below the models (:mod:`.steady_loop`). The chain's
energy terms that both energy balances share are methods of
:class:`rotaflex.gear.models.chain.Chain`.
"""

from __future__ import annotations

import time

import numpy as np

from rotaflex.core.errors import InputError
from rotaflex.gear.models.chain import OperatingPoint, TorsionalSystem
from rotaflex.gear.results.steady_sweep import sweep_dataset
from rotaflex.gear.solvers.registry import METHODS
from rotaflex.gear.solvers.steady_loop import SteadyMethod, periodicity, run_steady

__all__ = ["DIRECTIONS", "LateProgress", "SteadyMethod", "continuation", "periodicity", "run_steady", "sweep_steady"]

#: the legs of a continuation, in run order (as ``rotaflex sweep --continuation``)
DIRECTIONS = ("up", "down")


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
