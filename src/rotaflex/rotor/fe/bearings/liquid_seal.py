"""Liquid annular seal (``[bearing.NAME.liquid_seal]``): Childs' short-seal model with added mass.

Childs (1983), "Dynamic analysis of turbulent annular seals based on Hirs' lubrication
equation", J. Lubr. Technol. 105, 429-436; Childs (1993), Turbomachinery Rotordynamics, ch. 3
(the short-seal solution in the Black-Jenssen form). A plain annulus of radius R, length L and
radial clearance Cr; circumferential velocity fully developed at R w / 2 (inlet swirl ratio 0.5,
the default; ``inlet_swirl`` below), circumferential pressure gradients negligible against axial
ones, Hirs' turbulent wall shear on both walls

    tau_z = rho n0 (2 H / nu)^m0 (W^2 + (R w / 2)^2)^((1 + m0)/2) W,   n0 = 0.066, m0 = -0.25,

an entrance loss P(0) = P_in - (1 + xi) rho W(0)^2 / 2 and P(L) = P_out. The centred flow has the
axial velocity V of dP = (1 + xi + 2 sigma) rho V^2 / 2, sigma = lambda L / Cr with
lambda = n0 Ra^m0 (1 + 1/(4 b^2))^((1+m0)/2), Ra = 2 Cr V / nu, b = V / (R w). The coefficients

    K = mu3 (mu0 - mu2 T^2 w^2 / 4),  k = mu3 mu1 T w / 2,  C = mu3 mu1 T,  c = mu3 mu2 T^2 w,
    M = mu3 mu2 T^2,  (m = 0)
    mu0 = 2 sigma^2 E (1 - m0) / (1 + xi + 2 sigma)
    mu1 = 2 sigma^2 [E / sigma + B / 2 (1/6 + E)] / (1 + xi + 2 sigma)
    mu2 = sigma (1/6 + E) / (1 + xi + 2 sigma)
    mu3 = pi R dP / lambda,  T = L / V,  E = (1 + xi) / (2 (1 + xi + B sigma)),
    B = 1 + 4 b^2 (1 + m0) / (1 + 4 b^2).

:meth:`LiquidSealElement.impedance` integrates the first-order bulk-flow equations along z in
closed form (a second formulation): on a circular orbit at whirl W, with s = i (W - w/2),
continuity gives Cr dw/dz = s h and the axial momentum
-Cr dp/dz = ((m0 - 1) tau0 / Cr + rho V s) h + dtau/dW w - rho Cr s (w - a w(0)),
p(0) = -(1 + xi) rho V w(0), p(L) = 0. With a = 1 (Childs' closed form) the local acceleration
of the inlet-velocity perturbation w(0) is left out and the Taylor coefficients of the force in
s are exactly mu0, mu1, mu2 (sympy and numerical tests); a = 0 keeps it (``inlet_acceleration``:
C -17 %, M -56 % for the neck ring of the tests; not Childs' published result, kept to show the
sensitivity, docs/stability.md).

``inlet_swirl`` u0 (Childs 1983: the circumferential velocity u enters at u0 R w and develops
towards R w / 2). Zeroth order, rho H V du/dz = -(tau_s + tau_r) with Hirs' circumferential shears
linearised about u = R w / 2 (their sum is rho lambda V B_t (u - R w / 2), B_t = 1 + (1 + m0) /
(1 + 4 b^2)):

    u(z) = R w [1/2 + (u0 - 1/2) e^(-beta z)],   beta = lambda B_t / Cr.

The axial shear is even in u - R w / 2, so lambda, the leakage and tau0, dtau/dW keep their values
(to first order in u0 - 1/2). First order: every s above becomes the local s(z) = i (W - u(z) / R)
= s - i w (u0 - 1/2) e^(-beta z) (continuity and the inertia terms); the integrals of s(z) and of
S(z)^2, S(z) = int_0^z s, are elementary and :meth:`impedance` stays closed form. The force is
quadratic in W: K, k, C, c, M, m are its coefficients (:meth:`expanded`); u0 = 1/2 gives Childs'
closed form, C and M do not depend on u0, k falls with u0 (swirl brakes).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from rotaflex.core.config import param
from rotaflex.core.errors import InputError
from rotaflex.rotor.fe.elements.bearing import ComputedBearing

HIRS = (0.066, -0.25)  #: n0, m0 of Hirs' friction law for smooth surfaces (Yamada's data; Childs 1983)


@dataclass(frozen=True)
class LiquidSeal:
    """``[bearing.NAME.liquid_seal]``: a plain (smooth) annular seal of a pump: neck ring or damper seal."""

    radius: float = param(unit="m", gt=0, doc="seal radius R")
    length: float = param(unit="m", gt=0, doc="seal length L")
    clearance: float = param(unit="m", gt=0, doc="radial clearance Cr")
    inlet_pressure: float = param(unit="Pa", doc="upstream pressure")
    outlet_pressure: float = param(unit="Pa", doc="downstream pressure (< inlet)")
    density: float = param(unit="kg/m^3", gt=0, doc="liquid density")
    viscosity: float = param(unit="Pa s", gt=0, doc="dynamic viscosity")
    entrance_loss: float = param(0.1, ge=0, doc="entrance loss coefficient xi")
    inlet_swirl: float | None = param(
        None, ge=-1, le=1.5, doc="inlet swirl ratio u0 = u(0) / (R w) (none: developed at 1/2 along the seal)"
    )

    def validate(self, where: str) -> None:
        if self.outlet_pressure >= self.inlet_pressure:
            raise InputError(
                f"{where}.outlet_pressure", self.outlet_pressure, f"< inlet_pressure = {self.inlet_pressure:g} Pa"
            )
        if self.clearance >= 0.05 * self.radius:
            raise InputError(
                f"{where}.clearance", self.clearance, f"< 0.05 radius = {0.05 * self.radius:g} m (an annular gap)"
            )


class LiquidSealElement(ComputedBearing):
    """Constant-in-whirl K, k, C, c and M, m at each spin speed (element contract, nonzero mass)."""

    def __init__(self, spec: LiquidSeal, name: str):
        self.spec, self.name = spec, name

    def flow(self, speed: float) -> tuple[float, float, float]:
        """Axial velocity V [m/s], lambda and sigma of the centred seal at spin ``speed`` [rad/s]."""
        sp, (n0, m0) = self.spec, HIRS
        nu, dp = sp.viscosity / sp.density, sp.inlet_pressure - sp.outlet_pressure

        def lam(V):
            return n0 * (2 * sp.clearance * V / nu) ** m0 * (1 + (sp.radius * speed / (2 * V)) ** 2) ** ((1 + m0) / 2)

        from scipy.optimize import brentq

        def res(V):  # dP = (1 + xi + 2 sigma) rho V^2 / 2
            return (1 + sp.entrance_loss + 2 * lam(V) * sp.length / sp.clearance) * sp.density * V**2 / 2 - dp

        hi = np.sqrt(2 * dp / (sp.density * (1 + sp.entrance_loss)))  # frictionless upper bound
        V = brentq(res, 1e-9 * hi, hi, xtol=1e-14 * hi, rtol=1e-14)
        return V, lam(V), lam(V) * sp.length / sp.clearance

    def swirl_decay(self, speed: float) -> float:
        """beta [1/m]: the inlet swirl relaxes as u(z) = R w [1/2 + (u0 - 1/2) e^(-beta z)] (module docstring)."""
        V, lam, _ = self.flow(speed)
        u = self.spec.radius * speed / 2
        return lam / self.spec.clearance * (1 + (1 + HIRS[1]) * u**2 / (V**2 + u**2))

    def impedance(self, speed: float, s, inlet_acceleration: bool = False) -> np.ndarray:
        """G(s) [N/m] for a unit orbit, s = i (W - w/2) [1/s] (force on the rotor = -G (x + i y)).

        The first-order equations integrated along z in closed form; with ``inlet_swirl`` the local
        s(z) = s - i w (u0 - 1/2) e^(-beta z) (module docstring), else s(z) = s.
        ``inlet_acceleration``: keep rho Cr s w(0) in the axial momentum (False: Childs' model).
        """
        sp, m0 = self.spec, HIRS[1]
        R, L, Cr, rho, xi = sp.radius, sp.length, sp.clearance, sp.density, sp.entrance_loss
        V, lam, _ = self.flow(speed)
        u = R * speed / 2
        tau0 = lam * rho * V**2
        tau_w = tau0 / V * (1 + (1 + m0) / (1 + (u / V) ** 2))  # d tau / d W at fixed u: tau0 B / V
        h = -1.0
        s = np.asarray(s, complex)
        A = (m0 - 1) * tau0 / Cr
        # S_n = n-fold integral over (0, L) of s(z), Q = int_0^L S(z)^2 dz, S(z) = int_0^z s
        d = 0.0 if sp.inlet_swirl is None else -1j * speed * (sp.inlet_swirl - 0.5)
        S0, S1, S2, Q = s * L, s * L**2 / 2, s * L**3 / 6, s**2 * L**3 / 3
        if d != 0.0:
            b = self.swirl_decay(speed)
            e, e2 = np.exp(-b * L), np.exp(-2 * b * L)
            g0 = (1 - e) / b  # int_0^L e^(-b z)
            g1 = (L - g0) / b  # int_0^L int_0^z ...
            g2 = (L**2 / 2 - g1) / b
            zg = (L**2 / 2 - (1 - e * (1 + b * L)) / b**2) / b  # int_0^L z (1 - e^(-b z)) / b dz
            gg = (L - 2 * g0 + (1 - e2) / (2 * b)) / b**2  # int_0^L ((1 - e^(-b z)) / b)^2 dz
            S0, S1, S2 = S0 + d * g0, S1 + d * g1, S2 + d * g2
            Q = Q + 2 * s * d * zg + d**2 * gg
        # -Cr (p(z) - p0) = A h z + rho V h S + tau_w w0 z + tau_w h S_1(z) / Cr - rho h S^2 / 2 - (1 - a) rho Cr w0 S:
        # the inertia -rho Cr s(z) acts on w(z) - w(0) (Childs, a = 1) or on all of w (inlet_acceleration, a = 0)
        keep = 1.0 if inlet_acceleration else 0.0
        w0 = -(A * h * L + rho * V * h * S0 + tau_w * h * S1 / Cr - rho * h * S0**2 / 2) / (
            Cr * (1 + xi) * rho * V + tau_w * L - keep * rho * Cr * S0
        )
        p0 = -(1 + xi) * rho * V * w0
        int_p = (
            p0 * L
            - (
                A * h * L**2 / 2
                + rho * V * h * S1
                + tau_w * w0 * L**2 / 2
                + tau_w * h * S2 / Cr
                - rho * h * Q / 2
                - keep * rho * Cr * w0 * S1
            )
            / Cr
        )
        return np.pi * R * np.conj(int_p)

    def childs(self, speed: float) -> dict:
        """Childs' short-seal constants at spin ``speed`` [rad/s]: mu0, mu1, mu2 [-], mu3 [N/m],
        T [s], B, E, b [-], sigma, lambda, V [m/s]."""
        sp, m0 = self.spec, HIRS[1]
        xi = sp.entrance_loss
        V, lam, sig = self.flow(speed)
        q = 1.0 / (1.0 + (sp.radius * speed / (2 * V)) ** 2)  # 4 b^2 / (1 + 4 b^2), finite at w = 0
        B = 1 + (1 + m0) * q
        E = (1 + xi) / (2 * (1 + xi + B * sig))
        den = 1 + xi + 2 * sig
        return {
            "mu0": 2 * sig**2 * E * (1 - m0) / den,
            "mu1": 2 * sig**2 * (E / sig + B / 2 * (1 / 6 + E)) / den,
            "mu2": sig * (1 / 6 + E) / den,
            "mu3": np.pi * sp.radius * (sp.inlet_pressure - sp.outlet_pressure) / lam,
            "T": sp.length / V,
            "B": B,
            "E": E,
            "b": V / (sp.radius * speed) if speed > 0 else np.inf,
            "sigma": sig,
            "lambda": lam,
            "V": V,
        }

    def expanded(self, speed: float, inlet_acceleration: bool = False) -> tuple[float, ...]:
        """K, k, C, c, M, m at ``speed`` [rad/s] from :meth:`impedance`: its Taylor expansion to second
        order about W = w/2 (central differences, step 1e-3 of the inverse transit time): the
        second formulation of :meth:`constants` (``inlet_acceleration=False``) or the variant."""
        V = self.flow(speed)[0]
        d = 1e-3 * V / self.spec.length
        g0, gp, gm = (self.impedance(speed, 1j * x, inlet_acceleration) for x in (0.0, d, -d))
        # G as a function of x = W - w/2: Re = K0 + c0 x - M x^2, Im = C x - k0 + m x^2
        K0, M = g0.real, -(gp.real - 2 * g0.real + gm.real) / (2 * d**2)  # f'' = 2 x (coefficient of x^2)
        c0 = (gp.real - gm.real) / (2 * d)
        C, m = (gp.imag - gm.imag) / (2 * d), (gp.imag - 2 * g0.imag + gm.imag) / (2 * d**2)
        k0 = -g0.imag
        x0 = speed / 2  # back to W = x + w/2: K + W c - W^2 M and W C - k + W^2 m
        return K0 - c0 * x0 - M * x0**2, k0 + C * x0 - m * x0**2, C - 2 * m * x0, c0 + 2 * M * x0, M, m

    def constants(self, speed: float) -> tuple[float, float, float, float, float, float]:
        """K, k, C, c [N/m, N s/m], M, m [kg] at spin ``speed`` [rad/s]: Childs' short seal (m = 0), or with
        ``inlet_swirl`` the coefficients of the force, quadratic in the whirl frequency (module docstring)."""
        return _constants(self, float(speed))

    def coefficients(self, speed, whirl=None) -> tuple[np.ndarray, np.ndarray]:
        speed = np.atleast_1d(np.asarray(speed, float))
        K, C = np.zeros((speed.size, 2, 2)), np.zeros((speed.size, 2, 2))
        for j, s in enumerate(speed):
            kd, kc, cd, cc, _, _ = self.constants(float(s))
            K[j], C[j] = [[kd, kc], [-kc, kd]], [[cd, cc], [-cc, cd]]
        return K, C

    def mass(self, speed) -> np.ndarray:
        """Added mass (n, 2, 2) [kg]: [[M, m], [-m, M]]."""
        speed = np.atleast_1d(np.asarray(speed, float))
        out = np.zeros((speed.size, 2, 2))
        for j, s in enumerate(speed):
            M, m = self.constants(float(s))[4:]
            out[j] = [[M, m], [-m, M]]
        return out

    def outputs(self, speed) -> dict:
        """Leakage [kg/s] and axial velocity [m/s] at the spin speeds."""
        import xarray as xr

        sp = self.spec
        V = np.array([self.flow(float(s))[0] for s in np.atleast_1d(speed)])
        return {
            "leakage": xr.DataArray(
                sp.density * V * 2 * np.pi * sp.radius * sp.clearance, dims=("seal_speed",), attrs={"units": "kg/s"}
            ),
            "axial_velocity": xr.DataArray(V, dims=("seal_speed",), attrs={"units": "m/s"}),
        }


@functools.lru_cache(maxsize=4096)
def _constants(el: LiquidSealElement, speed: float) -> tuple[float, float, float, float, float, float]:
    """K, k, C, c, M, m of ``el`` at ``speed`` (cached: coefficients and mass ask for the same speeds)."""
    if el.spec.inlet_swirl is not None:
        return tuple(float(x) for x in el.expanded(speed))
    d = el.childs(speed)
    mu3, T, w = d["mu3"], d["T"], speed
    M = mu3 * d["mu2"] * T**2
    return (mu3 * d["mu0"] - M * w**2 / 4, mu3 * d["mu1"] * T * w / 2, mu3 * d["mu1"] * T, M * w, M, 0.0)


def element(spec: LiquidSeal, where: str) -> LiquidSealElement:
    spec.validate(where)
    return LiquidSealElement(spec, where)
