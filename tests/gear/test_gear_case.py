"""Gear case configuration, run_case, GearResult output."""

import math

import pytest

from rotaflex.core.errors import InputError
from rotaflex.core.result import load_result
from rotaflex.gear.cases.simulate import run_case

FAST = {"operation": {"span_deg": 0.3}, "mesh": {"preset": "coarse"}, "output": {"every": 5}}


def test_bad_inputs_name_the_field():
    with pytest.raises(InputError, match="solver.dt"):
        run_case({"solver": {"dt": -1.0}})
    with pytest.raises(InputError, match="operation.speed"):
        run_case({"operation": {"speeds": [1, 2]}})
    with pytest.raises(InputError, match="theta_2"):
        run_case({"operation": {"theta_2_deg": 12.0, "theta_s_deg": 21.0}})
    with pytest.raises(InputError, match="stability limit"):
        run_case({**FAST, "solver": {"dt": 1e-6}})


def test_run_case_result_and_save(tmp_path):
    res = run_case(FAST)
    ds = res.dataset
    assert res.status == "success"
    assert ds["contact_force"].attrs["units"] == "N"
    assert ds["rotation_angle"].dims == ("time", "gear")
    assert abs(math.degrees(float(ds["rotation_angle"].sel(gear="A")[-1])) - 0.3) < 0.01
    s = res.summary()
    assert abs(s["nominal_force"]["value"] - 532.7) < 0.1
    assert s["steps"]["value"] > 100
    paths = res.save(tmp_path)
    assert (tmp_path / "contact_force.png").exists()
    back = load_result(tmp_path / "result.nc")
    assert back.kind == "gear"
    assert float(back.dataset["peak_contact_force"]) == pytest.approx(float(ds["peak_contact_force"]))
    assert len(paths) >= 3
