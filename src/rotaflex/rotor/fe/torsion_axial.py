"""Torsional and axial natural frequencies of the FE rotor (uncoupled from the lateral motion).

For an axisymmetric shaft on linear lateral bearings the torsional (twist phi_z) and axial (w)
motions are uncoupled from the lateral DOFs and from each other. Each shaft element is a
two-node element with linear interpolation: torsion K = G J / L [[1, -1], [-1, 1]],
M = rho J L / 6 [[2, 1], [1, 2]]; axial the same with E A and rho A. J and A follow the
(tapered) section at Gauss points, as for the bending element. Disks add Ip (torsion) and m
(axial); point masses add m (axial). Bearings do not restrain the twist; their axial (thrust)
stiffness ``kzz`` restrains w (:func:`axial_matrices`). Without thrust stiffness the rotor is free
axially: the first frequency is the rigid-body mode at 0 (reported).
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla

from rotaflex.rotor.fe.elements.shaft import WEIGHT, XI
from rotaflex.rotor.fe.model import Rotor


def _assemble(rotor: Rotor, kind: str) -> tuple[np.ndarray, np.ndarray]:
    e = rotor.elements
    do = e["do_l"][:, None] + (e["do_r"] - e["do_l"])[:, None] * XI[None, :]
    di = e["di_l"][:, None] + (e["di_r"] - e["di_l"])[:, None] * XI[None, :]
    N = np.stack([1 - XI, XI], -1)  # (g, 2) linear shape functions
    if kind == "torsion":
        prop = np.pi / 32 * (do**4 - di**4)  # polar moment J [m^4]
        stiff, dens = e["G"], e["rho"]
    else:
        prop = np.pi / 4 * (do**2 - di**2)  # area A [m^2]
        stiff, dens = e["E"], e["rho"]
    L = e["L"]
    ke = (stiff * (prop @ WEIGHT) / L)[:, None, None] * np.array([[1.0, -1.0], [-1.0, 1.0]])
    me = np.einsum("ng,gi,gj->nij", (dens * L)[:, None] * prop * WEIGHT[None, :], N, N)
    n = rotor.n_nodes
    K, M = np.zeros((n, n)), np.zeros((n, n))
    idx = np.arange(L.size)[:, None] + np.arange(2)[None, :]
    np.add.at(K, (idx[:, :, None], idx[:, None, :]), ke)
    np.add.at(M, (idx[:, :, None], idx[:, None, :]), me)
    for node, d in rotor.disks:
        M[node, node] += d.Ip if kind == "torsion" else d.mass
    if kind == "axial":
        for node, p in rotor.point_masses:
            M[node, node] += p.mass
    return K, M


def axial_matrices(rotor: Rotor) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Axial stiffness, mass and damping (n_nodes, n_nodes) [N/m, kg, N s/m]: the shaft's linear
    two-node bar elements, disk and point masses, and the bearings' thrust springs and dampers
    ``kzz``/``czz`` (to ground, or between the bearing's node and its ``to_node``)."""
    K, M = _assemble(rotor, "axial")
    C = np.zeros_like(K)
    for b, (node, other, _) in zip(rotor.bearing, rotor.bearings, strict=True):
        for X, v in ((K, b.kzz), (C, b.czz)):
            if v:
                X[node, node] += v
                if other is not None:
                    X[other, other] += v
                    X[node, other] -= v
                    X[other, node] -= v
    return K, M, C


def torsion_matrices(rotor: Rotor) -> tuple[np.ndarray, np.ndarray]:
    """Torsional stiffness [N m/rad] and mass [kg m^2] (n_nodes, n_nodes) of the FE rotor: the one
    torsional shaft assembly (the machine's twist blocks, :func:`rotaflex.system.assembly.matrices`,
    are these)."""
    return _assemble(rotor, "torsion")


def torsional_modes(rotor: Rotor, n_modes: int = 6) -> tuple[np.ndarray, np.ndarray]:
    """Torsional natural frequencies [rad/s] (first: rigid rotation, 0) and mode shapes (m, n_nodes)."""
    K, M = torsion_matrices(rotor)
    return _solve(K, M, n_modes)


def axial_modes(rotor: Rotor, n_modes: int = 6) -> tuple[np.ndarray, np.ndarray]:
    """Axial natural frequencies [rad/s] (first: rigid translation, 0, without thrust stiffness) and
    mode shapes (m, n_nodes)."""
    K, M, _ = axial_matrices(rotor)
    return _solve(K, M, n_modes)


def _solve(K, M, n_modes):
    k = min(n_modes, K.shape[0])
    w2, v = sla.eigh(K, M, subset_by_index=(0, k - 1))
    return np.sqrt(np.clip(w2, 0.0, None)), v.T
