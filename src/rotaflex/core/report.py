"""The reproduction report: figures beside the paper's captions, checks with measured numbers.

Each domain's ``reproduce`` module returns a :class:`Section`; :func:`write_report` renders all
sections to ``report.md`` and a self-contained ``index.html`` (figures linked, not embedded), and
the checks to ``checks.json``.
"""

from __future__ import annotations

import html
import logging
import math
import re
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import asdict, dataclass, field
from pathlib import Path

from rotaflex.core.io import write_json_atomic, write_text_atomic
from rotaflex.core.jit import CompileTimer  # noqa: F401 - its home is core.jit; imported from here too


@dataclass
class Check:
    """One numerical check.

    Parameters
    ----------
    name : str
        What is checked, e.g. ``"K_q* = K_q (max relative difference)"``.
    measured : float
        Measured value.
    unit : str
        Unit of ``measured`` (``""`` for ratios).
    criterion : str
        The pass criterion in words/numbers, e.g. ``"< 1e-12"``.
    passed : bool
        Whether the criterion holds. A claim of the paper that does not hold is still reported,
        with ``passed=False`` and the outcome in ``note``.
    note : str
        Interpretation in one or two sentences.
    claim : bool
        A claim of the paper: reported as holding or not, not counted as a check.
    info : bool
        A measured number shown for information (a wall time, a value beyond the method's
        range): no criterion, so not counted as a check (a check that cannot fail is none).
    """

    name: str
    measured: float
    unit: str
    criterion: str
    passed: bool
    note: str = ""
    claim: bool = False  # a claim of the paper: reported as holds / does not hold, not as pass/fail
    info: bool = False  # information only: neither pass/fail nor a claim

    @property
    def outcome(self) -> str:
        if self.info:
            return "info"
        if self.claim:
            return "claim holds" if self.passed else "claim does not hold"
        return "pass" if self.passed else "FAIL"

    def value_text(self) -> str:
        v = self.measured
        if isinstance(v, float) and (math.isnan(v) or abs(v) >= 1e4 or 0 < abs(v) < 1e-3):
            text = f"{v:.3e}"
        elif isinstance(v, float):
            text = f"{v:.6g}"
        else:
            text = str(v)
        return f"{text} {self.unit}".strip()


@dataclass
class FigureEntry:
    """A reproduced figure: the paper's label and caption, our PNG and data, its checks."""

    label: str
    caption: str
    image: str  # path relative to the report directory
    data: str = ""  # NetCDF behind the figure, relative path
    description: str = ""
    checks: list[Check] = field(default_factory=list)
    #: the solvers' own status messages behind the figure: folded away under "Solver log", never
    #: in the text a reader signs off (they are written for debugging, not for a report)
    log: list[str] = field(default_factory=list)


@dataclass
class Section:
    """One domain's part of the report.

    ``parts`` are further sections the same reproduce module computed (e.g. the FE rotor model
    beside the rotor-rotation paper): the report shows each under its own heading, right after
    this one, with its own wall time (not included in this one's).
    """

    title: str
    intro: str = ""
    figures: list[FigureEntry] = field(default_factory=list)
    checks: list[Check] = field(default_factory=list)  # checks not tied to one figure
    notes: list[str] = field(default_factory=list)
    wall_time: float = float("nan")
    compile_time: float = 0.0  # numba kernel compilation inside the section [s], not in wall_time
    provenance: dict = field(default_factory=dict)
    parts: list[Section] = field(default_factory=list)

    def flat(self) -> list[Section]:
        """This section followed by its parts, the report's order (each without parts, so that
        flattening twice changes nothing)."""
        from dataclasses import replace

        return [replace(self, parts=[])] + [q for p in self.parts for q in p.flat()]

    def all_checks(self) -> list[Check]:
        """Verification checks (pass/fail), excluding the paper's claims and information rows."""
        return [c for c in self._every() if not (c.claim or c.info)]

    def claims(self) -> list[Check]:
        return [c for c in self._every() if c.claim and not c.info]

    def _every(self) -> list[Check]:
        return self.checks + [c for f in self.figures for c in f.checks]


#: how each outcome is shown: (marker in report.md, CSS class in index.html, meaning for the legend)
OUTCOMES: dict[str, tuple[str, str, str]] = {
    "pass": ("\U0001f7e2", "pass", "our check passed: the measured value meets the criterion"),
    "FAIL": ("\U0001f534", "fail", "our check failed: the measured value misses the criterion (a defect to fix)"),
    "claim holds": ("\U0001f7e2", "holds", "a statement of the paper that our measurement confirms"),
    "claim does not hold": (
        "\U0001f7e0",
        "nothold",
        "a statement of the paper that our measurement contradicts (the note says why); reported, "
        "not counted as a failed check",
    ),
    "info": ("\u26aa", "info", "a measured number shown for information (no criterion)"),
}


