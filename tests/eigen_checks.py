"""Checks of eigenvalues that use no eigen-solver of the code under test (tests import this
module by name: pytest puts ``tests/`` on the path for its root conftest)."""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla


def backward_error(lam, M, D, K) -> float:
    """Largest sigma_min(lam^2 M + lam D + K) / (|lam|^2 |M|_2 + |lam| |D|_2 + |K|_2) over the
    eigenvalues ``lam`` (array)."""
    nm, nd, nk = (np.linalg.norm(X, 2) for X in (M, D, K))
    out = 0.0
    for x in np.atleast_1d(lam):
        a = abs(x)
        out = max(out, sla.svdvals(x * x * M + x * D + K)[-1] / (a * a * nm + a * nd + nk))
    return float(out)


def lowest_oscillatory(M, D, K, m: int) -> np.ndarray:
    """The ``m`` lowest damped frequencies [rad/s] of the generalised eigenproblem."""
    n = M.shape[0]
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-K, -D]])
    B = np.block([[np.eye(n), np.zeros((n, n))], [np.zeros((n, n)), M]])
    ref = sla.eig(A, B, right=False)
    return np.sort(ref.imag[ref.imag > 1e-6 * np.abs(ref).max()])[:m]
