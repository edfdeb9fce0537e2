"""examples/gear/one_pair_all_verbs.toml: one unequal, root-clamped [pinion]/[wheel] file through
`gear static`, `gear steady` and a rattling `gear simulate` (speed mismatch), coarse settings."""

import json
import math
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

from rotaflex.cli import app

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "gear" / "one_pair_all_verbs.toml"


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("one_pair")
    text = EXAMPLE.read_text().replace("n_angles = 240", "n_angles = 60")
    text = text.replace("[operation]\n", "[operation]\nspan_deg = 0.4\n", 1)  # simulate: past the first strike
    cfg = tmp / "pair.toml"
    cfg.write_text(text)
    out = {}
    for verb in ("static", "steady", "simulate"):
        res = CliRunner().invoke(app, ["gear", verb, str(cfg), "--out", str(tmp / verb), "-q", "--no-figures"])
        assert res.exit_code == 0, (verb, res.output)
        out[verb] = tmp / verb
    return out


def test_static_and_steady_read_the_same_pair_and_torque(runs):
    static = json.loads((runs["static"] / "summary.json").read_text())
    steady = xr.open_dataset(runs["steady"] / "result.nc")
    assert steady.attrs["status"] == "success"
    # torque_on = "pinion", 80 N m: static's pinion torque as written, steady's wheel torque x 40/20
    assert json.loads(steady.attrs["config"])["operation"]["torque"] == pytest.approx(160.0, rel=1e-15)
    assert static["geometry_contact_ratio"] == {"value": pytest.approx(1.5485, abs=1e-4), "unit": "1"}
    for key, row in static.items():
        if key.startswith("geometry_"):
            assert row["unit"], key  # every geometry entry names its unit
    rb2 = 40 * 2e-3 / 2 * math.cos(math.radians(20.0))
    assert float(steady["static_mesh_force"]) == pytest.approx(160.0 / rb2, rel=1e-12)


def test_simulate_rattles_from_the_speed_mismatch(runs):
    ds = xr.open_dataset(runs["simulate"] / "result.nc")
    assert ds.attrs["status"] == "success"
    w = ds["angular_velocity"].values[0] * 30 / math.pi  # first record [rpm]
    assert abs(w[0]) == pytest.approx(1000.0, rel=1e-3)  # pinion as written
    assert abs(w[1]) == pytest.approx(505.0, rel=1e-3)  # wheel 1 % above 1000 / 2
    force = ds["contact_force"].values.reshape(ds.sizes["time"], -1).sum(axis=1)
    gap = ds["gap"].values.reshape(ds.sizes["time"], -1)[:, 0]
    first = int(np.argmax(force > 0))
    assert first > 10 and np.all(gap[1:first] > 0)  # the faster wheel runs ahead: teeth apart
    assert force.max() > 0  # ... until they strike again
    assert float(ds["energy_balance_abs"]) < 0.05
