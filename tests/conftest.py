"""Suite-wide rules.

With ``-n 2 --dist loadgroup`` (the README's command) every test of one kernel family runs in
the same worker, so a cold numba cache (a fresh clone, CI) compiles each family once instead
of once per worker; the other tests are balanced over the workers as usual.

The family is given to pytest-xdist's scheduler directly (:func:`pytest_xdist_make_scheduler`)
rather than as an ``xdist_group`` mark: xdist passes marks to its scheduler by editing node
IDs, which pytest 9.2 no longer honours, so the groups were silently ignored
(pytest-dev/pytest-xdist#1386).
"""

from __future__ import annotations

import signal
import sys

import pytest

#: test folder -> the family of compiled kernels its tests run
KERNEL_FAMILY = {"gear": "gear-kernels", "floating": "floating-kernels"}


def kernel_family(nodeid: str) -> str | None:
    """The kernel family of a test (``tests/<folder>/...`` node ID), or None."""
    parts = nodeid.split("::", 1)[0].split("/")
    return KERNEL_FAMILY.get(parts[1]) if len(parts) > 2 and parts[0] == "tests" else None


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
        """Load-group scheduling with each kernel family as one group."""

        def _split_scope(self, nodeid: str) -> str:
            return kernel_family(nodeid) or super()._split_scope(nodeid)

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
