"""Involute spur-gear geometry: flank, rack-generated root fillet and contact-ratio quantities.

Conventions
-----------
Gear frame: gear centre at the origin, the modelled tooth's centreline along ``+y``. The
"right" flank is the one at ``x > 0``, the "left" flank its mirror image. Angles are radians
(``GearGeometry.pressure_angle`` too); config keys in degrees say so (``pressure_angle_deg``) and
are converted where the config is read (:mod:`rotaflex.core.units`).

Generating rack (stated assumption)
-----------------------------------
The tooth is cut by a basic rack (ISO 53 type) with pressure angle ``alpha`` equal to the gear's,
straight flanks, a cutter addendum ``h_aP0 = dedendum_coef * m`` (which cuts the root circle
``r_f = r + x m - h_aP0``) and a tip round of radius ``rho_fP = rack_tip_radius_coef * m``
(default 0.38 m, ISO 53 profile A) tangent to the cutter flank and to the cutter tip line.
The rack rolls without slip on the reference (pitch) circle, its reference line shifted outwards
by ``x m``. The straight cutter flank generates the involute; the tip round generates the root
fillet, an offset of the extended trochoid described by the round's centre (the envelope point is
the round point on the ray from the instantaneous centre, the pitch point, through the round's
centre). Below the root-fillet end the root is the root circle.

References
----------
ISO 21771 (involute geometry), ISO 53 (basic rack), Litvin & Fuentes, *Gear Geometry and Applied
Theory* (generation of the fillet by a rack).
"""

from __future__ import annotations

import dataclasses
import math
from typing import Literal

import numpy as np

from rotaflex.core.config import param
from rotaflex.core.errors import InputError
from rotaflex.core.units import deg_to_rad

__all__ = [
    "GearGeometry",
    "ProfileRelief",
    "involute",
    "center_distance_no_backlash",
    "path_of_contact",
    "contact_ratio",
    "contact_angles",
]


#: the standard reference pressure angle, 20 deg [rad]
STANDARD_PRESSURE_ANGLE = deg_to_rad(20.0)


def involute(alpha: np.ndarray | float) -> np.ndarray | float:
    """Involute function ``inv(a) = tan(a) - a`` [rad]."""
    return np.tan(alpha) - alpha


def _inv_inverse(value: float) -> float:
    """Inverse involute function by Newton iteration [rad]."""
    a = (3.0 * value) ** (1.0 / 3.0)  # small-angle start
    for _ in range(50):
        f = math.tan(a) - a - value
        a_new = a - f / math.tan(a) ** 2
        if abs(a_new - a) < 1e-15:
            return a_new
        a = a_new
    return a


@dataclasses.dataclass(frozen=True)
class ProfileRelief:
    """A tip or root relief of the involute flank (material removed along the involute normal).

    The depth is a function of the roll length ``u = sqrt(r^2 - r_b^2)`` (proportional to the
    roll angle): ``c = amount * t**p`` with ``t`` running linearly in ``u`` from 0 at
    ``start_radius`` to 1 at ``end_radius`` (the tip radius for a tip relief, the form radius for
    a root relief), ``p = 1`` (linear) or 2 (parabolic). Because every involute normal is tangent
    to the base circle, removing ``c`` along the normal opens a gap of exactly ``c`` along the
    line of action at that contact position.

    Parameters
    ----------
    amount : float
        Depth at the end of the relief (tip or form radius) [m].
    start_radius : float
        Radius where the relief starts (depth 0) [m].
    shape : {"linear", "parabolic"}
    """

    amount: float = param(unit="m", ge=0.0, doc="relief depth at the tip (or form) radius")
    start_radius: float = param(unit="m", gt=0.0, doc="radius where the relief starts")
    shape: Literal["linear", "parabolic"] = param("linear", doc="depth ~ t or t^2")

    def depth(self, radius: np.ndarray, base_radius: float, end_radius: float) -> np.ndarray:
        """Relief depth [m] at ``radius`` (0 on the unrelieved side of ``start_radius``)."""
        r = np.maximum(np.asarray(radius, dtype=float), base_radius)
        u = np.sqrt(r**2 - base_radius**2)
        u0 = math.sqrt(max(self.start_radius**2 - base_radius**2, 0.0))
        u1 = math.sqrt(max(end_radius**2 - base_radius**2, 0.0))
        t = np.clip((u - u0) / (u1 - u0), 0.0, 1.0)
        return self.amount * (t if self.shape == "linear" else t**2)


