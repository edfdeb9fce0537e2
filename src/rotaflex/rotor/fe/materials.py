"""Named shaft and disk materials (SI): Young's modulus, shear modulus, density.

``steel`` uses the values of Friswell, Penny, Garvey & Lees (2010), *Dynamics of Rotating
Machines*, Example 5.9.1 (E = 211 GPa, G = 81.2 GPa, rho = 7810 kg/m^3).
"""

from __future__ import annotations

from dataclasses import dataclass

from rotaflex.core.config import param
from rotaflex.core.errors import InputError


@dataclass(frozen=True)
class Material:
    """Isotropic linear-elastic material.

    Parameters
    ----------
    E : float
        Young's modulus [Pa].
    G : float
        Shear modulus [Pa].
    rho : float
        Density [kg/m^3].
    """

    E: float = param(unit="Pa", gt=0, doc="Young's modulus")
    G: float = param(unit="Pa", gt=0, doc="shear modulus")
    rho: float = param(unit="kg/m^3", gt=0, doc="density")

    @property
    def nu(self) -> float:
        """Poisson's ratio E / (2 G) - 1 [-]."""
        return self.E / (2.0 * self.G) - 1.0


MATERIALS: dict[str, Material] = {
    "steel": Material(E=211e9, G=81.2e9, rho=7810.0),
    "aluminium": Material(E=70e9, G=26.3e9, rho=2700.0),
    "titanium": Material(E=114e9, G=44e9, rho=4430.0),
}


def material(name: str, where: str = "material", extra: dict[str, Material] | None = None) -> Material:
    """The material called ``name`` (user-defined ``extra`` first, then :data:`MATERIALS`)."""
    table = {**MATERIALS, **(extra or {})}
    if name not in table:
        raise InputError(where, name, "one of " + ", ".join(sorted(table)) + " or a [material.<name>] table")
    return table[name]