def md_cell(text: object) -> str:
    """``text`` as one cell of a Markdown table: ``|`` escaped (an unescaped one starts a new
    cell, also inside backticks), line breaks as spaces (one ends the row)."""
    return " ".join(str(text).replace("|", "\\|").split())


def md_row(*cells: object) -> str:
    """One Markdown table row of :func:`md_cell` cells."""
    return "| " + " | ".join(md_cell(c) for c in cells) + " |"


def _md_checks(checks: list[Check]) -> list[str]:
    if not checks:
        return []
    rows = ["| | check | measured | criterion | result | note |", "|---|---|---|---|---|---|"]
    for c in checks:
        mark = OUTCOMES[c.outcome][0]
        result = f"**{c.outcome}**" if c.outcome in ("FAIL", "claim does not hold") else c.outcome
        rows.append(md_row(mark, c.name, c.value_text(), c.criterion, result, c.note))
    return rows + [""]


def _md_log(log: list[str]) -> list[str]:
    """Solver messages folded away (``<details>``: GitHub and most Markdown viewers fold it)."""
    if not log:
        return []
    items = "".join(f"<li>{html.escape(m)}</li>" for m in log)
    return [f"<details><summary>Solver log</summary><ul>{items}</ul></details>", ""]


def _time_text(s: Section) -> str:
    text = f"{s.wall_time:.2f} s"
    if s.compile_time >= 0.05:
        text += f" (plus {s.compile_time:.1f} s compiling numba kernels, first run only)"
    return text


#: how a reproduce module marks a figure the paper does not have: ``(not in the paper) text``,
#: ``(not in the papers; text)``, ``(no figure in the paper: text)``
_ADDED = re.compile(
    r"^\((?:not in the papers?|no figure in the papers?)\s*(?:[;:,]\s*(?P<inner>[^)]*))?\)\s*(?P<rest>.*)$", re.S
)


def _caption(caption: str) -> str | None:
    """The caption line: ``Paper's caption: ...``, ``Added figure (not in the paper): ...`` for
    one the paper does not have, or None when there is no caption to show (no line at all)."""
    c = caption.strip()
    m = _ADDED.match(c)
    if m is None:
        return f"Paper's caption: {c}" if c else None
    text = "; ".join(t.strip() for t in (m["inner"] or "", m["rest"]) if t.strip())
    return f"Added figure (not in the paper): {text}" if text else None


def anchor(*parts: str) -> str:
    """An HTML id from words: lower case, runs of other characters as one hyphen."""
    return "-".join(re.sub(r"[^a-z0-9]+", "-", p.lower()).strip("-") for p in parts if p)


def _figure_id(s: Section, f: FigureEntry) -> str:
    """The figure's anchor: section and label, numbered when a label repeats in a section."""
    base = anchor(s.title[:24], f.label)
    same = [g for g in s.figures if anchor(s.title[:24], g.label) == base]
    return base if len(same) == 1 else f"{base}-{next(i for i, g in enumerate(same, 1) if g is f)}"


def _toc(sections: list[Section], has_intro: bool, has_glossary: bool) -> list[tuple[int, str, str]]:
    """``(level, text, id)`` of every entry of the table of contents."""
    out: list[tuple[int, str, str]] = []
    if has_intro:
        out.append((0, "Introduction", "introduction"))
    out.append((0, "How to read the check tables", "legend"))
    for s in sections:
        out.append((0, s.title, anchor(s.title)))
        out += [(1, f.label, _figure_id(s, f)) for f in s.figures]
    if has_glossary:
        out.append((0, "Glossary of symbols and acronyms", "glossary"))
    return out


def _summary(sections: list[Section]) -> str:
    n_all = sum(len(s.all_checks()) for s in sections)
    n_ok = sum(c.passed for s in sections for c in s.all_checks())
    claims = [c for s in sections for c in s.claims()]
    held = sum(c.passed for c in claims)
    return (
        f"Checks passed: **{n_ok} / {n_all}**. Paper claims examined: {len(claims)} "
        f"({held} hold, {len(claims) - held} do not hold)."
    )


