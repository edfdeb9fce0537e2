"""Every FE rotor verb sizes its run before it starts: clean one-line refusals (exit 2), raisable limits."""

from pathlib import Path

import pytest
from typer.testing import CliRunner

from rotaflex.cli import app

EXAMPLE = Path(__file__).resolve().parents[3] / "examples" / "rotor" / "fe_friswell_5_9_1.toml"


def _run(tmp_path, verb, old, new, *extra, env=None):
    text = EXAMPLE.read_text()
    assert old in text
    cfg = tmp_path / "c.toml"
    cfg.write_text(text.replace(old, new, 1))
    return CliRunner().invoke(app, ["rotor", verb, str(cfg), "--out", str(tmp_path / "o"), "-q", *extra], env=env)


@pytest.mark.parametrize(
    "verb, old, new, field",
    [
        ("modal", "elements = 6", "elements = 3000", "shaft[0].elements"),
        ("static", "elements = 6", "elements = 100000", "shaft[0].elements"),
        ("transient", "n_output = 4001", "n_output = 1000000000", "transient.n_output"),
        (
            "transient",
            'method = "modal"',
            'method = "direct"\nsteps_per_output = 1000000000',
            "transient.steps_per_output",
        ),
        ("unbalance", "n_speeds = 500", "n_speeds = 1000000000", "unbalance.n_speeds"),
        ("campbell", "n_speeds = 50", "n_speeds = 1000000000", "campbell.n_speeds"),
        ("ucs", "n_points = 40", "n_points = 1000000000", "ucs.n_points"),
    ],
)
def test_oversized_runs_are_refused_in_one_line(tmp_path, verb, old, new, field):
    res = _run(tmp_path, verb, old, new)
    assert res.exit_code == 2, res.output
    lines = res.output.strip().splitlines()
    assert len(lines) == 1 and field in lines[0] and "Traceback" not in res.output
    assert not (tmp_path / "o").exists()


def test_memory_estimate_refuses_and_limit_is_raisable(tmp_path):
    # 20,000 speeds x 28 DOF: ~1 GB planned for the batched solve; refused under 100 MB, runs under the default
    env = {"ROTAFLEX_MAX_MEMORY": "100MB"}
    res = _run(tmp_path, "unbalance", "n_speeds = 500", "n_speeds = 20000", "--no-figures", env=env)
    assert res.exit_code == 2 and "ROTAFLEX_MAX_MEMORY" in res.output and "unbalance.n_speeds" in res.output
    res = _run(tmp_path, "modal", "elements = 6", "elements = 1200")
    assert res.exit_code == 2 and "max_dof" in res.output
    res = _run(tmp_path, "modal", "elements = 6", "elements = 60", "--no-figures")
    assert res.exit_code == 0, res.output


def test_reduce_above_dofs_is_a_full_solve_with_a_note(tmp_path):
    import json

    res = _run(tmp_path, "campbell", "n_modes = 6\nharmonics", "n_modes = 6\nreduce = 500\nharmonics", "--no-figures")
    assert res.exit_code == 0, res.output
    s = json.loads((tmp_path / "o" / "summary.json").read_text())
    assert "full solve" in s["note"]["value"]


def test_ucs_n_modes_above_the_plane_dofs_is_clamped(tmp_path):
    import json

    res = _run(tmp_path, "ucs", "n_points = 40", "n_points = 5\nn_modes = 100", "--no-figures")
    assert res.exit_code == 0, res.output
    s = json.loads((tmp_path / "o" / "summary.json").read_text())
    assert "clamped to 14" in s["note"]["value"]


def test_campbell_n_modes_above_the_dofs_is_clamped(tmp_path):
    """n_modes 100 in a 28-DOF rotor: once a crash (non-finite matrix); now clamped, with figures."""
    import json

    res = _run(tmp_path, "campbell", "n_speeds = 50\nn_modes = 6", "n_speeds = 8\nn_modes = 100")
    assert res.exit_code == 0, res.output
    s = json.loads((tmp_path / "o" / "summary.json").read_text())
    assert "clamped to 28" in s["note"]["value"] and (tmp_path / "o" / "campbell.png").exists()


def test_modal_transient_that_the_explicit_step_cannot_finish_is_refused():
    """A shaft of negligible mass keeps a 0.96 MHz mode in the modal basis: DOP853 would need
    ~4e7 right-hand sides for 0.7 s (9.4 per radian measured: 3.07e6 for 0.05 s); the run is
    refused up front naming transient.n_modes, and the implicit direct method runs it."""
    import numpy as np

    from rotaflex.core.errors import InputError
    from rotaflex.rotor.fe import Bearing, PointMass, Rotor, Shaft
    from rotaflex.rotor.fe.study import transient_response

    light = Shaft(outer_diameter=0.02, length=0.6, elements=4, G=1e20, shear_coefficient=1.0, rho=1.0)
    brg = (Bearing(node=0, kxx=1e7, kyy=1e7), Bearing(node=4, kxx=1e7, kyy=1e7))
    rotor = Rotor(shaft=(light,), point_mass=(PointMass(node=2, mass=10.0),), bearing=brg)
    kw = dict(speed_rpm=(1500.0, 1500.0), masses=[{"node": 2, "magnitude": 1e-4}], n_output=71)
    with pytest.raises(InputError, match=r"transient\.n_modes.*mode at 9\.\d+e\+05 Hz.*method = 'direct'"):
        transient_response(rotor, duration=0.7, method="modal", **kw)
    res = transient_response(rotor, duration=0.7, method="direct", **kw)
    assert np.all(np.isfinite(res.dataset["displacement"].values))
