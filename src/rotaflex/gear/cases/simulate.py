"""``rotaflex gear simulate``: configuration -> solver -> result.

The schema and the conversion to SI are in :mod:`rotaflex.gear.cases.simulate_config` (TOML layout there), the
integrators in :mod:`rotaflex.gear.solvers.registry` (``METHODS``), the dataset and figures in
:mod:`rotaflex.gear.results.transient`.

Driver: gear A (the pinion of a ``[pinion]``/``[wheel]`` pair) turns counter-clockwise about the
origin, B clockwise about (0, a) (``direction = "reverse"``: the mirror image about x = 0). The
driver gets the drive torque (in its running direction), the other gear the load torque times
the ratio (against its running direction). ``driver = "B"`` (``"wheel"``) is run as the mirror
image (reflection about y = a/2 maps a counter-clockwise driver at the origin onto a clockwise
driver at (0, a)): the kernel simulates the driver as its gear A, and the outputs are relabelled
(gear axes swapped, contact points mirrored), which is exact for any two gears.
"""

from __future__ import annotations

import json
import time
from dataclasses import asdict

from rotaflex.gear.cases.simulate_config import GearCaseConfig, build, elastic_constants, load_config, to_run
from rotaflex.gear.results.sweep_figures import sweep_figures
from rotaflex.gear.results.transient import GearResult, build_dataset

#: root schema of the configuration (for generated templates and config docs)
SCHEMA = GearCaseConfig

__all__ = [
    "SCHEMA",
    "GearCaseConfig",
    "GearResult",
    "build",
    "prepare",
    "run_case",
    "sweep_figures",
    "validate_config",
]


#: the last :func:`prepare` of :func:`validate_config`, by config content, handed to the
#: :func:`run_case` of the same config once (the CLI validates, then runs: one model build)
_VALIDATED: dict[str, tuple] = {}


def _key(config: dict) -> str:
    return json.dumps(config, sort_keys=True, default=repr)


def prepare(config: dict):
    """Validated configuration, geometry, mesh, model (with the static preload of several teeth)
    and the SI run description, without integrating."""
    cfg = load_config(config)
    geo, mesh, model = build(cfg)
    run = to_run(cfg, geo, model)
    return cfg, geo, mesh, model, run


def validate_config(config: dict) -> None:
    """Raise :class:`~rotaflex.core.errors.InputError` for a configuration that
    :func:`run_case` would refuse: schema, geometry, angles, step and memory budgets and the
    time-step limits of the model are checked; builds the model (FE assembly, about a second on
    the default mesh) but does not integrate."""
    from rotaflex.core.errors import InputError
    from rotaflex.gear.models.fe_pair import tie_eigen_bounds

    prepared = prepare(config)
    cfg, _, _, model, run = prepared
    if run.method == "paper_rk4":
        if run.dt > model.dt_limit:
            raise InputError(
                "solver.dt", cfg.solver.dt, f"a step <= the RK4 stability limit of the mesh, {model.dt_limit:.4g} s"
            )
        tie_eigen_bounds(model, run.dt)
    _VALIDATED.clear()  # one entry: a sweep validates every case before any runs
    _VALIDATED[_key(config)] = prepared


def _preload(cfg, model, run):
    if run.teeth_per_gear == 1:
        return model
    from rotaflex.gear.models.multitooth import static_preload

    smoothing = run.options.get("smoothing", 0)
    return static_preload(model, run.torque, *elastic_constants(cfg), run.theta_s, run.window, smoothing=smoothing)


#: measured first-run compilation before the first result of `gear simulate` per method [s]
#: (benchmarks/bench_compile.py gear-coarse, gear-reduced: CPU time on the 2-core machine;
#: docs/performance.md)
COMPILE_SECONDS = {"paper_rk4": 41.0, "reduced_hht": 16.0}


def announce_kernels(method: str) -> bool:
    """Say once, before the first kernel call, that ``method``'s kernels compile now (cold numba
    cache only). The entry kernel is checked: the kernels it calls are compiled into it."""
    from rotaflex.core.jit import announce_compilation

    if method == "reduced_hht":
        from rotaflex.gear.kernels.hht import run_hht as entry
    else:
        from rotaflex.gear.kernels.rk4 import run_steps as entry
    return announce_compilation("gear", [entry], COMPILE_SECONDS.get(method, COMPILE_SECONDS["paper_rk4"]))


def run_case(config: dict, *, progress: bool = False) -> GearResult:
    """Validate ``config`` (see :mod:`rotaflex.gear.cases.simulate_config`), simulate, and wrap the histories."""
    from rotaflex.gear.solvers.registry import METHODS

    t_wall = time.perf_counter()
    prepared = _VALIDATED.pop(_key(config), None)
    cfg, geo, _, model, run = prepare(config) if prepared is None else prepared
    announce_kernels(run.method)
    model = _preload(cfg, model, run)
    probe = None
    # reduced_hht eliminates the fillet nodes' FE field (Craig-Bampton): no root stress there
    if cfg.output.root_stress and run.method == "paper_rk4" and run.teeth_per_gear == 1:
        from rotaflex.gear.results.post import root_stress_probe

        probe = root_stress_probe(model, *elastic_constants(cfg))
    kw = dict(
        run.options,
        speeds=run.speeds,
        torque=run.torque,
        theta_2=run.theta_2,
        theta_s=run.theta_s,
        span=run.span,
        dt=run.dt,
        record_every=run.every,
        snapshots=cfg.output.vtu_snapshots,
    )
    if probe is not None:
        kw["record_nodes"] = probe.nodes
    if run.teeth_per_gear > 1:
        kw.update(window=run.window)
    bar = None
    if progress:  # a bar on a terminal, one line per update in a log
        from rotaflex.core.progress import Progress

        bar = Progress(1, "gear", "step")

        def cb(done, total):
            bar.update(done, total)

        kw["progress"] = cb
    try:
        out = METHODS[run.method](model, kw)
    finally:
        if bar is not None:
            bar.close()
    ds = build_dataset(out, model, geo, run, probe)
    ds.attrs.update(wall_time=time.perf_counter() - t_wall, config=json.dumps(asdict(cfg)))
    return GearResult(ds)
