"""Figures a reader can read: :func:`rotaflex.core.plotting.layout_problems` (overlapping
texts, texts outside the figure, a unit hidden in a scale offset, legends over data), measured
from the rendered artists.

First the check itself, on figures made bad on purpose: each defect is certain from geometry
alone (two texts at the same data point, a legend centred on a dense curve, a label beyond the
figure edge) and its repaired twin must pass, so the check fails on the defect, not on the
figure. Then every figure the commands draw (issue 37), on small runs of the shipped examples
(rotor and system verbs) or on sweep datasets shaped as `rotaflex sweep` writes them.
"""

from __future__ import annotations

import functools
import importlib
import tomllib
from pathlib import Path

import numpy as np
import pytest

from rotaflex.core.plotting import layout_problems, legend_outside, new_figure


def test_a_clean_figure_has_no_problems():
    fig, ax = new_figure()
    x = np.linspace(0.0, 1.0, 50)
    ax.plot(x, x**2, label="x²")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m²]")
    ax.set_title("clean")
    legend_outside(ax)
    assert layout_problems(fig) == []


def test_two_annotations_at_one_point_are_caught():
    fig, ax = new_figure()
    ax.plot([0, 1], [0, 1])
    ax.annotate("1X crossing", (0.5, 0.5))
    ax.annotate("2X crossing", (0.5, 0.5))
    problems = layout_problems(fig)
    assert any("'1X crossing' overlaps" in p and "'2X crossing'" in p for p in problems), problems


def test_crowded_tick_labels_are_caught_and_thinned_ones_pass():
    fig, ax = new_figure(figsize=(3.0, 2.0))
    ax.plot([0, 1000000], [0, 1])
    ax.set_xticks(np.linspace(0, 1000000, 21))  # 21 seven-digit labels on a 3-inch axis
    assert any("tick label" in p and "overlaps" in p for p in layout_problems(fig))
    ax.set_xticks(np.linspace(0, 1000000, 3))
    assert layout_problems(fig) == []


def test_a_text_outside_the_figure_is_caught():
    fig, ax = new_figure()
    ax.plot([0, 1], [0, 1])
    ax.annotate("1X", (1.3, 0.5), xycoords="axes fraction", annotation_clip=False)
    problems = layout_problems(fig)
    assert any("'1X' reaches outside the figure" in p for p in problems), problems


def test_a_legend_over_the_curve_is_caught_also_between_sparse_vertices():
    fig, ax = new_figure()
    ax.plot([0.0, 1.0], [0.5, 0.5], label="flat line")  # two vertices, none under the legend
    ax.legend(loc="center")
    problems = layout_problems(fig)
    assert any("covers" in p and "data points of axes 0" in p for p in problems), problems
    ax.get_legend().remove()
    legend_outside(ax)
    assert layout_problems(fig) == []


def test_a_legend_over_a_twin_axes_scatter_is_caught():
    fig, ax = new_figure()
    ax.plot([0, 1], [0, 0.1], label="low line")
    twin = ax.twinx()
    twin.scatter([0.05, 0.1, 1.0], [0.95, 0.95, 0.0])  # two at the top left, where the legend goes
    ax.legend(loc="upper left")
    problems = layout_problems(fig)
    assert any("covers 2 data points of axes 1" in p for p in problems), problems


def test_an_axis_with_a_unit_and_a_scale_offset_is_caught():
    fig, ax = new_figure()
    ax.plot([0, 1, 2], [7.2e-6, 8.1e-6, 7.9e-6])
    ax.set_ylabel("DTE [m]")
    assert any("scaled by" in p and "DTE [m]" in p for p in layout_problems(fig))
    ax.set_ylabel("relative change [-]")  # a pure number may keep its multiplier
    assert layout_problems(fig) == []


# -- every figure the commands make, on small runs of the shipped examples ---------------------

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _assert_readable(figs: dict, where: str) -> None:
    assert figs, where  # a command that draws nothing would pass vacuously
    problems = [f"{where} {name}: {p}" for name, fig in figs.items() for p in layout_problems(fig)]
    assert not problems, "\n".join(problems)


def _config(rel: str, **tables) -> dict:
    cfg = tomllib.loads((EXAMPLES / rel).read_text())
    cfg.pop("domain", None)  # the CLI's: it picks the runner
    for table, overrides in tables.items():
        cfg[table] = {**cfg[table], **overrides}
    return cfg


