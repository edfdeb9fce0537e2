"""3-D Euler-Bernoulli frame elements reduced to free-free elastic modes.

Each element is straight between two nodes with 6 DOFs per node ``(u_x, u_y, u_z, th_x, th_y,
th_z)`` in global axes. Inside an element (local axes ``x`` along it, ``y``, ``z``): axial
displacement and twist are linear, the two transverse deflections are Hermite cubics, and the
section rotations are ``th_x`` (twist), ``th_y = -dw/dx``, ``th_z = dv/dx``.

Mass by quadrature: at each of 3 Gauss points per element, four point masses ``m_g/4`` sit at
``+-a e_y`` and ``+-b e_z`` with ``a^2 = 2 I_z / A`` and ``b^2 = 2 I_y / A``; they carry the
translational mass and the section's rotary and polar inertia (a Rayleigh beam). The FE mass
matrix *is* the quadrature ``sum m N^T N`` over these points, so the modes are mass-orthonormal
with respect to exactly the point data used for the floating-body integrals.
"""

from __future__ import annotations

import numpy as np

from rotaflex.core.errors import InputError
from rotaflex.floating.body import Body, plain, skew

_GP, _GW = np.polynomial.legendre.leggauss(3)
_GP, _GW = 0.5 * (_GP + 1.0), 0.5 * _GW


def _frames(nodes, elements, up):
    d = nodes[elements[:, 1]] - nodes[elements[:, 0]]
    L = np.linalg.norm(d, axis=1)
    if np.any(L <= 0.0):
        k = int(np.argmin(L))
        raise InputError("body.elements", int(k), "elements of non-zero length (distinct nodes)")
    ex = d / L[:, None]
    ref = np.tile(np.asarray(up, dtype=float), (len(ex), 1))
    par = np.abs(np.einsum("ij,ij->i", ref, ex)) > 0.99
    ref[par] = np.array([0.0, 1.0, 0.0]) if abs(up[1]) < 0.99 else np.array([1.0, 0.0, 0.0])
    ey = np.cross(ref, ex)
    ey /= np.linalg.norm(ey, axis=1)[:, None]
    ez = np.cross(ex, ey)
    return L, np.stack([ex, ey, ez], axis=1)  # Lam: rows = local axes in global components


def _local_stiffness(L, EA, GJ, EIy, EIz):
    k = np.zeros((len(L), 12, 12))

    def put(idx, mat):
        k[:, idx[:, None], idx[None, :]] += mat

    a = EA / L
    put(np.array([0, 6]), a[:, None, None] * np.array([[1, -1], [-1, 1]]))
    t = GJ / L
    put(np.array([3, 9]), t[:, None, None] * np.array([[1, -1], [-1, 1]]))
    for idx, EI, sg in ((np.array([1, 5, 7, 11]), EIz, 1.0), (np.array([2, 4, 8, 10]), EIy, -1.0)):
        L1 = L[:, None, None]
        m = np.array([[12, 6, -12, 6], [6, 4, -6, 2], [-12, -6, 12, -6], [6, 2, -6, 4]], float)
        scale = np.array([[1, 1, 1, 1], [1, 1, 1, 1], [1, 1, 1, 1], [1, 1, 1, 1]], float)
        pw = np.array([[0, 1, 0, 1], [1, 2, 1, 2], [0, 1, 0, 1], [1, 2, 1, 2]])
        sgn = np.array([[1, sg, 1, sg], [sg, 1, sg, 1], [1, sg, 1, sg], [sg, 1, sg, 1]])
        put(idx, (EI / L**3)[:, None, None] * m * scale * L1**pw * sgn)
    return k


