"""The driver loop shared by every gear integrator, its status -> error mapping and its output.

Every method of :data:`rotaflex.gear.solvers.registry.METHODS` runs its compiled kernel in chunks
through :func:`drive` (one loop for progress, snapshots, recorded nodes and the status -> error
mapping of :data:`STATUS`) and returns a :class:`SolverOutput` whose per-pair histories carry a
``pair`` dimension. This module imports no other gear module.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from rotaflex.core.errors import ConvergenceError

#: kernel status -> the iteration that failed (0 = ok). Shared by every method.
STATUS = {
    1: "displacement pass (eq. 19)",
    2: "velocity pass (eq. 20)",
    3: "acceleration pass (eq. 21)",
    4: "contact search",
    5: "HHT Newton iteration (reduced method)",
}


def raise_status(status: int, info: np.ndarray) -> None:
    """Raise the :class:`ConvergenceError` of a kernel status (no-op for 0)."""
    if status == 0:
        return
    what = STATUS.get(int(status), f"kernel status {status}")
    if status == 4:
        raise ConvergenceError(what, float(info[0]), float("nan"), 0.0)
    raise ConvergenceError(what, float(info[0]), float(info[1]), float(info[2]))


@dataclass
class SolverOutput:
    """Histories of one run (all SI).

    ``records`` holds the global columns (time, disk angles and speeds, energies, pass
    statistics), ``pair_records`` the per-pair columns as (n_rec, npair) arrays.
    """

    records: dict
    pair_records: dict
    tie_multipliers: np.ndarray
    steps: int
    wall_time: float
    initial_energy: float
    dt: float
    snapshots: list = field(default_factory=list)  # (time, positions (N, 2))
    node_positions: np.ndarray | None = None  # (n_rec, len(record_nodes), 2)
    record_nodes: np.ndarray | None = None


def drive(
    step: Callable[[int, bool], tuple[int, int]],
    *,
    n_steps: int,
    record_every: int,
    time_of: Callable[[], float],
    positions: Callable[[], np.ndarray],
    info: np.ndarray,
    snapshots: int = 0,
    record_nodes=None,
    rec_x=None,
    progress=None,
    progress_every: int = 2000,
) -> tuple[int, list, float]:
    """The driver loop shared by every method.

    ``step(n, first)`` advances ``n`` steps and returns ``(status, rows written so far)``;
    ``positions()`` the current nodal positions (N, 2); ``time_of()`` the current time.
    The kernel is called in chunks of ``progress_every`` steps (a multiple of ``record_every``),
    shorter when snapshots are kept, and of one record when ``record_nodes`` are recorded (the
    state on return is then the recorded one). Returns (rows, snapshots, wall time [s]).
    """
    snaps = []
    snap_every = max(1, n_steps // snapshots) if snapshots else 0
    chunk = max(record_every, (progress_every // record_every) * record_every)
    if snap_every:
        chunk = min(chunk, max(record_every, (snap_every // record_every) * record_every))
    if record_nodes is not None:
        chunk = record_every
    t0 = time.perf_counter()
    done = 0
    row = 0
    first = True
    next_progress = progress_every
    while done < n_steps:
        n = min(chunk, n_steps - done)
        row_before = row
        status, row = step(n, first)
        first = False
        if rec_x is not None and row > row_before:
            rec_x[row - 1] = positions()[record_nodes]
        raise_status(status, info)
        done += n
        if snap_every and (done % snap_every < chunk or done == n_steps):
            snaps.append((float(time_of()), positions().copy()))
        if progress is not None and (done >= next_progress or done == n_steps):
            progress(done, n_steps)
            next_progress = done + progress_every
    return row, snaps, time.perf_counter() - t0