#: (command, example, table overrides): small runs, each about 1-3 s of CPU with its figures
RUNS = {
    "rotor campbell": (
        "rotor/fe_friswell_5_9_1.toml",
        {"campbell": {"n_speeds": 16, "operating_range_rpm": [2500, 3500]}},
    ),
    "rotor unbalance": ("rotor/fe_friswell_5_9_1.toml", {"unbalance": {"n_speeds": 80}}),
    "rotor modal": ("rotor/fe_friswell_5_9_1.toml", {}),
    "system campbell": ("system/gearbox.toml", {"campbell": {"n_speeds": 8}}),
    "system response": ("system/gearbox.toml", {"response": {"n_speeds": 40}}),
    "system unbalance": ("system/motor_coupling_pump.toml", {"unbalance": {"n_speeds": 120}}),
    "system frf": ("system/turbine_gearbox_generator.toml", {"frf": {"n_frequencies": 400}}),
    "gear steady": (  # the in-process speed sweep across n_E1 and the 1x resonance: speed_sweep.png
        "gear/steady/torsional_dynamic_factor.toml",
        {"sweep": {"speeds_rpm": [8000.0, 12000.0, 13000.0, 16000.0, 20000.0]}, "steady": {"eval_cycles": 4}},
    ),
}


def _run(command: str, example: str, overrides: dict) -> dict:
    """The figures ``rotaflex <command> <example>`` writes (the verb's runner, in process)."""
    from rotaflex.core.domains import COMMANDS

    domain, verb = command.split()
    module, name = COMMANDS[domain][verb].split(":")
    return getattr(importlib.import_module(module), name)(_config(example, **overrides)).plot()


@functools.cache
def _figures(command: str) -> dict:
    """The figures of one of :data:`RUNS`, run once for every test that reads them."""
    return _run(command, *RUNS[command])


@pytest.mark.parametrize("command", list(RUNS))
def test_command_figures_are_readable(command):
    _assert_readable(_figures(command), command)


@pytest.mark.slow
@pytest.mark.parametrize("command", ["rotor campbell", "rotor unbalance", "rotor modal"])
def test_fluid_film_rotor_figures_are_readable(command):
    """The same on the fluid-film example (bearing coefficient figure, an unstable mode, the
    operating range in the log-dec panel): about 4 s of CPU each."""
    overrides = {"campbell": {"n_speeds": 16}, "unbalance": {"n_speeds": 80}}
    _assert_readable(_run(command, "rotor/fe_fluid_film.toml", overrides), command)


def test_system_figures_speak_an_engineers_words():
    # gearbox.toml: one 20/40 mesh, rotors "input" and "output", bearings at nodes 1 and 9 of
    # each: no dataset keys such as "mesh0 x2", "input:1", "h = 1" on the figures
    campbell = _figures("system campbell")["campbell"]
    tags = {t.get_text() for t in campbell.axes[0].texts}
    assert tags == {"1× mesh frequency", "2× mesh frequency", "3× mesh frequency", "1X input", "1X output"}
    response = _figures("system response")["response"]
    legends = [t.get_text() for ax in response.axes if ax.get_legend() for t in ax.get_legend().get_texts()]
    assert {"1× mesh frequency", "input, node 1", "output, node 9"} <= set(legends)
    labels = " ".join(ax.get_ylabel() for ax in response.axes)
    assert not any(raw in labels + " ".join(legends) for raw in (":", "h =", "sum of h"))
    assert "0-pk" in labels


