"""Every benchmark script runs at its tiny size, so that none rots unnoticed.

Timings live in ``benchmarks/`` (scripts that print figures) and are never asserted here. Each
script takes ``--tiny``: the same code path at the smallest size that still exercises it
(benchmarks/README.md). This test runs ``python benchmarks/X.py --tiny`` for every
``benchmarks/bench_*.py`` found by glob (a new benchmark without ``--tiny`` fails it) and for
the other runnable scripts listed in :data:`OTHER_SCRIPTS`, and asserts exit 0 and at least one
printed number.

Marked ``bench`` (deselected by default: about 100 s of CPU, most of it worker pools and
figures); ``.ci/run`` and the README's test command run it after the suite.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.bench

ROOT = Path(__file__).resolve().parents[1]
BENCHMARKS = ROOT / "benchmarks"
#: runnable scripts in benchmarks/ not named bench_*.py (helper modules start with an underscore)
OTHER_SCRIPTS = ("compare.py", "reference_floating.py")
SCRIPTS = sorted(p.name for p in BENCHMARKS.glob("bench_*.py")) + list(OTHER_SCRIPTS)
#: per script [s]: a tiny run takes seconds with a warm numba cache; a cold cache (fresh clone)
#: compiles a domain's kernels first: bench_gear.py --tiny took 455 s so on a 2-core machine at
#: load average 10 (above pytest's default 600 s per test, hence the mark below)
TIMEOUT = 840
#: a number as the scripts print them (12, 0.45, 3.0e-05, 1.2e+07)
NUMBER = re.compile(r"(?<![A-Za-z_])\d+(?:\.\d+)?(?:e[-+]?\d+)?")


def test_scripts_found():
    """The glob sees the benchmarks (a moved folder would otherwise make the test vacuous)."""
    assert {"bench_rotor_fe.py", "bench_gear.py", "bench_floating.py"} <= set(SCRIPTS)


@pytest.mark.timeout(TIMEOUT + 60)
@pytest.mark.parametrize("script", SCRIPTS)
def test_tiny_run(script, tmp_path):
    source = (BENCHMARKS / script).read_text()
    assert "--tiny" in source, f"benchmarks/{script} has no --tiny flag (see benchmarks/README.md)"
    env = {
        **os.environ,
        "PYTHONPATH": str(ROOT / "src"),
        # as the scripts' docstrings say to run them: one BLAS thread per process
        "OMP_NUM_THREADS": "1",
        "OPENBLAS_NUM_THREADS": "1",
        "MKL_NUM_THREADS": "1",
    }
    proc = subprocess.run(
        [sys.executable, str(BENCHMARKS / script), "--tiny"],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=TIMEOUT,
    )
    assert proc.returncode == 0, f"benchmarks/{script} --tiny failed:\n{proc.stderr[-3000:]}"
    assert NUMBER.search(proc.stdout), f"benchmarks/{script} --tiny printed no number:\n{proc.stdout[-2000:]}"
