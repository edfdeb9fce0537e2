"""Re-run the seed papers' numerical examples and write the shared report.

One module per paper (``rotor``, ``floating``, ``gear``) plus ``geared_rotor`` (FE rotors coupled
through a gear mesh) and ``sweep``, each with
``run(out_dir, *, fast, progress) -> Section``; :func:`reproduce` runs the requested ones, each
into its own sub-directory, and writes ``report.md``, ``index.html``, ``checks.json`` and
``provenance.json``. A module reports its progress with :func:`rotaflex.core.report.step`.

On a machine with several cores the sections run at once in worker processes (one per core,
longest expected first); the report is assembled here in the requested order either way.
"""

from __future__ import annotations

import importlib
import logging
import os
import signal
import time
from collections.abc import Callable
from pathlib import Path

from rotaflex.core.domains import REPRODUCE
from rotaflex.core.errors import InputError
from rotaflex.core.progress import Progress
from rotaflex.core.report import CompileTimer, ExpectedWarnings, reporting, undefined_terms, write_report
from rotaflex.core.threads import limit_blas_threads
from rotaflex.reproduce.guide import GLOSSARY, introduction

log = logging.getLogger("rotaflex.reproduce")

#: ``--fast`` wall time of each target [s], kernels and equations already cached, measured on
#: the idle 2-core development machine with two sections at a time (2026-11-26, 118 checks,
#: 67.2 s in all; the sweep section's own pool then has one process)
MEASURED_FAST_S: dict[str, float] = {"rotor": 8.4, "gear": 65.7, "floating": 15.8, "geared_rotor": 3.5, "sweep": 20.5}
#: full-settings wall time of each target [s], kernels and equations cached: ``reproduce all``
#: of a wheel install on the idle 2-core machine, two sections at a time (2026-11-28, 121
#: checks, 190.5 s in all). The sweep section's work runs in its own worker pool, so its wall
#: time (109 s) is far above the CPU time its process reports (30 s)
MEASURED_FULL_S: dict[str, float] = {
    "rotor": 15.4,
    "gear": 138.5,
    "floating": 79.0,
    "geared_rotor": 5.1,
    "sweep": 109.2,
}
#: extra time of the first run after install [s]: sympy deriving the rotor equations, numba
#: compiling the kernels (all cached afterwards): the compile time each section reported in the
#: first run after that install (same day and machine as :data:`MEASURED_FULL_S`: 266.6 s in
#: all); rotor: its first run minus its second (empty equation cache)
FIRST_RUN_S: dict[str, float] = {"rotor": 8.9, "gear": 89.0, "floating": 64.1, "sweep": 8.5}


def expected_seconds(name: str, fast: bool) -> float:
    """Expected wall time of one reproduce target [s] (kernels cached)."""
    return (MEASURED_FAST_S if fast else MEASURED_FULL_S).get(name, 30.0)


def cpu_seconds() -> float:
    """CPU time of this process and its finished children so far [s] (user + system)."""
    t = os.times()
    return t.user + t.system + t.children_user + t.children_system


def _minutes(seconds: float) -> str:
    return f"about {seconds / 60:.0f} min" if seconds >= 90 else f"about {seconds:.0f} s"


def schedule(names: list[str], fast: bool, workers: int) -> list[list[str]]:
    """The sections each of ``workers`` processes runs, longest expected first.

    Longest-processing-time list scheduling, as the pool does it: the sections are queued by
    decreasing expected time (ties in the requested order) and each worker takes the next one
    when it is free.
    """
    queue = sorted(names, key=lambda n: -expected_seconds(n, fast))
    lanes: list[list[str]] = [[] for _ in range(max(1, min(workers, len(names))))]
    busy = [0.0] * len(lanes)
    for name in queue:
        k = busy.index(min(busy))
        lanes[k].append(name)
        busy[k] += expected_seconds(name, fast)
    return lanes


