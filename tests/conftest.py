"""Suite-wide rules.

With ``-n 2 --dist loadgroup`` (the README's command) every test of one kernel family runs in
the same worker, so a cold numba cache (a fresh clone, CI) compiles each family once instead
of once per worker; the other tests are balanced over the workers as usual.

A test file whose module-scoped fixtures or ``functools`` caches (its own, or those of a
``conftest.py`` of its folder) compute something shared is one group too: split over two workers, each would compute it
(seen: the continuation sweep of tests/sweep/test_continuation.py, 9 s CPU, ran in both).

The family is given to pytest-xdist's scheduler directly (:func:`pytest_xdist_make_scheduler`)
rather than as an ``xdist_group`` mark: xdist passes marks to its scheduler by editing node
IDs, which pytest 9.2 no longer honours, so the groups were silently ignored
(pytest-dev/pytest-xdist#1386).
"""

from __future__ import annotations

import functools
import re
import signal
import sys
from pathlib import Path

import pytest

#: test folder -> the family of compiled kernels its tests run
KERNEL_FAMILY = {"gear": "gear-kernels", "floating": "floating-kernels"}


def kernel_family(nodeid: str) -> str | None:
    """The kernel family of a test (``tests/<folder>/...`` node ID), or None."""
    parts = nodeid.split("::", 1)[0].split("/")
    return KERNEL_FAMILY.get(parts[1]) if len(parts) > 2 and parts[0] == "tests" else None


#: a fixture evaluated once per module or session, or a function cache shared by a file's tests
#: (text of a test file or conftest.py)
_SHARED_SCOPE = re.compile(r"scope\s*=\s*[\"'](module|session)[\"']|@functools\.(cache|lru_cache)\b")
_ROOT = Path(__file__).resolve().parents[1]


@functools.cache
def shares_module_fixture(path: str) -> bool:
    """True if the test file at ``path`` (relative to the checkout), or a ``conftest.py`` in its
    folder or a parent folder below ``tests/``, defines a module- or session-scoped fixture or a
    ``functools`` cache (results its tests share within one process)."""
    file = _ROOT / path
    texts = [file]
    folder = file.parent
    while folder != _ROOT / "tests" and _ROOT in folder.parents:
        texts.append(folder / "conftest.py")
        folder = folder.parent
    return any(t.is_file() and _SHARED_SCOPE.search(t.read_text(encoding="utf-8")) for t in texts)


def schedule_group(nodeid: str) -> str | None:
    """The scheduling group of a test: its kernel family, else its file if the file shares a
    module-scoped fixture, else None (the test is scheduled on its own)."""
    family = kernel_family(nodeid)
    if family is not None:
        return family
    path = nodeid.split("::", 1)[0]
    return path if shares_module_fixture(path) else None


def pytest_configure(config):
    """Take Ctrl-C back if the suite was started with it ignored (a background job of a
    non-interactive shell, ``nohup``): the command-line processes the signal tests start inherit
    the disposition, and an ignored SIGINT would make them finish instead of stopping."""
    if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
        signal.signal(signal.SIGINT, signal.default_int_handler)
    # One BLAS thread per test process, as the command line runs (rotaflex.core.threads): two
    # workers with a two-thread pool each oversubscribe two cores; tests/system took 79-113 s
    # wall with the default pools against 43 s with one thread (back to back, loaded machine).
    from rotaflex.core.threads import limit_blas_threads

    limit_blas_threads()


@pytest.hookimpl(optionalhook=True)
def pytest_xdist_make_scheduler(config, log):
    if config.getvalue("dist") != "loadgroup":
        return None
    from xdist.scheduler import LoadGroupScheduling

    class KernelFamilyScheduling(LoadGroupScheduling):
        """Load-group scheduling with each kernel family, and each file sharing a module-scoped
        fixture, as one group."""

        def _split_scope(self, nodeid: str) -> str:
            return schedule_group(nodeid) or super()._split_scope(nodeid)

    return KernelFamilyScheduling(config, log)


@pytest.fixture(autouse=True)
def _close_figures():
    """Close the figures a test left open (pyplot keeps every figure until closed)."""
    yield
    pyplot = sys.modules.get("matplotlib.pyplot")
    if pyplot is not None:
        pyplot.close("all")


@pytest.fixture
def python_json():
    """Run Python ``code`` (dedented) in a fresh interpreter with rotaflex's src/ on the path
    (and ``extra_path`` entries, ``env`` overrides); return the JSON its last output line holds."""
    import json
    import os
    import subprocess
    import textwrap
    from pathlib import Path

    src = Path(__file__).resolve().parents[1] / "src"

    def run(code: str, *, extra_path=(), env=None, timeout: float = 300) -> dict:
        full = {**os.environ, "PYTHONPATH": os.pathsep.join([str(src), *map(str, extra_path)]), **(env or {})}
        proc = subprocess.run(
            [sys.executable, "-c", textwrap.dedent(code)], env=full, capture_output=True, text=True, timeout=timeout
        )
        assert proc.returncode == 0, proc.stderr
        return json.loads(proc.stdout.strip().splitlines()[-1])

    return run
