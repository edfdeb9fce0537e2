"""Rotor models as frozen data, validated from TOML tables.

Two kinds of case share these pieces:

* ``RotorModel``: a disk spinning at a prescribed rate ``spin_speed`` about its polar axis, free to
  translate (U, V) and tilt; the paper's rotor-disk problem (eq. 31-38).
* ``FreeBody``: a free rigid body with arbitrary principal inertias, initial attitude and body
  rates, and an optional constant torque; every parameterisation can simulate it, so formulations
  can be checked against each other.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

from rotaflex.core.config import param
from rotaflex.core.errors import InputError
from rotaflex.rotation.euler import SEQUENCES

Parameterisation = Literal["euler", "quaternion_spherical", "quaternion"]


#: relative slack of the triangle inequality: a thin disk (I_polar = 2 I_diametral) typed in
#: decimals must pass
_TRIANGLE_RTOL = 1e-9


def check_principal_inertias(field: str, value: object, inertias) -> None:
    """Refuse principal moments of inertia that no rigid body has.

    For any mass distribution ``I_a + I_b >= I_c`` for every ordering (e.g. ``I_x + I_y =
    integral (x^2 + y^2 + 2 z^2) dm >= I_z``); equality is a plane lamina. A body breaking it
    would have negative mass somewhere, and the equations of motion would be meaningless.

    Parameters
    ----------
    field, value : str, object
        The config key and the value as typed, for the message.
    inertias : (3,) float
        Principal moments [kg m^2].
    """
    a, b, c = sorted(float(x) for x in inertias)
    if a + b < c * (1.0 - _TRIANGLE_RTOL):
        raise InputError(
            field,
            value,
            f"principal inertias of a rigid body: each at most the sum of the other two (here {a:.6g} + "
            f"{b:.6g} < {c:.6g})",
        )


@dataclass(frozen=True)
class Disk:
    """Rigid disk: mass [kg] and principal moments of inertia [kg m^2] about the body axes.

    ``inertia`` (body x, y, z) overrides ``polar_inertia``/``diametral_inertia``; without it the
    polar moment sits on the body axis of the spin rotation.
    """

    mass: float = param(1.0, unit="kg", gt=0, doc="disk mass")
    polar_inertia: float = param(2.0, unit="kg m^2", gt=0, doc="moment of inertia about the spin axis")
    diametral_inertia: float = param(1.0, unit="kg m^2", gt=0, doc="moment of inertia about a diameter")
    inertia: tuple[float, float, float] | None = param(
        None, unit="kg m^2", gt=0, doc="principal inertias about body x, y, z (overrides polar/diametral)"
    )


@dataclass(frozen=True)
class Support:
    """Isotropic linear support: translational [N/m] and tilt [N m/rad] stiffness.

    The tilt potential is ``k_tilt (1 - n . n0)`` with ``n`` the disk's polar axis and ``n0`` its
    nominal direction, i.e. ``1/2 k_tilt beta^2`` for a small tilt angle ``beta`` whatever the
    parameterisation.
    """

    stiffness: float = param(0.0, unit="N/m", ge=0, doc="translational support stiffness")
    tilt_stiffness: float = param(0.0, unit="N m/rad", ge=0, doc="tilt support stiffness")


@dataclass(frozen=True)
class Formulation:
    """How the disk's rotation is parameterised and which energy generates the equations.

    Attributes
    ----------
    parameterisation : {"euler", "quaternion_spherical", "quaternion"}
        Euler angles of ``sequence``; the paper's spherical-coordinate quaternion (eq. 21-23);
        or (free body only) a unit quaternion with Newton-Euler equations.
    sequence : str
        Euler sequence, e.g. "123", "313".
    convention : {"right-handed", "paper"}
        "paper" uses the printed (left-handed second rotation) 1-2-3 maps of eq. 6/10.
    energy : {"body", "inertial_paper"}
        "body": 1/2 w*^T J w* (the kinetic energy). "inertial_paper": the paper's
        1/2 w^T J w with inertial components and body inertia (eq. 24b, 25b, 29).
    expansion : {"nonlinear", "second_order", "paper_truncated"}
        Full energy; its exact second-order Taylor expansion in the tilt coordinates and rates
        (linear equations); or that expansion without the pure coordinate-squared kinetic terms,
        as in the paper's eq. 27.
    spin_angle : int or None
        Index (0, 1, 2) of the Euler angle prescribed as ``spin_speed * t``; default 0 for
        Tait-Bryan and 2 for proper Euler sequences (the paper's choices for 1-2-3 and 3-1-3).
    """

    parameterisation: Parameterisation = param("euler", doc="rotation coordinates")
    sequence: str = param("123", doc="Euler sequence, e.g. 123 or 313")
    convention: Literal["right-handed", "paper"] = param("right-handed", doc="'paper': the printed 1-2-3 maps")
    energy: Literal["body", "inertial_paper"] = param("body", doc="kinetic energy used (see docs/rotor.md)")
    expansion: Literal["nonlinear", "second_order", "paper_truncated"] = param(
        "nonlinear", doc="full equations or their second-order expansion"
    )
    spin_angle: int | None = param(None, ge=0, le=2, doc="index of the prescribed Euler angle (default by sequence)")

    def __post_init__(self):
        if self.sequence not in SEQUENCES:
            raise InputError("formulation.sequence", self.sequence, "one of " + ", ".join(SEQUENCES))
        if self.convention == "paper" and self.sequence != "123":
            raise InputError(
                "formulation.convention",
                "paper",
                "'right-handed' for sequences other than 123 (the paper prints only 1-2-3 differently)",
            )

    @property
    def spin_index(self) -> int:
        if self.spin_angle is not None:
            return self.spin_angle
        return 2 if self.sequence[0] == self.sequence[2] else 0


@dataclass(frozen=True)
class Motion:
    """Prescribed spin and initial state of the tilt/translation coordinates.

    ``initial_tilt`` and ``initial_tilt_rate`` are the two free rotation coordinates in the
    formulation's order (Euler: the non-spin angles by increasing index; spherical quaternion:
    eps_theta, eps_psi) [rad], [rad/s].
    """

    spin_speed: float = param(10.0, unit="rad/s", doc="prescribed spin rate")
    initial_spin_angle: float = param(0.0, unit="rad", doc="spin angle at t = 0")
    initial_tilt: tuple[float, float] = param((0.0, 0.0), unit="rad", doc="the two free rotation coordinates")
    initial_tilt_rate: tuple[float, float] = param((1.0, 1.0), unit="rad/s", doc="their rates")
    initial_displacement: tuple[float, float] = param((0.0, 0.0), unit="m", doc="U, V")
    initial_velocity: tuple[float, float] = param((0.0, 0.0), unit="m/s", doc="dU/dt, dV/dt")


@dataclass(frozen=True)
class Solver:
    """Time integration with ``scipy.integrate.solve_ivp``."""

    t_end: float = param(10.0, unit="s", gt=0, doc="end of the simulated interval")
    method: Literal["DOP853", "RK45", "Radau", "BDF", "LSODA"] = param("DOP853", doc="scipy solve_ivp method")
    rtol: float = param(1e-9, gt=0, lt=1, doc="relative tolerance")
    atol: float = param(1e-12, gt=0, doc="absolute tolerance")
    n_output: int = param(1001, ge=2, le=1_000_000, doc="output samples, evenly spaced over [0, t_end]")
    max_steps: int = param(
        2_000_000,
        ge=1,
        le=10**9,
        doc="step budget: runs estimated to need more steps are refused, runs that take more are stopped",
    )
    singular_tolerance: float = param(
        1e-8, gt=0, lt=1, doc="relative det(M) below which the mass matrix counts as singular"
    )


@dataclass(frozen=True)
class RotorModel:
    """The rotor-disk case (paper section 3.3)."""

    disk: Disk = param(Disk())
    support: Support = param(Support())
    formulation: Formulation = param(Formulation())
    motion: Motion = param(Motion())
    solver: Solver = param(Solver())

    def __post_init__(self):
        d = self.disk
        if d.inertia is not None:
            check_principal_inertias("disk.inertia", list(d.inertia), d.inertia)
        elif d.polar_inertia > 2.0 * d.diametral_inertia * (1.0 + _TRIANGLE_RTOL):
            raise InputError(
                "disk.polar_inertia",
                d.polar_inertia,
                f"a value at most 2 x disk.diametral_inertia = {2.0 * d.diametral_inertia:.6g} kg m^2 "
                "(I_polar <= 2 I_diametral for any rigid disk; equality is a thin disk)",
            )
        if self.formulation.parameterisation == "quaternion":
            raise InputError(
                "formulation.parameterisation",
                "quaternion",
                "'euler' or 'quaternion_spherical' for a rotor disk with prescribed spin "
                "('quaternion' is for [free_body] cases)",
            )


@dataclass(frozen=True)
class FreeBody:
    """A free rigid body.

    Attributes
    ----------
    inertia : tuple of 3 float
        Principal moments about body x, y and z [kg m^2].
    initial_angles : tuple of 3 float
        Euler angles of ``formulation.sequence`` [rad] giving the initial attitude.
    initial_body_rate : tuple of 3 float
        Body-frame angular velocity at t = 0 [rad/s].
    torque : tuple of 3 float
        Constant applied torque [N m] in the frame ``torque_frame``.
    """

    inertia: tuple[float, float, float] = param((1.0, 1.0, 2.0), unit="kg m^2", gt=0, doc="principal inertias")
    initial_angles: tuple[float, float, float] = param((0.1, 0.4, 0.2), unit="rad", doc="initial Euler angles")
    initial_body_rate: tuple[float, float, float] = param((0.3, 0.0, 5.0), unit="rad/s", doc="body-frame rates")
    torque: tuple[float, float, float] = param((0.0, 0.0, 0.0), unit="N m", doc="constant applied torque")
    torque_frame: Literal["body", "inertial"] = param("body", doc="frame of the torque components")
    formulation: Formulation = param(Formulation(sequence="123"))
    solver: Solver = param(Solver())

    def __post_init__(self):
        check_principal_inertias("free_body.inertia", list(self.inertia), self.inertia)
        f = self.formulation
        if f.parameterisation == "quaternion_spherical":
            raise InputError(
                "free_body.formulation.parameterisation",
                f.parameterisation,
                "'euler' or 'quaternion' (the spherical quaternion needs a prescribed spin)",
            )
        if f.energy != "body" or f.expansion != "nonlinear" or f.convention != "right-handed":
            raise InputError(
                "free_body.formulation",
                f"{f.energy}/{f.expansion}/{f.convention}",
                "energy='body', expansion='nonlinear', convention='right-handed' for a free body",
            )
