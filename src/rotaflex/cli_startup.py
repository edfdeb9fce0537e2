"""What the command line does so that a verb starts fast (issue 25: ``rotor campbell`` as a
whole process, the rotor disk's first solve): parameters coerced without pydantic, numpy
submodules no verb uses left unexecuted, OpenBLAS started with the thread count a verb runs
with, garbage collection paused while a verb imports its modules. docs/performance.md gives
what each one saves.
"""

from __future__ import annotations

import gc
import os
import sys
from contextlib import contextmanager
from pathlib import Path
from typing import Any


def plain_coercion() -> bool:
    """Coerce this CLI's plain ``str``, ``int``, ``bool`` and ``Path`` parameters without pydantic.

    typer (0.29) checks every parameter that is not a flag through a pydantic ``TypeAdapter``:
    importing pydantic and building the adapters costs every verb ~0.11 s of CPU, a tenth of
    ``rotor campbell --no-figures``. For an annotation ``str``, ``int``, ``bool`` or ``Path``
    without parser, range, choices or path type, a value typer would pass through unchanged
    (a ``str`` or ``bool`` of that type, an ``int`` or a string of ASCII digits for ``int``, a
    non-empty string or a Path for ``Path``, then typer's own path checks) is converted here; any other
    value or annotation goes to typer's adapter, so every result and error message is
    typer's. Written against typer's internals (``typer.core.build_runtime_param``,
    ``typer._coercion.RuntimeParam``): if they are not there, nothing is changed and typer
    runs as before (slower, not wrong). Returns whether the plain path is installed.
    """
    from dataclasses import dataclass

    try:
        from typer import core as typer_core
        from typer._coercion import RuntimeParam
        from typer._param_types import coerce_cli_path
    except ImportError:  # pragma: no cover - another typer
        return False
    typer_build = getattr(typer_core, "build_runtime_param", None)
    if typer_build is None or getattr(typer_build, "plain", False):
        return typer_build is not None

    made: dict[str, type] = {}

    def plain_param() -> type:  # made on first use: --help parses no parameter (a class costs ~1 ms)
        if not made:

            @dataclass(frozen=True)
            class PlainParam(RuntimeParam):
                descriptor: Any

                def _coerce_value(self, value: Any, param: Any, ctx: Any) -> Any:
                    kind = self.annotation
                    if (kind is str or kind is bool) and type(value) is kind:
                        return value
                    if kind is int and (
                        type(value) is int or (type(value) is str and value.isascii() and value.isdigit())
                    ):
                        return int(value)
                    if kind is Path and ((type(value) is str and value) or isinstance(value, Path)):
                        try:
                            return coerce_cli_path(
                                Path(value), self.parameter_info, path_type=Path, param=param, ctx=ctx
                            )
                        except (TypeError, AttributeError):  # another typer's signature: typer's own way
                            pass
                    return typer_build(self.descriptor)._coerce_value(value, param=param, ctx=ctx)

            made["class"] = PlainParam
        return made["class"]

    def build_runtime_param(descriptor: Any) -> Any:
        info = getattr(descriptor, "parameter_info", None)
        plain = (
            getattr(descriptor, "annotation", None) in (str, int, bool, Path)
            and getattr(descriptor, "file_annotation", 0) is None
            and getattr(info, "parser", 0) is None
            and getattr(info, "min", 0) is None
            and getattr(info, "max", 0) is None
            and getattr(info, "path_type", 0) is None
            and not getattr(info, "clamp", True)
            and getattr(descriptor, "is_choice", True) is False
        )
        if plain:
            try:
                return plain_param()(parameter_info=info, annotation=descriptor.annotation, descriptor=descriptor)
            except (TypeError, AttributeError):  # another typer's RuntimeParam: typer's own way
                pass
        return typer_build(descriptor)

    build_runtime_param.plain = True
    typer_core.build_runtime_param = build_runtime_param
    return True


plain_coercion()

#: numpy submodules no verb uses that SciPy's array-API layer imports only to copy numpy's
#: namespace (``scipy._lib.array_api_compat.numpy`` reads every public numpy attribute, and
#: numpy imports a submodule on first access): ~0.06 s of every verb that loads scipy.linalg
UNUSED_NUMPY = ("numpy.f2py", "numpy.testing")


def defer_unused_numpy(names: tuple[str, ...] = UNUSED_NUMPY) -> list[str]:
    """Make the numpy submodules ``names`` lazy: loaded on their first attribute access.

    Each module not yet imported is registered with :class:`importlib.util.LazyLoader` (in
    ``sys.modules`` and as numpy's attribute), so taking a reference to it, as SciPy's
    namespace copy does, costs nothing, while any use (``numpy.testing.assert_equal``, an
    import from it) runs the module as a plain import would. Returns the names deferred.
    """
    import importlib.util

    import numpy

    deferred = []
    for name in names:
        if name in sys.modules:
            continue
        spec = importlib.util.find_spec(name)
        if spec is None or spec.loader is None:  # pragma: no cover - a numpy without it
            continue
        spec.loader = importlib.util.LazyLoader(spec.loader)
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        spec.loader.exec_module(module)
        setattr(numpy, name.rpartition(".")[2], module)
        deferred.append(name)
    return deferred


def blas_threads_at_load() -> None:
    """Start OpenBLAS with the thread count a verb runs with (``ROTAFLEX_BLAS_THREADS``, else 1).

    A verb runs inside ``rotaflex.cli._limit_threads`` anyway; this sets ``OPENBLAS_NUM_THREADS`` (unless
    the user did) before numpy and SciPy load their OpenBLAS copies, each of which would
    otherwise start a thread per core whose spinning costs a start-up ~0.1 s of CPU on two
    cores (``import numpy, scipy.linalg``: 0.43 s of CPU against 0.30 s). Call it before
    anything imports numpy; afterwards it changes nothing for libraries already loaded.
    """
    count = os.environ.get("ROTAFLEX_BLAS_THREADS", "1")
    if count.isascii() and count.isdigit() and int(count) > 0:
        os.environ.setdefault("OPENBLAS_NUM_THREADS", count)


@contextmanager
def collection_paused():
    """Garbage collection off while a verb imports its modules; yields ``resume()``.

    A verb's imports (numpy, SciPy, xarray, pandas, its own modules) make ~10^5 objects that
    live as long as the process; every full collection during the imports walks all of them
    and frees nothing (the second pass measured 0.11 s of ``rotor campbell --no-figures``).
    ``resume()`` moves what exists to the permanent generation (``gc.freeze``) and turns
    collection back on, as before the verb's function runs; leaving the block turns it on
    in any case (as it was).
    """
    was = gc.isenabled()
    gc.disable()

    def resume() -> None:
        gc.freeze()
        if was:
            gc.enable()

    try:
        yield resume
    finally:
        if was:
            gc.enable()