def _interp(s, L):
    """Local interpolation at fraction ``s`` (P,) of elements of length ``L`` (P,).

    Returns ``Nu`` (P, 3, 12) displacement and ``Nt`` (P, 3, 12) section rotation matrices.
    """
    P = len(s)
    Nu = np.zeros((P, 3, 12))
    Nt = np.zeros((P, 3, 12))
    h1, h2 = 1 - 3 * s**2 + 2 * s**3, L * (s - 2 * s**2 + s**3)
    h3, h4 = 3 * s**2 - 2 * s**3, L * (-(s**2) + s**3)
    d1, d2 = (-6 * s + 6 * s**2) / L, 1 - 4 * s + 3 * s**2
    d3, d4 = (6 * s - 6 * s**2) / L, -2 * s + 3 * s**2
    Nu[:, 0, 0], Nu[:, 0, 6] = 1 - s, s
    Nu[:, 1, 1], Nu[:, 1, 5], Nu[:, 1, 7], Nu[:, 1, 11] = h1, h2, h3, h4
    Nu[:, 2, 2], Nu[:, 2, 4], Nu[:, 2, 8], Nu[:, 2, 10] = h1, -h2, h3, -h4
    Nt[:, 0, 3], Nt[:, 0, 9] = 1 - s, s
    Nt[:, 2, 1], Nt[:, 2, 5], Nt[:, 2, 7], Nt[:, 2, 11] = d1, d2, d3, d4  # th_z = v'
    Nt[:, 1, 2], Nt[:, 1, 4], Nt[:, 1, 8], Nt[:, 1, 10] = -d1, d2, -d3, d4  # th_y = -w'
    return Nu, Nt


def frame_body(
    nodes,
    elements=None,
    *,
    e: float,
    g: float,
    rho: float,
    area: float,
    iy: float,
    iz: float,
    j: float,
    n_modes: int,
    up=(0.0, 0.0, 1.0),
    name: str = "FE frame body",
    attachment_points=(),
    moment_points=(),
    geometric: bool = True,
) -> Body:
    """Free-free modes of a 3-D frame model as a :class:`Body` (mean axes).

    Parameters
    ----------
    nodes : array (N, 3)
        Node positions in the body frame [m].
    elements : array (E, 2) of int, optional
        Node pairs; default: a chain ``(0,1), (1,2), ...``.
    e, g : float
        Young's and shear modulus [Pa] (> 0).
    rho : float
        Density [kg/m^3] (> 0).
    area, iy, iz, j : float
        Section area [m^2], second moments about local y and z [m^4], torsion constant [m^4].
    n_modes : int
        Number of lowest elastic (non-rigid) modes kept (>= 1).
    up : (3,) floats
        Reference vector for the element local y axis (``y = up x x``).
    attachment_points : sequence of (3,) floats
        Load points [m] (on an element axis) at which inertia-relief attachment modes for unit
        forces along x, y, z are added to the elastic modes (see :func:`augment_ritz`).
    geometric : bool
        Compute the unit centrifugal geometric stiffness ``G[a, b]`` from the axial forces of the
        inertia-relieved static centrifugal load (see :func:`centrifugal_geometric`).

    Returns
    -------
    Body
        Points: 12 mass points per element (3 Gauss points x 4 section points).
    """
    for fname, v in (
        ("e", e),
        ("g", g),
        ("rho", rho),
        ("area", area),
        ("iy", iy),
        ("iz", iz),
        ("j", j),
    ):
        if not (np.isfinite(v) and v > 0):
            raise InputError(f"body.{fname}", v, "a number > 0 (SI units)")
    X = np.asarray(nodes, dtype=float).reshape(-1, 3)
    nn = len(X)
    El = np.array([[i, i + 1] for i in range(nn - 1)] if elements is None else elements, dtype=int)
    if El.ndim != 2 or El.shape[1] != 2 or El.size == 0 or El.min() < 0 or El.max() >= nn:
        raise InputError("body.elements", El.tolist(), f"pairs of node indices in [0, {nn - 1}]")
    L, Lam = _frames(X, El, up)
    if np.any(L <= 0):
        raise InputError("body.elements", int(np.argmin(L)), "elements of non-zero length")
    ndof = 6 * nn
    if n_modes < 1 or n_modes > ndof - 6:
        raise InputError("body.n_modes", n_modes, f"an integer in [1, {ndof - 6}]")
    T, K, dofs = _stiffness(L, Lam, El, ndof, e, g, area, iy, iz, j)
    mass, pos, Nglob, E_, M = _mass_points(X, El, L, Lam, T, dofs, ndof, rho, area, iy, iz)
    _require_connected(El, nn)
    from scipy.linalg import eigh

    w2, V = eigh(K, M, subset_by_index=[0, min(ndof - 1, 6 + n_modes - 1)])
    keep = slice(6, 6 + n_modes)
    Rg, modes = _mean_axes(X, M, V[:, keep])
    om2 = w2[keep]
    size = float(np.ptp(X, axis=0).max())
    interp = _interpolator(X, El, L, Lam, T, dofs, size)
    labels = [f"fe{k + 1}" for k in range(n_modes)]
    if len(attachment_points) or len(moment_points):
        U = inertia_relief_solve(K, M, Rg, _unit_loads(interp, ndof, attachment_points, moment_points))
        modes, om2, n_att = augment_ritz(modes, U, M, K)
        labels += [f"attach{k + 1}" for k in range(n_att)]
    G = load_geometric = None
    if geometric:
        G = centrifugal_geometric(K, M, Rg, modes, mass, pos, Nglob, dofs[E_], L, Lam, T, El, e * area)
        load_geometric = _load_geometric_fn(K, M, Rg, modes, interp, L, Lam, T, El, e * area)
    Phi = np.einsum("pad,pdj->paj", Nglob, modes[dofs[E_]])

    def shape_fn(pts):
        Ng, Nr, dd = interp(pts)
        md = modes[dd]
        return np.einsum("pad,pdj->paj", Ng, md), np.einsum("pad,pdj->paj", Nr, md)

    body = Body(
        name=name,
        masses=mass,
        points=pos,
        shapes=Phi,
        stiffness=np.diag(om2),
        shape_fn=shape_fn,
        geometric=G,
        frame="mean axes (free-free FE modes, axes parallel to the model's axes)",
        length=size,
        mode_labels=tuple(labels),
        load_geometric=load_geometric,
        params={
            "source": "frame_body",
            "nodes": plain(nodes),
            "elements": None if elements is None else np.asarray(elements).tolist(),
            **{
                k: float(v)
                for k, v in (("e", e), ("g", g), ("rho", rho), ("area", area), ("iy", iy), ("iz", iz), ("j", j))
            },
            "n_modes": int(n_modes),
            "up": plain(up),
            "attachment_points": plain([list(p) for p in attachment_points]),
            "moment_points": plain([list(p) for p in moment_points]),
            "geometric": bool(geometric),
        },
    )
    return body


