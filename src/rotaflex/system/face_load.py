"""Axial position of a helical mesh's resultant: the static load distribution over the face.

The lumped mesh of :mod:`.helical` puts the resultant of the contact lines at one point. With
lead modifications or a misalignment the load over the face width is not uniform and its
resultant sits off mid-face; this module finds that axial offset ``z_c`` from the gear
package's sliced face model (:func:`rotaflex.gear.static.helical.sliced_te`, the one load
distribution model of the project) at the mesh's mean load, averaged over a mesh cycle:

    z_c = sum_j z_j <f_j> / sum_j <f_j>

(z_j: slice centres from mid-face along +z, the shafts' axis; <f_j>: slice j's load summed over
the tooth pairs and averaged over the cycle; the sum of the slice loads is the transverse force
F at every phase, so z_c is the cycle mean of the instantaneous resultant's position).

Transverse section. For ``source = "loaded_te"`` the FE tooth compliance along the path of
contact and the profile reliefs (:func:`rotaflex.gear.static.loaded_te.pair_line`, the data of
the mesh table); for every other source a path of contact of constant pair compliance without
profile gaps (:class:`UniformLine`), its compliance set so that the unmodified sliced face has
the mesh table's mean stiffness (ISO 6336-1's assumption of a constant mesh stiffness per unit
length of contact line, c_gamma).
"""

from __future__ import annotations

import dataclasses

import numpy as np

__all__ = ["UniformLine", "face_line", "face_load", "contact_offset"]

#: phases per mesh cycle of the cycle average: the load is a step function of the phase (slices
#: enter and leave the path), so the error does not fall smoothly; for the tests' pair with a
#: slope deviation the offset at 32 / 64 / 128 / 256 phases is 6.6e-4 / 1.5e-3 / 1.3e-3 / 2.0e-4
#: (relative) from 1024 phases
PHASES = 256


@dataclasses.dataclass(frozen=True)
class UniformLine:
    """A transverse section for :func:`~rotaflex.gear.static.helical.sliced_te` with a constant
    pair compliance ``q`` [m/N] over the path of contact ``[s_start, s_end]`` [m] and no profile
    gaps; ``base_pitch`` [m], ``force`` the transverse force along the line of action [N]."""

    s_start: float
    s_end: float
    base_pitch: float
    force: float
    q: float = 1.0

    def compliance(self, s) -> np.ndarray:
        """Pair compliance [m/N] at line-of-action positions ``s`` [m]."""
        return np.full(np.shape(s), self.q)

    def gap(self, s) -> np.ndarray:
        """No profile modification: zero gap [m]."""
        return np.zeros(np.shape(s))


def face_line(pair, gm, face, source: str, mesh_preset: str = "default"):
    """The transverse section of a mesh's sliced face at its mean load F = T_1 / r_b1.

    Parameters
    ----------
    pair : PairSpec
        The checked pair.
    gm : rotaflex.gear.GearMesh
        Its mesh (torque, mean stiffness).
    face : FaceModel
        The face in slices (:func:`rotaflex.gear.static.helical.face_model`).
    source : str
        The mesh table's source: ``"loaded_te"`` takes the FE tooth data, any other a
        :class:`UniformLine` with the table's mean stiffness.
    mesh_preset : str
        FE tooth mesh of ``"loaded_te"``.
    """
    from rotaflex.gear.static.helical import sliced_te

    force = gm.torque / gm.base_radius[0]
    if source == "loaded_te":
        from rotaflex.gear.cases.static import gear_meshes
        from rotaflex.gear.static.loaded_te import pair_line

        (e1, nu1, _), (e2, nu2, _) = pair.pinion.material.values, pair.wheel.material.values
        g1, g2 = pair.gears
        return pair_line(g1, g2, *gear_meshes(pair, mesh_preset), gm.center_distance, force, (e1, nu1, e2, nu2))
    line = UniformLine(0.0, pair.path_of_contact, pair.gears[0].base_pitch, force)
    s = _phases(line, PHASES)
    c = sliced_te(line, face, s, with_gaps=False)["stiffness"].mean()  # mean stiffness at q = 1
    return dataclasses.replace(line, q=c / gm.mean_stiffness)


def _phases(line, n: int) -> np.ndarray:
    """n reference positions [m] evenly over one base pitch, the set symmetric about the middle of
    the path of contact (modulo p_b): a face symmetric about mid-face and a path symmetric about
    its middle (:class:`UniformLine`) then give exactly a mid-face resultant, not one off by the
    sampling of the cycle (~3e-4 b at 64 phases with the set started at the path's start)."""
    return 0.5 * (line.s_start + line.s_end) + (np.arange(n) + 0.5) / n * line.base_pitch


def face_load(line, face, phases: int = PHASES) -> tuple[np.ndarray, np.ndarray]:
    """Cycle-mean load distribution over the face: (z_j [m] from mid-face, load per unit face
    width [N/m] at z_j, summed over the tooth pairs, along the transverse line of action)."""
    from rotaflex.gear.static.helical import slice_positions, sliced_te

    s = _phases(line, phases)
    load = sliced_te(line, face, s)["load"]  # (phases, pairs, slices) [N]
    db = face.face_width / face.n_slices
    return slice_positions(face.face_width, face.n_slices), load.sum(axis=1).mean(axis=0) / db


def contact_offset(line, face, phases: int = PHASES) -> float:
    """Axial offset z_c [m] of the resultant from mid-face (module docstring)."""
    z, w = face_load(line, face, phases)
    return float(np.sum(z * w) / np.sum(w))
