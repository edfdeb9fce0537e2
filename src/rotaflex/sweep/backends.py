"""Executors for the sweep: a local process pool (default), serial, or a Dask cluster, and
:class:`_Backend`, how :func:`rotaflex.sweep.runner.run_sweep` submits to one of them.

Dask is optional (the ``rotaflex[dask]`` extra). ``executor_for`` turns the CLI's ``-j`` and
``--scheduler`` into an executor inside a context manager that cleans up what it started.
"""

from __future__ import annotations

import logging
import multiprocessing
import os
from collections.abc import Callable, Iterator
from concurrent.futures import (
    Executor,
    Future,
    ProcessPoolExecutor,
    ThreadPoolExecutor,
)
from concurrent.futures.process import BrokenProcessPool
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from rotaflex.core.errors import InputError
from rotaflex.sweep._worker import Outcome, WriteTo, execute_case, init_worker, ping, write_outcome
from rotaflex.sweep.spec import Case

log = logging.getLogger("rotaflex.sweep")

#: seconds to wait for a scheduler to answer and for its first worker
CONNECT_TIMEOUT = 30.0

_EXTRA = "rotaflex installed with the Dask extra: pip install 'rotaflex[dask]'"


def _distributed():
    try:
        import distributed
    except ImportError as exc:
        raise InputError("scheduler", "dask", f"{_EXTRA} (import failed: {exc})") from None
    return distributed


@contextmanager
def dask_executor(address: str, *, n_workers: int | None = None, timeout: float | None = None) -> Iterator[Any]:
    """A ``concurrent.futures`` executor on a Dask cluster.

    Parameters
    ----------
    address : str
        ``tcp://host:port`` of a running ``dask scheduler``, or ``"dask-local"`` to start a
        ``LocalCluster`` here (processes, one thread per worker, ``n_workers`` of them).
    n_workers : int, optional
        Workers of the local cluster (default: one per core); ignored for an address.
    timeout : float, optional
        Seconds to wait for the scheduler to answer and for a first worker [s]
        (default :data:`CONNECT_TIMEOUT`).

    Yields
    ------
    distributed.cfexecutor.ClientExecutor
        ``Client(address).get_executor(pure=False)``: each submission is a new task, so a case
        can be resubmitted after ``KilledWorker``.
    """
    distributed = _distributed()
    timeout = CONNECT_TIMEOUT if timeout is None else timeout
    cluster = None
    client = None
    dlog = logging.getLogger("distributed")
    level = dlog.level
    if not log.isEnabledFor(logging.DEBUG):
        dlog.setLevel(logging.WARNING)  # cluster start/stop chatter is INFO
    try:
        if address == "dask-local":
            cluster = _local_cluster(distributed, n_workers)
            client = distributed.Client(cluster)
        else:
            try:
                client = distributed.Client(address, timeout=timeout)
            except (OSError, TimeoutError, ValueError) as exc:
                raise InputError(
                    "scheduler",
                    address,
                    f"the address of a reachable Dask scheduler, tcp://host:port, or 'dask-local' ({exc})",
                ) from None
        try:
            client.wait_for_workers(1, timeout=timeout)
        except TimeoutError:
            raise InputError(
                "scheduler",
                address,
                f"a Dask scheduler with at least one worker (none connected within {timeout:g} s)",
            ) from None
        _check_versions(client)
        log.info(
            "Dask: %d worker threads at %s",
            sum(client.nthreads().values()),
            client.scheduler.address,
        )
        yield client.get_executor(pure=False)
    except BaseException:
        # Ctrl-C/SIGTERM or an error: the CLI says so in one line; the cluster's notes on
        # cancelled tasks and on workers killed after its grace period are only noise now
        logging.disable(logging.CRITICAL)
        raise
    finally:
        try:
            if client is not None:
                client.close()
            if cluster is not None:
                cluster.close()
        finally:
            logging.disable(logging.NOTSET)
            dlog.setLevel(level)


def _local_cluster(distributed, n_workers: int | None):
    """A LocalCluster of single-threaded worker processes for simulations (logging errors only).

    Dask's nanny sets ``MALLOC_TRIM_THRESHOLD_=65536`` in its workers (to return memory to the
    OS). Setting it disables glibc's adaptive mmap threshold, so every numpy temporary above
    128 kB becomes an mmap/munmap pair: a loop of 150 x 150 matrix products ran 4-5x slower
    here. The workers of our local cluster keep glibc's default; the thread limits stay.
    """
    import dask

    env = dict(dask.config.get("distributed.nanny.pre-spawn-environ", {}) or {})
    env.pop("MALLOC_TRIM_THRESHOLD_", None)
    # the workers' own log lines (a task cancelled by Ctrl-C, ...) go to the user's terminal;
    # errors are enough there (a case's failure reaches the client with its traceback)
    env.setdefault("DASK_LOGGING__DISTRIBUTED", "error")
    with dask.config.set({"distributed.nanny.pre-spawn-environ": env}):
        return distributed.LocalCluster(
            n_workers=n_workers, threads_per_worker=1, processes=True, dashboard_address=":0"
        )


