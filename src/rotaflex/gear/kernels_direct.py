"""Direct (non-iterative) solve of one constraint pass: numba kernels.

The error of a pass after a multiplier change ``dmu`` is ``e + C dmu`` with
``C = G W G^T`` (see :func:`rotaflex.gear.kernels.iterate_pass`). Split into the tie rows ``t``
and the contact row ``c``::

    C = [[C_t, c_t], [c_t^T, c_cc]],   C_t = C_0 + sum_g (c1 / J_g) b_g b_g^T

``C_0 = c1 M_t^-1 - c2 M_t^-1 K_tt M_t^-1`` (tie nodes, disk frame) does not change during a
run: it is factored once per pass type (banded Cholesky after a reverse Cuthill-McKee
ordering, :func:`factor_tie_blocks`). The disk terms ``b_g`` (one per gear, they turn with the
tie positions) enter through the Woodbury identity (a 2 x 2 system) and the contact row through
its Schur complement, so every pass is solved exactly with a few banded triangular solves.

Unilateral contact: with ``s_0`` the contact error of the tie-only solution (contact force set
to zero), the force stays zero if ``s_0 <= tol`` or contact is not allowed in this pass;
otherwise the contact row is made active and ``p = p_0 - s_0 / sigma < 0`` (``sigma > 0`` the
Schur complement). For one contact row this active-set choice is the exact solution of the
linear complementarity problem.
"""

from __future__ import annotations

import numpy as np
from numba import njit


def factor_tie_blocks(model, dt: float):
    """Banded Cholesky factors of C_0 for the three passes, with the Woodbury data.

    Returns ``(packed, perm, bw)``. ``packed`` (3, n + 1, bw + 3) holds per pass: rows 0..n-1,
    columns 0..bw the band ``L[i, i - k]`` (permuted order), columns bw + 1, bw + 2 the vectors
    C_0^-1 b_g of the reference disk vectors, row n the 2 x 2 matrix
    diag(J_g / c1) + B^T C_0^-1 B (first four entries). ``perm`` (n,) is the row order, ``bw``
    the lower bandwidth.
    """
    import scipy.sparse as sp
    from scipy.sparse.csgraph import reverse_cuthill_mckee

    nt = len(model.tie_node)
    n = 2 * nt
    mt = np.repeat(model.minv[model.tie_node], 2)
    ktt = np.zeros((n, n))
    for i, j, b in zip(model.tb_i, model.tb_j, model.tb_b, strict=True):
        ktt[2 * i : 2 * i + 2, 2 * j : 2 * j + 2] = b
    pattern = sp.csr_matrix((np.abs(ktt) > 0) | np.eye(n, dtype=bool))
    perm = np.asarray(reverse_cuthill_mckee(pattern, symmetric_mode=True), dtype=np.int64)
    kp = ktt[np.ix_(perm, perm)]
    rows, cols = np.nonzero(kp)
    bw = int(np.max(np.abs(rows - cols))) if len(rows) else 0
    lband = np.zeros((3, n, bw + 1))
    for p, (c1, c2) in enumerate(((dt * dt / 2, dt**4 / 24), (dt, dt**3 / 6), (1.0, 0.0))):
        c0 = c1 * np.diag(mt) - c2 * (mt[:, None] * ktt * mt[None, :])
        low = np.linalg.cholesky(c0[np.ix_(perm, perm)])
        for k in range(bw + 1):
            lband[p, k:, k] = np.diagonal(low, -k)
    # Woodbury data of the reference disk vectors b_g = J X_k (the tie positions once the ties
    # hold); the small change of b_g during a step is absorbed by the refinement of
    # :func:`rotaflex.gear.kernels.direct_solve`.
    nb = bw + 1
    packed = np.zeros((3, n + 1, nb + 2))
    packed[:, :n, :nb] = lband
    bmat = np.zeros((n, 2))
    xl = model.xloc[model.tie_node]
    for k, g in enumerate(model.tie_gear):
        bmat[2 * k, g] = -xl[k, 1]
        bmat[2 * k + 1, g] = xl[k, 0]
    for p, c1 in enumerate((dt * dt / 2, dt, 1.0)):
        y = np.empty((2, n))
        s2 = np.empty((2, 2))
        prepare_woodbury(np.ascontiguousarray(lband[p]), perm, bmat, c1 / np.asarray(model.inertia, dtype=float), y, s2)
        packed[p, :n, nb] = y[0]
        packed[p, :n, nb + 1] = y[1]
        packed[p, n, :4] = s2.ravel()
    return packed, perm, bw


@njit(cache=True)
def band_solve(lb, r, out):
    """Solve L L^T out = r with the banded factor ``lb`` (n, bw + 1); ``out`` may alias ``r``."""
    n = r.shape[0]
    bw = lb.shape[1] - 1
    for i in range(n):
        acc = r[i]
        k0 = max(0, i - bw)
        for j in range(k0, i):
            acc -= lb[i, i - j] * out[j]
        out[i] = acc / lb[i, 0]
    for i in range(n - 1, -1, -1):
        acc = out[i]
        k1 = min(n - 1, i + bw)
        for j in range(i + 1, k1 + 1):
            acc -= lb[j, j - i] * out[j]
        out[i] = acc / lb[i, 0]


