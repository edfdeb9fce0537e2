"""Annular gas labyrinth seal (``[bearing.NAME.labyrinth]``): one-control-volume bulk-flow model.

The model of Iwatsubo (1980) in the form of Childs & Scharrer (1986), "An Iwatsubo-based solution
for labyrinth seals: comparison to experimental results", J. Eng. Gas Turbines Power 108,
325-331; the gas is ideal and (by default) isothermal at the inlet temperature T (rho = P / (R_g T)).

Leakage per unit circumference through tooth k (Neumann's equation):

    m = mu_1k mu_2 Cr sqrt((P_{k-1}^2 - P_k^2) / (R_g T)),
    mu_1 = pi / (pi + 2 - 5 s + 2 s^2),  s = (P_{k-1} / P_k)^((gamma-1)/gamma) - 1   (Chaplygin)
    mu_2 = sqrt(NT / (NT (1 - j) + j)),  j = 1 - (1 + 16.6 Cr / pitch)^-2         (kinetic carry-over)

with mu_2 = 1 for the first tooth (``leakage = "neumann"``, the default). mu_1 -> pi / (pi + 2) = 0.611
for a vanishing pressure drop, the free-streamline contraction of a slot (Kirchhoff). The same m
passes every tooth: the cavity pressures follow by marching and m by a root search on the outlet
pressure. A tooth chokes at the critical pressure ratio (2 / (gamma + 1))^(gamma / (gamma - 1)):
below it the flow stays Neumann's at that ratio (proportional to the upstream pressure), the last
cavity's pressure then exceeds the outlet's and the seal is reported choked.

``leakage = "vermes"``: the leakage model of Scharrer's LABY3 (Scharrer 1988, "Theory versus
experiment for the rotordynamic coefficients of labyrinth gas seals: part I - a two control volume
model", J. Vib. Acoust. Stress Reliab. Des. 110, 270-280; the code as ported in ROSS). Each tooth is
an isentropic nozzle fed by the cavity upstream, plus the part nu of the previous jet's kinetic
energy that crosses the cavity (Vermes 1961, "A fluid mechanics approach to the labyrinth seal
leakage problem", J. Eng. Power 83, 161-169):

    m = C_d Cr rho_{k-1} r^(1/gamma) sqrt(nu w_{k-1}^2 + 2 gamma/(gamma-1) R_g T (1 - r^((gamma-1)/gamma))),
    r = P_k / P_{k-1},  w_k = m / (C_d Cr rho_{k-1} r^(1/gamma))  (jet velocity, w_0 = 0),
    nu = 8.52 / ((pitch - width) / Cr + 7.23)                       (Vermes' carry-over factor)
    C_d = 0.67675 - 0.08519 x + 0.0878 x^2 - 0.01819 x^3 + 0.00111 x^4,  x = width / Cr  (LABY3)

A tooth chokes at r_c = (2 / (gamma + 1) (1 + nu w_{k-1}^2 (gamma-1) / (2 gamma R_g T)))^(gamma/(gamma-1)),
where this flow is largest and the jet sonic. Martin's formula with Vermes' factor (Martin 1908;
Vermes 1961) is LABY3's first estimate only; here Brent's method needs none. The first-order leakage
of this option is Scharrer's (as LABY3): delta m_k = m (P_{k-1} delta P_{k-1} - P_k delta P_k) /
(P_{k-1}^2 - P_k^2), the linearised Neumann form at the actual leakage m; a choked last tooth
passes delta m = m delta P_{k-1} / P_{k-1} (its flow is proportional to its upstream pressure).

LABY3's further modelling choices, each an option (defaults: this model's; docs/stability.md
measures each one against LABY3):

- ``cavity_temperature = "isentropic"``: cavity k at its jet's temperature T_k = T_{k-1}
  r^((gamma-1)/gamma), density P_k / (R_g T_k), tooth k + 1 fed at R_g T_k (default
  ``"isothermal"``: the jet's kinetic energy is dissipated in the cavity, total enthalpy is conserved
  and an ideal gas keeps the inlet temperature). The perturbations stay isothermal at T_k.
- ``cavity_length = "pitch"``: L = pitch (default pitch - tooth width) in the cavity area, the
  hydraulic diameter, the wetted lengths and the force; Vermes' nu keeps pitch - width.
- ``sutherland_constant = S``: mu = mu_in (T / T_in)^1.5 (T_in + S) / (T + S) at each cavity's
  temperature (LABY3 fits S through two states); without it mu is constant.
- ``shear_linearisation = "laby3"``: the perturbed shear tau_1 / tau = P_1 / P (the Reynolds number
  held at its centred value); default the linearisation of the shear law itself, (1 + m0) P_1 / P.
- ``vermes_linearisation = "exact"`` (not LABY3's; the default is Scharrer's form above): the
  derivatives of the Vermes law itself, each tooth's flow depending on its two pressures and on the
  previous jet, w = m R_g T / (C_d Cr P_{k-1}^(1-1/gamma) P_k^(1/gamma)), so on every upstream
  pressure (a dense d m_k / d P_j); C_d and nu keep their centred values.
- ``choking = "laby3"``: r_c^((gamma-1)/gamma) = 2 / (gamma + 1) + nu w_{k-1}^2 (gamma-1) /
  (2 gamma R_g T), and a choked last tooth linearised as an unchoked one (Scharrer's form above with
  P_k the throat pressure), 1 / (1 - r_c^2) times the sensitivity of a choked flow.

Circumferential momentum of cavity i (length L = pitch - tooth width by default, depth B + Cr, area
A = (B + Cr) L), zeroth order: m (V_i - V_{i-1}) = L (a_r tau_r - a_s tau_s), V_0 = preswirl R w,
wall shear tau = 1/2 n rho |u| u (rho |u| D_h / mu)^m0 (Blasius, n = 0.079, m0 = -0.25) with
u = R w - V on the rotor and u = V on the stator, D_h = 2 (Cr + B) L / (Cr + B + L) and the wetted
lengths a = (2 B + L) / L on the toothed side, 1 on the smooth side.

First order: the rotor on a circular orbit of radius r at whirl frequency W gives the clearance
h = -r cos(theta - W t); every perturbation is Re[X e^{i(theta - W t)}], and the perturbed cavity
continuity and circumferential momentum (Childs & Scharrer's eqs. with the cavity-area and
hydraulic-diameter perturbations) form a complex linear system of 2 NC unknowns (NC = NT - 1
cavities). The force on the rotor F_x + i F_y = -pi R L sum conj(P_i) e^{iWt} equals
-[(K + W c) + i (W C - k)] (x + i y); forward (W) and backward (-W) orbits separate the four
coefficients. The model gives coefficients that depend on the whirl frequency
(``frequency_dependent``); ``whirl = None`` is synchronous whirl (W = spin speed).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Literal

import numpy as np

from rotaflex.core.config import param
from rotaflex.core.errors import InputError
from rotaflex.rotor.fe.elements.bearing import ComputedBearing

R_UNIVERSAL = 8.314462618  # J/(mol K)
#: named gases: molar mass [kg/mol], ratio of specific heats, dynamic viscosity [Pa s] near 300 K
GASES = {
    "air": (0.028965, 1.40, 1.85e-5),
    "nitrogen": (0.028013, 1.40, 1.78e-5),
    "methane": (0.016043, 1.31, 1.11e-5),
    "carbon_dioxide": (0.044010, 1.29, 1.50e-5),
    "hydrogen": (0.002016, 1.41, 0.89e-5),
}
BLASIUS = (0.079, -0.25)  #: n, m of the wall friction factor f = n Re^m (rotor and stator)
CARRY_OVER = 16.6  #: j = 1 - (1 + 16.6 Cr / pitch)^-2 (Childs & Scharrer 1986)
VERMES = (8.52, 7.23)  #: nu = 8.52 / ((pitch - width) / Cr + 7.23) (Vermes 1961)
#: LABY3's discharge coefficient C_d(x), x = tooth width / Cr: polynomial coefficients, x^0 .. x^4
LABY3_DISCHARGE = (0.67675, -0.08519, 0.0878, -0.01819, 0.00111)


@dataclass(frozen=True)
class Labyrinth:
    """``[bearing.NAME.labyrinth]``: a see-through labyrinth as on its drawing, the gas and the pressures."""

    teeth: int = param(ge=2, doc="number of teeth NT (NT - 1 cavities)")
    pitch: float = param(unit="m", gt=0, doc="axial tooth pitch")
    tooth_height: float = param(unit="m", gt=0, doc="tooth height B (cavity depth)")
    clearance: float = param(unit="m", gt=0, doc="radial clearance Cr at the tooth tips")
    radius: float = param(unit="m", gt=0, doc="shaft radius R at the seal")
    inlet_pressure: float = param(unit="Pa", gt=0)
    outlet_pressure: float = param(unit="Pa", gt=0)
    inlet_temperature: float = param(unit="K", gt=0)
    tooth_width: float = param(0.0, unit="m", ge=0, doc="tooth tip width (cavity length = pitch - width by default)")
    teeth_on: Literal["stator", "rotor"] = param("stator", doc="side carrying the teeth")
    preswirl: float = param(0.0, doc="inlet swirl V_0 / (R w) (0: swirl brake)")
    leakage: Literal["neumann", "vermes"] = param(
        "neumann", doc="tooth flow: Neumann with Childs-Scharrer carry-over, or LABY3's (Vermes' carry-over)"
    )
    cavity_temperature: Literal["isothermal", "isentropic"] = param(
        "isothermal", doc="cavity gas at the inlet temperature, or at its jet's isentropic temperature (LABY3)"
    )
    cavity_length: Literal["pitch_minus_width", "pitch"] = param(
        "pitch_minus_width", doc="axial cavity length L: pitch - tooth width, or the pitch (LABY3)"
    )
    shear_linearisation: Literal["exact", "laby3"] = param(
        "exact", doc="perturbed wall shear: tau ~ rho^(1+m) (density in Re), or tau ~ rho (LABY3)"
    )
    choking: Literal["sonic_jet", "laby3"] = param(
        "sonic_jet", doc="vermes: tooth chokes where its jet is sonic, or at LABY3's ratio, linearised unchoked"
    )
    vermes_linearisation: Literal["scharrer", "exact"] = param(
        "scharrer", doc="vermes: perturbed leakage in Scharrer's (LABY3's) form, or the tooth law's own with its jets"
    )
    sutherland_constant: float | None = param(
        None, unit="K", doc="viscosity ~ T^1.5 / (T + S) from the inlet's (None: constant viscosity)"
    )
    gas: Literal["air", "nitrogen", "methane", "carbon_dioxide", "hydrogen"] | None = param(
        "air", doc="a named gas (or give molar_mass, gamma, viscosity)"
    )
    molar_mass: float | None = param(None, unit="kg/mol", gt=0, doc="overrides the named gas")
    gamma: float | None = param(None, gt=1, doc="ratio of specific heats (overrides the named gas)")
    viscosity: float | None = param(None, unit="Pa s", gt=0, doc="dynamic viscosity (overrides the named gas)")

    def validate(self, where: str) -> None:
        """InputError naming ``where.<key>`` for inconsistent values."""
        if self.outlet_pressure >= self.inlet_pressure:
            raise InputError(
                f"{where}.outlet_pressure", self.outlet_pressure, f"< inlet_pressure = {self.inlet_pressure:g} Pa"
            )
        if self.tooth_width >= self.pitch:
            raise InputError(f"{where}.tooth_width", self.tooth_width, f"< pitch = {self.pitch:g} m")
        if self.choking == "laby3" and self.leakage != "vermes":
            raise InputError(
                f"{where}.choking", self.choking, '"sonic_jet" (LABY3\'s choking needs leakage = "vermes")'
            )
        s = self.sutherland_constant
        if s is not None and -self.inlet_temperature <= s < 0:  # T + S would change sign between 0 and T_in
            raise InputError(
                f"{where}.sutherland_constant", s, f">= 0 K or < -inlet_temperature = {-self.inlet_temperature:g} K"
            )
        if self.gas is None and None in (self.molar_mass, self.gamma, self.viscosity):
            key = next(k for k in ("molar_mass", "gamma", "viscosity") if getattr(self, k) is None)
            raise InputError(f"{where}.{key}", "<missing>", "a value, or a named gas")

    @property
    def properties(self) -> tuple[float, float, float]:
        """R_g [J/(kg K)], gamma, viscosity [Pa s]."""
        mm, g, mu = GASES[self.gas] if self.gas else (None, None, None)
        mm, g, mu = self.molar_mass or mm, self.gamma or g, self.viscosity or mu
        return R_UNIVERSAL / mm, g, mu


def tooth_flow(p_up, p_down, clearance, rt, gamma, mu2=1.0):
    """Neumann's leakage per unit circumference [kg/(s m)] of one tooth (module docstring); below the
    critical pressure ratio the tooth is choked and passes the flow of that ratio."""
    p_down = np.maximum(p_down, (2 / (gamma + 1)) ** (gamma / (gamma - 1)) * p_up)
    s = (p_up / p_down) ** ((gamma - 1) / gamma) - 1
    mu1 = np.pi / (np.pi + 2 - 5 * s + 2 * s**2)
    return mu1 * mu2 * clearance * np.sqrt((p_up**2 - p_down**2) / rt)


def vermes_flow(p_up, p_down, w_up, clearance, rt, gamma, cd, nu):
    """LABY3's tooth flow per unit circumference [kg/(s m)] (module docstring) from the cavity at
    ``p_up`` [Pa] fed by a jet of velocity ``w_up`` [m/s], and that tooth's jet velocity [m/s];
    below the critical ratio the tooth is choked and passes the flow of that ratio."""
    g1 = (gamma - 1) / gamma
    head = nu * w_up**2
    r = np.maximum(p_down / p_up, (2 / (gamma + 1) * (1 + head * g1 / (2 * rt))) ** (1 / g1))
    rho_t = p_up / rt * r ** (1 / gamma)
    w = np.sqrt(head + 2 * rt / g1 * (1 - r**g1))
    return cd * clearance * rho_t * w, w


@dataclass(frozen=True)
class Zeroth:
    """Centred-seal solution at one speed: leakage m [kg/(s m)], cavity pressures, temperatures and swirl."""

    m: float
    p: np.ndarray  #: P_0 .. P_NT [Pa] (inlet, cavities, outlet)
    v: np.ndarray  #: V_0 .. V_NC [m/s] (inlet swirl, cavities)
    choked: bool
    t: np.ndarray  #: T_0 .. T_NT [K] (inlet, cavities, the last jet)


class LabyrinthElement(ComputedBearing):
    """Element of the contract over the bulk-flow model; coefficients at any speed and whirl frequency."""

    frequency_dependent = True

    def __init__(self, spec: Labyrinth, name: str):
        self.spec, self.name = spec, name
        sp = spec
        self.rg, self.gamma, self.mu = sp.properties
        self.rt = self.rg * sp.inlet_temperature
        self.nc = sp.teeth - 1
        self.L = sp.pitch - sp.tooth_width if sp.cavity_length == "pitch_minus_width" else sp.pitch
        self.A = (sp.tooth_height + sp.clearance) * self.L
        depth = sp.clearance + sp.tooth_height
        self.dh = 2 * depth * self.L / (depth + self.L)
        self.dlndh = self.L / (depth * (depth + self.L))  # d ln D_h / d h
        toothed = (2 * sp.tooth_height + self.L) / self.L
        self.a_r, self.a_s = (toothed, 1.0) if sp.teeth_on == "rotor" else (1.0, toothed)
        j = 1 - (1 + CARRY_OVER * sp.clearance / sp.pitch) ** -2
        mu2 = np.sqrt(sp.teeth / (sp.teeth * (1 - j) + j))
        self.mu2 = np.r_[1.0, np.full(sp.teeth - 1, mu2)]
        # a tooth chokes at the critical pressure ratio: its flow stays Neumann's at that ratio below it
        self.r_choke = (2 / (self.gamma + 1)) ** (self.gamma / (self.gamma - 1))
        x = sp.tooth_width / sp.clearance
        self.cd = float(np.polyval(LABY3_DISCHARGE[::-1], x))
        self.nu = VERMES[0] / ((sp.pitch - sp.tooth_width) / sp.clearance + VERMES[1])
        # d ln tau / d ln P at fixed T: 1 + m with the density in the Reynolds number, 1 in LABY3
        self.shear_p = 1 + BLASIUS[1] if sp.shear_linearisation == "exact" else 1.0
        *self.leak, self.temperature = self._leakage()  # (m, P, choked), T_0..T_NT [K]
        self.leak = tuple(self.leak)

    def tooth(self, k: int, pu, pd, w_up: float = 0.0, rt: float | None = None):
        """Flow [kg/(s m)] of tooth ``k`` (0-based) from ``pu`` to ``pd`` [Pa] fed by gas at ``rt`` = R_g T
        [J/kg] (None: the inlet's), and its jet velocity [m/s] (``vermes``; 0 for ``neumann``, whose
        carry-over is the factor mu_2)."""
        sp, rt = self.spec, self.rt if rt is None else rt
        if sp.leakage == "vermes":
            return vermes_flow(pu, pd, w_up, sp.clearance, rt, self.gamma, self.cd, self.nu)
        return tooth_flow(pu, pd, sp.clearance, rt, self.gamma, self.mu2[k]), 0.0

    def critical_ratio(self, w_up: float = 0.0, rt: float | None = None) -> float:
        """Pressure ratio P_k / P_{k-1} at which a tooth fed by a jet of ``w_up`` [m/s] from gas at
        ``rt`` = R_g T [J/kg] (None: the inlet's) chokes."""
        if self.spec.leakage == "neumann":
            return self.r_choke
        g1, rt = (self.gamma - 1) / self.gamma, self.rt if rt is None else rt
        head = self.nu * w_up**2 * g1 / (2 * rt)  # the carried-over jet's share of the stagnation enthalpy
        if self.spec.choking == "laby3":  # LABY3 adds it without the factor 2 / (gamma + 1)
            return (2 / (self.gamma + 1) + head) ** (1 / g1)
        return (2 / (self.gamma + 1) * (1 + head)) ** (1 / g1)

    def viscosity(self, t):
        """Dynamic viscosity [Pa s] at temperature ``t`` [K]: Sutherland's law through the inlet's value,
        mu = mu_in (T / T_in)^1.5 (T_in + S) / (T + S), or constant without ``sutherland_constant``."""
        sp = self.spec
        if sp.sutherland_constant is None:
            return self.mu + 0.0 * np.asarray(t)
        s, t0 = sp.sutherland_constant, sp.inlet_temperature
        return self.mu * (np.asarray(t) / t0) ** 1.5 * (t0 + s) / (np.asarray(t) + s)

    # -- zeroth order -------------------------------------------------------------------
    def _march(self, m: float) -> tuple[np.ndarray, np.ndarray] | None:
        """Pressures P_0..P_NT and temperatures T_0..T_NT passing ``m`` through every tooth; None if a
        tooth cannot pass it. Isentropic cavities take the jet's temperature T_k = T_{k-1} r^((gamma-1)/gamma)."""
        from scipy.optimize import brentq  # here, so that importing the bearing kinds does not load it

        sp, p, t, w = self.spec, [self.spec.inlet_pressure], [self.spec.inlet_temperature], 0.0
        isentropic = sp.cavity_temperature == "isentropic"
        g1 = (self.gamma - 1) / self.gamma
        for k in range(sp.teeth):
            pu, rt = p[-1], self.rg * t[-1]
            rc = self.critical_ratio(w, rt)

            def f(pd, pu=pu, k=k, w=w, rt=rt):
                return self.tooth(k, pu, pd, w, rt)[0] - m

            if f(rc * pu) < 0:
                return None
            p.append(brentq(f, rc * pu, pu * (1 - 1e-15), xtol=1e-12 * pu, rtol=1e-14))
            w = self.tooth(k, pu, p[-1], w, rt)[1]
            t.append(t[-1] * (p[-1] / pu) ** g1 if isentropic else t[-1])
        return np.array(p), np.array(t)

    def _leakage(self) -> tuple[float, np.ndarray, bool, np.ndarray]:
        """Leakage m [kg/(s m)], pressures P_0..P_NT [Pa], choked, temperatures T_0..T_NT [K]."""
        from scipy.optimize import brentq

        sp = self.spec

        def g(m):
            if m <= 0:
                return sp.inlet_pressure - sp.outlet_pressure
            pt = self._march(m)
            return -sp.inlet_pressure if pt is None else pt[0][-1] - sp.outlet_pressure

        # bracket: twice the first tooth alone against the outlet pressure (it has no carry-over; mu_2 < 2)
        hi = 2.0 * self.tooth(0, sp.inlet_pressure, sp.outlet_pressure)[0]
        m = brentq(g, 0.0, hi, xtol=1e-14 * hi, rtol=1e-13)
        pt = self._march(m)
        choked = pt is None or abs(pt[0][-1] - sp.outlet_pressure) > 1e-6 * sp.inlet_pressure
        if pt is None:  # the root sits at the largest flow the teeth pass: step back onto it
            pt = self._march(m * (1 - 1e-9))
        return m, pt[0], choked, pt[1]

    def shear(self, rho, u, n_m=BLASIUS, mu=None):
        """Wall shear [Pa] and d tau / d u at density ``rho``, velocity ``u`` relative to the wall and
        viscosity ``mu`` [Pa s] (None: the inlet's)."""
        n, m0 = n_m
        c = 0.5 * n * (self.dh / (self.mu if mu is None else mu)) ** m0 * rho ** (1 + m0)
        au = np.abs(u)
        return c * au ** (1 + m0) * u, (2 + m0) * c * au ** (1 + m0)

    @functools.lru_cache(maxsize=256)  # noqa: B019 - elements live as long as their model
    def zeroth(self, speed: float) -> Zeroth:
        """Centred solution at spin ``speed`` [rad/s]: leakage, pressures, temperatures, cavity swirl."""
        from scipy.optimize import brentq

        (m, p, choked), t = self.leak, self.temperature
        mus = self.viscosity(t)
        R, v = self.spec.radius, [self.spec.preswirl * self.spec.radius * speed]
        for i in range(1, self.nc + 1):
            rho = p[i] / (self.rg * t[i])

            def res(V, i=i, rho=rho):
                tr = self.shear(rho, R * speed - V, mu=mus[i])[0]
                ts = self.shear(rho, V, mu=mus[i])[0]
                return m * (V - v[-1]) - self.L * (self.a_r * tr - self.a_s * ts)

            lo, hi = min(v[-1], 0.0, R * speed) - 1.0, max(v[-1], 0.0, R * speed) + 1.0
            v.append(brentq(res, lo, hi, xtol=1e-13 * (abs(hi) + abs(lo)), rtol=1e-14))
        return Zeroth(m, p, np.array(v), choked, t)

    # -- first order ----------------------------------------------------------------------
    def _response(self, speed: float, whirl: float) -> complex:
        """G = pi R L sum conj(P_i) for a unit orbit at whirl ``whirl`` [rad/s] (force = -G z)."""
        z, sp = self.zeroth(speed), self.spec
        nc, R, L, A = self.nc, sp.radius, self.L, self.A
        p, v, m, rts = z.p, z.v, z.m, self.rg * z.t
        mus = self.viscosity(z.t)
        h = -1.0 + 0j  # unit orbit: h = -r cos(theta - W t)
        # d m_k / d P_{k-1}, d m_k / d P_k (central differences, relative step 1e-7)
        a, b = np.zeros(sp.teeth), np.zeros(sp.teeth)
        for k in range(sp.teeth if sp.leakage == "neumann" else 0):
            pu, pd = p[k], p[k + 1]
            du, dd = 1e-7 * pu, 1e-7 * pd
            fl = functools.partial(tooth_flow, clearance=sp.clearance, rt=rts[k], gamma=self.gamma, mu2=self.mu2[k])
            if z.choked and k == sp.teeth - 1:  # choked last tooth: the flow follows the upstream pressure only
                rc = self.r_choke
                a[k] = (fl(pu + du, rc * (pu + du)) - fl(pu - du, rc * (pu - du))) / (2 * du)
                continue
            a[k] = (fl(pu + du, pd) - fl(pu - du, pd)) / (2 * du)
            b[k] = (fl(pu, pd + dd) - fl(pu, pd - dd)) / (2 * dd)
        dm = None  # d m_k / d P_j over every station (the exact Vermes form): dense
        if sp.leakage == "vermes" and sp.vermes_linearisation == "exact":
            dm = self._vermes_jacobian(z)[:, 1 : nc + 1]
        elif sp.leakage == "vermes":  # Scharrer's linearisation (module docstring); choked last tooth: m ~ P
            d2 = p[:-1] ** 2 - p[1:] ** 2
            a, b = m * p[:-1] / d2, -m * p[1:] / d2
            if z.choked and sp.choking == "sonic_jet":  # LABY3 linearises its choked tooth as unchoked
                a[-1], b[-1] = m / p[-2], 0.0
        # unknowns: P_1..P_NC (columns 0..nc-1), V_1..V_NC (columns nc..2nc-1)
        M = np.zeros((2 * nc, 2 * nc), complex)
        rhs = np.zeros(2 * nc, complex)
        iw = -1j * whirl
        for i in range(1, nc + 1):
            r, P, V = i - 1, i - 1, nc + i - 1
            rt = rts[i]
            rho = p[i] / rt
            # continuity: d/dt(rho A) + 1/R d/dtheta(rho A V) + m_{i+1} - m_i = 0 (tooth i+1 leaves, tooth i enters)
            M[r, P] += iw * A / rt + 1j * A * v[i] / (rt * R)
            M[r, V] += 1j * rho * A / R
            rhs[r] -= (iw * rho * L + 1j * rho * v[i] * L / R) * h
            M[r, P] += a[i]  # m_{i+1} = a_{i+1} P_i + b_{i+1} P_{i+1} (tooth index i in 0-based a, b)
            if i < nc:
                M[r, P + 1] += b[i]
            M[r, P] -= b[i - 1]  # - m_i = -(a_i P_{i-1} + b_i P_i)
            if i > 1:
                M[r, P - 1] -= a[i - 1]
            # momentum: rho A (dV/dt + V/R dV/dtheta) + m (V_i - V_{i-1}) + m1_i (V0_i - V0_{i-1})
            #           = -A/R dP/dtheta + L (a_r tau_r - a_s tau_s)
            q = nc + r
            tr, dtr = self.shear(rho, R * speed - v[i], mu=mus[i])
            ts, dts = self.shear(rho, v[i], mu=mus[i])
            n_r = n_s = BLASIUS[1]
            dv = v[i] - v[i - 1]
            M[q, V] += rho * A * (iw + 1j * v[i] / R) + m + L * (self.a_r * dtr + self.a_s * dts)
            if i > 1:
                M[q, V - 1] -= m
            M[q, P] += 1j * A / R - L * (self.a_r * tr - self.a_s * ts) * self.shear_p / p[i]
            # m1_i = a_i P_{i-1} + b_i P_i + m / Cr h
            M[q, P] += b[i - 1] * dv
            if i > 1:
                M[q, P - 1] += a[i - 1] * dv
            rhs[q] -= (m / sp.clearance) * dv * h
            if dm is not None:  # m_{i+1} - m_i in continuity, m1_i (V_i - V_{i-1}) in momentum
                M[r, :nc] += dm[i] - dm[i - 1]
                M[q, :nc] += dm[i - 1] * dv
            rhs[q] += L * (self.a_r * tr * n_r - self.a_s * ts * n_s) * self.dlndh * h
        x = np.linalg.solve(M, rhs)
        return np.pi * R * L * np.sum(np.conj(x[:nc]))

    def _vermes_jacobian(self, z: Zeroth) -> np.ndarray:
        """d m_k / d P_j [kg/(s m Pa)] of the Vermes tooth law itself (teeth x stations 0..NT, temperatures
        frozen): tooth k depends on P_k, P_{k+1} and the jet of tooth k - 1, whose velocity
        w = m R_g T / (C_d Cr P^(1-1/gamma) P_down^(1/gamma)) carries every upstream perturbation.
        Central differences, relative step 1e-7; a choked last tooth is differentiated below its
        critical ratio (its flow then follows the upstream state only)."""
        sp, p, g = self.spec, z.p, self.gamma
        n = sp.teeth
        jac, dw, w = np.zeros((n, n + 1)), np.zeros(n + 1), 0.0

        def flow(pu, pd, wu, rt):
            return vermes_flow(pu, pd, wu, sp.clearance, rt, g, self.cd, self.nu)

        for k in range(n):
            pu, pd, rt = p[k], p[k + 1], self.rg * z.t[k]
            pe = 0.5 * pd if (z.choked and k == n - 1) else pd
            du, dd, dj = 1e-7 * pu, 1e-7 * pd, 1e-7 * max(w, 1.0)
            row = dw * (flow(pu, pe, w + dj, rt)[0] - flow(pu, pe, w - dj, rt)[0]) / (2 * dj)
            row[k] += (flow(pu + du, pe, w, rt)[0] - flow(pu - du, pe, w, rt)[0]) / (2 * du)
            row[k + 1] += (flow(pu, pe + dd, w, rt)[0] - flow(pu, pe - dd, w, rt)[0]) / (2 * dd)
            jac[k] = row
            mk, w = flow(pu, pd, w, rt)
            dw = w * row / mk  # d ln w = d ln m - (1 - 1/gamma) d ln P_k - (1/gamma) d ln P_{k+1}
            dw[k] -= w * (1 - 1 / g) / pu
            dw[k + 1] -= w / (g * pd)
        return jac

    def coefficients(self, speed, whirl=None) -> tuple[np.ndarray, np.ndarray]:
        """K, C (n, 2, 2) [N/m, N s/m] at spin ``speed`` and whirl ``whirl`` [rad/s] (None: synchronous)."""
        speed = np.atleast_1d(np.asarray(speed, float))
        whirl = speed if whirl is None else np.broadcast_to(np.asarray(whirl, float), speed.shape)
        K, C = np.zeros((speed.size, 2, 2)), np.zeros((speed.size, 2, 2))
        for j, (s, w) in enumerate(zip(speed, np.abs(whirl), strict=True)):
            w = max(w, 1e-6 * max(s, 1.0))  # W -> 0: the W c and W C terms vanish; a tiny W separates them
            gf, gb = self._response(float(s), w), self._response(float(s), -w)
            kd, kc = 0.5 * (gf.real + gb.real), -0.5 * (gf.imag + gb.imag)
            cd, cc = (gf.imag - gb.imag) / (2 * w), (gf.real - gb.real) / (2 * w)
            K[j] = [[kd, kc], [-kc, kd]]
            C[j] = [[cd, cc], [-cc, cd]]
        return K, C

    def outputs(self, speed) -> dict:
        """Leakage [kg/s], cavity pressures [Pa] and swirl ratios V / (R w) at the spin speeds, and the
        cavity temperatures [K] when they are isentropic."""
        import xarray as xr

        speed = np.atleast_1d(np.asarray(speed, float))
        zs = [self.zeroth(float(s)) for s in speed]
        R = self.spec.radius
        swirl = np.array(
            [z.v[1:] / (R * s) if s > 0 else np.full(self.nc, np.nan) for z, s in zip(zs, speed, strict=True)]
        )
        out = {
            "leakage": xr.DataArray(2 * np.pi * R * zs[0].m, attrs={"units": "kg/s", "choked": int(zs[0].choked)}),
            "cavity_pressure": xr.DataArray(zs[0].p[1:-1], dims=("cavity",), attrs={"units": "Pa"}),
            "cavity_swirl": xr.DataArray(swirl, dims=("seal_speed", "cavity"), attrs={"units": "1"}),
        }
        if self.spec.cavity_temperature == "isentropic":
            out["cavity_temperature"] = xr.DataArray(zs[0].t[1:-1], dims=("cavity",), attrs={"units": "K"})
        return out


def element(spec: Labyrinth, where: str) -> LabyrinthElement:
    """The labyrinth element (inputs checked, naming ``where.<key>``)."""
    spec.validate(where)
    return LabyrinthElement(spec, where)