def _check_versions(client) -> None:
    """Warn when a worker's rotaflex differs from the client's (its results would differ)."""
    import rotaflex
    from rotaflex.sweep._worker import rotaflex_version

    try:
        versions = client.run(rotaflex_version)
    except Exception as exc:  # noqa: BLE001 - a worker without rotaflex fails here
        raise InputError(
            "scheduler",
            str(client.scheduler.address),
            f"workers that can import rotaflex {rotaflex.__version__} ({exc})",
        ) from None
    bad = {w: v for w, v in versions.items() if v != rotaflex.__version__}
    if bad:
        log.warning(
            "workers run another rotaflex version than the client (%s): %s",
            rotaflex.__version__,
            bad,
        )


@contextmanager
def executor_for(jobs: int | None = None, scheduler: str | None = None) -> Iterator[Any]:
    """The executor for ``run_sweep`` from the CLI options.

    ``scheduler`` given: a Dask executor (see :func:`dask_executor`); ``jobs == 0``: serial in
    this process; otherwise ``jobs`` local processes (``None``: one per core) - returned as an
    int so that ``run_sweep`` owns the pool and can rebuild it if a worker dies.
    """
    if jobs is not None and jobs < 0:
        raise InputError("jobs", jobs, "an integer >= 0 (0 = serial in this process)")
    if scheduler:
        with dask_executor(scheduler, n_workers=jobs or None) as ex:
            yield ex
    elif jobs == 0:
        yield "serial"
    else:
        yield jobs


class SerialExecutor(Executor):
    """Runs each submitted call at once in this process (debugging, tiny sweeps, reference)."""

    _max_workers = 1

    def submit(self, fn, /, *args, **kwargs):
        """Call ``fn(*args, **kwargs)`` now; the returned future holds its result or exception."""
        fut: Future = Future()
        try:
            fut.set_result(fn(*args, **kwargs))
        except BaseException as exc:  # noqa: BLE001 - handed to the caller through the future
            fut.set_exception(exc)
        return fut


#: thread-count variables set to 1 for local workers unless the user set them (as Dask's nanny
#: does): N processes x M BLAS threads on N cores oversubscribe the CPU and run much slower
THREAD_VARS = (
    "OMP_NUM_THREADS",
    "OPENBLAS_NUM_THREADS",
    "MKL_NUM_THREADS",
    "VECLIB_MAXIMUM_THREADS",
    "NUMEXPR_NUM_THREADS",
    "NUMBA_NUM_THREADS",
)


#: modules every local worker needs, imported once in the fork server (``h5netcdf``: the
#: workers write their cases' files). Not ``dask.array``: xarray would import it (0.5-1.5 s)
#: when it builds its first Dataset, but :func:`~rotaflex.sweep._worker.init_worker` lets
#: xarray answer its "is this dask data" question without it (:func:`rotaflex.core.io.defer_dask`)
PRELOAD = ("numpy", "xarray", "h5netcdf", "rotaflex.sweep._worker", "rotaflex.core.result")


def _quiet_resource_tracker() -> None:
    """Keep multiprocessing's resource tracker from printing warnings after an interrupt.

    Ctrl-C ends a sweep with one line and ``os._exit``; the tracker (a separate process started
    with this process's environment) then unlinks the pool's semaphores, which is its job, and
    warns about each one. The cleanup is right; the warnings only bury the one line.
    """
    rule = "ignore:resource_tracker:UserWarning"
    current = os.environ.get("PYTHONWARNINGS", "")
    if rule not in current.split(","):
        os.environ["PYTHONWARNINGS"] = f"{current},{rule}" if current else rule


#: longest path of the temporary directory multiprocessing is given inside an output: the fork
#: server listens on a socket there (``listener-XXXXXXXX``) and AF_UNIX paths end at 107 bytes
MAX_MP_DIR = 80


