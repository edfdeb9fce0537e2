"""Size of a ``gear steady`` run, estimated before it starts, and the limits it is held to.

Two checks. :func:`check_size` runs at the config boundary (nothing built): steady states
(speeds x directions), mesh-table points, RK4 steps at ``steady.steps_per_cycle`` and the memory of
the histories. :func:`check_model_size` runs once the model is built, before the first step, with
the steps per cycle the solver will really take (raised above ``steady.steps_per_cycle`` where the
fastest mode needs it, e.g. at low speed); for ``steady.fixed_cycles`` its step count is exact.
Refusals name the key, the estimate and the limit (:mod:`rotaflex.core.limits`).
"""

from __future__ import annotations

from rotaflex.core.limits import require, require_memory
from rotaflex.gear.models.chain import OperatingPoint, TorsionalSystem

__all__ = [
    "MAX_STEPS",
    "MAX_SWEEP_POINTS",
    "MAX_TABLE_POINTS",
    "check_model_size",
    "check_size",
    "model_steps_per_cycle",
    "planned_size",
]

#: RK4 steps a run may plan (all speeds and directions together): ~1 us a lumped step and
#: ~10-100 us an elastic-teeth step on this 2-core machine, so 5e7 is about a minute (lumped)
MAX_STEPS = 50_000_000
#: samples per mesh cycle of the mesh stiffness and TE tables
MAX_TABLE_POINTS = 100_000
#: speeds x directions of an in-process sweep (larger sweeps: ``rotaflex sweep --continuation``)
MAX_SWEEP_POINTS = 10_000
#: float64 values per history row: angle and speed of up to 6 chain nodes (motor, pinion,
#: wheel, load, two lateral gear centres), mesh force, DTE and its rate, time
_ROW_VALUES = 2 * 6 + 4


def planned_size(cfg) -> dict:
    """Size of ``cfg``'s run estimated from the config alone (nothing is built).

    Returns
    -------
    dict
        ``points`` (steady states: speeds x directions, or 1), ``cycles`` (mesh cycles per
        point at most: ``fixed_cycles``, else ``max_cycles``), ``steps`` (RK4 steps at most,
        at ``steady.steps_per_cycle``; the solver raises the steps per cycle where the fastest
        train mode needs 40 points a period, so this is a lower bound then), ``history_bytes``
        (peak memory of the histories of one point [bytes]: the block being integrated, the
        kept cycles and the copy made when they are joined).
    """
    s = cfg.steady
    sp = cfg.sweep.speeds_rpm
    points = len(sp) * len(cfg.sweep.directions) if len(sp) >= 2 else 1
    cycles = s.fixed_cycles if s.fixed_cycles is not None else s.max_cycles
    block = min(s.eval_cycles, cycles)
    kept = min(max(s.eval_cycles, 8), cycles)  # the solver keeps max(eval_cycles, 2 x max_period=4)
    rows = (block + 2 * (kept + block)) * s.steps_per_cycle
    return {
        "points": points,
        "cycles": cycles,
        "steps": float(points) * cycles * s.steps_per_cycle,
        "history_bytes": 8.0 * _ROW_VALUES * rows,
    }


def check_size(cfg, table_name: str = "mesh_stiffness") -> None:
    """Refuse a run beyond :data:`MAX_STEPS`, :data:`MAX_TABLE_POINTS`, :data:`MAX_SWEEP_POINTS`
    or the memory limit, naming the key that makes it large."""
    s, size = cfg.steady, planned_size(cfg)
    table = f"{table_name}.table_points"
    points = cfg.mesh_stiffness.table_points
    require(
        table, points, points, MAX_TABLE_POINTS, "table points per mesh cycle", "fixed (gear steady MAX_TABLE_POINTS)"
    )
    require_memory(table, points, 8.0 * 12 * points, "the mesh tables")
    if size["points"] > 1:
        n = len(cfg.sweep.speeds_rpm)
        require(
            "sweep.speeds_rpm",
            f"{n} speeds",
            size["points"],
            MAX_SWEEP_POINTS,
            "steady states (speeds x directions)",
            "for more use rotaflex sweep --continuation operation.speed_rpm",
        )
    # blame the largest factor of the product: that is the key the user most likely mistyped
    cycles_key = "steady.fixed_cycles" if s.fixed_cycles is not None else "steady.max_cycles"
    factors = [
        (size["cycles"], cycles_key, size["cycles"]),
        (s.steps_per_cycle, "steady.steps_per_cycle", s.steps_per_cycle),
        (size["points"], "sweep.speeds_rpm", f"{len(cfg.sweep.speeds_rpm)} speeds"),
    ]
    _, key, value = max(factors, key=lambda f: f[0])
    require(
        key,
        value,
        size["steps"],
        MAX_STEPS,
        "RK4 steps (cycles x steady.steps_per_cycle x speeds)",
        "fixed (gear steady MAX_STEPS): lower the cycles, steady.steps_per_cycle or the speeds",
    )
    hist_key, hist_value = (
        ("steady.eval_cycles", s.eval_cycles)
        if s.eval_cycles * 8 > s.steps_per_cycle
        else ("steady.steps_per_cycle", s.steps_per_cycle)
    )
    require_memory(hist_key, hist_value, size["history_bytes"], "the histories of one steady state")


