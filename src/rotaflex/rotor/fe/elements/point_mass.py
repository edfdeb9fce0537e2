"""Point mass at a node (translational inertia only)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class PointMassElement:
    """Lumped mass on the translations of one node.

    Parameters
    ----------
    mass : float  [kg]
    """

    mass: float

    def M(self) -> np.ndarray:
        """Mass matrix (4, 4) on [x, y, theta_x, theta_y]."""
        return np.diag([self.mass, self.mass, 0.0, 0.0])

    def K(self) -> np.ndarray:
        return np.zeros((4, 4))

    def C(self) -> np.ndarray:
        return np.zeros((4, 4))

    def G(self) -> np.ndarray:
        return np.zeros((4, 4))
