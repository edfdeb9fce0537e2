"""Rotational kinetic energy: the physical one and the paper's inertial-frame variant.

``K = 1/2 omega_body^T J omega_body = 1/2 omega_inertial^T (R J R^T) omega_inertial`` is the same
number in every frame. Yun & Ren (2008, eq. 24b, 25b, 29) instead evaluate
``1/2 omega_inertial^T J omega_inertial`` with the *body* inertia J, which is not a kinetic energy
unless J is isotropic or R commutes with J; :func:`kinetic_energy_inertial_paper` reproduces it.
"""

from __future__ import annotations

import numpy as np


def _quad(J, w) -> np.ndarray:
    w = np.asarray(w, dtype=float)
    return 0.5 * np.einsum("...i,...ij,...j->...", w, np.asarray(J, dtype=float), w)


def kinetic_energy_body(inertia, omega_body) -> np.ndarray:
    """``1/2 w*^T J w*`` [J]; ``inertia`` (3, 3) body-frame [kg m^2], ``omega_body`` (..., 3)."""
    return _quad(inertia, omega_body)


def kinetic_energy_inertial(inertia, R, omega_inertial) -> np.ndarray:
    """``1/2 w^T (R J R^T) w`` [J]: the physical energy from inertial-frame components."""
    R = np.asarray(R, dtype=float)
    J_inertial = R @ np.asarray(inertia, dtype=float) @ np.swapaxes(R, -1, -2)
    return _quad(J_inertial, omega_inertial)


def kinetic_energy_inertial_paper(inertia, omega_inertial) -> np.ndarray:
    """The paper's ``1/2 w^T J w`` with body inertia and inertial components [J]."""
    return _quad(inertia, omega_inertial)
