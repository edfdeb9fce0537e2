"""Physical bounds on the speeds and frequencies an analysis of a rotor may ask for.

Refused before anything is computed, naming the key as written, because beyond them the
linear model returns numbers without meaning (issue 32: `system modal` at 1e300 rpm reported
"lowest 2.9e131 Hz"):

* **Spin speed.** A thin ring of radius r spinning at omega carries the hoop stress
  sigma = rho omega^2 r^2 (Timoshenko & Goodier, Theory of Elasticity, 3rd ed., 1970, sec. 32),
  i.e. the hoop strain rho (omega r)^2 / E. At the rim speed omega r = sqrt(E / rho) (the bar
  wave speed, ~5,100 m/s for steel) that strain is 1: the small-strain model has no meaning
  long before (steel bursts at ~500 m/s). The limit is sqrt(E / rho) / r_max with the softest
  shaft material and the largest radius of the model (shaft sections and disks; a disk given by
  mass and Ip has the radius of the solid disk with that inertia, r = sqrt(2 Ip / m)).
* **Excitation frequency.** A bending wave shorter than an element cannot be represented by
  the mesh. The shortest wave any element carries is longer than the element, and the
  fastest waves in a beam travel at the bar wave speed sqrt(E / rho); so above
  f = sqrt(E / rho) / L_min (L_min the shortest element) the mesh has no mode and the
  response is that of lumped masses, not of the shaft.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from rotaflex.core.errors import InputError
from rotaflex.core.units import rad_s_to_rpm

__all__ = ["check_frequencies", "check_speeds", "max_frequency_hz", "max_speed"]


def _wave_speed(rotor) -> float:
    """Lowest bar wave speed sqrt(E / rho) of the shaft's sections [m/s]."""
    e = rotor.elements
    return float(np.min(np.sqrt(e["E"] / e["rho"])))


def max_speed(rotor) -> float:
    """Largest spin speed [rad/s] at which the rim strain rho (omega r)^2 / E stays below 1."""
    e = rotor.elements
    r = [float(np.max(np.maximum(e["do_l"], e["do_r"]))) / 2]
    for d in rotor.disk:
        if d.outer_diameter is not None:
            r.append(d.outer_diameter / 2)
        elif d.mass and d.Ip:
            r.append(float(np.sqrt(2 * d.Ip / d.mass)))
    return _wave_speed(rotor) / max(r)


def max_frequency_hz(rotor) -> float:
    """Largest frequency [Hz] whose fastest wave is still longer than the shortest element."""
    return _wave_speed(rotor) / float(np.min(rotor.elements["L"]))


def _numbers(value) -> list[float]:
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return [float(value)]
    if isinstance(value, (tuple, list)):
        return [x for v in value for x in _numbers(v)]
    return []


def check_speeds(rotor, spec, table: str) -> None:
    """Refuse any ``*_rpm`` key of the analysis table ``table`` (a dataclass ``spec``) above
    :func:`max_speed`, naming it as written (``modal.speed_rpm``)."""
    limit = rad_s_to_rpm(max_speed(rotor))
    for f in dataclasses.fields(spec):
        value = getattr(spec, f.name)
        if f.name.endswith("_rpm") and any(not x <= limit for x in _numbers(value)):
            shown = list(value) if isinstance(value, tuple) else value
            raise InputError(
                f"{table}.{f.name}",
                shown,
                f"speeds of at most {limit:.4g} rpm (there the rim speed of the largest radius reaches the "
                "bar wave speed sqrt(E/rho): a hoop strain of 1, far beyond any material)",
            )


def check_frequencies(rotor, key: str, value) -> None:
    """Refuse frequencies [Hz] at ``key`` above :func:`max_frequency_hz`."""
    limit = max_frequency_hz(rotor)
    if any(not x <= limit for x in _numbers(value)):
        raise InputError(
            key,
            list(value) if isinstance(value, tuple) else value,
            f"frequencies of at most {limit:.4g} Hz (above, the fastest wave in the shaft is shorter than "
            "its shortest element: the mesh cannot represent the response)",
        )
