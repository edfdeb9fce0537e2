"""``gear static`` of a helical or lead-modified pair: the sliced face model's results.

The transverse FE data of the pair (``PairLine``, computed once) feed
:func:`rotaflex.gear.static.helical.sliced_te` over one mesh cycle and over one tooth pair's
engagement; this module turns them into the quantities ``gear static`` writes for every pair
(STE, mesh stiffness, load share, fillet stress) plus the helical ones: the load per unit length
over the face width and the roll angle, the normal, axial force and tilting moments.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from rotaflex.gear.static.helical import face_model, slice_positions, sliced_te

__all__ = ["SlicedResults", "sliced_results"]


@dataclasses.dataclass(frozen=True)
class SlicedResults:
    """What ``gear static`` writes from the sliced model (arrays over its grids, SI)."""

    cyc: dict
    cyc0: dict
    eng_te: np.ndarray
    share: np.ndarray
    share0: np.ndarray
    total_share: np.ndarray
    stress: np.ndarray
    pair_stiffness: np.ndarray
    data: dict  # extra variables: name -> (dims, values, units, long_name)
    coords: dict  # their coordinates: name -> (values, units, long_name)
    scalars: dict  # name -> (value, units, long_name)


def _tooth_sweep(res: dict, line, n_slices: int, face_width: float):
    """Load per unit length of ONE tooth pair over its engagement from one mesh cycle of all
    pairs: pair k at cycle position s is the same tooth pair at mid-face position s + k p_b."""
    pos = (
        res["s"][:, :, n_slices // 2]
        if n_slices % 2
        else res["s"][:, :, n_slices // 2 - 1 : n_slices // 2 + 1].mean(-1)
    )
    pos = pos.T.ravel()  # pair-major: k ascending, then the cycle
    load = np.transpose(res["load"], (1, 0, 2)).reshape(pos.size, n_slices)
    order = np.argsort(pos, kind="stable")
    pos, load = pos[order], load[order]
    keep = np.nonzero(load.sum(axis=1) > 0.0)[0]
    lo, hi = keep.min(), keep.max() + 1
    return pos[lo:hi], load[lo:hi] / (face_width / n_slices)


def sliced_results(cfg, pair, line, line0, s_cyc, s_eng) -> SlicedResults:
    """Sliced-model results of ``gear static``.

    Parameters
    ----------
    cfg : StaticConfig
        Its ``face`` table: slices, coupling length, misalignment.
    pair : PairSpec
    line, line0 : PairLine
        Transverse FE data with and without the profile reliefs.
    s_cyc, s_eng : ndarray
        Mid-face contact positions [m] of the reference pair over one mesh cycle and over its
        engagement (transverse line of action).
    """
    face = face_model(pair, cfg.face.slices, cfg.face.coupling_length_coef, cfg.face.misalignment)
    force = line.force
    cyc = sliced_te(line, face, s_cyc)
    cyc0 = sliced_te(line0, face, s_cyc, with_gaps=False)
    eng = sliced_te(line, face, s_eng)
    eng0 = sliced_te(line0, face, s_eng, with_gaps=False)
    k0 = int(np.nonzero(eng["k"] == 0)[0][0])
    ref = eng["load"][:, k0, :]  # (n, N) slice loads of the reference pair
    share = ref.sum(axis=1) / force
    share0 = eng0["load"][:, k0, :].sum(axis=1) / force
    # fillet stress of a slice: its line load f_j / db carried over the whole face (FE per newton
    # of a whole-face load), the largest over the face
    n_s, b = face.n_slices, face.face_width
    s_ref = eng["s"][:, k0, :]
    inside = (s_ref >= line.s_start) & (s_ref <= line.s_end)
    s_in = np.where(inside, s_ref, line.s_start)
    stress = line.fillet_stress(s_in.ravel(), (ref * n_s).ravel()).reshape(*ref.shape, 2).max(axis=1)
    kk = np.where(inside, 1.0 / (n_s * line.compliance(s_in.ravel()).reshape(s_in.shape)), 0.0)
    pos, line_load = _tooth_sweep(cyc, line, n_s, b)
    g1, g2 = pair.gears
    beta_b = pair.base_helix_angle
    aw = pair.operating_pressure_angle
    rw1, rw2 = g1.base_radius / math.cos(aw), g2.base_radius / math.cos(aw)
    axial = force * math.tan(beta_b)
    z = slice_positions(b, n_s)
    data = {
        "line_load": (
            ("tooth_roll", "z"),
            line_load,
            "N/m",
            "normal load per unit length of contact line of one tooth pair",
        ),
        "lead_gap": ("z", face.lead_gap, "m", "unloaded gap of the lead modifications and misalignment"),
        "slices_in_contact": ("cycle", cyc["n_contact"], "1", "slices in contact"),
    }
    scalars = {
        "normal_force": (force / math.cos(beta_b), "N", "total normal tooth force F / cos(beta_b)"),
        "axial_force": (axial, "N", "axial mesh force F tan(beta_b) = T tan(beta_w) / r_w1"),
        "tilting_moment_pinion": (axial * rw1, "N m", "tilting moment of the axial force at r_w1"),
        "tilting_moment_wheel": (axial * rw2, "N m", "tilting moment of the axial force at r_w2"),
        "line_load_max": (float(line_load.max()), "N/m", "largest load per unit length of contact line"),
        "line_load_mean_uniform": (
            force / (pair.contact_ratio * b),
            "N/m",
            "normal force over the mean total contact line length eps_alpha b / cos(beta_b)",
        ),
        "slices": (float(n_s), "1", "slices over the face width"),
        "coupling_length": (face.coupling_length, "m", "shear-layer coupling length lambda"),
    }
    return SlicedResults(
        cyc=cyc,
        cyc0=cyc0,
        eng_te=eng["te"],
        share=share,
        share0=share0,
        total_share=eng["load"].sum(axis=(1, 2)) / force,
        stress=stress,
        pair_stiffness=kk.sum(axis=1),
        data=data,
        scalars=scalars,
        coords={
            "tooth_roll": ((pos - line.s_start) / g1.base_radius, "rad", "pinion roll angle of the mid-face contact"),
            "z": (z, "m", "axial slice centre from mid-face"),
        },
    )
