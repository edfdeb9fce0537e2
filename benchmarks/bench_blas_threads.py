"""Symmetric eigenproblem (600 x 600) with the default BLAS threads and pinned to one thread.

Why rotaflex pins BLAS/OpenMP pools to one thread per process (threadpoolctl) in single runs
and sweep workers. Prints the median wall time of each; run on an idle and on a loaded machine.

    PYTHONPATH=src python benchmarks/bench_blas_threads.py [--tiny]

``--tiny``: a 100 x 100 matrix, one repeat (checks the script runs).
"""

import argparse
import time

import numpy as np
from threadpoolctl import threadpool_info, threadpool_limits


def median_time(fn, repeat: int = 5) -> float:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return float(np.median(times))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tiny", action="store_true", help="100 x 100, one repeat (checks it runs)")
    tiny = ap.parse_args().tiny
    n, repeat = (100, 1) if tiny else (600, 5)
    rng = np.random.default_rng(0)
    a = rng.standard_normal((n, n))
    a = a + a.T
    pools = ", ".join(f"{p['internal_api']}:{p['num_threads']}" for p in threadpool_info())
    default = median_time(lambda: np.linalg.eigh(a), repeat)
    with threadpool_limits(limits=1):
        one = median_time(lambda: np.linalg.eigh(a), repeat)
    print(f"thread pools: {pools}")
    print(f"eigh {n}x{n}, default threads: {default * 1e3:.1f} ms")
    print(f"eigh {n}x{n}, one thread:      {one * 1e3:.1f} ms")


if __name__ == "__main__":
    main()
