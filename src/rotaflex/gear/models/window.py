"""Fast continuous-meshing model: reduced elastic teeth in a window that travels with the mesh.

The torsional chain of :mod:`~.chain` (motor, pinion, wheel, load; shafts, drive law) with
the lumped mesh spring replaced by the tooth pairs themselves. Pair ``n`` (pinion tooth ``n``
against wheel tooth ``n``) sits at the line-of-action (LoA) position
``s_n = r_b1 theta_1 + s_A - n p_b`` (``s`` from the pinion's base tangency point, ``s_A`` the
start of the path of contact, ``theta_1 = 0`` when pair 0 enters). Each pair is:

* two **reduced elastic teeth**: the lowest ``n_modes`` fixed-root modes of each gear's FE tooth
  (plane stress, consistent mass), mass-normalised, with participation ``a_k(r) = phi_k . p(r)``
  of a unit Hertzian flank load ``p(r)`` at contact radius ``r``; modal damping ratio
  ``zeta_t``;
* in series with a massless **residual spring** ``q_res(s) = q_pair(s) - sum_k a_k^2/omega_k^2``
  (both gears), where ``q_pair`` is the FE pair compliance of :mod:`~.loaded_te` (tooth
  compliances + Weber's contact term). So the model's static pair compliance is exactly the
  ``gear static`` one, whatever ``n_modes``; ``n_modes = 0`` gives massless teeth;
* a **gap** ``e(s)``: the profile reliefs of both flanks on the path of contact and, beyond its
  ends, the separation of the mate's tip corner from the flank (premature corner contact:
  rigid involute kinematics, :func:`corner_gap`), so a pair takes load gradually when the
  loaded gears let the corner touch early, instead of appearing with a finite overlap;
* mesh damping: the lumped model's dashpot ``c_m`` between the base circles, acting while
  any pair touches, growing linearly with the largest pair deflection up to
  ``damping_onset`` (10 % of the mean static deflection) so that first touch gives no force
  step. Joined to the bodies, it damps vibration but not the kinematic approach of a relieved
  or corner profile rolling through the contact (a dashpot on each pair's full approach rate
  resists the corner sweeping in at up to ~0.5 m/s and gave force spikes of 4x the static
  load at 20,000 rpm, which no mesh damping measurement supports).

Pair force ``F_n = k_res delta_n`` while ``delta_n > 0`` (else 0) with
``delta_n = r_b1 theta_1 - r_b2 theta_2 - e(s_n) - a_1(s_n).eta_1n - a_2(s_n).eta_2n``.
Only the ``window`` teeth from one base pitch before the first possible contact to beyond the
last carry modal states; a tooth entering the window starts undeformed and at rest (its ring-down
from the previous engagement, a revolution earlier, has decayed), a tooth leaving it gives up its
remaining vibration energy (reported as ``dropped`` in the energy balance). The tooth's elastic
motion feeds back on the gear bodies through the contact force only (no rotating-frame terms).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from scipy.interpolate import CubicSpline

from rotaflex.core.errors import InputError
from rotaflex.gear.models.chain import TorsionalSystem
from rotaflex.gear.static.loaded_te import PairLine, contact_half_width
from rotaflex.gear.static.tooth_analysis import surface_load

__all__ = ["ToothModes", "WindowModel", "tooth_modes", "corner_gap", "build_window_model"]

DEFAULT_TOOTH_DAMPING_RATIO = 0.02


@dataclasses.dataclass(frozen=True)
class ToothModes:
    """Fixed-root modes of one tooth and their participation in flank loads.

    Attributes
    ----------
    radius : ndarray (n_r,)
        Contact radii [m].
    omega : ndarray (n_m,)
        Natural circular frequencies [rad/s].
    participation : ndarray (n_r, n_m)
        ``a_k(r)`` per unit normal load [1/sqrt(kg)] (mass-normalised modes).
    mass : float
        Tooth + rim-sector mass [kg].
    """

    radius: np.ndarray
    omega: np.ndarray
    participation: np.ndarray
    mass: float

    @property
    def modal_compliance(self) -> np.ndarray:
        """``sum_k a_k(r)^2 / omega_k^2`` [m/N] (the retained modes' static compliance)."""
        if self.omega.size == 0:
            return np.zeros(self.radius.size)
        return (self.participation**2 / self.omega**2).sum(axis=1)


def tooth_modes(mesh, radii, e, nu, density, half_width, n_modes: int) -> ToothModes:
    """Lowest ``n_modes`` modes of ``mesh``'s tooth with the root nodes fixed.

    Parameters
    ----------
    mesh : ToothMesh
    radii : ndarray
        Contact radii of the participation table [m].
    e, nu, density : float
        Young's modulus [Pa], Poisson ratio, density [kg/m^3].
    half_width : ndarray
        Hertzian half-width of the load patch at each radius [m].
    n_modes : int
        Modes kept (0: massless teeth).
    """
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    from rotaflex.gear.pair.plane_stress import consistent_mass, stiffness_matrix

    radii = np.asarray(radii, dtype=float)
    m_full = consistent_mass(mesh, density)
    total = float(np.ones(m_full.shape[0]) @ (m_full @ np.ones(m_full.shape[0]))) / 2.0
    if n_modes == 0:
        return ToothModes(radii, np.zeros(0), np.zeros((radii.size, 0)), total)
    k = stiffness_matrix(mesh, e, nu)
    fixed = np.concatenate([2 * mesh.root_nodes, 2 * mesh.root_nodes + 1])
    free = np.setdiff1d(np.arange(k.shape[0]), fixed)
    kf = sp.csc_matrix(k[free][:, free])
    mf = sp.csc_matrix(m_full[free][:, free])
    # a fixed start vector: ARPACK's random one made the modes (and results) differ by ~1e-9
    # from run to run
    w2, vec = spla.eigsh(kf, k=n_modes, M=mf, sigma=0.0, which="LM", v0=np.ones(kf.shape[0]))
    order = np.argsort(w2)
    w2, vec = w2[order], vec[:, order]
    vec /= np.sqrt(np.einsum("ik,ik->k", vec, mf @ vec))  # mass-normalise
    loads = np.stack([surface_load(mesh, r, 1.0, a)[free] for r, a in zip(radii, half_width, strict=True)], axis=1)
    return ToothModes(radii, np.sqrt(w2), loads.T @ vec, total)


def corner_gap(rb_flank, rb_corner, r_tip_corner, length, s) -> np.ndarray:
    """Separation [m] of the corner gear's tip corner from the flank gear's involute.

    Rigid involute kinematics. ``s`` is the conjugate contact point's distance from the flank
    gear's base tangency point along the LoA (``length`` = T1T2); the corner (radius
    ``r_tip_corner`` on the corner gear's involute) touches the flank at
    ``s = length - sqrt(r_tip_corner^2 - rb_corner^2)`` and is clear of it for smaller ``s``
    (before the path of contact). Computed in the flank gear's frame: a point at radius ``r``
    and polar angle ``phi`` is ``sqrt(r^2 - rb^2) - rb (phi + acos(rb / r))`` from the involute
    unwound from angle 0 (measured along its normal, a base-circle tangent).
    """
    s = np.asarray(s, dtype=float)
    u1 = s / rb_flank  # flank involute roll angle at the conjugate contact point
    e = np.stack([np.sin(u1), -np.cos(u1)], axis=-1)  # LoA direction T1 -> T2
    radial = np.stack([np.cos(u1), np.sin(u1)], axis=-1)
    t2 = rb_flank * radial + length * e
    o2 = t2 + rb_corner * radial
    rho_a = math.sqrt(r_tip_corner**2 - rb_corner**2)
    g = u1 + math.pi + (rho_a - (length - s)) / rb_corner
    c = o2 + rb_corner * np.stack([np.cos(g), np.sin(g)], axis=-1) + rho_a * np.stack([np.sin(g), -np.cos(g)], axis=-1)
    r = np.hypot(c[..., 0], c[..., 1])
    # polar angle unwrapped near the contact point's (u1 - atan(s / rb)), no 2 pi ambiguity
    ref = u1 - np.arctan2(s, rb_flank)
    phi = ref + np.angle(np.exp(1j * (np.arctan2(c[..., 1], c[..., 0]) - ref)))
    d = np.sqrt(np.maximum(r**2 - rb_flank**2, 0.0)) - rb_flank * (phi + np.arccos(np.minimum(rb_flank / r, 1.0)))
    return np.abs(d)


@dataclasses.dataclass(frozen=True)
class WindowModel:
    """Data of the travelling-window model (see module docstring); tables on a uniform s grid.

    Attributes
    ----------
    system : TorsionalSystem
        The chain and drive; its ``mesh`` (the loaded k(phi), e(phi) at the design load) is
        used for the linear natural frequencies and the initial state only.
    line : PairLine
    modes : tuple[ToothModes, ToothModes]
    s_grid : ndarray
        LoA positions of the tables [m], uniform, ``s_A - extension`` ... ``s_E + extension``.
    k_res, gap : ndarray
        Residual stiffness [N/m] and gap [m] on ``s_grid``.
    a1, a2 : ndarray (n_s, n_m)
        Participations of the pinion and wheel tooth modes [1/sqrt(kg)].
    fillet1, fillet2 : ndarray
        Tension-side fillet stress per newton of pair load [Pa/N] (quasi-static).
    tooth_damping_ratio : float
    window : int
        Tooth pairs with modal states.
    s_low : float
        LoA position where a tooth pair enters the window [m].
    damping_onset : float
        Largest pair deflection over which the mesh dashpot grows to ``c_m`` [m].
    """

    system: TorsionalSystem
    line: PairLine
    modes: tuple
    s_grid: np.ndarray
    k_res: np.ndarray
    gap: np.ndarray
    a1: np.ndarray
    a2: np.ndarray
    fillet1: np.ndarray
    fillet2: np.ndarray
    tooth_damping_ratio: float
    window: int
    s_low: float
    damping_onset: float

    @property
    def n_modes(self) -> int:
        return self.a1.shape[1]

    @property
    def highest_frequency(self) -> float:
        """Upper bound of the tooth frequencies in contact [Hz]: ``omega_k^2 + a_k^2 k_res``."""
        f = 0.0
        for om, a in ((self.modes[0].omega, self.a1), (self.modes[1].omega, self.a2)):
            if om.size:
                f = max(f, float(np.sqrt((om**2 + a**2 * self.k_res[:, None]).max())) / (2 * np.pi))
        return f


def build_window_model(
    system: TorsionalSystem,
    line: PairLine,
    meshes,
    densities,
    *,
    n_modes: int = 0,
    tooth_damping_ratio: float = DEFAULT_TOOTH_DAMPING_RATIO,
    corner_contact: bool = True,
    extension: float = 0.3,
    n_s: int = 801,
) -> WindowModel:
    """The travelling-window model of ``line``'s pair in ``system``'s chain.

    Parameters
    ----------
    system : TorsionalSystem
        Chain, drive and mesh damping (``mesh_damping`` sets ``c_m``; its mesh table the mean
        stiffness the damping ratio refers to).
    line : PairLine
        FE pair data (:func:`~.loaded_te.pair_line`), the same meshes as ``meshes``.
    meshes, densities : pair of ToothMesh, pair of float [kg/m^3]
    n_modes : int
        Tooth modes per gear; 0 (default): massless, statically condensed FE teeth (the
        tooth springs of DANST-type models); 1-6 add tooth inertia (docs/gear-steady-state.md).
    tooth_damping_ratio : float
        Modal damping ratio of the tooth modes.
    corner_contact : bool
        Premature tip-corner contact beyond the path ends (False: contact only on the path).
    extension : float
        Corner-contact range beyond each path end [base pitches].
    n_s : int
        Table points.
    """
    if n_modes < 0 or n_modes > 6:
        raise InputError("n_modes", n_modes, "0 ... 6")
    if not 0.0 <= tooth_damping_ratio < 1.0:
        raise InputError("tooth_damping_ratio", tooth_damping_ratio, "0 <= zeta < 1")
    e1, nu1, e2, nu2 = line.elastic
    pb, sa, se = line.base_pitch, line.s_start, line.s_end
    ext = extension * pb if corner_contact else 0.0
    s = np.linspace(sa - ext, se + ext, n_s)
    sc = np.clip(s, sa, se)  # corner contact: tooth data of the path end
    r1, r2 = line.radii(sc)
    hw = np.array(
        [
            contact_half_width(line.force, line.g1.face_width, e1, nu1, e2, nu2, x, y)
            for x, y in zip(sc, line.length - sc, strict=True)
        ]
    )
    mods = []
    for mesh, rho, rr, (e, nu), tooth in zip(
        meshes, densities, (r1, r2), ((e1, nu1), (e2, nu2)), (line.tooth1, line.tooth2), strict=True
    ):
        nodes = tooth.radius
        w = np.interp(nodes, rr if rr[0] < rr[-1] else rr[::-1], hw if rr[0] < rr[-1] else hw[::-1])
        mods.append(tooth_modes(mesh, nodes, e, nu, rho, w, n_modes))
    q_pair = line.compliance(sc)
    a = []
    for m, rr in zip(mods, (r1, r2), strict=True):
        a.append(CubicSpline(m.radius, m.participation, axis=0)(rr) if n_modes else np.zeros((n_s, 0)))
    q_modal = (a[0] ** 2 / mods[0].omega ** 2).sum(axis=1) + (a[1] ** 2 / mods[1].omega ** 2).sum(axis=1)
    q_res = q_pair - q_modal
    if np.any(q_res <= 0.05 * q_pair):
        raise InputError(
            "n_modes",
            n_modes,
            f"fewer modes: the retained modes hold {np.max(q_modal / q_pair):.0%} of the pair "
            "compliance, leaving no contact compliance in series",
        )
    gap = line.gap(sc)
    if corner_contact:
        before, after = s < sa, s > se
        gap[before] += corner_gap(line.g1.base_radius, line.g2.base_radius, line.g2.tip_radius_, line.length, s[before])
        gap[after] += corner_gap(
            line.g2.base_radius, line.g1.base_radius, line.g1.tip_radius_, line.length, line.length - s[after]
        )
    fil = line.fillet_stress(sc, np.ones(n_s))
    s_low = sa - ext - pb
    window = int(math.ceil((se + ext - s_low) / pb)) + 1
    return WindowModel(
        system,
        line,
        tuple(mods),
        s,
        1.0 / q_res,
        gap,
        a[0],
        a[1],
        fil[:, 0],
        fil[:, 1],
        float(tooth_damping_ratio),
        window,
        s_low,
        0.1 * line.force / system.mesh.mean_stiffness,
    )
