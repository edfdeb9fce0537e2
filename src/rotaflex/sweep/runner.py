"""Run the cases of a sweep over a ``concurrent.futures.Executor``; write one directory per case.

The client (this process) submits ``execute_case(case_fn, case.data)`` to the executor. Each
finished case gets its directory ``out_dir/cases/<id>/``: ``result.nc`` and ``summary.json``
(:meth:`Result.save`, the directory swapped in as a whole), then ``case.json``, the marker that
the case is done, always written last by the client. On a local executor (process pool, serial)
the worker that computed the case writes its result files itself, so the files of different
cases are written in parallel and only the summary comes back; on any other executor (Dask,
whose workers may not share this file system) the Result comes back and the client writes them.
A re-run skips the cases whose marker says done; cases that raised (or whose files could not
be made, e.g. a figure that raised) are recorded in ``error.txt`` and attempted again by the
next run. A full disk (:class:`~rotaflex.core.io.WriteFailed`) ends the sweep.

Worker deaths: a local process pool that breaks (a worker was killed) is rebuilt and the cases
that were in flight are re-run one at a time, so the case that kills its worker is identified
and retried alone, and the others are not blamed. On Dask, a task whose workers keep dying
ends in ``KilledWorker``; the case is resubmitted up to ``max_retries`` times.
"""

from __future__ import annotations

import importlib
import json
import logging
import threading
import time
from collections import deque
from collections.abc import Callable, Iterable, Mapping
from concurrent.futures import (
    FIRST_COMPLETED,
    CancelledError,
    Future,
    ThreadPoolExecutor,
    wait,
)
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from rotaflex.core.io import WriteFailed, write_json_atomic, write_text_atomic
from rotaflex.sweep._worker import Outcome
from rotaflex.sweep.backends import (
    SerialExecutor,
    _Backend,
    _modules_of,
)
from rotaflex.sweep.spec import Case, as_cases, case_id

log = logging.getLogger("rotaflex.sweep")


@dataclass
class CaseRecord:
    """What the sweep knows about one case after the run.

    ``status`` is the Result's status (``"success"`` or a failure word), ``"error"`` when the
    case function raised or its worker kept dying, or ``"missing"`` when it was never run.
    """

    id: str
    params: dict[str, Any]
    status: str = "missing"
    error: str = ""
    summary: dict[str, dict[str, Any]] = field(default_factory=dict)
    wall_time: float = float("nan")
    attempts: int = 0
    computed: bool = False
    worker: str = ""

    @property
    def ok(self) -> bool:
        """True when done (success or a finding; :func:`rotaflex.core.result.completed`)."""
        from rotaflex.core.result import completed

        return completed(self.status)


@dataclass
class SweepResult:
    """Outcome of :func:`run_sweep`.

    Attributes
    ----------
    records : list of CaseRecord
        One per case, in the order given.
    dataset : xarray.Dataset
        Combined summary scalars with the swept parameters as dimensions (see
        :func:`rotaflex.sweep.combine.combine`); written to ``out_dir/sweep.nc``.
    out_dir : Path or None
    wall_time : float
        Wall time of the whole sweep [s].
    """

    records: list[CaseRecord]
    dataset: Any
    out_dir: Path | None = None
    wall_time: float = float("nan")
    figures: list[Path] = field(default_factory=list)

    @property
    def n_cases(self) -> int:
        return len(self.records)

    @property
    def n_failed(self) -> int:
        return sum(not r.ok for r in self.records)

    @property
    def n_computed(self) -> int:
        return sum(r.computed for r in self.records)

    @property
    def n_reused(self) -> int:
        return sum(r.ok and not r.computed for r in self.records)

    @property
    def failed(self) -> list[CaseRecord]:
        return [r for r in self.records if not r.ok]

    def to_xarray(self):
        return self.dataset

    def summary_text(self) -> str:
        """One line: counts of cases computed, reused and failed, and the wall time."""
        text = (
            f"{self.n_cases} cases: {self.n_computed} computed, {self.n_reused} reused from an "
            f"earlier run, {self.n_failed} failed; {self.wall_time:.1f} s"
        )
        found = [r for r in self.records if r.ok and r.status != "success"]
        if found:
            text += f"; {len(found)} with a finding ({', '.join(sorted({r.status for r in found}))})"
        return text


def _data_hash(data: Any) -> str:
    return case_id(0, data).split("-", 1)[1]


