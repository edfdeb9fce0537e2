"""Issue part 5 through the CLI: each bad input gives exit status 2 and one clear error line."""

import tomllib

import pytest
from typer.testing import CliRunner

from rotaflex.cli import app

# 4-node user body (a cross in the xy plane), one out-of-plane "saddle" mode, mass-orthonormal
POINTS = """
domain = "floating"
[body]
type = "points"
[body.points]
masses = [1.0, 1.0, 1.0, 1.0]
positions = [[-0.5, 0.0, 0.0], [0.5, 0.0, 0.0], [0.0, -0.5, 0.0], [0.0, 0.5, 0.0]]
shapes = [[[0.0, 0.0, 0.5], [0.0, 0.0, 0.5], [0.0, 0.0, -0.5], [0.0, 0.0, -0.5]]]
frequencies = [3.0]
[solver]
t_end = 0.1
dt_out = 0.01
"""

BEAM = """
domain = "floating"
[body]
type = "beam"
[body.beam]
length = 2.0
rho_a = 1.0
ei = 10.0
n_modes = 2
[solver]
t_end = 0.1
dt_out = 0.01
[outputs]
tip = [1.0, 0.0, 0.0]
"""


def _write(tmp_path, text):
    p = tmp_path / "case.toml"
    p.write_text(text)
    tomllib.loads(text)  # the case file itself is valid TOML
    return p


@pytest.mark.parametrize(
    "base, old, new, words",
    [
        (
            POINTS,
            "masses = [1.0, 1.0, 1.0, 1.0]",
            "masses = [1.0, -1.0, 1.0, 1.0]",
            ["body.points.masses[1]", "mass > 0"],
        ),
        (BEAM, "rho_a = 1.0", "rho_a = 0.0", ["body.beam.rho_a"]),
        (BEAM, "ei = 10.0", "ei = -5.0", ["body.beam.ei"]),
        (POINTS, "frequencies = [3.0]", "frequencies = [0.0]", ["body.points.frequencies[0]", "> 0"]),
        (
            POINTS,
            "[0.0, 0.0, -0.5], [0.0, 0.0, -0.5]]]",
            "[0.0, 0.0, -0.6], [0.0, 0.0, -0.5]]]",
            ["body.points.shapes", "mass-orthonormal"],
        ),
        (
            POINTS,
            "shapes = [[[0.0, 0.0, 0.5], [0.0, 0.0, 0.5], [0.0, 0.0, -0.5], [0.0, 0.0, -0.5]]]\nfrequencies = [3.0]",
            "shapes = []\nfrequencies = []",
            ["body.points.shapes", "no elastic modes"],
        ),
        (
            POINTS,
            "[0.0, -0.5, 0.0], [0.0, 0.5, 0.0]]",
            "[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0]]",
            ["body", "non-singular inertia"],
        ),
        (BEAM, "tip = [1.0, 0.0, 0.0]", "tip = [1.5, 0.0, 0.0]", ["outputs.tip", "beam axis"]),
        (BEAM, "tip = [1.0, 0.0, 0.0]", "tip = [0.5, 0.2, 0.0]", ["outputs.tip", "beam axis"]),
        (
            POINTS,
            "frequencies = [3.0]\n",
            "frequencies = [3.0]\n[outputs]\nfar = [0.2, 0.0, 0.0]\n",
            ["outputs.far", "node"],
        ),
    ],
)
def test_bad_input_one_line(tmp_path, base, old, new, words):
    assert old in base
    path = _write(tmp_path, base.replace(old, new))
    res = CliRunner().invoke(app, ["floating", "simulate", str(path), "--out", str(tmp_path / "o")])
    assert res.exit_code == 2, res.output
    lines = [ln for ln in res.output.strip().splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("error:"), res.output
    for w in words:
        assert w in lines[0], lines[0]


def test_good_points_case_runs(tmp_path):
    path = _write(tmp_path, POINTS)
    res = CliRunner().invoke(app, ["floating", "simulate", str(path), "--out", str(tmp_path / "o")])
    assert res.exit_code == 0, res.output
