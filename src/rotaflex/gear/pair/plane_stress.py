"""Plane-stress 8-node serendipity quadrilateral: stiffness, HRZ-lumped mass, stresses.

DOF order is interleaved: ``[u0x, u0y, u1x, u1y, ...]`` (node ``i`` has DOFs ``2i`` and ``2i+1``).
All element integrals use 3x3 Gauss quadrature and are evaluated for all elements at once
(numpy einsum); global matrices are assembled as scipy.sparse COO -> CSR.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp

from rotaflex.core.errors import InputError

__all__ = [
    "shape_functions",
    "shape_derivatives",
    "jacobian_determinants",
    "elasticity_matrix",
    "stiffness_matrix",
    "consistent_mass",
    "lumped_mass",
    "stable_time_step",
    "stress_operator",
    "element_dofs",
    "RK4_STABILITY",
]

#: RK4 stability bound used for dt * omega_max (2.785 = real-axis limit; the imaginary-axis
#: limit for undamped oscillation is 2*sqrt(2) = 2.828, so this keeps a small margin)
RK4_STABILITY = 2.785

_XI = np.array([-1.0, 1.0, 1.0, -1.0, 0.0, 1.0, 0.0, -1.0])
_ETA = np.array([-1.0, -1.0, 1.0, 1.0, -1.0, 0.0, 1.0, 0.0])
_G = math.sqrt(0.6)
_GP1 = np.array([-_G, 0.0, _G])
_GW1 = np.array([5.0, 8.0, 5.0]) / 9.0
GAUSS_POINTS = np.array([(a, b) for a in _GP1 for b in _GP1])  # (9, 2)
GAUSS_WEIGHTS = np.array([wa * wb for wa in _GW1 for wb in _GW1])  # (9,)


def shape_functions(xi: np.ndarray, eta: np.ndarray) -> np.ndarray:
    """Serendipity shape functions N_a(xi, eta), shape (..., 8)."""
    xi, eta = np.asarray(xi, float)[..., None], np.asarray(eta, float)[..., None]
    c = 0.25 * (1 + xi * _XI[:4]) * (1 + eta * _ETA[:4]) * (xi * _XI[:4] + eta * _ETA[:4] - 1)
    m_xi = 0.5 * (1 - xi**2) * (1 + eta * _ETA[[4, 6]])  # nodes 4, 6 (xi_i = 0)
    m_eta = 0.5 * (1 + xi * _XI[[5, 7]]) * (1 - eta**2)  # nodes 5, 7 (eta_i = 0)
    return np.concatenate([c, m_xi[..., :1], m_eta[..., :1], m_xi[..., 1:], m_eta[..., 1:]], axis=-1)


def shape_derivatives(xi: np.ndarray, eta: np.ndarray) -> np.ndarray:
    """Derivatives dN_a/d(xi, eta), shape (..., 8, 2)."""
    xi, eta = np.asarray(xi, float)[..., None], np.asarray(eta, float)[..., None]
    xc, ec = _XI[:4], _ETA[:4]
    dc_dxi = 0.25 * xc * (1 + eta * ec) * (2 * xi * xc + eta * ec)
    dc_deta = 0.25 * ec * (1 + xi * xc) * (xi * xc + 2 * eta * ec)
    e46 = _ETA[[4, 6]]
    x57 = _XI[[5, 7]]
    d46_dxi = -xi * (1 + eta * e46)
    d46_deta = 0.5 * (1 - xi**2) * e46
    d57_dxi = 0.5 * x57 * (1 - eta**2)
    d57_deta = -eta * (1 + xi * x57)
    dxi = np.concatenate([dc_dxi, d46_dxi[..., :1], d57_dxi[..., :1], d46_dxi[..., 1:], d57_dxi[..., 1:]], axis=-1)
    deta = np.concatenate(
        [dc_deta, d46_deta[..., :1], d57_deta[..., :1], d46_deta[..., 1:], d57_deta[..., 1:]],
        axis=-1,
    )
    return np.stack([dxi, deta], axis=-1)


_N_GP = shape_functions(GAUSS_POINTS[:, 0], GAUSS_POINTS[:, 1])  # (9, 8)
_DN_GP = shape_derivatives(GAUSS_POINTS[:, 0], GAUSS_POINTS[:, 1])  # (9, 8, 2)


def _jacobians(xe: np.ndarray, dn: np.ndarray) -> np.ndarray:
    """J[e, g, k, l] = d x_l / d xi_k for element coords xe (ne, 8, 2), dn (ng, 8, 2)."""
    return np.einsum("gak,eal->egkl", dn, xe)


def jacobian_determinants(mesh) -> np.ndarray:
    """det J at the 3x3 Gauss points of every element, shape (ne, 9) [m^2]."""
    j = _jacobians(mesh.nodes[mesh.elements], _DN_GP)
    return j[..., 0, 0] * j[..., 1, 1] - j[..., 0, 1] * j[..., 1, 0]


def elasticity_matrix(youngs_modulus: float, poisson_ratio: float) -> np.ndarray:
    """Plane-stress constitutive matrix D (3x3) for (sxx, syy, sxy) = D (exx, eyy, gxy) [Pa]."""
    if not youngs_modulus > 0:
        raise InputError("youngs_modulus", youngs_modulus, "> 0 [Pa]")
    if not -1.0 < poisson_ratio < 0.5:
        raise InputError("poisson_ratio", poisson_ratio, "in (-1, 0.5)")
    e, nu = youngs_modulus, poisson_ratio
    c = e / (1.0 - nu**2)
    return c * np.array([[1.0, nu, 0.0], [nu, 1.0, 0.0], [0.0, 0.0, 0.5 * (1.0 - nu)]])


def _b_matrices(xe: np.ndarray, dn: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Strain-displacement matrices B (ne, ng, 3, 16) and det J (ne, ng)."""
    j = _jacobians(xe, dn)
    det = j[..., 0, 0] * j[..., 1, 1] - j[..., 0, 1] * j[..., 1, 0]
    inv = np.empty_like(j)
    inv[..., 0, 0] = j[..., 1, 1] / det
    inv[..., 1, 1] = j[..., 0, 0] / det
    inv[..., 0, 1] = -j[..., 0, 1] / det
    inv[..., 1, 0] = -j[..., 1, 0] / det
    # dN/dx_l = sum_k (J^-1)[l, k] dN/dxi_k
    dndx = np.einsum("eglk,gak->egal", inv, dn)  # (ne, ng, 8, 2)
    ne, ng = det.shape
    b = np.zeros((ne, ng, 3, 16))
    b[..., 0, 0::2] = dndx[..., 0]
    b[..., 1, 1::2] = dndx[..., 1]
    b[..., 2, 0::2] = dndx[..., 1]
    b[..., 2, 1::2] = dndx[..., 0]
    return b, det


