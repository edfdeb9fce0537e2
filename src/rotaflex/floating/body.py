"""Flexible bodies as data: quadrature points with masses and mode shapes, and their integrals.

A :class:`Body` is a set of ``N`` mass points (quadrature points of the mass distribution):
mass ``m_k`` [kg], undeformed body-frame position ``r_k`` [m] and mode-shape rows ``Phi_k``
(3 x n, [1/sqrt(kg)] for mass-orthonormal modes), plus the modal stiffness ``K_b`` [N m/kg].
Every body integral of the paper is a vectorised sum over the points (:func:`integrals`,
:func:`gamma`, :func:`m_tilde`, :func:`phi_hat`).

Three sources of bodies:

* :func:`rotaflex.floating.beam.uniform_beam` -- uniform Euler-Bernoulli beam with analytic
  modes (free-free or cantilever), planar (deflection along y) or spatial (along y and z);
* :func:`rotaflex.floating.fe.frame_body` -- 3-D frame finite elements reduced to free-free modes;
* :func:`point_body` -- user-supplied nodes, masses and mode-shape vectors.

The floating frame of a free-free body is the mean-axis frame: the elastic modes are
mass-orthogonal to the rigid modes, so ``sum m_k Phi_k = 0`` and ``sum m_k r_k~ Phi_k = 0``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from rotaflex.core.errors import InputError

ORTHONORMAL_TOL = 1e-6


def skew(v: np.ndarray) -> np.ndarray:
    """Skew matrices ``v~`` of vectors ``v`` (..., 3) -> (..., 3, 3)."""
    v = np.asarray(v, dtype=float)
    S = np.zeros(v.shape[:-1] + (3, 3))
    S[..., 0, 1], S[..., 0, 2] = -v[..., 2], v[..., 1]
    S[..., 1, 0], S[..., 1, 2] = v[..., 2], -v[..., 0]
    S[..., 2, 0], S[..., 2, 1] = -v[..., 1], v[..., 0]
    return S


@dataclass(frozen=True, eq=False)
class Body:
    """A flexible body as quadrature data.

    Parameters
    ----------
    name : str
        Description.
    masses : ndarray (N,)
        Point masses [kg], all > 0.
    points : ndarray (N, 3)
        Undeformed positions in the body frame [m].
    shapes : ndarray (N, 3, n)
        Mode shapes at the points, mass-orthonormal: ``sum m Phi^T Phi = I``.
    stiffness : ndarray (n, n)
        Modal stiffness ``K_b`` [1/s^2] (diagonal ``omega^2`` for normal modes).
    shape_fn : callable
        ``shape_fn(points (P, 3)) -> (Phi (P, 3, n), Psi (P, 3, n))``: translational and rotational
        mode shapes at arbitrary body points; raises InputError for points outside the body.
    geometric : ndarray (3, 3, n, n) or None
        Unit centrifugal geometric stiffness ``G[a, b]`` (symmetric in ``a, b``): the stiffening
        at body angular velocity ``w`` is ``K_G(w) = sum_ab w_a w_b G[a, b]`` (for a beam along
        the body x axis only ``G[1, 1] = G[2, 2] = K_Gw`` are non-zero); None if not available.
    frame : str
        The floating frame, stated for output.
    length : float
        Characteristic size [m] (divergence guard, tolerances).
    mode_labels : tuple of str
    extra_inertia : ndarray (3, 3)
        Inertia [kg m^2] of rigid (non-elastic) mass about the body origin added to ``J``, e.g. the
        polar inertia of a beam's cross-sections, which a line of points does not carry.
    load_geometric : callable or None
        ``load_geometric(point) -> (3, n, n)``: geometric stiffness per unit body-frame force
        along x, y, z applied at ``point`` (axial load state including the inertia relief of the
        floating body); None if the body cannot provide it (then applied loads do not stiffen).
    planar : bool
        True for a planar line beam (points on the x axis, deflection along y only): its rotation
        about its own axis carries no inertia and is decoupled from in-plane motion, so the
        solvers accept zero inertia about x and require in-plane loads and initial state.
    inextensible : InextensibleBeam or None
        Quadrature data for the exact inextensible kinematics (``solver.kinematics =
        "inextensible"``, :mod:`rotaflex.floating.inextensible`); planar cantilever beams only.
    damping : ndarray (n,) or None
        Modal viscous damping ratios ``zeta_i`` (the modal equations get ``2 zeta_i omega_i
        p_i``); None: undamped. Set with :func:`with_damping`.
    rigid : bool
        True only for :func:`rigid_body` (no elastic modes, for cross-checks against rigid-body
        solvers); a normal body must have at least one elastic mode.
    params : dict
        How the body was made, as plain data for provenance (``source``: the function, and its
        scalar arguments; see :func:`record`).
    """

    name: str
    masses: np.ndarray
    points: np.ndarray
    shapes: np.ndarray
    stiffness: np.ndarray
    shape_fn: Callable = field(repr=False)
    geometric: np.ndarray | None = None
    frame: str = "mean axes"
    length: float = 1.0
    mode_labels: tuple = ()
    extra_inertia: np.ndarray = field(default_factory=lambda: np.zeros((3, 3)))
    rigid: bool = False
    planar: bool = False
    load_geometric: Callable | None = field(default=None, repr=False)
    inextensible: object | None = field(default=None, repr=False)
    params: dict = field(default_factory=dict, repr=False)
    damping: np.ndarray | None = field(default=None, repr=False)

    def __post_init__(self):
        validate_body(self)

    @property
    def n_modes(self) -> int:
        return self.shapes.shape[2]

    @property
    def frequencies(self) -> np.ndarray:
        """Natural frequencies [rad/s] of the (clamped-frame) modal model."""
        ev = np.linalg.eigvalsh(0.5 * (self.stiffness + self.stiffness.T))
        return np.sqrt(np.clip(ev, 0.0, None))

    @property
    def mass(self) -> float:
        return float(self.masses.sum())


def validate_body(b: Body) -> None:
    """Section 5 checks: positive masses/stiffness, modes present, mass-orthonormal."""
    m = np.asarray(b.masses, dtype=float)
    if m.ndim != 1 or m.size == 0 or not np.all(np.isfinite(m)):
        raise InputError("body.masses", f"shape {m.shape}", "a non-empty list of finite masses [kg]")
    if np.any(m <= 0.0):
        k = int(np.argmin(m))
        raise InputError(f"body.masses[{k}]", float(m[k]), "a mass > 0 [kg]")
    if b.points.shape != (m.size, 3):
        raise InputError("body.points", f"shape {b.points.shape}", f"shape ({m.size}, 3) [m]")
    if b.shapes.ndim != 3 or b.shapes.shape[:2] != (m.size, 3):
        raise InputError("body.shapes", f"shape {b.shapes.shape}", f"shape ({m.size}, 3, n_modes)")
    n = b.shapes.shape[2]
    if b.rigid:
        if n != 0:
            raise InputError("body.n_modes", n, "0 for a rigid body")
        return
    if n == 0:
        raise InputError(
            "body.n_modes",
            0,
            "at least one elastic mode (a body with no elastic "
            "modes is rigid: use the rotor domain's rigid-body solver)",
        )
    K = np.asarray(b.stiffness, dtype=float)
    if K.shape != (n, n):
        raise InputError("body.stiffness", f"shape {K.shape}", f"shape ({n}, {n})")
    ev = np.linalg.eigvalsh(0.5 * (K + K.T))
    if np.any(ev <= 0.0) or not np.allclose(K, K.T, rtol=1e-9, atol=1e-12 * np.abs(K).max()):
        raise InputError(
            "body.stiffness",
            f"eigenvalues min {ev.min():.6g}",
            "a symmetric positive definite modal stiffness (frequencies > 0)",
        )
    if b.damping is not None:
        z = np.asarray(b.damping, dtype=float)
        if z.shape != (n,) or not np.all(np.isfinite(z)) or np.any(z < 0.0) or np.any(z >= 1.0):
            raise InputError("body.damping_ratio", plain(z), f"{n} ratios (one per mode) or one ratio, each in [0, 1)")
        if np.abs(K - np.diag(np.diag(K))).max() > 1e-9 * np.abs(K).max():
            raise InputError("body.damping_ratio", plain(z), "none for a body whose modal stiffness is not diagonal")
    Mb = np.einsum("k,kai,kaj->ij", m, b.shapes, b.shapes)
    dev = float(np.abs(Mb - np.eye(n)).max())
    if dev > ORTHONORMAL_TOL:
        raise InputError(
            "body.shapes",
            f"max |sum m Phi^T Phi - I| = {dev:.3e}",
            f"mass-orthonormal modes (deviation <= {ORTHONORMAL_TOL:g})",
        )


def with_damping(body: Body, ratio) -> Body:
    """``body`` with modal damping ratios (one number for every mode, or one per mode).

    Examples
    --------
    >>> from rotaflex.floating.beam import uniform_beam
    >>> b = with_damping(uniform_beam(2.0, 1.0, 40.0, 3), 0.01)
    >>> b.damping.tolist()
    [0.01, 0.01, 0.01]
    """
    from dataclasses import replace

    z = np.broadcast_to(np.asarray(ratio, dtype=float), (body.n_modes,)) if np.ndim(ratio) == 0 else ratio
    z = np.asarray(z, dtype=float)
    return replace(body, damping=z.copy(), params={**body.params, "damping_ratio": plain(z)})


def record(body: Body) -> dict:
    """The body as plain data for a result's ``attrs["config"]``: its name, size, frame, modal
    frequencies [rad/s] and the parameters it was made from (``body.params``)."""
    return {
        "name": body.name,
        **body.params,
        "n_points": int(body.masses.size),
        "n_modes": int(body.n_modes),
        "mass": float(body.mass),
        "frame": body.frame,
        "frequencies": [float(f) for f in body.frequencies],
    }


def plain(value):
    """``value`` with arrays and tuples turned into (nested) lists of floats, for JSON."""
    if value is None or isinstance(value, (bool, str, int, float)):
        return value
    if isinstance(value, dict):
        return {str(k): plain(v) for k, v in value.items()}
    return np.asarray(value, dtype=float).tolist()


#: library names of a point body's fields -> their paths in a case file (``[body.points]``)
POINT_FIELDS = {
    "body.masses": "body.points.masses",
    "body.points": "body.points.positions",
    "body.shapes": "body.points.shapes",
    "body.n_modes": "body.points.shapes",
    "body.frequencies": "body.points.frequencies",
    "body.stiffness": "body.points.frequencies",
    "body.rotation_shapes": "body.points.rotation_shapes",
    "body.rotary_inertias": "body.points.rotary_inertias",
    "body.geometric": "body.points.geometric",
}


def renamed(exc: InputError, table: dict[str, str], default_prefix: str = "") -> InputError:
    """The same error with its field named by ``table`` (old prefix -> new prefix, whole path
    components only); other ``body.*`` fields get ``default_prefix`` instead of ``body.``."""
    f = exc.field
    for old, new in table.items():
        if f == old or f.startswith(old + "[") or f.startswith(old + "."):
            return InputError(new + f[len(old) :], exc.value, exc.allowed)
    if default_prefix and f.startswith("body.") and not f.startswith(default_prefix):
        tail = f[len("body.") :]
        if tail.split(".")[0].split("[")[0] not in ("attachment_points", "attach_at_loads"):
            return InputError(default_prefix + tail, exc.value, exc.allowed)
    return exc


# ----------------------------------------------------------------------------------------
# body integrals (eq. 23, 25, 32), all by vectorised quadrature over the points
# ----------------------------------------------------------------------------------------
def integrals(body: Body, q: np.ndarray | None = None) -> dict[str, np.ndarray]:
    """Mass-matrix integrals of eq. 23 at modal displacement ``q`` (default 0).

    Returns
    -------
    dict
        ``m`` [kg], ``S`` (3,) first moment [kg m] (``S~ = skew(S)``), ``Phibar`` (3, n),
        ``J`` (3, 3) inertia tensor [kg m^2], ``Phitilde`` (3, n) ``= sum m c~ Phi``,
        ``Mb`` (n, n), ``M`` the assembled (6+n)^2 mass matrix of eq. 22 in the ordering
        ``x = [V_o, w, p]``.
    """
    m, Phi = body.masses, body.shapes
    n = Phi.shape[2]
    q = np.zeros(n) if q is None else np.asarray(q, dtype=float)
    c = body.points + Phi @ q
    S = m @ c
    J = np.einsum(
        "k,kab->ab",
        m,
        np.einsum("ka,ka->k", c, c)[:, None, None] * np.eye(3) - c[:, :, None] * c[:, None, :],
    )
    J = J + body.extra_inertia
    Phibar = np.einsum("k,kaj->aj", m, Phi)
    Phit = np.einsum("k,kab,kbj->aj", m, skew(c), Phi)
    Mb = np.einsum("k,kai,kaj->ij", m, Phi, Phi)
    M = np.zeros((6 + n, 6 + n))
    M[:3, :3] = m.sum() * np.eye(3)
    M[:3, 3:6], M[3:6, :3] = -skew(S), skew(S)
    M[3:6, 3:6] = J
    M[:3, 6:], M[6:, :3] = Phibar, Phibar.T
    M[3:6, 6:], M[6:, 3:6] = Phit, Phit.T
    M[6:, 6:] = Mb
    return {"m": m.sum(), "S": S, "Phibar": Phibar, "J": J, "Phitilde": Phit, "Mb": Mb, "M": M}


def gamma(body: Body, w) -> np.ndarray:
    """``Gamma(w) = int rho Phi^T w~ Phi dD`` (eq. 32e), (n, n), skew-symmetric."""
    W = skew(np.asarray(w, dtype=float))
    return np.einsum("k,kai,ab,kbj->ij", body.masses, body.shapes, W, body.shapes)


def m_tilde(body: Body, w) -> np.ndarray:
    """``M~(w) = int rho Phi^T w~ w~ Phi dD`` (eq. 32f), (n, n), symmetric."""
    W = skew(np.asarray(w, dtype=float))
    return np.einsum("k,kai,ab,kbj->ij", body.masses, body.shapes, W @ W, body.shapes)


def phi_hat(body: Body, w) -> np.ndarray:
    """``Phi^(w) = 2 int rho r~ w~ Phi dD - w~ Phitilde_b`` (eq. 32d as printed), (3, n)."""
    W = skew(np.asarray(w, dtype=float))
    R = skew(body.points)
    first = 2.0 * np.einsum("k,kab,bc,kcj->aj", body.masses, R, W, body.shapes)
    return first - W @ integrals(body)["Phitilde"]


_PAIRS = {"xx": (0, 0), "yy": (1, 1), "zz": (2, 2), "xy": (0, 1), "xz": (0, 2), "yz": (1, 2)}


def geometric_tensor_from(data, n: int) -> np.ndarray:
    """Unit geometric stiffness tensor (3, 3, n, n) from a dict of pairs or a full array."""
    G = np.zeros((3, 3, n, n))
    if isinstance(data, dict):
        for key, mat in data.items():
            if key not in _PAIRS:
                raise InputError(f"body.geometric.{key}", key, "one of " + ", ".join(_PAIRS))
            a, b = _PAIRS[key]
            G[a, b] = G[b, a] = _sym_matrix(mat, n, f"body.geometric.{key}")
    else:
        arr = np.asarray(data, dtype=float)
        if arr.shape != (3, 3, n, n):
            raise InputError("body.geometric", f"shape {arr.shape}", f"shape (3, 3, {n}, {n})")
        for a in range(3):
            for b in range(3):
                G[a, b] = _sym_matrix(arr[a, b], n, f"body.geometric[{a}][{b}]")
        if not np.allclose(G, np.swapaxes(G, 0, 1)):
            raise InputError("body.geometric", "G[a, b] != G[b, a]", "symmetric in a, b")
    return G


def _sym_matrix(mat, n, where):
    m = np.asarray(mat, dtype=float)
    if m.shape != (n, n) or not np.all(np.isfinite(m)):
        raise InputError(where, f"shape {m.shape}", f"a finite {n} x {n} matrix")
    if not np.allclose(m, m.T, rtol=1e-9, atol=1e-12 * max(np.abs(m).max(), 1e-300)):
        raise InputError(where, "non-symmetric", "a symmetric matrix [1]")
    return 0.5 * (m + m.T)


def check_inertia(J, where: str) -> None:
    """A physical inertia tensor: symmetric, principal moments > 0 that satisfy the triangle
    inequality ``J1 + J2 >= J3`` (every mass distribution does; e.g. [10, 1, 1] does not)."""
    J = np.asarray(J, dtype=float)
    if J.shape != (3, 3) or not np.all(np.isfinite(J)) or not np.allclose(J, J.T):
        raise InputError(where, J.tolist(), "a symmetric 3 x 3 tensor or 3 principal moments [kg m^2]")
    ev = np.linalg.eigvalsh(J)
    shown = ev.tolist() if not np.allclose(J, np.diag(np.diag(J))) else np.diag(J).tolist()
    if ev.min() <= 0:
        raise InputError(where, shown, "principal moments > 0 [kg m^2]")
    if ev[0] + ev[1] < ev[2] * (1 - 1e-12):
        raise InputError(where, shown, "principal moments with J1 + J2 >= J3 (triangle inequality) [kg m^2]")


def rigid_body(mass: float, inertia, *, name: str = "rigid body") -> Body:
    """A body without elastic modes (cross-check path only, e.g. against the rotor domain).

    Parameters
    ----------
    mass : float
        Mass [kg] (> 0), concentrated at the body origin (the centre of mass).
    inertia : array (3,) or (3, 3)
        Principal moments about body x, y, z, or the full inertia tensor about the origin
        [kg m^2] (symmetric positive definite).
    """
    J = np.asarray(inertia, dtype=float)
    J = np.diag(J) if J.shape == (3,) else J
    check_inertia(J, "body.inertia")

    def shape_fn(pts):
        pts = np.atleast_2d(np.asarray(pts, dtype=float))
        return np.zeros((len(pts), 3, 0)), np.zeros((len(pts), 3, 0))

    return Body(
        name=name,
        masses=np.array([float(mass)]),
        points=np.zeros((1, 3)),
        shapes=np.zeros((1, 3, 0)),
        stiffness=np.zeros((0, 0)),
        shape_fn=shape_fn,
        frame="centre of mass (rigid body)",
        length=float(np.sqrt(np.trace(J) / mass)) if mass > 0 else 1.0,
        extra_inertia=J,
        rigid=True,
    )


# ----------------------------------------------------------------------------------------
# user-supplied points
# ----------------------------------------------------------------------------------------
def point_body(
    masses,
    positions,
    shapes,
    frequencies=None,
    stiffness=None,
    rotation_shapes=None,
    *,
    rotary_inertias=None,
    geometric=None,
    name: str = "user-supplied point body",
) -> Body:
    """A body from nodes with masses and mode-shape vectors (e.g. exported from an FE program).

    Parameters
    ----------
    masses : array (N,)
        Nodal masses [kg] (> 0).
    positions : array (N, 3)
        Nodal positions in the body frame [m].
    shapes : array (n, N, 3)
        Mode ``j`` displacement vector at node ``k``: ``shapes[j, k]``; must be mass-orthonormal.
    frequencies : array (n,), optional
        Natural frequencies [rad/s] (> 0); gives ``K_b = diag(omega^2)``.
    stiffness : array (n, n), optional
        Modal stiffness (instead of ``frequencies``).
    rotation_shapes : array (n, N, 3), optional
        Nodal rotation per unit modal coordinate [rad]; needed for torques applied at nodes.
    rotary_inertias : array (N, 3), optional
        Principal rotary inertias of the nodes about body x, y, z [kg m^2] (each obeying the
        triangle inequality). They are added to the rigid-body inertia ``J``; the elastic
        equations use the translational node masses only (``sum m Phi^T Phi = I`` is checked).
    geometric : dict or array (3, 3, n, n), optional
        Unit centrifugal geometric stiffness (from the user's FE program: the modal projection
        of the geometric stiffness of the axial stress under the centrifugal load of
        ``w_a w_b = 1``), as ``{"xx": (n, n), "yy": ..., "xy": ...}`` (missing pairs are zero) or
        a full tensor; ``K_G(w) = sum_ab w_a w_b G[a, b]``. Without it the body has no geometric
        stiffness option.

    Output points and load points must coincide with a node. Errors name the fields as a case
    file does (``body.points.masses[1]``, ``body.points.frequencies`` for ``stiffness`` too).
    """
    args = (masses, positions, shapes, frequencies, stiffness, rotation_shapes, rotary_inertias, geometric, name)
    try:
        return _point_body(*args)
    except InputError as exc:
        table = POINT_FIELDS if stiffness is None else {**POINT_FIELDS, "body.stiffness": "body.points.stiffness"}
        raise renamed(exc, table) from None


def _point_body(masses, positions, shapes, frequencies, stiffness, rotation_shapes, rotary_inertias, geometric, name):
    m = np.asarray(masses, dtype=float).ravel()
    P = np.asarray(positions, dtype=float).reshape(-1, 3)
    S = np.asarray(shapes, dtype=float)
    if S.size == 0:
        S = S.reshape(0, m.size, 3)
    if S.ndim != 3 or S.shape[1:] != (m.size, 3):
        raise InputError("body.shapes", f"shape {S.shape}", f"an array (n_modes, {m.size}, 3)")
    Phi = np.transpose(S, (1, 2, 0))
    n = Phi.shape[2]
    if stiffness is not None:
        K = np.asarray(stiffness, dtype=float)
    elif frequencies is not None:
        f = np.asarray(frequencies, dtype=float).ravel()
        if f.size != n:
            raise InputError("body.frequencies", f.tolist(), f"{n} frequencies [rad/s]")
        if np.any(f <= 0):
            k = int(np.argmin(f))
            raise InputError(f"body.frequencies[{k}]", float(f[k]), "a frequency > 0 [rad/s]")
        K = np.diag(f**2)
    else:
        raise InputError("body.frequencies", "<missing>", "frequencies [rad/s] or a stiffness matrix")
    Psi_nodes = None
    if rotation_shapes is not None:
        R = np.asarray(rotation_shapes, dtype=float)
        if R.shape != S.shape:
            raise InputError("body.rotation_shapes", f"shape {R.shape}", f"shape {S.shape}")
        Psi_nodes = np.transpose(R, (1, 2, 0))
    extra = np.zeros((3, 3))
    if rotary_inertias is not None:
        Ir = np.asarray(rotary_inertias, dtype=float)
        if Ir.shape != (m.size, 3):
            raise InputError("body.rotary_inertias", f"shape {Ir.shape}", f"shape ({m.size}, 3)")
        for k in range(m.size):
            if np.any(Ir[k] != 0.0):
                check_inertia(np.diag(Ir[k]), f"body.rotary_inertias[{k}]")
        extra = np.diag(Ir.sum(axis=0))
    size = float(np.ptp(P, axis=0).max()) if m.size > 1 else 1.0
    size = size if size > 0 else 1.0

    def shape_fn(pts):
        pts = np.atleast_2d(np.asarray(pts, dtype=float))
        d = np.linalg.norm(pts[:, None, :] - P[None, :, :], axis=2)
        idx = np.argmin(d, axis=1)
        bad = d[np.arange(len(pts)), idx] > 1e-9 * size
        if np.any(bad):
            k = int(np.argmax(bad))
            raise InputError("point", pts[k].tolist(), "the position of one of the body's nodes [m]")
        Psi = Psi_nodes[idx] if Psi_nodes is not None else np.full((len(pts), 3, n), np.nan)
        return Phi[idx], Psi

    return Body(
        name=name,
        masses=m,
        points=P,
        shapes=Phi,
        stiffness=K,
        shape_fn=shape_fn,
        geometric=None if geometric is None else geometric_tensor_from(geometric, n),
        frame="as supplied (mean axes if the modes are free-free)",
        length=size,
        mode_labels=tuple(f"mode{j + 1}" for j in range(n)),
        extra_inertia=extra,
        params={"source": "point_body"},
    )
