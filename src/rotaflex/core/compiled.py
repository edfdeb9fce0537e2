"""The two ways a numba kernel is compiled in rotaflex (importing this module imports numba).

``@entry``
    A kernel called from Python: a solver's entry point, or a helper that other Python code or
    the tests call directly. Cached on disk, with numba's Python wrapper. The cache is keyed
    on the source of every kernel module of its package (numba keys it on the entry's own
    file only, so an edited callee in a sibling module would load stale machine code).
``@inner``
    A kernel called only from other kernels: compiled without the Python and C wrappers, not
    cached, and *linked, not optimised*: its LLVM module is not optimised and no machine code
    is made for it; the entry point that calls it optimises and compiles the whole tree once.
    Calling an ``@inner`` kernel from Python raises a TypeError.

Why: numba links the kernels a kernel calls into the caller's module and, by default,
optimises it and makes machine code at every level of the call tree, so a tree four levels
deep (the gear step, about 40 kernels) was optimised four times. Linking only at the inner
levels took the gear paper method's first-run compilation from 62 to 40 s CPU with
bit-identical results (docs/performance.md).
"""

from __future__ import annotations

import functools
import hashlib
import threading
from pathlib import Path

from numba.core import codegen as _codegen
from numba.core import sigutils
from numba.core.compiler_lock import require_global_compiler_lock
from numba.core.registry import CPUDispatcher

#: per thread, the kernels being compiled: the qualname of an ``@inner`` one, None for others
_COMPILING = threading.local()


def _stack() -> list:
    stack = getattr(_COMPILING, "stack", None)
    if stack is None:
        stack = _COMPILING.stack = []
    return stack


class _EntryDispatcher(CPUDispatcher):
    def compile(self, sig):
        _stack().append(None)
        try:
            return super().compile(sig)
        finally:
            _stack().pop()


class _InnerDispatcher(CPUDispatcher):
    """A dispatcher without the Python wrapper: refuses calls from Python (which would crash)."""

    def __call__(self, *args, **kwargs):
        raise TypeError(f"{self.py_func.__qualname__} is compiled only for calls from other kernels (@inner)")

    def compile(self, sig):
        _stack().append(self.py_func.__qualname__)
        try:
            return super().compile(sig)
        finally:
            _stack().pop()


_FINALIZE = _codegen.CPUCodeLibrary.finalize
_SET_ENV = _codegen.JITCPUCodegen.set_env


def _finalize(library) -> None:
    """numba's finalisation, except for the library of the ``@inner`` kernel being compiled:
    link its callees in, verify, and stop (no optimisation, no machine code)."""
    stack = _stack()
    if not stack or stack[-1] is None or stack[-1] != library.name:
        return _FINALIZE(library)
    require_global_compiler_lock()
    library._raise_if_finalized()
    seen = set()
    for lib in library._linking_libraries:
        if lib not in seen:
            seen.add(lib)
            library._reload_init.update(lib._reload_init)
            library._final_module.link_in(lib._get_module_for_linking(), preserve=True)
    library._final_module.verify()
    library._finalize_dynamic_globals()
    library._verify_declare_only_symbols()
    library._finalized = True
    return None


def _set_env(codegen, env_name, env) -> None:
    # A link-only library is not in the execution engine, so its environment global has no
    # address; in the entry's machine code it stays unset, as numba leaves it for every
    # callee of an entry loaded from the disk cache.
    if codegen._engine.get_global_value_address(env_name) == 0:
        return
    _SET_ENV(codegen, env_name, env)


_codegen.CPUCodeLibrary.finalize = _finalize
_codegen.JITCPUCodegen.set_env = _set_env


@functools.cache
def _package_stamp(folder: str) -> bytes:
    """SHA-256 of the kernel modules (those importing this module) in ``folder``, and of this
    module."""
    digest = hashlib.sha256(Path(__file__).read_bytes())
    for path in sorted(Path(folder).glob("*.py")):
        text = path.read_bytes()
        if b"rotaflex.core.compiled" in text:
            digest.update(path.name.encode() + text)
    return digest.digest()


def _key_cache_on_package(dispatcher) -> None:
    """Key ``dispatcher``'s disk cache on its package (:func:`_package_stamp`), name its data
    files after that stamp, and load only data of the signature asked for.

    numba writes a cache entry's index before its data and numbers the data files from 1 for
    every fresh index: a second process compiling the same kernels at the same time (``reproduce
    --jobs``, a sweep) could read the new index while the data file it names was still the one
    of an older source, and run that older code (seen: a gear sweep case typed with the old
    stiffness layout). With the stamp in the data file's name a stale file is never named by a
    fresh index, and a loaded entry whose signature is not the one asked for is treated as a
    miss (compiled again)."""
    cache = getattr(dispatcher, "_cache", None)
    cache_file = getattr(cache, "_cache_file", None)
    if cache_file is None or not hasattr(cache_file, "_source_stamp"):
        return
    stamp = _package_stamp(str(Path(dispatcher.py_func.__code__.co_filename).parent))
    cache_file._source_stamp = stamp
    pattern = getattr(cache_file, "_data_name_pattern", None)
    if isinstance(pattern, str) and pattern.endswith(".{number:d}.nbc"):
        cache_file._data_name_pattern = pattern[: -len(".{number:d}.nbc")] + f".{stamp.hex()[:12]}.{{number:d}}.nbc"
    load = cache.load_overload

    def load_checked(sig, target_context):
        cres = load(sig, target_context)
        if cres is not None and tuple(cres.signature.args) != tuple(sigutils.normalize_signature(sig)[0]):
            return None
        return cres

    cache.load_overload = load_checked


def entry(func=None, **options):
    """A kernel called from Python: ``njit(cache=True, **options)``, cached per package."""

    def decorate(f):
        dispatcher = _EntryDispatcher(py_func=f, locals={}, targetoptions={"nopython": True, **options})
        dispatcher.enable_caching()
        _key_cache_on_package(dispatcher)
        return dispatcher

    return decorate if func is None else decorate(func)


def inner(func=None, **options):
    """Compile ``func`` lazily for calls from other kernels only; ``options`` are numba's
    (e.g. ``error_model="numpy"``)."""

    def decorate(f):
        targetoptions = {"nopython": True, "no_cpython_wrapper": True, "no_cfunc_wrapper": True, **options}
        return _InnerDispatcher(py_func=f, locals={}, targetoptions=targetoptions)

    return decorate if func is None else decorate(func)


__all__ = ["entry", "inner"]
