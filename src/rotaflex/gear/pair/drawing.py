"""Gears and gear pairs as specified on a drawing (ISO 21771 quantities), with checks.

A :class:`GearSpec` is one gear as a drawing gives it (``[pinion]`` or ``[wheel]`` TOML table);
a :class:`PairSpec` is the pair with its centre distance or backlash. Both are frozen data built
with :func:`rotaflex.core.config.from_mapping`; derived quantities are properties, and
:meth:`PairSpec.check` raises :class:`~rotaflex.core.errors.InputError` naming the dotted field
(``pinion.profile_shift``, ``wheel.tip_relief.amount`` ...) for a pair that cannot run.

Formulas (ISO 21771, external spur and helical gears, SI inside)
----------------------------------------------------------------
A helical gear (``helix_angle_deg`` beta > 0) is given in its normal section: ``module`` is the
normal module m_n, ``pressure_angle_deg`` the normal pressure angle alpha_n, ``profile_shift``
the normal shift x_n, the height coefficients are relative to m_n. Its transverse section is
the spur gear of module ``m_t = m_n / cos(beta)``, pressure angle ``tan(alpha_t) = tan(alpha_n) /
cos(beta)``, coefficients ``h_a* cos(beta)``, ``h_f* cos(beta)``, ``x_n cos(beta)`` (the same
radii and the same transverse thickness ``s_t = m_t (pi/2 + 2 x_n tan(alpha_n))``), which
:meth:`GearSpec.geometry` returns, so every formula below holds in the transverse plane. The
generating rack's tip round is a circle in that section whose tangent point on the straight
flank lies at the normal section's height (form point and undercut limit exact; the true
section is an ellipse, which shapes the fillet only: ``GearSpec._transverse_rack_tip_coef``). Helical
quantities (:meth:`PairSpec.helical_summary`): base helix angle ``tan(beta_b) = tan(beta)
cos(alpha_t)``, lead ``p_z = 2 pi r / tan(beta)``, axial pitch ``p_x = pi m_n / sin(beta)``,
overlap ratio ``eps_beta = b sin(beta) / (pi m_n)`` (b the common face width), total contact
ratio ``eps_gamma = eps_alpha + eps_beta``, working helix angle ``tan(beta_w) = tan(beta_b) /
cos(alpha_wt)``; normal backlash ``j_bn = j_wt cos(alpha_wt) cos(beta_b)``. beta = 0 takes the
spur code path unchanged.

* reference radius ``r = m z / 2``, base radius ``r_b = r cos(alpha)``, base pitch
  ``p_b = pi m cos(alpha)``;
* tip / root radius ``r_a = r + (h_a* + x) m``, ``r_f = r + (x - h_f*) m`` unless given;
* tooth thickness at radius ``r_y``: ``s_y = 2 r_y (s / (2 r) + inv(alpha) - inv(alpha_y))``,
  ``s = m (pi/2 + 2 x tan(alpha))``, ``cos(alpha_y) = r_b / r_y``;
* no-backlash operating pressure angle
  ``inv(alpha_w) = inv(alpha) + 2 tan(alpha) (x1 + x2) / (z1 + z2)``, centre distance
  ``a_w = (r_b1 + r_b2) / cos(alpha_w)``;
* at a larger centre distance ``a'``: ``cos(alpha') = (r_b1 + r_b2) / a'``, circumferential
  backlash on the operating pitch circles ``j_wt = 2 pi r_w1 / z1 - s_w1 - s_w2``, normal
  backlash ``j_bn = j_wt cos(alpha')``;
* transverse contact ratio
  ``eps = (sqrt(r_a1^2 - r_b1^2) + sqrt(r_a2^2 - r_b2^2) - a' sin(alpha')) / p_b``.
"""

from __future__ import annotations

import dataclasses
import math
import re
from typing import Literal

import numpy as np

from rotaflex.core.config import from_mapping, param
from rotaflex.core.errors import InputError
from rotaflex.core.units import deg_to_rad, rad_to_deg
from rotaflex.gear.pair.geometry import GearGeometry, ProfileRelief, _inv_inverse, involute
from rotaflex.gear.pair.lead import LeadSpec

__all__ = [
    "ReliefSpec",
    "MaterialSpec",
    "BlankSpec",
    "GearSpec",
    "PairSpec",
    "MATERIALS",
    "MIN_TIP_THICKNESS_COEF",
    "pair_from_mapping",
    "pair_meshes",
]

#: smallest allowed tip thickness / module (pointed-tip check; common design practice 0.2-0.4)
MIN_TIP_THICKNESS_COEF = 0.2
#: smallest Young's modulus accepted [Pa], in every gear verb: 0.1 GPa admits the stiffest
#: polymers (moulded polymers; steels 210 GPa); below it the teeth deflect by a sizeable fraction
#: of the module under any useful torque, outside the small-strain co-rotational model
MIN_YOUNGS_MODULUS = 1e8

