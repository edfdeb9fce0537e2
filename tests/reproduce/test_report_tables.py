"""report.md tables, captions, sections and solver messages (issue 37, "Figures and report").

A table row is read back the way GitHub-flavoured Markdown splits it (on every ``|`` not
preceded by a backslash, also inside backticks), so a row that breaks shows as a wrong cell
count; the cell texts must come back as written.
"""

import re

from rotaflex.core.report import Check, FigureEntry, Section, md_cell, render_html, render_markdown


def _cells(row: str) -> list[str]:
    """A GFM table row's cells, escapes undone (GFM: ``\\|`` is a literal pipe)."""
    parts = re.split(r"(?<!\\)\|", row.strip())
    assert parts[0] == "" and parts[-1] == "", row  # a row starts and ends with a pipe
    return [p.strip().replace("\\|", "|") for p in parts[1:-1]]


PIPES = Check("|x_max| / |x_ref| - 1", 1e-9, "", "|d| < 1e-6", True, "norm `|v|` of\ntwo lines")


def test_pipes_and_line_breaks_stay_inside_their_cell():
    md = render_markdown([Section("S", figures=[FigureEntry("F", "cap", "a.png", checks=[PIPES])])], "t")
    rows = [line for line in md.splitlines() if line.startswith("| ")]
    header = next(r for r in rows if r.startswith("| | check |"))
    row = next(r for r in rows if "x_max" in r)
    assert len(_cells(row)) == len(_cells(header)) == 6
    assert _cells(row)[1] == "|x_max| / |x_ref| - 1"
    assert _cells(row)[3] == "|d| < 1e-6"
    assert _cells(row)[5] == "norm `|v|` of two lines"  # the line break would end the row
    for r in rows:  # legend, glossary and check tables alike: as many cells as their header
        assert len(_cells(r)) in (2, 3, 6), r


def test_md_cell_escapes_every_pipe():
    assert md_cell("a|b||c") == "a\\|b\\|\\|c"
    assert _cells("| " + md_cell("a|b||c") + " |") == ["a|b||c"]


def _caption_lines(caption: str) -> list[str]:
    md = render_markdown([Section("S", figures=[FigureEntry("F", caption, "a.png")])], "t")
    return [line for line in md.splitlines() if line.startswith("> ")]


def test_caption_line_says_whose_caption_or_is_left_out():
    assert _caption_lines("Fig. 3 Kinetic energy") == ["> Paper's caption: Fig. 3 Kinetic energy"]
    for ours in ("(not in the papers) Campbell diagram", "(not in the paper; Campbell diagram)"):
        assert _caption_lines(ours) == ["> Added figure (not in the paper): Campbell diagram"]
    assert _caption_lines("(no figure in the paper: only derived there)") == [
        "> Added figure (not in the paper): only derived there"
    ]
    for none in ("", "(not in the papers)", "(not in the paper)"):  # nothing to say: no line
        assert _caption_lines(none) == []
        page = render_html([Section("S", figures=[FigureEntry("F", none, "a.png")])], "t")
        assert "caption" not in page and "not in the paper" not in page


def test_a_part_is_its_own_section_after_its_parent():
    fe = Section("FE rotor-bearing model", "FE intro", [FigureEntry("Campbell", "(not in the paper) c", "c.png")])
    fe.wall_time = 2.0
    rot = Section("Rotor rotation: Euler angles vs quaternions", "", [FigureEntry("Fig. 3", "cap", "a.png")])
    rot.wall_time, rot.parts = 5.0, [fe]
    md = render_markdown([rot], "t")
    heads = [line for line in md.splitlines() if line.startswith("## ") or line.startswith("### ")]
    i = heads.index("## Rotor rotation: Euler angles vs quaternions")
    assert heads[i + 1 : i + 4] == ["### Fig. 3", "## FE rotor-bearing model", "### Campbell"]
    assert "Wall time: 2.00 s." in md and "Wall time: 5.00 s." in md
    toc = md[md.index("## Contents") : md.index('<a id="legend">')]
    assert "\n- [FE rotor-bearing model](#fe-rotor-bearing-model)" in toc  # top level, not under rotation
    assert render_markdown(rot.flat(), "t") == md  # flattening twice changes nothing
    assert "<h2 id='fe-rotor-bearing-model'>" in render_html([rot], "t")


def test_solver_messages_are_folded_away_not_in_the_text():
    msg = "The solver successfully reached the end of the integration interval."
    f = FigureEntry("Run-up", "(not in the paper) run-up", "r.png", description="Linear run-up.", log=[msg])
    md = render_markdown([Section("S", figures=[f])], "t")
    details = re.findall(r"<details><summary>Solver log</summary>.*?</details>", md)
    assert len(details) == 1 and msg in details[0]
    assert md.count(msg) == 1  # only in the folded log
    page = render_html([Section("S", figures=[f])], "t")
    assert page.count(msg) == 1 and "<summary>Solver log</summary>" in page
