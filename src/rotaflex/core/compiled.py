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


def entry(func=None, **options):
    """``njit(cache=True, **options)``: a kernel called from Python."""
    decorate = njit(cache=True, **options)
    return decorate if func is None else decorate(func)


class _InnerDispatcher(CPUDispatcher):
    """A dispatcher without the Python wrapper: refuses calls from Python (which would crash)."""

    def __call__(self, *args, **kwargs):
        raise TypeError(f"{self.py_func.__qualname__} is compiled only for calls from other kernels (@inner)")


def inner(func=None, **options):
    """Compile ``func`` (lazily, cached) for calls from other kernels only; ``options`` are
    numba's (e.g. ``error_model="numpy"``)."""

    def decorate(f):
        targetoptions = {"nopython": True, "no_cpython_wrapper": True, "no_cfunc_wrapper": True, **options}
        dispatcher = _InnerDispatcher(py_func=f, locals={}, targetoptions=targetoptions)
        dispatcher.enable_caching()
        return dispatcher

    return decorate if func is None else decorate(func)


__all__ = ["entry", "inner"]
