"""Code that runs on the workers (local processes or Dask workers).

Everything here is importable by name and takes/returns plain picklable data: the client sends
``execute_case(case_fn, data)`` and gets an :class:`Outcome` back. Exceptions raised by the case
function are caught *in the worker* and returned as text, so an exception that reaches the
client from a future always means the infrastructure failed (worker died, pool broken,
connection lost), never the case itself.
"""

from __future__ import annotations

import importlib
import os
import socket
import time
import traceback
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any


@dataclass
class Outcome:
    """What a worker sends back for one case.

    Parameters
    ----------
    result : Result or None
        The case's result (None when the case raised).
    error : str
        ``"ExceptionType: message"`` when the case raised, else ``""``.
    traceback : str
        Formatted traceback of the error (``""`` on success).
    wall_time : float
        Time spent in the case function on the worker [s].
    worker : str
        ``host:pid`` of the worker process.
    """

    result: Any
    error: str
    traceback: str
    wall_time: float
    worker: str


def execute_case(case_fn: Callable[[Any], Any], data: Any, **kwargs: Any) -> Outcome:
    """Run ``case_fn(data, **kwargs)`` and wrap its result or its exception in an :class:`Outcome`."""
    t0 = time.perf_counter()
    worker = f"{socket.gethostname()}:{os.getpid()}"
    try:
        result = case_fn(data, **kwargs)
    except Exception as exc:  # noqa: BLE001 - every case error is recorded, the sweep goes on
        return Outcome(
            None,
            f"{type(exc).__name__}: {exc}",
            traceback.format_exc(),
            time.perf_counter() - t0,
            worker,
        )
    return Outcome(result, "", "", time.perf_counter() - t0, worker)


def run_module_case(module: str, config: dict) -> Any:
    """``run_case(config)`` of the domain module ``module`` (e.g. ``"rotaflex.rotor.case"``).

    The client resolves the domain name to the module, so the workers need only the module
    importable (same rotaflex version), not the client's registry.
    """
    return importlib.import_module(module).run_case(config, progress=False)


def run_target(target: str, config: dict, **kwargs: Any) -> Any:
    """``function(config, progress=False, **kwargs)`` of a ``"module:function"`` target (a
    domain verb, :func:`rotaflex.core.domains.command_target`); ``kwargs`` e.g.
    ``initial_state`` of a continuation."""
    module, _, name = target.partition(":")
    return getattr(importlib.import_module(module), name)(config, progress=False, **kwargs)


def rotaflex_version() -> str:
    """The rotaflex version importable on this worker (compared with the client's)."""
    import rotaflex

    return rotaflex.__version__


#: seconds between checks that the client process is still alive
PARENT_POLL = 1.0


def init_worker(client_pid: int) -> None:
    """Initializer of local pool workers.

    * Ctrl-C goes to the whole process group; the client handles it (one line, exit 130), so
      workers ignore SIGINT instead of printing their own tracebacks.
    * A daemon thread polls the client's pid and ends this worker when the client is gone
      (``kill -9`` of the client would otherwise leave workers computing for the rest of their
      case, orphaned).
    * BLAS/OpenMP pools pinned to one thread (one process per core already fills the machine).
    """
    import signal
    import threading

    signal.signal(signal.SIGINT, signal.SIG_IGN)

    def watch() -> None:
        while True:
            time.sleep(PARENT_POLL)
            try:
                os.kill(client_pid, 0)
            except ProcessLookupError:
                os._exit(1)
            except PermissionError:  # pid reused by another user's process: the client is gone
                os._exit(1)

    threading.Thread(target=watch, name="rotaflex-parent-watch", daemon=True).start()
    try:
        from rotaflex.core.threads import limit_blas_threads

        limit_blas_threads(1)
    except ImportError:  # pragma: no cover - a dependency, but never fatal in a worker
        pass


def ping() -> int:
    """Health probe of a freshly started worker: its process id."""
    return os.getpid()
