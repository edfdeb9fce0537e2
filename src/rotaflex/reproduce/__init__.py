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
import time
from collections.abc import Callable
from pathlib import Path

from rotaflex.core.domains import REPRODUCE
from rotaflex.core.report import CompileTimer, ExpectedWarnings, reporting, write_report

log = logging.getLogger("rotaflex.reproduce")


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
    sections = []
    n = len(names)
    compile_total = 0.0
    for i, name in enumerate(names, 1):
        prefix = f"[{i}/{n} {name}]"
        say = (lambda m, p=prefix: emit(f"{p} {m}")) if emit else None
        if say:
            say("starting")
        module = importlib.import_module(REPRODUCE[name])
        t0 = time.perf_counter()
        with reporting(say), CompileTimer(say) as compiling, ExpectedWarnings(say):
            section = module.run(out_dir, fast=fast, progress=bars)
        total = time.perf_counter() - t0
        # compile time is reported apart: it is paid once per machine, not by the solvers
        section.compile_time = compiling.seconds
        section.wall_time = total - compiling.seconds
        compile_total += compiling.seconds
        sections.append(section)
        if say:
            checks = section.all_checks()
            extra = f" + {compiling.seconds:.1f} s compiling kernels" if compiling.seconds >= 0.05 else ""
            say(f"done in {section.wall_time:.1f} s{extra}; {sum(c.passed for c in checks)}/{len(checks)} checks pass")
    title = "rotaflex reproduction report" + (" (fast mode)" if fast else "")
    write_report(out_dir, sections, title)
    checks = [c for s in sections for c in s.all_checks()]
    return {"checks": len(checks), "passed": sum(c.passed for c in checks), "compile_time": compile_total}
