"""Progress of floating runs and the deflection figure."""

import numpy as np
from typer.testing import CliRunner

from rotaflex.cli import app
from rotaflex.floating.beam import uniform_beam
from rotaflex.floating.model import Load, Settings
from rotaflex.floating.solve import simulate

CASE = """
domain = "floating"
[body]
type = "beam"
[body.beam]
length = 2.0
rho_a = 1.0
ei = 10.0
n_modes = 2
[[loads]]
kind = "torque"
vector = [0.0, 0.0, 0.2]
profile = "bang-bang"
duration = 0.5
[solver]
method = "both"
t_end = 1.0
dt_out = 0.01
[outputs]
tip = [1.0, 0.0, 0.0]
"""


def test_progress_in_chunks_gives_the_same_steps():
    b = uniform_beam(2.0, 1.0, 10.0, 3)
    ld = [Load(kind="torque", vector=(0.0, 0.0, 0.2), profile="bang-bang", duration=0.5)]
    st = Settings(t_end=1.0, dt_out=0.01)
    seen = []
    for m in ("full", "perturbation"):
        one = simulate(b, ld, settings=st, method=m)
        chunked = simulate(b, ld, settings=st, method=m, progress=seen.append)
        assert np.array_equal(one.q, chunked.q) and np.array_equal(one.euler_123, chunked.euler_123)
        assert one.nstep == chunked.nstep and one.nfev == chunked.nfev
    assert np.all(np.diff(seen[: len(seen) // 2]) > 0) and seen[-1] == 1.0


def test_cli_prints_progress_lines_off_a_terminal_and_a_readable_deflection_figure(tmp_path):
    path = tmp_path / "case.toml"
    path.write_text(CASE)
    out = tmp_path / "o"
    res = CliRunner().invoke(app, ["floating", "simulate", str(path), "--out", str(out)])
    assert res.exit_code == 0, res.output
    lines = [ln for ln in res.output.splitlines() if ln.startswith("simulating")]
    # the one progress style of every verb (rotaflex.core.progress): a line per 10 % of each solution
    for m in ("full", "perturbation"):
        mine = [ln for ln in lines if ln.startswith(f"simulating {m}: ")]
        assert len(mine) >= 10 and mine[-1].startswith(f"simulating {m}: 100 % (1/1 s), ")
        assert f"simulating {m}: 50 % (0.5/1 s), " in "\n".join(mine)
    assert (out / "deflection.png").is_file()

    import xarray as xr

    from rotaflex.floating.result import FloatingResult

    with xr.open_dataset(out / "result.nc") as ds:
        figs = FloatingResult(ds.load()).plot()
    ax = figs["deflection"].axes[0]
    lines = ax.get_lines()
    assert len(lines) == 2 == len(ax.get_legend().get_texts())  # one per solution, both visible
    assert {ln.get_linestyle() for ln in lines} == {"-", "--"}
    assert "um]" not in ax.get_ylabel() and ax.get_ylabel().endswith(("[m]", "[mm]", "[µm]"))
    assert "max |perturbation - full|" in ax.get_title()