#: acronyms (two or more capitals/digits, e.g. ``MAC``, ``RK4``) and one-letter symbols with a
#: subscript (``K_v``, ``K*_123``, ``n_E1``) in report text; code in backticks is not scanned
_TERM = re.compile(r"(?<![\w.*/-])(?:[A-Z][A-Z0-9]*[A-Z][A-Z0-9]*|[A-Za-z]\*?_[A-Za-z0-9]+)(?![\w*])")


def terms_used(text: str) -> set[str]:
    """Acronyms and subscripted symbols in ``text`` (outside backtick code spans and links)."""
    text = re.sub(r"`[^`]*`", " ", text)
    text = re.sub(r"\]\([^)]*\)", "]", text)  # link targets are file names
    return set(_TERM.findall(text))


def undefined_terms(text: str, glossary: dict[str, str]) -> set[str]:
    """Terms of :func:`terms_used` that no glossary entry names (an entry may list several
    spellings separated by ``" / "``, e.g. ``"AF / SM"``)."""
    known = {t.strip() for key in glossary for t in key.split(" / ")} | set(OUTCOMES)  # FAIL: the legend
    return {t for t in terms_used(text) if t not in known}


def used_glossary(text: str, glossary: dict[str, str]) -> dict[str, str]:
    """The glossary entries of which a spelling occurs in ``text`` as a whole word (so ``SM``
    is not found in ``SMALL``), in the glossary's order."""
    text = re.sub(r"`[^`]*`", " ", text)

    def occurs(term: str) -> bool:
        return re.search(rf"(?<![\w*]){re.escape(term.strip())}(?![\w*])", text) is not None

    return {k: v for k, v in glossary.items() if any(occurs(t) for t in k.split(" / "))}


def render_markdown(
    sections: list[Section], title: str, intro: list[str] | None = None, glossary: dict[str, str] | None = None
) -> str:
    """``report.md``: summary, legend, table of contents, introduction, sections, glossary.

    Parameters
    ----------
    intro : list of str, optional
        Paragraphs of the introduction (what each section shows and why it matters).
    glossary : dict, optional
        Term -> meaning; only the terms that occur in the report are listed.
    """
    sections = [q for s in sections for q in s.flat()]
    lines = [f"# {title}", "", _summary(sections), ""]
    body: list[str] = []
    if intro:
        body += ['<a id="introduction"></a>', "", "## Introduction", ""]
        for p in intro:
            body += [p, ""]
    body += ['<a id="legend"></a>', "", "## How to read the check tables", ""]
    body += ["| mark | result | meaning |", "|---|---|---|"]
    body += [md_row(m, k, why) for k, (m, _c, why) in OUTCOMES.items()]
    body += [""]
    for s in sections:
        body += [f'<a id="{anchor(s.title)}"></a>', "", f"## {s.title}", ""]
        if not math.isnan(s.wall_time):
            body += [f"Wall time: {_time_text(s)}.", ""]
        if s.intro:
            body += [s.intro, ""]
        body += _md_checks(s.checks)
        for f in s.figures:
            body += [f'<a id="{_figure_id(s, f)}"></a>', "", f"### {f.label}", ""]
            cap = _caption(f.caption)
            body += [f"> {cap}", ""] if cap else []
            body += [f"![{f.label}]({f.image})", ""]
            if f.description:
                body += [f.description, ""]
            if f.data:
                body += [f"Data: [`{f.data}`]({f.data})", ""]
            body += _md_checks(f.checks)
            body += _md_log(f.log)
        if s.notes:
            body += ["### Notes", ""] + [f"- {n}" for n in s.notes] + [""]
    terms = used_glossary("\n".join(lines + body), glossary or {})
    if terms:
        body += ['<a id="glossary"></a>', "", "## Glossary of symbols and acronyms", ""]
        body += ["| term | meaning |", "|---|---|"] + [md_row(k, v) for k, v in terms.items()] + [""]
    toc = ["## Contents", ""] + [
        f"{'  ' * level}- [{text}](#{ident})" for level, text, ident in _toc(sections, bool(intro), bool(terms))
    ]
    return "\n".join(lines + toc + [""] + body)


def _html_checks(checks: list[Check]) -> str:
    if not checks:
        return ""
    e = html.escape
    rows = "".join(
        f"<tr class='{OUTCOMES[c.outcome][1]}'><td>{e(c.name)}</td>"
        f"<td>{e(c.value_text())}</td><td>{e(c.criterion)}</td><td>{c.outcome}</td><td>{e(c.note)}</td></tr>"
        for c in checks
    )
    return (
        f"<table><tr><th>check</th><th>measured</th><th>criterion</th><th>result</th><th>note</th></tr>{rows}</table>"
    )


