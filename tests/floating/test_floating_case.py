"""TOML cases: every example parses and runs (shortened); bad input gives one InputError."""

from pathlib import Path

import numpy as np
import pytest

from rotaflex.core.config import load_toml, set_dotted
from rotaflex.core.domains import run_config
from rotaflex.core.errors import InputError

EXAMPLES = sorted((Path(__file__).parents[2] / "examples" / "floating").glob("*.toml"))


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.stem)
def test_examples_run(path, tmp_path):
    cfg = set_dotted(set_dotted(load_toml(path), "solver.t_end", 0.5), "solver.dt_out", 0.01)
    res = run_config(cfg)
    assert res.status == "success"
    ds = res.dataset
    assert ds["point_deflection"].attrs["units"] == "m"
    assert np.all(np.isfinite(ds["position"].values))
    res.save(tmp_path, figures=False)
    assert (tmp_path / "result.nc").exists()


def test_bad_input_is_one_input_error():
    base = load_toml(next(p for p in EXAMPLES if p.stem == "planar_slew"))
    for key, value, word in [
        ("body.beam.rho_a", -1.0, "rho_a"),
        ("outputs.far", [9.0, 0.0, 0.0], "outputs.far"),
        ("solver.method", "magic", "solver.method"),
        ("loads", [{"kind": "torque", "profile": "ramp"}], "duration"),
    ]:
        with pytest.raises(InputError, match=word):
            run_config(set_dotted(base, key, value))