@njit(cache=True)
def tie_solve(lb, perm, bmat, r, out, tmp, y, s2):
    """out = C_t^-1 r with C_t = C_0 + B diag(c1 / J) B^T (Woodbury, B = ``bmat`` (n, 2)).

    ``y`` (2, n) must hold C_0^-1 b_g in permuted order and ``s2`` the 2 x 2 matrix
    diag(1/dcoef) + B^T C_0^-1 B (see :func:`prepare_woodbury`).
    """
    n = r.shape[0]
    for i in range(n):
        tmp[i] = r[perm[i]]
    band_solve(lb, tmp, tmp)
    q0 = 0.0
    q1 = 0.0
    for i in range(n):
        q0 += bmat[perm[i], 0] * tmp[i]
        q1 += bmat[perm[i], 1] * tmp[i]
    det = s2[0, 0] * s2[1, 1] - s2[0, 1] * s2[1, 0]
    z0 = (s2[1, 1] * q0 - s2[0, 1] * q1) / det
    z1 = (-s2[1, 0] * q0 + s2[0, 0] * q1) / det
    for i in range(n):
        out[perm[i]] = tmp[i] - y[0, i] * z0 - y[1, i] * z1


@njit(cache=True)
def prepare_woodbury(lb, perm, bmat, dcoef, y, s2):
    """y[g] = C_0^-1 b_g (permuted order), s2 = diag(1/dcoef) + B^T C_0^-1 B."""
    n = bmat.shape[0]
    for g in range(2):
        for i in range(n):
            y[g, i] = bmat[perm[i], g]
        band_solve(lb, y[g], y[g])
    for g in range(2):
        for h in range(2):
            acc = 0.0
            for i in range(n):
                acc += bmat[perm[i], g] * y[h, i]
            s2[g, h] = acc + (1.0 / dcoef[g] if g == h else 0.0)


@njit(cache=True)
def direct_pass(mode, e0, mu, pbar, packed, perm, tie_gear, bvec, ccol, tol, dmu, buf):
    """Multiplier change ``dmu`` of one pass from the factored C (unilateral contact by active set).

    Parameters
    ----------
    mode : int
        1 displacement, 2 velocity, 3 acceleration pass (contact allowed in passes 2-3 only if
        ``pbar < 0``, as in the iterative scheme).
    e0 : (nc,) array
        Error vector at the current multipliers ``mu`` (tie rows, then the contact row).
    packed, perm : factor data of this pass (see :func:`factor_tie_blocks`) and the row order.
    ccol : (nc,) array
        Contact column of C (tie part, then the diagonal entry).
    dmu : (nc,) output
    buf : (6, nc) scratch
    Returns ``(C_ref dmu)`` at the contact row. ``C_ref`` uses the reference disk vectors, so
    the caller re-evaluates the error with the exact C and repeats if needed.
    """
    nc = e0.shape[0]
    ic = nc - 1
    n = ic
    nb = packed.shape[1] - 2
    lb = packed[:n, :nb]
    y = buf[4:6, :n]
    for r in range(n):
        y[0, r] = packed[r, nb]
        y[1, r] = packed[r, nb + 1]
    s2 = packed[n, :4].reshape((2, 2))
    bmat = np.zeros((n, 2))
    nt = n // 2
    for k in range(nt):
        g = tie_gear[k]
        bmat[2 * k, g] = bvec[k, 0]
        bmat[2 * k + 1, g] = bvec[k, 1]
    tmp = buf[0]
    w = buf[1]
    u = buf[2]
    rhs = buf[3]
    p0 = mu[ic]
    # tie-only solution with the contact force set to zero: dp = -p0
    dp = -p0
    for r in range(n):
        rhs[r] = e0[r] + ccol[r] * dp
    tie_solve(lb, perm, bmat, rhs[:n], w[:n], tmp[:n], y, s2)
    s0 = e0[ic] + ccol[ic] * dp
    for r in range(n):
        s0 -= ccol[r] * w[r]
    allowed = mode == 1 or pbar < 0.0
    if allowed and s0 > tol:
        # active contact: Schur complement of the contact row
        tie_solve(lb, perm, bmat, ccol[:n], u[:n], tmp[:n], y, s2)
        sig = ccol[ic]
        for r in range(n):
            sig -= ccol[r] * u[r]
        ddp = -s0 / sig
        dp += ddp
        for r in range(n):
            w[r] += u[r] * ddp
    for r in range(n):
        dmu[r] = -w[r]
    dmu[ic] = dp
    yc = ccol[ic] * dp
    for r in range(n):
        yc += ccol[r] * dmu[r]
    return yc