#: row colours of index.html: green pass/holds, red FAIL, amber "does not hold", grey info
_STYLE = (
    "body{font-family:sans-serif;max-width:1200px;margin:auto;padding:1em}"
    "img{max-width:640px;width:100%}.row{display:flex;gap:1em;align-items:flex-start}"
    ".cap{flex:1}table{border-collapse:collapse;margin:.5em 0}td,th{border:1px solid #ccc;"
    "padding:3px 6px;font-size:90%}"
    "tr.pass td:nth-child(4),tr.holds td:nth-child(4){color:#070}"
    "tr.fail td{background:#fdd}tr.fail td:nth-child(4){color:#b00;font-weight:bold}"
    "tr.nothold td{background:#ffe8cc}tr.nothold td:nth-child(4){color:#a50;font-weight:bold}"
    "tr.info td:nth-child(4){color:#666}nav li{margin:.1em 0}dt{font-weight:bold}"
)


def render_html(
    sections: list[Section], title: str, intro: list[str] | None = None, glossary: dict[str, str] | None = None
) -> str:
    """``index.html``: the same content as :func:`render_markdown`, one self-contained page."""
    e = html.escape
    sections = [q for s in sections for q in s.flat()]
    body = [f"<h1>{e(title)}</h1><p>{_summary(sections).replace('**', '')}</p>"]
    parts: list[str] = []
    text_parts: list[str] = [title]  # the text a reader sees, for the glossary
    if intro:
        parts.append("<h2 id='introduction'>Introduction</h2>" + "".join(f"<p>{e(p)}</p>" for p in intro))
        text_parts += intro
    legend = "".join(
        f"<tr class='{cls}'><td>example</td><td></td><td></td><td>{k}</td><td>{e(why)}</td></tr>"
        for k, (_m, cls, why) in OUTCOMES.items()
    )
    parts.append(
        "<h2 id='legend'>How to read the check tables</h2><p>Each row is one numerical check or one "
        "claim of the paper; its colour and the result column say which:</p><table><tr><th>check</th>"
        f"<th>measured</th><th>criterion</th><th>result</th><th>meaning</th></tr>{legend}</table>"
    )
    for s in sections:
        parts.append(f"<h2 id='{anchor(s.title)}'>{e(s.title)}</h2>")
        if not math.isnan(s.wall_time):
            parts.append(f"<p>Wall time: {e(_time_text(s))}.</p>")
        if s.intro:
            parts.append("".join(f"<p>{e(p)}</p>" for p in s.intro.split("\n\n")))
        parts.append(_html_checks(s.checks))
        for f in s.figures:
            data = f"<p>Data: <a href='{e(f.data)}'>{e(f.data)}</a></p>" if f.data else ""
            cap = _caption(f.caption)
            cap = f"<p><i>{e(cap)}</i></p>" if cap else ""
            log = "".join(f"<li>{e(m)}</li>" for m in f.log)
            log = f"<details><summary>Solver log</summary><ul>{log}</ul></details>" if log else ""
            parts.append(
                f"<div class='fig'><h3 id='{_figure_id(s, f)}'>{e(f.label)}</h3><div class='row'>"
                f"<img src='{e(f.image)}' alt='{e(f.label)}'>"
                f"<div class='cap'>{cap}"
                f"<p>{e(f.description)}</p>{data}</div></div>{_html_checks(f.checks)}{log}</div>"
            )
            text_parts += [f.label, f.caption, f.description]
            text_parts += [f"{c.name} {c.criterion} {c.note} {c.unit}" for c in f.checks]
        if s.notes:
            parts.append("<h3>Notes</h3><ul>" + "".join(f"<li>{e(n)}</li>" for n in s.notes) + "</ul>")
        text_parts += [s.title, s.intro, *s.notes]
        text_parts += [f"{c.name} {c.criterion} {c.note} {c.unit}" for c in s.checks]
    terms = used_glossary("\n".join(text_parts), glossary or {})
    if terms:
        parts.append(
            "<h2 id='glossary'>Glossary of symbols and acronyms</h2><dl>"
            + "".join(f"<dt>{e(k)}</dt><dd>{e(v)}</dd>" for k, v in terms.items())
            + "</dl>"
        )
    toc = "".join(
        f"<li style='margin-left:{1.5 * level}em'><a href='#{ident}'>{e(text)}</a></li>"
        for level, text, ident in _toc(sections, bool(intro), bool(terms))
    )
    body.append(f"<nav><h2>Contents</h2><ul>{toc}</ul></nav>")
    return (
        f"<!doctype html><html><head><meta charset='utf-8'><title>{e(title)}</title>"
        f"<style>{_STYLE}</style></head><body>{''.join(body + parts)}</body></html>\n"
    )


