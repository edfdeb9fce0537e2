"""The example cases shipped inside the package (``rotaflex/examples``).

The examples are package data, so an installed rotaflex (wheel or editable) reads the same
files; the ``examples`` folder at the top of a source checkout is a link to them. Code that
needs an example (the reproduce sections, the sweep hooks) asks this module for its path,
never the source tree.

Examples
--------
>>> example_path("system/gearbox.toml").name
'gearbox.toml'
"""

from __future__ import annotations

import shutil
from importlib.resources import files
from pathlib import Path

from rotaflex.core.errors import InputError

__all__ = ["IncompleteInstall", "copy_examples", "example_path", "examples_dir", "list_examples", "match_examples"]

_SUFFIXES = (".toml", ".py", ".md")


class IncompleteInstall(RuntimeError):
    """A file that ships inside the package is missing: the installation, not the input, is at fault."""


def examples_dir() -> Path:
    """The folder of the shipped examples (inside the installed package)."""
    return Path(str(files("rotaflex") / "examples"))


def example_path(relative: str) -> Path:
    """Path of the shipped example ``relative`` (e.g. ``"system/gearbox.toml"``).

    Raises
    ------
    IncompleteInstall
        Naming the full path looked for: the package data were not installed.
    """
    path = examples_dir() / relative
    if not path.is_file():
        raise IncompleteInstall(f"shipped example missing from the installation: {path}")
    return path


def list_examples() -> list[str]:
    """Every shipped example, as paths relative to :func:`examples_dir` (sorted)."""
    root = examples_dir()
    return sorted(p.relative_to(root).as_posix() for p in root.rglob("*") if p.is_file() and p.suffix in _SUFFIXES)


def match_examples(pattern: str = "*") -> list[str]:
    """The shipped examples matching ``pattern``: a glob (``"system/*"``) or a folder (``"gear/steady"``)."""
    chosen = [r for r in list_examples() if Path(r).match(pattern) or r.startswith(pattern.rstrip("*/") + "/")]
    if not chosen:
        raise InputError("pattern", pattern, "a glob matching shipped examples (`rotaflex examples` lists them)")
    return chosen


def copy_examples(dest: str | Path, pattern: str = "*") -> list[Path]:
    """Copy the shipped examples whose relative path matches ``pattern`` (glob) under ``dest``.

    Existing files are not overwritten (refused, naming the first). Returns the written paths.
    """
    dest = Path(dest)
    chosen = match_examples(pattern)
    clash = [dest / r for r in chosen if (dest / r).exists()]
    if clash:
        raise InputError("--to", str(dest), f"a folder without {clash[0]} (files are never overwritten)")
    written = []
    for r in chosen:
        target = dest / r
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(examples_dir() / r, target)
        written.append(target)
    return written
