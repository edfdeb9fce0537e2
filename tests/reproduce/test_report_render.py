"""report.md and index.html: introduction, contents whose links resolve, legend, glossary, and
claims that do not hold marked in words and colour apart from passes."""

import re

import pytest

from rotaflex.core.report import OUTCOMES, Check, FigureEntry, Section, write_report
from rotaflex.reproduce.guide import GLOSSARY, introduction


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    out = tmp_path_factory.mktemp("rep")
    holds = Check("K*_123 != K_123", 0.01, "", "> 0", True, claim=True)
    fails = Check("claim X: the MAC stays above 0.9", 0.5, "", "> 0.9", False, "it drops", claim=True)
    ok = Check("energy drift", 1e-9, "", "< 1e-6", True)
    bad = Check("DTE at 1000 rpm", 3.0, "um", "< 1", False)
    info = Check("wall time", 1.2, "s", "none (information)", True, info=True)
    sections = [
        Section(
            "Rotor rotation: Euler (Yun & Ren 2008)",
            "intro",
            [FigureEntry("Fig. 3", "cap", "a.png", checks=[holds, fails])],
        ),
        Section("Spur gears", "", [FigureEntry("Fig. 8", "cap", "b.png", checks=[ok, bad])], checks=[info]),
    ]
    write_report(out, sections, "t", intro=introduction(["rotor", "gear"]), glossary=GLOSSARY)
    return (out / "report.md").read_text(), (out / "index.html").read_text()


def test_markdown_contents_links_resolve(report):
    md, _ = report
    links = re.findall(r"\]\(#([^)]+)\)", md)
    ids = set(re.findall(r'<a id="([^"]+)"></a>', md))
    assert {"introduction", "legend", "glossary"} <= set(links)
    assert len(links) == 3 + 2 + 2  # intro, legend, glossary; two sections; two figures
    assert set(links) <= ids, set(links) - ids


def test_html_contents_links_resolve(report):
    _, page = report
    nav = page[page.index("<nav>") : page.index("</nav>")]
    links = re.findall(r"href='#([^']+)'", nav)
    ids = set(re.findall(r"id='([^']+)'", page))
    assert len(links) == 7 and set(links) <= ids, set(links) - ids


def test_claims_that_do_not_hold_are_marked_apart_from_passes(report):
    md, page = report
    row = next(line for line in md.splitlines() if "claim X" in line)
    assert "**claim does not hold**" in row and OUTCOMES["claim does not hold"][0] in row
    assert OUTCOMES["claim does not hold"][0] != OUTCOMES["pass"][0]
    tr = re.search(r"<tr class='(\w+)'><td>claim X", page).group(1)
    assert tr == "nothold" and tr != re.search(r"<tr class='(\w+)'><td>energy drift", page).group(1)
    style = page[page.index("<style>") : page.index("</style>")]
    assert "tr.nothold td{background:" in style  # its own colour, not the pass style
    assert re.search(r"<tr class='fail'><td>DTE at 1000 rpm", page)


def test_legend_explains_every_outcome_in_both_files(report):
    md, page = report
    for outcome, (mark, cls, why) in OUTCOMES.items():
        assert f"| {mark} | {outcome} | {why} |" in md
        assert f"<tr class='{cls}'><td>example</td><td></td><td></td><td>{outcome}</td>" in page
    assert "1 hold, 1 do not hold" in md


def test_introduction_and_glossary_of_the_terms_used(report):
    md, page = report
    assert md.index("## Introduction") < md.index("## Rotor rotation") < md.index("## Glossary")
    glossary = md[md.index("## Glossary") :]
    for term in ("K_123 / K_313 / K_q", "K*_123 / K*_q", "MAC", "DTE", "Fig. / eq."):
        assert f"| {term} |" in glossary and f"<dt>{term}</dt>" in page
    assert "| HHT / HHT-alpha |" not in glossary  # not used in this report


def test_repeated_figure_labels_get_distinct_anchors(tmp_path):
    sec = Section("Sweeps", figures=[FigureEntry("gear", "c", "a.png"), FigureEntry("gear", "c", "b.png")])
    write_report(tmp_path, [sec], "t")
    md = (tmp_path / "report.md").read_text()
    ids = re.findall(r'<a id="([^"]+)"></a>', md)
    assert len(ids) == len(set(ids)) and "sweeps-gear-1" in ids and "sweeps-gear-2" in ids
