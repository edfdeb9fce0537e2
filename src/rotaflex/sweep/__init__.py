"""Parameter studies: many cases of one model, on local processes or a Dask cluster.

Data in, data out, over a ``concurrent.futures.Executor``: the case function is an importable
top-level function taking plain picklable data and returning a
:class:`~rotaflex.core.result.Result`; the client writes one directory per finished case, so
an interrupted sweep resumes.

Python API::

    from rotaflex.sweep import run_sweep, grid_cases, sweep_config
    res = run_sweep(case_fn, cases, executor=None, out_dir="out/s", progress=True)
    res.dataset            # xarray.Dataset, swept parameters as dimensions

Command line: ``rotaflex sweep CONFIG.toml --vary KEY=START:STOP:N --out DIR [-j N]
[--scheduler tcp://host:port | dask-local] [--continuation KEY]``; a top-level ``verb`` key in
the config sweeps another verb of the domain (e.g. ``verb = "steady"`` for gear).
"""

from rotaflex.sweep.backends import SerialExecutor, process_pool
from rotaflex.sweep.runner import CaseRecord, SweepResult, run_sweep
from rotaflex.sweep.spec import Case, as_cases, grid_cases, parse_vary
from rotaflex.sweep.study import Study, plan, plan_study, sweep_config

__all__ = [
    "Case",
    "CaseRecord",
    "SerialExecutor",
    "Study",
    "SweepResult",
    "as_cases",
    "grid_cases",
    "parse_vary",
    "plan",
    "plan_study",
    "process_pool",
    "run_sweep",
    "sweep_config",
]
