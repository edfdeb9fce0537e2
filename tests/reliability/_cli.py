"""Shared helpers of the issue-32 CLI tests: run a verb in-process on an example edited as a
user would edit it, and read the one line it prints on stderr."""

from __future__ import annotations

import copy
import tomllib
from pathlib import Path

import pytest

from rotaflex.cli import main

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"


def example(rel: str) -> dict:
    """The parsed example ``examples/<rel>``."""
    return tomllib.loads((EXAMPLES / rel).read_text())


def dump(data: dict) -> str:
    """``data`` as TOML (tables, arrays of tables, inline arrays; enough for the examples)."""
    out: list[str] = []

    def value(v) -> str:
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, str):
            return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
        if isinstance(v, float):
            return repr(v)
        if isinstance(v, (list, tuple)):
            return "[" + ", ".join(value(x) for x in v) + "]"
        if isinstance(v, dict):
            return "{ " + ", ".join(f"{k} = {value(x)}" for k, x in v.items()) + " }"
        return str(v)

    def table(prefix: str, d: dict) -> None:
        scalars = {k: v for k, v in d.items() if not _is_table(v)}
        for k, v in scalars.items():
            out.append(f"{k} = {value(v)}")
        for k, v in d.items():
            if isinstance(v, dict):
                out.append(f"\n[{prefix}{k}]")
                table(f"{prefix}{k}.", v)
            elif _is_table(v):
                for item in v:
                    out.append(f"\n[[{prefix}{k}]]")
                    table(f"{prefix}{k}.", item)

    table("", data)
    return "\n".join(out) + "\n"


def _is_table(v) -> bool:
    return isinstance(v, dict) or (isinstance(v, list) and v and all(isinstance(x, dict) for x in v))


def run(capsys, *args) -> tuple[int, str, str]:
    """``rotaflex ARGS``: exit status, stdout, stderr."""
    with pytest.raises(SystemExit) as exc:
        main([str(a) for a in args])
    cap = capsys.readouterr()
    return exc.value.code, cap.out, cap.err


def verb_on(capsys, tmp_path, verb: str, data: dict, *extra) -> tuple[int, str]:
    """Run ``rotaflex <verb> case.toml`` on ``data``; exit status and the one line on stderr
    (asserted to be exactly one line, no traceback, no warning)."""
    path = tmp_path / "case.toml"
    path.write_text(dump(data))
    code, _, err = run(capsys, *verb.split(), path, "--out", tmp_path / "o", "-q", "--no-figures", *extra)
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert "Traceback" not in err and "Warning" not in err.split(":", 1)[0], err
    return code, lines[0]


def edited(rel: str, edit) -> dict:
    """A deep copy of the example ``rel`` after ``edit(data)``."""
    data = copy.deepcopy(example(rel))
    edit(data)
    return data
