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
