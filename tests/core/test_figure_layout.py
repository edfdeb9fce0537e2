"""The layout check :func:`rotaflex.core.plotting.layout_problems` on figures made bad on purpose.

Each bad figure is built so that the defect is certain from geometry alone (two texts at the
same data point, a legend centred on a dense curve, a label placed beyond the figure edge),
and its repaired twin must pass: the check fails on the defect, not on the figure.
"""

from __future__ import annotations

import numpy as np

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
