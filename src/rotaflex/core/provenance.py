"""Provenance of every output: rotaflex version, git commit, UTC time, input file and its hash."""

from __future__ import annotations

import datetime as _dt
import functools
import hashlib
import subprocess
from pathlib import Path
from typing import Any


@functools.cache
def git_commit() -> str:
    """Commit of the rotaflex source tree if it is a git checkout (``""`` otherwise)."""
    here = Path(__file__).resolve().parent
    try:
        out = subprocess.run(
            ["git", "-C", str(here), "rev-parse", "HEAD"], capture_output=True, text=True, timeout=5, check=False
        )
    except (OSError, subprocess.SubprocessError):
        return ""
    if out.returncode != 0:
        return ""
    dirty = subprocess.run(
        ["git", "-C", str(here), "status", "--porcelain", "--untracked-files=no"],
        capture_output=True,
        text=True,
        timeout=5,
        check=False,
    )
    return out.stdout.strip() + ("-dirty" if dirty.returncode == 0 and dirty.stdout.strip() else "")


def sha256_file(path: str | Path) -> str:
    h = hashlib.sha256()
    with Path(path).open("rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def provenance(input_path: str | Path | None = None) -> dict[str, Any]:
    """Global attributes naming what produced an output.

    Returns
    -------
    dict
        ``rotaflex_version``, ``git_commit`` (``""`` if not a git checkout), ``created_utc``
        (ISO 8601), and for an input file ``input_file`` (absolute path) and ``input_sha256``.
    """
    import rotaflex

    out: dict[str, Any] = {
        "rotaflex_version": rotaflex.__version__,
        "git_commit": git_commit(),
        "created_utc": _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%dT%H:%M:%SZ"),
    }
    if input_path is not None:
        p = Path(input_path)
        out["input_file"] = str(p.absolute())
        try:
            out["input_sha256"] = sha256_file(p) if p.is_file() else ""
        except OSError:
            out["input_sha256"] = ""
    return out
