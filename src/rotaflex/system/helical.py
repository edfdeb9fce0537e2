"""Outputs of helical meshes in a gearbox: axial mesh forces, tilting moments, thrust reactions.

A helical mesh (:func:`~.assembly.coupling_vector`) pushes the two gears apart axially with
``F_a = tan(beta_b) F`` (F: the transverse mesh force, along the transverse line of action) and
tilts each gear with the moment of that axial force at the pitch point, ``r_P x F_a e_z``
(magnitude ``F_a r_w``). The axial displacements w of the rotors carrying a helical mesh are
held by the bearings' thrust springs and dampers ``kzz``/``czz``; their reactions on the rotor
are ``-kzz (w - w_other) - czz (w' - w_other')``. Everything here is for boxes with
:attr:`~.model.Gearbox.axial`; spur boxes have none of it.
"""

from __future__ import annotations

import math

import numpy as np

from rotaflex.system.assembly import Matrices, bearing_matrices, load_vector, matrices, system_matrices
from rotaflex.system.model import Gearbox


def thrust_bearings(box: Gearbox) -> list[tuple[int, int, int | None, float, float, str]]:
    """(rotor, node, other node or None, kzz [N/m], czz [N s/m], label) of every bearing with an
    axial stiffness or damping on a rotor with axial DOFs; label ``"<rotor>:<node>"``."""
    out = []
    for r, pr in enumerate(box.rotors):
        if not pr.axial:
            continue
        for b, (node, other, _) in zip(pr.rotor.bearing, pr.rotor.bearings, strict=True):
            if b.kzz or b.czz:
                out.append((r, node, other, b.kzz, b.czz, f"{pr.name}:{node}"))
    return out