def estimate(
    names: list[str], fast: bool, load: float | None = None, cores: int | None = None, workers: int = 1
) -> str:
    """The line ``reproduce`` prints at its start: the expected wall time, from measured numbers.

    ``workers`` processes run the sections at once (the longest of :func:`schedule`'s lanes);
    ``load`` and ``cores`` (default: this machine's 1-minute load average and CPU count) add a
    warning when the machine is busy, since the times grow with the load.
    """
    seconds = max(sum(expected_seconds(n, fast) for n in lane) for lane in schedule(names, fast, workers))
    # the sweep target runs every domain's example, so it compiles their kernels too
    compiled = set(names) | (set(FIRST_RUN_S) if "sweep" in names else set())
    first = sum(FIRST_RUN_S.get(n, 0.0) for n in compiled)
    line = f"expected time: {_minutes(seconds)} on 2 cores{' with --fast' if fast else ''} once kernels are cached"
    if workers > 1 and len(names) > 1:
        line += f" ({min(workers, len(names))} sections at a time)"
    if first:
        line += f"; the first run after install also compiles them ({_minutes(first)} more at most)"
    if load is None:
        try:
            load = os.getloadavg()[0]
        except (AttributeError, OSError):  # pragma: no cover - not on every platform
            load = 0.0
    cores = cores or os.cpu_count() or 1
    if load > 2 * cores:
        line += f"; this machine is busy now (load average {load:.0f} on {cores} cores): expect longer"
    return line


#: True in a worker process of a parallel run (set by :func:`_section_in_worker`)
_IN_WORKER = False


def section_processes() -> int:
    """Processes a section may keep busy at once (the sweep section's pool).

    Every core when the sections run one after the other in this process; one inside a worker
    of a parallel run, whose other workers already keep the other cores busy.
    """
    return 1 if _IN_WORKER else (os.cpu_count() or 1)


def _run_section(module_name: str, out_dir: Path, fast: bool, bars: bool, say) -> tuple:
    """Run one reproduce module; returns its Section (times filled in) and its CPU time [s]."""
    if say:
        say("starting")
    module = importlib.import_module(module_name)
    t0, c0 = time.perf_counter(), cpu_seconds()
    with reporting(say), CompileTimer(say) as compiling, ExpectedWarnings(say):
        section = module.run(out_dir, fast=fast, progress=bars)
    total = time.perf_counter() - t0
    # CPU time tells a section's cost on a shared machine, where the wall time grows with the load
    cpu = cpu_seconds() - c0
    # compile time is reported apart: it is paid once per machine, not by the solvers
    # parts timed themselves (solver and compile time apart): the section's own is what is left
    parts = section.flat()[1:]
    section.compile_time = compiling.seconds - sum(p.compile_time for p in parts)
    section.wall_time = total - compiling.seconds - sum(p.wall_time for p in parts)
    return section, cpu


def _done_line(section, cpu: float) -> str:
    checks = [c for s in section.flat() for c in s.all_checks()]
    extra = f" + {section.compile_time:.1f} s compiling kernels" if section.compile_time >= 0.05 else ""
    return (
        f"done in {section.wall_time:.1f} s{extra} (CPU {cpu:.1f} s); "
        f"{sum(c.passed for c in checks)}/{len(checks)} checks pass"
    )


def _prefix(i: int, names: list[str]) -> str:
    return f"[{i + 1}/{len(names)} {names[i]}]"


def _run_sections(names, out_dir, fast, bars, emit, weights, overall) -> list:
    """Run each target into ``out_dir`` here, one after the other; the serial part of :func:`reproduce`."""
    sections = []
    for i, name in enumerate(names):
        prefix = _prefix(i, names)
        say = (lambda m, p=prefix: emit(f"{p} {m}")) if emit else None
        section, cpu = _run_section(REPRODUCE[name], out_dir, fast, bars, say)
        sections.append(section)
        if say:
            say(_done_line(section, cpu))
            with reporting(emit):
                overall.update(sum(weights[: i + 1]))
    return sections


def _worker_setup() -> dict:
    """This process's settings that a worker process must share: figure format and resolution
    (the CLI's ``--format``/``--dpi``), the memory limit and how warnings are logged."""
    from rotaflex.core import plotting
    from rotaflex.core.limits import max_memory

    root = logging.getLogger()
    fmt = next((h.formatter._fmt for h in root.handlers if h.formatter is not None), None)
    return {
        "figures": dict(plotting._CHOSEN),
        "max_memory": max_memory(),
        "log": (root.level, fmt if root.handlers else None),
    }


