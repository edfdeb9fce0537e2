"""Linear bearing or seal: full 2x2 stiffness and damping, constant or tabulated vs speed."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from rotaflex.core.errors import InputError
from rotaflex.core.units import rad_s_to_rpm
from rotaflex.rotor.fe.bearings.fluid_film import fluid_film_table

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

    @classmethod
    def constant(
        cls, kxx=0.0, kyy=0.0, kxy=0.0, kyx=0.0, cxx=0.0, cyy=0.0, cxy=0.0, cyx=0.0, name: str = "bearing"
    ) -> BearingElement:
        """Speed-independent coefficients [N/m, N s/m]."""
        return cls(np.array([[[kxx, kxy], [kyx, kyy]]], float), np.array([[[cxx, cxy], [cyx, cyy]]], float), None, name)

    def coefficients(self, speed) -> tuple[np.ndarray, np.ndarray]:
        """Stiffness and damping (n_speed, 2, 2) at the spin speeds ``speed`` [rad/s]."""
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
                round(rad_s_to_rpm(s), 6),
                f"requested speeds within the coefficient table [{rad_s_to_rpm(lo):g}, {rad_s_to_rpm(hi):g}] rpm",
            )
        flat_k = self.k.reshape(len(self.speeds), 4)
        flat_c = self.c.reshape(len(self.speeds), 4)
        k = np.stack([np.interp(speed, self.speeds, flat_k[:, j]) for j in range(4)], -1).reshape(-1, 2, 2)
        c = np.stack([np.interp(speed, self.speeds, flat_c[:, j]) for j in range(4)], -1).reshape(-1, 2, 2)
        return k, c

    def M(self) -> np.ndarray:
        """Mass (2, 2) on the translations: zero."""
        return np.zeros((2, 2))

    def K(self, speed: float = 0.0) -> np.ndarray:
        """Stiffness (2, 2) [N/m] at ``speed`` [rad/s]."""
        return self.coefficients(speed)[0][0]

    def C(self, speed: float = 0.0) -> np.ndarray:
        """Damping (2, 2) [N s/m] at ``speed`` [rad/s]."""
        return self.coefficients(speed)[1][0]

    def G(self) -> np.ndarray:
        """Gyroscopic (2, 2): zero."""
        return np.zeros((2, 2))

    @classmethod
    def from_fluid_film(cls, bearing, where: str = "bearing") -> BearingElement:
        """Speed-tabulated element of a ``[bearing.NAME.fluid_film]`` table (coefficient keys refused).

        ``bearing`` is a :class:`rotaflex.rotor.fe.model.Bearing` whose ``fluid_film`` is set.
        """
        for key in COEFFICIENTS:
            if any(getattr(bearing, key)):
                raise InputError(f"{where}.{key}", list(getattr(bearing, key)), "no coefficients with fluid_film")
        if bearing.speed_rpm is not None:
            raise InputError(f"{where}.speed_rpm", list(bearing.speed_rpm), "fluid_film.speed_rpm instead")
        table = fluid_film_table(bearing.fluid_film, f"{where}.fluid_film")
        return cls(table.k, table.c, table.speed, f"{where}.fluid_film", table)
