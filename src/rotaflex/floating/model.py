"""Case description as frozen dataclasses (loadable from TOML with ``from_mapping``)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np

from rotaflex.core.config import param
from rotaflex.core.errors import InputError

Vec3 = tuple[float, float, float]

#: load time profiles; see kernels.profile_value
Profile = Literal["constant", "step", "ramp", "bang-bang", "sinusoid", "pulse"]


@dataclass(frozen=True)
class Load:
    """A force or torque with a time profile ``s(t)``: value = ``s(t) * vector``.

    Profiles: ``constant`` (1), ``step`` (1 from ``start``), ``ramp`` (0 -> 1 over ``duration``),
    ``bang-bang`` (+1 for the first half of ``duration``, -1 for the second: a rest-to-rest slew),
    ``sinusoid`` (``sin(2 pi frequency (t - start) + phase)`` from ``start``, for ``duration`` if
    > 0), ``pulse`` (1 for ``start <= t < start + duration``).

    Constructed directly, only the cross-field rules are checked (errors name ``loads.<field>``:
    the index is not known here); :func:`load_from`, which ``run`` and case files use, checks
    every field and names ``loads[i].<field>``.
    """

    kind: Literal["force", "torque"] = param("force", doc="force [N] or torque [N m]")
    vector: Vec3 = param((0.0, 0.0, 0.0), doc="amplitude vector [N] or [N m]")
    point: Vec3 = param((0.0, 0.0, 0.0), unit="m", doc="material point (undeformed, body frame)")
    frame: Literal["body", "inertial", "material"] = param(
        "body",
        doc="axes of `vector`: body = follows the floating frame, inertial = fixed direction, "
        "material = follows the deformed body at the point (turns with the section rotation)",
    )
    profile: Profile = param("constant")
    start: float = param(0.0, unit="s", ge=0.0)
    duration: float = param(0.0, unit="s", ge=0.0)
    frequency: float = param(0.0, unit="Hz", ge=0.0)
    phase: float = param(0.0, unit="rad")

    def __post_init__(self):
        if self.profile in ("ramp", "bang-bang", "pulse") and self.duration <= 0.0:
            raise InputError("duration", self.duration, f"a duration > 0 s for a {self.profile}")
        if self.profile == "sinusoid" and self.frequency <= 0.0:
            raise InputError("frequency", self.frequency, "a frequency > 0 Hz for a sinusoid")

    def breakpoints(self) -> list[float]:
        t0, d = self.start, self.duration
        return {
            "constant": [],
            "step": [t0],
            "ramp": [t0, t0 + d],
            "bang-bang": [t0, t0 + 0.5 * d, t0 + d],
            "sinusoid": [t0] + ([t0 + d] if d > 0 else []),
            "pulse": [t0, t0 + d],
        }[self.profile]


def load_from(data, where: str) -> Load:
    """A :class:`Load` from a ``Load`` or a mapping with its keys (a ``[[loads]]`` table), checked
    like a case file's load: types, ranges and the cross-field rules.

    Parameters
    ----------
    data : Load or mapping
    where : str
        Path of the load in error messages, e.g. ``"loads[2]"``.

    Raises
    ------
    InputError
        Naming ``where.field`` (``loads[2].duration``), the value and what is allowed.
    """
    from dataclasses import asdict

    from rotaflex.core.config import from_mapping

    if isinstance(data, Load):
        data = {k: _python(v) for k, v in asdict(data).items()}
    try:
        return from_mapping(Load, data, where)
    except InputError as exc:
        if exc.field.startswith("loads."):  # raised by Load's own cross-field checks
            raise InputError(f"{where}.{exc.field[len('loads.') :]}", exc.value, exc.allowed) from None
        raise


def _python(v):
    """NumPy scalars and arrays as Python numbers and lists (as a TOML table would hold them)."""
    if isinstance(v, np.generic):
        return v.item()
    if isinstance(v, (np.ndarray, list, tuple)):
        return [_python(x) for x in v]
    return v


@dataclass(frozen=True)
class Initial:
    """Initial state: inertial position and attitude, body-frame velocities, modal state."""

    position: Vec3 = param((0.0, 0.0, 0.0), unit="m")
    quaternion: tuple[float, float, float, float] = param((1.0, 0.0, 0.0, 0.0), doc="scalar-first unit quaternion")
    velocity: Vec3 = param((0.0, 0.0, 0.0), unit="m/s", doc="V_o in body axes")
    angular_velocity: Vec3 = param((0.0, 0.0, 0.0), unit="rad/s", doc="w in body axes")
    modal_displacement: tuple[float, ...] = param((), doc="q(0) (default zeros)")
    modal_velocity: tuple[float, ...] = param((), doc="p(0) (default zeros)")

    def __post_init__(self):
        nq = float(np.linalg.norm(self.quaternion))
        if abs(nq - 1.0) > 1e-6:
            raise InputError("initial.quaternion", list(self.quaternion), "a unit quaternion (norm 1)")


@dataclass(frozen=True)
class Prescribed:
    """Prescribed rigid rotation about a body-fixed axis through the body origin (the origin is
    held; only the elastic coordinates are integrated).

    ``profile``: ``spin-up`` (Kane-Ryan-Banerjee: ``Omega(t) = rate/T (t - T/(2 pi) sin(2 pi
    t/T))`` for ``t < T = spin_up_time``, then ``rate``); ``bang-bang`` (rest-to-rest slew by
    ``angle`` in ``duration`` from ``start``: constant acceleration ``4 angle / duration^2`` for
    the first half, the same deceleration for the second); ``versine`` (cycloidal rest-to-rest
    slew ``angle (s - sin(2 pi s) / (2 pi))``, ``s = (t - start) / duration``: smooth
    acceleration, a full sine period).
    """

    axis: Vec3 = param((0.0, 0.0, 1.0), doc="rotation axis (body frame, normalised)")
    rate: float = param(6.0, unit="rad/s", doc="final spin rate (spin-up)")
    spin_up_time: float = param(15.0, unit="s", gt=0.0, doc="spin-up time T (spin-up)")
    profile: Literal["spin-up", "bang-bang", "versine"] = param("spin-up")
    angle: float = param(0.0, unit="rad", doc="slew angle (bang-bang, versine)")
    duration: float = param(1.0, unit="s", gt=0.0, doc="slew duration (bang-bang, versine)")
    start: float = param(0.0, unit="s", ge=0.0, doc="slew start time (bang-bang, versine)")

    def __post_init__(self):
        if float(np.linalg.norm(self.axis)) == 0.0:
            raise InputError("prescribed.axis", list(self.axis), "a non-zero vector")

    def packed(self) -> np.ndarray:
        """``(axis (3, unit), a, b, kind, start)`` for :func:`rotaflex.floating.kernels.motion_profile`."""
        ax = np.asarray(self.axis, dtype=float)
        kind = ("spin-up", "bang-bang", "versine").index(self.profile)
        a, b = (self.rate, self.spin_up_time) if kind == 0 else (self.angle, self.duration)
        return np.array([*(ax / np.linalg.norm(ax)), a, b, float(kind), self.start if kind else 0.0])

    def breakpoints(self) -> list[float]:
        """Times [s] where the angular acceleration jumps (the integrator steps onto them)."""
        if self.profile == "spin-up":
            return [self.spin_up_time]
        t0, d = self.start, self.duration
        return [t0, t0 + 0.5 * d, t0 + d] if self.profile == "bang-bang" else [t0, t0 + d]


@dataclass(frozen=True)
class Settings:
    """Solver settings."""

    method: Literal["full", "perturbation", "both"] = param(
        "both", doc="full nonlinear, perturbation (zero + first order), or both"
    )
    t_end: float = param(10.0, unit="s", gt=0.0)
    dt_out: float = param(0.01, unit="s", gt=0.0, doc="output interval")
    rtol: float = param(1e-7, gt=0.0, lt=1.0)
    atol: float = param(1e-9, gt=0.0)
    max_steps: int = param(2_000_000, gt=0)
    geometric_stiffness: bool | None = param(None, doc="centrifugal stiffening; default: on when the body provides it")
    kinematics: Literal["linear", "inextensible"] = param(
        "linear",
        doc="linear floating-frame deflection (+ geometric stiffness), or the exact inextensible "
        "kinematics of a planar cantilever beam under [prescribed] motion (no loads; contains "
        "the stiffening, so leave geometric_stiffness unset)",
    )

    def __post_init__(self):
        if self.dt_out > self.t_end:
            raise InputError("solver.dt_out", self.dt_out, f"an interval <= t_end = {self.t_end:g} s")
