"""Code that runs on the workers (local processes or Dask workers).

Everything here is importable by name and takes/returns plain picklable data: the client sends
``execute_case(case_fn, data)`` and gets an :class:`Outcome` back. Exceptions raised by the case
function are caught *in the worker* and returned as text, so an exception that reaches the
client from a future always means the infrastructure failed (worker died, pool broken,
connection lost), never the case itself.

With ``write_to`` (local workers, which share the client's file system) the worker also writes
the case's result files (:meth:`Result.save` into ``cases/<id>/``, a whole directory swapped in
at once) and sends back only a :class:`Written` (summary, status, continuation state); the
client then writes ``case.json``, the marker that the case is done. So the case files of
different cases are written in parallel, and a worker that dies while writing leaves no marker:
the case is run again.
"""

from __future__ import annotations

import importlib
import os
import socket
import time
import traceback
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
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
    #: the worker wrote the case's result files (``result`` is then a :class:`Written`)
    written: bool = False
    #: time the worker spent writing them [s]
    write_time: float = 0.0
    #: the I/O error (:class:`~rotaflex.core.io.WriteFailed`) that stopped the worker writing
    write_failed: BaseException | None = None
    #: CPU time of the worker process for this case, computing and writing [s]
    cpu_time: float = float("nan")


@dataclass(frozen=True)
class WriteTo:
    """Where a worker writes the result files of its case.

    Parameters
    ----------
    case_dir : str
        The case's directory (``out_dir/cases/<id>``), replaced as a whole.
    figures : bool
        Also write the case's own figures.
    """

    case_dir: str
    figures: bool = False


@dataclass
class Written:
    """What the client needs of a Result whose files a worker wrote: its summary scalars, status
    and message, and the state a continuation goes on from (None if the Result has none)."""

    scalars: dict[str, dict[str, Any]]
    status: str
    message: str
    state: Any = None

    def summary(self) -> dict[str, dict[str, Any]]:
        return self.scalars

    def final_state(self) -> Any:
        return self.state


def execute_case(case_fn: Callable[[Any], Any], data: Any, write_to: WriteTo | None = None, **kwargs: Any) -> Outcome:
    """Run ``case_fn(data, **kwargs)`` and wrap its result or its exception in an :class:`Outcome`.

    With ``write_to``, also write the Result's files there (:func:`write_case`).
    """
    t0, c0 = time.perf_counter(), time.process_time()
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
            cpu_time=time.process_time() - c0,
        )
    outcome = Outcome(result, "", "", time.perf_counter() - t0, worker)
    if write_to is not None:
        write_case(outcome, write_to, continued="initial_state" in kwargs)
    outcome.cpu_time = time.process_time() - c0
    return outcome


def write_case(outcome: Outcome, write_to: WriteTo, continued: bool = False) -> None:
    """Write ``outcome.result``'s files into ``write_to.case_dir`` and replace the Result by a
    :class:`Written` (in place).

    What fails here becomes the case's error, as if the case function had raised: a returned
    object that is not a Result, a ``summary()`` or ``final_state()`` (``continued``: the case
    is a link of a continuation) that raises, a figure that cannot be drawn. An I/O error
    (:class:`~rotaflex.core.io.WriteFailed`: full disk, ...) is sent back in ``write_failed``
    for the client to raise: it ends the sweep, as when the client writes. In every failure
    nothing was swapped into the case directory (:meth:`Result.save` writes a sibling first).
    """
    from rotaflex.core.io import WriteFailed

    t0 = time.perf_counter()
    result = outcome.result
    if not (hasattr(result, "save") and hasattr(result, "summary")):
        outcome.result = None
        outcome.error = f"TypeError: the case function returned {type(result).__name__}, not a Result"
        return
    try:
        written = Written(result.summary(), str(result.status), str(getattr(result, "message", "")))
        fs = getattr(result, "final_state", None)
        if continued and fs is not None:
            written.state = fs()
        case_dir = Path(write_to.case_dir)
        case_dir.parent.mkdir(parents=True, exist_ok=True)
        result.save(case_dir, figures=write_to.figures)
    except WriteFailed as exc:
        outcome.write_failed = exc
        return  # the client raises it
    except Exception as exc:  # noqa: BLE001 - this case's error; the sweep goes on
        outcome.result = None
        outcome.error, outcome.traceback = f"{type(exc).__name__}: {exc}", traceback.format_exc()
        return
    finally:
        outcome.write_time = time.perf_counter() - t0
    outcome.result, outcome.written = written, True


def write_outcome(outcome: Outcome, write_to: WriteTo) -> Outcome:
    """Write the files of a case computed by another worker (:func:`write_case`) and return the
    outcome with a :class:`Written` instead of the Result; its ``cpu_time`` grows by this
    process's CPU time for the writing.

    A continuation chain has one case in flight at a time, so with fewer chains than workers
    the spare workers write finished cases (:func:`rotaflex.sweep.continuation.drive_chains`).
    """
    c0 = time.process_time()
    write_case(outcome, write_to)
    outcome.cpu_time += time.process_time() - c0
    return outcome


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


def init_worker(client_pid: int, niceness: int = 0) -> None:
    """Initializer of local pool workers (``niceness``: added to the process's nice value).

    * Ctrl-C goes to the whole process group; the client handles it (one line, exit 130), so
      workers ignore SIGINT instead of printing their own tracebacks.
    * A daemon thread polls the client's pid and ends this worker when the client is gone
      (``kill -9`` of the client would otherwise leave workers computing for the rest of their
      case, orphaned).
    * BLAS/OpenMP pools pinned to one thread (one process per core already fills the machine).
    * xarray tells numpy from dask data without importing dask (:func:`rotaflex.core.io.defer_dask`):
      no case of a local sweep has dask data, and the import costs 0.5-1.5 s per worker.
    """
    import signal
    import threading

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if niceness:
        os.nice(niceness)

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
        from rotaflex.core.io import defer_dask

        defer_dask()
    except ImportError:  # pragma: no cover - xarray is a dependency
        pass
    try:
        from rotaflex.core.threads import limit_blas_threads

        limit_blas_threads(1)
    except ImportError:  # pragma: no cover - a dependency, but never fatal in a worker
        pass


def ping() -> int:
    """Health probe of a freshly started worker: its process id."""
    return os.getpid()
