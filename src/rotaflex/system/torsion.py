"""Torsional analysis of a machine train as practised (API 684 section 4): the twist DOFs only.

The torsional model of a :class:`~rotaflex.system.model.Gearbox` keeps the twist DOF of every node
of the rotors with ``torsion = true``: the shafts' torsional elements and disks (the assembly's
blocks), the couplings' torsional springs and dampers (rigid couplings as constraints), and each
gear mesh as a torsional spring ``k_m`` on the base-circle arcs ``s_d (r_bd theta_d + r_bf
theta_f)`` (the twist part of the mesh coupling vector; lateral motion of the gears held, the
usual train model). The train is free-free: the rigid-body rotation (theta proportional to
each rotor's speed ratio and sense) is a zero-frequency mode, dropped from the natural
frequencies.

- :func:`torsional_model`: J, C, K on the solved twist coordinates and the map to all twists;
- :func:`torsional_modes`: natural frequencies [rad/s] and mode shapes;
- :func:`excitation_lines`, :func:`crossings`, :func:`separation_margins`: the interference
  (torsional Campbell) diagram and the API 684 separation margins;
- :func:`startup`: run-up from rest under a motor torque-speed curve against a load
  (:mod:`scipy.integrate`, Radau), with the work and energy bookkeeping of the run.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla

from rotaflex.rotor.fe.modal import line_crossings
from rotaflex.system.assembly import constraint, matrices
from rotaflex.system.model import Gearbox


@dataclass(frozen=True)
class TorsionalModel:
    """Twist-only equations ``J p'' + C p' + K p = T^T tau`` of a train.

    ``dofs``: global twist DOF indices (n_twist,); ``labels``: ``"rotor:node"`` per twist;
    ``T`` (n_twist, n): twists of the solved coordinates p; ``sense``/``ratio`` per twist: sense
    of rotation (+1 ccw) and speed per unit drive speed of its rotor.
    """

    J: np.ndarray
    C: np.ndarray
    K: np.ndarray
    T: np.ndarray
    dofs: np.ndarray
    labels: list
    sense: np.ndarray
    ratio: np.ndarray

    def index(self, box: Gearbox, rotor: int, node: int) -> int:
        """Position of a node's twist in :attr:`dofs`."""
        return int(np.flatnonzero(self.dofs == box.torsion_dof(rotor, node))[0])

    @property
    def rigid_body(self) -> np.ndarray:
        """Solved coordinates of the rigid rotation at unit drive angle (twists = sense x ratio)."""
        return np.linalg.lstsq(self.T, self.sense * self.ratio, rcond=None)[0]


def torsional_model(box: Gearbox) -> TorsionalModel:
    """The free-free torsional model of ``box`` (see the module docstring)."""
    mats = matrices(box)
    dofs, labels, sense, ratio = [], [], [], []
    for r, pr in enumerate(box.rotors):
        if pr.torsion:
            for node in range(pr.rotor.n_nodes):
                dofs.append(box.torsion_dof(r, node))
                labels.append(f"{pr.name}:{node}")
                sense.append(pr.sense)
                ratio.append(pr.ratio)
    tw = np.array(dofs)
    K = mats.K0[np.ix_(tw, tw)].copy()
    C = mats.C0[np.ix_(tw, tw)].copy()
    if len(box.meshes):
        gt = mats.g[:, tw]
        K += (gt.T * mats.k_mean) @ gt
        C += (gt.T * mats.c_mesh) @ gt
    # rigid couplings tie twists to twists; the train is free-free (no speed-controlled drive)
    _, Tf = constraint(dataclasses.replace(box, drive_kind="torque"))
    if Tf is None:
        T = np.eye(tw.size)
    else:
        T = Tf[tw]
        T = T[:, np.any(T != 0, 0)]
    return TorsionalModel(
        T.T @ mats.M[np.ix_(tw, tw)] @ T,
        T.T @ C @ T,
        T.T @ K @ T,
        T,
        tw,
        labels,
        np.array(sense, float),
        np.array(ratio),
    )


