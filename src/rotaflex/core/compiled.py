"""The two ways a numba kernel is compiled in rotaflex (importing this module imports numba).

``@entry``
    A kernel called from Python: a solver's entry point, or a helper that other Python code or
    the tests call directly. Cached on disk, with numba's Python wrapper.
``@inner``
    A kernel called only from other kernels. Cached on disk, compiled *without* the Python and C
    wrappers. Those wrappers unbox every argument from Python objects; for kernels that take
    the solvers' named groups of arrays (tens of arrays each) they were about a third of the
    first-run compilation (gear paper method, cold cache: 88 -> 61 s CPU, results
    bit-identical; docs/performance.md). Calling an ``@inner`` kernel from Python fails.

numba links every kernel a kernel calls into its own machine code, so a deep call tree is
optimised and compiled once per level: keep the chain from an entry point to its leaves short.
"""

from __future__ import annotations

from numba import njit
from numba.core.registry import CPUDispatcher

entry = njit(cache=True)


class _InnerDispatcher(CPUDispatcher):
    """A dispatcher without the Python wrapper: refuses calls from Python (which would crash)."""

    def __call__(self, *args, **kwargs):
        raise TypeError(f"{self.py_func.__qualname__} is compiled only for calls from other kernels (@inner)")


def inner(func):
    """Compile ``func`` (lazily, cached) for calls from other kernels only."""
    dispatcher = _InnerDispatcher(
        py_func=func,
        locals={},
        targetoptions={"nopython": True, "no_cpython_wrapper": True, "no_cfunc_wrapper": True},
    )
    dispatcher.enable_caching()
    return dispatcher


__all__ = ["entry", "inner"]
