"""The threaded batched eigen-solve of the Campbell diagram equals one np.linalg.eig call bitwise."""

import numpy as np

from rotaflex.rotor.fe.modal import batched_eig


def test_threaded_chunks_equal_one_call_bitwise():
    A = np.random.default_rng(3).standard_normal((13, 24, 24))  # 13 matrices: unequal chunks
    ref = np.linalg.eig(A)
    for workers in (1, 2, 3):
        lam, vec = batched_eig(A, workers)
        assert np.array_equal(lam, ref[0]) and np.array_equal(vec, ref[1])
    # the eigenpairs are eigenpairs (a check independent of LAPACK agreeing with itself)
    lam, vec = batched_eig(A, 2)
    np.testing.assert_allclose(A @ vec, vec * lam[:, None, :], atol=1e-10)
