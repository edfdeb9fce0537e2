"""Executors for the sweep: a local process pool (default) or a Dask cluster.

Dask is optional (the ``rotaflex[dask]`` extra). ``executor_for`` turns the CLI's ``-j`` and
``--scheduler`` into an executor inside a context manager that cleans up what it started.
"""

from __future__ import annotations

import logging
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

from rotaflex.core.errors import InputError

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
