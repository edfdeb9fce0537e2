"""Active magnetic bearing (``[bearing.NAME.magnetic]``): frequency-dependent K(w), C(w) from the
actuator constants and a PID controller with a first-order low-pass filter.

Per axis (x and y alike, no coupling), linearised about the bias current (Schweitzer & Maslen
2009, ch. 2 and 7):

    f = k_s x - k_i i,        i = H(s) x,
    H(s) = g_s g_a (k_p + k_I / s + k_D s) / (1 + s / w_f)

with k_s [N/m] the negative (open-loop) position stiffness given as a positive number, k_i [N/A]
the force-current factor, g_s [V/m] the sensor gain, g_a [A/V] the amplifier gain and w_f the
low-pass corner. The bearing force on the rotor is f = -Z(s) x with the impedance
Z(s) = k_i H(s) - k_s, so at a whirl (vibration) frequency w the equivalent coefficients are

    K(w) = Re Z(i w),    C(w) = Im Z(i w) / w.

At w = 0, C is the limit of the proportional-derivative-filter part only (the integral path
gives C -> -inf there, a static force, not damping) and K is the limit of Re Z (finite).

ISO 14839-3 rates the sensitivity function S = 1 / (1 + G_o) of the loop G_o(s) = k_i H(s) /
(m s^2 - k_s) closed over the rotor mass m the bearing carries (key ``mass``): peak |S| < 3
zone A, < 4 zone B, < 5 zone C, else zone D.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rotaflex.core.config import param
from rotaflex.core.errors import InputError
from rotaflex.rotor.fe.elements.bearing import ComputedBearing

#: ISO 14839-3 zone limits of the peak sensitivity |S|max (A/B, B/C, C/D)
ISO14839_ZONES = ((3.0, "A"), (4.0, "B"), (5.0, "C"))


@dataclass(frozen=True)
class Magnetic:
    """``[bearing.NAME.magnetic]``: actuator constants, sensor, amplifier and PID + low-pass."""

    k_i: float = param(unit="N/A", gt=0, doc="force-current factor")
    k_s: float = param(unit="N/m", ge=0, doc="open-loop negative stiffness, given as a positive number")
    sensor_gain: float = param(unit="V/m", gt=0, doc="position sensor gain g_s")
    p_gain: float = param(unit="1", gt=0, doc="controller proportional gain k_p [V/V]")
    amplifier_gain: float = param(1.0, unit="A/V", gt=0, doc="power amplifier gain g_a")
    i_gain: float = param(0.0, unit="1/s", ge=0, doc="controller integral gain k_I")
    d_gain: float = param(0.0, unit="s", ge=0, doc="controller derivative gain k_D")
    lowpass_hz: float | None = param(None, unit="Hz", gt=0, doc="first-order low-pass corner (none: no filter)")
    mass: float | None = param(
        None, unit="kg", gt=0, doc="rotor mass this bearing carries (for the ISO 14839-3 rating)"
    )


def impedance(spec: Magnetic, s) -> np.ndarray:
    """Z(s) = k_i H(s) - k_s [N/m] at complex ``s`` [1/s] (the force on the rotor is -Z x)."""
    s = np.asarray(s, complex)
    pid = spec.p_gain + spec.d_gain * s + np.divide(spec.i_gain, s, out=np.zeros_like(s), where=s != 0)
    lp = 1.0 if spec.lowpass_hz is None else 1.0 / (1.0 + s / (2 * np.pi * spec.lowpass_hz))
    return spec.k_i * spec.sensor_gain * spec.amplifier_gain * pid * lp - spec.k_s


def sensitivity(spec: Magnetic, w) -> np.ndarray:
    """|S(i w)| of the loop closed over ``spec.mass`` at frequencies ``w`` [rad/s]."""
    s = 1j * np.asarray(w, float)
    g_o = (impedance(spec, s) + spec.k_s) / (spec.mass * s**2 - spec.k_s)
    return np.abs(1.0 / (1.0 + g_o))


def sensitivity_peak(spec: Magnetic) -> tuple[float, float]:
    """Peak |S| and its frequency [rad/s]: a log grid over the loop's band refined by golden search."""
    from scipy.optimize import minimize_scalar

    wc = np.sqrt(abs(impedance(spec, 0.0).real) + spec.k_s) / np.sqrt(spec.mass)  # ~ the loop's crossover
    w = np.geomspace(1e-3 * wc, 1e3 * wc, 4001)
    S = sensitivity(spec, w)
    j = int(np.argmax(S))
    lo, hi = np.log(w[max(j - 1, 0)]), np.log(w[min(j + 1, w.size - 1)])
    r = minimize_scalar(
        lambda t: -sensitivity(spec, np.exp(t)), bounds=(lo, hi), method="bounded", options={"xatol": 1e-10}
    )
    return float(-r.fun), float(np.exp(r.x))