def _read_done(case: Case, case_dir: Path) -> CaseRecord | None:
    """The record of a case finished by an earlier run, or None if it must be (re)computed."""
    marker = case_dir / "case.json"
    if not marker.exists():
        return None
    try:
        info = json.loads(marker.read_text())
    except (OSError, ValueError):
        return None
    if info.get("state") != "done" or not (case_dir / "result.nc").exists():
        return None
    if info.get("data_hash") != _data_hash(case.data):
        log.warning("case %s: stored config differs from this sweep's; recomputing", case.id)
        return None
    try:
        summary = json.loads((case_dir / "summary.json").read_text())
    except (OSError, ValueError):
        return None
    return CaseRecord(
        case.id,
        dict(case.params),
        info.get("status", "unknown"),
        info.get("error", ""),
        summary,
        info.get("wall_time", float("nan")),
        info.get("attempts", 1),
        False,
        info.get("worker", ""),
    )


def _jsonable(data: Any) -> Any:
    try:
        json.dumps(data)
        return data
    except (TypeError, ValueError):
        return repr(data)


def _store(case: Case, outcome: Outcome, attempts: int, out_dir: Path | None, case_figures: bool) -> CaseRecord:
    """Record a finished case; write its marker (and its files, unless its worker wrote them)
    when ``out_dir`` is given.

    Raises
    ------
    WriteFailed
        The case's files could not be written (full disk, I/O error), here or by its worker.
    """
    if outcome.write_failed is not None:
        raise outcome.write_failed
    rec = CaseRecord(
        case.id,
        dict(case.params),
        attempts=attempts,
        computed=True,
        wall_time=outcome.wall_time,
        worker=outcome.worker,
    )
    result = outcome.result
    is_result = outcome.written or (hasattr(result, "save") and hasattr(result, "summary"))
    if not outcome.error and not is_result:
        outcome.error = f"TypeError: the case function returned {type(result).__name__}, not a Result"
    if not outcome.error:
        try:
            rec.summary = result.summary()
            rec.status = str(result.status)
        except Exception as exc:  # noqa: BLE001 - a broken summary is this case's error
            _fail(outcome, exc)
    if out_dir is None:
        if outcome.error:
            rec.status, rec.error = "error", outcome.error
        return rec
    case_dir = out_dir / "cases" / case.id
    case_dir.parent.mkdir(parents=True, exist_ok=True)
    if not outcome.error and not outcome.written:
        try:
            result.save(case_dir, figures=case_figures)
        except WriteFailed:
            raise
        except Exception as exc:  # noqa: BLE001 - e.g. a figure that raised: this case's error
            _fail(outcome, exc)
    if outcome.error:
        rec.status, rec.error = "error", outcome.error
    case_dir.mkdir(parents=True, exist_ok=True)
    info = {
        "id": case.id,
        "params": case.params,
        "status": rec.status,
        "error": rec.error,
        "attempts": attempts,
        "wall_time": rec.wall_time,
        "worker": rec.worker,
        "data_hash": _data_hash(case.data),
        "config": _jsonable(case.data),
    }
    if rec.status == "error":
        write_text_atomic(case_dir / "error.txt", f"{rec.error}\n\n{outcome.traceback}")
        write_json_atomic(case_dir / "case.json", {**info, "state": "error"})
        log.warning("case %s failed: %s", case.id, rec.error)
        return rec
    # the result directory was swapped in as a whole (no error.txt of an earlier run in it)
    write_json_atomic(case_dir / "case.json", {**info, "state": "done"})
    if not rec.ok:
        log.warning("case %s finished with status %r: %s", case.id, rec.status, result.message)
    return rec


def _fail(outcome: Outcome, exc: Exception) -> None:
    """Make the exception being handled the case's error."""
    import traceback

    outcome.error, outcome.traceback = f"{type(exc).__name__}: {exc}", traceback.format_exc()


