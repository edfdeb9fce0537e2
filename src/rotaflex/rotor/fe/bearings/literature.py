"""Published reference values for fluid-film bearings (used by the tests and ``reproduce rotor``).

Written from the literature, independently of the solvers in this package:

- Ocvirk's short bearing: load relation and the load-normalised 8 coefficients as printed by
  Childs (1993), Turbomachinery Rotordynamics, ch. 3, and Friswell, Penny, Garvey & Lees (2010),
  Dynamics of Rotating Machines, section 5.5.2.
- Someya (1989), Journal-Bearing Databook, two-axial-groove bearing, L/D = 0.5 (p. 14).
- Someya (1989), four-pad tilting-pad bearing, load between pads, L/D = 0.5 (p. 83).
- Raimondi & Boyd (1958), full 360 deg bearing, L/D = 1 (as tabulated in Shigley's Mechanical
  Engineering Design).
- Kanki & Kawakami (1984), measured leakage and coefficients of a short plain water seal.
- The stability threshold of a symmetric rotor on two bearings from the linearised equations:
  rigid (4x4; Lund 1987, Review of the concept of dynamic coefficients, J. Tribology 109) and
  the Jeffcott rotor (central disk on a massless flexible shaft, massless journals; 6 states).
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq

G_ACC = 9.81  #: m/s^2


def ocvirk_sommerfeld(eps, l_over_d):
    """Sommerfeld number S = mu N L D (R/c)^2 / W of the short bearing at eccentricity ratio eps."""
    q = 1 - eps**2
    return (1 / l_over_d) ** 2 * q**2 / (np.pi * eps * np.sqrt(np.pi**2 * q + 16 * eps**2))


def ocvirk_attitude(eps):
    """Attitude angle [rad] of the short bearing: tan phi = pi sqrt(1 - eps^2) / (4 eps)."""
    return np.arctan(np.pi * np.sqrt(1 - eps**2) / (4 * eps))


def ocvirk_coefficients(e):
    """K c / W and C c omega / W of the short bearing in the frame (u, v): v along the static
    load, u such that the spin turns u into v (Childs 1993; Friswell et al. 2010)."""
    q = 1 - e * e
    h0 = 1 / (np.pi**2 * q + 16 * e * e) ** 1.5
    auu = h0 * 4 * (np.pi**2 * (2 - e * e) + 16 * e * e)
    auv = h0 * np.pi * (np.pi**2 * q * q - 16 * e**4) / (e * np.sqrt(q))
    avu = -h0 * np.pi * (np.pi**2 * q * (1 + 2 * e * e) + 32 * e * e * (1 + e * e)) / (e * np.sqrt(q))
    avv = h0 * 4 * (np.pi**2 * (1 + 2 * e * e) + 32 * e * e * (1 + e * e) / q)
    buu = h0 * 2 * np.pi * np.sqrt(q) * (np.pi**2 * (1 + 2 * e * e) - 16 * e * e) / e
    buv = -h0 * 8 * (np.pi**2 * (1 + 2 * e * e) - 16 * e * e)
    bvv = h0 * 2 * np.pi * (np.pi**2 * q * q + 48 * e * e) / (e * np.sqrt(q))
    return np.array([[auu, auv], [avu, avv]]), np.array([[buu, buv], [buv, bvv]])


#: Someya (1989) two-axial-groove bearing, L/D = 0.5: (S, eps, attitude [deg],
#: K c/W (xx, xy, yx, yy), C c omega/W (xx, xy, yx, yy)); x along the load, y at +90 deg in the spin sense
SOMEYA_LD05 = [
    (0.517, 0.50, 51.1, (2.89, 3.57, -0.924, 2.03), (6.81, 2.10, 2.10, 2.60)),
    (0.323, 0.60, 44.7, (3.65, 3.62, -0.427, 1.92), (6.81, 2.08, 2.08, 2.06)),
    (0.187, 0.70, 38.2, (4.92, 3.88, 0.0235, 1.83), (7.32, 2.16, 2.16, 1.70)),
    (0.0926, 0.80, 31.2, (7.35, 4.46, 0.527, 1.78), (8.17, 2.05, 2.05, 1.24)),
    (0.0315, 0.90, 22.7, (13.8, 5.76, 1.24, 1.72), (10.6, 2.03, 2.03, 0.846)),
]

#: Someya (1989) four-pad tilting-pad bearing, load between pads, L/D = 0.5, no preload (p. 83):
#: (S, eps, K c/W along and across the load, C c omega/W along and across); cross terms are 0
SOMEYA_TILTING_PAD_LBP_LD05 = [
    (5.76, 0.1, 0.901, 0.901, 10.8, 10.8),
    (2.67, 0.2, 1.22, 1.22, 6.03, 6.03),
    (1.05, 0.4, 1.68, 1.68, 3.61, 3.61),
    (0.550, 0.6, 2.26, 2.26, 3.21, 3.21),
    (0.259, 0.8, 3.15, 3.15, 3.01, 3.01),
]

#: Raimondi & Boyd (1958), 360 deg bearing, L/D = 1: (eps, S, attitude [deg])
RAIMONDI_BOYD_LD1 = [
    (0.2, 0.631, 74.02),
    (0.4, 0.264, 63.10),
    (0.6, 0.121, 50.58),
    (0.8, 0.0446, 36.24),
    (0.9, 0.0188, 26.45),
]


#: Kanki & Kawakami (1984), "Experimental study on the dynamic characteristics of pump annular seals",
#: Proc. IMechE Conf. Vibrations in Rotating Machinery, C297/84, pp. 159-166: the short plain seal
#: (L/D = 0.2) as transcribed in the validation case val/val02 of the public bulk-flow code
#: trosny/bulk_flow (the paper itself was not at hand: its table or figure number is not known).
#: Geometry [m], water at 25.6 C [kg/m^3, Pa s], pressures [Pa], speeds [rpm]; measured leakage
#: [m^3/s], direct K_xx, K_yy [N/m] and C_xx, C_yy [N s/m], cross-coupled |K_xy|, |K_yx| [N/m] and
#: |C_xy|, |C_yx| [N s/m] (the transcription runs the rotor backwards: magnitudes only).
KANKI_KAWAKAMI_SHORT = {
    "radius": 0.1,
    "length": 0.04,
    "clearance": 0.5e-3,
    "density": 995.5,
    "viscosity": 7.888e-4,
    "inlet_pressure": 1.47e6,
    "outlet_pressure": 0.49e6,
    "speed_rpm": 2000.0,
    "inlet_rotation_rpm": 400.0,
    "leakage": 9047e-6,
    "K": (3.96e6, 4.01e6),
    "k": (0.664e6, 0.337e6),
    "C": (24.82e3, 24.46e3),
    "c": (12.3e3, 10.88e3),
}


def rigid_rotor_growth(w, m, diameter, length, clearance, viscosity, shaft_stiffness=np.inf):
    """Largest real part [1/s] of a symmetric rotor (mass m per bearing, load m g) on two short
    bearings at spin speed w [rad/s], cylindrical whirl.

    ``shaft_stiffness`` = inf: rigid rotor, m x'' + C x' + K x = 0 (4 states). Finite: the
    Jeffcott rotor with midspan shaft stiffness k_s (N/m, between the disk and both journals):
    per bearing m x_d'' = k (x_j - x_d), C x_j' + (K + k) x_j = k x_d with k = k_s / 2 and massless
    journals (6 states).
    """
    W, R = m * G_ACC, diameter / 2
    S = viscosity * (w / (2 * np.pi)) * length * diameter * (R / clearance) ** 2 / W
    eps = brentq(lambda e: ocvirk_sommerfeld(e, length / diameter) - S, 1e-9, 1 - 1e-9, xtol=1e-14)
    a, b = ocvirk_coefficients(eps)
    K, C = W / clearance * a, W / (clearance * w) * b
    Z, I2 = np.zeros((2, 2)), np.eye(2)
    if np.isinf(shaft_stiffness):
        A = np.block([[Z, I2], [-K / m, -C / m]])
    else:
        k, Ci = shaft_stiffness / 2, np.linalg.inv(C)
        A = np.block([[Z, I2, Z], [-k / m * I2, Z, k / m * I2], [k * Ci, Z, -Ci @ (K + k * I2)]])
    return np.linalg.eigvals(A).real.max()


def rigid_rotor_whip_threshold(m, diameter, length, clearance, viscosity, bracket, shaft_stiffness=np.inf):
    """Onset speed [rad/s] of oil whip within ``bracket`` [rad/s] (see :func:`rigid_rotor_growth`)."""
    args = (m, diameter, length, clearance, viscosity, shaft_stiffness)
    return brentq(rigid_rotor_growth, *bracket, args=args, xtol=1e-9)
