"""Liquid annular seal (``[bearing.NAME.liquid_seal]``): short-seal bulk-flow model with added mass.

The short-seal assumptions of Black & Jenssen (1970) and Childs (1983, "Dynamic analysis of
turbulent annular seals based on Hirs' lubrication equation", J. Lubr. Technol. 105, 429-436):
a plain annulus of radius R, length L and radial clearance Cr, circumferential velocity fully
developed at R w / 2, circumferential pressure gradients negligible against axial ones, Hirs'
turbulent wall shear (both walls)

    tau_z = rho n0 (2 H / nu)^m0 (W^2 + (R w / 2)^2)^((1 + m0)/2) W,   n0 = 0.066, m0 = -0.25,

an entrance loss P(0) = P_in - (1 + xi) rho W(0)^2 / 2 and P(L) = P_out. The centred flow has the
axial velocity V of dP = (1 + xi + 2 sigma) rho V^2 / 2, sigma = lambda L / Cr with
lambda = n0 Ra^m0 (1 + 1/(4 b^2))^((1+m0)/2), Ra = 2 Cr V / nu, b = V / (R w).

First order (this module's derivation of the equations above): on a circular orbit at whirl W the
clearance h = -r cos(theta - W t), and with s = i (W - w/2) continuity gives
Cr dw/dz = s h, the axial momentum
-Cr dp/dz = ((m0 - 1) tau0 / Cr + rho V s) h + (dtau/dW - rho Cr s) w,
both integrated in closed form along z (w linear, p quadratic) with p(0) = -(1 + xi) rho V w(0) and
p(L) = 0. The force G(s) = pi R int conj(p) dz is a function of W - w/2 only; its Taylor expansion
to second order about W = w/2 gives constant coefficients in Childs' form:
K = K0 - M w^2 / 4, k = C w / 2, c = M w (and a cross-coupled mass m, nearly zero).
"""

from __future__ import annotations

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

    def impedance(self, speed: float, s) -> np.ndarray:
        """G(s) [N/m] for a unit orbit, s = i (W - w/2) [1/s] (force on the rotor = -G (x + i y))."""
        sp, m0 = self.spec, HIRS[1]
        R, L, Cr, rho, xi = sp.radius, sp.length, sp.clearance, sp.density, sp.entrance_loss
        V, lam, _ = self.flow(speed)
        u = R * speed / 2
        tau0 = lam * rho * V**2
        tau_w = tau0 / V * (1 + (1 + m0) / (1 + (u / V) ** 2))  # d tau / d W at fixed u
        h = -1.0
        s = np.asarray(s, complex)
        a = s * h / Cr  # dw/dz
        alpha = ((m0 - 1) * tau0 / Cr + rho * V * s) * h
        beta = tau_w - rho * Cr * s
        w0 = -(alpha * L + beta * a * L**2 / 2) / (Cr * (1 + xi) * rho * V + beta * L)
        p0 = -(1 + xi) * rho * V * w0
        int_p = p0 * L - (alpha * L**2 / 2 + beta * (w0 * L**2 / 2 + a * L**3 / 6)) / Cr
        return np.pi * R * np.conj(int_p)

    def constants(self, speed: float) -> tuple[float, float, float, float, float, float]:
        """K, k, C, c [N/m, N s/m], M, m [kg] at spin ``speed`` [rad/s] (Taylor expansion about W = w/2)."""
        V = self.flow(speed)[0]
        d = 1e-3 * V / self.spec.length  # step in x = W - w/2 [rad/s]: 1e-3 of the inverse transit time
        g0, gp, gm = (self.impedance(speed, 1j * x) for x in (0.0, d, -d))
        # G as a function of x: Re = K0 + c0 x - M x^2, Im = C x - k0 + m x^2
        K0, M = g0.real, -(gp.real - 2 * g0.real + gm.real) / d**2
        c0 = (gp.real - gm.real) / (2 * d)
        C, m = (gp.imag - gm.imag) / (2 * d), (gp.imag - 2 * g0.imag + gm.imag) / d**2
        k0 = -g0.imag
        # back to W = x + w/2: K + W c - W^2 M and W C - k + W^2 m
        x0 = speed / 2
        K = K0 - c0 * x0 - M * x0**2
        c = c0 + 2 * M * x0
        k = k0 + C * x0 - m * x0**2
        C = C - 2 * m * x0
        return K, k, C, c, M, m

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


def element(spec: LiquidSeal, where: str) -> LiquidSealElement:
    spec.validate(where)
    return LiquidSealElement(spec, where)