def _prepare_outputs(figures: bool, domain: str | None) -> None:
    """Import what combining and the sweep figures need, and draw one small figure.

    Run in a thread of the client while the workers compute: the client has nothing else to
    do then, and after the workers wrote the case files it has not imported xarray, h5netcdf
    or matplotlib yet (1-2 s on the gear sweep, otherwise spent after the last case). Drawing
    one figure loads the fonts and the Agg renderer. Nothing here is needed for correctness;
    a failure only leaves the work to the outputs.
    """
    try:
        import io

        import h5netcdf  # noqa: F401 - imported for its import time only

        import rotaflex.sweep.combine  # noqa: F401
        from rotaflex.core.result import import_xarray

        import_xarray()
        if not figures:
            return
        from rotaflex.core.domains import CASES
        from rotaflex.core.plotting import new_figure, pyplot
        from rotaflex.sweep import figures as _figures  # noqa: F401

        if domain in CASES:
            importlib.import_module(CASES[domain])
        fig, ax = new_figure()
        ax.plot([0.0, 1.0], [0.0, 1.0], label="x")
        ax.set_xlabel("x [m]")
        ax.legend()
        fig.savefig(io.BytesIO(), format="png", dpi=30)
        pyplot().close(fig)
    except Exception:  # noqa: BLE001 - a warm-up only
        log.debug("preparing the outputs failed", exc_info=True)


def _crash_error(exc: BaseException, n: int) -> str:
    return (
        f"WorkerDied: the worker process died while running this case {n} time(s) (last: {type(exc).__name__}: {exc})"
    )


