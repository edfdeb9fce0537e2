"""The general rule of the sweep summary figures, checked on the figure data: constant and
round-off-only scalars get no panel (and are named in the footnote), labels are words with the
unit, never raw keys, and the x axis always shows its unit."""

import numpy as np
import pytest
import xarray as xr

from rotaflex.sweep.figures import display_scale, generic_figures, uninformative

KEY = "operation.speed_rpm"


def _ds():
    speed = np.linspace(1000.0, 5000.0, 5)
    dim = "operation_speed_rpm"
    rng = np.random.default_rng(0)
    data = {
        "dynamic_factor": (dim, 1 + speed / 2e4, {"units": "1", "long_name": "dynamic factor K_v"}),
        "dte_peak_to_peak": (dim, [2e-6, 3e-6, 5e-6, 4e-6, 1e-6], {"units": "m"}),
        "normal_backlash": (dim, 1e-18 * (1 + rng.random(5)), {"units": "m"}),  # round-off of a zero gap
        "reduced_mass": (dim, np.full(5, 0.41), {"units": "kg"}),  # the same model at every speed
        "max_tie_residual": (dim, 3e-17 * rng.random(5), {"units": "m"}),
        "wall_time": (dim, [1.0, 1.2, 0.9, 1.1, 1.3], {"units": "s"}),
        "attempts": (dim, np.ones(5), {"units": "1"}),
    }
    coords = {dim: (dim, speed, {"units": "rpm", "config_key": KEY})}
    return xr.Dataset(data, coords=coords)


def _panels(fig):
    return {ax.get_ylabel().replace("\n", " "): ax for ax in fig.axes if ax.get_visible() and ax.get_ylabel()}


def test_constant_and_round_off_scalars_get_no_panel_but_are_named():
    figs = generic_figures(_ds())
    summary = _panels(figs["summary_vs_speed_rpm"])
    assert set(summary) == {"dynamic factor K_v [-]", "DTE peak to peak [µm]"}
    note = figs["summary_vs_speed_rpm"].rotaflex_dropped
    assert "constant: reduced_mass = 0.41 kg" in note
    assert "round-off only: normal_backlash)" in note
    diag = _panels(figs["diagnostics_vs_speed_rpm"])
    assert set(diag) == {"wall time [s]"}  # the flat attempts panel and the round-off residual are gone
    note = figs["diagnostics_vs_speed_rpm"].rotaflex_dropped
    assert "attempts = 1" in note and "round-off only: max_tie_residual" in note


def test_labels_are_words_with_units_and_the_x_unit_is_always_shown():
    figs = generic_figures(_ds())
    for fig in figs.values():
        for ax in (a for a in fig.axes if a.get_visible()):
            assert ax.get_xlabel() == "speed [rpm]"  # not "operation.speed_rpm [rpm]"
            assert "_" not in ax.get_ylabel().replace("K_v", "") and "[" in ax.get_ylabel()
        assert "speed [rpm]" in fig._suptitle.get_text()
    ds = _ds()
    del ds["operation_speed_rpm"].attrs["units"]  # a key without a unit attribute: from the key
    fig = generic_figures(ds)["summary_vs_speed_rpm"]
    assert {a.get_xlabel() for a in fig.axes if a.get_visible()} == {"speed [rpm]"}


def test_drawn_data_are_the_dataset_values():
    ds = _ds()
    ax = _panels(generic_figures(ds)["summary_vs_speed_rpm"])["DTE peak to peak [µm]"]
    (line,) = ax.get_lines()
    np.testing.assert_array_equal(line.get_xdata(), ds["operation_speed_rpm"].values)
    np.testing.assert_allclose(line.get_ydata(), ds["dte_peak_to_peak"].values * 1e6, rtol=1e-15)  # in um


@pytest.mark.parametrize(
    ("values", "units", "why"),
    [
        ([1.0, 1.0, 1.0], "1", "constant"),
        ([0.0, 0.0], "m", "constant"),
        ([2e-13, -5e-13], "m", "round-off"),  # below a picometre
        ([2e-13, -5e-13], "N", "round-off"),
        ([1e-9, 2e-9], "m", ""),  # nanometres vary: drawn
        ([1.0, 1.0 + 1e-6], "1", ""),
        ([np.nan, 3.0, 3.0], "1", "constant"),
    ],
)
def test_uninformative_rule(values, units, why):
    assert uninformative(xr.DataArray(values, attrs={"units": units})) == why


@pytest.mark.parametrize(
    ("values", "units", "expected"),
    [
        ([2e-6, 5e-6], "m", (1e6, "um")),
        ([0.2, 1.5], "m", (1.0, "m")),
        ([7e7, 1.4e8], "Pa", (1e-6, "MPa")),
        ([500.0, 900.0], "N", (1.0, "N")),
        ([0.5, 2.0], "1", (1.0, "1")),
    ],
)
def test_display_scale_picks_a_prefix_by_the_largest_magnitude(values, units, expected):
    assert display_scale(xr.DataArray(values, attrs={"units": units})) == expected


def test_an_indexed_sweep_key_gets_the_unit_of_its_schema_key():
    from rotaflex.sweep.combine import param_units
    from rotaflex.sweep.study import _schema_units

    units = _schema_units("rotaflex.floating.case")
    assert units["loads[].duration"] == "s"  # the schema lists the keys of one [[loads]] entry
    assert param_units("loads[0].duration", units) == "s" and param_units("loads[3].start", units) == "s"


def test_variable_labels_keep_every_part_of_the_name():
    var = xr.DataArray([1e-3, 2e-3], name="perturbation.tip.max_deflection", attrs={"units": "m"})
    fig = generic_figures(xr.Dataset({var.name: ("x", var.values, var.attrs)}, coords={"x": ("x", [1.0, 2.0])}))
    labels = [a.get_ylabel().replace("\n", " ") for a in fig["summary_vs_x"].axes if a.get_visible()]
    assert labels == ["perturbation tip max deflection [mm]"]
