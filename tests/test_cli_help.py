"""``rotaflex --help`` prints plain text without loading a formatter (issue 25).

Checked as a property of ``sys.modules`` in a fresh process, not as a time (times:
``benchmarks/bench_startup.py``): typer's rich formatter (rich, markdown_it) cost about half of
``--help``'s CPU time, and ``logging`` is set up only when a command runs.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _fresh(code: str) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    return subprocess.run(
        [sys.executable, "-c", textwrap.dedent(code)], env=env, capture_output=True, text=True, timeout=120
    )


def test_help_is_plain_text_and_loads_no_formatter():
    proc = _fresh(
        """
        import json, sys
        from rotaflex.cli import main

        try:
            main(["--help"])
        except SystemExit as exc:
            assert exc.code == 0, exc.code
        print(json.dumps(sorted(m for m in ("rich", "markdown_it", "logging") if m in sys.modules)))
        """
    )
    assert proc.returncode == 0, proc.stderr
    *text, loaded = proc.stdout.strip().splitlines()
    assert json.loads(loaded) == []
    text = "\n".join(text)
    assert text.startswith("Usage: rotaflex [OPTIONS] COMMAND [ARGS]...")
    assert "rotor" in text and "gear" in text
    assert not any(c in text for c in "╭╮╰╯│")  # no boxes drawn around the sections


def test_usage_error_stays_one_line_with_a_suggestion():
    proc = _fresh(
        """
        from rotaflex.cli import main

        main(["rotr"])
        """
    )
    assert proc.returncode == 2
    err = proc.stderr.strip()
    assert "\n" not in err and err.startswith("error: No such command 'rotr'. Did you mean 'rotor'")
    assert err.endswith("(see 'rotaflex --help')")
