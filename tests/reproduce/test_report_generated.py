"""A real generated report (one domain, fast settings): its text has no undefined term and its
contents links resolve. Slow (about a minute on the 2-core machine): run with ``-m slow``."""

import re

import pytest

from rotaflex.core.report import undefined_terms
from rotaflex.reproduce import reproduce
from rotaflex.reproduce.guide import GLOSSARY


@pytest.mark.slow
@pytest.mark.parametrize("target", ["rotor", "floating"])
def test_generated_report_defines_every_term_and_links_resolve(tmp_path, target):
    reproduce([target], tmp_path, fast=True)
    md = (tmp_path / "report.md").read_text(encoding="utf-8")
    assert not undefined_terms(md, GLOSSARY)
    links = set(re.findall(r"\]\(#([^)]+)\)", md))
    assert links and links <= set(re.findall(r'<a id="([^"]+)"></a>', md))
    page = (tmp_path / "index.html").read_text(encoding="utf-8")
    assert set(re.findall(r"href='#([^']+)'", page)) <= set(re.findall(r"id='([^']+)'", page))
    # issue 37: every table row has its header's cell count (a "|" in a cell split rows), no
    # caption line that only says there is none, solver messages only in the folded logs
    header = 0
    for line in md.splitlines():
        if not line.startswith("|"):
            header = 0
            continue
        cells = len(re.split(r"(?<!\\)\|", line)) - 2
        header = header or cells
        assert cells == header, line
    assert "Paper's caption: (" not in md and "> Added figure (not in the paper)." not in md
    body = re.sub(r"<details>.*?</details>", "", md)
    assert "Solver log" not in body and not re.search(
        r"(?i)integration (successful|interval)|solver successfully", body
    )
    if target == "rotor":  # the FE rotor model is its own section, after the rotation paper's
        heads = re.findall(r"^## (.+)$", md, re.M)
        rotation = next(i for i, h in enumerate(heads) if h.startswith("Rotor rotation"))
        assert heads[rotation + 1].startswith("FE rotor-bearing model")
