"""Loaded static transmission error of a general spur pair (unequal, shifted, relieved teeth).

Model
-----
Along the line of action (LoA) of a pair at working centre distance ``a'``, ``s`` is the
distance of the contact point from the pinion's base-circle tangency point T1 (``r1^2 =
r_b1^2 + s^2``, ``r2^2 = r_b2^2 + (T1T2 - s)^2``). Each tooth pair in contact is a spring of
compliance ``q(s) = q1(r1) + q2(r2) + q_H(s)`` (FE tooth compliances of each gear on its own
mesh, interpolated by cubic splines in the contact radius, plus Weber's 2-D contact term) that
starts carrying load once the LoA approach ``delta`` exceeds its unloaded gap
``e(s) = c1(r1) + c2(r2)``, the profile-relief depths of the two flanks (the same functions
that moved the mesh flank nodes, :meth:`GearGeometry.relief_depth`). The loaded static
transmission error ``delta`` [m along the LoA] solves ``sum_j max(delta - e_j, 0) / q_j = F``
with ``F = T_pinion / r_b1`` (all pairs ``s + k p_b`` on the path of contact). Without relief all
gaps are zero and ``delta = F / sum_j (1 / q_j)``, the result of :func:`static.mesh_stiffness`.

Mesh cycle: the reference pair runs over one base pitch ``s in [s_A, s_A + p_b)`` from the
start of its contact ``s_A``; means over the cycle are one-cycle means (uniform samples,
endpoint excluded). Engagement: the reference pair's whole contact ``s in [s_A, s_E]``.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from scipy.interpolate import CubicSpline

from rotaflex.gear.pair.geometry import GearGeometry
from rotaflex.gear.pair.tooth_mesh import ToothMesh
from rotaflex.gear.static.tooth_analysis import (
    hertz_half_width,
    root_stress_operator,
    solve_static,
    surface_load,
    tooth_compliance,
    weber_contact_compliance,
)

__all__ = ["ToothData", "tooth_data", "PairLine", "pair_line", "loaded_te", "contact_half_width", "contact_compliance"]


def contact_half_width(force, b, e1, nu1, e2, nu2, rho1, rho2) -> float:
    """Hertzian half-width of two cylinders (plane stress, 1/E* = 1/E1 + 1/E2) [m].

    For identical materials this is :func:`static.hertz_half_width` (called as such so the
    identical-gear numbers stay bit-identical).
    """
    if e1 == e2 and nu1 == nu2:
        return hertz_half_width(force, b, e1, nu1, rho1, rho2)
    r = rho1 * rho2 / (rho1 + rho2)
    e_star = 1.0 / (1.0 / e1 + 1.0 / e2)
    return math.sqrt(4.0 * force * r / (math.pi * b * e_star))


def contact_compliance(force, b, e1, nu1, e2, nu2, h1, h2, half_width):
    """Weber's 2-D contact compliance between the two centreline points [m/N] (plane stress).

    ``2/(pi b) [(ln(2 h1/a) - nu1/2)/E1 + (ln(2 h2/a) - nu2/2)/E2]``; identical materials:
    :func:`static.weber_contact_compliance`.
    """
    if e1 == e2 and nu1 == nu2:
        return weber_contact_compliance(force, b, e1, nu1, h1, h2, half_width)
    h1, h2, a = np.asarray(h1), np.asarray(h2), np.asarray(half_width)
    return 2.0 / (math.pi * b) * ((np.log(2.0 * h1 / a) - 0.5 * nu1) / e1 + (np.log(2.0 * h2 / a) - 0.5 * nu2) / e2)


@dataclasses.dataclass(frozen=True)
class ToothData:
    """FE results of one tooth at contact radii (per unit normal load).

    Attributes
    ----------
    radius : ndarray
        Contact radii [m].
    compliance : ndarray
        Structural (centreline-point) compliance [m/N].
    load_point : ndarray
        Work-conjugate load-patch compliance [m/N] (mesh dependent).
    arm : ndarray
        Contact point to centreline distance along the LoA [m].
    fillet_stress : ndarray, shape (n, 2)
        Tangential fillet stress at the 30-degree points (loaded side = "right"; columns
        left = compression side, right = tension side) per newton [Pa/N].
    """

    radius: np.ndarray
    compliance: np.ndarray
    load_point: np.ndarray
    arm: np.ndarray
    fillet_stress: np.ndarray


def tooth_data(mesh: ToothMesh, radii, e, nu, force, mate: GearGeometry, e_mate=None, nu_mate=None) -> ToothData:
    """Compliance and fillet stress of ``mesh``'s tooth under a flank load at ``radii``."""
    radii = np.asarray(radii, dtype=float)
    c = (
        tooth_compliance(mesh, radii, e, nu, force=force, mate=mate)
        if (e_mate is None or (e_mate == e and nu_mate == nu))
        else _tooth_compliance_mixed(mesh, radii, e, nu, force, mate, e_mate, nu_mate)
    )
    loads = np.stack([surface_load(mesh, r, force, a) for r, a in zip(radii, c.half_width, strict=True)], axis=1)
    u = solve_static(mesh, loads, e, nu)
    s = root_stress_operator(mesh, e, nu) @ u / force  # (2, n)
    return ToothData(radii, c.structural, c.load_point, c.arm, s.T)