def torsional_modes(model: TorsionalModel, n_modes: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Undamped torsional natural frequencies [rad/s] (rigid-body modes dropped) and mode shapes
    (n_modes, n_twist): twist per node, largest |twist| = +1.

    The rigid-body modes are the lowest :func:`n_rigid` ones (one per group of twists that no
    spring joins to another)."""
    w2, phi = eigen(model)
    nr = n_rigid(model.K)
    w, phi = np.sqrt(np.clip(w2[nr:], 0.0, None)), phi[:, nr:]
    if n_modes is not None:
        w, phi = w[:n_modes], phi[:, :n_modes]
    shape = (model.T @ phi).T
    j = np.argmax(np.abs(shape), 1)
    shape = shape / shape[np.arange(shape.shape[0]), j][:, None]
    return w, shape


def eigen(model: TorsionalModel) -> tuple[np.ndarray, np.ndarray]:
    """All eigenpairs of (K, J): omega^2 ascending [rad^2/s^2] and shapes with ``Phi^T J Phi = I``.

    Solved as the shifted inverse pencil ``J phi = mu (K + s J) phi``, ``omega^2 = 1/mu - s``
    (s = 1e-6 trace(K) / trace(J)): the low modes, the ones a train analysis is about, are then
    the largest eigenvalues and keep their relative accuracy (~1e-13 on a disk-on-light-shaft
    train whose direct form ``eigh(K, J)`` loses 1e-5, tests/system/test_train_torsional.py);
    the upper modes take the Rayleigh quotient of their shapes instead."""
    K = 0.5 * (model.K + model.K.T)
    s = 1e-6 * np.trace(K) / np.trace(model.J)
    mu, phi = sla.eigh(model.J, K + s * model.J)
    order = np.argsort(mu)[::-1]
    mu, phi = mu[order], phi[:, order]
    phi = phi / np.sqrt(np.einsum("ik,ij,jk->k", phi, model.J, phi))
    w2 = 1.0 / mu - s
    # the inverse form loses eps (w^2 + s) / s on a mode, the Rayleigh quotient phi^T K phi loses
    # eps w_max^2 / w^2: take the better of the two per mode (the quotient for the upper modes)
    rq = np.einsum("ik,ij,jk->k", phi, K, phi)
    better = w2.max() * s < np.maximum(w2, 0.0) * (w2 + s)
    return np.where(better, rq, w2), phi


def n_rigid(K: np.ndarray) -> int:
    """Number of rigid-body rotations of a free torsional stiffness K: its connected groups of
    coordinates (K is a weighted graph Laplacian; counted on the pattern, not on round-off)."""
    from scipy.sparse.csgraph import connected_components

    return int(connected_components(np.abs(K) > 0, directed=False)[0])


def excitation_lines(box: Gearbox, listed) -> list[dict]:
    """Excitation frequencies of the listed sources: ``{"name", "kind", "factor", "fixed"}``
    with omega = factor x drive speed + fixed [rad/s].

    ``listed``: dicts with ``kind`` ("shaft": order x a rotor's speed; "mesh": order x a mesh's
    tooth-passing frequency; "fixed": order x ``frequency`` [rad/s], e.g. twice the line
    frequency of a motor), ``order``, ``rotor`` (index) / ``mesh`` (index) / ``frequency``,
    optional ``name``."""
    out = []
    for e in listed:
        h = float(e.get("order", 1.0))
        if e["kind"] == "shaft":
            pr = box.rotors[e["rotor"]]
            factor, fixed, name = h * pr.ratio, 0.0, f"{pr.name} {h:g}X"
        elif e["kind"] == "mesh":
            factor, fixed, name = h * box.mesh_frequency(e["mesh"], 1.0), 0.0, f"mesh{e['mesh']} x{h:g}"
        else:
            factor, fixed, name = 0.0, h * float(e["frequency"]), f"{h:g} x {e['frequency'] / (2 * np.pi):g} Hz"
        out.append({"name": e.get("name") or name, "kind": e["kind"], "factor": float(factor), "fixed": float(fixed)})
    return out


def default_excitations(box: Gearbox) -> list[dict]:
    """1X and 2X of each rotor and the first two orders of each mesh."""
    out = [{"kind": "shaft", "rotor": r, "order": h} for r in range(len(box.rotors)) for h in (1.0, 2.0)]
    return out + [{"kind": "mesh", "mesh": m, "order": h} for m in range(len(box.meshes)) for h in (1.0, 2.0)]


def crossings(freqs: np.ndarray, lines: list[dict], speed_range) -> list[dict]:
    """Drive speeds [rad/s] in ``speed_range`` where a speed-proportional line meets a natural
    frequency, by rotor/fe's :func:`~rotaflex.rotor.fe.modal.line_crossings` (the one crossing
    interpolation of every Campbell diagram) over the two ends of the range.

    The torsional frequencies do not depend on speed, so ``omega_n - fixed - factor Omega`` is
    linear in Omega and the interpolation between the ends is the exact crossing ``Omega =
    (omega_n - fixed) / factor`` up to round-off (2.2e-16 relative at most on the train
    examples, every crossing found by both; tests/system/test_torsional_crossings.py). As for
    every Campbell diagram, a crossing counts where the difference changes sign: one exactly at
    an end of the range (a zero there) is not counted."""
    ends = np.asarray(speed_range, float)
    w = np.asarray(freqs, float)
    out = []
    for li, ln in enumerate(lines):
        if ln["factor"] <= 0:
            continue
        for k, _, _, s in line_crossings(ends, np.tile(w - ln["fixed"], (2, 1)), ln["factor"]):
            out.append({"mode": k, "line": ln["name"], "line_index": li, "speed": float(s), "frequency": float(w[k])})
    out.sort(key=lambda c: c["speed"])
    return out


def separation_margins(freqs: np.ndarray, lines: list[dict], operating, required: float = 0.10):
    """API 684 separation margins of each mode from each excitation over the operating range.

    The excitation sweeps ``[f_lo, f_hi]`` = the line at the lowest and highest operating drive
    speed (one frequency for a fixed line). The margin of a natural frequency ``f_n`` is
    ``max(f_n / f_hi - 1, 1 - f_n / f_lo)``: the relative distance above the band's top or below
    its bottom, negative inside the band. API 684 (2005) 4.3 / API 617 asks for at least 10 %
    (``required``) above or below every excitation frequency in the operating range.

    Returns
    -------
    margin : (n_modes, n_lines) relative margin [1]
    passed : (n_modes, n_lines) bool, margin >= required
    """
    lo, hi = operating
    f_lo = np.array([ln["factor"] * lo + ln["fixed"] for ln in lines])
    f_hi = np.array([ln["factor"] * hi + ln["fixed"] for ln in lines])
    fn = np.asarray(freqs, float)[:, None]
    with np.errstate(divide="ignore"):
        margin = np.maximum(fn / f_hi[None] - 1.0, 1.0 - fn / f_lo[None])
    return margin, margin >= required - 1e-12
