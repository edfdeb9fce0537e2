"""The reproduction report: figures beside the paper's captions, checks with measured numbers.

Each domain's ``reproduce`` module returns a :class:`Section`; :func:`write_report` renders all
sections to ``report.md`` and a self-contained ``index.html`` (figures linked, not embedded), and
the checks to ``checks.json``.
"""

from __future__ import annotations

import html
import math
from dataclasses import asdict, dataclass, field
from pathlib import Path

from rotaflex.core.io import write_json_atomic, write_text_atomic


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
    """

    name: str
    measured: float
    unit: str
    criterion: str
    passed: bool
    note: str = ""
    claim: bool = False  # a claim of the paper: reported as holds / does not hold, not as pass/fail

    @property
    def outcome(self) -> str:
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

    def all_checks(self) -> list[Check]:
        """Verification checks (pass/fail), excluding the paper's claims."""
        return [c for c in self._every() if not c.claim]

    def claims(self) -> list[Check]:
        return [c for c in self._every() if c.claim]

    def _every(self) -> list[Check]:
        return self.checks + [c for f in self.figures for c in f.checks]


def _md_checks(checks: list[Check]) -> list[str]:
    if not checks:
        return []
    rows = ["| check | measured | criterion | result | note |", "|---|---|---|---|---|"]
    for c in checks:
        rows.append(f"| {c.name} | {c.value_text()} | {c.criterion} | {c.outcome} | {c.note} |")
    return rows + [""]


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
            lines += [f"Wall time: {s.wall_time:.2f} s.", ""]
        if s.intro:
            lines += [s.intro, ""]
        lines += _md_checks(s.checks)
        for f in s.figures:
            lines += [f"### {f.label}", "", f"> Paper's caption: {f.caption}", ""]
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
        f"<tr class='{'ok' if c.passed or c.claim else 'fail'}'><td>{e(c.name)}</td>"
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
            body.append(f"<p>Wall time: {s.wall_time:.2f} s.</p>")
        if s.intro:
            body.append("".join(f"<p>{e(p)}</p>" for p in s.intro.split("\n\n")))
        body.append(_html_checks(s.checks))
        for f in s.figures:
            data = f"<p>Data: <a href='{e(f.data)}'>{e(f.data)}</a></p>" if f.data else ""
            body.append(
                f"<div class='fig'><h3>{e(f.label)}</h3><div class='row'>"
                f"<img src='{e(f.image)}' alt='{e(f.label)}'>"
                f"<div class='cap'><p><i>Paper's caption:</i> {e(f.caption)}</p>"
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


def write_report(out_dir: str | Path, sections: list[Section], title: str) -> list[Path]:
    """Write ``report.md``, ``index.html`` and ``checks.json`` into ``out_dir`` atomically."""
    out_dir = Path(out_dir)
    checks = {s.title: [asdict(c) for c in s._every()] for s in sections}
    return [
        write_text_atomic(out_dir / "report.md", render_markdown(sections, title)),
        write_text_atomic(out_dir / "index.html", render_html(sections, title)),
        write_json_atomic(out_dir / "checks.json", checks),
    ]
