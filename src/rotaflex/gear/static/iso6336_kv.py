"""ISO 6336-1 method B dynamic factor K_v of spur gears.

Implements the method-B procedure of ISO 6336-1 ("Calculation of load capacity of spur and
helical gears - Part 1", clause 6, dynamic factor K_v; the method-B formulas are those of the
2006 edition, kept in the 2019 edition) for spur gears (total contact ratio eps_gamma =
eps_alpha, 1 < eps_gamma):

* reduced mass per unit face width ``m_red = m1* m2* / (m1* + m2*)``, ``m_i* = J_i* / r_bi^2``
  with ``J_i*`` the polar moment of inertia per unit face width;
* resonance speed of the pinion ``n_E1 = 30000 / (pi z1) sqrt(c_gamma_alpha / m_red)``
  [min^-1] with c_gamma_alpha in N/(mm um) and m_red in kg/mm; here evaluated in SI as the
  angular speed ``omega_E1 = sqrt(c_gamma_alpha / m_red) / z1`` [rad/s] (the mesh frequency
  ``z1 omega_E1`` meets ``sqrt(c_gamma_alpha / m_red)``; ``n_E1 = 30 omega_E1 / pi``);
* resonance ratio ``N = n1 / n_E1 = omega1 / omega_E1``, lower limit of the main resonance range
  ``N_S = 0.5 + 0.35 sqrt(K_A F_t / (100 b))`` for ``K_A F_t / b < 100 N/mm``, else 0.85;
* ``B_p = c' f_pb,eff / (K_A F_t / b)``, ``B_f = c' f_f,eff / (K_A F_t / b)``,
  ``B_k = |1 - c' C_a / (K_A F_t / b)|`` (C_a: tip relief; 0 gives B_k = 1);
* ranges
    - subcritical ``N <= N_S``: ``K_v = N K + 1``, ``K = C_v1 B_p + C_v2 B_f + C_v3 B_k``;
    - main resonance ``N_S < N <= 1.15``: ``K_v = C_v1 B_p + C_v2 B_f + C_v4 B_k + 1``;
    - intermediate ``1.15 < N < 1.5``: linear in N between K_v(1.15) and K_v(1.5);
    - supercritical ``N >= 1.5``: ``K_v = C_v5 B_p + C_v6 B_f + C_v7``;
* the coefficient table C_v1..C_v7 for 1 < eps_gamma <= 2 and eps_gamma > 2 (see
  :func:`cv_coefficients`).

Units: SI at the interface (N/m^2 for stiffness per unit face width, m for deviations, N/m for
load per width, rad/s for speeds; a config in rpm is converted where it is read, with
:func:`rotaflex.core.units.rpm_to_rad_s`); the N/(mm um) values of the standard are 1e9 times smaller numbers in SI
(1 N/(mm um) = 1e9 N/m^2).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rotaflex.core.config import param
from rotaflex.core.errors import InputError
from rotaflex.core.units import rad_s_to_rpm

__all__ = [
    "IsoKvInput",
    "cv_coefficients",
    "iso_kv",
    "reduced_mass_per_width",
    "resonance_speed",
    "resonance_speed_rpm",
]


def cv_coefficients(eps_gamma: float) -> dict[str, float]:
    """ISO 6336-1 method B coefficients C_v1..C_v7 for a total contact ratio eps_gamma.

    Parameters
    ----------
    eps_gamma : float
        Total contact ratio [-] (= transverse contact ratio for spur gears), > 1.

    Returns
    -------
    dict
        ``Cv1`` ... ``Cv7`` [-].
    """
    e = float(eps_gamma)
    if not e > 1.0:
        raise InputError("eps_gamma", eps_gamma, "a contact ratio > 1")
    if e <= 2.0:
        cv = {"Cv1": 0.32, "Cv2": 0.34, "Cv3": 0.23, "Cv4": 0.90, "Cv5": 0.47, "Cv6": 0.47}
    else:
        cv = {
            "Cv1": 0.32,
            "Cv2": 0.57 / (e - 0.3),
            "Cv3": 0.096 / (e - 1.56),
            "Cv4": (0.57 - 0.05 * e) / (e - 1.44),
            "Cv5": 0.47,
            "Cv6": 0.12 / (e - 1.74),
        }
    if e <= 1.5:
        cv["Cv7"] = 0.75
    elif e <= 2.5:
        cv["Cv7"] = 0.125 * math.sin(math.pi * (e - 2.0)) + 0.875
    else:
        cv["Cv7"] = 1.0
    return cv


def reduced_mass_per_width(inertia, base_radius, face_width: float) -> float:
    """Reduced mass of the pair per unit face width, ``m_red`` [kg/m].

    Parameters
    ----------
    inertia : (2,) array_like
        Polar moments of inertia of pinion and wheel [kg m^2].
    base_radius : (2,) array_like
        Base radii [m].
    face_width : float
        Common face width b [m].
    """
    j1, j2 = (float(v) for v in inertia)
    r1, r2 = (float(v) for v in base_radius)
    return j1 * j2 / (j1 * r2**2 + j2 * r1**2) / face_width


def resonance_speed(c_gamma_alpha: float, m_red: float, z1: int) -> float:
    """Pinion resonance speed ``omega_E1`` [rad/s] from c_gamma_alpha [N/m^2] and m_red [kg/m]:
    the pinion speed at which the mesh frequency ``z1 omega_E1`` meets ``sqrt(c_gamma_alpha / m_red)``."""
    return math.sqrt(c_gamma_alpha / m_red) / z1


def resonance_speed_rpm(c_gamma_alpha: float, m_red: float, z1: int) -> float:
    """:func:`resonance_speed` in rpm (ISO's ``n_E1`` [min^-1]), for reports."""
    return rad_s_to_rpm(resonance_speed(c_gamma_alpha, m_red, z1))


@dataclass(frozen=True)
class IsoKvInput:
    """Data for ISO 6336-1 method B K_v of a spur pair (SI units).

    Stiffnesses are per unit face width: 1 N/(mm um) = 1e9 N/m^2.
    """

    z1: int = param(28, gt=0, doc="pinion teeth")
    c_single: float = param(14e9, unit="N/m^2", gt=0.0, doc="single stiffness c' per width")
    c_gamma_alpha: float = param(20e9, unit="N/m^2", gt=0.0, doc="mesh stiffness c_gamma_alpha per width")
    m_red: float = param(10.0, unit="kg/m", gt=0.0, doc="reduced mass per face width")
    load_per_width: float = param(1e5, unit="N/m", gt=0.0, doc="K_A F_t / b")
    eps_gamma: float = param(1.6, gt=1.0, doc="total contact ratio")
    f_pb_eff: float = param(0.0, unit="m", ge=0.0, doc="effective base pitch deviation")
    f_f_eff: float = param(0.0, unit="m", ge=0.0, doc="effective profile form deviation")
    tip_relief: float = param(0.0, unit="m", ge=0.0, doc="C_a (0: no relief, B_k = 1)")

    @property
    def resonance_speed(self) -> float:
        """omega_E1 [rad/s]."""
        return resonance_speed(self.c_gamma_alpha, self.m_red, self.z1)

    @property
    def resonance_speed_rpm(self) -> float:
        """n_E1 [rpm] (for reports)."""
        return resonance_speed_rpm(self.c_gamma_alpha, self.m_red, self.z1)

    @property
    def n_s(self) -> float:
        """Lower limit N_S of the main resonance range [-]."""
        w_mm = self.load_per_width * 1e-3  # N/mm
        return 0.5 + 0.35 * math.sqrt(w_mm / 100.0) if w_mm < 100.0 else 0.85

    def b_factors(self) -> tuple[float, float, float]:
        """(B_p, B_f, B_k) [-]."""
        w = self.load_per_width
        return (
            self.c_single * self.f_pb_eff / w,
            self.c_single * self.f_f_eff / w,
            abs(1.0 - self.c_single * self.tip_relief / w),
        )


def iso_kv(inp: IsoKvInput, speed) -> np.ndarray:
    """ISO 6336-1 method B dynamic factor K_v at the pinion speeds ``speed``.

    Parameters
    ----------
    inp : IsoKvInput
    speed : array_like
        Pinion speeds omega1 [rad/s], >= 0 (from rpm: :func:`rotaflex.core.units.rpm_to_rad_s`).

    Returns
    -------
    ndarray
        K_v [-], same shape as ``speed``.

    Examples
    --------
    >>> inp = IsoKvInput(f_pb_eff=5e-6, f_f_eff=4e-6)
    >>> float(iso_kv(inp, 0.0))
    1.0
    """
    omega = np.asarray(speed, dtype=float)
    if np.any(~np.isfinite(omega)) or np.any(omega < 0):
        raise InputError("speed", speed, "finite pinion speeds >= 0 rad/s")
    cv = cv_coefficients(inp.eps_gamma)
    bp, bf, bk = inp.b_factors()
    ratio = omega / inp.resonance_speed
    k_sub = cv["Cv1"] * bp + cv["Cv2"] * bf + cv["Cv3"] * bk
    kv_main = cv["Cv1"] * bp + cv["Cv2"] * bf + cv["Cv4"] * bk + 1.0
    kv_super = cv["Cv5"] * bp + cv["Cv6"] * bf + cv["Cv7"]
    kv_mid = kv_super + (kv_main - kv_super) / 0.35 * (1.5 - ratio)
    return np.select(
        [ratio <= inp.n_s, ratio <= 1.15, ratio < 1.5],
        [ratio * k_sub + 1.0, np.full_like(ratio, kv_main), kv_mid],
        default=kv_super,
    )
