"""Generic sweep panels: no speed drawn against speed, and each number's meaning on its panel
(issue 37: a system sweep's summary had 3 of 9 panels speed vs speed and a force minimum of
-650 N that nothing explained)."""

import math

import numpy as np
import xarray as xr

from rotaflex.sweep.combine import combine
from rotaflex.sweep.figures import generic_figures, proportional
from rotaflex.sweep.runner import CaseRecord


def _sweep():
    rpm = np.array([1000.0, 2000.0, 3000.0, 4000.0])
    attrs = {"units": "rpm", "config_key": "steady.speed_rpm"}
    return xr.Dataset(
        {
            "speed": ("steady_speed_rpm", rpm * 2 * math.pi / 60, {"units": "rad/s"}),
            "mesh_frequency": ("steady_speed_rpm", rpm * 20 / 60, {"units": "Hz"}),  # 20 teeth
            "force_min": ("steady_speed_rpm", [1481.0, 1034.0, -20.1, 2110.0], {"units": "N", "description": "why"}),
            "force_max": ("steady_speed_rpm", rpm * 2.0, {"units": "N"}),  # proportional, but a result
        },
        coords={"steady_speed_rpm": ("steady_speed_rpm", rpm, attrs)},
    )


def test_speeds_and_frequencies_proportional_to_the_swept_speed_get_no_panel():
    ds = _sweep()
    # 2 pi / 60 = 0.10472 rad/s per rpm; 20 teeth / 60 = 0.3333 Hz per rpm
    assert math.isclose(proportional(ds, "speed", "steady_speed_rpm"), 2 * math.pi / 60, rel_tol=1e-12)
    assert math.isclose(proportional(ds, "mesh_frequency", "steady_speed_rpm"), 1 / 3, rel_tol=1e-12)
    assert proportional(ds, "force_max", "steady_speed_rpm") is None  # newtons: a result, drawn
    fig = generic_figures(ds)["summary_vs_speed_rpm"]
    drawn = [a.get_ylabel() for a in fig.axes if a.get_visible()]
    assert len(drawn) == 2 and not any("speed" in y or "frequency" in y for y in drawn)
    assert "speed [rad/s] = 0.1047 × speed [rpm]" in fig.rotaflex_dropped
    assert "mesh_frequency [Hz] = 0.3333 × speed [rpm]" in fig.rotaflex_dropped


def test_a_speed_that_is_not_proportional_keeps_its_panel():
    ds = _sweep()
    ds["speed"] = ds["speed"] + np.array([0.0, 0.0, 1.0, 0.0])  # e.g. a slip
    assert proportional(ds, "speed", "steady_speed_rpm") is None


def test_the_summary_long_name_is_the_panel_title():
    def rec(i, v):  # one case as the runner hands it to combine
        summary = {"force_min": {"value": v, "unit": "N", "long_name": "smallest mesh force; below 0: pull"}}
        return CaseRecord(f"{i}", {"steady.speed_rpm": 1000.0 * (i + 1)}, "success", summary=summary)

    ds = combine([rec(0, 10.0), rec(1, -5.0)])
    assert ds["force_min"].attrs["description"] == "smallest mesh force; below 0: pull"
    fig = next(iter(generic_figures(ds).values()))
    assert fig.axes[0].get_title() == "smallest mesh force; below 0: pull"