def _speed_sweep(verb: str):
    """A combined sweep over the pinion speed with a second swept key (two variants), as
    `rotaflex sweep` writes it: two lines per panel and a legend to place."""
    import xarray as xr

    speeds = np.linspace(4000.0, 20000.0, 9)
    kv = 1.0 + 0.6 * np.exp(-(((speeds - 12000.0) / 3000.0) ** 2))
    shape = (speeds.size, 2)
    dims = ("operation_speed_rpm", "model_relief")
    ds = xr.Dataset(
        {
            "dynamic_factor": (dims, np.stack([kv, 0.9 * kv], 1), {"units": "1"}),
            "dte_pp": (dims, np.stack([8e-6 * kv, 7e-6 * kv], 1), {"units": "m"}),
            "status": (dims, np.full(shape, "success")),
            "mesh_natural_frequency": (dims, np.full(shape, 4000.0), {"units": "Hz"}),
            "resonance_speed": (dims, np.full(shape, 4000.0 * 60 / 28), {"units": "rpm"}),
            "iso_resonance_speed": (dims, np.full(shape, 9000.0), {"units": "rpm"}),
        },
        coords={
            "operation_speed_rpm": (
                "operation_speed_rpm",
                speeds,
                {"units": "rpm", "config_key": "operation.speed_rpm"},
            ),
            "model_relief": ("model_relief", [True, False], {"config_key": "model.relief"}),
        },
    )
    ds.attrs["verb"] = verb
    return ds


def test_gear_speed_sweep_and_steady_sweep_figures():
    from rotaflex.sweep.figures import sweep_figures

    for verb in ("simulate", "steady"):
        _assert_readable(sweep_figures(_speed_sweep(verb), "gear"), f"gear {verb} sweep")


def test_system_sweep_summary_figures():
    """The summary pages of a `system steady` sweep over the drive speed (the scalars a case
    writes, with their long names as `rotaflex sweep` combines them)."""
    import xarray as xr

    from rotaflex.sweep.figures import sweep_figures

    rpm = np.linspace(1000.0, 6000.0, 6)
    rng = np.random.default_rng(1)
    dim = "steady_speed_rpm"
    values = {
        "speed": (rpm * np.pi / 30, "rad/s", ""),
        "speed_rpm": (rpm, "rpm", ""),
        "mesh_frequency": (rpm / 3, "Hz", ""),
        "dynamic_factor": (1.5 + rng.random(6), "1", "max mesh force / static"),
        "force_max": (5000 + 3000 * rng.random(6), "N", "largest mesh force (static + dynamic)"),
        "force_min": (
            [1481.0, 1034.0, -20.1, 2110.0, 2093.0, 1157.0],
            "N",
            "smallest mesh force (static + dynamic); below 0: the mesh damper pulls as the teeth separate "
            "(contact lost where contact_loss_fraction > 0) or back-flank contact",
        ),
        "dte_pp": (1e-5 * (1 + rng.random(6)), "m", ""),
        "contact_loss_fraction": ([0, 0, 0.0039, 0, 0, 0], "1", "fraction of the evaluated samples out of contact"),
        "cycles": (np.arange(6) * 50.0 + 90, "", ""),
        "wall_time": (rng.random(6), "s", ""),
    }
    ds = xr.Dataset(
        {
            n: (dim, np.asarray(v, float), {"units": u, **({"description": d} if d else {})})
            for n, (v, u, d) in values.items()
        },
        coords={dim: (dim, rpm, {"units": "rpm", "config_key": "steady.speed_rpm"})},
    )
    figs = sweep_figures(ds, "system")
    _assert_readable(figs, "system sweep")
    ylabels = [ax.get_ylabel() for fig in figs.values() for ax in fig.axes if ax.get_visible()]
    assert not any("speed" in y or "frequency" in y for y in ylabels)  # no speed against speed
    titles = [ax.get_title() for ax in figs["summary_vs_speed_rpm"].axes]
    assert any(t.startswith("smallest mesh force") and "damper pulls" in t.replace("\n", " ") for t in titles)


def test_floating_slew_figure():
    """Two solutions that differ by 1 % of a 1 mm vibration: the difference panel shows it."""
    from rotaflex.floating.figures import full_vs_perturbation_figure

    t = np.linspace(0.0, 10.0, 1001)
    angles = np.stack([np.sin(t), 0.5 * np.cos(t), 0.1 * t], 1)
    u = 1e-3 * np.stack([np.sin(40 * t), 0.2 * np.sin(31 * t), 0.1 * np.cos(25 * t)], 1)
    fig = full_vs_perturbation_figure(t, angles, u, t, angles, 1.01 * u)
    _assert_readable({"slew_3d": fig}, "floating")
    diff = np.concatenate([line.get_ydata() for line in fig.axes[2].get_lines()])
    assert np.max(np.abs(diff)) == pytest.approx(0.01 * 1e3, rel=1e-3)  # 1 % of 1 mm, in um
