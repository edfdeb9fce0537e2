"""The UCS map's two solves of one pencil: the one-plane reduction of an axisymmetric system and
the general Hermitian pencil (rotor/fe/modal.ucs_solve) give the same forward critical speeds."""

import numpy as np
import pytest

from rotaflex.rotor.fe.model import NDOF_NODE, Bearing, Disk, Rotor, Shaft
from rotaflex.rotor.fe.ucs import plane_dofs, support_stiffness, ucs_solve


def _pencil(kxx=1e8, kyy=1e8):
    r = Rotor(
        shaft=(Shaft(outer_diameter=0.05, length=1.2, elements=12),),
        disk=(Disk(node=3, mass=25.0, Ip=0.6, Id=0.3), Disk(node=9, mass=8.0, Ip=0.05, Id=0.03)),
        bearing=(Bearing(node=0, kxx=kxx, kyy=kyy), Bearing(node=12, kxx=kxx, kyy=kyy)),
    )
    nr = r.n_rotor_dof
    ends = [(NDOF_NODE * node + np.arange(2), None) for node, _, _ in r.bearings]
    K1 = support_stiffness(nr, ends, [np.eye(2)] * len(ends))
    eye = np.eye(nr)
    return r.M[:nr, :nr], r.G[:nr, :nr], r.K_shaft[:nr, :nr], K1, eye[0::NDOF_NODE], eye[1::NDOF_NODE], r.n_nodes


def test_one_plane_equals_general_pencil():
    M, G, K0, K1, Tx, Ty, n = _pencil()
    k = np.geomspace(1e5, 1e10, 9)
    w1, f1 = ucs_solve(M, G, K0, K1, k, 5, Tx, Ty, planes=plane_dofs(n))
    w2, f2 = ucs_solve(M, G, K0, K1, k, 5, Tx, Ty)
    assert np.all(np.isfinite(w1))
    np.testing.assert_allclose(w1, w2, rtol=1e-11)
    assert np.all(f1 == 1.0) and np.all(f2 > 0.99)  # circular forward whirl


@pytest.mark.parametrize("coupled", ["anisotropic", "cross-plane"])
def test_planes_ignored_where_the_system_is_not_axisymmetric(coupled):
    M, G, K0, K1, Tx, Ty, n = _pencil()
    K0 = K0.copy()
    if coupled == "anisotropic":  # a stiffer y support at node 6: the planes differ
        K0[6 * NDOF_NODE + 1, 6 * NDOF_NODE + 1] += 3e7
    else:  # an x-y spring at node 6: the planes couple
        i, j = 6 * NDOF_NODE, 6 * NDOF_NODE + 1
        K0[i, i] += 2e7
        K0[j, j] += 2e7
        K0[i, j] = K0[j, i] = 1e7
    k = np.geomspace(1e6, 1e9, 4)
    w1, _ = ucs_solve(M, G, K0, K1, k, 4, Tx, Ty, planes=plane_dofs(n))
    w2, _ = ucs_solve(M, G, K0, K1, k, 4, Tx, Ty)
    np.testing.assert_array_equal(w1, w2)  # the general pencil, not the reduction