def _tooth_compliance_mixed(mesh, radii, e, nu, force, mate, e_mate, nu_mate):
    from rotaflex.gear.static.tooth_analysis import _mate_curvatures

    rho1, rho2 = _mate_curvatures(mesh.geometry, radii, mate)
    hw = np.array(
        [
            contact_half_width(force, mesh.geometry.face_width, e, nu, e_mate, nu_mate, a, b)
            for a, b in zip(rho1, rho2, strict=True)
        ]
    )
    # one patch width per radius: call per radius (tooth_compliance takes a scalar width)
    parts = [
        tooth_compliance(mesh, np.array([r]), e, nu, force=force, half_width=w) for r, w in zip(radii, hw, strict=True)
    ]
    from rotaflex.gear.static.tooth_analysis import ToothCompliance

    return ToothCompliance(
        radii,
        np.concatenate([p.structural for p in parts]),
        np.concatenate([p.load_point for p in parts]),
        np.concatenate([p.arm for p in parts]),
        hw,
    )


@dataclasses.dataclass(frozen=True)
class PairLine:
    """Pair quantities along the line of action (see module docstring)."""

    g1: GearGeometry
    g2: GearGeometry
    center_distance: float
    length: float  # T1T2 [m]
    s_start: float  # s_A [m]
    s_end: float  # s_E [m]
    base_pitch: float
    force: float
    tooth1: ToothData
    tooth2: ToothData
    elastic: tuple  # (E1, nu1, E2, nu2)

    def radii(self, s):
        """Contact radii (r1, r2) at LoA positions ``s`` [m]."""
        s = np.asarray(s, dtype=float)
        return (np.sqrt(self.g1.base_radius**2 + s**2), np.sqrt(self.g2.base_radius**2 + (self.length - s) ** 2))

    def compliance(self, s) -> np.ndarray:
        """Pair compliance q1 + q2 + q_H [m/N] at ``s``."""
        e1, nu1, e2, nu2 = self.elastic
        s = np.asarray(s, dtype=float)
        r1, r2 = self.radii(s)
        q1 = CubicSpline(self.tooth1.radius, self.tooth1.compliance)
        q2 = CubicSpline(self.tooth2.radius, self.tooth2.compliance)
        h1 = CubicSpline(self.tooth1.radius, self.tooth1.arm)
        h2 = CubicSpline(self.tooth2.radius, self.tooth2.arm)
        hw = np.array(
            [
                contact_half_width(self.force, self.g1.face_width, e1, nu1, e2, nu2, x, y)
                for x, y in zip(s, self.length - s, strict=True)
            ]
        )
        qh = contact_compliance(self.force, self.g1.face_width, e1, nu1, e2, nu2, h1(r1), h2(r2), hw)
        return q1(r1) + q2(r2) + qh

    def gap(self, s) -> np.ndarray:
        """Unloaded gap from the profile reliefs of both flanks [m] at ``s``."""
        r1, r2 = self.radii(s)
        return self.g1.relief_depth(r1) + self.g2.relief_depth(r2)

    def fillet_stress(self, s, load) -> np.ndarray:
        """Tension-side fillet stress of pinion and wheel [Pa], shape (n, 2), for pair loads."""
        r1, r2 = self.radii(s)
        f1 = np.interp(r1, self.tooth1.radius, self.tooth1.fillet_stress[:, 1])
        f2 = np.interp(r2, self.tooth2.radius, self.tooth2.fillet_stress[:, 1])
        return np.column_stack([f1 * load, f2 * load])