def _section_in_worker(module_name: str, prefix: str, out_dir: Path, fast: bool, lines, setup: dict) -> tuple:
    """Worker side of a parallel run: one section; its progress lines go to the queue ``lines``."""
    global _IN_WORKER
    from rotaflex.core import plotting
    from rotaflex.core.limits import set_max_memory

    _IN_WORKER = True
    plotting.configure(**setup["figures"])
    set_max_memory(setup["max_memory"])
    level, fmt = setup["log"]
    logging.getLogger().setLevel(level)
    if fmt is not None and not logging.getLogger().handlers:
        # the same stderr as the parent's, so that ExpectedWarnings can filter as in a serial run
        logging.basicConfig(level=level, format=fmt)
    say = (lambda m: lines.put(f"{prefix} {m}")) if lines is not None else None
    try:
        with limit_blas_threads():
            # no bars: two processes redrawing bars on one terminal garble both; one line per stage
            return _run_section(module_name, out_dir, fast, False, say)
    except Exception as exc:  # noqa: BLE001 - raised again in the parent, see _Raised
        return _Raised(exc)


class _Raised:
    """An exception raised by a section in a worker, on its way back to the parent.

    Our errors take several arguments and keep one message (``InputError(field, value,
    allowed)``), so they do not unpickle, and an exception that fails to unpickle breaks the
    pool instead of reaching the caller. This carries the class, the arguments and the
    attributes, and :meth:`rebuild` makes the same exception (same type, same message) with
    the worker's traceback as its cause (seen with ``--debug``).
    """

    def __init__(self, exc: Exception):
        import pickle
        import traceback

        self.cls, self.args, self.attrs = type(exc), exc.args, dict(vars(exc))
        self.trace = traceback.format_exc()
        try:
            pickle.loads(pickle.dumps((self.cls, self.args, self.attrs)))
        except Exception:  # noqa: BLE001 - e.g. a class defined in a function: its text only
            self.cls, self.args, self.attrs = RuntimeError, (f"{type(exc).__name__}: {exc}",), {}

    def rebuild(self) -> Exception:
        exc = self.cls.__new__(self.cls)
        exc.args = self.args
        exc.__dict__.update(self.attrs)
        exc.__cause__ = _WorkerTraceback(self.trace)
        return exc


class _WorkerTraceback(Exception):
    def __str__(self) -> str:
        return "\n" + self.args[0]


def _drain(lines, emit) -> None:
    import queue

    while lines is not None:
        try:
            emit(lines.get_nowait())
        except queue.Empty:
            return


def _run_parallel(names, out_dir, fast, emit, weights, overall, workers: int) -> list:
    """Run the targets in ``workers`` processes, longest expected first; the sections come back
    in the requested order. A section that raises stops the run with its exception, as in the
    serial run: the sections before it are finished, the ones after it stopped."""
    import multiprocessing
    from concurrent.futures import FIRST_COMPLETED, wait
    from multiprocessing.managers import SyncManager

    # the sweep runner's pool: forkserver, one BLAS thread per worker, workers that ignore
    # Ctrl-C (this process handles it) and end when this process dies; terminated on error
    from rotaflex.sweep.backends import _Backend

    order = sorted(range(len(names)), key=lambda i: -weights[i])
    backend = _Backend(workers, preload=(__name__, *dict.fromkeys(REPRODUCE[n] for n in names)))
    manager = None
    lines = None
    setup = _worker_setup()
    ok = False
    try:
        if emit:
            # a managed queue, because a pool's tasks cannot take a plain multiprocessing queue;
            # the manager ignores Ctrl-C so that the interrupt reaches this process's handler only
            method = "forkserver" if "forkserver" in multiprocessing.get_all_start_methods() else "spawn"
            started = SyncManager(ctx=multiprocessing.get_context(method))
            started.start(signal.signal, (signal.SIGINT, signal.SIG_IGN))
            manager, lines = started, started.Queue()
        futures = {
            backend.executor.submit(
                _section_in_worker, REPRODUCE[names[i]], _prefix(i, names), out_dir, fast, lines, setup
            ): i
            for i in order
        }
        sections: dict[int, object] = {}
        failed: dict[int, BaseException] = {}
        pending = set(futures)
        while pending:
            done, pending = wait(pending, timeout=0.2, return_when=FIRST_COMPLETED)
            if emit:
                _drain(lines, emit)  # before the done lines: a section's lines were queued before it returned
            for fut in sorted(done, key=futures.get):
                i = futures[fut]
                if fut.exception() is not None:
                    failed[i] = fut.exception()
                    continue
                result = fut.result()
                if isinstance(result, _Raised):
                    failed[i] = result.rebuild()
                    continue
                sections[i], cpu = result
                if emit:
                    emit(f"{_prefix(i, names)} {_done_line(sections[i], cpu)}")
                    with reporting(emit):
                        overall.update(sum(weights[j] for j in sections))
            if failed:  # a serial run would not have started the sections after the first failure
                pending = {f for f in pending if futures[f] < min(failed)}
        if failed:
            raise failed[min(failed)]
        ok = True
    finally:
        backend.shutdown(wait=ok)
        if manager is not None:
            manager.shutdown()
    return [sections[i] for i in range(len(names))]