#: unit of every :meth:`PairSpec.summary` entry (and of ``gear static``'s ``geometry_*`` rows)
SUMMARY_UNITS = {
    "ratio": "1",
    "center_distance": "m",
    "center_distance_no_backlash": "m",
    "normal_backlash": "m",
    "operating_pressure_angle_deg": "deg",
    "contact_ratio": "1",
    "path_of_contact": "m",
    "pinion_tip_thickness": "m",
    "wheel_tip_thickness": "m",
    "pinion_inertia": "kg m^2",
    "wheel_inertia": "kg m^2",
    **{
        f"{g}_{r}": "m"
        for g in ("pinion", "wheel")
        for r in ("tip_radius", "root_radius", "form_radius", "start_of_active_profile_radius")
    },
    # helical pairs only (PairSpec.helical_summary)
    "helix_angle_deg": "deg",
    "pinion_hand": "text",
    "transverse_module": "m",
    "transverse_pressure_angle_deg": "deg",
    "base_helix_angle_deg": "deg",
    "working_helix_angle_deg": "deg",
    "pinion_lead": "m",
    "wheel_lead": "m",
    "axial_pitch": "m",
    "transverse_base_pitch": "m",
    "common_face_width": "m",
    "overlap_ratio": "1",
    "total_contact_ratio": "1",
}

#: coefficients given relative to the normal module (transverse ones = these x cos(beta))
_NORMAL_COEFS = ("addendum_coef", "dedendum_coef", "profile_shift", "rack_tip_radius_coef")

#: largest helix angle accepted [deg] (exclusive): beyond it the transverse section of a
#: narrow-face pair is no longer a useful model and ISO 6336's helical terms are out of range
MAX_HELIX_ANGLE_DEG = 45.0

#: the keys of :class:`ReliefSpec` that say where a relief starts (exactly one is given)
RELIEF_STARTS = ("start_diameter", "start_roll_deg", "start_fraction")

#: largest root relief / tooth thickness at the form circle
MAX_ROOT_RELIEF_FRACTION = 0.1

#: named materials: (Young's modulus [Pa], Poisson ratio, density [kg/m^3])
MATERIALS = {
    "steel": (210e9, 0.3, 7800.0),
    "cast_iron": (110e9, 0.28, 7200.0),
    "bronze": (110e9, 0.34, 8800.0),
    "aluminium": (70e9, 0.33, 2700.0),
}


@dataclasses.dataclass(frozen=True)
class ReliefSpec:
    """Tip or root relief on a drawing: amount and where it starts, given by one of a diameter,
    a roll angle or a fraction of the active profile (converted to the start radius of
    :class:`~rotaflex.gear.pair.geometry.ProfileRelief` where the pair is read)."""

    amount: float = param(unit="m", gt=0.0, doc="depth along the involute normal at its end")
    start_diameter: float | None = param(
        None, unit="m", gt=0.0, doc="diameter where it starts (one of start_diameter, start_roll_deg, start_fraction)"
    )
    start_roll_deg: float | None = param(
        None, unit="deg", gt=0.0, doc="roll angle xi = tan(alpha_y) where it starts: r = r_b sqrt(1 + xi^2)"
    )
    start_fraction: float | None = param(
        None,
        ge=0.0,
        lt=1.0,
        doc="where it starts along the active profile's roll length: 0 at the start of active "
        "profile (set by the mate's tip), 1 at the tip",
    )
    shape: Literal["linear", "parabolic"] = param("linear", doc="depth ~ t (linear) or t^2")


@dataclasses.dataclass(frozen=True)
class MaterialSpec:
    """Material by name (``MATERIALS``) or by values; values override the name's."""

    name: Literal["steel", "cast_iron", "bronze", "aluminium"] = param("steel")
    youngs_modulus: float | None = param(
        None, unit="Pa", gt=MIN_YOUNGS_MODULUS, doc="> 1e8 Pa: engineering gear materials"
    )
    poisson_ratio: float | None = param(None, gt=0.0, lt=0.5)
    density: float | None = param(None, unit="kg/m^3", gt=0.0)

    @property
    def values(self) -> tuple[float, float, float]:
        """(E [Pa], nu, rho [kg/m^3])."""
        e, nu, rho = MATERIALS[self.name]
        return (
            e if self.youngs_modulus is None else self.youngs_modulus,
            nu if self.poisson_ratio is None else self.poisson_ratio,
            rho if self.density is None else self.density,
        )


@dataclasses.dataclass(frozen=True)
class BlankSpec:
    """Gear blank: polar inertia given, or computed from a solid or rimmed (web) blank.

    The inertia of the teeth is that of the annulus between root and tip circles with half its
    density (a tooth fills about half of the pitch); ``solid``: full disk to the root circle
    minus the bore; ``rimmed``: rim ring of ``rim_thickness`` under the root circle, web of
    ``web_thickness`` down to the hub of ``hub_diameter``, hub over the face width.
    """

    kind: Literal["solid", "rimmed"] = param("solid")
    inertia: float | None = param(None, unit="kg m^2", gt=0.0, doc="given polar inertia")
    bore_diameter: float = param(0.0, unit="m", ge=0.0)
    rim_thickness: float | None = param(None, unit="m", gt=0.0, doc="rimmed: rim depth")
    web_thickness: float | None = param(None, unit="m", gt=0.0, doc="rimmed: web axial width")
    hub_diameter: float | None = param(None, unit="m", gt=0.0, doc="rimmed: hub outer diameter")


