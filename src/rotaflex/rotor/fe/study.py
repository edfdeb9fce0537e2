"""The FE rotor analyses from Python, with the command line's results: a :class:`Rotor` built
in a few lines goes through the same runners as ``rotaflex rotor <verb>`` (same validation,
messages, verdicts and figures), and comes back as a result object over an ``xarray.Dataset``
with ``.summary()`` and plot methods (``.plot_campbell()``, ``.plot_bode()``, ``.plot_orbit()``,
``.plot_mode(k)``; ``.plot()`` gives every figure the CLI writes).

The other verbs have the machine's names (:mod:`rotaflex.system.study`) and keywords:
:func:`static_state`, :func:`critical_speed_map`, :func:`frf`, :func:`stability`,
:func:`transient_response`.

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
from typing import Literal

from rotaflex.core.errors import InputError
from rotaflex.core.units import rad_s_to_rpm
from rotaflex.rotor.fe.model import ROTOR_KEYS, Rotor

__all__ = [
    "campbell_diagram",
    "critical_speed_map",
    "frf",
    "modes",
    "rotor_tables",
    "speed_in_rpm",
    "stability",
    "static_state",
    "transient_response",
    "unbalance_response_study",
]


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

    spec = {
        "speed_rpm": speed_in_rpm(speed_rpm, speed, "unbalance", pair=True),
        "n_speeds": n_speeds,
        "probes": [int(p) for p in probes],
        "mass": _tables(unbalance, "unbalance.mass"),
    }
    if operating_range_rpm is not None:
        spec["operating_range_rpm"] = list(operating_range_rpm)
    return run_unbalance({**rotor_tables(rotor), "unbalance": spec})


def _tables(items: Iterable, where: str) -> list[dict]:
    """Spec dataclasses or mappings as the list of TOML tables ``where`` holds (unset keys left out,
    so the table's defaults apply as in a case file)."""
    if isinstance(items, (Mapping, str)) or not isinstance(items, Iterable):
        raise InputError(where, items, "a list of tables (spec objects or mappings)")
    plain = [dataclasses.asdict(x) if dataclasses.is_dataclass(x) else dict(x) for x in items]
    return [{k: v for k, v in t.items() if v is not None} for t in plain]


#: the keys of a DOF of ``frf(inputs=, outputs=)``: a machine's ``[[frf.inputs]]`` without ``rotor``
_DOF_KEYS = ("node", "direction")


def _frf_pairs(inputs, outputs) -> list[dict]:
    """``[[frf.pair]]`` tables of every (output, input), output fastest: the machine verb's order."""
    sides = {}
    for side, items in (("inputs", inputs), ("outputs", outputs if outputs is not None else inputs)):
        dofs = _tables(items, f"frf.{side}")
        for i, d in enumerate(dofs):
            for k in d:
                if k not in _DOF_KEYS:
                    raise InputError(f"frf.{side}[{i}].{k}", d[k], "one of " + ", ".join(_DOF_KEYS))
            if "node" not in d:
                raise InputError(f"frf.{side}[{i}].node", "<missing>", "a node number")
        sides[side] = dofs
    return [
        {
            "input_node": a["node"],
            "input_direction": a.get("direction", "x"),
            "output_node": b["node"],
            "output_direction": b.get("direction", "x"),
        }
        for a in sides["inputs"]
        for b in sides["outputs"]
    ]


def frf(
    rotor: Rotor,
    *,
    inputs: Iterable[Mapping] | None = None,
    outputs: Iterable[Mapping] | None = None,
    speed_rpm: float | None = None,
    speed: float | None = None,
    frequency_hz: tuple[float, float] = (1.0, 200.0),
    n_frequencies: int = 2000,
    kind: Literal["receptance", "mobility", "accelerance"] = "receptance",
):
    """Frequency response functions at one spin speed (``rotaflex rotor frf``).

    Parameters
    ----------
    rotor : Rotor
    inputs : iterable of mapping, optional
        DOFs of the unit forces (moments): ``node``, ``direction`` (``x``, ``y``, ``theta_x``,
        ``theta_y``; default ``x``). Default: the verb's, direct x and y at the first disk node
        (mid-shaft node without disks).
    outputs : iterable of mapping, optional
        Response DOFs (default: the inputs). One ``[[frf.pair]]`` per (output, input), output
        fastest, as the machine's ``frf`` orders them.
    speed_rpm, speed : float, optional
        Spin speed [rpm] or [rad/s] (at most one; neither: at rest).
    frequency_hz : (float, float)
        Excitation frequency range [Hz].
    n_frequencies : int
    kind : {"receptance", "mobility", "accelerance"}
        H = X/F [m/N], i w H [m/(N s)] or -w^2 H [m/(N s^2)] for a force to a displacement.

    Returns
    -------
    FRFResult
        ``.dataset`` (``H_real``, ``H_imag`` per ``pair`` vs ``frequency``), ``.summary()``
        (peaks, half-power damping), ``.plot()``.

    Examples
    --------
    >>> from rotaflex.rotor.fe import Bearing, Disk, Rotor, Shaft
    >>> brg = dict(kxx=1e7, kyy=1e7, cxx=2e3, cyy=2e3)
    >>> r = Rotor(shaft=(Shaft(outer_diameter=0.05, length=0.8, elements=4),),
    ...           disk=(Disk(node=2, mass=20.0, Id=0.1, Ip=0.2),),
    ...           bearing=(Bearing(node=0, **brg), Bearing(node=4, **brg)))
    >>> h = frf(r, inputs=[{"node": 2}], frequency_hz=(1, 100), n_frequencies=100)
    >>> round(h.summary()["x2/Fx2_peak_0_frequency_hz"]["value"])  # [Hz], at rest
    66
    """
    from rotaflex.rotor.fe.case import run_frf

    table = {"frequency_hz": [float(f) for f in frequency_hz], "n_frequencies": n_frequencies, "kind": kind}
    if inputs is not None:
        table["pair"] = _frf_pairs(inputs, outputs)
    elif outputs is not None:
        raise InputError("frf.outputs", "<given without inputs>", "inputs= as well (outputs default to the inputs)")
    if speed_rpm is not None or speed is not None:
        table["speed_rpm"] = speed_in_rpm(speed_rpm, speed, "frf", pair=False)
    return run_frf({**rotor_tables(rotor), "frf": table})


def stability(
    rotor: Rotor,
    *,
    speed_rpm: float | None = None,
    speed: float | None = None,
    rated_speed_rpm: float | None = None,
    kind: Literal["centrifugal_compressor", "axial_compressor", "turbine", "pump"] = "centrifugal_compressor",
    stages: Iterable[Mapping] = (),
    location: Literal["midspan", "stages"] = "midspan",
    mean_density: float | None = None,
    n_points: int = 41,
    log_dec_min: float | None = None,
):
    """API 617 Level I and Level II stability at the maximum continuous speed
    (``rotaflex rotor stability``, docs/stability.md).

    Parameters
    ----------
    rotor : Rotor
    speed_rpm, speed : float
        Maximum continuous speed [rpm] or [rad/s] (one of them).
    rated_speed_rpm : float, optional
        Speed N of the q_A formula [rpm] (default: the MCS).
    kind : str
        The ``[stability] machine`` key: ``pump`` has no Q_A and no Level I.
    stages : iterable of Stage or mapping
        The ``[[stability.stage]]`` tables: ``power`` [W], ``diameter`` [m], ``width`` [m],
        ``density_ratio``, ``node`` or ``position`` [m] (needed for Q_A).
    location : {"midspan", "stages"}
        Where Q is applied in Level I (and Q_A in Level II).
    mean_density : float, optional
        Mean gas density [kg/m^3] (critical speed ratio map of compressors).
    n_points : int
        Points of the Level I sweep of Q.
    log_dec_min : float, optional
        Level II acceptance log decrement (default: API 617's 0.1).

    Returns
    -------
    StabilityResult
        ``.dataset`` (log decrements and frequencies [rad/s] of Level I and Level II),
        ``.summary()`` (verdicts), ``.plot()``.

    Examples
    --------
    >>> from rotaflex.rotor.fe import Bearing, Disk, Rotor, Shaft
    >>> brg = dict(kxx=1e7, kyy=1e7, cxx=2e3, cyy=2e3)
    >>> r = Rotor(shaft=(Shaft(outer_diameter=0.05, length=0.8, elements=4),),
    ...           disk=(Disk(node=2, mass=20.0, Id=0.1, Ip=0.2),),
    ...           bearing=(Bearing(node=0, **brg), Bearing(node=4, **brg)))
    >>> s = stability(r, kind="pump", speed_rpm=3000)
    >>> s.summary()["level2_verdict"]["value"], round(s.summary()["level2_log_dec"]["value"], 3)
    ('fail', 0.069)
    """
    from rotaflex.rotor.fe.case import run_stability

    table = {
        "speed_rpm": speed_in_rpm(speed_rpm, speed, "stability", pair=False),
        "machine": kind,
        "location": location,
        "n_points": n_points,
    }
    slist = _tables(stages, "stability.stage")
    if slist:
        table["stage"] = slist
    optional = {"rated_speed_rpm": rated_speed_rpm, "mean_density": mean_density, "log_dec_min": log_dec_min}
    table.update({k: v for k, v in optional.items() if v is not None})
    return run_stability({**rotor_tables(rotor), "stability": table})


def static_state(
    rotor: Rotor,
    *,
    gravity: float = 9.80665,
    gravity_direction: tuple[float, float] = (0.0, -1.0),
    loads: Iterable[Mapping] = (),
    speed_rpm: float | None = None,
    speed: float | None = None,
):
    """Static deflection, bearing reactions, shear force and bending moment under gravity and
    point loads (``rotaflex rotor static``).

    Parameters
    ----------
    rotor : Rotor
    gravity : float
        Acceleration of gravity [m/s^2] (0: point loads only).
    gravity_direction : (float, float)
        Direction of gravity (g_x, g_y) (default -y).
    loads : iterable of PointLoad or mapping
        The ``[[static.load]]`` tables: ``node`` or ``position`` [m], ``fx``, ``fy`` [N].
    speed_rpm, speed : float, optional
        Speed of the bearing coefficients [rpm] or [rad/s] (at most one; neither: 0 or the
        bearing tables' lowest speed).

    Returns
    -------
    StaticResult
        ``.dataset`` (``deflection`` [m] per node, ``reaction`` [N] per bearing, ``shear`` [N],
        ``moment`` [N m], ``stress`` [Pa] at the cuts), ``.summary()`` (bearing loads, maxima),
        ``.plot()``.

    Examples
    --------
    >>> from rotaflex.rotor.fe import Bearing, Disk, Rotor, Shaft
    >>> brg = dict(kxx=1e7, kyy=1e7, cxx=2e3, cyy=2e3)
    >>> r = Rotor(shaft=(Shaft(outer_diameter=0.05, length=0.8, elements=4),),
    ...           disk=(Disk(node=2, mass=20.0, Id=0.1, Ip=0.2),),
    ...           bearing=(Bearing(node=0, **brg), Bearing(node=4, **brg)))
    >>> s = static_state(r, loads=[{"node": 2, "fy": -100.0}])
    >>> shaft = 7810.0 * 3.141592653589793 * 0.025**2 * 0.8  # [kg], steel
    >>> half = (20.0 + shaft) * 9.80665 / 2 + 50.0  # [N]: half the weight and half the load
    >>> round(s.summary()["load_bearing[0]"]["value"], 1), round(half, 1)
    (208.2, 208.2)
    """
    from rotaflex.rotor.fe.case import run_static

    table = {
        "gravity": float(gravity),
        "gravity_direction": [float(g) for g in gravity_direction],
        "load": _tables(loads, "static.load"),
    }
    if speed_rpm is not None or speed is not None:
        table["speed_rpm"] = speed_in_rpm(speed_rpm, speed, "static", pair=False)
    return run_static({**rotor_tables(rotor), "static": table})


def critical_speed_map(
    rotor: Rotor, *, stiffness: tuple[float, float] = (1e5, 1e10), n_points: int = 40, n_modes: int = 4
):
    """Undamped critical speed map: critical speeds against the stiffness of every bearing
    (``rotaflex rotor ucs``).

    Parameters
    ----------
    rotor : Rotor
    stiffness : (float, float)
        Range of the bearings' stiffness kxx = kyy [N/m] (log spaced).
    n_points : int
        Stiffness values.
    n_modes : int
        Critical speeds per stiffness, lowest first.

    Returns
    -------
    UCSResult
        ``.dataset`` (``critical_speed`` [rad/s] vs ``stiffness`` [N/m] and ``mode``),
        ``.summary()``, ``.plot()`` (the map with the bearings' kxx, kyy).

    Examples
    --------
    >>> from rotaflex.rotor.fe import Bearing, Rotor, Shaft
    >>> r = Rotor(shaft=(Shaft(outer_diameter=0.05, length=0.8, elements=4),),
    ...           bearing=(Bearing(node=0, kxx=1e5, kyy=1e5), Bearing(node=4, kxx=1e5, kyy=1e5)))
    >>> u = critical_speed_map(r, stiffness=(1e4, 1e9), n_points=6, n_modes=2)
    >>> w = float(u.dataset["critical_speed"][0, 0])  # [rad/s] at 1e4 N/m: rigid-body bounce
    >>> bounce = (2 * 1e4 / (7810.0 * 3.141592653589793 * 0.025**2 * 0.8)) ** 0.5  # sqrt(2 k / m)
    >>> round(w / bounce, 3)  # the shaft's own bending makes the mode slightly softer
    0.999
    """
    from rotaflex.rotor.fe.case import run_ucs

    table = {"stiffness": [float(k) for k in stiffness], "n_points": n_points, "n_modes": n_modes}
    return run_ucs({**rotor_tables(rotor), "ucs": table})


def transient_response(
    rotor: Rotor,
    *,
    duration: float = 1.0,
    speed_rpm: tuple[float, float] | None = None,
    speed: tuple[float, float] | None = None,
    masses: Iterable[Mapping] = (),
    probes: Iterable[int] = (),
    n_output: int = 2001,
    method: Literal["modal", "direct"] = "modal",
    n_modes: int = 20,
    steps_per_output: int = 4,
):
    """Time response to unbalance at a constant speed or on a linear ramp
    (``rotaflex rotor transient``).

    Parameters
    ----------
    rotor : Rotor
    duration : float
        Simulated time [s].
    speed_rpm, speed : (float, float)
        Speed at the start and the end [rpm] or [rad/s] (one of them; equal: constant).
    masses : iterable of UnbalanceMass or mapping
        The ``[[transient.mass]]`` tables: ``node`` or ``position`` [m], ``magnitude`` m e
        [kg m], ``phase_deg`` [deg] (the rotor's angle at t = 0).
    probes : iterable of int
        Orbit nodes (default: the unbalance nodes).
    n_output : int
        Samples written.
    method : {"modal", "direct"}
        Integration in the undamped modal basis at the mid speed, or all coordinates (Newmark).
    n_modes : int
        Modes kept by the modal method.
    steps_per_output : int
        Newmark steps per output interval (direct method).

    Returns
    -------
    TransientResult
        ``.dataset`` (``displacement`` [m] per probe and axis, ``speed`` [rad/s] vs ``time``
        [s]), ``.summary()`` (largest radial displacement), ``.plot_orbit()``, ``.plot()``.

    Examples
    --------
    >>> from rotaflex.rotor.fe import Bearing, Disk, Rotor, Shaft
    >>> brg = dict(kxx=1e7, kyy=1e7, cxx=2e3, cyy=2e3)
    >>> r = Rotor(shaft=(Shaft(outer_diameter=0.05, length=0.8, elements=4),),
    ...           disk=(Disk(node=2, mass=20.0, Id=0.1, Ip=0.2),),
    ...           bearing=(Bearing(node=0, **brg), Bearing(node=4, **brg)))
    >>> t = transient_response(r, duration=0.1, speed_rpm=(3000, 3000), n_output=101,
    ...                        masses=[{"node": 2, "magnitude": 1e-4}])
    >>> t.dataset["displacement"].shape  # (time, probe, axis)
    (101, 1, 2)
    """
    from rotaflex.rotor.fe.case import run_transient

    table = {
        "speed_rpm": speed_in_rpm(speed_rpm, speed, "transient", pair=True),
        "duration": float(duration),
        "n_output": n_output,
        "method": method,
        "n_modes": n_modes,
        "steps_per_output": steps_per_output,
        "mass": _tables(masses, "transient.mass"),
    }
    if isinstance(probes, (str, Mapping)) or not isinstance(probes, Iterable):
        raise InputError("transient.probes", probes, "a list of node numbers")
    plist = list(probes)
    return run_transient({**rotor_tables(rotor), "transient": {**table, **({"probes": plist} if plist else {})}})
