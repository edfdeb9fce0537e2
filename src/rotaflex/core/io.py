"""Atomic file output: single files and whole result directories.

A file is written to a temporary name beside the target and renamed over it; a result directory
is written into a sibling temporary directory and swapped in as a whole (an atomic exchange of
the two names where the kernel offers it). A crash or an exception while writing never leaves a
half-written file, and never a directory mixing new and old files. Files get the permissions
the user's umask allows (``tempfile`` alone would make them 0600).
"""

from __future__ import annotations

import ctypes
import ctypes.util
import functools
import json
import os
import shutil
import tempfile
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from rotaflex.core.errors import InputError

_TMP_TAG = ".rotaflex-tmp-"


@functools.cache
def _umask() -> int:
    # os.umask can only be read by setting it: read once per process and restore at once
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def _chmod_default(path: Path, *, directory: bool = False) -> None:
    os.chmod(path, (0o777 if directory else 0o666) & ~_umask())


@contextmanager
def atomic_path(target: str | Path) -> Iterator[Path]:
    """Yield a temporary path; on success it is renamed to ``target``, on error removed."""
    target = Path(target)
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
    os.close(fd)
    tmp_path = Path(tmp)
    try:
        yield tmp_path
        _chmod_default(tmp_path)
        os.replace(tmp_path, target)
    finally:
        if tmp_path.exists():
            tmp_path.unlink()


def write_atomic(target: str | Path, writer: Callable[[Path], Any]) -> Path:
    """Call ``writer(tmp_path)`` and move the file to ``target`` only if it succeeds."""
    with atomic_path(target) as tmp:
        writer(tmp)
    return Path(target)


def write_text_atomic(target: str | Path, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``target`` atomically."""
    return write_atomic(target, lambda p: p.write_text(text, encoding="utf-8"))


def write_json_atomic(target: str | Path, data: Any) -> Path:
    """Write ``data`` as indented JSON to ``target`` atomically."""
    return write_text_atomic(target, json.dumps(data, indent=2, default=_json_default) + "\n")


def _json_default(obj: Any) -> Any:
    import numpy as np

    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, Path):
        return str(obj)
    raise TypeError(f"not JSON serialisable: {type(obj).__name__}")


# -- whole directories ------------------------------------------------------------------------
_RENAME_EXCHANGE = 2
_AT_FDCWD = -100


def _exchange(a: Path, b: Path) -> bool:
    """Atomically swap the names ``a`` and ``b`` (Linux ``renameat2``); False if unsupported."""
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or None, use_errno=True)
        fn = libc.renameat2
    except (OSError, AttributeError):
        return False
    fn.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_uint]
    rc = fn(_AT_FDCWD, os.fsencode(a), _AT_FDCWD, os.fsencode(b), _RENAME_EXCHANGE)
    return rc == 0


def _stale_siblings(target: Path) -> list[Path]:
    return sorted(target.parent.glob(f".{target.name}{_TMP_TAG}*"))


def recover_dir(target: str | Path) -> None:
    """Finish or undo a directory swap that a killed process left half done.

    If ``target`` is missing but a complete previous version was parked beside it (the
    two-rename fallback was interrupted), that version is put back; leftover temporary
    directories are removed.
    """
    target = Path(target)
    for stale in _stale_siblings(target):
        if not target.exists() and stale.name.endswith(".old"):
            os.replace(stale, target)
        else:
            shutil.rmtree(stale, ignore_errors=True)


def replace_dir(target: str | Path, writer: Callable[[Path], list[Path]]) -> list[Path]:
    """Write a directory as a set: ``writer(tmp_dir)`` fills a sibling temporary directory, which
    then replaces ``target`` in one step.

    Parameters
    ----------
    target : path
        The result directory; its parent must exist. A previous ``target`` is replaced as a
        whole (its files are not merged with the new ones).
    writer : callable
        ``writer(tmp_dir) -> list of written paths`` (inside ``tmp_dir``).

    Returns
    -------
    list of Path
        The written paths, under ``target``.
    """
    target = Path(target)
    recover_dir(target)
    tmp = new = Path(tempfile.mkdtemp(prefix=f".{target.name}{_TMP_TAG}", dir=target.parent))
    try:
        _chmod_default(tmp, directory=True)
        written = writer(tmp)
        if target.exists():
            if not _exchange(tmp, target):
                parked = target.parent / f".{target.name}{_TMP_TAG}{os.getpid()}.old"
                os.replace(target, parked)
                os.replace(tmp, target)
                tmp = parked
        else:
            os.replace(tmp, target)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)  # the old version, or the failed new one
    return [target / Path(p).relative_to(new) for p in written]


def check_out_dir(path: str | Path, *, marker: tuple[str, ...] = (), field: str = "--out") -> Path:
    """Refuse an unusable output directory before any computation starts.

    Parameters
    ----------
    path : str or Path
        The ``--out`` value as typed.
    marker : tuple of str
        Names of which at least one must exist in an existing, non-empty ``path`` (so that a
        directory of other files is never replaced or mixed with results); empty: no check.
    field : str
        Name of the option in messages.

    Raises
    ------
    InputError
        Empty path, an existing file, a path under a file, a missing or read-only parent, a
        non-empty directory that is not an earlier result of this command.
    """
    text = str(path)
    if text.strip() == "":
        raise InputError(field, text, "a directory path (an empty string would write into the current directory)")
    p = Path(text).expanduser()
    if p.exists() and not p.is_dir():
        raise InputError(field, text, "a directory, not an existing file")
    for parent in p.absolute().parents:
        if parent.exists() and not parent.is_dir():
            raise InputError(field, text, f"a path not under the file {str(parent)!r}")
    parent = p.absolute().parent
    if not parent.exists():
        raise InputError(field, text, f"a directory whose parent exists ({str(parent)!r} does not)")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise InputError(field, text, f"a directory in a writable location ({str(parent)!r} is read-only)")
    if p.exists():
        if not os.access(p, os.W_OK | os.X_OK):
            raise InputError(field, text, "a writable directory")
        entries = [e.name for e in p.iterdir()]
        if marker and entries and not any(m in entries for m in marker):
            raise InputError(
                field,
                text,
                "a new or empty directory, or an earlier output of this command (it holds other files, "
                "which would be replaced)",
            )
    return p
