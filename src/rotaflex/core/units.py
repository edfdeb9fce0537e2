"""Unit conversions at the config boundary: one helper per conversion.

Config keys with a non-SI unit say so (``speed_rpm``, ``pressure_angle_deg``); the module that
reads the config converts them here, once, and everything behind it sees SI (rad/s, rad).
Scalars give a float, array-likes an ``ndarray``. The arithmetic is that of ``x * pi / 30`` and
``math.radians``: bit-identical to the gear package's earlier expressions; the rotor package
used ``x * (pi / 30)``, which differs by an ulp for some speeds (what that moves and why is in
docs/architecture.md, "Rules the layout keeps").

Examples
--------
>>> rpm_to_rad_s(30.0) == math.pi
True
>>> rad_to_deg(deg_to_rad(20.0))
20.0
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["deg_to_rad", "rad_s_to_rpm", "rad_to_deg", "rpm_to_rad_s"]


def _scalar(x) -> bool:
    return np.ndim(x) == 0


def rpm_to_rad_s(rpm):
    """Speed [rpm] -> angular speed [rad/s]."""
    if _scalar(rpm):
        return float(rpm) * math.pi / 30.0
    return np.asarray(rpm, dtype=float) * math.pi / 30.0


def rad_s_to_rpm(omega):
    """Angular speed [rad/s] -> speed [rpm]."""
    if _scalar(omega):
        return float(omega) * 30.0 / math.pi
    return np.asarray(omega, dtype=float) * 30.0 / math.pi


def deg_to_rad(deg):
    """Angle [deg] -> [rad]."""
    return math.radians(deg) if _scalar(deg) else np.radians(np.asarray(deg, dtype=float))


def rad_to_deg(rad):
    """Angle [rad] -> [deg]."""
    return math.degrees(rad) if _scalar(rad) else np.degrees(np.asarray(rad, dtype=float))
