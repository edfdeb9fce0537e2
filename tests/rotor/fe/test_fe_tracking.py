"""Mode-tracking assignment and the critical-speed root finder without scipy.optimize.

Both replace a SciPy call on the start-up path of ``rotor campbell``; the references here are
SciPy's own functions (a second implementation) and brute force over all assignments.
"""

import itertools

import numpy as np
import pytest
from scipy.optimize import brentq, linear_sum_assignment

from rotaflex.rotor.fe.critical import brent_root
from rotaflex.rotor.fe.modal import ASSIGN_MARGIN, assign_modes


def _best_by_brute_force(mm: np.ndarray) -> float:
    n, m = mm.shape
    return max(sum(mm[i, c] for i, c in enumerate(cols)) for cols in itertools.permutations(range(m), n))


@pytest.mark.parametrize("seed", range(40))
def test_assignment_is_optimal_and_scipys(seed):
    rng = np.random.default_rng(seed)
    n, m = rng.integers(1, 6), 0
    m = n + rng.integers(0, 4)
    if seed % 2:  # MAC-like: near-identity block (a well-tracked step), noise elsewhere
        mm = 0.2 * rng.random((n, m))
        mm[np.arange(n), rng.permutation(m)[:n]] = 0.9 + 0.1 * rng.random(n)
    else:  # general matrices: often no clear row-wise best, so SciPy decides
        mm = rng.random((n, m))
    rows, cols = assign_modes(mm)
    r_ref, c_ref = linear_sum_assignment(-mm)
    assert np.array_equal(rows, r_ref) and np.array_equal(cols, c_ref)
    assert mm[rows, cols].sum() == pytest.approx(_best_by_brute_force(mm), abs=1e-12)


def test_assignment_ties_and_crossings_go_to_scipy():
    # two tracked modes want the same candidate (a crossing): not the row-wise best
    mm = np.array([[0.9, 0.8, 0.1], [0.95, 0.1, 0.2]])
    rows, cols = assign_modes(mm)
    assert list(cols) == [1, 0] and list(rows) == [0, 1]
    # a tie within the margin: the result is SciPy's, whichever it picks
    tied = np.array([[0.5, 0.5 + ASSIGN_MARGIN / 2], [0.1, 0.2]])
    assert [list(a) for a in assign_modes(tied)] == [list(a) for a in linear_sum_assignment(-tied)]
    # more tracked modes than candidates, and NaN: SciPy's answer (or its error)
    wide = np.array([[0.9], [0.8]])
    assert [list(a) for a in assign_modes(wide)] == [list(a) for a in linear_sum_assignment(-wide)]
    with pytest.raises(ValueError):
        assign_modes(np.array([[np.nan, 0.5], [0.1, 0.9]]))


FUNCTIONS = [
    (lambda x: x**3 - 2 * x - 5, 2.0, 3.0),
    (lambda x: np.cos(x) - x, 0.0, 1.0),
    (lambda x: np.exp(x) - 1e3, 0.0, 20.0),
    (lambda x: (x - 1.234) ** 3 + 1e-4 * (x - 1.234), -5.0, 7.0),  # nearly a triple root: slow
    (lambda x: np.tanh(50 * (x - 0.3)), -1.0, 1.0),  # steep: interpolation rejected often
    (lambda x: 1e-3 * np.sin(3 * x) + 0.1 * (x - 2.0), 0.5, 4.0),
    (lambda x: x - 700.0 + 1e-9 * x**2, 100.0, 1000.0),
]


@pytest.mark.parametrize("k", range(len(FUNCTIONS)))
@pytest.mark.parametrize("tol", [(2e-12, 8.9e-16), (1e-6, 1e-10), (1e-14, 4 * np.finfo(float).eps)])
def test_brent_root_is_brentq_to_the_bit(k, tol):
    f, a, b = FUNCTIONS[k]
    calls_ours, calls_ref = [], []
    ours = brent_root(lambda x: calls_ours.append(x) or f(x), a, b, xtol=tol[0], rtol=tol[1])
    ref = brentq(lambda x: calls_ref.append(x) or f(x), a, b, xtol=tol[0], rtol=tol[1])
    assert ours == ref
    assert calls_ours == calls_ref  # the same points, in the same order
    assert abs(f(ours)) <= abs(f(ours + 10 * (tol[0] + tol[1] * abs(ours)))) + 1e-300  # near a root


def test_brent_root_errors_like_brentq():
    with pytest.raises(ValueError, match="different signs"):
        brent_root(lambda x: x * x + 1, -1.0, 1.0, 1e-12, 1e-15)
    with pytest.raises(ValueError, match="NaN"):
        brent_root(lambda x: np.nan if x > 0 else -1.0, -1.0, 1.0, 1e-12, 1e-15)
    with pytest.raises(RuntimeError):
        brent_root(lambda x: np.tanh(50 * (x - 0.3)), -1.0, 1.0, 1e-12, 4 * np.finfo(float).eps, maxiter=3)
    with pytest.raises(RuntimeError):
        brentq(lambda x: np.tanh(50 * (x - 0.3)), -1.0, 1.0, xtol=1e-12, maxiter=3)
    assert brent_root(lambda x: x, 0.0, 1.0, 1e-12, 1e-15) == 0.0