def mp_temp_dir(out_dir: str | Path) -> Path | None:
    """Give multiprocessing its temporary directory inside ``out_dir`` (``.mp``), not ``/tmp``.

    The client's fork server listens on a socket in that directory, which multiprocessing
    removes at a normal exit; a client killed with SIGKILL cannot, and left a ``pymp-*`` temporary
    directory per killed sweep. Inside the output, the next run in it removes what a killed run
    left. Nothing changes when this process has its directory already (a fork server started
    by an earlier sweep of the same process) or the path would be too long for a socket.
    Returns the directory used, or None.
    """
    import shutil
    from multiprocessing import process, util

    d = Path(out_dir) / ".mp"
    config = process.current_process()._config
    if config.get("tempdir") == str(d):
        return d
    shutil.rmtree(d, ignore_errors=True)  # left by a killed run in this output
    if config.get("tempdir") is not None or len(str(d.resolve())) > MAX_MP_DIR:
        return None
    d.mkdir(parents=True)
    config["tempdir"] = str(d.resolve())
    util.Finalize(None, shutil.rmtree, args=(str(d.resolve()), True), exitpriority=-100)
    # the fork server and the workers (other processes) make their own: there too
    os.environ["TMPDIR"] = str(d.resolve())
    return d


def process_pool(
    max_workers: int | None = None, preload: tuple[str, ...] = (), probe: bool = True, niceness: int = 0
) -> ProcessPoolExecutor:
    """A local process pool whose workers start from a clean interpreter, one thread each.

    POSIX uses the ``forkserver`` start method with :data:`PRELOAD` and ``preload`` (e.g. the
    module of the case function) imported once in the fork server, so each worker starts with
    them imported (fast worker start, no fork of a threaded client; a module that fails to
    import is skipped there and imported by the worker as usual); elsewhere ``spawn``. The
    preload applies when this process starts its fork server, i.e. for its first pool. The
    variables of :data:`THREAD_VARS` are 1 in the workers unless already set. The pool is
    started (and, with ``probe``, probed) before it is returned.
    """
    _quiet_resource_tracker()
    methods = multiprocessing.get_all_start_methods()
    if "forkserver" in methods:
        ctx = multiprocessing.get_context("forkserver")
        ctx.set_forkserver_preload(list(dict.fromkeys([*PRELOAD, *preload])))
    else:  # pragma: no cover - Windows
        ctx = multiprocessing.get_context("spawn")
    pool = ProcessPoolExecutor(
        max_workers=max_workers or os.cpu_count() or 1,
        mp_context=ctx,
        initializer=init_worker,
        initargs=(os.getpid(), niceness),
    )
    added = {k: "1" for k in THREAD_VARS if k not in os.environ}
    os.environ.update(added)  # inherited by the fork server / spawned workers started now
    try:
        probed = pool.submit(ping)
        if probe:
            probed.result()
    except BrokenProcessPool:
        pool.shutdown(wait=False, cancel_futures=True)
        raise RuntimeError(
            "the local worker processes could not start. If the sweep is run from a script, put "
            'the code that starts it under `if __name__ == "__main__":` (workers import the main '
            "module; see the multiprocessing docs)"
        ) from None
    finally:
        for k in added:
            os.environ.pop(k, None)
    return pool


#: added to the nice value of the processes that write the cases of fewer chains than workers
WRITER_NICENESS = 10


#: executors whose workers write into this process's file system (the case files are then
#: written by the worker that computed the case)
LOCAL_EXECUTORS = (ProcessPoolExecutor, ThreadPoolExecutor, SerialExecutor)


