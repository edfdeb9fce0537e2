import json

import numpy as np
import pytest
import xarray as xr

from rotaflex.core.io import write_atomic
from rotaflex.core.report import Check, FigureEntry, Section, write_report
from rotaflex.core.result import Result, load_result


def test_atomic_write_keeps_old_file_on_failure(tmp_path):
    target = tmp_path / "result.nc"
    target.write_text("old")

    def failing(p):
        p.write_text("half")
        raise RuntimeError("crash while writing")

    with pytest.raises(RuntimeError):
        write_atomic(target, failing)
    assert target.read_text() == "old"
    assert list(tmp_path.iterdir()) == [target]


def test_result_round_trip_and_summary(tmp_path):
    t = np.linspace(0, 1, 11)
    ds = xr.Dataset(
        {"energy": ("time", t**2, {"units": "J"}), "peak": ((), 3.0, {"units": "N"})},
        coords={"time": ("time", t, {"units": "s"})},
        attrs={"status": "success", "wall_time": 0.5},
    )
    paths = Result(ds).save(tmp_path)
    assert {p.name for p in paths} >= {"result.nc", "summary.json", "energy.png"}
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["peak"] == {"value": 3.0, "unit": "N"}
    back = load_result(tmp_path / "result.nc")
    np.testing.assert_array_equal(back.dataset["energy"].values, t**2)
    assert back.dataset["energy"].attrs["units"] == "J"


def test_report_lists_failed_checks(tmp_path):
    section = Section(
        "Demo",
        figures=[FigureEntry("Fig. 1", "caption", "a.png", checks=[Check("c", 1.0, "J", "< 0.5", False)])],
        checks=[Check("d", 1e-12, "", "< 1e-9", True)],
    )
    write_report(tmp_path, [section], "t")
    md = (tmp_path / "report.md").read_text()
    assert "1 / 2" in md and "FAIL" in md and "1.000e-12" in md
    assert "caption" in (tmp_path / "index.html").read_text()


def test_information_rows_are_shown_but_not_counted_as_checks(tmp_path):
    # a wall time or a value beyond a method's range has no criterion: a row that cannot fail is
    # information, not a passing check
    info = Check("wall time", 0.9, "s", "none (information)", True, info=True)
    section = Section("Demo", checks=[Check("d", 1e-12, "", "< 1e-9", True), info])
    assert section.all_checks() == [section.checks[0]] and section.claims() == []
    write_report(tmp_path, [section], "t")
    md = (tmp_path / "report.md").read_text()
    assert "1 / 1" in md and "| wall time | 0.9 s | none (information) | info |" in md


def test_compile_timer_counts_outermost_numba_compilations_once():
    import numba

    from rotaflex.core.report import CompileTimer

    said = []

    @numba.njit(cache=False)
    def inner(x):
        return x + 1.0

    @numba.njit(cache=False)
    def outer(x):
        return inner(x) * 2.0

    with CompileTimer(said.append) as timer:
        assert outer(1.0) == 4.0  # compiles outer, and inner inside it
        assert outer(2.0) == 6.0  # no new compilation
    assert timer.count == 1 and timer.seconds > 0
    assert len(said) == 1 and "compiling numba kernels" in said[0]


def test_step_messages_reach_the_installed_reporter_only():
    from rotaflex.core.report import reporting, step

    got = []
    step("dropped: no reporter")
    with reporting(got.append):
        step("Fig. 3")
        with reporting(None):
            step("dropped: inner reporter is None")
    assert got == ["Fig. 3"]


def test_added_figures_are_not_labelled_as_paper_captions():
    from rotaflex.core.report import FigureEntry, Section, render_markdown

    sec = Section(
        "s", figures=[FigureEntry("A", "(not in the paper) extra run", "a.png"), FigureEntry("B", "Fig. 2", "b.png")]
    )
    md = render_markdown([sec], "t")
    assert "> Added figure (not in the paper): extra run" in md and "> Paper's caption: Fig. 2" in md
    assert "Paper's caption: (not in the paper" not in md
