"""The exact beam through the CLI (exit statuses, one-line errors, ParaView output), its
material damping against linear theory, and the benchmark script at tiny size."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from test_exact_beam_static import elastica_tip
from typer.testing import CliRunner

from rotaflex.cli import app
from rotaflex.floating.exact_beam import PointLoads, cantilever
from rotaflex.floating.exact_solve import simulate_exact

ROOT = Path(__file__).resolve().parents[2]

CANTILEVER = """
domain = "floating"
[body]
type = "beam"
model = "exact"
[body.beam]
length = 1.0
rho_a = 1.0
ei = 1.0
support = "cantilever"
[body.exact]
elements = 8
analysis = "static"
[[loads]]
kind = "force"
vector = [0.0, -2.0, 0.0]
point = [1.0, 0.0, 0.0]
frame = "inertial"
[solver]
t_end = 1.0
dt_out = 1.0
[outputs]
tip = [1.0, 0.0, 0.0]
[paraview]
"""


def invoke(tmp_path, text):
    path = tmp_path / "case.toml"
    path.write_text(text)
    return CliRunner().invoke(app, ["floating", "simulate", str(path), "--out", str(tmp_path / "o"), "--no-figures"])


def test_static_case_writes_result_summary_and_paraview(tmp_path):
    res = invoke(tmp_path, CANTILEVER)
    assert res.exit_code == 0, res.output
    summary = json.loads((tmp_path / "o" / "summary.json").read_text())
    # P L^2 / EI = 2: the elastica's tip (elliptic integrals); 8 elements, O(h^2) ~ 3e-3 L
    x, y, _ = elastica_tip(2.0)
    assert summary["static.tip.max_deflection"]["value"] == pytest.approx(np.hypot(1 - x, y), abs=5e-3)
    assert summary["static.modal_body_adequate"]["value"] is False
    pvd = tmp_path / "o" / "paraview" / "static.pvd"
    assert pvd.exists() and len(list(pvd.parent.glob("static_*.vtu"))) == 2


@pytest.mark.parametrize(
    ("old", "new", "words"),
    [
        ("elements = 8", "elements = 0", ["body.exact.elements"]),
        ("ei = 1.0", "ei = -1.0", ["body.beam.ei"]),
        ('analysis = "static"', 'analysis = "static"\nea = 0.0', ["body.exact.ea"]),
        ('analysis = "static"', 'analysis = "static"\nga = -2.0', ["body.exact.ga"]),
        ("vector = [0.0, -2.0, 0.0]", "vector = [0.0, -2.0, 1.0]", ["loads[0].vector", "x-y plane"]),
    ],
)
def test_bad_input_is_one_line_exit_2(tmp_path, old, new, words):
    res = invoke(tmp_path, CANTILEVER.replace(old, new))
    assert res.exit_code == 2, res.output
    lines = [ln for ln in res.output.strip().splitlines() if ln.strip()]
    assert len(lines) == 1 and all(w in lines[0] for w in words), res.output


def test_load_beyond_reach_is_one_line_exit_1(tmp_path):
    # a 1e9 EI/L^2 follower load on 8 elements: Newton's load stepping gives up, naming the
    # fraction reached
    text = CANTILEVER.replace("vector = [0.0, -2.0, 0.0]", "vector = [0.0, -1e9, 0.0]").replace(
        'frame = "inertial"', 'frame = "material"'
    )
    res = invoke(tmp_path, text)
    assert res.exit_code == 1, res.output
    lines = [ln for ln in res.output.strip().splitlines() if ln.strip()]
    assert len(lines) == 1 and "load fraction" in lines[0], res.output


def test_material_damping_gives_the_first_mode_its_ratio():
    # Kelvin-Voigt eta = 2 zeta / omega_1 is stiffness-proportional damping: mode 1 decays with
    # ratio zeta (log decrement 2 pi zeta / sqrt(1 - zeta^2)); linear range (1e-4 L)
    zeta, w1 = 0.02, 1.8751040687**2
    n = 16
    b = cantilever(1.0, n, ea=1e6, ga=1e6, ei=1.0, rho_a=1.0)
    v0 = np.zeros(b.n_dof)
    s = b.nodes[:, 0]
    v0[1 : 3 * (n + 1) : 3] = 1e-4 * (3 * s**2 - s**3) / 2
    v0[2 : 3 * (n + 1) : 3] = 1e-4 * (6 * s - 3 * s**2) / 2
    T1 = 2 * np.pi / w1
    sol = simulate_exact(
        b, PointLoads.build(b, [], [], [], []), t_end=6 * T1, dt_out=T1 / 400, time_step=T1 / 400,
        rho_inf=1.0, eta=2 * zeta / w1, v0=v0,
    )  # fmt: skip
    y = sol.q[:, 3 * n + 1]
    peaks = [i for i in range(1, len(y) - 1) if y[i] > y[i - 1] and y[i] >= y[i + 1] and sol.time[i] > T1]
    dec = np.log(y[peaks[0]] / y[peaks[-1]]) / (len(peaks) - 1)
    assert dec == pytest.approx(2 * np.pi * zeta / np.sqrt(1 - zeta**2), rel=0.03)


def test_benchmark_runs_at_tiny_size():
    proc = subprocess.run(
        [sys.executable, str(ROOT / "benchmarks" / "bench_exact_beam.py"), "--tiny"],
        capture_output=True,
        text=True,
        env={**os.environ, "PYTHONPATH": str(ROOT / "src")},
        timeout=600,
    )
    assert proc.returncode == 0, proc.stderr
    rows = json.loads(proc.stdout.strip().splitlines()[-1])["rows"]
    assert rows[0]["exact_wall_s"] > 0 and rows[0]["modal_wall_s"] > 0
    # 1 deg of slew bends the arm ~0.2 % of L: both bodies agree to a few % of the peak there
    assert rows[0]["modal_minus_exact_relative"] < 0.05