def run_sweep(
    case_fn: Callable[[Any], Any],
    cases: Iterable[Case | Mapping[str, Any]],
    executor: Any = None,
    *,
    out_dir: str | Path | None = None,
    progress: bool | Callable[[CaseRecord, int, int], None] = False,
    max_retries: int = 2,
    figures: bool = True,
    case_figures: bool = False,
    domain: str | None = None,
    attrs: Mapping[str, Any] | None = None,
    units: Mapping[str, str] | None = None,
    chains: list[list[str]] | None = None,
) -> SweepResult:
    """Run ``case_fn`` on every case, write each case as it finishes, then combine.

    Parameters
    ----------
    case_fn : callable
        Importable top-level function ``case_fn(data) -> Result`` (``functools.partial`` of one
        is fine); it runs on the workers, so it and ``data`` must pickle.
    cases : iterable of Case or dict
        The cases (see :func:`rotaflex.sweep.grid_cases`). A plain dict is its own data, and
        its scalar entries are the swept coordinates.
    executor : None, "serial", int, Executor or callable
        ``None``: a local process pool with one process per core; an int: that many
        processes; ``"serial"``: in this process; an ``Executor`` instance (e.g.
        ``distributed.Client(address).get_executor(pure=False)``) is used and not shut down;
        a zero-argument callable returns a fresh executor (rebuilt if a worker dies).
    out_dir : path, optional
        Sweep directory: ``cases/<id>/`` per case, ``sweep.nc``, ``summary.csv``,
        ``figures/``, ``sweep.json``. Cases already done there are reused (resume).
        Without it, nothing is written and nothing is reused.
    progress : bool or callable
        True: a tqdm bar over cases. A callable is called as ``progress(record, done, total)``
        after each case.
    max_retries : int
        How many times a case whose worker died is run again before it is recorded as failed.
    figures : bool
        Write the sweep figures to ``out_dir/figures/``.
    case_figures : bool
        Also write each case's own PNG figures (slow for big sweeps).
    domain : str, optional
        Domain name (selects the sweep figures) stored in ``sweep.nc``.
    attrs : dict, optional
        Extra global attributes of ``sweep.nc`` (e.g. the base config as JSON).
    units : dict, optional
        Units of the swept keys (default: from their names, e.g. ``speed_rpm``).
    chains : list of list of str, optional
        Continuation (:mod:`rotaflex.sweep.continuation`): case ids per chain in run order,
        every case in one chain; ``case_fn(data, initial_state=...)`` runs from its
        predecessor's ``final_state()``, the chains in parallel.

    Returns
    -------
    SweepResult

    Examples
    --------
    >>> from rotaflex.sweep import run_sweep, Case
    >>> from rotaflex.sweep._selftest_case import run_case           # doctest: +SKIP
    >>> res = run_sweep(run_case, [{"x": 1.0}, {"x": 2.0}], "serial")  # doctest: +SKIP
    >>> res.dataset["a"].values                                        # doctest: +SKIP
    array([1., 4.])
    """
    from rotaflex.sweep.combine import combine, write_outputs

    t0 = time.perf_counter()
    cases = as_cases(cases)
    out = Path(out_dir) if out_dir is not None else None
    records: dict[str, CaseRecord] = {}
    todo: deque[Case] = deque()
    if chains is None:
        for case in cases:
            done = _read_done(case, out / "cases" / case.id) if out is not None else None
            if done is not None:
                records[case.id] = done
            else:
                todo.append(case)
    else:
        chain_todo, chain_states = _pending_chains(cases, chains, out, records)
        todo.extend(c for ch in chain_todo for c in ch)
    total = len(cases)
    if out is not None:
        log.info(
            "sweep of %d cases in %s: %d done earlier, %d to run",
            total,
            out,
            total - len(todo),
            len(todo),
        )

    bar = None
    if progress is True:  # a bar on a terminal, one line per update in a log
        from rotaflex.core.progress import Progress

        bar = Progress(total, "sweep", "case")
        bar.update(total - len(todo))
    callback = progress if callable(progress) else None

    # where the wall time goes, logged at the end: [pool start, running cases, of which the
    # client writing case files, combining + figures] [s]
    spent = {"start": 0.0, "cases": 0.0, "writing": 0.0, "worker_writing": 0.0, "worker_cpu": 0.0, "outputs": 0.0}

    def finish(case: Case, outcome: Outcome, n_attempts: int) -> None:
        tw = time.perf_counter()
        rec = _store(case, outcome, n_attempts, out, case_figures)
        spent["writing"] += time.perf_counter() - tw
        spent["worker_writing"] += outcome.write_time
        if outcome.cpu_time == outcome.cpu_time:  # not NaN (a case whose worker died)
            spent["worker_cpu"] += outcome.cpu_time
        records[case.id] = rec
        if bar is not None:
            bar.update(len(records))
        if callback is not None:
            callback(rec, len(records), total)

    warm = None
    backend = None
    if todo:
        ts = time.perf_counter()
        streams = len(todo) if chains is None else sum(1 for ch in chain_todo if ch)
        backend = _Backend(executor, _modules_of(case_fn), (out, case_figures) if out is not None else None, streams)
        spent["start"] = time.perf_counter() - ts
        # only while this process has nothing else to do: not beside cases (and their figures,
        # matplotlib is not thread-safe) run here, nor beside this process writing case files
        in_process = isinstance(backend.executor, (SerialExecutor, ThreadPoolExecutor))
        if out is not None and (backend.workers_write or backend.writer is not None) and not in_process:
            warm = threading.Thread(target=_prepare_outputs, args=(figures, domain), daemon=True)
            warm.start()
        try:
            if chains is None:
                _drive(backend, case_fn, todo, finish, max_retries)
            else:
                from rotaflex.sweep.continuation import drive_chains

                drive_chains(backend, case_fn, chain_todo, chain_states, finish, max_retries)
        except BaseException:
            backend.shutdown(wait=False)
            raise
        finally:
            spent["cases"] = time.perf_counter() - ts - spent["start"]
            if bar is not None:
                bar.close()
    elif bar is not None:
        bar.close()

    ordered = [records.get(c.id) or CaseRecord(c.id, dict(c.params)) for c in cases]
    from rotaflex.core.provenance import provenance

    to = time.perf_counter()
    try:
        if warm is not None:
            warm.join()
        meta = {"domain": domain or "", **provenance(), **(attrs or {})}
        dataset = combine(ordered, attrs=meta, units=dict(units or {}))
        result = SweepResult(ordered, dataset, out, time.perf_counter() - t0)
        if out is not None:
            pools = backend.figure_pools() if backend is not None else []  # the workers draw too
            result.figures = write_outputs(result, domain=domain, figures=figures, pools=pools)
    except BaseException:
        if backend is not None:
            backend.shutdown(wait=False)
        raise
    if backend is not None:
        backend.shutdown(wait=True)
    result.wall_time = time.perf_counter() - t0
    spent["outputs"] = time.perf_counter() - to
    log.info(
        "wall time: %.2f s starting workers, %.2f s running cases (of which %.2f s writing case "
        "files here), %.2f s combining and figures; the workers spent %.2f s writing case files "
        "(%.2f s CPU on cases, writing included)",
        spent["start"],
        spent["cases"],
        spent["writing"],
        spent["outputs"],
        spent["worker_writing"],
        spent["worker_cpu"],
    )
    log.info("%s", result.summary_text())
    return result


