"""Coupled lateral-torsional modes and Campbell diagram of a gearbox (mean mesh stiffness).

The first-order eigenproblem of ``A = [[0, I], [-M^-1 K, -M^-1 D]]`` on the free DOFs
(:func:`~.assembly.system_matrices`), as rotor/fe does for one rotor. Each mode's kinetic-energy
split over DOF groups (per rotor: lateral, torsional; exact, since M is block diagonal over these
groups) and its mesh strain-energy fraction ``sum_m k_m |g_m^T v|^2 / v^H K v`` tell which modes
are mesh modes. Excitation lines: ``h z_p Omega_p`` per mesh (the mesh order and harmonics) and
``Omega_r`` per rotor (1X).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla

# loaded with the module, as before the tracking was shared: the mesh modes of a geared rotor
# give close MACs, where assign_modes solves the assignment with scipy.optimize, so its import
# (~9 MB, ~0.17 s) would otherwise land inside the first Campbell diagram of a run
import scipy.optimize  # noqa: F401

from rotaflex.core.errors import InputError
from rotaflex.core.units import rad_s_to_rpm
from rotaflex.rotor.fe.modal import EigenvalueView, line_crossings, oscillatory_pairs, state_matrix, track_modes
from rotaflex.system.assembly import (
    Matrices,
    free_dofs,
    matrices,
    reduced_basis,
    system_matrices,
    undamped_modes,
)
from rotaflex.system.model import Gearbox
from rotaflex.system.size import check_campbell, check_modal

#: a machine's eigenvalue is oscillatory when omega_d > OSCILLATORY_TOL (max |lambda| + 1 [1/s]):
#: the machine's threshold since its first version, looser than the FE rotor's 1e-9; kept so that
#: every machine keeps the modes it had (a shared value would be a change of results)
OSCILLATORY_TOL = 1e-7


@dataclass(frozen=True)
class SystemModes(EigenvalueView):
    """Modes at one or more drive speeds (leading dim: speed); frequencies, damping ratio and log
    decrement from :class:`~rotaflex.rotor.fe.modal.EigenvalueView`.

    Attributes
    ----------
    speed : (s,) drive speed [rad/s]
    eigenvalue : (s, m) complex [1/s]
    shape : (s, m, n_dof) complex, full DOF vector (constrained DOFs 0), v^H M v = 1
    energy : (s, m, n_groups) kinetic-energy fractions per group (:attr:`groups`)
    mesh_energy : (s, m) mesh strain-energy fraction
    groups : list of str, ``"<rotor>.lateral"`` / ``"<rotor>.torsion"`` (/ ``"<rotor>.axial"``)
    """

    speed: np.ndarray
    eigenvalue: np.ndarray
    shape: np.ndarray
    energy: np.ndarray
    mesh_energy: np.ndarray
    groups: list

    @property
    def torsional_fraction(self) -> np.ndarray:
        """Kinetic-energy fraction in twist DOFs (s, m)."""
        cols = [i for i, g in enumerate(self.groups) if g.endswith(".torsion")]
        return self.energy[..., cols].sum(-1)


def groups(box: Gearbox) -> tuple[list[str], list[np.ndarray]]:
    """Names and DOF indices of the energy groups."""
    names, idx = [], []
    for i, pr in enumerate(box.rotors):
        off, nl, nt = box.layout[i]
        names.append(f"{pr.name}.lateral")
        idx.append(np.arange(off, off + nl))
        if nt:
            names.append(f"{pr.name}.torsion")
            idx.append(np.arange(off + nl, off + nl + nt))
        if pr.axial:  # rotors carrying a helical mesh
            names.append(f"{pr.name}.axial")
            idx.append(np.arange(off + nl + nt, off + nl + nt + pr.rotor.n_nodes))
    return names, idx


def _energy(box: Gearbox, mats: Matrices, K_full: np.ndarray, v: np.ndarray):
    """Kinetic fractions per group (m, n_groups) and mesh strain fraction (m,) of full shapes v (m, n)."""
    _, idx = groups(box)
    Mv = v @ mats.M.T
    e = np.stack([np.real(np.sum(np.conj(v[:, i]) * Mv[:, i], 1)) for i in idx], -1)
    e /= np.maximum(e.sum(-1, keepdims=True), 1e-300)
    strain = np.real(np.sum(np.conj(v) * (v @ K_full.T), 1))
    if len(mats.k_mean):
        gm = np.abs(v @ mats.g.T) ** 2 * mats.k_mean
        mesh = gm.sum(-1) / np.maximum(strain, 1e-300)
    else:
        mesh = np.zeros(v.shape[0])
    return e, mesh


def speed_pencil(box, mats, basis):
    """Function of the drive speed giving (M, D, K) on the free DOFs or in ``basis``; with
    speed-independent bearings the projections are made once (D = D0 + Omega G_sum)."""
    constant = all(el.speed_independent for pr in box.rotors for _, _, el in pr.rotor.bearings)
    P = np.eye(mats.free.size) if basis is None else basis
    if not constant:

        def at(speed):
            M, D, K = system_matrices(box, speed, mats)
            return P.T @ M @ P, P.T @ D @ P, P.T @ K @ P

        return at
    M, D0, K = (P.T @ X @ P for X in system_matrices(box, 0.0, mats))
    Gs = sum(pr.sense * pr.ratio * G for pr, G in zip(box.rotors, mats.G, strict=True))
    Gr = P.T @ mats.reduce(Gs) @ P
    return lambda speed: (M, D0 + speed * Gr, K)


def _solve(box, mats, speed, n_keep, basis, pencil=None):
    M, D, K = (pencil or speed_pencil(box, mats, basis))(speed)
    n = M.shape[0]
    # rotor/fe's state matrix and selection; M^-1 [K D] by one solve (M is not inverted), one
    # LAPACK geev (right vectors only)
    MinvKD = sla.solve(M, np.concatenate([K, D], 1), check_finite=False)
    A = state_matrix(MinvKD[:, :n], MinvKD[:, n:])
    lam, vec = sla.eig(A, check_finite=False, overwrite_a=True)
    lam, v = oscillatory_pairs(lam, vec, n, n_keep, OSCILLATORY_TOL)
    # M-normalise where M is small (M_free = P^T M P in the basis): v^H M v is basis-invariant
    norm = np.sqrt(np.real(np.sum(np.conj(v) * (v @ M.T), 1)))
    v = v / norm[:, None]
    if basis is not None:
        v = v @ basis.T
    full = mats.expand(v.T).T
    # phase: largest component real
    j = np.argmax(np.abs(full), 1)
    ph = full[np.arange(full.shape[0]), j]
    full *= (np.abs(ph) / ph)[:, None]
    return lam, full


def _stiffness_full(box, mats, speed):
    from rotaflex.system.assembly import bearing_matrices

    Kb, _ = bearing_matrices(box, speed)
    K = mats.K0 + Kb
    if len(mats.k_mean):
        K = K + (mats.g.T * mats.k_mean) @ mats.g
    return 0.5 * (K + K.T)


def modal(box: Gearbox, speed: float = 0.0, n_modes: int = 12) -> SystemModes:
    """Damped modes of the coupled system at drive ``speed`` [rad/s], all DOFs (no reduction).

    Examples
    --------
    >>> # box = Gearbox.from_toml("examples/system/gearbox.toml"); modal(box, 300.0).wn
    """
    n_free = free_dofs(box).size
    check_modal(box.n_dof, n_free, len(box.rotors), "modal.n_modes", n_modes)
    mats = matrices(box)
    lam, v = _solve(box, mats, float(speed), n_modes, None)
    e, me = _energy(box, mats, _stiffness_full(box, mats, speed), v)
    return SystemModes(np.array([speed]), lam[None], v[None], e[None], me[None], groups(box)[0])


def reduction_basis(box: Gearbox, speed: float, n_modes: int, mats: Matrices | None = None) -> np.ndarray:
    """Basis of :func:`~.assembly.reduced_basis` keeping the undamped modes below 1.2 x the
    ``n_modes``-th undamped frequency at drive ``speed`` [rad/s]."""
    mats = matrices(box) if mats is None else mats
    M, _, K = system_matrices(box, speed, mats)
    w = undamped_modes(M, K, n_modes)[0]
    return reduced_basis(box, mats, speed, float(w[-1]), 1.2, bearings=False)


@dataclass(frozen=True)
class SystemCampbell:
    """Tracked modes vs drive speed, excitation lines and their crossings."""

    modes: SystemModes
    mac_min: np.ndarray
    lines: list  # {"name", "kind", "mesh"|"rotor", "order", "factor"}: omega = factor * Omega
    crossings: list  # {"mode", "line", "speed", "frequency", "mesh_energy", "torsional_fraction"}


def excitation_lines(box: Gearbox, harmonics=(1, 2, 3)) -> list[dict]:
    """Excitation frequencies per unit drive speed: mesh orders and each rotor's 1X."""
    out = []
    for i in range(len(box.meshes)):
        base = box.mesh_frequency(i, 1.0)
        for h in harmonics:
            out.append({"name": f"mesh{i} x{h:g}", "kind": "mesh", "mesh": i, "order": float(h), "factor": h * base})
    for pr in box.rotors:
        out.append({"name": f"{pr.name} 1X", "kind": "1X", "rotor": pr.name, "order": 1.0, "factor": pr.ratio})
    return out