def check_needs(names: list[str]) -> None:
    """Refuse to start when a shipped file a section reads is missing (before anything runs).

    Each section module lists the example files it reads in ``NEEDS`` (paths relative to the
    shipped examples); a missing one is an incomplete installation, named in full, not bad input.
    """
    from rotaflex.core.examples import IncompleteInstall, examples_dir

    missing = []
    for name in names:
        module = importlib.import_module(REPRODUCE[name])
        missing += [
            examples_dir() / rel for rel in getattr(module, "NEEDS", ()) if not (examples_dir() / rel).is_file()
        ]
    if missing:
        raise IncompleteInstall(
            "rotaflex is installed without its example files; missing: "
            + ", ".join(str(p) for p in missing)
            + " (reinstall with `pip install .` from a complete source tree)"
        )


def workers_for(jobs: int | None, n_sections: int) -> int:
    """Worker processes of a run of ``n_sections`` sections: ``jobs`` (None: one per core),
    at most one per section; 0 or 1 means serial in this process (returned as 1)."""
    if jobs is not None and (isinstance(jobs, bool) or not isinstance(jobs, int) or jobs < 0):
        raise InputError("jobs", jobs, "an integer >= 0 (0 = serial in this process)")
    if jobs is None:
        jobs = os.cpu_count() or 1
    return max(1, min(jobs, n_sections))


def reproduce(
    names: list[str],
    out_dir: str | Path,
    *,
    fast: bool = False,
    progress: bool | Callable[[str], None] = False,
    bars: bool | None = None,
    jobs: int | None = None,
) -> dict:
    """Run the reproduce modules ``names`` into ``out_dir``; returns check counts.

    A domain's figures and data go to ``out_dir/<name>/`` so that a failing domain leaves the
    other domains' earlier output intact.

    Parameters
    ----------
    progress : bool or callable
        A callable receives one line per stage (domain start/end, each case or figure the
        module reports, kernel compilation); True logs those lines at INFO level.
    bars : bool, optional
        Let the modules draw tqdm bars (default: ``bool(progress)``); the CLI turns them off
        when stderr is not a terminal, so a log gets one line per stage, not bar redraws. A
        parallel run draws none (one line per stage).
    jobs : int, optional
        Worker processes that run sections at once, longest expected first (default: one per
        core, at most one per section); 0 or 1: one after the other in this process. The
        report, its checks and their order are the same either way.

    Returns
    -------
    dict
        ``checks`` and ``passed`` counts, and ``compile_time`` [s] spent compiling kernels.
    """
    out_dir = Path(out_dir)
    check_needs(names)
    workers = workers_for(jobs, len(names))
    emit: Callable[[str], None] | None = progress if callable(progress) else (log.info if progress else None)
    bars = bool(progress) if bars is None else bars
    n = len(names)
    if emit:
        emit(estimate(names, fast, workers=workers))
    # overall progress in expected seconds (a line after each stage, with the time left)
    weights = [expected_seconds(nm, fast) for nm in names]
    overall = Progress(sum(weights), "reproduce", "expected s", enabled=bool(emit) and n > 1, tty=False)
    with limit_blas_threads():
        if workers > 1:
            sections = _run_parallel(names, out_dir, fast, emit, weights, overall, workers)
        else:
            sections = _run_sections(names, out_dir, fast, bars, emit, weights, overall)
    sections = [q for s in sections for q in s.flat()]  # parts under their own headings
    compile_total = sum(s.compile_time for s in sections)
    title = "rotaflex reproduction report" + (" (fast mode)" if fast else "")
    write_report(out_dir, sections, title, intro=introduction(names), glossary=GLOSSARY)
    missing = undefined_terms((out_dir / "report.md").read_text(encoding="utf-8"), GLOSSARY)
    if missing:  # a maintainer's reminder: tests/reproduce/test_report_glossary.py checks the texts
        log.warning("report terms without a glossary entry: %s", ", ".join(sorted(missing)))
    checks = [c for s in sections for c in s.all_checks()]
    return {"checks": len(checks), "passed": sum(c.passed for c in checks), "compile_time": compile_total}
