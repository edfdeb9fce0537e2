"""Re-run the seed papers' numerical examples and write the shared report.

One module per paper (``rotor``, ``floating``, ``gear``) plus ``geared_rotor`` (FE rotors coupled
through a gear mesh) and ``sweep``, each with
``run(out_dir, *, fast, progress) -> Section``; :func:`reproduce` runs the requested ones, each
into its own sub-directory, and writes ``report.md``, ``index.html``, ``checks.json`` and
``provenance.json``. A module reports its progress with :func:`rotaflex.core.report.step`.
"""

from __future__ import annotations

import importlib
import logging
import os
import time
from collections.abc import Callable
from pathlib import Path

from rotaflex.core.domains import REPRODUCE
from rotaflex.core.progress import Progress
from rotaflex.core.report import CompileTimer, ExpectedWarnings, reporting, undefined_terms, write_report
from rotaflex.core.threads import limit_blas_threads
from rotaflex.reproduce.guide import GLOSSARY, introduction

log = logging.getLogger("rotaflex.reproduce")

#: ``--fast`` wall time of each target [s], kernels and equations already cached, measured on
#: the idle 2-core development machine (2026-11-26, 118 checks, 117.2 s in all)
MEASURED_FAST_S: dict[str, float] = {"rotor": 11.2, "gear": 65.5, "floating": 16.3, "geared_rotor": 3.6, "sweep": 20.1}
#: ``--fast`` wall time of each target before its fast settings were cut down [s] (idle machine,
#: 2026-11-26); the full settings did not change, so the full-time estimate scales these
FAST_BEFORE_CUTS_S: dict[str, float] = {
    "rotor": 16.7,
    "gear": 95.0,
    "floating": 22.5,
    "geared_rotor": 5.4,
    "sweep": 32.7,
}
#: full settings over ``--fast``, from the two totals last measured together on that machine
#: (214 s / 75.2 s); applied to :data:`FAST_BEFORE_CUTS_S`
FULL_OVER_FAST = 214.0 / 75.2
#: extra time of the first run after install [s]: sympy deriving the rotor equations, numba
#: compiling the gear and floating kernels (all cached afterwards); measured in a fresh install
#: on the same machine under a heavier load (load average about 15 on 2 cores)
FIRST_RUN_S: dict[str, float] = {"rotor": 62.0, "gear": 540.0, "floating": 302.0}


def expected_seconds(name: str, fast: bool) -> float:
    """Expected wall time of one reproduce target [s] (kernels cached)."""
    if fast:
        return MEASURED_FAST_S.get(name, 30.0)
    return FAST_BEFORE_CUTS_S.get(name, 30.0) * FULL_OVER_FAST


def cpu_seconds() -> float:
    """CPU time of this process and its finished children so far [s] (user + system)."""
    t = os.times()
    return t.user + t.system + t.children_user + t.children_system


def _minutes(seconds: float) -> str:
    return f"about {seconds / 60:.0f} min" if seconds >= 90 else f"about {seconds:.0f} s"


def estimate(names: list[str], fast: bool, load: float | None = None, cores: int | None = None) -> str:
    """The line ``reproduce`` prints at its start: the expected wall time, from measured numbers.

    ``load`` and ``cores`` (default: this machine's 1-minute load average and CPU count) add a
    warning when the machine is busy, since the times grow with the load.
    """
    seconds = sum(expected_seconds(n, fast) for n in names)
    # the sweep target runs every domain's example, so it compiles their kernels too
    compiled = set(names) | (set(FIRST_RUN_S) if "sweep" in names else set())
    first = sum(FIRST_RUN_S.get(n, 0.0) for n in compiled)
    line = f"expected time: {_minutes(seconds)} on 2 cores{' with --fast' if fast else ''} once kernels are cached"
    if first:
        line += f"; the first run after install also compiles them ({_minutes(first)} measured on a busy machine)"
    if load is None:
        try:
            load = os.getloadavg()[0]
        except (AttributeError, OSError):  # pragma: no cover - not on every platform
            load = 0.0
    cores = cores or os.cpu_count() or 1
    if load > 2 * cores:
        line += f"; this machine is busy now (load average {load:.0f} on {cores} cores): expect longer"
    return line


def _run_sections(names, out_dir, fast, bars, emit, weights, overall) -> list:
    """Run each target into ``out_dir``; the per-section part of :func:`reproduce`."""
    sections = []
    n = len(names)
    for i, name in enumerate(names, 1):
        prefix = f"[{i}/{n} {name}]"
        say = (lambda m, p=prefix: emit(f"{p} {m}")) if emit else None
        if say:
            say("starting")
        module = importlib.import_module(REPRODUCE[name])
        t0, c0 = time.perf_counter(), cpu_seconds()
        with reporting(say), CompileTimer(say) as compiling, ExpectedWarnings(say):
            section = module.run(out_dir, fast=fast, progress=bars)
        total = time.perf_counter() - t0
        # CPU time tells a section's cost on a shared machine, where the wall time grows with the load
        cpu = cpu_seconds() - c0
        # compile time is reported apart: it is paid once per machine, not by the solvers
        section.compile_time = compiling.seconds
        section.wall_time = total - compiling.seconds
        sections.append(section)
        if say:
            checks = section.all_checks()
            extra = f" + {compiling.seconds:.1f} s compiling kernels" if compiling.seconds >= 0.05 else ""
            say(
                f"done in {section.wall_time:.1f} s{extra} (CPU {cpu:.1f} s); "
                f"{sum(c.passed for c in checks)}/{len(checks)} checks pass"
            )
            with reporting(emit):
                overall.update(sum(weights[:i]))
    return sections


def reproduce(
    names: list[str],
    out_dir: str | Path,
    *,
    fast: bool = False,
    progress: bool | Callable[[str], None] = False,
    bars: bool | None = None,
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
        when stderr is not a terminal, so a log gets one line per stage, not bar redraws.

    Returns
    -------
    dict
        ``checks`` and ``passed`` counts, and ``compile_time`` [s] spent compiling kernels.
    """
    out_dir = Path(out_dir)
    emit: Callable[[str], None] | None = progress if callable(progress) else (log.info if progress else None)
    bars = bool(progress) if bars is None else bars
    n = len(names)
    if emit:
        emit(estimate(names, fast))
    # overall progress in expected seconds (a line after each stage, with the time left)
    weights = [expected_seconds(nm, fast) for nm in names]
    overall = Progress(sum(weights), "reproduce", "expected s", enabled=bool(emit) and n > 1, tty=False)
    with limit_blas_threads():
        sections = _run_sections(names, out_dir, fast, bars, emit, weights, overall)
    compile_total = sum(s.compile_time for s in sections)
    title = "rotaflex reproduction report" + (" (fast mode)" if fast else "")
    write_report(out_dir, sections, title, intro=introduction(names), glossary=GLOSSARY)
    missing = undefined_terms((out_dir / "report.md").read_text(encoding="utf-8"), GLOSSARY)
    if missing:  # a maintainer's reminder: tests/reproduce/test_report_glossary.py checks the texts
        log.warning("report terms without a glossary entry: %s", ", ".join(sorted(missing)))
    checks = [c for s in sections for c in s.all_checks()]
    return {"checks": len(checks), "passed": sum(c.passed for c in checks), "compile_time": compile_total}