def _annulus(rho: float, width: float, r_in: float, r_out: float) -> float:
    return 0.5 * math.pi * rho * width * (r_out**4 - r_in**4)


#: the tool tip radius / module of ISO 53 profile A, used unless it does not fit the rack
DEFAULT_RACK_TIP_RADIUS_COEF = 0.38


@dataclasses.dataclass(frozen=True)
class GearSpec:
    """One external spur or helical gear as on a drawing (helical: normal-section values)."""

    teeth: int = param(gt=5, doc="number of teeth z")
    module: float = param(unit="m", gt=0.0, le=0.1, doc="(normal) module m_n in metres (3 mm: 3e-3)")
    face_width: float = param(unit="m", gt=0.0, le=2.0, doc="face width b in metres")
    pressure_angle_deg: float = param(20.0, unit="deg", gt=5.0, lt=45.0, doc="(normal) pressure angle alpha_n")
    addendum_coef: float = param(1.0, gt=0.0, le=2.0, doc="h_a / m_n")
    dedendum_coef: float = param(1.25, gt=0.0, le=2.5, doc="h_f / m_n (= rack addendum)")
    profile_shift: float = param(0.0, ge=-1.0, le=1.5, doc="(normal) profile shift coefficient x_n")
    helix_angle_deg: float = param(
        0.0, unit="deg", ge=0.0, lt=MAX_HELIX_ANGLE_DEG, doc="reference helix angle beta (0: spur)"
    )
    hand: Literal["left", "right"] | None = param(None, doc="hand of the helix (required when beta > 0)")
    rack_tip_radius_coef: float | None = param(
        None, ge=0.0, le=0.6, doc="tool tip radius / m_n (default 0.38, or the full round where that does not fit)"
    )
    tip_radius: float | None = param(None, unit="m", gt=0.0, doc="explicit r_a (else ISO)")
    root_radius: float | None = param(None, unit="m", gt=0.0, doc="explicit r_f (else ISO)")
    material: MaterialSpec = param(MaterialSpec())
    blank: BlankSpec = param(BlankSpec())
    tip_relief: ReliefSpec | None = param(None)
    root_relief: ReliefSpec | None = param(None)
    lead: LeadSpec | None = param(None, doc="lead modifications (crowning, end relief, slope deviation)")
    support: Literal["root_clamp", "rim"] = param(
        "rim", doc="tooth tied to the rigid disk at the root circle, or through a rim sector"
    )
    rim_depth_coef: float = param(2.0, gt=0.0, le=6.0, doc="rim depth below r_f / m ('rim')")

    # ------------------------------------------------------------------ geometry
    @property
    def helix_angle(self) -> float:
        """Reference helix angle beta [rad]."""
        return deg_to_rad(self.helix_angle_deg)

    @property
    def transverse_pressure_angle(self) -> float:
        """alpha_t = atan(tan(alpha_n) / cos(beta)) [rad] (alpha_n for a spur gear)."""
        a_n = deg_to_rad(self.pressure_angle_deg)
        if self.helix_angle_deg == 0.0:
            return a_n
        return math.atan(math.tan(a_n) / math.cos(self.helix_angle))

    def _transverse_rack_tip_coef(self, c: float, coef: float) -> float:
        """rho_fP / m_t of the circle standing for the rack's tip round in the transverse section:
        its tangent point on the straight flank at the height of the normal section's,
        rho_t (1 - sin(alpha_t)) = rho_fP (1 - sin(alpha_n)), so the form point, the undercut
        limit and the root circle are exact (the true section is an ellipse of semi-axes rho_fP,
        rho_fP / cos(beta); only the fillet's shape is approximated)."""
        a_n = deg_to_rad(self.pressure_angle_deg)
        rho_t = coef * (1.0 - math.sin(a_n)) / (1.0 - math.sin(self.transverse_pressure_angle))
        return rho_t * c

    def _plain(self, where: str) -> GearGeometry:
        """The transverse section as a spur :class:`GearGeometry` (module docstring). Without a
        ``rack_tip_radius_coef`` the tool round is 0.38 m_n, or the full round of the rack's tip
        where that does not fit (pressure angles above ~22 deg), as a hob for such a gear is made."""
        if self.helix_angle_deg > 0.0 and self.hand is None:
            raise InputError(f"{where}.hand", None, "'left' or 'right' for a helical gear (helix_angle_deg > 0)")
        if self.helix_angle_deg == 0.0 and self.hand is not None:
            raise InputError(f"{where}.hand", self.hand, "omitted for a spur gear (helix_angle_deg = 0)")
        c = math.cos(self.helix_angle) if self.helix_angle_deg > 0.0 else 1.0
        coef = DEFAULT_RACK_TIP_RADIUS_COEF if self.rack_tip_radius_coef is None else self.rack_tip_radius_coef
        try:
            try:
                return self._geometry(coef, c)
            except InputError as exc:
                if self.rack_tip_radius_coef is not None or exc.field != "rack_tip_radius_coef":
                    raise
            full = self._geometry(0.0, c)
            t = full._rack_tip_radius_max() / full.module  # the largest transverse coefficient
            normal = t if c == 1.0 else t / self._transverse_rack_tip_coef(c, 1.0)
            return self._geometry(min(coef, normal * (1 - 1e-12)), c)
        except InputError as exc:
            if c == 1.0 or exc.field not in _NORMAL_COEFS:
                raise InputError(f"{where}.{exc.field}", exc.value, exc.allowed) from None
            # the transverse coefficients are the user's normal ones times cos(beta): say the
            # bound in the user's (normal) terms
            allowed = re.sub(r"^([<>]=) (-?[0-9.]+)", lambda m: f"{m[1]} {float(m[2]) / c:.4f}", exc.allowed)
            raise InputError(f"{where}.{exc.field}", getattr(self, exc.field), allowed) from None

    def _geometry(self, coef: float, c: float) -> GearGeometry:
        """The transverse section with the normal tool tip coefficient ``coef`` (``c = cos(beta)``)."""
        if c == 1.0:
            return GearGeometry(
                module=self.module,
                teeth=self.teeth,
                face_width=self.face_width,
                pressure_angle=deg_to_rad(self.pressure_angle_deg),
                addendum_coef=self.addendum_coef,
                dedendum_coef=self.dedendum_coef,
                profile_shift=self.profile_shift,
                rack_tip_radius_coef=coef,
                tip_radius=self.tip_radius,
                root_radius=self.root_radius,
            )
        return GearGeometry(
            module=self.module / c,
            teeth=self.teeth,
            face_width=self.face_width,
            pressure_angle=self.transverse_pressure_angle,
            addendum_coef=self.addendum_coef * c,
            dedendum_coef=self.dedendum_coef * c,
            profile_shift=self.profile_shift * c,
            rack_tip_radius_coef=self._transverse_rack_tip_coef(c, coef),
            tip_radius=self.tip_radius,
            root_radius=self.root_radius,
        )

    def _relief(self, rel: ReliefSpec | None, g: GearGeometry, where: str, sap: float | None):
        if rel is None:
            return None
        given = [k for k in RELIEF_STARTS if getattr(rel, k) is not None]
        if len(given) != 1:
            key = given[1] if given else "start_diameter"
            raise InputError(f"{where}.{key}", getattr(rel, key), "exactly one of " + ", ".join(RELIEF_STARTS))
        key = given[0]
        rb = g.base_radius
        if key == "start_diameter":
            r0 = 0.5 * rel.start_diameter
        elif key == "start_roll_deg":  # roll angle xi_y = tan(alpha_y): r_y = r_b sqrt(1 + xi^2)
            r0 = rb * math.sqrt(1.0 + deg_to_rad(rel.start_roll_deg) ** 2)
        else:  # linear in the roll length u = sqrt(r^2 - r_b^2) (= r_b xi), as the relief's depth
            if sap is None:
                raise InputError(
                    f"{where}.start_fraction",
                    rel.start_fraction,
                    "start_diameter or start_roll_deg for a gear read without its mate (the start of "
                    "active profile needs the pair)",
                )
            u_sap, u_a = math.sqrt(max(sap**2 - rb**2, 0.0)), math.sqrt(g.tip_radius_**2 - rb**2)
            r0 = math.hypot(rb, u_sap + rel.start_fraction * (u_a - u_sap))
        if not g.form_radius < r0 < g.tip_radius_:
            raise InputError(
                f"{where}.{key}",
                getattr(rel, key),
                f"a start radius between the form radius {g.form_radius:.6g} m "
                f"and the tip radius {g.tip_radius_:.6g} m (got {r0:.6g} m)",
            )
        return ProfileRelief(amount=rel.amount, start_radius=r0, shape=rel.shape)

    def geometry(self, where: str = "gear", sap: float | None = None) -> GearGeometry:
        """The :class:`GearGeometry` with its reliefs (InputError fields prefixed by ``where``);
        ``sap``: the start-of-active-profile radius in the pair [m] (needed by a relief given by
        ``start_fraction``)."""
        g = self._plain(where)
        tip = self._relief(self.tip_relief, g, f"{where}.tip_relief", sap)
        root = self._relief(self.root_relief, g, f"{where}.root_relief", sap)
        if tip is None and root is None:
            return g
        g = dataclasses.replace(g, tip_relief=tip, root_relief=root)
        if tip is not None:
            s_a = relieved_tip_thickness(g)
            lim = MIN_TIP_THICKNESS_COEF * g.module
            if s_a < lim:
                raise InputError(
                    f"{where}.tip_relief.amount",
                    tip.amount,
                    f"a relief leaving a tip thickness >= {lim:.4g} m "
                    f"({MIN_TIP_THICKNESS_COEF} x module); it leaves {s_a:.4g} m",
                )
        if root is not None:
            s_f = thickness_at(g, g.form_radius)
            if root.amount > MAX_ROOT_RELIEF_FRACTION * s_f:
                raise InputError(
                    f"{where}.root_relief.amount",
                    root.amount,
                    f"<= {MAX_ROOT_RELIEF_FRACTION * s_f:.4g} m "
                    f"({MAX_ROOT_RELIEF_FRACTION} x the tooth thickness at the "
                    "form circle)",
                )
        return g

    @property
    def elastic(self) -> tuple[float, float]:
        """(E [Pa], nu)."""
        e, nu, _ = self.material.values
        return e, nu

    def _annuli(self, where: str) -> list[tuple[float, float, float, float]]:
        """The gear body as coaxial annuli (density [kg/m^3], axial width, inner and outer
        radius [m]); teeth: the root-tip annulus at half density (BlankSpec)."""
        b = self.blank
        g = self._plain(where)
        rho = self.material.values[2]
        rf, ra, w = g.root_radius_, g.tip_radius_, self.face_width
        r_bore = 0.5 * b.bore_diameter
        teeth = (0.5 * rho, w, rf, ra)
        if r_bore >= rf:
            raise InputError(f"{where}.blank.bore_diameter", b.bore_diameter, f"< root diameter {2 * rf:.6g} m")
        if b.kind == "solid":
            return [(rho, w, r_bore, rf), teeth]
        for key in ("rim_thickness", "web_thickness", "hub_diameter"):
            if getattr(b, key) is None:
                raise InputError(f"{where}.blank.{key}", None, "a value for kind = 'rimmed'")
        r_rim, r_hub = rf - b.rim_thickness, 0.5 * b.hub_diameter
        if not r_bore < r_hub < r_rim:
            raise InputError(
                f"{where}.blank.hub_diameter",
                b.hub_diameter,
                f"between the bore {2 * r_bore:.6g} and the rim's inner diameter {2 * r_rim:.6g} m",
            )
        if b.web_thickness > w:
            raise InputError(f"{where}.blank.web_thickness", b.web_thickness, f"<= face width {w:.6g} m")
        return [(rho, w, r_rim, rf), (rho, b.web_thickness, r_hub, r_rim), (rho, w, r_bore, r_hub), teeth]

    def inertia(self, where: str = "gear") -> float:
        """Polar inertia of the gear body (blank + teeth) [kg m^2]."""
        if self.blank.inertia is not None:
            return self.blank.inertia
        return sum(_annulus(*a) for a in self._annuli(where))

    def mass(self, where: str = "gear") -> float | None:
        """Mass of the gear body (blank + teeth) [kg]; None when the blank is given by its
        inertia alone."""
        if self.blank.inertia is not None:
            return None
        return sum(math.pi * rho * w * (r_out**2 - r_in**2) for rho, w, r_in, r_out in self._annuli(where))

    def blank_factor(self) -> float:
        """ISO 6336-1 gear-blank factor C_R: 1 for solid blanks; rimmed (web) blanks
        ``1 + ln(b_s / b) / (5 exp(s_R / (5 m)))`` with web width b_s and rim thickness s_R,
        b_s/b clipped to [0.2, 1.2] and s_R/m to >= 1 (the standard's range)."""
        b = self.blank
        if b.kind == "solid" or b.web_thickness is None or b.rim_thickness is None:
            return 1.0
        bs = min(max(b.web_thickness / self.face_width, 0.2), 1.2)
        sr = max(b.rim_thickness / self.module, 1.0)
        return 1.0 + math.log(bs) / (5.0 * math.exp(sr / 5.0))

    def mesh_options(self) -> dict:
        """Keyword options of :func:`rotaflex.gear.pair.tooth_mesh.build_tooth_mesh` for the support."""
        if self.support == "root_clamp":
            return {"support": "root_circle"}
        return {"support": "bottom_and_sides", "rim_depth_coef": self.rim_depth_coef}