def iso14839_zone(peak: float) -> str:
    """ISO 14839-3 zone of a peak sensitivity."""
    return next((z for lim, z in ISO14839_ZONES if peak < lim), "D")


class MagneticElement(ComputedBearing):
    """Isotropic AMB: K(w), C(w) on x and y, no cross-coupling (element contract)."""

    frequency_dependent = True

    def __init__(self, spec: Magnetic, name: str):
        self.spec, self.name = spec, name

    def coefficients(self, speed, whirl=None) -> tuple[np.ndarray, np.ndarray]:
        """K, C (n, 2, 2) at the whirl frequencies ``whirl`` [rad/s] (None: = ``speed``)."""
        speed = np.atleast_1d(np.asarray(speed, float))
        w = np.abs(speed if whirl is None else np.broadcast_to(np.asarray(whirl, float), speed.shape))
        z = impedance(self.spec, 1j * w)
        k = z.real
        if np.any(w == 0):  # the static limit: K finite; C of the PD-filter part (no integral)
            sp = self.spec
            g = sp.k_i * sp.sensor_gain * sp.amplifier_gain
            tau = 0.0 if sp.lowpass_hz is None else 1.0 / (2 * np.pi * sp.lowpass_hz)
            k0 = g * (sp.p_gain - sp.i_gain * tau) - sp.k_s
            c0 = g * (sp.d_gain - sp.p_gain * tau + sp.i_gain * tau**2)
        c = np.where(w > 0, z.imag / np.where(w > 0, w, 1.0), 0.0)
        if np.any(w == 0):
            k, c = np.where(w == 0, k0, k), np.where(w == 0, c0, c)
        eye = np.eye(2)
        return k[:, None, None] * eye, c[:, None, None] * eye

    def outputs(self, speed) -> dict:
        """The ISO 14839-3 peak sensitivity and zone (when ``mass`` is given)."""
        if self.spec.mass is None:
            return {}
        import xarray as xr

        peak, w = sensitivity_peak(self.spec)
        return {
            "sensitivity_peak": xr.DataArray(peak, attrs={"units": "1", "iso14839_zone": iso14839_zone(peak)}),
            "sensitivity_peak_frequency": xr.DataArray(w, attrs={"units": "rad/s"}),
        }


def element(spec: Magnetic, where: str) -> MagneticElement:
    """The AMB element; refuses a controller that cannot hold the rotor on its own (naming the key)."""
    g = spec.k_i * spec.sensor_gain * spec.amplifier_gain
    if g * spec.p_gain <= spec.k_s:
        raise InputError(
            f"{where}.p_gain",
            spec.p_gain,
            f"> k_s / (k_i g_s g_a) = {spec.k_s / g:.6g}: the closed loop's static stiffness "
            f"k_i g_s g_a k_p - k_s must be positive (the controller alone is unstable)",
        )
    if spec.mass is not None:
        tau = 0.0 if spec.lowpass_hz is None else 1.0 / (2 * np.pi * spec.lowpass_hz)
        # m s^2 (1 + tau s) s + g (k_p s + k_I + k_D s^2) - k_s s (1 + tau s) = 0, times s (1 + tau s)
        poly = np.polyadd(
            np.polysub(np.polymul([spec.mass, 0, 0], [tau, 1, 0]), np.polymul([spec.k_s], [tau, 1, 0])),
            g * np.array([spec.d_gain, spec.p_gain, spec.i_gain]),
        )
        roots = np.roots(np.trim_zeros(poly, "f"))
        if np.any(roots.real > 0):
            raise InputError(
                f"{where}.d_gain",
                spec.d_gain,
                f"gains that make the loop closed over mass = {spec.mass:g} kg stable "
                f"(poles with real part {roots.real.max():.4g} 1/s > 0)",
            )
    return MagneticElement(spec, where)
