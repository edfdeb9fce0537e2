"""The progress helper: one line per update in a log, routed through the reproduce reporter,
nothing when disabled."""

import io

from rotaflex.core.progress import Progress
from rotaflex.core.report import reporting


def test_log_gets_one_line_per_tenth_with_time_left():
    out = io.StringIO()
    p = Progress(200, "gear", "step", tty=False, interval=1e9, stream=out)
    for done in range(0, 201, 5):
        p.update(done)
    p.close()
    lines = out.getvalue().splitlines()
    assert len(lines) == 10  # 10 %, 20 %, ... 100 %: one line each, not one per update
    assert lines[0].startswith("gear: 10 % (20/200 step), ") and "elapsed" in lines[0]
    assert "about" in lines[3] and "left" in lines[3]  # an estimate while running
    assert lines[-1].startswith("gear: 100 % (200/200 step)") and "left" not in lines[-1]
    assert "\r" not in out.getvalue()  # no bar redraws


def test_interval_writes_lines_between_tenths_and_total_can_change():
    out = io.StringIO()
    p = Progress(1, "sweep", "case", tty=False, interval=0.0, stream=out)
    p.update(1, 1000)
    p.update(2)
    assert out.getvalue().splitlines() == p.lines and len(p.lines) == 2
    assert p.lines[1].startswith("sweep: 0 % (2/1000 case)")


def test_close_writes_the_last_state_once():
    out = io.StringIO()
    p = Progress(100, "x", tty=False, interval=1e9, stream=out)
    p.update(5)  # below 10 %: nothing yet
    assert out.getvalue() == ""
    p.close()
    assert out.getvalue().startswith("x: 5 % (5/100)")


def test_inside_reproduce_lines_go_to_the_reporter():
    got, out = [], io.StringIO()
    with reporting(got.append):
        p = Progress(10, "simulating", "s", tty=False, stream=out)
        p.update(10)
    assert out.getvalue() == "" and got and got[0].startswith("simulating: 100 %")


def test_disabled_shows_nothing():
    out = io.StringIO()
    p = Progress(10, "q", enabled=False, tty=False, stream=out)
    p.update(10)
    p.close()
    assert out.getvalue() == "" and p.lines == []