@dataclasses.dataclass(frozen=True)
class GearGeometry:
    """A standard or profile-shifted external involute spur gear.

    Parameters
    ----------
    module : float
        Normal module m [m].
    teeth : int
        Number of teeth z (>= 6).
    pressure_angle : float
        Reference pressure angle alpha [rad] (default 20 deg).
    face_width : float
        Face width b [m] (the plane-stress thickness of the FE model).
    addendum_coef : float
        Tooth addendum h_a / m (ignored when ``tip_radius`` is given).
    dedendum_coef : float
        Tooth dedendum h_f / m = generating-rack addendum h_aP0 / m (ignored when ``root_radius``
        is given).
    profile_shift : float
        Profile shift coefficient x (positive: rack pulled outwards).
    rack_tip_radius_coef : float
        Generating-rack tip round radius rho_fP / m.
    tip_radius : float or None
        Explicit tip (addendum) radius r_a [m], overrides ``addendum_coef``.
    root_radius : float or None
        Explicit root radius r_f [m], overrides ``dedendum_coef``.
    tip_relief, root_relief : ProfileRelief or None
        Profile modifications applied to the generated involute points (and hence to the mesh
        flank nodes); ``None`` leaves the true involute (bit-identical to an unmodified gear).

    Examples
    --------
    >>> g = GearGeometry(module=3.175e-3, teeth=28, face_width=6.35e-3,
    ...                  tip_radius=0.047625, root_radius=0.04048)
    >>> round(g.base_radius, 6)
    0.041769
    """

    module: float = param(unit="m", gt=0.0, doc="module")
    teeth: int = param(gt=5, doc="number of teeth")
    face_width: float = param(unit="m", gt=0.0, doc="face width")
    pressure_angle: float = param(STANDARD_PRESSURE_ANGLE, unit="rad", gt=0.0, lt=0.5 * math.pi, doc="pressure angle")
    addendum_coef: float = param(1.0, gt=0.0, le=2.0, doc="addendum / module")
    dedendum_coef: float = param(1.25, gt=0.0, le=2.5, doc="dedendum / module")
    profile_shift: float = param(0.0, ge=-1.0, le=1.5, doc="profile shift coefficient")
    rack_tip_radius_coef: float = param(0.38, ge=0.0, le=0.6, doc="rack tip radius / module")
    tip_radius: float | None = param(None, unit="m", gt=0.0, doc="explicit tip radius")
    root_radius: float | None = param(None, unit="m", gt=0.0, doc="explicit root radius")
    tip_relief: ProfileRelief | None = param(None, doc="tip relief")
    root_relief: ProfileRelief | None = param(None, doc="root relief")

    def __post_init__(self) -> None:
        m, x = self.module, self.profile_shift
        if self.tip_radius is not None and self.tip_radius <= self.pitch_radius:
            raise InputError("tip_radius", self.tip_radius, f"> pitch radius {self.pitch_radius:.6g} m")
        if self.root_radius is not None and not (
            0.5 * self.pitch_radius < self.root_radius < self.pitch_radius + x * m
        ):
            raise InputError(
                "root_radius",
                self.root_radius,
                f"between {0.5 * self.pitch_radius:.6g} and {self.pitch_radius + x * m:.6g} m",
            )
        if self.tip_radius_ <= self.base_radius:
            raise InputError("tip_radius", self.tip_radius_, f"> base radius {self.base_radius:.6g} m")
        rho_max = self._rack_tip_radius_max()
        if self.rack_tip_radius_coef * m > rho_max + 1e-15:
            raise InputError(
                "rack_tip_radius_coef",
                self.rack_tip_radius_coef,
                f"<= {rho_max / m:.4f} (full round of the generating rack tip)",
            )
        if self.rack_tip_radius_coef * m > self.cutter_addendum:
            raise InputError(
                "rack_tip_radius_coef",
                self.rack_tip_radius_coef,
                f"<= dedendum {self.cutter_addendum / m:.4f}",
            )
        # undercut: the lower end of the straight cutter flank must stay above the interference
        # point, i.e. its depth below the rolling line must not exceed r sin^2(alpha)
        a = self.pressure_angle
        depth = self.pitch_radius - self._rack_flank_lowest_y()
        limit = self.pitch_radius * math.sin(a) ** 2
        if depth > limit * (1.0 + 1e-12):
            x_min = (depth - limit) / m + x
            raise InputError(
                "profile_shift",
                x,
                f">= {x_min:.4f} to avoid undercut with {self.teeth} teeth",
            )
        if self.tip_thickness <= 0.0:
            raise InputError(
                "tip_radius",
                self.tip_radius_,
                f"a non-pointed tooth (tip thickness {self.tip_thickness:.3e} m)",
            )
        if self.form_radius >= self.tip_radius_:
            raise InputError("tip_radius", self.tip_radius_, f"> form radius {self.form_radius:.6g} m")
        for name, rel, lo, hi in (
            ("tip_relief", self.tip_relief, self.form_radius, self.tip_radius_),
            ("root_relief", self.root_relief, self.form_radius, self.tip_radius_),
        ):
            if rel is not None and not lo < rel.start_radius < hi:
                raise InputError(
                    f"{name}.start_radius",
                    rel.start_radius,
                    f"between the form radius {lo:.6g} and the tip radius {hi:.6g} m",
                )

    # ------------------------------------------------------------------ radii
    @property
    def pitch_radius(self) -> float:
        """Reference (pitch) radius r = m z / 2 [m]."""
        return 0.5 * self.module * self.teeth

    @property
    def base_radius(self) -> float:
        """Base radius r_b = r cos(alpha) [m]."""
        return self.pitch_radius * math.cos(self.pressure_angle)

    @property
    def tip_radius_(self) -> float:
        """Tip radius actually used [m] (explicit or r + (h_a + x) m)."""
        if self.tip_radius is not None:
            return float(self.tip_radius)
        return self.pitch_radius + (self.addendum_coef + self.profile_shift) * self.module

    @property
    def root_radius_(self) -> float:
        """Root radius actually used [m] (explicit or r + (x - h_f) m)."""
        if self.root_radius is not None:
            return float(self.root_radius)
        return self.pitch_radius + (self.profile_shift - self.dedendum_coef) * self.module

    @property
    def cutter_addendum(self) -> float:
        """Generating-rack addendum h_aP0 = r + x m - r_f [m]."""
        return self.pitch_radius + self.profile_shift * self.module - self.root_radius_

    @property
    def base_pitch(self) -> float:
        """Base pitch p_b = pi m cos(alpha) [m]."""
        return math.pi * self.module * math.cos(self.pressure_angle)

    @property
    def pitch_thickness(self) -> float:
        """Tooth thickness on the reference circle s = m (pi/2 + 2 x tan alpha) [m] (arc)."""
        return self.module * (0.5 * math.pi + 2.0 * self.profile_shift * math.tan(self.pressure_angle))

    @property
    def tip_thickness(self) -> float:
        """Arc tooth thickness on the tip circle [m] (<= 0 means a pointed tooth)."""
        ra = self.tip_radius_
        return 2.0 * ra * float(self.flank_half_angle(np.array([ra]))[0])

    # -------------------------------------------------------------- involute
    def flank_half_angle(self, radius: np.ndarray) -> np.ndarray:
        """Polar half-angle of the involute flank from the tooth centreline [rad].

        Parameters
        ----------
        radius : ndarray
            Radii >= r_b [m].
        """
        r = np.asarray(radius, dtype=float)
        a_r = np.arccos(np.clip(self.base_radius / r, -1.0, 1.0))
        return self.pitch_thickness / (2.0 * self.pitch_radius) + involute(self.pressure_angle) - involute(a_r)

    def involute_points(self, radius: np.ndarray, side: str = "right") -> np.ndarray:
        """Involute flank points at the given radii, shape (n, 2) [m].

        Parameters
        ----------
        radius : ndarray
            Radii in [r_b, r_a] [m].
        side : {"right", "left"}
            Flank at x > 0 ("right") or its mirror image.
        """
        r = np.asarray(radius, dtype=float)
        psi = self.flank_half_angle(r)
        pts = np.column_stack([r * np.sin(psi), r * np.cos(psi)])
        if self.tip_relief is not None or self.root_relief is not None:
            # remove the relief along the outward involute normal (tangent to the base circle)
            a_r = np.arccos(np.clip(self.base_radius / r, -1.0, 1.0))
            c = self.relief_depth(r)
            pts -= c[:, None] * np.column_stack([np.cos(a_r - psi), np.sin(a_r - psi)])
        if side == "left":
            pts[:, 0] *= -1.0
        return pts

    def relief_depth(self, radius: np.ndarray) -> np.ndarray:
        """Total profile-relief depth along the involute normal at ``radius`` [m] (0 if none)."""
        r = np.atleast_1d(np.asarray(radius, dtype=float))
        c = np.zeros_like(r)
        if self.tip_relief is not None:
            c = c + self.tip_relief.depth(r, self.base_radius, self.tip_radius_)
        if self.root_relief is not None:
            c = c + self.root_relief.depth(r, self.base_radius, self.form_radius)
        return c

    # ------------------------------------------------------------ rack/fillet
    def _rack_round_centre(self) -> tuple[float, float]:
        """Centre (x_c, y_c) of the right cutter tooth's tip round, rack frame, phi = 0 [m]."""
        a, rp, rho = self.pressure_angle, self.pitch_radius, self.rack_tip_radius_coef * self.module
        y_c = self.root_radius_ + rho
        x_c = 0.5 * self.pitch_thickness + (rp - y_c) * math.tan(a) + rho / math.cos(a)
        return x_c, y_c

    def _rack_tip_radius_max(self) -> float:
        a, m = self.pressure_angle, self.module
        h = self.pitch_radius - self.root_radius_
        return (0.5 * math.pi * m - 0.5 * self.pitch_thickness - h * math.tan(a)) / (1.0 / math.cos(a) - math.tan(a))

    def _rack_flank_lowest_y(self) -> float:
        """y of the tangency between cutter flank and tip round (rack frame) [m]."""
        rho = self.rack_tip_radius_coef * self.module
        return self.root_radius_ + rho - rho * math.sin(self.pressure_angle)

    def _fillet_phi_range(self) -> tuple[float, float]:
        x_c, y_c = self._rack_round_centre()
        rp, a = self.pitch_radius, self.pressure_angle
        return x_c / rp, (x_c + (rp - y_c) / math.tan(a)) / rp

    def fillet_points(self, phi: np.ndarray) -> np.ndarray:
        """Right-flank root-fillet points for generating-roll angles ``phi``, shape (n, 2) [m].

        ``phi`` runs from ``fillet_phi[0]`` (fillet end on the root circle) to ``fillet_phi[1]``
        (form point, where the fillet joins the involute).
        """
        phi = np.asarray(phi, dtype=float)
        x_c, y_c = self._rack_round_centre()
        rp, rho = self.pitch_radius, self.rack_tip_radius_coef * self.module
        cx = x_c - rp * phi
        cy = np.full_like(phi, y_c)
        dx, dy = cx, cy - rp
        nrm = np.hypot(dx, dy)
        qx, qy = cx + rho * dx / nrm, cy + rho * dy / nrm
        c, s = np.cos(phi), np.sin(phi)
        return np.column_stack([c * qx + s * qy, -s * qx + c * qy])

    @property
    def fillet_phi(self) -> tuple[float, float]:
        """Generating-roll-angle range of the fillet (root end, form point) [rad]."""
        return self._fillet_phi_range()

    @property
    def form_radius(self) -> float:
        """Radius where the fillet meets the involute (start of the active-capable flank) [m]."""
        p = self.fillet_points(np.array([self.fillet_phi[1]]))[0]
        return float(np.hypot(*p))

    @property
    def root_half_angle(self) -> float:
        """Polar angle of the fillet end on the root circle from the tooth centreline [rad]."""
        return self.fillet_phi[0]

    def profile(self, n_fillet: int = 40, n_involute: int = 60, side: str = "right") -> np.ndarray:
        """Tooth profile from the fillet end on the root circle to the tip corner, (n, 2) [m].

        Parameters
        ----------
        n_fillet, n_involute : int
            Number of points on the fillet and on the involute (the shared form point is not
            repeated).
        side : {"right", "left"}
        """
        pa, pb = self.fillet_phi
        fil = self.fillet_points(np.linspace(pa, pb, n_fillet))
        r = np.linspace(self.form_radius, self.tip_radius_, n_involute)[1:]
        inv = self.involute_points(r)
        pts = np.vstack([fil, inv])
        if side == "left":
            pts[:, 0] *= -1.0
        return pts


