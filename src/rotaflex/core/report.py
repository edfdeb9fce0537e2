"""The reproduction report: figures beside the paper's captions, checks with measured numbers.

Each domain's ``reproduce`` module returns a :class:`Section`; :func:`write_report` renders all
sections to ``report.md`` and a self-contained ``index.html`` (figures linked, not embedded), and
the checks to ``checks.json``.
"""

from __future__ import annotations

import html
import logging
import math
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


@dataclass
class Section:
    """One domain's part of the report."""

    title: str
    intro: str = ""
    figures: list[FigureEntry] = field(default_factory=list)
    checks: list[Check] = field(default_factory=list)  # checks not tied to one figure
    notes: list[str] = field(default_factory=list)
    wall_time: float = float("nan")
    compile_time: float = 0.0  # numba kernel compilation inside the section [s], not in wall_time
    provenance: dict = field(default_factory=dict)

    def all_checks(self) -> list[Check]:
        """Verification checks (pass/fail), excluding the paper's claims and information rows."""
        return [c for c in self._every() if not (c.claim or c.info)]

    def claims(self) -> list[Check]:
        return [c for c in self._every() if c.claim and not c.info]

    def _every(self) -> list[Check]:
        return self.checks + [c for f in self.figures for c in f.checks]


def _md_checks(checks: list[Check]) -> list[str]:
    if not checks:
        return []
    rows = ["| check | measured | criterion | result | note |", "|---|---|---|---|---|"]
    for c in checks:
        rows.append(f"| {c.name} | {c.value_text()} | {c.criterion} | {c.outcome} | {c.note} |")
    return rows + [""]


def _time_text(s: Section) -> str:
    text = f"{s.wall_time:.2f} s"
    if s.compile_time >= 0.05:
        text += f" (plus {s.compile_time:.1f} s compiling numba kernels, first run only)"
    return text


def _caption(caption: str) -> str:
    """``Paper's caption: ...``, or ``Added figure: ...`` for one the paper does not have."""
    c = caption.strip()
    for tag in ("(not in the paper;", "(not in the paper)"):
        if c.startswith(tag):
            rest = c[len(tag) :].strip().rstrip(")").strip() if tag.endswith(";") else c[len(tag) :].strip()
            return "Added figure (not in the paper)" + (f": {rest}" if rest else ".")
    return f"Paper's caption: {c}"


def render_markdown(sections: list[Section], title: str) -> str:
    lines = [f"# {title}", ""]
    n_all = sum(len(s.all_checks()) for s in sections)
    n_ok = sum(c.passed for s in sections for c in s.all_checks())
    claims = [c for s in sections for c in s.claims()]
    lines += [
        f"Checks passed: **{n_ok} / {n_all}**. Paper claims examined: {len(claims)} "
        f"({sum(c.passed for c in claims)} hold).",
        "",
    ]
    for s in sections:
        lines += [f"## {s.title}", ""]
        if not math.isnan(s.wall_time):
            lines += [f"Wall time: {_time_text(s)}.", ""]
        if s.intro:
            lines += [s.intro, ""]
        lines += _md_checks(s.checks)
        for f in s.figures:
            lines += [f"### {f.label}", "", f"> {_caption(f.caption)}", ""]
            lines += [f"![{f.label}]({f.image})", ""]
            if f.description:
                lines += [f.description, ""]
            if f.data:
                lines += [f"Data: [`{f.data}`]({f.data})", ""]
            lines += _md_checks(f.checks)
        if s.notes:
            lines += ["### Notes", ""] + [f"- {n}" for n in s.notes] + [""]
    return "\n".join(lines)


def _html_checks(checks: list[Check]) -> str:
    if not checks:
        return ""
    e = html.escape
    rows = "".join(
        f"<tr class='{'ok' if c.passed or c.claim or c.info else 'fail'}'><td>{e(c.name)}</td>"
        f"<td>{e(c.value_text())}</td><td>{e(c.criterion)}</td><td>{c.outcome}</td><td>{e(c.note)}</td></tr>"
        for c in checks
    )
    return (
        f"<table><tr><th>check</th><th>measured</th><th>criterion</th><th>result</th><th>note</th></tr>{rows}</table>"
    )


def render_html(sections: list[Section], title: str) -> str:
    e = html.escape
    n_all = sum(len(s.all_checks()) for s in sections)
    n_ok = sum(c.passed for s in sections for c in s.all_checks())
    claims = [c for s in sections for c in s.claims()]
    body = [
        f"<h1>{e(title)}</h1><p>Checks passed: <b>{n_ok} / {n_all}</b>. Paper claims examined: "
        f"{len(claims)} ({sum(c.passed for c in claims)} hold).</p>"
    ]
    for s in sections:
        body.append(f"<h2>{e(s.title)}</h2>")
        if not math.isnan(s.wall_time):
            body.append(f"<p>Wall time: {e(_time_text(s))}.</p>")
        if s.intro:
            body.append("".join(f"<p>{e(p)}</p>" for p in s.intro.split("\n\n")))
        body.append(_html_checks(s.checks))
        for f in s.figures:
            data = f"<p>Data: <a href='{e(f.data)}'>{e(f.data)}</a></p>" if f.data else ""
            body.append(
                f"<div class='fig'><h3>{e(f.label)}</h3><div class='row'>"
                f"<img src='{e(f.image)}' alt='{e(f.label)}'>"
                f"<div class='cap'><p><i>{e(_caption(f.caption))}</i></p>"
                f"<p>{e(f.description)}</p>{data}</div></div>{_html_checks(f.checks)}</div>"
            )
        if s.notes:
            body.append("<h3>Notes</h3><ul>" + "".join(f"<li>{e(n)}</li>" for n in s.notes) + "</ul>")
    style = (
        "body{font-family:sans-serif;max-width:1200px;margin:auto;padding:1em}"
        "img{max-width:640px;width:100%}.row{display:flex;gap:1em;align-items:flex-start}"
        ".cap{flex:1}table{border-collapse:collapse;margin:.5em 0}td,th{border:1px solid #ccc;"
        "padding:3px 6px;font-size:90%}tr.fail td{background:#fdd}tr.ok td:nth-child(4){color:#070}"
    )
    return (
        f"<!doctype html><html><head><meta charset='utf-8'><title>{e(title)}</title>"
        f"<style>{style}</style></head><body>{''.join(body)}</body></html>\n"
    )


def write_report(
    out_dir: str | Path, sections: list[Section], title: str, provenance: dict | None = None
) -> list[Path]:
    """Write ``report.md``, ``index.html``, ``checks.json`` and ``provenance.json`` into ``out_dir``.

    Figure paths ending in ``.png`` follow the format chosen with
    :func:`rotaflex.core.plotting.configure` (``--format``).
    """
    from rotaflex.core.provenance import provenance as _prov

    out_dir = Path(out_dir)
    prov = {**_prov(), **(provenance or {})}
    fmt = _figure_format()
    if fmt != "png":
        for s in sections:
            for f in s.figures:
                if f.image.endswith(".png"):
                    f.image = f.image[:-4] + "." + fmt
    stamp = f"rotaflex {prov['rotaflex_version']}" + (f", commit {prov['git_commit']}" if prov["git_commit"] else "")
    stamp += f", {prov['created_utc']}"
    md = render_markdown(sections, title).replace("\n", f"\n\nGenerated by {stamp}.\n", 1)
    page = render_html(sections, title).replace("</h1>", f"</h1><p>Generated by {html.escape(stamp)}.</p>", 1)
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