def element_dofs(mesh) -> np.ndarray:
    """Global DOF numbers of every element, shape (ne, 16), ordered [n0x, n0y, n1x, ...]."""
    e = mesh.elements
    return np.stack([2 * e, 2 * e + 1], axis=-1).reshape(e.shape[0], 16)


def _assemble(mesh, ke: np.ndarray) -> sp.csr_matrix:
    dofs = element_dofs(mesh)
    rows = np.broadcast_to(dofs[:, :, None], ke.shape).ravel()
    cols = np.broadcast_to(dofs[:, None, :], ke.shape).ravel()
    n = 2 * mesh.nodes.shape[0]
    return sp.coo_matrix((ke.ravel(), (rows, cols)), shape=(n, n)).tocsr()


def element_stiffness(mesh, youngs_modulus: float, poisson_ratio: float) -> np.ndarray:
    """Element stiffness matrices, shape (ne, 16, 16) [N/m]."""
    d = elasticity_matrix(youngs_modulus, poisson_ratio)
    b, det = _b_matrices(mesh.nodes[mesh.elements], _DN_GP)
    if np.any(det <= 0.0):
        raise InputError("mesh", "element geometry", "positive Jacobian at every Gauss point")
    w = mesh.thickness * det * GAUSS_WEIGHTS[None, :]
    return np.einsum("eg,egia,ij,egjb->eab", w, b, d, b, optimize=True)


def stiffness_matrix(mesh, youngs_modulus: float, poisson_ratio: float) -> sp.csr_matrix:
    """Global plane-stress stiffness matrix K, CSR of shape (2n, 2n) [N/m].

    Parameters
    ----------
    mesh : ToothMesh
        Mesh (``nodes``, ``elements``, ``thickness``).
    youngs_modulus : float
        E [Pa].
    poisson_ratio : float
        nu [-].
    """
    return _assemble(mesh, element_stiffness(mesh, youngs_modulus, poisson_ratio))


def _element_mass_scalar(mesh, density: float) -> tuple[np.ndarray, np.ndarray]:
    """Scalar consistent mass blocks m_ab = int rho t N_a N_b dA (ne, 8, 8) and element masses."""
    if not density > 0:
        raise InputError("density", density, "> 0 [kg/m^3]")
    xe = mesh.nodes[mesh.elements]
    j = _jacobians(xe, _DN_GP)
    det = j[..., 0, 0] * j[..., 1, 1] - j[..., 0, 1] * j[..., 1, 0]
    w = density * mesh.thickness * det * GAUSS_WEIGHTS[None, :]
    me = np.einsum("eg,ga,gb->eab", w, _N_GP, _N_GP)
    return me, w.sum(axis=1)


