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
    from rotaflex.core.units import deg_to_rad
    from rotaflex.gear.pair.geometry import GearGeometry

    return GearGeometry(
        module=MODULE,
        teeth=TEETH,
        face_width=FACE_WIDTH,
        pressure_angle=deg_to_rad(PRESSURE_ANGLE_DEG),
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


def pair_tables(verb: str) -> dict:
    """The paper's pair as a drawing pair: the ``[pinion]``/``[wheel]`` tables (explicit radii,
    the paper's steel, the disk inertia as the blank's) and ``verb``'s ``[operation]`` defaults
    (tau_0 on the pinion, the driver; the speed of the 4000 rpm case), in the verb's spelling.

    The ``pair = "lee_jang"`` preset of every gear verb
    (:func:`rotaflex.gear.cases.pair_config.with_pair_preset`).

    Parameters
    ----------
    verb : {"simulate", "static", "steady"}
        ``simulate`` gives the speed as ``driver_speed_rpm`` and the torque on the driver (its
        default ``torque_on``); ``steady`` as the pinion's ``speed_rpm`` with ``torque_on =
        "pinion"``; ``static`` the torque alone (its design load).
    """

    def gear() -> dict:  # one fresh mapping per gear (callers may change them)
        return {
            "teeth": TEETH,
            "module": MODULE,
            "face_width": FACE_WIDTH,
            "pressure_angle_deg": PRESSURE_ANGLE_DEG,
            "tip_radius": TIP_RADIUS,
            "root_radius": ROOT_RADIUS,
            "material": {"youngs_modulus": YOUNGS_MODULUS, "poisson_ratio": POISSON_RATIO, "density": DENSITY},
            "blank": {"inertia": DISK_INERTIA},
        }

    operation = {
        "simulate": {"torque": TORQUE, "driver_speed_rpm": SPEED_RPM},
        "static": {"torque": TORQUE, "torque_on": "pinion"},
        "steady": {"torque": TORQUE, "torque_on": "pinion", "speed_rpm": SPEED_RPM},
    }[verb]
    return {"pinion": gear(), "wheel": gear(), "operation": operation}
