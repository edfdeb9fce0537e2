"""The FE rotor analyses from Python, with the command line's results: a :class:`Rotor` built
in a few lines goes through the same runners as ``rotaflex rotor <verb>`` (same validation,
messages, verdicts and figures), and comes back as a result object over an ``xarray.Dataset``
with ``.summary()`` and plot methods (``.plot_campbell()``, ``.plot_bode()``, ``.plot_orbit()``,
``.plot_mode(k)``; ``.plot()`` gives every figure the CLI writes).

Speeds are explicit in their names: ``speed_rpm=`` [rpm] or ``speed=`` [rad/s], one of them,
for one speed or a ``(start, stop)`` range; a bare number never changes its unit by path.

Examples
--------
>>> from rotaflex.rotor.fe import Bearing, Disk, Rotor, Shaft
>>> from rotaflex.rotor.fe.study import campbell_diagram
>>> rotor = Rotor(
...     shaft=(Shaft(outer_diameter=0.05, length=1.5, elements=6),),
...     disk=(Disk(position=0.5, width=0.07, outer_diameter=0.28, inner_diameter=0.05),),
...     bearing=(Bearing(node=0, kxx=1e6, kyy=1e6, cxx=3e3, cyy=3e3),
...              Bearing(position=1.5, kxx=1e6, kyy=1e6, cxx=3e3, cyy=3e3)),
... )
>>> c = campbell_diagram(rotor, speed_rpm=(0, 4000), n_speeds=20, n_modes=4)
>>> c.status, sorted({cr["harmonic"] for cr in c.critical})
('success', [1.0])
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable, Mapping

from rotaflex.core.errors import InputError
from rotaflex.core.units import rad_s_to_rpm
from rotaflex.rotor.fe.model import ROTOR_KEYS, Rotor

__all__ = ["campbell_diagram", "modes", "rotor_tables", "speed_in_rpm", "unbalance_response_study"]


def rotor_tables(rotor: Rotor, where: str = "rotor") -> dict:
    """The rotor as the case file's tables (the runners read those: one validation path).

    Parameters
    ----------
    rotor : Rotor
    where : str
        The argument's name in messages when ``rotor`` is not a :class:`Rotor`.

    Returns
    -------
    dict
        ``shaft``, ``disk``, ``point_mass``, ``bearing``, ``material``, ``free``, ``max_dof``
        as plain data (SI), as :meth:`Rotor.from_mapping` reads them.
    """
    if not isinstance(rotor, Rotor):
        raise InputError(where, type(rotor).__name__, "a rotaflex.rotor.fe.Rotor")
    plain = dataclasses.asdict(rotor)
    return {k: plain[k] for k in ROTOR_KEYS}


def speed_in_rpm(speed_rpm, speed, what: str, pair: bool, name: str = "speed"):
    """The speed(s) in rpm from exactly one of ``speed_rpm`` [rpm] and ``speed`` [rad/s].

    Parameters
    ----------
    speed_rpm, speed : float or (float, float) or None
        The arguments as the user passed them; exactly one is not None.
    what : str
        The analysis table the speed belongs to (``campbell``), for messages.
    pair : bool
        A ``(start, stop)`` range (True) or one speed (False).
    name : str
        The argument's stem: ``speed`` for ``speed_rpm=``/``speed=``, ``operating_speed`` for
        ``operating_speed_rpm=``/``operating_speed=``.

    Returns
    -------
    float or list of float
        The speed(s) [rpm].
    """
    if (speed_rpm is None) == (speed is None):
        raise InputError(
            f"{what}.{name}_rpm",
            "<both>" if speed_rpm is not None else "<missing>",
            f"one of {name}_rpm= [rpm] or {name}= [rad/s]",
        )
    value = speed_rpm if speed is None else speed
    key = f"{what}.{f'{name}_rpm' if speed is None else name}"
    if pair:
        if isinstance(value, (int, float)) or len(value) != 2:
            raise InputError(key, value, "a (start, stop) pair")
        out = [float(v) for v in value]
    else:
        if not isinstance(value, (int, float)):
            raise InputError(key, value, "one speed")
        out = float(value)
    return out if speed is None else (rad_s_to_rpm(out) if not pair else [rad_s_to_rpm(v) for v in out])


def modes(rotor: Rotor, *, speed_rpm: float | None = None, speed: float | None = None, n_modes: int = 8):
    """Damped modes at one spin speed (``rotaflex rotor modal``).

    Parameters
    ----------
    rotor : Rotor
    speed_rpm, speed : float
        The spin speed [rpm] or [rad/s] (one of them).
    n_modes : int
        Modes reported, lowest damped frequency first.

    Returns
    -------
    ModalResult
        ``.dataset`` (frequencies [rad/s], damping ratio, log decrement, whirl, shapes),
        ``.summary()``, ``.plot_mode(k)``, ``.plot_orbits()``, ``.plot()``.
    """
    from rotaflex.rotor.fe.case import run_modal

    rpm = speed_in_rpm(speed_rpm, speed, "modal", pair=False)
    return run_modal({**rotor_tables(rotor), "modal": {"speed_rpm": rpm, "n_modes": n_modes}})


def campbell_diagram(
    rotor: Rotor,
    *,
    speed_rpm: tuple[float, float] | None = None,
    speed: tuple[float, float] | None = None,
    n_speeds: int = 50,
    n_modes: int = 8,
    harmonics: Iterable[float] = (1.0,),
    operating_range_rpm: tuple[float, float] | None = None,
    frequency_limit_hz: float | None = None,
):
    """Campbell diagram with tracked modes, critical speeds and stability (``rotaflex rotor campbell``).

    Parameters
    ----------
    rotor : Rotor
    speed_rpm, speed : (float, float)
        Speed range [rpm] or [rad/s] (one of them).
    n_speeds, n_modes : int
    harmonics : iterable of float
        Excitation orders whose crossings are critical speeds (0.5 for 0.5X).
    operating_range_rpm : (float, float), optional
        Shaded, and the stability verdict over it in the summary.
    frequency_limit_hz : float, optional
        Figures: modes up to this frequency.

    Returns
    -------
    CampbellResult
        ``.critical`` (speed_rpm, frequency_hz, harmonic, whirl, mode), ``.summary()``,
        ``.plot_campbell()``, ``.plot()``.
    """
    from rotaflex.rotor.fe.case import run_campbell

    spec = {
        "speed_rpm": speed_in_rpm(speed_rpm, speed, "campbell", pair=True),
        "n_speeds": n_speeds,
        "n_modes": n_modes,
        "harmonics": [float(h) for h in harmonics],
    }
    if operating_range_rpm is not None:
        spec["operating_range_rpm"] = list(operating_range_rpm)
    if frequency_limit_hz is not None:
        spec["frequency_limit_hz"] = frequency_limit_hz
    return run_campbell({**rotor_tables(rotor), "campbell": spec})


def unbalance_response_study(
    rotor: Rotor,
    unbalance: Iterable[Mapping],
    *,
    speed_rpm: tuple[float, float] | None = None,
    speed: tuple[float, float] | None = None,
    n_speeds: int = 500,
    probes: Iterable[int] = (),
    operating_range_rpm: tuple[float, float] | None = None,
):
    """Unbalance response with API 684 verdicts (``rotaflex rotor unbalance``).

    Parameters
    ----------
    rotor : Rotor
    unbalance : iterable of mapping
        Each as a ``[[unbalance.mass]]`` table: ``magnitude`` [kg m], ``node`` or ``position``
        [m], ``phase_deg`` [deg] (or :class:`~rotaflex.rotor.fe.case_config.UnbalanceMass`).
    speed_rpm, speed : (float, float)
        Speed range [rpm] or [rad/s] (one of them).
    n_speeds : int
    probes : iterable of int
        Probe nodes (default: the unbalance nodes); every probe counts for the peaks.
    operating_range_rpm : (float, float), optional
        Separation margins, vibration limit and stability over it: ``summary()["verdict"]``.

    Returns
    -------
    UnbalanceResult
        ``.summary()``, ``.plot_bode()``, ``.plot_orbit()``, ``.plot()``.
    """
    from rotaflex.rotor.fe.case import run_unbalance

    masses = [dataclasses.asdict(u) if dataclasses.is_dataclass(u) else dict(u) for u in unbalance]
    spec = {
        "speed_rpm": speed_in_rpm(speed_rpm, speed, "unbalance", pair=True),
        "n_speeds": n_speeds,
        "probes": [int(p) for p in probes],
        "mass": [{k: v for k, v in m.items() if v is not None} for m in masses],
    }
    if operating_range_rpm is not None:
        spec["operating_range_rpm"] = list(operating_range_rpm)
    return run_unbalance({**rotor_tables(rotor), "unbalance": spec})