def _stiffness(L, Lam, El, ndof, e, g, area, iy, iz, j):
    """Element transformations ``T`` (E, 12, 12), the global stiffness ``K`` and the element
    DOF indices (E, 12)."""
    T = np.zeros((len(El), 12, 12))
    for b in range(4):
        T[:, 3 * b : 3 * b + 3, 3 * b : 3 * b + 3] = Lam
    kl = _local_stiffness(L, e * area, g * j, e * iy, e * iz)
    kg = np.einsum("eji,ejk,ekl->eil", T, kl, T)
    dofs = np.concatenate([6 * El[:, :1] + np.arange(6), 6 * El[:, 1:] + np.arange(6)], axis=1)
    K = np.zeros((ndof, ndof))
    np.add.at(K, (dofs[:, :, None], dofs[:, None, :]), kg)
    return T, K, dofs


def _mass_points(X, El, L, Lam, T, dofs, ndof, rho, area, iy, iz):
    """Mass points (element e, Gauss point gp, section point sp: 12 per element) and the mass
    matrix they give: ``(mass, pos, Nglob, E_, M)`` with ``Nglob`` the global 3 x 12
    interpolation of each point and ``E_`` its element."""
    a, b_ = np.sqrt(2 * iz / area), np.sqrt(2 * iy / area)
    offs = np.array([[0, a, 0], [0, -a, 0], [0, 0, b_], [0, 0, -b_]], float)
    E_, G_, S_ = np.meshgrid(np.arange(len(El)), np.arange(3), np.arange(4), indexing="ij")
    E_, G_, S_ = E_.ravel(), G_.ravel(), S_.ravel()
    s = _GP[G_]
    Nu, Nt = _interp(s, L[E_])
    Npt = Nu - np.einsum("pab,pbc->pac", skew(offs[S_]), Nt)  # u + th x s = u - s~ th
    Nglob = np.einsum("pba,pbc,pcd->pad", Lam[E_], Npt, T[E_])  # global 3 x 12 per point
    mass = rho * area * L[E_] * _GW[G_] / 4.0
    pos = X[El[E_, 0]] + s[:, None] * (X[El[E_, 1]] - X[El[E_, 0]]) + np.einsum("pba,pb->pa", Lam[E_], offs[S_])
    Me = np.einsum("p,pai,paj->pij", mass, Nglob, Nglob)
    M = np.zeros((ndof, ndof))
    np.add.at(M, (dofs[E_][:, :, None], dofs[E_][:, None, :]), Me)
    return mass, pos, Nglob, E_, M