def _pending_chains(cases: list[Case], chains, out: Path | None, records: dict[str, CaseRecord]):
    """The runs still to do: per stretch of unfinished cases of a chain, those cases and the
    state the first of them starts from (the saved final state of the case before it; None at
    the start of a chain).

    A chain is resumed wherever it was left, not only after its longest finished prefix: a
    client killed while one case's files were written leaves later cases finished (they were
    written by the writer pool meanwhile), and those are reused; the unfinished case is run
    again from its predecessor's saved state, so each later case still follows from the state
    it was computed from. A finished case whose state cannot be read is run again too.
    """
    from rotaflex.sweep.continuation import saved_state

    by_id = {c.id: c for c in cases}
    if sorted(i for ch in chains for i in ch) != sorted(by_id):
        raise ValueError("chains must list every case id exactly once")
    pending: list[deque[Case]] = []
    states: list[Any] = []
    for chain in chains:
        done = [_read_done(by_id[cid], out / "cases" / cid) if out is not None else None for cid in chain]
        start: dict[int, Any] = {}  # finished case -> its saved state, where a stretch follows it
        k = 1
        while k < len(chain):
            if done[k] is None and done[k - 1] is not None and k - 1 not in start:
                start[k - 1] = saved_state(out / "cases" / chain[k - 1])
                if start[k - 1] is None:  # no state to go on from: that case again too
                    done[k - 1] = None
                    del start[k - 1]
                    k = max(k - 1, 1)  # the case before it now needs a state in turn
                    continue
            k += 1
        k = 0
        while k < len(chain):
            if done[k] is not None:
                k += 1
                continue
            end = k
            while end < len(chain) and done[end] is None:
                end += 1
            pending.append(deque(by_id[cid] for cid in chain[k:end]))
            states.append(start.get(k - 1))
            k = end
        for cid, rec in zip(chain, done, strict=True):
            if rec is not None:
                records[cid] = rec
    return pending, states


def _drive(
    backend: _Backend,
    case_fn,
    todo: deque[Case],
    finish: Callable[[Case, Outcome, int], None],
    max_retries: int,
) -> None:
    """Submit/collect loop: keep ``backend.window`` cases in flight; handle worker deaths."""
    attempts: dict[str, int] = {}
    deaths: dict[str, int] = {}
    suspects: deque[Case] = deque()  # in flight when a pool broke or a worker died: re-run one at a time
    inflight: dict[Future, Case] = {}

    def submit(case: Case, queue: deque[Case]) -> bool:
        try:
            fut = backend.submit(case_fn, case)
        except BrokenProcessPool:  # broke since the last wait; its futures will tell
            queue.appendleft(case)
            return False
        attempts[case.id] = attempts.get(case.id, 0) + 1
        inflight[fut] = case
        return True

    def died(case: Case, exc: BaseException, queue: deque[Case]) -> None:
        deaths[case.id] = deaths.get(case.id, 0) + 1
        if deaths[case.id] > max_retries:
            err = _crash_error(exc, deaths[case.id])
            finish(case, Outcome(None, err, "", float("nan"), ""), attempts[case.id])
        else:
            log.warning("case %s: worker died (%s); retrying", case.id, type(exc).__name__)
            queue.appendleft(case)

    while todo or suspects or inflight:
        ok = True
        if suspects:
            if not inflight:
                ok = submit(suspects.popleft(), suspects)
        else:
            while ok and todo and len(inflight) < backend.window:
                ok = submit(todo.popleft(), todo)
        if not inflight:
            if not ok:
                backend.rebuild()
            continue
        isolated = len(inflight) == 1
        done, _ = wait(list(inflight), return_when=FIRST_COMPLETED)
        broken = False
        for fut in done:
            case = inflight.pop(fut)
            try:
                outcome = fut.result()
            except BrokenProcessPool as exc:
                broken = True
                if isolated:
                    died(case, exc, suspects)
                else:
                    suspects.append(case)
            except (CancelledError, Exception) as exc:  # KilledWorker, lost connection, ...
                if isolated:
                    died(case, exc, suspects)
                else:
                    # a cluster queues several cases on one worker, and a worker's death fails
                    # them all: which case killed it is known only when each runs alone
                    log.warning("case %s: lost with its worker (%s); re-running it alone", case.id, type(exc).__name__)
                    suspects.append(case)
            else:
                finish(case, outcome, attempts[case.id])
        if broken:
            # every other in-flight future of the broken pool fails too; collect them
            rest, _ = wait(list(inflight))
            for fut in rest:
                case = inflight.pop(fut)
                exc = fut.exception()
                if exc is None:
                    finish(case, fut.result(), attempts[case.id])
                else:
                    suspects.append(case)
            backend.rebuild()