def thickness_at(g: GearGeometry, radius: float) -> float:
    """Arc tooth thickness of the true involute at ``radius`` [m] (ISO 21771 s_y)."""
    return 2.0 * radius * float(g.flank_half_angle(np.array([radius]))[0])


def relieved_tip_thickness(g: GearGeometry) -> float:
    """Chordal tooth thickness across the relieved tip corners [m]."""
    p = g.involute_points(np.array([g.tip_radius_]))[0]
    return 2.0 * float(p[0])


@dataclasses.dataclass(frozen=True)
class PairSpec:
    """A pinion-wheel pair: the two gears, centre distance or backlash, and the driver."""

    pinion: GearSpec = param(doc="gear 1")
    wheel: GearSpec = param(doc="gear 2")
    center_distance: float | None = param(None, unit="m", gt=0.0, doc="working centre distance (default: no backlash)")
    backlash: float | None = param(None, unit="m", ge=0.0, doc="normal backlash j_bn (alternative to center_distance)")
    driver: Literal["pinion", "wheel"] = param("pinion", doc="gear that drives")

    # ---------------------------------------------------------------- derived
    @property
    def gears(self) -> tuple[GearGeometry, GearGeometry]:
        """(pinion, wheel) geometries with their reliefs."""
        sap = self.start_of_active_profile()
        return self.pinion.geometry("pinion", sap[0]), self.wheel.geometry("wheel", sap[1])

    @property
    def ratio(self) -> float:
        """Gear ratio z_wheel / z_pinion."""
        return self.wheel.teeth / self.pinion.teeth

    @property
    def operating_pressure_angle_no_backlash(self) -> float:
        """alpha_w from inv(alpha_w) = inv(alpha) + 2 tan(alpha) (x1 + x2)/(z1 + z2) [rad]."""
        # transverse section: alpha_t and x_t = x_n cos(beta), so tan(alpha_t) x_t = tan(alpha_n) x_n
        g1, g2 = self.pinion._plain("pinion"), self.wheel._plain("wheel")
        a = g1.pressure_angle
        inv_w = float(involute(a)) + 2.0 * (g1.profile_shift + g2.profile_shift) * math.tan(a) / (
            self.pinion.teeth + self.wheel.teeth
        )
        return _inv_inverse(inv_w)

    @property
    def center_distance_no_backlash(self) -> float:
        """a_w = (r_b1 + r_b2) / cos(alpha_w) [m]."""
        g1, g2 = self.pinion._plain("pinion"), self.wheel._plain("wheel")
        return (g1.base_radius + g2.base_radius) / math.cos(self.operating_pressure_angle_no_backlash)

    def normal_backlash_at(self, a: float) -> float:
        """Normal backlash j_bn at centre distance ``a`` [m] (ISO 21771, unrelieved teeth)."""
        g1, g2 = self.pinion._plain("pinion"), self.wheel._plain("wheel")
        aw = math.acos((g1.base_radius + g2.base_radius) / a)
        rw1, rw2 = g1.base_radius / math.cos(aw), g2.base_radius / math.cos(aw)
        j_wt = 2.0 * math.pi * rw1 / g1.teeth - thickness_at(g1, rw1) - thickness_at(g2, rw2)
        if self.helical:
            return j_wt * math.cos(aw) * math.cos(self.base_helix_angle)
        return j_wt * math.cos(aw)

    @property
    def working_center_distance(self) -> float:
        """Centre distance used [m]: given, from the backlash, or the no-backlash one."""
        if self.center_distance is not None and self.backlash is not None:
            raise InputError("backlash", self.backlash, "omitted when center_distance is given")
        a0 = self.center_distance_no_backlash
        if self.center_distance is not None:
            if self.center_distance < a0 * (1.0 - 1e-12):  # before any angle is taken of it
                raise InputError(
                    "center_distance",
                    self.center_distance,
                    f">= {a0:.6g} m (the no-backlash centre distance; smaller gives negative backlash)",
                )
            return self.center_distance
        if not self.backlash:
            return a0
        from scipy.optimize import brentq

        return float(brentq(lambda a: self.normal_backlash_at(a) - self.backlash, a0, a0 * 1.2, xtol=1e-15))

    @property
    def operating_pressure_angle(self) -> float:
        """alpha' at the working centre distance [rad]."""
        g1, g2 = self.pinion._plain("pinion"), self.wheel._plain("wheel")
        return math.acos((g1.base_radius + g2.base_radius) / self.working_center_distance)

    @property
    def line_of_action_length(self) -> float:
        """Distance T1T2 between the base-circle tangency points, a' sin(alpha') [m]."""
        return self.working_center_distance * math.sin(self.operating_pressure_angle)

    @property
    def path_of_contact(self) -> float:
        """g_alpha along the line of action [m]."""
        g1, g2 = self.pinion._plain("pinion"), self.wheel._plain("wheel")
        return (
            math.sqrt(g1.tip_radius_**2 - g1.base_radius**2)
            + math.sqrt(g2.tip_radius_**2 - g2.base_radius**2)
            - self.line_of_action_length
        )

    @property
    def contact_ratio(self) -> float:
        """Transverse contact ratio eps_alpha = g_alpha / p_b."""
        return self.path_of_contact / self.pinion._plain("pinion").base_pitch

    def start_of_active_profile(self) -> tuple[float, float]:
        """(pinion, wheel) radius [m] where the mate's tip circle meets the line of action: the
        lowest flank point in contact, r_SAP = sqrt(r_b^2 + (a' sin(alpha') - sqrt(r_a,mate^2
        - r_b,mate^2))^2)."""
        g1, g2 = self.pinion._plain("pinion"), self.wheel._plain("wheel")  # reliefs keep r_a, r_b
        length = self.working_center_distance * math.sin(self.operating_pressure_angle)
        out = []
        for g, mate in ((g1, g2), (g2, g1)):
            s = length - math.sqrt(mate.tip_radius_**2 - mate.base_radius**2)
            out.append(math.hypot(g.base_radius, s))
        return out[0], out[1]

    # ---------------------------------------------------------------- helical
    @property
    def helical(self) -> bool:
        """True for a helical pair (beta > 0)."""
        return self.pinion.helix_angle_deg > 0.0

    @property
    def base_helix_angle(self) -> float:
        """beta_b: tan(beta_b) = tan(beta) cos(alpha_t) [rad] (0 for spur)."""
        p = self.pinion
        return math.atan(math.tan(p.helix_angle) * math.cos(p.transverse_pressure_angle))

    @property
    def face_width(self) -> float:
        """Common face width b = min(b1, b2) [m] (ISO 6336: the smaller one)."""
        return min(self.pinion.face_width, self.wheel.face_width)

    @property
    def overlap_ratio(self) -> float:
        """eps_beta = b sin(beta) / (pi m_n) (0 for spur)."""
        return self.face_width * math.sin(self.pinion.helix_angle) / (math.pi * self.pinion.module)

    @property
    def total_contact_ratio(self) -> float:
        """eps_gamma = eps_alpha + eps_beta."""
        return self.contact_ratio + self.overlap_ratio

    @property
    def working_helix_angle(self) -> float:
        """beta_w: tan(beta_w) = tan(beta_b) / cos(alpha_wt) [rad]."""
        return math.atan(math.tan(self.base_helix_angle) / math.cos(self.operating_pressure_angle))

    @property
    def sliced(self) -> bool:
        """True when the face width is modelled in slices: a helical pair or lead modifications."""
        return self.helical or any(g.lead is not None and g.lead.active for g in (self.pinion, self.wheel))

    def helical_summary(self) -> dict:
        """ISO 21771 helical quantities (SI, angles in degrees where named so); empty for spur."""
        if not self.helical:
            return {}
        p = self.pinion
        g1, g2 = self.pinion._plain("pinion"), self.wheel._plain("wheel")
        tb = math.tan(p.helix_angle)
        return {
            "helix_angle_deg": p.helix_angle_deg,
            "pinion_hand": p.hand,
            "transverse_module": g1.module,
            "transverse_pressure_angle_deg": rad_to_deg(p.transverse_pressure_angle),
            "base_helix_angle_deg": rad_to_deg(self.base_helix_angle),
            "working_helix_angle_deg": rad_to_deg(self.working_helix_angle),
            "pinion_lead": 2.0 * math.pi * g1.pitch_radius / tb,
            "wheel_lead": 2.0 * math.pi * g2.pitch_radius / tb,
            "axial_pitch": math.pi * p.module / math.sin(p.helix_angle),
            "transverse_base_pitch": g1.base_pitch,
            "common_face_width": self.face_width,
            "overlap_ratio": self.overlap_ratio,
            "total_contact_ratio": self.total_contact_ratio,
        }

    def spur_only(self, verb: str, where: str = "") -> PairSpec:
        """Refuse a helical or lead-modified pair in a verb whose tooth model is one transverse
        section (``where``: the prefix of the pair's tables in the user's file); return self."""
        pre = f"{where}." if where else ""
        if self.helical:
            raise InputError(
                f"{pre}pinion.helix_angle_deg",
                self.pinion.helix_angle_deg,
                f"0 in {verb} (spur pairs only; helical pairs run in gear static, lumped gear steady and system)",
            )
        for name in ("pinion", "wheel"):
            lead = getattr(self, name).lead
            if lead is not None and lead.active:
                raise InputError(
                    f"{pre}{name}.lead",
                    "a table",
                    f"omitted in {verb} (lead modifications run in gear static and gear steady)",
                )
        return self

    def summary(self) -> dict:
        """Pair geometry numbers (SI; angles in degrees where named so); units in
        :data:`SUMMARY_UNITS`."""
        g1, g2 = self.gears
        sap = self.start_of_active_profile()
        out = {
            "ratio": self.ratio,
            "center_distance": self.working_center_distance,
            "center_distance_no_backlash": self.center_distance_no_backlash,
            "normal_backlash": self.normal_backlash_at(self.working_center_distance),
            "operating_pressure_angle_deg": rad_to_deg(self.operating_pressure_angle),
            "contact_ratio": self.contact_ratio,
            "path_of_contact": self.path_of_contact,
            "pinion_tip_thickness": g1.tip_thickness,
            "wheel_tip_thickness": g2.tip_thickness,
            "pinion_inertia": self.pinion.inertia("pinion"),
            "wheel_inertia": self.wheel.inertia("wheel"),
        }
        for name, g, r_sap in (("pinion", g1, sap[0]), ("wheel", g2, sap[1])):
            out[f"{name}_tip_radius"] = g.tip_radius_
            out[f"{name}_root_radius"] = g.root_radius_
            out[f"{name}_form_radius"] = g.form_radius
            out[f"{name}_start_of_active_profile_radius"] = r_sap
        out.update(self.helical_summary())
        return out

    # ------------------------------------------------------------------ checks
    def check(self) -> PairSpec:
        """Raise InputError (one line, dotted field) if the pair cannot run; return self."""
        p, w = self.pinion, self.wheel
        if not math.isclose(p.module, w.module, rel_tol=1e-9):
            raise InputError("wheel.module", w.module, f"equal to pinion.module = {p.module}")
        if not math.isclose(p.pressure_angle_deg, w.pressure_angle_deg, rel_tol=1e-9):
            raise InputError(
                "wheel.pressure_angle_deg",
                w.pressure_angle_deg,
                f"equal to pinion.pressure_angle_deg = {p.pressure_angle_deg}",
            )
        if p.helix_angle_deg != w.helix_angle_deg:
            raise InputError(
                "wheel.helix_angle_deg",
                w.helix_angle_deg,
                f"equal to pinion.helix_angle_deg = {p.helix_angle_deg} (parallel axes)",
            )
        if p.hand is not None and p.hand == w.hand:
            raise InputError("wheel.hand", w.hand, f"the opposite of pinion.hand = '{p.hand}' (external pair)")
        for g, name in ((p, "pinion"), (w, "wheel")):  # hand given exactly for helical gears
            if (g.helix_angle_deg > 0.0) != (g.hand is not None):
                g._plain(name)
        for g, name in ((p, "pinion"), (w, "wheel")):
            if g.lead is not None:
                g.lead.check(g.face_width, f"{name}.lead")
        if self.sliced and w.face_width != p.face_width:
            raise InputError(
                "wheel.face_width",
                w.face_width,
                f"equal to pinion.face_width = {p.face_width} m for a helical or lead-modified pair "
                "(the sliced face model has one common face)",
            )
        g1, g2 = self.gears  # undercut, relief limits (GearGeometry / geometry())
        for g, name in ((g1, "pinion"), (g2, "wheel")):
            lim = MIN_TIP_THICKNESS_COEF * g.module
            if g.tip_thickness < lim:
                key = "profile_shift" if getattr(self, name).tip_radius is None else "tip_radius"
                raise InputError(
                    f"{name}.{key}",
                    getattr(getattr(self, name), key),
                    f"a tooth whose tip thickness is >= {lim:.4g} m "
                    f"({MIN_TIP_THICKNESS_COEF} x module); this profile shift leaves "
                    f"{g.tip_thickness:.4g} m",
                )
        a0 = self.center_distance_no_backlash
        a = self.working_center_distance
        if a < a0 * (1.0 - 1e-12):
            raise InputError(
                "center_distance",
                a,
                f">= {a0:.6g} m (the no-backlash centre distance; smaller gives negative backlash)",
            )
        length = self.line_of_action_length
        for gi, go, name, mate in ((g1, g2, "pinion", "wheel"), (g2, g1, "wheel", "pinion")):
            reach = math.sqrt(gi.tip_radius_**2 - gi.base_radius**2)
            if reach > length:
                raise InputError(
                    f"{name}.tip_radius",
                    gi.tip_radius_,
                    f"a tip radius whose contact ends before the {mate}'s base-circle "
                    f"tangency point (tip interference: reach {reach:.6g} m > "
                    f"{length:.6g} m)",
                )
            lowest = math.hypot(go.base_radius, length - reach)
            if lowest < go.form_radius * (1.0 - 1e-9):
                raise InputError(
                    f"{name}.tip_radius",
                    gi.tip_radius_,
                    f"a tip whose contact stays above the {mate}'s form radius "
                    f"{go.form_radius:.6g} m (reaches {lowest:.6g} m: fillet "
                    "interference)",
                )
        eps = self.contact_ratio
        if eps < 1.0:
            if self.center_distance is None and self.backlash:  # the centre distance came from it
                raise InputError("backlash", self.backlash, f"a backlash leaving contact ratio >= 1 (got {eps:.4f})")
            raise InputError("center_distance", a, f"a pair with contact ratio >= 1 (got {eps:.4f})")
        return self