def pair_line(g1, g2, mesh1, mesh2, center_distance, force, elastic, n_radii=9) -> PairLine:
    """FE tooth data of both gears over the path of contact at ``center_distance``.

    Parameters
    ----------
    g1, g2 : GearGeometry
        Pinion and wheel (with reliefs).
    mesh1, mesh2 : ToothMesh
        Their tooth meshes.
    center_distance : float
        Working centre distance [m].
    force : float
        Design normal load [N] (sets the Hertz patches; the tooth model is linear).
    elastic : tuple
        (E1, nu1, E2, nu2).
    n_radii : int
        FE load cases per tooth over its active profile (cubic interpolation between).
    """
    aw = math.acos((g1.base_radius + g2.base_radius) / center_distance)
    length = center_distance * math.sin(aw)
    s_end = math.sqrt(g1.tip_radius_**2 - g1.base_radius**2)
    # same operation order as static.mesh_stiffness (bit-identical identical-gear numbers)
    g = s_end + math.sqrt(g2.tip_radius_**2 - g2.base_radius**2) - length
    s_start = s_end - g
    e1, nu1, e2, nu2 = elastic
    rr1 = np.sqrt(g1.base_radius**2 + np.linspace(s_start, s_end, n_radii) ** 2)
    rr2 = np.sqrt(g2.base_radius**2 + np.linspace(length - s_end, length - s_start, n_radii) ** 2)
    t1 = tooth_data(mesh1, rr1, e1, nu1, force, g2, e2, nu2)
    t2 = tooth_data(mesh2, rr2, e2, nu2, force, g1, e1, nu1)
    return PairLine(g1, g2, center_distance, length, s_start, s_end, g1.base_pitch, force, t1, t2, tuple(elastic))


def loaded_te(line: PairLine, s_ref: np.ndarray, force: float | None = None) -> dict:
    """Loaded static TE with all pairs ``s_ref + k p_b`` on the path of contact.

    Returns
    -------
    dict
        ``te`` [m] along the LoA, ``stiffness`` (sum of the loaded pairs' 1/q) [N/m],
        ``share`` (n, 5) load fraction of pairs k = -2..2 (k = 0 the reference pair),
        ``pair_load`` (n, 5) [N], ``n_loaded`` number of loaded pairs, ``s`` (n, 5) positions.
    """
    force = line.force if force is None else float(force)
    s_ref = np.asarray(s_ref, dtype=float)
    ks = np.arange(-2, 3)
    s = s_ref[:, None] + ks[None, :] * line.base_pitch
    inside = (s >= line.s_start - 1e-15) & (s <= line.s_end + 1e-15)
    q = np.full(s.shape, np.inf)
    gap = np.full(s.shape, np.inf)
    q[inside] = line.compliance(s[inside])
    gap[inside] = line.gap(s[inside])
    kk = np.where(inside, 1.0 / q, 0.0)
    te = np.empty(s_ref.size)
    for i in range(s_ref.size):  # <= 5 pairs per position: active-set by increasing gap
        order = np.argsort(gap[i])
        num, den = force, 0.0
        for j in order:
            if not inside[i, j]:
                break
            if den > 0.0 and num / den <= gap[i, j]:
                break  # this pair's gap is not closed
            num += kk[i, j] * gap[i, j]
            den += kk[i, j]
        te[i] = num / den
    if gap[np.isfinite(gap)].max(initial=0.0) == 0.0:  # no relief: pairs in parallel
        ksum = kk.sum(axis=1)
        te, stiff = force / ksum, ksum
        share = kk / ksum[:, None]
        load = share * force
    else:
        load = np.where(inside, np.maximum(te[:, None] - gap, 0.0) * kk, 0.0)
        stiff = np.where(load > 0.0, kk, 0.0).sum(axis=1)
        share = load / force
    return {
        "te": te,
        "stiffness": stiff,
        "share": share,
        "pair_load": load,
        "n_loaded": (load > 0.0).sum(axis=1),
        "s": s,
    }
