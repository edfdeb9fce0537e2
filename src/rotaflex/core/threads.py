"""One BLAS/OpenMP thread per process, for every BLAS library the process uses.

Our matrices are small, and on a loaded machine the extra pool threads cost far more than they
gain (benchmarks/bench_blas_threads.py: a 600x600 eigh 1.36 s with 2 threads under load,
0.23 s with one). A sweep runs one case per core instead. SciPy loads its own OpenBLAS on
first use; a limit set before that does not cover it (its two threads doubled the CPU time of
the geared-rotor eigen-solves, 13.0 s vs 6.9 s), so SciPy's linear algebra is loaded first.
``ROTAFLEX_BLAS_THREADS`` overrides the count.
"""

from __future__ import annotations

import os


def limit_blas_threads(limit: int | None = None):
    """Limit every loaded BLAS/OpenMP pool (SciPy's own included) to ``limit`` threads
    (default ``ROTAFLEX_BLAS_THREADS`` or 1). Returns threadpoolctl's limiter, usable as a
    context manager that restores the previous limits."""
    import scipy.linalg  # noqa: F401 - loads SciPy's BLAS so that the limit covers it
    from threadpoolctl import threadpool_limits

    if limit is None:
        limit = blas_thread_count()
    return threadpool_limits(limits=limit)


def blas_thread_count() -> int:
    """The thread count of ``ROTAFLEX_BLAS_THREADS`` (1 when unset).

    Raises
    ------
    InputError
        The variable is set to anything but a whole number >= 1.
    """
    text = os.environ.get("ROTAFLEX_BLAS_THREADS", "1").strip()
    if not (text.isascii() and text.isdigit() and int(text) >= 1):
        from rotaflex.core.errors import InputError

        raise InputError("ROTAFLEX_BLAS_THREADS", text, "a whole number of threads >= 1 (environment variable)")
    return int(text)
