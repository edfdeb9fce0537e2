"""The report explains itself: every acronym and subscripted symbol of its text has a glossary
entry, and the glossary finds terms as whole words only."""

import ast
from pathlib import Path

import pytest

from rotaflex.core.report import terms_used, undefined_terms, used_glossary
from rotaflex.reproduce.guide import GLOSSARY, SECTIONS, introduction

SRC = Path(__file__).resolve().parents[2] / "src" / "rotaflex" / "reproduce"


def _report_strings(path: Path):
    """String literals of a reproduce module that can reach the report: not docstrings, and
    with a space (a bare word like ``"q_body"`` is a dictionary key or an argument)."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    docs = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.FunctionDef, ast.ClassDef)) and node.body:
            first = node.body[0]
            if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant):
                docs.add(id(first.value))
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in docs:
            if " " in node.value:
                yield node.value


@pytest.mark.parametrize("module", sorted(p.name for p in SRC.glob("*.py")))
def test_every_term_of_the_report_texts_is_in_the_glossary(module):
    missing = {}
    for text in _report_strings(SRC / module):
        for term in undefined_terms(text, GLOSSARY):
            missing.setdefault(term, text[:70])
    assert not missing, f"add to rotaflex.reproduce.guide.GLOSSARY: {missing}"


def test_the_scan_finds_acronyms_and_symbols_but_not_code_or_words():
    text = "MAC > 0.9 and K*_123 vs K_v at n_E1; RK4 steps; `result.nc` and `speed_rpm`; Fig. 3 A"
    assert terms_used(text) == {"MAC", "K*_123", "K_v", "n_E1", "RK4"}
    assert undefined_terms("the ABC check and MAC", GLOSSARY) == {"ABC"}


def test_glossary_lists_only_terms_that_occur_as_words():
    used = used_glossary("SMALL SMOOTHING of the DTE (AF is 3)", GLOSSARY)
    assert "DTE" in used and "AF / SM" in used
    assert "MAC" not in used and "K_v" not in used
    assert "AF / SM" not in used_glossary("SMALL", GLOSSARY)


def test_introduction_has_one_paragraph_per_section_and_its_terms_are_defined():
    paras = introduction(list(SECTIONS))
    assert len(paras) == 1 + len(SECTIONS)
    assert not undefined_terms("\n".join(paras), GLOSSARY)
    for entry in GLOSSARY.values():  # the glossary's own words need no glossary
        assert not undefined_terms(entry, GLOSSARY), entry
