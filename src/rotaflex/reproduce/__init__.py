"""Re-run the seed papers' numerical examples and write the shared report.

One module per seed (``rotor``, ``floating``, ``gear``), each with
``run(out_dir, *, fast, progress) -> Section``; :func:`reproduce` runs the requested ones, each
into its own sub-directory, and writes ``report.md``, ``index.html`` and ``checks.json``.
"""

from __future__ import annotations

import importlib
import time
from pathlib import Path

from rotaflex.core.domains import REPRODUCE
from rotaflex.core.report import write_report


def reproduce(names: list[str], out_dir: str | Path, *, fast: bool = False, progress: bool = False) -> dict:
    """Run the reproduce modules ``names`` into ``out_dir``; returns check counts.

    A domain's figures and data go to ``out_dir/<name>/`` so that a failing domain leaves the
    other domains' earlier output intact.
    """
    out_dir = Path(out_dir)
    sections = []
    for name in names:
        module = importlib.import_module(REPRODUCE[name])
        t0 = time.perf_counter()
        section = module.run(out_dir, fast=fast, progress=progress)
        section.wall_time = time.perf_counter() - t0
        sections.append(section)
    title = "rotaflex reproduction report" + (" (fast mode)" if fast else "")
    write_report(out_dir, sections, title)
    checks = [c for s in sections for c in s.all_checks()]
    return {"checks": len(checks), "passed": sum(c.passed for c in checks)}