#: points per period of the fastest train mode the steady solvers resolve (their default)
POINTS_PER_PERIOD = 40


def model_steps_per_cycle(model, cfg) -> list[int]:
    """RK4 steps per mesh cycle the solver will take at each speed of ``cfg`` (sweep speeds, or
    the operating speed), for the built ``model``: ``steady.steps_per_cycle`` raised where the
    fastest train mode (and, for elastic teeth, the highest tooth frequency) needs it. At low
    speed this is far above ``steady.steps_per_cycle`` (the mesh cycle grows, the modes do not)."""
    s, op = cfg.steady, cfg.operation
    speeds = cfg.sweep.speeds_rpm if len(cfg.sweep.speeds_rpm) >= 2 else (op.speed_rpm,)
    if isinstance(model, TorsionalSystem):
        from rotaflex.gear.models.chain import _steps_per_cycle as per_cycle
    else:
        from rotaflex.gear.solvers.window_run import cycle_steps as per_cycle
    return [
        per_cycle(model, OperatingPoint(rpm, op.torque, op.ramp_cycles), s.steps_per_cycle, POINTS_PER_PERIOD)
        for rpm in speeds
    ]


def check_model_size(model, cfg) -> None:
    """The step and memory limits again with the steps per cycle of the built model (the
    config-boundary check in :func:`check_size` assumes ``steady.steps_per_cycle``)."""
    s, size = cfg.steady, planned_size(cfg)
    spc = model_steps_per_cycle(model, cfg)
    directions = len(cfg.sweep.directions) if len(spc) > 1 else 1
    steps = float(sum(spc)) * directions * size["cycles"]
    raised = max(spc) > s.steps_per_cycle
    # the speed is to blame when it multiplies the steps more than the cycle count does
    by_speed = max(spc) / s.steps_per_cycle > size["cycles"]
    key, value = ("operation.speed_rpm", cfg.operation.speed_rpm) if by_speed and len(spc) == 1 else (None, None)
    if key is None:
        key, value = (
            ("sweep.speeds_rpm", list(cfg.sweep.speeds_rpm)) if len(spc) > 1 else ("steady.max_cycles", s.max_cycles)
        )
        if len(spc) == 1 and s.fixed_cycles is not None:
            key, value = "steady.fixed_cycles", s.fixed_cycles
    why = f"; at this speed the fastest mode needs {max(spc)} steps per mesh cycle" if raised else ""
    require(
        key,
        value,
        steps,
        MAX_STEPS,
        "RK4 steps",
        f"fixed (gear steady MAX_STEPS): fewer cycles or speeds, or a higher speed{why}",
    )
    require_memory(
        key, value, size["history_bytes"] * max(spc) / s.steps_per_cycle, "the histories of one steady state"
    )


#: measured first-run compilation of the steady kernels [s]: the lumped chain (kernels/chain)
#: and the elastic-teeth window (kernels/window), cold NUMBA_CACHE_DIR, CPU time of the
#: compilations on the 2-core machine (benchmarks/bench_compile.py gear-steady: 2.1 s; the
#: elastic_teeth_relief example: 3.8 s; docs/performance.md)
COMPILE_SECONDS = {"lumped": 2.0, "elastic_teeth": 4.0}


def announce_kernels(method: str) -> bool:
    """Say once, before the first kernel call, that ``method``'s kernels compile now (cold numba
    cache only). The entry kernel is checked: the kernels it calls are compiled into it."""
    from rotaflex.core.jit import announce_compilation

    if method == "elastic_teeth":
        from rotaflex.gear.kernels.window import run_window_rk4 as entry
    else:
        from rotaflex.gear.kernels.chain import run_rk4 as entry
    return announce_compilation("gear steady", [entry], COMPILE_SECONDS[method])