# ---------------------------------------------------------------------------- pair quantities
def center_distance_no_backlash(g1: GearGeometry, g2: GearGeometry) -> float:
    """Centre distance without backlash for two external gears [m].

    Solves ``inv(alpha_w) = inv(alpha) + 2 (x1 + x2) tan(alpha) / (z1 + z2)``.
    """
    _check_pair(g1, g2)
    a = g1.pressure_angle
    inv_w = float(involute(a)) + 2.0 * (g1.profile_shift + g2.profile_shift) * math.tan(a) / (g1.teeth + g2.teeth)
    a_w = _inv_inverse(inv_w)
    return (g1.base_radius + g2.base_radius) / math.cos(a_w)


def _check_pair(g1: GearGeometry, g2: GearGeometry) -> None:
    if not math.isclose(g1.module, g2.module, rel_tol=1e-9):
        raise InputError("gear2.module", g2.module, f"equal to gear1.module = {g1.module}")
    if not math.isclose(g1.pressure_angle, g2.pressure_angle, rel_tol=1e-9):
        raise InputError(
            "gear2.pressure_angle", g2.pressure_angle, f"equal to gear1.pressure_angle = {g1.pressure_angle} rad"
        )


def _working_pressure_angle(g1: GearGeometry, g2: GearGeometry, center_distance: float) -> float:
    rb = g1.base_radius + g2.base_radius
    if not (rb < center_distance < g1.tip_radius_ + g2.tip_radius_):
        raise InputError(
            "center_distance",
            center_distance,
            f"between {rb:.6g} and {g1.tip_radius_ + g2.tip_radius_:.6g} m",
        )
    return math.acos(rb / center_distance)