def campbell(
    box: Gearbox, speeds, n_modes: int = 12, harmonics=(1, 2, 3), reduce: bool = True, extra: int = 6
) -> SystemCampbell:
    """Campbell diagram over drive speeds [rad/s], modes tracked by MAC (rotor/fe's
    :func:`~rotaflex.rotor.fe.modal.track_modes`, the Hungarian assignment of the total MAC).

    ``reduce`` solves in the basis of :func:`reduction_basis` at the middle speed (the benchmark
    prints the difference to the full solve); False: all DOFs.
    """
    speeds = np.asarray(speeds, float)
    if speeds.ndim != 1 or speeds.size < 2 or np.any(np.diff(speeds) <= 0):
        raise InputError("campbell.speed_rpm", list(np.round(rad_s_to_rpm(speeds), 6)), "increasing speeds (>= 2)")
    nfree = free_dofs(box).size
    check_campbell(box.n_dof, nfree, len(box.rotors), speeds.size, n_modes, nfree)
    mats = matrices(box)
    basis = None
    n_cand = min(n_modes + extra, nfree)
    if reduce:
        basis = reduction_basis(box, float(speeds[speeds.size // 2]), n_cand, mats)
        n_cand = min(n_cand, basis.shape[1])
    ns = speeds.size
    pencil = speed_pencil(box, mats, basis)
    cands = (_solve(box, mats, w, n_cand, basis, pencil) for w in speeds)
    # rotor/fe's tracking; the candidates are oscillatory modes only, so no track starts late
    lam_t, v_t, mac_min = track_modes(cands, np.zeros(ns, int), n_modes)
    if all(el.speed_independent for pr in box.rotors for _, _, el in pr.rotor.bearings):
        # speed-independent bearings: one stiffness matrix, energies of all speeds in one product
        e, me = _energy(box, mats, _stiffness_full(box, mats, 0.0), v_t.reshape(ns * n_modes, -1))
        e, me = e.reshape(ns, n_modes, -1), me.reshape(ns, n_modes)
    else:
        e = np.zeros((ns, n_modes, len(groups(box)[0])))
        me = np.zeros((ns, n_modes))
        for s in range(ns):
            e[s], me[s] = _energy(box, mats, _stiffness_full(box, mats, speeds[s]), v_t[s])
    modes = SystemModes(speeds, lam_t, v_t, e, me, groups(box)[0])
    lines = excitation_lines(box, harmonics)
    return SystemCampbell(modes, mac_min, lines, crossings(modes, lines))


def crossings(modes: SystemModes, lines: list[dict]) -> list[dict]:
    """Speeds where a tracked damped frequency crosses an excitation line (rotor/fe's
    :func:`~rotaflex.rotor.fe.modal.line_crossings`, quantities interpolated alike)."""
    sp, wd = modes.speed, modes.wd
    tf = modes.torsional_fraction
    out = []
    for li, line in enumerate(lines):
        for k, s, t, x in line_crossings(sp, wd, line["factor"]):
            out.append(
                {
                    "mode": k,
                    "line": line["name"],
                    "line_index": li,
                    "speed": float(x),
                    "frequency": float(line["factor"] * x),
                    "mesh_energy": float(
                        modes.mesh_energy[s, k] + t * (modes.mesh_energy[s + 1, k] - modes.mesh_energy[s, k])
                    ),
                    "torsional_fraction": float(tf[s, k] + t * (tf[s + 1, k] - tf[s, k])),
                }
            )
    out.sort(key=lambda c: c["speed"])
    return out
