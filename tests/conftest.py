"""Suite-wide collection rules.

With ``-n 2 --dist loadgroup`` (the README's command) every test of one kernel family runs in
the same worker, so a cold numba cache (a fresh clone, CI) compiles each family once instead
of once per worker; the other tests are balanced over the workers as usual.
"""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

_TESTS = Path(__file__).resolve().parent
#: test folder -> the family of compiled kernels its tests run
_KERNEL_FAMILY = {"gear": "gear-kernels", "floating": "floating-kernels"}


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(config, items):
    for item in items:
        try:
            folder = Path(item.fspath).resolve().relative_to(_TESTS).parts[0]
        except ValueError:
            continue
        family = _KERNEL_FAMILY.get(folder)
        if family is not None:
            item.add_marker(pytest.mark.xdist_group(family))


@pytest.fixture(autouse=True)
def _close_figures():
    """Close the figures a test left open (pyplot keeps every figure until closed)."""
    yield
    pyplot = sys.modules.get("matplotlib.pyplot")
    if pyplot is not None:
        pyplot.close("all")
