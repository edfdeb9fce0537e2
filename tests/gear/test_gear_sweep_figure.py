"""The gear steady-state sweep figure (``gear_steady_sweep``) and ISO 6336-1's n_E1 (issue 22).

n_E1 is checked against the standard's formula worked by hand; the figure's tags against each
other and against the plotting area with the renderer's own boxes (matplotlib
``get_window_extent``), for the case that overprinted: two variants whose resonances lie 0.2 %
apart, with ISO's n_E1 between the orders.
"""

from __future__ import annotations

import json
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from rotaflex.gear.static.iso6336_kv import IsoKvInput, resonance_speed_rpm

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "gear" / "steady" / "torsional_dynamic_factor.toml"


def test_n_e1_matches_the_iso_formula_worked_by_hand():
    # ISO 6336-1: n_E1 = 30000 / (pi z1) sqrt(c_gamma_alpha / m_red), c_gamma_alpha in N/(mm um),
    # m_red in kg/mm. z1 = 20, c_gamma_alpha = 20 N/(mm um), m_red = 0.01 kg/mm:
    # 30000 / (20 pi) = 477.4648, sqrt(20 / 0.01) = 44.72136, n_E1 = 21,352.9 rpm
    n_e1 = resonance_speed_rpm(20.0e9, 10.0, 20)  # the same data in SI: N/m^2, kg/m
    assert n_e1 == pytest.approx(21352.9, abs=0.1)
    assert n_e1 == pytest.approx(30000.0 / (math.pi * 20) * math.sqrt(20.0 / 0.01), rel=1e-12)
    assert IsoKvInput(z1=20, c_gamma_alpha=20.0e9, m_red=10.0).resonance_speed_rpm == n_e1


def _sweep(fn=(12956.0, 12985.0), n_e1=29967.0):
    """A continuation sweep of two variants (model.relief) as `rotaflex sweep` combines it; the
    model resonances (60 f_n / z1, z1 = 20) of the two variants 0.2 % apart."""
    import xarray as xr

    speeds = np.linspace(4000.0, 48000.0, 12)
    shape = (speeds.size, 2, 2)
    per_variant = lambda v: np.broadcast_to(np.asarray(v, float)[None, :, None], shape).copy()  # noqa: E731
    kv = 1.0 + 0.5 * np.exp(-(((speeds - 36000.0) / 8000.0) ** 2))
    dims = ("operation_speed_rpm", "model_relief", "direction")
    speed_attrs = {"units": "rpm", "config_key": "operation.speed_rpm"}
    ds = xr.Dataset(
        {
            "dynamic_factor": (dims, np.broadcast_to(kv[:, None, None], shape).copy(), {"units": "1"}),
            "dte_pp": (dims, np.full(shape, 2e-6), {"units": "m"}),
            "status": (dims, np.full(shape, "success")),
            "mesh_natural_frequency": (dims, per_variant(fn), {"units": "Hz"}),
            "resonance_speed": (dims, per_variant(np.asarray(fn) * 60.0 / 20), {"units": "rpm"}),
            "iso_resonance_speed": (dims, per_variant([n_e1, n_e1]), {"units": "rpm"}),
            "iso_kv": (dims, np.full(shape, 1.2), {"units": "1"}),
        },
        coords={
            "operation_speed_rpm": ("operation_speed_rpm", speeds, speed_attrs),
            "model_relief": ("model_relief", [True, False], {"config_key": "model.relief"}),
            "direction": ["up", "down"],
        },
    )
    ds.attrs["verb"] = "steady"
    return ds


def _figure(ds):
    from rotaflex.gear.results.sweep_figures import sweep_figures

    fig = sweep_figures(ds)["gear_steady_sweep"]
    fig.canvas.draw()  # constrained layout done: the boxes below are those of the saved image
    return fig


def test_resonance_tags_overlap_neither_each_other_nor_the_curves_nor_the_title():
    fig = _figure(_sweep())
    r = fig.canvas.get_renderer()
    top = fig.axes[0]
    tags = [t for t in top.texts if t.get_text() in ("1x", "2x", "n_E1")]
    # two variants x (1x, 2x) + n_E1, all inside the 4,000-48,000 rpm range
    assert sorted(t.get_text() for t in tags) == ["1x", "1x", "2x", "2x", "n_E1"]
    boxes = [t.get_window_extent(r) for t in tags]
    for i, a in enumerate(boxes):
        for b in boxes[i + 1 :]:
            assert not a.overlaps(b), (a, b)
    plot_area = top.get_window_extent(r)
    title = fig._suptitle.get_window_extent(r)
    for b in boxes:
        assert b.y0 >= plot_area.y1  # above the plotting area: never across a curve
        assert not b.overlaps(title)
    for ax in fig.axes:  # nothing written inside the panels
        assert all(t.get_window_extent(r).y0 >= plot_area.y1 for t in ax.texts)


def test_each_variant_has_its_own_f_n_and_the_title_no_mean():
    fig = _figure(_sweep())
    assert "f_n =" not in fig._suptitle.get_text()  # two variants: no single (mean) value
    labels = fig.axes[1].get_legend().get_texts()
    text = "\n".join(t.get_text() for t in labels)
    assert "12956 Hz, model.relief = True" in text and "12985 Hz, model.relief = False" in text
    assert "1x f_mesh = f_n (12956 Hz, model.relief = True): 38,868 rpm" in text
    one = _figure(_sweep(fn=(12956.0, 12956.0)))
    assert one._suptitle.get_text().endswith("(linear mesh mode f_n = 12956 Hz)")


def test_n_e1_is_drawn_and_labelled_with_its_value():
    fig = _figure(_sweep(n_e1=resonance_speed_rpm(20.0e9, 10.0, 20)))
    lines = [ln for ln in fig.axes[0].lines if ln.get_label().startswith("ISO 6336-1 main resonance n_E1")]
    assert len(lines) == 1
    assert lines[0].get_xdata()[0] == pytest.approx(21352.9, abs=0.1)
    assert lines[0].get_label().endswith(": 21,353 rpm")


def test_x_label_is_words_and_unit_not_the_raw_key():
    fig = _figure(_sweep())
    assert fig.axes[1].get_xlabel() == "pinion speed [rpm]"


def test_a_gear_steady_point_writes_n_e1_with_its_unit(tmp_path):
    from rotaflex.gear.cases.steady import run_torsional

    cfg = tomllib.loads(EXAMPLE.read_text())
    cfg = {k: v for k, v in cfg.items() if k not in ("sweep", "domain", "verb")}  # one operating point
    cfg["steady"] = {**cfg["steady"], "fixed_cycles": 4, "eval_cycles": 2}
    res = run_torsional(cfg)
    res.save(tmp_path, figures=False)
    entry = json.loads((tmp_path / "summary.json").read_text())["iso_resonance_speed"]
    assert entry["unit"] == "rpm" and "n_E1" in entry["long_name"]
    assert entry["value"] == float(res.dataset["iso_resonance_speed"]) > 0