def path_of_contact(g1: GearGeometry, g2: GearGeometry, center_distance: float | None = None) -> float:
    """Length of the path of contact g_alpha along the line of action [m].

    ``g = sqrt(ra1^2 - rb1^2) + sqrt(ra2^2 - rb2^2) - a sin(alpha_w)``.
    """
    a = center_distance_no_backlash(g1, g2) if center_distance is None else float(center_distance)
    aw = _working_pressure_angle(g1, g2, a)
    g = (
        math.sqrt(g1.tip_radius_**2 - g1.base_radius**2)
        + math.sqrt(g2.tip_radius_**2 - g2.base_radius**2)
        - a * math.sin(aw)
    )
    # each tip must not reach beyond the interference point of the other gear
    for gi, go in ((g1, g2), (g2, g1)):
        reach = math.sqrt(gi.tip_radius_**2 - gi.base_radius**2)
        if reach > a * math.sin(aw):
            raise InputError("tip_radius", gi.tip_radius_, "a tip radius free of tip-to-base interference")
        # active contact must stay on the involute of the mating gear (above its form circle)
        lowest = math.hypot(go.base_radius, a * math.sin(aw) - reach)
        if lowest < go.form_radius * (1 - 1e-9):
            raise InputError(
                "tip_radius",
                gi.tip_radius_,
                f"a radius whose contact stays above the mate's form radius {go.form_radius:.6g} m",
            )
    return g


def contact_ratio(g1: GearGeometry, g2: GearGeometry, center_distance: float | None = None) -> float:
    """Transverse contact ratio eps_alpha = g_alpha / p_b; raises InputError when < 1."""
    eps = path_of_contact(g1, g2, center_distance) / g1.base_pitch
    if eps < 1.0:
        raise InputError("tip_radius", g1.tip_radius_, f"radii giving contact ratio >= 1 (got {eps:.4f})")
    return eps


def contact_angles(g1: GearGeometry, g2: GearGeometry, center_distance: float | None = None) -> tuple[float, float]:
    """Rotation angles of gear 1 over one tooth pair's contact and over each two-pair zone [rad].

    Returns
    -------
    theta_s : float
        g_alpha / r_b1, rotation while one tooth pair is in contact.
    theta_2 : float
        (g_alpha - p_b) / r_b1, rotation of each two-pair zone (start and end of contact).
    """
    g = path_of_contact(g1, g2, center_distance)
    contact_ratio(g1, g2, center_distance)
    return g / g1.base_radius, (g - g1.base_pitch) / g1.base_radius
