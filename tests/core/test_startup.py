"""A verb imports only what it uses (issue 25): checked as a property of sys.modules in a fresh
process, not as a time (times are in benchmarks/bench_startup.py)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_help_and_campbell_import_neither_numba_nor_sympy_nor_scipy_integrate(tmp_path):
    code = f"""
        import json, sys
        from rotaflex.cli import main

        def run(argv):
            try:
                main(argv)
            except SystemExit as exc:
                assert exc.code == 0, (argv, exc.code)
            return sorted(m for m in ("numba", "sympy", "scipy.integrate", "distributed", "matplotlib",
                                      "xarray") if m in sys.modules)

        helped = run(["--help"])
        campbell = run(["rotor", "campbell", {str(ROOT / "examples/rotor/fe_friswell_5_9_1.toml")!r},
                        "--out", {str(tmp_path / "out")!r}, "--no-figures", "--quiet"])
        print(json.dumps({{"help": helped, "campbell": campbell}}))
    """
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    proc = subprocess.run(
        [sys.executable, "-c", textwrap.dedent(code)], env=env, capture_output=True, text=True, timeout=300
    )
    assert proc.returncode == 0, proc.stderr
    got = json.loads(proc.stdout.strip().splitlines()[-1])
    assert got["help"] == []  # --help loads none of the heavy libraries
    # campbell computes eigenvalues and writes NetCDF: xarray only; no compiler, no symbolic
    # algebra, no ODE integrator, no Dask cluster client, no plotting with --no-figures
    assert got["campbell"] == ["xarray"]
    assert (tmp_path / "out" / "result.nc").exists()
