"""Undamped critical speed (UCS) map: critical whirl speeds against the stiffness of chosen supports.

:func:`ucs_solve` is the one solve, on matrices: the Hermitian-definite pencil
``(K0 + k K1 - omega^2 (M - i G)) u = 0`` with its forward roots, or, for an axisymmetric
system, its one-plane reduction. ``rotor ucs`` (:func:`ucs_map`) and ``system ucs``
(:mod:`rotaflex.system.ucs`) call it.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import scipy.linalg as sla

from rotaflex.rotor.fe.modal import PLANAR_BAND
from rotaflex.rotor.fe.model import NDOF_NODE, Rotor


def support_stiffness(n: int, ends, blocks) -> np.ndarray:
    """Stiffness (n, n) of two-DOF supports: ``blocks[i]`` (2, 2) [N/m] between the DOFs
    ``ends[i] = (a, b)`` (x and y of each end; b None: ground), as a bearing joins its ends."""
    K = np.zeros((n, n))
    for (a, b), kb in zip(ends, blocks, strict=True):
        K[np.ix_(a, a)] += kb
        if b is not None:
            K[np.ix_(b, b)] += kb
            K[np.ix_(a, b)] -= kb
            K[np.ix_(b, a)] -= kb
    return K


def ucs_map(
    rotor: Rotor, stiffness, n_modes: int = 4, progress: Callable[[float, float], None] | None = None
) -> np.ndarray:
    """Undamped synchronous forward critical speeds [rad/s] vs isotropic bearing stiffness [N/m].

    Every bearing's coefficients are replaced by kxx = kyy = ``stiffness`` between its node and
    the ground or its other node (no damping, no cross-coupling, no pedestal, no added mass of a
    computed kind): :func:`ucs_solve` on the shaft's lateral DOFs, the whirl omega = Omega
    (``r_i / r_c = 1``), which takes the axisymmetric rotor's one-plane reduction
    (``(K_p - omega^2 (M_p - sym(G_p))) u = 0`` on the x-z plane, :func:`plane_dofs`).

    Returns
    -------
    ndarray (n_stiffness, n_modes)
        Critical speeds [rad/s] (nan where fewer than ``n_modes`` exist).

    ``progress(done, total)`` is called with the stiffness values done.
    """
    nr = rotor.n_rotor_dof  # pedestal DOFs left out: the map's k is the support seen by the shaft
    ends = [
        (NDOF_NODE * node + np.arange(2), None if other is None else NDOF_NODE * other + np.arange(2))
        for node, other, _ in rotor.bearings
    ]
    K1 = support_stiffness(nr, ends, [np.eye(2)] * len(ends))
    eye = np.eye(nr)
    sub = np.ix_(np.arange(nr), np.arange(nr))
    w, _ = ucs_solve(
        rotor.M[sub],
        rotor.G[sub],
        rotor.K_shaft[sub],
        K1,
        stiffness,
        n_modes,
        eye[0::NDOF_NODE],
        eye[1::NDOF_NODE],
        planes=plane_dofs(nr // NDOF_NODE),
        progress=progress,
    )
    return w


def plane_dofs(n_nodes: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """x-z plane DOFs (x, theta_y), their y-z partners (y, theta_x) and the partners' signs
    (1, -1) of ``n_nodes`` nodes in rotor/fe order: the planes of :func:`ucs_solve`."""
    base = NDOF_NODE * np.arange(n_nodes)[:, None]
    ia = (base + np.array([0, 3])).ravel()
    ib = (base + np.array([1, 2])).ravel()
    sb = np.tile([1.0, -1.0], n_nodes)
    return ia, ib, sb


def _one_plane(M, G, K0, K1, planes) -> tuple | None:
    """The one-plane pencil ``(M_p - sym(G_p), K0_p, K1_p)`` of an axisymmetric system, or None.

    With ``planes = (ia, ib, sb)`` (x-z DOFs, their y-z partners and signs), the system is
    axisymmetric when M, K0 and K1 do not couple the planes and are equal in both (up to the
    signs) and G couples only the planes (to 1e-12 of each matrix's largest entry). Forward
    circular whirl ``u_b = -i sb u_a`` then turns ``(K - omega^2 (M - i G)) u = 0`` into the real
    symmetric ``(K_p - omega^2 (M_p - sym(G_ab sb))) u_a = 0``: half the size, real, and only the
    forward roots."""
    ia, ib, sb = planes
    S = np.outer(sb, sb)
    for X in (M, K0, K1):
        tol = 1e-12 * np.max(np.abs(X), initial=0.0)
        if np.max(np.abs(X[np.ix_(ia, ib)]), initial=0.0) > tol:
            return None
        if np.max(np.abs(X[np.ix_(ia, ia)] - S * X[np.ix_(ib, ib)]), initial=0.0) > tol:
            return None
    tol = 1e-12 * np.max(np.abs(G), initial=0.0)
    if max(np.max(np.abs(G[np.ix_(i, i)]), initial=0.0) for i in (ia, ib)) > tol:
        return None
    Gp = G[np.ix_(ia, ib)] * sb[None, :]
    if np.max(np.abs(Gp - Gp.T), initial=0.0) > tol:
        return None
    return M[np.ix_(ia, ia)] - 0.5 * (Gp + Gp.T), K0[np.ix_(ia, ia)], K1[np.ix_(ia, ia)]


#: roots of the UCS pencil closer than this fraction of the largest |root| form one degenerate
#: eigenspace (equal up to the solver's round-off, ~n eps of the largest), in which the whirl
#: senses are separated (see :func:`ucs_solve`); roots split by gyroscopic moments lie farther apart
UCS_CLUSTER_TOL = 1e-12
#: roots mu below this fraction of the largest |mu| are zero (round-off of a massless DOF's
#: infinite frequency): critical speeds above 1e6 times the lowest one are not reported
UCS_ZERO_ROOT = 1e-12


def _whirl_split(V: np.ndarray, B: np.ndarray, K: np.ndarray, Tx: np.ndarray, Ty: np.ndarray):
    """Roots, vectors and forward fractions of a degenerate eigenspace V (n, c) of ``B v = mu K v``:
    the basis of V whose vectors have stationary forward fraction f / (f + b) (generalised
    Hermitian eigenproblem of the two quadratic forms), so a pair of equal forward and backward
    roots is split into the two circular whirls instead of two straight-line (planar) orbits;
    each vector's root is its Rayleigh quotient (the cluster's root to round-off)."""
    P, N = Tx @ V + 1j * (Ty @ V), Tx @ V - 1j * (Ty @ V)
    F, Bk = P.conj().T @ P, N.conj().T @ N
    try:
        frac, C = sla.eigh(F, F + Bk)
    except np.linalg.LinAlgError:  # no lateral motion in some combination: keep the basis
        C, frac = np.eye(V.shape[1]), _forward_fraction(V, Tx, Ty)
    V = V @ C
    mu = np.real(np.sum(V.conj() * (B @ V), 0)) / np.real(np.sum(V.conj() * (K @ V), 0))
    return mu, V, np.clip(frac, 0.0, 1.0)


def _forward_fraction(V: np.ndarray, Tx: np.ndarray, Ty: np.ndarray) -> np.ndarray:
    """``sum |X + iY|^2 / (sum |X + iY|^2 + sum |X - iY|^2)`` of the columns of V (NaN: no lateral motion)."""
    X, Y = Tx @ V, Ty @ V
    f = np.sum(np.abs(X + 1j * Y) ** 2, 0)
    b = np.sum(np.abs(X - 1j * Y) ** 2, 0)
    with np.errstate(invalid="ignore"):
        return f / (f + b)


def ucs_solve(
    M: np.ndarray,
    G: np.ndarray,
    K0: np.ndarray,
    K1: np.ndarray,
    stiffness,
    n_modes: int,
    Tx: np.ndarray,
    Ty: np.ndarray,
    rigid: np.ndarray | None = None,
    progress: Callable[[float, float], None] | None = None,
    planes: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Undamped synchronous forward critical whirl frequencies vs support stiffness, general form.

    With every spin proportional to the whirl frequency omega (rotor i at ``Omega_i = r_i
    omega / r_c`` when the critical is the 1X of rotor c), undamped motion ``u e^{i omega t}``
    obeys ``(K0 + k K1 - omega^2 (M - i G)) u = 0`` with G the gyroscopic matrices weighted by
    ``r_i / r_c``. G is real skew-symmetric, so ``M - i G`` is Hermitian; ``K = K0 + k K1`` is
    real symmetric and positive definite (supported, after ``rigid`` is removed): a
    Hermitian-definite pencil, solved as ``(M - i G) u = mu K u`` (LAPACK zhegvd; real mu),
    ``omega = mu^-1/2`` for mu > 0 (above :data:`UCS_ZERO_ROOT`); mu < 0 are whirls that
    gyroscopic stiffening keeps from ever meeting the 1X line (a disk with Ip > Id). Both
    whirl senses solve it (the pencil is even in omega); a root is forward when its forward
    fraction (``Tx``, ``Ty`` rows: x and y translations, y signed by the sense of its rotor's
    spin relative to rotor c) is at least 0.5 - :data:`PLANAR_BAND` (:func:`critical_whirl`,
    as the Campbell diagram calls its criticals).
    Equal roots (within :data:`UCS_CLUSTER_TOL` of the largest) are split into their whirl
    senses first (:func:`_whirl_split`): a rotor without gyroscopic moments has each forward
    root equal to a backward one.

    Parameters
    ----------
    M, G, K0, K1 : ndarray (n, n)
        Mass [kg], weighted gyroscopic matrix [kg m^2 per rad/s of whirl], stiffness without the
        swept supports [N/m] and the swept supports' stiffness per unit k [1].
    stiffness : array_like (s,)
        Support stiffness values k [N/m].
    n_modes : int
        Forward roots kept per stiffness (lowest first).
    Tx, Ty : ndarray (p, n)
        x and sense-signed y translations of p points as rows acting on the coordinates.
    rigid : ndarray (n, r), optional
        Motions without strain at every k (a free rigid-body twist): the roots are solved in the
        M-orthogonal complement of these (their root omega = 0 is no critical speed).
    progress : callable ``progress(done, total)``, optional
    planes : (ia, ib, sb), optional
        The x-z plane coordinates, their y-z partners and signs (:func:`plane_dofs`). Where the
        system is axisymmetric in them (:func:`_one_plane`), the forward roots are solved on one
        plane (real, half the size: 0.21 s against 7.0 s for 20 stiffness values of a 604-DOF
        rotor); otherwise, or without ``planes``, on the general pencil.

    Returns
    -------
    omega : ndarray (s, n_modes)
        Critical whirl frequencies [rad/s], ascending (NaN where fewer forward roots exist).
    fraction : ndarray (s, n_modes)
        Forward fraction of each root's mode [1].

    Examples
    --------
    A disk m = 2 kg on a massless shaft (k_s = 1e6 N/m) between two bearings of k = 1e6 N/m:
    ``1/k_eq = 1/k_s + 1/(2 k)``, omega = sqrt(k_eq / m).

    >>> import numpy as np
    >>> M = np.diag([2.0, 2.0, 1.0, 1.0]); G = np.zeros((4, 4))
    >>> K0 = np.zeros((4, 4)); K0[:2, :2] = np.eye(2) * 1e6; K0[:2, 2:] = K0[2:, :2] = -np.eye(2) * 1e6
    >>> K0[2:, 2:] = np.eye(2) * 1e6; K1 = np.zeros((4, 4)); K1[2:, 2:] = 2 * np.eye(2)
    >>> w, f = ucs_solve(M * [[1, 1, 1e-9, 1e-9]], G, K0, K1, [1e6], 1, np.eye(4)[[0]], np.eye(4)[[1]])
    >>> round(float(w[0, 0]), 3), float(f[0, 0])
    (577.35, 1.0)
    """
    M, G, K0, K1 = (np.asarray(X, float) for X in (M, G, K0, K1))
    for name, X, sign in (("M", M, 1), ("G", G, -1), ("K0", K0, 1), ("K1", K1, 1)):
        scale = np.max(np.abs(X)) if X.size else 0.0
        if np.max(np.abs(X - sign * X.T), initial=0.0) > 1e-12 * scale:
            raise ValueError(f"ucs_solve: {name} must be {'skew-' if sign < 0 else ''}symmetric")
    stiffness = np.atleast_1d(np.asarray(stiffness, float))
    plane = None if planes is None or (rigid is not None and rigid.size) else _one_plane(M, G, K0, K1, planes)
    if plane is not None:
        return _ucs_one_plane(*plane, stiffness, n_modes, progress)
    Q = None
    if rigid is not None and rigid.size:
        Q = sla.null_space(rigid.T @ M)  # the M-orthogonal complement of the rigid motions
        M, G, K0, K1 = (Q.T @ X @ Q for X in (M, G, K0, K1))
        Tx, Ty = Tx @ Q, Ty @ Q
    B = M - 1j * G
    omega = np.full((stiffness.size, n_modes), np.nan)
    fraction = np.full((stiffness.size, n_modes), np.nan)
    for s, k in enumerate(stiffness):
        K = K0 + k * K1
        mu, V = sla.eigh(B, K, check_finite=False, driver="gvd")  # zhegvd: 0.67 ms against 1.1 ms (52 DOFs)
        frac = _forward_fraction(V, Tx, Ty)
        gap = np.flatnonzero(np.diff(mu) > UCS_CLUSTER_TOL * np.max(np.abs(mu))) + 1
        for a, b in zip(np.r_[0, gap], np.r_[gap, mu.size], strict=True):  # clusters of equal roots
            if b - a > 1:
                mu[a:b], V[:, a:b], frac[a:b] = _whirl_split(V[:, a:b], B, K, Tx, Ty)
        real = mu > UCS_ZERO_ROOT * np.max(np.abs(mu))  # mu ~ 0: a massless DOF (omega infinite)
        keep = np.flatnonzero(real & (frac >= 0.5 - PLANAR_BAND))
        keep = keep[np.argsort(-mu[keep], kind="stable")]  # largest mu: lowest omega
        keep = keep[:n_modes]
        omega[s, : keep.size] = 1.0 / np.sqrt(mu[keep])
        fraction[s, : keep.size] = frac[keep]
        if progress is not None:
            progress(s + 1, stiffness.size)
    return omega, fraction


def _ucs_one_plane(Meff, K0, K1, stiffness, n_modes: int, progress) -> tuple[np.ndarray, np.ndarray]:
    """:func:`ucs_solve` on the one-plane pencil of :func:`_one_plane`: ``Meff u = mu K u``,
    omega = mu^-1/2 for mu > 0 (every root a forward circular whirl: fraction 1)."""
    omega = np.full((stiffness.size, n_modes), np.nan)
    for s, k in enumerate(stiffness):
        mu = sla.eigh(Meff, K0 + k * K1, eigvals_only=True)
        mu = np.sort(mu[mu > 0])[::-1]
        w = 1.0 / np.sqrt(mu[:n_modes])
        omega[s, : w.size] = w
        if progress is not None:
            progress(s + 1, stiffness.size)
    return omega, np.where(np.isnan(omega), np.nan, 1.0)
