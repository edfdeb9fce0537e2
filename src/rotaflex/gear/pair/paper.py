"""The gear pair of the paper (Lee & Jang, section 4): the one definition of its data.

Two identical 28-tooth spur gears, module 3.175 mm (8 diametral pitch), 20 deg pressure angle,
face width 6.35 mm, tip radius 47.625 mm, root radius 40.48 mm, steel (E = 210 GPa,
nu = 0.3, rho = 7800 kg/m^3), disk polar inertia 2.965e-4 kg m^2, tau_0 = 22.25 N m, running at
4000 or 20000 rpm. The configuration defaults (:mod:`rotaflex.gear.cases.simulate_config`), the reproduction,
the sweep figures and the benchmarks import these values from here.
"""

from __future__ import annotations

MODULE = 3.175e-3  # [m]
TEETH = 28
PRESSURE_ANGLE_DEG = 20.0  # [deg]
FACE_WIDTH = 6.35e-3  # [m]
TIP_RADIUS = 0.047625  # [m]
ROOT_RADIUS = 0.04048  # [m]
YOUNGS_MODULUS = 210e9  # [Pa]
POISSON_RATIO = 0.3
DENSITY = 7800.0  # [kg/m^3]
DISK_INERTIA = 2.965e-4  # [kg m^2]
TORQUE = 22.25  # tau_0 [N m]
SPEED_RPM = 4000.0  # [rpm] (also 20000)


def geometry():
    """The paper's gear (:class:`rotaflex.gear.pair.geometry.GearGeometry`)."""
    from rotaflex.gear.pair.geometry import GearGeometry

    return GearGeometry(
        module=MODULE,
        teeth=TEETH,
        face_width=FACE_WIDTH,
        pressure_angle_deg=PRESSURE_ANGLE_DEG,
        tip_radius=TIP_RADIUS,
        root_radius=ROOT_RADIUS,
    )


def material() -> dict:
    """Material keywords of :func:`rotaflex.gear.models.fe_pair.build_model` (SI)."""
    return {
        "youngs_modulus": YOUNGS_MODULUS,
        "poisson_ratio": POISSON_RATIO,
        "density": DENSITY,
        "inertia": (DISK_INERTIA, DISK_INERTIA),
    }
