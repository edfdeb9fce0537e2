"""TEST HELPER ONLY: a tiny deterministic case used by the sweep tests and benchmark.

It is not a physical model. It exists so the sweep machinery (executors, resume, retries after a
worker dies, combined output) can be tested without any simulation domain. It follows the
domain contract, ``run_case(config, *, progress=False) -> Result``, and on request it fails,
sleeps, burns CPU, or kills its own worker process (SIGKILL) to emulate a crashing worker.

Closed-form outputs (checked by the tests against the formulas, not against stored values):
``a = x**2 + y`` [m], ``b = n * sin(x)`` [s], and a series ``signal(t) = x sin(2 pi y t)``
on ``n`` points of ``t`` in [0, 1] s with ``signal_max = max |signal|`` [m].

:func:`run_chain` is a continuable verb for the continuation tests: its state is the running sum
of ``x`` and the number of cases so far, so the outputs ``running_sum`` and ``position`` show
the order in which a chain ran and that each case started from its predecessor's state.
"""

from __future__ import annotations

import json
import multiprocessing
import os
import signal
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rotaflex.core.config import from_mapping, param
from rotaflex.core.result import Result, register_result


@dataclass(frozen=True)
class SelftestConfig:
    x: float = param(1.0, unit="m", doc="first input")
    y: float = param(0.0, unit="Hz", doc="second input")
    n: int = param(16, ge=2, doc="number of samples of the series")
    fail: bool = param(False, doc="raise a RuntimeError")
    sleep: float = param(0.0, ge=0.0, unit="s", doc="sleep this long before returning")
    work: int = param(0, ge=0, doc="CPU work: number of 150x150 matrix products")
    kill_once: str = param("", doc="if set and this file does not exist: create it, then SIGKILL self")
    kill_always: bool = param(False, doc="SIGKILL the worker process every time")
    started_dir: str = param("", doc="if set, touch a file named after the pid here when starting")


def _die() -> None:
    if multiprocessing.parent_process() is None:
        raise RuntimeError("selftest refuses to kill a main process (use a process pool or Dask)")
    os.kill(os.getpid(), signal.SIGKILL)


def validate_config(config: dict) -> None:
    """Optional domain hook used by sweeps: raise InputError for a config ``run_case`` rejects."""
    from_mapping(SelftestConfig, config)


def run_case(config: dict, *, progress: bool = False) -> Result:
    """Compute the closed-form selftest outputs (see the module docstring)."""
    import xarray as xr

    cfg = from_mapping(SelftestConfig, config)
    t0 = time.perf_counter()
    if cfg.started_dir:
        Path(cfg.started_dir).mkdir(parents=True, exist_ok=True)
        (Path(cfg.started_dir) / f"{os.getpid()}-{time.time_ns()}").touch()
    if cfg.kill_always:
        _die()
    if cfg.kill_once:
        marker = Path(cfg.kill_once)
        try:
            marker.touch(exist_ok=False)
        except FileExistsError:
            pass
        else:
            _die()
    if cfg.fail:
        raise RuntimeError(f"selftest case asked to fail (x={cfg.x})")
    if cfg.sleep:
        time.sleep(cfg.sleep)
    if cfg.work:
        m = np.full((150, 150), 1.0 / 150)
        acc = np.eye(150)
        for _ in range(cfg.work):
            acc = acc @ m + np.eye(150) * 1e-3
    t = np.linspace(0.0, 1.0, cfg.n)
    sig = cfg.x * np.sin(2 * np.pi * cfg.y * t)
    ds = xr.Dataset(
        {
            "signal": ("time", sig, {"units": "m"}),
            "a": ((), cfg.x**2 + cfg.y, {"units": "m"}),
            "b": ((), cfg.n * np.sin(cfg.x), {"units": "s"}),
            "signal_max": ((), float(np.max(np.abs(sig))), {"units": "m"}),
        },
        coords={"time": ("time", t, {"units": "s"})},
        attrs={
            "status": "success",
            "message": "selftest",
            "wall_time": time.perf_counter() - t0,
            "config": json.dumps(config, sort_keys=True),
        },
    )
    return Result(ds)


@register_result
class ChainResult(Result):
    """Result of :func:`run_chain` with the state a continuation passes on."""

    kind = "selftest_chain"

    def final_state(self) -> dict:
        ds = self.dataset
        return {"sum": float(ds["running_sum"]), "count": int(ds["position"])}


def run_chain(config: dict, *, progress: bool = False, initial_state: dict | None = None) -> Result:
    """``run_case`` plus ``running_sum = previous sum + x`` and ``position = previous count + 1``."""
    base = run_case(config, progress=progress).dataset
    for key in ("result_kind", "result_class"):  # a ChainResult (it has the final state), not a Result
        base.attrs.pop(key, None)
    start = initial_state or {"sum": 0.0, "count": 0}
    x = from_mapping(SelftestConfig, config).x
    base["running_sum"] = ((), start["sum"] + x, {"units": "m"})
    base["position"] = ((), start["count"] + 1, {"units": "1"})
    return ChainResult(base)
