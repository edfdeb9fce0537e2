"""Global matrices of a gearbox: rotor/fe lateral blocks, torsional blocks, mesh coupling vectors.

Global DOF vector: rotor after rotor, each ``[lateral (4 per node, rotor/fe order), twist (1 per
node, if torsion), axial w (1 per node, only on rotors carrying a helical mesh)]``. The
equations of motion about the static state at drive speed Omega are

    M q'' + (C + sum_r Omega_r G_r + sum_m c_m g_m g_m^T) q' + (K + sum_m k_m g_m g_m^T) q = f

with ``g_m`` the coupling vector of mesh m (``delta = g^T q - e``; see :mod:`.model`), C and K
the bearings', shafts' (rotor/fe) and flexible couplings' (:mod:`.coupling`, added on the DOFs
of their two hubs), and f the TE excitation ``sum_m g_m (k_m e + c_m e')``.

The solved coordinates are ``q = T p`` (:attr:`Matrices.T`): a constant-speed drive removes the
twist of the drive node and a rigid coupling makes node b's DOFs copies of node a's. Without
rigid couplings T is a column selection, applied by indexing (:attr:`Matrices.free`), so the
matrices of every earlier model are the same arrays as before couplings existed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla

from rotaflex.rotor.fe.model import Rotor
from rotaflex.rotor.fe.torsion_axial import axial_matrices
from rotaflex.rotor.fe.torsion_axial import torsion_matrices as fe_torsion_matrices
from rotaflex.system.model import Gearbox


def torsion_matrices(rotor: Rotor) -> tuple[np.ndarray, np.ndarray]:
    """Torsional stiffness and mass (n_nodes, n_nodes) of an FE rotor: rotor/fe's
    :func:`~rotaflex.rotor.fe.torsion_axial.torsion_matrices` (linear two-node shaft elements,
    ``G J / L``, consistent mass, J at Gauss points of the taper, disks' polar inertias)."""
    return fe_torsion_matrices(rotor)


def coupling_vector(box: Gearbox, mesh: int) -> np.ndarray:
    """g of a mesh (n_dof,): ``delta = g^T q - e``; also the generalised force per unit mesh
    force is ``-g`` (the force ``+F n`` on the driven gear, ``-F n`` on the driver).

    For a helical mesh delta and F stay transverse (the gear package's tables: k along the
    transverse line of action, F = T / r_b): g is the flank-normal derivative g_n divided by
    cos(beta_b), so the axial DOFs get ``sigma tan(beta_b)`` and the tilts that times the pitch
    point's arm (k g g^T = k_n g_n g_n^T with k_n = k / cos^2(beta_b); docs/geared-rotor.md).
    A contact at ``z_c`` = :attr:`~.model.MeshElement.offset` from mid-face adds the arm
    ``z_c e_z``: ``z_c (-n_y, n_x)`` on the tilts (theta_x, theta_y) of the driver, the opposite
    on the driven gear.
    """
    m = box.meshes[mesh]
    g = np.zeros(box.n_dof)
    (rd, nd), (rf, nf) = m.driver, m.driven
    g[box.lateral_dof(rd, nd, 0)] += m.normal[0]
    g[box.lateral_dof(rd, nd, 1)] += m.normal[1]
    g[box.lateral_dof(rf, nf, 0)] -= m.normal[0]
    g[box.lateral_dof(rf, nf, 1)] -= m.normal[1]
    g[box.torsion_dof(rd, nd)] += m.sense * m.radius[0]
    g[box.torsion_dof(rf, nf)] += m.sense * m.radius[1]
    if m.helix > 0:  # the flank normal's axial part, per unit transverse deflection
        t = m.axial_sign * math.tan(m.helix)
        for (r, node), arm, side in (((rd, nd), m.arms[0], 1.0), ((rf, nf), m.arms[1], -1.0)):
            g[box.axial_dof(r, node)] += side * t
            g[box.lateral_dof(r, node, 2)] += side * t * arm[1]  # (theta x r_P) . e_z
            g[box.lateral_dof(r, node, 3)] -= side * t * arm[0]
            if m.offset:  # contact z_c off mid-face: (theta x z_c e_z) . n = z_c (n_x theta_y - n_y theta_x)
                g[box.lateral_dof(r, node, 2)] -= side * m.offset * m.normal[1]
                g[box.lateral_dof(r, node, 3)] += side * m.offset * m.normal[0]
    return g


@dataclass(frozen=True)
class Matrices:
    """Speed-independent parts of the equations (full DOF set) and the free DOFs.

    M, K0 (shafts, torsion; bearings excluded), C0 (the load's torque-speed slope), G (list per
    rotor, per unit signed speed, embedded), g (n_mesh, n_dof), k_mean (n_mesh,), c_mesh
    (n_mesh,), free (indices kept).
    """

    M: np.ndarray
    K0: np.ndarray
    C0: np.ndarray
    G: list
    g: np.ndarray
    k_mean: np.ndarray
    c_mesh: np.ndarray
    free: np.ndarray
    T: np.ndarray | None = None

    def reduce(self, X: np.ndarray) -> np.ndarray:
        """``T^T X T`` of a full (n_dof, n_dof) matrix: the matrix on the solved coordinates."""
        return X[np.ix_(self.free, self.free)] if self.T is None else self.T.T @ X @ self.T

    def project(self, F: np.ndarray) -> np.ndarray:
        """``F T`` of rows over the full DOFs (..., n_dof): forces or coupling vectors on the
        solved coordinates (a column vector f becomes ``T^T f`` with ``project(f.T).T``)."""
        return F[..., self.free] if self.T is None else F @ self.T

    def expand(self, V: np.ndarray) -> np.ndarray:
        """Full DOF vectors (n_dof, ...) of solved coordinates (n_solved, ...): ``T V``."""
        if self.T is not None:
            return self.T @ V
        out = np.zeros((self.M.shape[0], *V.shape[1:]), V.dtype)
        out[self.free] = V
        return out


def matrices(box: Gearbox) -> Matrices:
    """Assemble the speed-independent matrices of ``box``."""
    n = box.n_dof
    M, K0 = np.zeros((n, n)), np.zeros((n, n))
    Gs = []
    C0 = np.zeros((n, n))
    for i, pr in enumerate(box.rotors):
        off, nl, nt = box.layout[i]
        if pr.axial:  # bars and thrust bearings (constant): axial DOFs after the twists
            sa = slice(off + nl + nt, off + nl + nt + pr.rotor.n_nodes)
            K0[sa, sa], M[sa, sa], C0[sa, sa] = axial_matrices(pr.rotor)
        sl = slice(off, off + nl)
        M[sl, sl] = pr.rotor.M
        K0[sl, sl] = pr.rotor.K_shaft
        G = np.zeros((n, n))
        G[sl, sl] = pr.rotor.G
        Gs.append(G)
        if nt:
            kt, mt = torsion_matrices(pr.rotor)
            st = slice(off + nl, off + nl + nt)
            M[st, st], K0[st, st] = mt, kt
    g = np.array([coupling_vector(box, i) for i in range(len(box.meshes))]).reshape(-1, n)
    k = np.array([m.k_mean for m in box.meshes])
    c = np.array([m.damping for m in box.meshes])
    if box.load is not None and box.spec.load is not None and box.spec.load.damping > 0:
        i = box.torsion_dof(*box.load)
        C0[i, i] = box.spec.load.damping
    for cp in box.couplings:
        if not cp.rigid:
            d = cp.dofs(box)
            K0[np.ix_(d, d)] += cp.K()
            C0[np.ix_(d, d)] += cp.C()
    free, T = constraint(box)
    return Matrices(M, K0, C0, Gs, g, k, c, free, T)


def constraint(box: Gearbox) -> tuple[np.ndarray, np.ndarray | None]:
    """Solved coordinates: (``free``, T) with ``q = T p``.

    ``free`` are the DOFs kept as coordinates: each rigid coupling's node-b DOFs follow node a's
    (chains resolved to the first node), and the drive node's twist is removed under a
    constant-speed drive (with what is rigidly joined to it). T (n_dof, n_free) is None when no
    coupling is rigid (T is then the selection of ``free``).
    """
    n = box.n_dof
    rep = np.arange(n)  # each DOF's master DOF

    def root(i):
        while rep[i] != i:
            i = rep[i]
        return i

    rigid = [cp for cp in box.couplings if cp.rigid]
    for cp in rigid:
        d = cp.dofs(box)
        h = d.size // 2
        for da, db in zip(d[:h], d[h:], strict=True):
            ra, rb = root(da), root(db)
            rep[max(ra, rb)] = min(ra, rb)
    rep = np.array([root(i) for i in range(n)])
    masters = np.flatnonzero(rep == np.arange(n))
    if box.drive_kind == "constant_speed" and box.drive is not None:
        masters = masters[masters != rep[box.torsion_dof(*box.drive)]]
    if not rigid:
        return masters, None
    col = np.full(n, -1)
    col[masters] = np.arange(masters.size)
    T = np.zeros((n, masters.size))
    kept = col[rep] >= 0
    T[np.flatnonzero(kept), col[rep][kept]] = 1.0
    return masters, T


def load_vector(box: Gearbox) -> np.ndarray:
    """Static load vector (full DOFs): load torque against its rotor's rotation; with a torque
    drive, the drive torque that balances it (no losses: T_in Omega_in = T_L Omega_L)."""
    f = np.zeros(box.n_dof)
    if box.load is not None and box.load_torque > 0:
        r, node = box.load
        f[box.torsion_dof(r, node)] -= box.rotors[r].sense * box.load_torque
        if box.drive_kind == "torque":
            d, dn = box.drive
            t_in = box.load_torque * box.rotors[r].ratio / box.rotors[d].ratio
            f[box.torsion_dof(d, dn)] += box.rotors[d].sense * t_in
    return f


def free_dofs(box: Gearbox) -> np.ndarray:
    """DOFs solved for (see :func:`constraint`): all but the drive node's twist under a
    constant-speed drive and the DOFs that follow another through a rigid coupling."""
    return constraint(box)[0]


def bearing_matrices(box: Gearbox, drive_speed: float, with_mass: bool = False, include=None, whirl=None):
    """Bearing stiffness and damping (n_dof, n_dof) at a drive speed [rad/s] (each rotor's bearings
    at its own speed magnitude), from each rotor's one element assembly (``Rotor.MKC``).
    ``with_mass``: also the elements' added mass (a liquid seal's; zero for every other kind), the
    third of (K, C, M). ``include``: one list of flags per rotor, its bearings left out where
    False (None: all); ``whirl``: the frequency [rad/s] at which frequency-dependent elements are
    evaluated (None: synchronous) -- stability's element contributions and mode iteration."""
    n = box.n_dof
    K, C, M = np.zeros((n, n)), np.zeros((n, n)), np.zeros((n, n))
    wh = None if whirl is None else np.array([whirl])
    for i, pr in enumerate(box.rotors):
        off, nl, _ = box.layout[i]
        sl = slice(off, off + nl)
        mr, kr, cr = pr.rotor.MKC(abs(pr.ratio * drive_speed), wh, include=None if include is None else include[i])
        K[sl, sl] = kr[0] - pr.rotor.K_shaft
        C[sl, sl] = cr[0]
        M[sl, sl] = mr[0] - pr.rotor.M
    return (K, C, M) if with_mass else (K, C)


def system_matrices(
    box: Gearbox, drive_speed: float, mats: Matrices | None = None, mesh: bool = True, include=None, whirl=None
):
    """(M, D, K) on the free DOFs at a drive speed [rad/s]: D = C + gyroscopic (+ c_m g g^T),
    K = shafts + bearings (+ k_mean g g^T with ``mesh``); ``include``, ``whirl`` as
    :func:`bearing_matrices` takes them."""
    mats = matrices(box) if mats is None else mats
    Kb, Cb, Mb = bearing_matrices(box, drive_speed, with_mass=True, include=include, whirl=whirl)
    K = mats.K0 + Kb
    D = Cb + mats.C0
    for G, w in zip(mats.G, box.speeds(drive_speed), strict=True):
        D += w * G
    if mesh and len(mats.k_mean):
        K = K + (mats.g.T * mats.k_mean) @ mats.g
        D = D + (mats.g.T * mats.c_mesh) @ mats.g
    return mats.reduce(mats.M + Mb), mats.reduce(D), mats.reduce(K)


def undamped_modes(M: np.ndarray, K: np.ndarray, n: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Lowest ``n`` undamped modes of the symmetric part of K with M: (omega [rad/s], Phi) with
    ``Phi^T M Phi = I`` (rigid-body modes at omega = 0)."""
    Ks = 0.5 * (K + K.T)
    k = M.shape[0] if n is None else min(n, M.shape[0])
    w2, phi = sla.eigh(Ks, M, subset_by_index=(0, k - 1))
    return np.sqrt(np.clip(w2, 0.0, None)), phi


def reduced_basis(
    box: Gearbox, mats: Matrices, speed: float, w_max: float, cutoff: float, extra: bool = True, bearings: bool = True
) -> np.ndarray:
    """Reduction basis P (free DOFs, ``P^T M P = I``).

    The undamped modes (mean mesh stiffness, drive ``speed`` [rad/s]) below ``cutoff * w_max``
    [rad/s], plus static shapes ``K^-1 L`` of the loads that couple them to the truncated modes:
    the mesh forces g and, with ``extra``, unit forces at the bearings (their damping acts there)
    and the gyroscopic forces of the kept modes (without these the damped frequencies at speed
    are off by ~1 % on the example gearbox; with them by ~1e-6).
    """
    M, _, K = system_matrices(box, speed, mats)
    w, phi = undamped_modes(M, K)
    phi = phi[:, w <= cutoff * w_max]
    loads = [mats.project(mats.g).T]
    if extra:
        for r, pr in enumerate(box.rotors if bearings else ()):
            for node, _, _ in pr.rotor.bearings:
                for ax in (0, 1):
                    e = np.zeros((1, box.n_dof))
                    e[0, box.lateral_dof(r, node, ax)] = 1.0
                    loads.append(mats.project(e).T)
        Gs = sum(pr.sense * pr.ratio * G for pr, G in zip(box.rotors, mats.G, strict=True))
        loads.append(mats.reduce(Gs) @ phi)
    L = np.concatenate(loads, 1)
    Ks = 0.5 * (K + K.T)
    reg = 1e-12 * np.trace(Ks) / Ks.shape[0]  # rigid-body twist (torque drive): K is singular
    static = sla.solve(Ks + reg * np.eye(Ks.shape[0]), L, assume_a="sym")
    cols = [phi]
    for v in static.T:  # Gram-Schmidt in the M inner product, twice for round-off
        n0 = np.sqrt(v @ M @ v)
        for _ in range(2):
            B = np.concatenate(cols, 1)
            v = v - B @ (B.T @ (M @ v))
        n1 = np.sqrt(v @ M @ v)
        if n1 > 1e-8 * n0:
            cols.append((v / n1)[:, None])
    return np.concatenate(cols, 1)