def thrust_operator(box: Gearbox, basis: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(A, kzz, czz): A (n_thrust, n_dof) gives the axial displacement across each thrust
    bearing of full DOF vectors (``A @ basis`` with a basis (n_dof, r)); kzz [N/m], czz [N s/m]."""
    brg = thrust_bearings(box)
    A = np.zeros((len(brg), box.n_dof))
    for b, (r, node, other, *_) in enumerate(brg):
        A[b, box.axial_dof(r, node)] = 1.0
        if other is not None:
            A[b, box.axial_dof(r, other)] = -1.0
    k = np.array([b[3] for b in brg])
    c = np.array([b[4] for b in brg])
    return (A if basis is None else A @ basis), k, c


def axial_reactions(
    box: Gearbox, q: np.ndarray, qd: np.ndarray | None = None, basis: np.ndarray | None = None
) -> np.ndarray:
    """Axial forces [N] of the thrust bearings on the rotor (..., n_thrust) at full DOF vectors
    q (..., n_dof) [m] and velocities qd (same shape, or None: static). With ``basis`` (n_dof,
    r), q and qd are coordinates in it (q_full = basis q): only the thrust rows are expanded."""
    A, k, c = thrust_operator(box, basis)
    f = -k * (q @ A.T)
    return f if qd is None else f - c * (qd @ A.T)


def mesh_axial_force(box: Gearbox, force: np.ndarray) -> np.ndarray:
    """Axial force [N] on the driven gear of each mesh (..., n_mesh) from transverse mesh forces
    ``force`` (..., n_mesh) [N]: ``sigma tan(beta_b) F`` along +z (the driver gets the opposite)."""
    t = np.array([m.axial_sign * math.tan(m.helix) for m in box.meshes])
    return force * t


def tilting_moments(box: Gearbox, force: np.ndarray) -> np.ndarray:
    """Tilting moments [N m] (..., n_mesh, 2 gears (driver, driven), 2 (M_x, M_y)) of the mesh
    force about each gear's centre, from transverse mesh forces ``force`` (..., n_mesh) [N]:
    the axial force's at the pitch point, ``r_P x (F_a e_z) = F_a (r_y, -r_x)``, plus, with the
    contact at ``z_c`` off mid-face (:attr:`~.model.MeshElement.offset`), the transverse force's
    ``z_c e_z x F n = F z_c (-n_y, n_x)`` (on the driven gear; the driver's are opposite)."""
    fa = mesh_axial_force(box, force)
    out = np.zeros((*np.shape(force), 2, 2))
    for j, m in enumerate(box.meshes):
        if m.helix > 0:
            for k, (arm, side) in enumerate(((m.arms[0], -1.0), (m.arms[1], 1.0))):
                out[..., j, k, 0] = side * fa[..., j] * arm[1]
                out[..., j, k, 1] = -side * fa[..., j] * arm[0]
                if m.offset:
                    out[..., j, k, 0] -= side * force[..., j] * m.offset * m.normal[1]
                    out[..., j, k, 1] += side * force[..., j] * m.offset * m.normal[0]
    return out


def static_state(box: Gearbox, speed: float, mats: Matrices | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Static state under the load with the mean mesh stiffness and mean TE at drive ``speed``
    [rad/s]: (q full DOFs [m, rad], transverse mesh forces (n_mesh,) [N]). With a torque drive
    the rigid twist is left out (least squares), as the steady state's start."""
    mats = matrices(box) if mats is None else mats
    _, _, K = system_matrices(box, speed, mats)
    e = np.array([m.gear.table.unloaded_te.mean() for m in box.meshes])
    g = mats.project(mats.g)
    rhs = mats.project(load_vector(box)) + g.T @ (mats.k_mean * e)
    p = np.linalg.lstsq(K, rhs, rcond=1e-12)[0]
    q = mats.expand(p)
    return q, mats.k_mean * (mats.g @ q - e)


def modal_shares(box: Gearbox, shapes: np.ndarray, speed: float = 0.0) -> dict[str, np.ndarray]:
    """Axial and tilting shares of modes with full shapes (..., n_dof):

    ``axial_kinetic`` (exact: M is block diagonal over the axial DOFs), ``tilt_kinetic`` (the
    tilt DOFs' diagonal block of M over ``v^H M v``; the beam's consistent mass couples tilts
    and translations, so it is a share of the diagonal, not a partition) and ``axial_strain``
    (strain energy of the shafts' bars and thrust springs over the mode's ``v^H K v``, mesh and
    bearings at drive ``speed`` [rad/s] included; the bars and thrust springs act on the axial
    DOFs alone, so their energy is exact; the mesh's axial part is not separable from it)."""
    mats = matrices(box)
    ax = np.array([box.axial_dof(r, n) for r, pr in enumerate(box.rotors) if pr.axial for n in range(pr.rotor.n_nodes)])
    tilt = np.array(
        [box.lateral_dof(r, n, a) for r, pr in enumerate(box.rotors) for n in range(pr.rotor.n_nodes) for a in (2, 3)]
    )
    v = np.asarray(shapes)

    def quad(X, idx=None):
        if idx is None:
            return np.real(np.sum(np.conj(v) * (v @ X.T), -1))
        return np.real(np.sum(np.conj(v[..., idx]) * (v[..., idx] @ X[np.ix_(idx, idx)].T), -1))

    Kb, _ = bearing_matrices(box, speed)
    K = mats.K0 + Kb + (mats.g.T * mats.k_mean) @ mats.g
    total_m = np.maximum(quad(mats.M), 1e-300)
    total_k = np.maximum(quad(0.5 * (K + K.T)), 1e-300)
    return {
        "axial_kinetic": quad(mats.M, ax) / total_m,
        "tilt_kinetic": quad(mats.M, tilt) / total_m,
        "axial_strain": quad(mats.K0, ax) / total_k,
    }


#: long names of the modal shares (units 1)
SHARES = {
    "axial_kinetic": "kinetic-energy fraction in the axial DOFs",
    "tilt_kinetic": "tilt DOFs' diagonal block of the kinetic energy / total",
    "axial_strain": "strain-energy fraction of the shafts' bars and thrust bearings",
}


def static_outputs(box: Gearbox, speed: float) -> tuple[dict, dict, dict]:
    """Dataset variables, coordinates and summary entries of the static state of a box with
    axial DOFs at drive ``speed`` [rad/s]: thrust bearing reactions, axial mesh forces and the
    tilting moments of the axial mesh force on each gear."""
    q, F = static_state(box, speed)
    ra = axial_reactions(box, q)
    fa = mesh_axial_force(box, F)
    tm = tilting_moments(box, F)
    names = [t[-1] for t in thrust_bearings(box)]
    data = {
        "static_axial_bearing_force": ("thrust", ra, {"units": "N", "long_name": "thrust bearing force on the rotor"}),
        "static_axial_mesh_force": ("mesh", fa, {"units": "N", "long_name": "axial mesh force on the driven gear"}),
        "static_tilting_moment": (
            ("mesh", "gear", "moment_axis"),
            tm,
            {"units": "N m", "long_name": "moment of the axial mesh force about the gear centre"},
        ),
    }
    coords = {"thrust": names, "gear": ["driver", "driven"], "moment_axis": ["x", "y"]}
    extra = {f"static_axial_force_{n}": {"value": float(f), "unit": "N"} for n, f in zip(names, ra, strict=True)}
    for j, m in enumerate(box.meshes):
        if m.helix > 0:
            extra[f"mesh{j}_static_axial_force"] = {
                "value": float(fa[j]),
                "unit": "N",
                "long_name": "on the driven gear",
            }
            for k, gear in enumerate(("driver", "driven")):
                extra[f"mesh{j}_static_tilting_moment_{gear}"] = {"value": float(np.hypot(*tm[j, k])), "unit": "N m"}
            if m.offset:
                extra[f"mesh{j}_contact_offset"] = {
                    "value": m.offset,
                    "unit": "m",
                    "long_name": "axial position of the mesh contact from mid-face (+z)",
                }
    if any(m.offset for m in box.meshes):
        data["contact_offset"] = (
            "mesh",
            np.array([m.offset for m in box.meshes]),
            {"units": "m", "long_name": "axial position of the mesh contact from mid-face (+z)"},
        )
    return data, coords, extra


# -- dataset outputs of the verbs (rotaflex system modal/campbell/steady) --------------------
def dataset_shares(box, ds, shapes, speed: float, dims) -> dict:
    """Add the axial and tilting energy shares of the modes (:func:`modal_shares`) to
    ``ds`` for a box with helical meshes; returns them ({} for spur boxes: nothing changes)."""
    if not box.axial:
        return {}
    shares = modal_shares(box, shapes, speed)
    for key, v in shares.items():
        ds[key] = (dims, v, {"units": "1", "long_name": SHARES[key]})
    return shares


def dataset_static(box, ds, extra: dict, speed: float) -> None:
    """Add the static thrust reactions, axial mesh forces and tilting moments (helical boxes)."""
    if not box.axial:
        return
    data, coords, more = static_outputs(box, speed)
    for key, v in data.items():
        ds[key] = v
    ds.coords.update(coords)
    extra.update(more)


def dataset_steady(box, ds, extra: dict, s, speed: float) -> None:
    """Thrust reactions, axial mesh forces and tilting moments of a steady state (helical)."""
    dataset_static(box, ds, extra, speed)
    fa = mesh_axial_force(box, s.force)
    tm = np.linalg.norm(tilting_moments(box, s.force), axis=-1)
    ds["axial_bearing_force"] = (("time", "thrust"), s.axial_force, {"units": "N", "long_name": "on the rotor"})
    ds["axial_mesh_force"] = (("time", "mesh"), fa, {"units": "N", "long_name": "on the driven gear"})
    ds["tilting_moment"] = (("time", "mesh", "gear"), tm, {"units": "N m", "long_name": "|moment| of the axial force"})
    extra["axial_bearing_force_max"] = {"value": float(np.abs(s.axial_force).max(initial=0.0)), "unit": "N"}
    extra["axial_mesh_force_max"] = {"value": float(np.abs(fa).max()), "unit": "N"}
    extra["tilting_moment_max"] = {"value": float(tm.max()), "unit": "N m"}
