"""Linear bearing or seal: full 2x2 stiffness and damping, constant or tabulated vs speed."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from rotaflex.core.errors import InputError

COEFFICIENTS = ("kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy")


@dataclass(frozen=True)
class BearingElement:
    """Bearing between a node's translations and ground (or another node's translations).

    The force on the rotor is f = -K(Omega) [x, y] - C(Omega) [x', y'] with
    K = [[kxx, kxy], [kyx, kyy]] and C likewise. Coefficients given at ``speeds`` are
    interpolated linearly; a speed outside the table raises :class:`InputError`.

    Parameters
    ----------
    k : ndarray (n, 2, 2)
        Stiffness [N/m] at each tabulated speed (n = 1: constant).
    c : ndarray (n, 2, 2)
        Damping [N s/m].
    speeds : ndarray (n,) or None
        Spin speeds of the table [rad/s]; None for constant coefficients.
    name : str
        Dotted config path, used in error messages.
    """

    k: np.ndarray
    c: np.ndarray
    speeds: np.ndarray | None = None
    name: str = "bearing"
    table: object = field(default=None, compare=False, repr=False)  #: FluidFilmTable of a fluid-film bearing
    frequency_dependent: ClassVar[bool] = False  #: coefficients depend on speed only (element contract)

    @classmethod
    def constant(
        cls, kxx=0.0, kyy=0.0, kxy=0.0, kyx=0.0, cxx=0.0, cyy=0.0, cxy=0.0, cyx=0.0, name: str = "bearing"
    ) -> BearingElement:
        """Speed-independent coefficients [N/m, N s/m]."""
        return cls(np.array([[[kxx, kxy], [kyx, kyy]]], float), np.array([[[cxx, cxy], [cyx, cyy]]], float), None, name)

    @property
    def static_load_dependent(self) -> bool:
        """A fluid-film bearing's coefficients depend on its static load."""
        return self.table is not None

    def coefficients(self, speed, whirl=None) -> tuple[np.ndarray, np.ndarray]:
        """Stiffness and damping (n_speed, 2, 2) at the spin speeds ``speed`` [rad/s] (``whirl``: unused)."""
        speed = np.atleast_1d(np.asarray(speed, float))
        if self.speeds is None:
            return (
                np.broadcast_to(self.k[0], (speed.size, 2, 2)).copy(),
                np.broadcast_to(self.c[0], (speed.size, 2, 2)).copy(),
            )
        lo, hi = self.speeds[0], self.speeds[-1]
        bad = (speed < lo * (1 - 1e-12) - 1e-12) | (speed > hi * (1 + 1e-12) + 1e-12)
        if np.any(bad):
            s = float(speed[bad][0])
            raise InputError(
                f"{self.name}.speed_rpm",
                round(s * 30 / np.pi, 6),
                f"requested speeds within the coefficient table [{lo * 30 / np.pi:g}, {hi * 30 / np.pi:g}] rpm",
            )
        flat_k = self.k.reshape(len(self.speeds), 4)
        flat_c = self.c.reshape(len(self.speeds), 4)
        k = np.stack([np.interp(speed, self.speeds, flat_k[:, j]) for j in range(4)], -1).reshape(-1, 2, 2)
        c = np.stack([np.interp(speed, self.speeds, flat_c[:, j]) for j in range(4)], -1).reshape(-1, 2, 2)
        return k, c

    def M(self) -> np.ndarray:
        """Mass (2, 2) on the translations: zero."""
        return np.zeros((2, 2))

    def mass(self, speed) -> np.ndarray:
        """Added mass (n_speed, 2, 2) [kg]: zero."""
        return np.zeros((np.atleast_1d(speed).size, 2, 2))

    def outputs(self, speed) -> dict:
        """The kind's own results over speed: none."""
        return {}

    def K(self, speed: float = 0.0) -> np.ndarray:
        """Stiffness (2, 2) [N/m] at ``speed`` [rad/s]."""
        return self.coefficients(speed)[0][0]

    def C(self, speed: float = 0.0) -> np.ndarray:
        """Damping (2, 2) [N s/m] at ``speed`` [rad/s]."""
        return self.coefficients(speed)[1][0]

    def G(self) -> np.ndarray:
        """Gyroscopic (2, 2): zero."""
        return np.zeros((2, 2))


class ComputedBearing:
    """Base of the bearing kinds whose coefficients are computed at any speed (seals, magnetic
    bearings): the element contract of docs/architecture.md with no speed table.

    Subclasses set ``name`` and implement :meth:`coefficients`; :meth:`mass` is zero unless overridden.
    """

    speeds = None  #: no table: any speed >= 0 is accepted
    table = None  #: no fluid-film table
    frequency_dependent = False
    static_load_dependent = False
    name = "bearing"

    def coefficients(self, speed, whirl=None) -> tuple[np.ndarray, np.ndarray]:  # pragma: no cover - abstract
        raise NotImplementedError

    def mass(self, speed) -> np.ndarray:
        """Added mass (n_speed, 2, 2) [kg]: zero."""
        return np.zeros((np.atleast_1d(speed).size, 2, 2))

    def outputs(self, speed) -> dict:
        """The kind's own results over speed [dict of xarray.DataArray]: none."""
        return {}

    def K(self, speed: float = 0.0) -> np.ndarray:
        """Stiffness (2, 2) [N/m] at ``speed`` [rad/s] (synchronous whirl)."""
        return self.coefficients(speed)[0][0]

    def C(self, speed: float = 0.0) -> np.ndarray:
        """Damping (2, 2) [N s/m] at ``speed`` [rad/s] (synchronous whirl)."""
        return self.coefficients(speed)[1][0]

    def M(self, speed: float = 0.0) -> np.ndarray:
        """Added mass (2, 2) [kg] at ``speed`` [rad/s]."""
        return self.mass(speed)[0]

    def G(self) -> np.ndarray:
        """Gyroscopic (2, 2): zero."""
        return np.zeros((2, 2))