class _Backend:
    """The executor a sweep runs on, whether it can be rebuilt after it breaks, and where its
    workers write the case files.

    ``case_files``: ``(out_dir, case_figures)`` of a sweep that writes its cases; on a local
    executor (:data:`LOCAL_EXECUTORS`) each submitted case then carries a :class:`WriteTo`,
    unless fewer cases than workers can run at once (``streams``: independent cases, or
    continuation chains): then the client writes a case while the next one of its chain
    computes, which is faster than the worker doing both in turn (a case of the gear example:
    ~72 ms CPU to write, ~32 ms to compute). A pool this backend starts itself (``None`` or an
    int) then gets one worker per chain, and the workers left over form :attr:`writer`, a
    pool at nice +10 (:data:`WRITER_NICENESS`) that writes finished cases next to the client
    (:func:`rotaflex.sweep.continuation.drive_chains`).
    """

    def __init__(
        self,
        executor: Any,
        preload: tuple[str, ...] = (),
        case_files: tuple[Path, bool] | None = None,
        streams: int | None = None,
    ):
        self.case_files = case_files
        self.streams = streams
        self.factory: Callable[[], Executor] | None = None
        self.owned = False
        #: a pool of its own for writing the case files of fewer chains than workers
        self.writer: Executor | None = None
        spare = 0
        if executor is None or (isinstance(executor, int) and not isinstance(executor, bool)):
            n = executor if executor is not None else os.cpu_count() or 1
            if n < 1:
                raise ValueError(f"executor = {executor}: a number of processes must be >= 1")
            if case_files is not None and streams is not None and 0 < streams < n:
                spare = n - streams
            self.factory, self.owned = (lambda: process_pool(n - spare, preload)), True
        elif executor == "serial":
            self.factory, self.owned = SerialExecutor, True
        elif isinstance(executor, Executor):
            self.executor = executor
        elif callable(executor):
            self.factory, self.owned = executor, True
        else:
            raise TypeError(f"executor must be None, 'serial', an int, an Executor or a factory, not {executor!r}")
        if self.factory is not None:
            self.executor = self._start()
        if spare:
            # not waited for (a broken one is dropped); lower priority: on a loaded machine
            # its writes take only CPU the chain's computing worker leaves
            self.writer = process_pool(spare, probe=False, niceness=WRITER_NICENESS)
        self.window = 2 * _n_workers(self.executor)

    @property
    def workers_write(self) -> bool:
        """The workers write the case files (a sweep with an output on a local executor, with
        at least as many cases or chains to run at once as workers)."""
        if self.case_files is None or self.writer is not None or not isinstance(self.executor, LOCAL_EXECUTORS):
            return False
        return self.streams is None or self.streams >= _n_workers(self.executor)

    def submit_write(self, case: Case, outcome: Outcome) -> Future:
        """Submit :func:`write_outcome` of a finished case (its Result) to :attr:`writer`."""
        out, figures = self.case_files
        return self.writer.submit(write_outcome, outcome, WriteTo(str(out / "cases" / case.id), figures))

    def drop_writer(self) -> None:
        """Stop using :attr:`writer` (it broke: the client writes from now on)."""
        if self.writer is not None:
            _stop_pool(self.writer)
            self.writer = None

    def submit(self, case_fn: Callable, case: Case, **kwargs: Any) -> Future:
        """Submit ``execute_case(case_fn, case.data, **kwargs)``, with the case's
        :class:`WriteTo` when the workers write."""
        if self.workers_write:
            out, figures = self.case_files
            kwargs["write_to"] = WriteTo(str(out / "cases" / case.id), figures)
        return self.executor.submit(execute_case, case_fn, case.data, **kwargs)

    def figure_pools(self) -> list[tuple[ProcessPoolExecutor, int]]:
        """Workers that draw sweep figures next to the client: the local process pool's, at
        most one fewer than the cores (the client draws too; a worker pays matplotlib's import
        first, ~0.6-0.9 s), not the lower-priority writer pool; none on Dask, serial or
        thread executors."""
        if not isinstance(self.executor, ProcessPoolExecutor):
            return []
        n = min(_n_workers(self.executor), (os.cpu_count() or 1) - 1)
        return [(self.executor, n)] if n > 0 else []

    def rebuild(self) -> None:
        if self.factory is None:
            raise RuntimeError(
                "the executor broke (a worker process died) and cannot be rebuilt: "
                "pass executor=None, an int, or a factory instead of an instance"
            )
        self.shutdown(wait=False)
        self.executor = self._start()
        log.warning("rebuilt the process pool after a worker died")

    def _start(self) -> Executor:
        return self.factory()

    def shutdown(self, wait: bool = True) -> None:
        if not self.owned:
            return
        ex = self.executor
        if isinstance(ex, ProcessPoolExecutor) and not wait:
            _stop_pool(ex)
        else:
            ex.shutdown(wait=wait)
        if self.writer is not None:
            if wait:
                self.writer.shutdown(wait=True)
            else:
                _stop_pool(self.writer)


def _stop_pool(ex: ProcessPoolExecutor) -> None:
    """Shut a process pool down at once, its running workers terminated (no public way in
    Python < 3.14)."""
    procs = list((getattr(ex, "_processes", None) or {}).values())
    ex.shutdown(wait=False, cancel_futures=True)
    for p in procs:
        if p.is_alive():
            p.terminate()


def _modules_of(case_fn: Any) -> tuple[str, ...]:
    """Modules a case function runs: its own and, for a ``partial`` of a ``"module:function"``
    target (:func:`~rotaflex.sweep._worker.run_target`), the target's module."""
    mods = []
    fn = getattr(case_fn, "func", case_fn)
    if isinstance(getattr(fn, "__module__", None), str) and fn.__module__ != "__main__":
        mods.append(fn.__module__)
    for arg in getattr(case_fn, "args", ()):
        if isinstance(arg, str) and ":" in arg:
            mods.append(arg.partition(":")[0])
    return tuple(mods)


def _n_workers(executor: Executor) -> int:
    n = getattr(executor, "_max_workers", None)
    if n:
        return int(n)
    client = getattr(executor, "_client", None)  # distributed.cfexecutor.ClientExecutor
    if client is not None:
        try:
            return max(1, sum(client.nthreads().values()))
        except Exception:  # noqa: BLE001 - best effort sizing only
            pass
    return os.cpu_count() or 1