def write_report(
    out_dir: str | Path,
    sections: list[Section],
    title: str,
    provenance: dict | None = None,
    *,
    intro: list[str] | None = None,
    glossary: dict[str, str] | None = None,
) -> list[Path]:
    """Write ``report.md``, ``index.html``, ``checks.json`` and ``provenance.json`` into ``out_dir``.

    Figure paths ending in ``.png`` follow the format chosen with
    :func:`rotaflex.core.plotting.configure` (``--format``). ``intro`` (paragraphs) and
    ``glossary`` (term -> meaning) are rendered as in :func:`render_markdown`.
    """
    from rotaflex.core.provenance import provenance as _prov

    out_dir = Path(out_dir)
    sections = [q for s in sections for q in s.flat()]
    prov = {**_prov(), **(provenance or {})}
    fmt = _figure_format()
    if fmt != "png":
        for s in sections:
            for f in s.figures:
                if f.image.endswith(".png"):
                    f.image = f.image[:-4] + "." + fmt
    stamp = f"rotaflex {prov['rotaflex_version']}" + (f", commit {prov['git_commit']}" if prov["git_commit"] else "")
    stamp += f", {prov['created_utc']}"
    md = render_markdown(sections, title, intro, glossary).replace("\n", f"\n\nGenerated by {stamp}.\n", 1)
    page = render_html(sections, title, intro, glossary)
    page = page.replace("</h1>", f"</h1><p>Generated by {html.escape(stamp)}.</p>", 1)
    checks = {s.title: [asdict(c) for c in s._every()] for s in sections}
    return [
        write_text_atomic(out_dir / "report.md", md),
        write_text_atomic(out_dir / "index.html", page),
        write_json_atomic(out_dir / "checks.json", checks),
        write_json_atomic(out_dir / "provenance.json", prov),
    ]


def _figure_format() -> str:
    try:
        from rotaflex.core.plotting import chosen_format
    except ImportError:  # pragma: no cover - matplotlib is a dependency
        return "png"
    return chosen_format()


# -- progress of a reproduction -----------------------------------------------------------------
_REPORTER: list[Callable[[str], None]] = []


def step(message: str) -> None:
    """Report progress of the running reproduction (e.g. ``"Fig. 5"``, ``"case 3/10"``).

    A reproduce module calls this between its cases; it does nothing unless
    :func:`rotaflex.reproduce.reproduce` installed a reporter (the CLI does, one line each).
    """
    if _REPORTER:
        _REPORTER[-1](message)


def reporter_active() -> bool:
    """Whether :func:`step` messages go anywhere (inside :func:`reporting`)."""
    return bool(_REPORTER)


@contextmanager
def reporting(callback: Callable[[str], None] | None) -> Iterator[None]:
    """Route :func:`step` messages to ``callback`` within the block (None: drop them)."""
    _REPORTER.append(callback or (lambda _m: None))
    try:
        yield
    finally:
        _REPORTER.pop()


_EXPECTED: list[tuple[str, str]] = []


def expect_warning(pattern: str, why: str) -> None:
    """Declare that a warning containing ``pattern`` is intended in this reproduction.

    A reproduce module calls this before a run that is meant to fail (e.g. the diverging
    spin-up beam): the warning is then shown as an expected outcome with ``why``, not as an
    error. Cleared when the module finishes.
    """
    _EXPECTED.append((pattern, why))


class ExpectedWarnings(logging.Filter):
    """Handler filter used by :func:`rotaflex.reproduce.reproduce`: warnings declared with
    :func:`expect_warning` are passed to ``say`` labelled as expected, and not printed raw."""

    def __init__(self, say: Callable[[str], None] | None):
        super().__init__()
        self.say = say

    def filter(self, record: logging.LogRecord) -> bool:
        msg = record.getMessage()
        for pattern, why in _EXPECTED:
            if pattern in msg:
                if self.say is not None:
                    self.say(f"expected, shown in the report: {msg} ({why})")
                return False
        return True

    def __enter__(self) -> ExpectedWarnings:
        for h in logging.getLogger().handlers:
            h.addFilter(self)
        return self

    def __exit__(self, *exc) -> None:
        for h in logging.getLogger().handlers:
            h.removeFilter(self)
        _EXPECTED.clear()
