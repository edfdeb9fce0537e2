"""Finite rotations: Euler sequences, quaternions (Euler parameters), angular-velocity maps.

Conventions (one module, stated once)
-------------------------------------
* Active rotation matrices: ``r_inertial = R @ r_body``.
* Euler sequences are intrinsic and right-handed, named by axis numbers ("123", "313", ...):
  ``R = R_a(angle0) @ R_b(angle1) @ R_c(angle2)`` for sequence "abc".
* Quaternions are scalar-first ``(e0, e1, e2, e3)`` with ``R(e) = I + 2 e0 e~ + 2 e~ e~``.
* ``omega_body`` (the paper's omega*) and ``omega_inertial`` (omega) are the same angular velocity
  in body and inertial components: ``omega_inertial = R @ omega_body``.
* ``convention="paper"`` reproduces the printed 1-2-3 maps of Yun & Ren (2008), eq. 6 and 10,
  which use a left-handed second rotation; see docs/rotation.md.
"""

from rotaflex.rotation.euler import (
    SEQUENCES,
    body_rate_matrix,
    elementary_rotation,
    euler_from_matrix,
    euler_rates_from_body,
    euler_rates_from_inertial,
    inertial_rate_matrix,
    rotation_matrix,
    singularity_measure,
)
from rotaflex.rotation.kinetic import (
    kinetic_energy_body,
    kinetic_energy_inertial,
    kinetic_energy_inertial_paper,
)
from rotaflex.rotation.quaternion import (
    euler_from_quaternion,
    integrate_attitude,
    quaternion_from_euler,
    quaternion_from_matrix,
    quaternion_matrices,
    quaternion_rates_from_body,
    quaternion_rates_from_inertial,
    quaternion_to_matrix,
    rates_from_quaternion,
)

__all__ = [
    "SEQUENCES",
    "body_rate_matrix",
    "elementary_rotation",
    "euler_from_matrix",
    "euler_from_quaternion",
    "euler_rates_from_body",
    "euler_rates_from_inertial",
    "inertial_rate_matrix",
    "integrate_attitude",
    "kinetic_energy_body",
    "kinetic_energy_inertial",
    "kinetic_energy_inertial_paper",
    "quaternion_from_euler",
    "quaternion_from_matrix",
    "quaternion_matrices",
    "quaternion_rates_from_body",
    "quaternion_rates_from_inertial",
    "quaternion_to_matrix",
    "rates_from_quaternion",
    "rotation_matrix",
    "singularity_measure",
]