def pair_meshes(pair: PairSpec, mesh_kw: dict, *, relief: bool = True):
    """Tooth meshes (pinion, wheel), each on its own geometry, reliefs and tooth support.

    The one way to build per-gear meshes of an unequal pair (static and dynamic analyses).

    Parameters
    ----------
    pair : PairSpec
    mesh_kw : dict
        Element counts of :func:`rotaflex.gear.pair.tooth_mesh.build_tooth_mesh` (n_flank, n_through,
        n_fillet, n_rim, e.g. ``mesh.DEFAULT``).
    relief : bool
        False: the same gears without their profile reliefs.
    """
    from rotaflex.gear.pair.tooth_mesh import build_tooth_mesh

    out = []
    for g, spec in zip(pair.gears, (pair.pinion, pair.wheel), strict=True):
        if not relief:
            g = dataclasses.replace(g, tip_relief=None, root_relief=None)
        out.append(build_tooth_mesh(g, **mesh_kw, **spec.mesh_options()))
    return tuple(out)


def pair_from_mapping(data: dict, where: str = "") -> PairSpec:
    """Build and check a :class:`PairSpec` from its TOML tables (``pinion``, ``wheel``, ...)."""
    pair = from_mapping(PairSpec, data, where)
    try:
        return pair.check()
    except InputError as exc:  # the pair's keys sit in the table ``where`` (gear_mesh[0] of a system)
        raise exc.relocated(where) from None