def consistent_mass(mesh, density: float) -> sp.csr_matrix:
    """Consistent mass matrix, CSR (2n, 2n) [kg]."""
    me, _ = _element_mass_scalar(mesh, density)
    m16 = np.zeros((me.shape[0], 16, 16))
    m16[:, 0::2, 0::2] = me
    m16[:, 1::2, 1::2] = me
    return _assemble(mesh, m16)


def lumped_mass(mesh, density: float) -> np.ndarray:
    """HRZ (Hinton-Rock-Zienkiewicz) lumped mass diagonal, shape (2n,) [kg].

    Each element's diagonal of the consistent mass matrix is scaled so that it sums to the
    element mass (per direction): ``m_a = M_aa * m_e / sum_b M_bb``. All entries are positive
    and the total equals the exact mass ``rho * t * area`` (area integrated with 3x3 Gauss).
    """
    me, mass = _element_mass_scalar(mesh, density)
    diag = np.einsum("eaa->ea", me)
    lumped = diag * (mass / diag.sum(axis=1))[:, None]  # (ne, 8)
    out = np.zeros(mesh.nodes.shape[0])
    np.add.at(out, mesh.elements.ravel(), lumped.ravel())
    return np.repeat(out, 2)


def stable_time_step(
    mesh,
    youngs_modulus: float,
    poisson_ratio: float,
    density: float,
    *,
    method: str = "global",
    factor: float = RK4_STABILITY,
) -> float:
    """Largest stable explicit RK4 step for the free (unsupported) FE tooth [s].

    ``dt_max = factor / omega_max`` with ``omega_max^2`` the largest eigenvalue of
    ``M^-1 K`` (HRZ-lumped M). Supports and rigid disk coupling only lower omega_max, so the
    estimate is conservative for the tied tooth.

    Parameters
    ----------
    mesh : ToothMesh
    youngs_modulus, poisson_ratio, density : float
        E [Pa], nu [-], rho [kg/m^3].
    method : {"global", "element"}
        "global": ``scipy.sparse.linalg.eigsh`` on ``M^-1/2 K M^-1/2``; "element": max over
        elements of the element eigenvalue, an upper bound on omega_max^2 (cheaper, smaller dt).
    factor : float
        Stability bound of the integrator on ``dt * omega`` (default 2.785 for RK4).
    """
    m = lumped_mass(mesh, density)
    if method == "global":
        from scipy.sparse.linalg import eigsh

        k = stiffness_matrix(mesh, youngs_modulus, poisson_ratio)
        s = sp.diags(1.0 / np.sqrt(m))
        a = (s @ k @ s).tocsr()
        lam = eigsh(a, k=1, which="LA", return_eigenvectors=False, tol=1e-6, v0=np.ones(a.shape[0]))[0]
    elif method == "element":
        ke = element_stiffness(mesh, youngs_modulus, poisson_ratio)
        me, mass = _element_mass_scalar(mesh, density)
        diag = np.einsum("eaa->ea", me)
        ml = np.repeat(diag * (mass / diag.sum(axis=1))[:, None], 2, axis=1)  # [m0, m0, m1, m1, ...]
        s = 1.0 / np.sqrt(ml)
        a = ke * s[:, :, None] * s[:, None, :]
        lam = float(np.linalg.eigvalsh(a)[:, -1].max())
    else:
        raise InputError("method", method, "'global' or 'element'")
    return factor / math.sqrt(lam)


def stress_operator(
    mesh,
    youngs_modulus: float,
    poisson_ratio: float,
    element: np.ndarray,
    xi: np.ndarray,
    eta: np.ndarray,
) -> np.ndarray:
    """Matrices S (npts, 3, 2n) giving stresses (sxx, syy, sxy) [Pa] = S @ u at points.

    Parameters
    ----------
    element : ndarray of int, shape (npts,)
        Element of each point.
    xi, eta : ndarray, shape (npts,)
        Natural coordinates of each point in its element.
    """
    d = elasticity_matrix(youngs_modulus, poisson_ratio)
    element = np.atleast_1d(element)
    dn = shape_derivatives(np.atleast_1d(xi), np.atleast_1d(eta))  # (npts, 8, 2)
    xe = mesh.nodes[mesh.elements[element]]  # (npts, 8, 2)
    out = np.zeros((element.size, 3, 2 * mesh.nodes.shape[0]))
    for p in range(element.size):  # few points: small loop outside any time stepping
        b, _ = _b_matrices(xe[p : p + 1], dn[p : p + 1])
        out[p][:, element_dofs(mesh)[element[p]]] = d @ b[0, 0]
    return out
