"""Timoshenko shaft element (shear, rotary inertia, gyroscopic), cylindrical, tapered, hollow.

The element is that of Nelson & McVaugh (1976) with the shear deformation of Nelson (1980):
per bending plane the DOFs are [w1, s1, w2, s2] (lateral displacement and section rotation in
the sense of dw/dz) and the interdependent interpolation gives

- translations  w = N_w(xi, Phi) q, section rotation  s = N_r(xi, Phi) q, xi = z / L,
- shear strain  gamma = dw/dz - s (constant along the element),
- Phi = 12 E I / (kappa G A L^2).

The matrices are the integrals M_t = int rho A N_w^T N_w, M_r = int rho I N_r^T N_r,
K = int E I N_r'^T N_r' + kappa G A gamma^T gamma and the gyroscopic coupling (polar moment
2 rho I per length), evaluated by 5-point Gauss quadrature. For a cylindrical element the
integrands are polynomials of degree <= 6, so the quadrature reproduces the closed-form
matrices exactly (tested); for a tapered element A(z) and I(z) follow the linear diameter
taper at the Gauss points and Phi uses the element-mean section.

The two bending planes are mapped onto the node DOFs [x, y, theta_x, theta_y]: the x-z plane
is (x, theta_y) and the y-z plane is (y, -theta_x).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rotaflex.rotor.fe.materials import Material

_XG, _WG = np.polynomial.legendre.leggauss(5)
XI, WEIGHT = 0.5 * (_XG + 1.0), 0.5 * _WG  # on [0, 1]

#: element DOFs of the x-z plane (x1, theta_y1, x2, theta_y2) and the y-z plane (y1, -theta_x1, ...)
IA, IB = np.array([0, 3, 4, 7]), np.array([1, 2, 5, 6])
SB = np.array([1.0, -1.0, 1.0, -1.0])


def cowper_shear_coefficient(ratio, nu):
    """Cowper (1966) shear coefficient of a hollow circular section, ``ratio`` = d_in / d_out."""
    r2 = np.asarray(ratio, float) ** 2
    a = (1.0 + r2) ** 2
    return 6.0 * (1.0 + nu) * a / ((7.0 + 6.0 * nu) * a + (20.0 + 12.0 * nu) * r2)


def _section(do, di):
    return np.pi / 4.0 * (do**2 - di**2), np.pi / 64.0 * (do**4 - di**4)


def _shape(xi, phi, L):
    """Shape functions at ``xi`` (shape (g,)) for elements (shape (n,)): arrays (n, g, 4)."""
    x = xi[None, :]
    p = phi[:, None]
    ll = L[:, None]
    c = 1.0 / (1.0 + p)
    nw = np.stack(
        [
            c * (2 * x**3 - 3 * x**2 - p * x + 1 + p),
            c * ll * (x**3 - (2 + p / 2) * x**2 + (1 + p / 2) * x),
            c * (-2 * x**3 + 3 * x**2 + p * x),
            c * ll * (x**3 - (1 - p / 2) * x**2 - p / 2 * x),
        ],
        -1,
    )
    nr = np.stack(
        [
            6 * c / ll * (x**2 - x),
            c * (3 * x**2 - (4 + p) * x + 1 + p),
            -6 * c / ll * (x**2 - x),
            c * (3 * x**2 - (2 - p) * x),
        ],
        -1,
    )
    dnr = np.stack(
        [6 * c / ll**2 * (2 * x - 1), c / ll * (6 * x - 4 - p), -6 * c / ll**2 * (2 * x - 1), c / ll * (6 * x - 2 + p)],
        -1,
    )
    one = np.ones_like(x)
    gamma = np.stack([-p * c / ll * one, -p * c / 2 * one, p * c / ll * one, -p * c / 2 * one], -1)
    return nw, nr, dnr, gamma


def plane_matrices(L, do_l, di_l, do_r, di_r, E, G, rho, kappa=None):
    """Single-plane matrices of ``n`` elements (arrays broadcast to shape (n,)).

    Returns
    -------
    Mt, Mr, K : ndarray (n, 4, 4)
        Translational mass [kg, kg m, kg m^2], rotary inertia, stiffness [N/m, N, N m].
        The gyroscopic matrix per unit speed is built from ``2 Mr``.
    """
    L, do_l, di_l, do_r, di_r, E, G, rho = np.broadcast_arrays(
        *(np.atleast_1d(np.asarray(v, float)) for v in (L, do_l, di_l, do_r, di_r, E, G, rho))
    )
    do = do_l[:, None] + (do_r - do_l)[:, None] * XI[None, :]
    di = di_l[:, None] + (di_r - di_l)[:, None] * XI[None, :]
    A, I = _section(do, di)  # (n, g)
    Am, Im = A @ WEIGHT, I @ WEIGHT
    dom, dim_ = (do_l + do_r) / 2, (di_l + di_r) / 2
    cowper = cowper_shear_coefficient(dim_ / dom, E / (2 * G) - 1.0)
    kappa = cowper if kappa is None else np.broadcast_to(np.asarray(kappa, float), L.shape)
    kappa = np.where(np.isnan(kappa), cowper, kappa)  # nan: Cowper's value
    phi = 12.0 * E * Im / (kappa * G * Am * L**2)
    nw, nr, dnr, gam = _shape(XI, phi, L)
    wl = WEIGHT[None, :] * L[:, None]  # (n, g) quadrature weights in z
    Mt = np.einsum("ng,ngi,ngj->nij", wl * rho[:, None] * A, nw, nw)
    Mr = np.einsum("ng,ngi,ngj->nij", wl * rho[:, None] * I, nr, nr)
    K = np.einsum("ng,ngi,ngj->nij", wl * E[:, None] * I, dnr, dnr) + np.einsum(
        "ng,ngi,ngj->nij", wl * (kappa * G)[:, None] * A, gam, gam
    )
    return Mt, Mr, K


def to_node_dofs(P, kind: str = "sym"):
    """Map single-plane (n, 4, 4) matrices to (n, 8, 8) on [x, y, theta_x, theta_y] x 2 nodes.

    ``kind``: ``"sym"`` puts P in both planes (mass, stiffness); ``"gyro"`` builds the
    skew-symmetric gyroscopic matrix from P = 2 Mr; ``"accel"`` builds the matrix multiplying
    the spin acceleration d(Omega)/dt (the y-z/x-z block of ``"gyro"`` only).
    """
    n = P.shape[0]
    out = np.zeros((n, 8, 8))
    if kind == "sym":
        out[:, IA[:, None], IA[None, :]] = P
        out[:, IB[:, None], IB[None, :]] = SB[:, None] * P * SB[None, :]
    elif kind == "gyro":
        out[:, IA[:, None], IB[None, :]] = P * SB[None, :]
        out[:, IB[:, None], IA[None, :]] = -SB[:, None] * P
    elif kind == "accel":
        out[:, IB[:, None], IA[None, :]] = -SB[:, None] * P
    else:  # programming error
        raise ValueError(kind)
    return out


def shaft_matrices(L, do_l, di_l, do_r, di_r, E, G, rho, kappa=None) -> dict[str, np.ndarray]:
    """Node-DOF matrices (n, 8, 8) of ``n`` shaft elements: ``M``, ``K``, ``G`` (per rad/s), ``Kst``."""
    Mt, Mr, K = plane_matrices(L, do_l, di_l, do_r, di_r, E, G, rho, kappa)
    return {
        "M": to_node_dofs(Mt + Mr),
        "K": to_node_dofs(K),
        "G": to_node_dofs(2 * Mr, "gyro"),
        "Kst": to_node_dofs(2 * Mr, "accel"),
    }


@dataclass(frozen=True)
class ShaftElement:
    """One Timoshenko shaft element between two consecutive nodes.

    Parameters
    ----------
    length : float
        Element length L [m].
    outer_diameter, inner_diameter : float
        Diameters at the left node [m].
    outer_diameter_right, inner_diameter_right : float
        Diameters at the right node [m] (equal to the left ones for a cylindrical element).
    material : Material
    shear_coefficient : float or None
        kappa [-]; None (or nan in the array form): Cowper's hollow-circle value
        from the mean section and Poisson's ratio.

    Examples
    --------
    >>> from rotaflex.rotor.fe.materials import MATERIALS
    >>> el = ShaftElement(0.25, 0.05, 0.0, 0.05, 0.0, MATERIALS["steel"])
    >>> el.M().shape
    (8, 8)
    """

    length: float
    outer_diameter: float
    inner_diameter: float
    outer_diameter_right: float
    inner_diameter_right: float
    material: Material
    shear_coefficient: float | None = None

    def _mats(self) -> dict[str, np.ndarray]:
        m = self.material
        out = shaft_matrices(
            self.length,
            self.outer_diameter,
            self.inner_diameter,
            self.outer_diameter_right,
            self.inner_diameter_right,
            m.E,
            m.G,
            m.rho,
            self.shear_coefficient,
        )
        return {k: v[0] for k, v in out.items()}

    def M(self) -> np.ndarray:
        """Mass matrix (8, 8) [kg, kg m, kg m^2]."""
        return self._mats()["M"]

    def K(self) -> np.ndarray:
        """Stiffness matrix (8, 8) [N/m, N, N m]."""
        return self._mats()["K"]

    def C(self) -> np.ndarray:
        """Damping matrix (8, 8): zero (no internal shaft damping is modelled)."""
        return np.zeros((8, 8))

    def G(self) -> np.ndarray:
        """Gyroscopic matrix per unit spin speed (8, 8) [kg m^2]; the force is Omega G q'."""
        return self._mats()["G"]
