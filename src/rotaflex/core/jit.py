"""Numba compilation seen from the user: time it, and say so once before a cold cache compiles.

Nothing here imports numba unless numba is already loaded or the caller hands over compiled
functions: a verb that compiles nothing (``rotor campbell``, ``--help``) never pays numba's
import (~0.2-0.5 s, ~60 MiB).

:class:`CompileTimer`
    Total time spent compiling inside a block (the CLI reports it apart from the solver time).
:func:`announce_compilation`
    One line, once per process, *before* a domain's kernels are compiled, and only if numba's
    on-disk cache holds none of them yet (see :func:`cache_is_cold`). Domains call it right
    before the first call of their kernels (docs/performance.md shows how).
"""

from __future__ import annotations

import importlib.abc
import importlib.util
import logging
import sys
import time
from collections.abc import Callable, Iterable
from types import ModuleType
from typing import Any

log = logging.getLogger(__name__)

#: where :func:`announce_compilation` writes while a :class:`CompileTimer` with an ``announce``
#: callable is active (the CLI's stderr line writer); else the module logger at INFO level
_SINK: list[Callable[[str], None]] = []
#: what :func:`announce_compilation` has announced in this process
_ANNOUNCED: set[str] = set()


def _dispatchers(kernels: Iterable[Any]) -> list[Any]:
    """The numba dispatchers among ``kernels``: dispatchers themselves, or modules (their
    module-level dispatchers). Anything else is ignored."""
    from numba.core.dispatcher import Dispatcher

    out = []
    for k in kernels:
        if isinstance(k, ModuleType):
            out += [v for v in vars(k).values() if isinstance(v, Dispatcher)]
        elif isinstance(k, Dispatcher):
            out.append(k)
    return out


def cache_is_cold(kernels: Iterable[Any]) -> bool:
    """True if at least one of ``kernels`` (numba dispatchers, or modules holding them) built
    with ``cache=True`` has no usable entry in numba's on-disk cache.

    "Usable" is numba's own test: the function's index file (``<name>-<line>.pyXY.nbi`` in the
    cache directory numba chose, ``NUMBA_CACHE_DIR`` if set) exists, was written by this numba
    version for the current source of the module, and lists at least one compiled signature.
    A signature the run needs but the index lacks still compiles (silently: a partial cache
    is seconds, a cold one tens of seconds). Kernels without a disk cache count as warm.
    """
    for d in _dispatchers(kernels):
        cache_file = getattr(getattr(d, "_cache", None), "_cache_file", None)
        if cache_file is None:  # cache=False (NullCache): nothing to load, nothing to announce
            continue
        try:
            if not cache_file._load_index():
                return True
        except Exception:  # noqa: BLE001 - an unreadable index is numba's business; it recompiles
            return True
    return False


def announce_compilation(what: str, kernels: Iterable[Any], seconds: float) -> bool:
    """Say once, before the first call of ``kernels``, that they are about to be compiled.

    Parameters
    ----------
    what : str
        The kernels' family as the user knows it ("gear", "floating-body").
    kernels : iterable
        The numba dispatchers the run will call, or the modules that hold them.
    seconds : float
        Measured first-run compilation time on a 2-core machine [s] (docs/performance.md).

    Returns
    -------
    bool
        True if the line was written (cold cache, first time for ``what`` in this process).
    """
    if what in _ANNOUNCED or not cache_is_cold(kernels):
        return False
    _ANNOUNCED.add(what)
    text = f"compiling the {what} kernels once, ~{seconds:.0f} s; later runs load them from the cache"
    if _SINK:
        _SINK[-1](text)
    else:
        log.info(text)
    return True


class _AfterImport(importlib.abc.MetaPathFinder):
    """Calls ``callback(module)`` right after the module ``name`` has been executed (once)."""

    def __init__(self, name: str, callback: Callable[[ModuleType], None]):
        self.name, self.callback = name, callback

    def find_spec(self, fullname, path, target=None):
        if fullname != self.name:
            return None
        self.remove()  # let the other finders find it; we only wrap its loader
        spec = importlib.util.find_spec(fullname)
        if spec is None or spec.loader is None:
            return spec
        exec_module, callback = spec.loader.exec_module, self.callback

        def exec_then_call(module):
            exec_module(module)
            callback(module)

        spec.loader.exec_module = exec_then_call
        return spec

    def install(self) -> None:
        sys.meta_path.insert(0, self)

    def remove(self) -> None:
        if self in sys.meta_path:
            sys.meta_path.remove(self)


class CompileTimer:
    """Time spent compiling numba kernels inside the block (outermost compilations only).

    Compilations that load from numba's cache are not counted (numba reports only real ones).
    If numba is not imported when the block starts, the timer starts listening when something
    inside the block imports it, so a block that compiles nothing never imports numba.
    ``announce`` receives :func:`announce_compilation`'s line inside the block; if no domain
    announced its kernels, the first real compilation is announced here instead. ``seconds``
    is the total, so callers can report it apart from the solver time.
    """

    def __init__(self, announce: Callable[[str], None] | None = None):
        self.seconds = 0.0
        self.count = 0
        self._depth = 0
        self._t0 = 0.0
        self._announce = announce
        self._said = False
        self._listener = None
        self._hook: _AfterImport | None = None
        self._announced_before: set[str] = set()

    def _said_by_domain(self) -> bool:
        return bool(_ANNOUNCED - self._announced_before)

    def _listen(self, _module: ModuleType | None = None) -> None:
        from numba.core import event

        timer = self

        class _Listener(event.Listener):
            def on_start(self, ev):
                if timer._depth == 0:
                    timer._t0 = time.perf_counter()
                    if not (timer._said or timer._said_by_domain()) and timer._announce is not None:
                        timer._announce("compiling numba kernels (first run only; cached afterwards)...")
                        timer._said = True
                timer._depth += 1

            def on_end(self, ev):
                timer._depth -= 1
                if timer._depth == 0:
                    timer.seconds += time.perf_counter() - timer._t0
                    timer.count += 1

        self._listener = _Listener()
        event.register("numba:compile", self._listener)

    def __enter__(self) -> CompileTimer:
        self._announced_before = set(_ANNOUNCED)
        if self._announce is not None:
            _SINK.append(self._announce)
        if "numba" in sys.modules:
            self._listen()
        else:
            self._hook = _AfterImport("numba", self._listen)
            self._hook.install()
        return self

    def __exit__(self, *exc) -> None:
        if self._hook is not None:
            self._hook.remove()
        if self._listener is not None:
            from numba.core import event

            event.unregister("numba:compile", self._listener)
            self._listener = None
        if self._announce is not None and _SINK and _SINK[-1] is self._announce:
            _SINK.pop()