def _require_connected(El, nn: int) -> None:
    """One connected structure (a free-free body has exactly 6 rigid-body modes)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    graph = coo_matrix((np.ones(len(El)), (El[:, 0], El[:, 1])), shape=(nn, nn))
    n_comp = connected_components(graph, directed=False)[0]
    if n_comp != 1:
        raise InputError(
            "body.elements",
            f"{n_comp} disconnected parts",
            "one connected structure (free-free: exactly 6 rigid-body modes)",
        )


def _mean_axes(X, M, modes):
    """Rigid-body modes ``Rg`` (ndof, 6) about the nodes' centroid, and ``modes`` in exact mean
    axes: the (round-off) rigid-body content removed, then mass-normalised."""
    nn = len(X)
    ndof = 6 * nn
    rel = X - X.mean(axis=0)
    Rg = np.zeros((ndof, 6))
    for a in range(3):
        Rg[a::6, a] = 1.0
        Rg[3 + a :: 6, 3 + a] = 1.0
        e_a = np.eye(3)[a]
        Rg[np.arange(nn)[:, None] * 6 + np.arange(3), 3 + a] = np.cross(e_a, rel)
    MR = M @ Rg
    modes = modes - Rg @ np.linalg.solve(Rg.T @ MR, MR.T @ modes)
    return Rg, modes / np.sqrt(np.einsum("ij,ik,kj->j", modes, M, modes))


def _interpolator(X, El, L, Lam, T, dofs, size):
    """``interp(points) -> (Ng, Nr, dofs)``: global displacement and rotation interpolation
    (P, 3, 12) of points on an element axis and the element DOF indices (InputError elsewhere)."""

    def interp(pts):
        pts = np.atleast_2d(np.asarray(pts, dtype=float))
        A0 = X[El[:, 0]]
        dvec = X[El[:, 1]] - A0
        t = np.einsum("pea,ea->pe", pts[:, None, :] - A0[None], dvec) / (L**2)[None]
        tc = np.clip(t, 0.0, 1.0)
        dist = np.linalg.norm(pts[:, None, :] - (A0[None] + tc[..., None] * dvec[None]), axis=2)
        ie = np.argmin(dist, axis=1)
        bad = dist[np.arange(len(pts)), ie] > 1e-9 * size
        if np.any(bad):
            k = int(np.argmax(bad))
            raise InputError("point", pts[k].tolist(), "a point on an element axis of the FE body")
        sp = tc[np.arange(len(pts)), ie]
        nu, nt = _interp(sp, L[ie])
        Tg = T[ie]
        Ng = np.einsum("pba,pbc,pcd->pad", Lam[ie], nu, Tg)
        Nr = np.einsum("pba,pbc,pcd->pad", Lam[ie], nt, Tg)
        return Ng, Nr, dofs[ie]

    return interp


def _unit_loads(interp, ndof: int, attachment_points, moment_points) -> np.ndarray:
    """Consistent nodal loads (ndof, 3 per point) of unit forces along x, y, z at the
    attachment points, then unit moments at the moment points (through the rotation
    interpolation)."""
    Fs = []
    for pts, where, use_rot in (
        (attachment_points, "body.attachment_points", False),
        (moment_points, "body.moment_points", True),
    ):
        if not len(pts):
            continue
        Pa = np.asarray(pts, dtype=float).reshape(-1, 3)
        try:
            Ng, Nr, dd = interp(Pa)
        except InputError as exc:
            raise InputError(where, exc.value, exc.allowed) from None
        Nu = Nr if use_rot else Ng  # unit moments act through the rotation interpolation
        F = np.zeros((ndof, 3 * len(Pa)))
        for i in range(len(Pa)):
            np.add.at(F, (dd[i], slice(3 * i, 3 * i + 3)), Nu[i].T)
        Fs.append(F)
    return np.hstack(Fs)


def inertia_relief_solve(K, M, Rg, F):
    """Static deflections ``U`` of a free structure under loads ``F`` (ndof, k) with inertia relief.

    The rigid-body part of the load is balanced by the rigid acceleration it causes
    (``F_r = F - M R (R^T M R)^-1 R^T F``) and ``U`` is mass-orthogonal to the rigid modes ``R``:
    ``K U = F_r``, ``R^T M U = 0`` (solved with the regularised ``K + M R (R^T M R)^-1 R^T M``).
    """
    MR = M @ Rg
    A = Rg.T @ MR
    Fr = F - MR @ np.linalg.solve(A, Rg.T @ F)
    return np.linalg.solve(K + MR @ np.linalg.solve(A, MR.T), Fr)


def augment_ritz(modes, U, M, K, tol: float = 1e-8):
    """Add attachment vectors ``U`` to mass-normalised ``modes``; return a normal-mode basis.

    ``U`` is made mass-orthogonal to ``modes`` (and to earlier columns; near-dependent columns
    with relative norm < ``tol`` are dropped), then the whole set is diagonalised by a
    Rayleigh-Ritz step, so the result is again mass-orthonormal with diagonal stiffness. Because
    the elastic modes are exact eigenvectors, they are reproduced and the attachment part becomes
    extra "pseudo-modes" (sorted after them).

    Returns ``(basis, omega^2, n_added)``.
    """
    V = [modes[:, j] for j in range(modes.shape[1])]
    added = []
    for k in range(U.shape[1]):
        u = U[:, k].copy()
        nrm0 = np.sqrt(u @ M @ u)
        for v in V + added:
            u -= v * (v @ M @ u)
        nrm = np.sqrt(max(u @ M @ u, 0.0))
        if nrm > tol * nrm0:
            added.append(u / nrm)
    A = np.column_stack([modes] + [a[:, None] for a in added])
    from scipy.linalg import eigh

    Kr = A.T @ K @ A
    Mr = A.T @ M @ A
    w2, C = eigh(0.5 * (Kr + Kr.T), 0.5 * (Mr + Mr.T))
    basis = A @ C
    basis = basis / np.sqrt(np.einsum("ij,ik,kj->j", basis, M, basis))
    # keep the sign of the original modes (first n columns match them)
    n = modes.shape[1]
    sg = np.sign(np.einsum("ij,ik,kj->j", basis[:, :n], M, modes))
    basis[:, :n] *= np.where(sg == 0, 1.0, sg)
    return basis, w2, len(added)


def centrifugal_geometric(K, M, Rg, modes, mass, pos, Nglob, pdofs, L, Lam, T, El, ea):
    """Unit geometric stiffness ``G[a, b]`` (3, 3, n, n) of a spinning free frame.

    The centrifugal load of ``w_a w_b`` on mass point ``k`` is
    ``m_k (delta_ab r_k - (e_a r_kb + e_b r_ka) / 2)`` (``r`` from the centre of mass). Its
    inertia-relieved static deflection gives the element axial forces ``N_e`` (tension > 0);
    each element contributes ``N_e int (v'^2 + w'^2) dx`` (consistent Hermite geometric
    stiffness of both bending planes; no torsional term). ``K_G(w) = sum_ab w_a w_b G[a, b]``.
    """
    rc = pos - (mass @ pos) / mass.sum()
    pairs = [(a, b) for a in range(3) for b in range(a, 3)]
    F = np.zeros((K.shape[0], len(pairs)))
    for c, (a, b) in enumerate(pairs):
        f = -0.5 * mass[:, None] * (np.eye(3)[a][None] * rc[:, b : b + 1] + np.eye(3)[b][None] * rc[:, a : a + 1])
        if a == b:
            f = f + mass[:, None] * rc
        np.add.at(F[:, c], pdofs, np.einsum("pad,pa->pd", Nglob, f))
    N = _axial_forces(inertia_relief_solve(K, M, Rg, F), L, Lam, El, ea)
    Ge = _modal_element_geometric(modes, L, T, El)
    G = np.zeros((3, 3, modes.shape[1], modes.shape[1]))
    for c, (a, b) in enumerate(pairs):
        G[a, b] = G[b, a] = np.einsum("e,eij->ij", N[:, c], Ge)
    return G


def _axial_forces(U, L, Lam, El, ea):
    """Element axial forces (E, k) [N] (tension > 0) of the deflections ``U`` (ndof, k)."""
    idx1 = 6 * El[:, 0][:, None] + np.arange(3)
    idx2 = 6 * El[:, 1][:, None] + np.arange(3)
    return (ea / L)[:, None] * np.einsum("ea,eak->ek", Lam[:, 0, :], U[idx2] - U[idx1])


def _modal_element_geometric(modes, L, T, El):
    """Per-element modal geometric stiffness for unit axial force (E, n, n): the consistent
    Hermite ``int (v'^2 + w'^2) dx`` of both bending planes (no torsional term)."""
    _, nt = _interp(np.repeat(_GP, len(L)), np.tile(L, len(_GP)))
    nt = nt.reshape(len(_GP), len(L), 3, 12)
    kg1 = np.einsum("g,e,geai,geaj->eij", _GW, L, nt[:, :, 1:, :], nt[:, :, 1:, :])
    kg1 = np.einsum("eji,ejk,ekl->eil", T, kg1, T)
    dofs = np.concatenate([6 * El[:, :1] + np.arange(6), 6 * El[:, 1:] + np.arange(6)], axis=1)
    me = modes[dofs]  # (E, 12, n)
    return np.einsum("eai,eab,ebj->eij", me, kg1, me)


def _load_geometric_fn(K, M, Rg, modes, interp, L, Lam, T, El, ea):
    """``load_geometric(point, clamped=False) -> (3, n, n)``: modal geometric stiffness per unit
    body-frame force along x, y, z at ``point`` (on an element axis), from the axial forces of
    its inertia-relieved static deflection: the free body's rigid acceleration under the force
    loads every element (translational and rotational inertia relief). ``clamped`` is not
    meaningful for a free-free FE body and is ignored (FE bodies float)."""
    Ge = _modal_element_geometric(modes, L, T, El)
    ndof = K.shape[0]

    def load_geometric(point, clamped=False):
        Ng, _, dd = interp(np.asarray(point, dtype=float)[None])
        F = np.zeros((ndof, 3))
        np.add.at(F, dd[0], Ng[0].T)  # consistent nodal loads of unit forces along x, y, z
        N = _axial_forces(inertia_relief_solve(K, M, Rg, F), L, Lam, El, ea)
        return np.einsum("ec,eij->cij", N, Ge)

    return load_geometric


def straight_beam_nodes(length: float, n_elements: int, start=(0.0, 0.0, 0.0), direction=(1.0, 0.0, 0.0)):
    """Equally spaced nodes of a straight beam ``(n_elements + 1, 3)`` [m]."""
    d = np.asarray(direction, float)
    d = d / np.linalg.norm(d)
    s = np.linspace(0.0, length, n_elements + 1)
    return np.asarray(start, float)[None] + s[:, None] * d[None]
