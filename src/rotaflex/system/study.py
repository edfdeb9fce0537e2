"""Geared and coupled machines from Python, with the command line's results: rotors built as
:class:`rotaflex.rotor.fe.Rotor` objects, joined by gear meshes (:class:`MeshSpec`) and
couplings (:class:`CouplingSpec`), driven (:class:`DriveSpec`) against a load
(:class:`LoadSpec`), make a :class:`Machine`. A machine is the TOML file's model tables as
Python objects: :meth:`Machine.to_mapping` gives the tables ``rotaflex system`` reads, and the
analyses below run the runners of ``rotaflex system <verb>`` on them (same validation, same
messages naming the same keys, same numbers, same figures).

Speeds are the drive rotor's, explicit in their names: ``speed_rpm=`` [rpm] or ``speed=``
[rad/s] (one of them), for one speed or a ``(start, stop)`` range.

Examples
--------
>>> from rotaflex.rotor.fe import Bearing, Disk, Rotor, Shaft
>>> from rotaflex.system.study import CouplingSpec, DriveSpec, Machine, MachineRotor, torsional_analysis
>>> def rotor(d, length, disk_node, mass, ip):
...     brg = dict(kxx=1e8, kyy=1e8)
...     return Rotor(shaft=(Shaft(outer_diameter=d, length=length, elements=4),),
...                  disk=(Disk(node=disk_node, mass=mass, Id=ip / 2, Ip=ip),),
...                  bearing=(Bearing(node=1, **brg), Bearing(node=3, **brg)))
>>> machine = Machine(
...     rotors={"motor": MachineRotor(rotor(0.075, 0.9, 2, 120.0, 1.2), speed_rpm=1480.0),
...             "pump": rotor(0.06, 0.8, 4, 25.0, 0.35)},
...     couplings=(CouplingSpec(rotor_a="motor", node_a=4, rotor_b="pump", node_b=0,
...                             torsional_stiffness=1.2e4),),
...     drive=DriveSpec(rotor="motor", node=2),
... )
>>> t = torsional_analysis(machine, operating_speed_rpm=(1440, 1500), n_modes=2)
>>> t.status, round(float(t.dataset["natural_frequency"][0]) / 6.283185307179586)
('success', 31)
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any, Literal

from rotaflex.core.errors import InputError
from rotaflex.rotor.fe.model import Rotor
from rotaflex.rotor.fe.stability import Stage
from rotaflex.rotor.fe.study import rotor_tables, speed_in_rpm
from rotaflex.system.case_specs import (
    ExcitationSpec,
    MachineDOF,
    MachineStaticLoad,
    MachineUnbalanceMass,
    Probe,
)
from rotaflex.system.coupling import CouplingSpec
from rotaflex.system.model import DriveSpec, Gearbox, LoadSpec, MeshSpec

__all__ = [
    "CouplingSpec",
    "DriveSpec",
    "ExcitationSpec",
    "LoadSpec",
    "Machine",
    "MachineDOF",
    "MachineRotor",
    "MachineStaticLoad",
    "MachineUnbalanceMass",
    "MeshSpec",
    "Probe",
    "Stage",
    "campbell_diagram",
    "critical_speed_map",
    "frf",
    "mesh_response",
    "modes",
    "stability",
    "startup",
    "static_state",
    "steady_state_study",
    "torsional_analysis",
    "transient_response",
    "unbalance_response_study",
]


@dataclass(frozen=True)
class MachineRotor:
    """A rotor of a machine with its placement (a ``[[rotor]]`` table's own keys).

    Parameters
    ----------
    rotor : Rotor
        The FE rotor (shaft, disks, bearings; SI).
    center : (float, float)
        (x, y) of the shaft axis in the gearbox plane [m]; rotors joined by a coupling share it.
    speed_rpm : float, optional
        Nominal speed [rpm] (the drive speed of analyses that take no speed; checked against
        the gear ratios).
    rotation : {"ccw", "cw"}, optional
        Sense seen from +z (default: from the drive and the meshes).
    torsion : bool
        A twist DOF at every node (needed under a gear, a torsional coupling or the drive).
    """

    rotor: Rotor
    center: tuple[float, float] = (0.0, 0.0)
    speed_rpm: float | None = None
    rotation: Literal["ccw", "cw"] | None = None
    torsion: bool = True


def _plain(spec: Any) -> dict:
    """A spec dataclass as its TOML table: keys left at None are left out (TOML has no None)."""
    return {k: v for k, v in dataclasses.asdict(spec).items() if v is not None}


@dataclass(frozen=True)
class Machine:
    """Rotors joined by gear meshes and couplings, a drive and a load (frozen, SI).

    Parameters
    ----------
    rotors : mapping of str to Rotor or MachineRotor
        The rotors by name (the names the meshes, couplings, drive and load use); a bare
        :class:`~rotaflex.rotor.fe.Rotor` sits at (0, 0) with torsion.
    meshes : tuple of MeshSpec
        Gear meshes (``[[gear_mesh]]`` tables: the pair as gear static's ``pinion``/``wheel``
        tables or a ``pair_file``).
    couplings : tuple of CouplingSpec
        Shaft couplings (``[[coupling]]`` tables).
    drive : DriveSpec
        The motor (``[drive]``).
    load : LoadSpec, optional
        The driven load (``[load]``).

    Attributes
    ----------
    gearbox : Gearbox
        The built model (placed rotors, meshes, couplings; :class:`rotaflex.system.Gearbox`),
        for the solver functions of :mod:`rotaflex.system` (``modal(machine.gearbox, ...)``).

    Notes
    -----
    Construction checks the machine as ``rotaflex system`` checks a file (names, stations,
    centres, ratios, pairs) and raises :class:`~rotaflex.core.errors.InputError` naming the key
    as the file would have it (``coupling[0].torsional_stiffness``, ``rotor[1].center``).
    """

    rotors: Mapping[str, Rotor | MachineRotor]
    meshes: tuple[MeshSpec, ...] = ()
    couplings: tuple[CouplingSpec, ...] = ()
    drive: DriveSpec | None = None
    load: LoadSpec | None = None
    gearbox: Gearbox = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        object.__setattr__(self, "gearbox", _build(self.to_mapping()))

    def to_mapping(self) -> dict:
        """The machine as the model tables of a ``rotaflex system`` file (plain data, SI; rpm
        where a key says so): what :meth:`rotaflex.system.Gearbox.from_mapping` reads."""
        if not isinstance(self.rotors, Mapping) or not self.rotors:
            raise InputError("rotor", self.rotors, "a mapping of rotor names to Rotor or MachineRotor objects")
        defaults = {f.name: f.default for f in dataclasses.fields(Rotor)}
        rotors = []
        for i, (name, r) in enumerate(self.rotors.items()):
            placed = r if isinstance(r, MachineRotor) else MachineRotor(r)
            tables = rotor_tables(placed.rotor, f"rotor[{i}]")
            # keys left at their default are left out, as a file that does not write them
            table = {k: v for k, v in tables.items() if k == "shaft" or v != defaults[k]}
            place = {k: v for k, v in _plain(placed).items() if k != "rotor"}
            rotors.append({"name": name, **place, **table})
        out: dict[str, Any] = {"rotor": rotors}
        for key, items, kind in (("gear_mesh", self.meshes, MeshSpec), ("coupling", self.couplings, CouplingSpec)):
            for i, item in enumerate(items):
                if not isinstance(item, kind):
                    raise InputError(f"{key}[{i}]", type(item).__name__, f"a {kind.__name__}")
            if items:
                out[key] = [_plain(item) for item in items]
        for key, item, kind in (("drive", self.drive, DriveSpec), ("load", self.load, LoadSpec)):
            if item is not None:
                if not isinstance(item, kind):
                    raise InputError(key, type(item).__name__, f"a {kind.__name__}")
                out[key] = _plain(item)
        return out


def _build(model: dict) -> Gearbox:
    """The gearbox of the model tables through the runners' own cache (built once: the
    analyses below find it there)."""
    from rotaflex.system.case import _gearbox

    return _gearbox(model, None)


def _run(machine: Machine, analysis: str, table: dict):
    from rotaflex.core.domains import command

    if not isinstance(machine, Machine):
        raise InputError("machine", type(machine).__name__, "a rotaflex.system.study.Machine")
    return command("system", analysis)({**machine.to_mapping(), analysis: table})


def _optional(**kw) -> dict:
    return {k: v for k, v in kw.items() if v is not None}


def modes(machine: Machine, *, speed_rpm: float | None = None, speed: float | None = None, n_modes: int = 12):
    """Coupled modes at one drive speed with their energy split (``rotaflex system modal``).

    Parameters
    ----------
    machine : Machine
    speed_rpm, speed : float, optional
        Drive speed [rpm] or [rad/s] (one of them; neither: the rotors' ``speed_rpm``).
    n_modes : int
        Modes reported, lowest first.

    Returns
    -------
    SystemModalResult
        ``.dataset`` (frequencies [rad/s], damping ratio, energy split, shapes),
        ``.summary()``, ``.plot_energy()``, ``.plot_model()``, ``.plot()``.
    """
    rpm = None if speed_rpm is None and speed is None else speed_in_rpm(speed_rpm, speed, "modal", pair=False)
    return _run(machine, "modal", _optional(speed_rpm=rpm, n_modes=n_modes))


def campbell_diagram(
    machine: Machine,
    *,
    speed_rpm: tuple[float, float] | None = None,
    speed: tuple[float, float] | None = None,
    n_speeds: int = 50,
    n_modes: int = 12,
    harmonics: Iterable[float] = (1.0, 2.0, 3.0),
    reduce: bool = True,
):
    """Campbell diagram over drive speeds with mesh-order lines (``rotaflex system campbell``).

    Parameters
    ----------
    machine : Machine
    speed_rpm, speed : (float, float)
        Drive-speed range [rpm] or [rad/s] (one of them).
    n_speeds, n_modes : int
    harmonics : iterable of float
        Mesh orders drawn and crossed.
    reduce : bool
        Solve in a reduced basis (modes and load shapes); False: all DOFs.

    Returns
    -------
    SystemCampbellResult
        ``.dataset`` (tracked frequencies [rad/s] vs ``speed``), ``.summary()`` (mesh-order
        crossings), ``.plot_campbell()``, ``.plot()``.
    """
    rng = speed_in_rpm(speed_rpm, speed, "campbell", pair=True)
    table = {"speed_rpm": rng, "n_speeds": n_speeds, "n_modes": n_modes, "reduce": reduce}
    return _run(machine, "campbell", {**table, "harmonics": [float(h) for h in harmonics]})


def torsional_analysis(
    machine: Machine,
    *,
    operating_speed_rpm: tuple[float, float] | None = None,
    operating_speed: tuple[float, float] | None = None,
    speed_rpm: tuple[float, float] | None = None,
    speed: tuple[float, float] | None = None,
    n_modes: int = 8,
    margin: float = 0.10,
    excitation: Iterable[ExcitationSpec] = (),
):
    """Torsional modes, interference diagram and API 684 separation margins (``rotaflex system
    torsional``).

    Parameters
    ----------
    machine : Machine
    operating_speed_rpm, operating_speed : (float, float), optional
        Drive-speed operating range (min, max continuous) [rpm] or [rad/s] (at most one; neither:
        the rotors' ``speed_rpm``).
    speed_rpm, speed : (float, float), optional
        Diagram range [rpm] or [rad/s] (at most one; default 0 to 1.25 x the operating maximum).
    n_modes : int
    margin : float
        Required separation (API 684: 0.10).
    excitation : iterable of ExcitationSpec
        Excitation lines (default: 1X and 2X of each rotor, 1x and 2x of each mesh).

    Returns
    -------
    TorsionalResult
        ``.dataset`` (frequencies [rad/s], shapes, margins), ``.summary()`` (API 684 verdict),
        ``.plot_interference()``, ``.plot_modes()``, ``.plot()``.
    """
    table = _optional(n_modes=n_modes, margin=margin)
    if operating_speed_rpm is not None or operating_speed is not None:
        table["operating_speed_rpm"] = speed_in_rpm(
            operating_speed_rpm, operating_speed, "torsional", pair=True, name="operating_speed"
        )
    if speed_rpm is not None or speed is not None:
        table["speed_rpm"] = speed_in_rpm(speed_rpm, speed, "torsional", pair=True)
    excitation = [_plain(e) if isinstance(e, ExcitationSpec) else dict(e) for e in excitation]
    if excitation:
        table["excitation"] = excitation
    return _run(machine, "torsional", table)


def startup(machine: Machine, *, duration: float = 5.0, n_out: int = 2001, max_frequency_hz: float | None = None):
    """Run-up from rest under the drive's torque-speed curve against the load (``rotaflex
    system startup``).

    Parameters
    ----------
    machine : Machine
        Its :class:`DriveSpec` gives ``curve_speed_rpm`` [rpm] and ``curve_torque`` [N m].
    duration : float
        Simulated time [s].
    n_out : int
        Samples written.
    max_frequency_hz : float, optional
        Highest torsional mode kept [Hz] (default: all).

    Returns
    -------
    StartupResult
        ``.dataset`` (speeds, torques vs ``time`` [s]), ``.summary()``, ``.plot_startup()``,
        ``.plot()``.
    """
    return _run(machine, "startup", _optional(duration=duration, n_out=n_out, max_frequency_hz=max_frequency_hz))


def mesh_response(
    machine: Machine,
    *,
    speed_rpm: tuple[float, float] | None = None,
    speed: tuple[float, float] | None = None,
    n_speeds: int = 500,
    harmonics: int = 3,
    excitation: Literal["loaded_te", "unloaded_te"] = "loaded_te",
    probes: Iterable[Probe] = (),
):
    """Linear response to the transmission-error harmonics vs drive speed (``rotaflex system
    response``).

    Parameters
    ----------
    machine : Machine
        With at least one gear mesh.
    speed_rpm, speed : (float, float)
        Drive-speed range [rpm] or [rad/s] (one of them).
    n_speeds, harmonics : int
    excitation : {"loaded_te", "unloaded_te"}
    probes : iterable of Probe
        Orbit nodes (default: the gear nodes).

    Returns
    -------
    SystemResponseResult
        ``.dataset`` (DTE [m], mesh and bearing forces [N], orbits vs ``speed``), ``.summary()``,
        ``.plot_response()``, ``.plot_orbits()``, ``.plot()``.
    """
    rng = speed_in_rpm(speed_rpm, speed, "response", pair=True)
    table = {"speed_rpm": rng, "n_speeds": n_speeds, "harmonics": harmonics, "excitation": excitation}
    plist = [_plain(p) if isinstance(p, Probe) else dict(p) for p in probes]
    return _run(machine, "response", {**table, **({"probes": plist} if plist else {})})


def steady_state_study(machine: Machine, *, speed_rpm: float | None = None, speed: float | None = None, **settings):
    """Nonlinear steady state at one drive speed, with contact loss (``rotaflex system steady``).

    Parameters
    ----------
    machine : Machine
        With at least one gear mesh.
    speed_rpm, speed : float, optional
        Drive speed [rpm] or [rad/s] (one of them; neither: the rotors' ``speed_rpm``).
    **settings
        Other keys of the ``[steady]`` table (``min_cycles``, ``max_cycles``, ``tol``, ...).

    Returns
    -------
    SystemSteadyResult
        ``.dataset`` (DTE, mesh and bearing forces vs ``time`` [s]), ``.summary()`` (dynamic
        factor), ``.plot_time_series()``, ``.plot()``.
    """
    rpm = None if speed_rpm is None and speed is None else speed_in_rpm(speed_rpm, speed, "steady", pair=False)
    return _run(machine, "steady", {**_optional(speed_rpm=rpm), **settings})


def _tables(items: Iterable, where: str) -> list[dict]:
    """Spec dataclasses or mappings as the list of TOML tables ``where`` holds."""
    if isinstance(items, (Mapping, str)) or not isinstance(items, Iterable):
        raise InputError(where, items, "a list of tables (spec objects or mappings)")
    return [_plain(x) if dataclasses.is_dataclass(x) else dict(x) for x in items]


def unbalance_response_study(
    machine: Machine,
    unbalance: Iterable[MachineUnbalanceMass | Mapping],
    *,
    speed_rpm: tuple[float, float] | None = None,
    speed: tuple[float, float] | None = None,
    n_speeds: int = 500,
    probes: Iterable[Probe | Mapping] = (),
    operating_speed_rpm: float | None = None,
    operating_range_rpm: tuple[float, float] | None = None,
    operating_bands_rpm: Iterable[tuple[float, float]] = (),
):
    """Steady unbalance response vs drive speed, each rotor's masses at its own 1X, with the API
    684 peaks and margins (``rotaflex system unbalance``).

    Parameters
    ----------
    machine : Machine
    unbalance : iterable of MachineUnbalanceMass or mapping
        The ``[[unbalance.mass]]`` tables: ``rotor`` (name), ``node`` or ``position`` [m],
        ``magnitude`` m e [kg m], ``phase_deg`` [deg].
    speed_rpm, speed : (float, float)
        Drive-speed range [rpm] or [rad/s] (one of them).
    n_speeds : int
    probes : iterable of Probe or mapping
        Orbit nodes (default: the unbalance nodes).
    operating_speed_rpm : float, optional
        Drive operating speed [rpm] (margins from it).
    operating_range_rpm : (float, float), optional
        Minimum and maximum continuous drive speed [rpm] (API margins below and above the band).
    operating_bands_rpm : iterable of (float, float)
        Several operating bands of the drive speed [rpm] (instead of ``operating_range_rpm``).

    Returns
    -------
    SystemUnbalanceResult
        ``.dataset`` (orbit amplitudes [m] vs ``speed``), ``.summary()`` (peaks, margins),
        ``.plot_bode()``, ``.plot_model()``, ``.plot()``.

    Examples
    --------
    >>> from rotaflex.rotor.fe import Bearing, Disk, Rotor, Shaft
    >>> from rotaflex.system.study import DriveSpec, Machine
    >>> brg = dict(kxx=1e7, kyy=1e7, cxx=2e3, cyy=2e3)
    >>> r = Rotor(shaft=(Shaft(outer_diameter=0.05, length=0.8, elements=4),),
    ...           disk=(Disk(node=2, mass=20.0, Id=0.1, Ip=0.2),),
    ...           bearing=(Bearing(node=0, **brg), Bearing(node=4, **brg)))
    >>> m = Machine(rotors={"r": r}, drive=DriveSpec(rotor="r", node=0))
    >>> u = unbalance_response_study(m, [{"rotor": "r", "node": 2, "magnitude": 1e-4}],
    ...                              speed_rpm=(500, 6000), n_speeds=111)
    >>> round(u.summary()["peak_0_speed_rpm"]["value"])  # the first critical [rpm]: 66 Hz
    3957
    """
    table = {
        "speed_rpm": speed_in_rpm(speed_rpm, speed, "unbalance", pair=True),
        "n_speeds": n_speeds,
        "mass": _tables(unbalance, "unbalance.mass"),
    }
    plist = _tables(probes, "unbalance.probes")
    bands = [list(b) for b in operating_bands_rpm]
    if plist:
        table["probes"] = plist
    if bands:
        table["operating_bands_rpm"] = bands
    if operating_range_rpm is not None:
        table["operating_range_rpm"] = list(operating_range_rpm)
    return _run(machine, "unbalance", {**table, **_optional(operating_speed_rpm=operating_speed_rpm)})


def frf(
    machine: Machine,
    *,
    inputs: Iterable[MachineDOF | Mapping],
    outputs: Iterable[MachineDOF | Mapping] | None = None,
    speed_rpm: float | None = None,
    speed: float | None = None,
    frequency_hz: tuple[float, float] = (1.0, 200.0),
    n_frequencies: int = 2000,
    kind: Literal["receptance", "mobility", "accelerance"] = "receptance",
):
    """Frequency response functions of the machine at one drive speed (``rotaflex system frf``).

    Parameters
    ----------
    machine : Machine
    inputs : iterable of MachineDOF or mapping
        DOFs of the unit forces (moments): ``rotor``, ``node``, ``direction`` (``x``, ``y``,
        ``theta_x``, ``theta_y``, ``twist``).
    outputs : iterable of MachineDOF or mapping, optional
        Response DOFs (default: the inputs).
    speed_rpm, speed : float, optional
        Drive speed [rpm] or [rad/s] (at most one; neither: at rest); every rotor at its ratio.
    frequency_hz : (float, float)
        Excitation frequency range [Hz].
    n_frequencies : int
    kind : {"receptance", "mobility", "accelerance"}
        H = X/F, i w H or -w^2 H: m/N, m/(N s), m/(N s^2) for a force to a displacement, rad/(N m),
        ... for a moment to a rotation (each pair's unit: ``pair_unit`` where they differ).

    Returns
    -------
    SystemFRFResult
        ``.dataset`` (``H_real``, ``H_imag`` per output/input ``pair`` vs ``frequency``),
        ``.summary()`` (peaks, half-power damping), ``.plot_model()``, ``.plot()``.

    Examples
    --------
    >>> from rotaflex.rotor.fe import Bearing, Disk, Rotor, Shaft
    >>> from rotaflex.system.study import DriveSpec, Machine
    >>> brg = dict(kxx=1e7, kyy=1e7, cxx=2e3, cyy=2e3)
    >>> r = Rotor(shaft=(Shaft(outer_diameter=0.05, length=0.8, elements=4),),
    ...           disk=(Disk(node=2, mass=20.0, Id=0.1, Ip=0.2),),
    ...           bearing=(Bearing(node=0, **brg), Bearing(node=4, **brg)))
    >>> m = Machine(rotors={"r": r}, drive=DriveSpec(rotor="r", node=0))
    >>> h = frf(m, inputs=[{"rotor": "r", "node": 2}], frequency_hz=(1, 100), n_frequencies=100)
    >>> round(h.summary()["r:2 x / r:2 Fx_peak_0_frequency_hz"]["value"])  # [Hz], at rest
    66
    """
    table = {
        "frequency_hz": [float(f) for f in frequency_hz],
        "n_frequencies": n_frequencies,
        "kind": kind,
        "inputs": _tables(inputs, "frf.inputs"),
    }
    if outputs is not None:
        table["outputs"] = _tables(outputs, "frf.outputs")
    if speed_rpm is not None or speed is not None:
        table["speed_rpm"] = speed_in_rpm(speed_rpm, speed, "frf", pair=False)
    return _run(machine, "frf", table)


def stability(
    machine: Machine,
    *,
    rotor: str | None = None,
    speed_rpm: float | None = None,
    speed: float | None = None,
    rated_speed_rpm: float | None = None,
    kind: Literal["centrifugal_compressor", "axial_compressor", "turbine", "pump"] = "centrifugal_compressor",
    stages: Iterable[Stage | Mapping] = (),
    location: Literal["midspan", "stages"] = "midspan",
    mean_density: float | None = None,
    n_points: int = 41,
    log_dec_min: float | None = None,
):
    """API 617 Level II stability of the whole machine and Level I of one rotor at the drive's
    maximum continuous speed (``rotaflex system stability``).

    Parameters
    ----------
    machine : Machine
    rotor : str, optional
        The rotor whose stages carry Q_A (``[stability] rotor``; default: the only rotor).
    speed_rpm, speed : float, optional
        Drive MCS [rpm] or [rad/s] (at most one; neither: the rotors' ``speed_rpm``).
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
    SystemStabilityResult
        ``.dataset`` (log decrements and frequencies [rad/s] of Level I and Level II),
        ``.summary()`` (verdicts), ``.plot_model()``, ``.plot()``.

    Examples
    --------
    >>> from rotaflex.rotor.fe import Bearing, Disk, Rotor, Shaft
    >>> from rotaflex.system.study import DriveSpec, Machine
    >>> brg = dict(kxx=1e7, kyy=1e7, cxx=2e3, cyy=2e3)
    >>> r = Rotor(shaft=(Shaft(outer_diameter=0.05, length=0.8, elements=4),),
    ...           disk=(Disk(node=2, mass=20.0, Id=0.1, Ip=0.2),),
    ...           bearing=(Bearing(node=0, **brg), Bearing(node=4, **brg)))
    >>> m = Machine(rotors={"r": r}, drive=DriveSpec(rotor="r", node=0))
    >>> s = stability(m, kind="pump", speed_rpm=3000)
    >>> s.summary()["level2_verdict"]["value"], round(s.summary()["level2_log_dec"]["value"], 3)
    ('fail', 0.069)
    """
    table = {"machine": kind, "location": location, "n_points": n_points}
    slist = _tables(stages, "stability.stage")
    if slist:
        table["stage"] = slist
    if speed_rpm is not None or speed is not None:
        table["speed_rpm"] = speed_in_rpm(speed_rpm, speed, "stability", pair=False)
    optional = _optional(rotor=rotor, rated_speed_rpm=rated_speed_rpm, mean_density=mean_density)
    return _run(machine, "stability", {**table, **optional, **_optional(log_dec_min=log_dec_min)})


def static_state(
    machine: Machine,
    *,
    gravity: float = 9.80665,
    gravity_direction: tuple[float, float] = (0.0, -1.0),
    loads: Iterable[MachineStaticLoad | Mapping] = (),
    speed_rpm: float | None = None,
    speed: float | None = None,
):
    """Static state of the machine: deflection, bearing reactions, shear and moment of every rotor
    under gravity, point loads and the ``[load]`` torque, the couplings and meshes carrying their
    static forces (``rotaflex system static``).

    Parameters
    ----------
    machine : Machine
    gravity : float
        Acceleration of gravity [m/s^2] (0: point loads only).
    gravity_direction : (float, float)
        Direction of gravity (g_x, g_y) in the rotors' x-y plane (default -y).
    loads : iterable of MachineStaticLoad or mapping
        The ``[[static.load]]`` tables: ``rotor`` (name), ``node`` or ``position`` [m], ``fx``,
        ``fy`` [N].
    speed_rpm, speed : float, optional
        Drive speed of the bearing coefficients [rpm] or [rad/s] (at most one; neither: the
        rotors' ``speed_rpm``, else the bearing tables' lowest speed).

    Returns
    -------
    SystemStaticResult
        ``.dataset`` (``deflection`` [m] per node, ``reaction`` [N] per bearing, ``shear`` [N],
        ``moment`` [N m], ``stress`` [Pa] along the shafts), ``.summary()`` (bearing loads,
        maxima per rotor), ``.plot_static(rotor)``, ``.plot_model()``, ``.plot()``.

    Examples
    --------
    >>> from rotaflex.rotor.fe import Bearing, Disk, Rotor, Shaft
    >>> from rotaflex.system.study import DriveSpec, Machine
    >>> brg = dict(kxx=1e7, kyy=1e7, cxx=2e3, cyy=2e3)
    >>> r = Rotor(shaft=(Shaft(outer_diameter=0.05, length=0.8, elements=4),),
    ...           disk=(Disk(node=2, mass=20.0, Id=0.1, Ip=0.2),),
    ...           bearing=(Bearing(node=0, **brg), Bearing(node=4, **brg)))
    >>> m = Machine(rotors={"r": r}, drive=DriveSpec(rotor="r", node=0))
    >>> s = static_state(m, loads=[{"rotor": "r", "node": 2, "fy": -100.0}])
    >>> shaft = 7810.0 * 3.141592653589793 * 0.025**2 * 0.8  # [kg], steel
    >>> half = (20.0 + shaft) * 9.80665 / 2 + 50.0  # [N]: half the weight and half the load
    >>> round(s.summary()["r_load_bearing[0]"]["value"], 1), round(half, 1)
    (208.2, 208.2)
    """
    table = {
        "gravity": float(gravity),
        "gravity_direction": [float(g) for g in gravity_direction],
        "load": _tables(loads, "static.load"),
    }
    if speed_rpm is not None or speed is not None:
        table["speed_rpm"] = speed_in_rpm(speed_rpm, speed, "static", pair=False)
    return _run(machine, "static", table)


def critical_speed_map(
    machine: Machine,
    *,
    stiffness: tuple[float, float] = (1e5, 1e10),
    n_points: int = 40,
    n_modes: int = 4,
    rotors: Iterable[str] = (),
    rotor: str | None = None,
    speed_rpm: float | None = None,
    speed: float | None = None,
):
    """Undamped critical speed map: the critical drive speeds against the stiffness of the swept
    bearings (``rotaflex system ucs``).

    Parameters
    ----------
    machine : Machine
    stiffness : (float, float)
        Range of the swept bearings' stiffness kxx = kyy [N/m] (log spaced).
    n_points : int
        Stiffness values.
    n_modes : int
        Critical speeds per stiffness, lowest first.
    rotors : iterable of str
        Rotors whose bearings get the swept stiffness (default: all).
    rotor : str, optional
        The rotor whose 1X defines the critical speeds (default: the drive rotor).
    speed_rpm, speed : float, optional
        Drive speed of the other bearings' kxx, kyy [rpm] or [rad/s] (at most one; neither: the
        rotors' ``speed_rpm``).

    Returns
    -------
    SystemUCSResult
        ``.dataset`` (``critical_speed`` [rad/s of the drive], ``whirl_frequency`` [rad/s] vs
        ``stiffness`` [N/m] and ``mode``), ``.summary()`` (criticals at the highest stiffness
        [rpm]), ``.plot_model()``, ``.plot()`` (the map with the bearings' kxx, kyy).

    Examples
    --------
    >>> from rotaflex.rotor.fe import Bearing, Rotor, Shaft
    >>> from rotaflex.system.study import DriveSpec, Machine
    >>> r = Rotor(shaft=(Shaft(outer_diameter=0.05, length=0.8, elements=4),),
    ...           bearing=(Bearing(node=0, kxx=1e5, kyy=1e5), Bearing(node=4, kxx=1e5, kyy=1e5)))
    >>> m = Machine(rotors={"r": r}, drive=DriveSpec(rotor="r", node=0))
    >>> u = critical_speed_map(m, stiffness=(1e4, 1e9), n_points=6, n_modes=2)
    >>> w = float(u.dataset["critical_speed"][0, 0])  # [rad/s] at 1e4 N/m: rigid-body bounce
    >>> bounce = (2 * 1e4 / (7810.0 * 3.141592653589793 * 0.025**2 * 0.8)) ** 0.5  # sqrt(2 k / m)
    >>> round(w / bounce, 3)  # the shaft's own bending makes the mode slightly softer
    0.999
    """
    names = rotors if isinstance(rotors, str) else list(rotors)  # a bare name: refused by the table's check
    table = {"stiffness": [float(k) for k in stiffness], "n_points": n_points, "n_modes": n_modes, "rotors": names}
    if speed_rpm is not None or speed is not None:
        table["speed_rpm"] = speed_in_rpm(speed_rpm, speed, "ucs", pair=False)
    return _run(machine, "ucs", {**table, **_optional(rotor=rotor)})


def transient_response(
    machine: Machine,
    *,
    duration: float = 1.0,
    speed_rpm: tuple[float, float] | None = None,
    speed: tuple[float, float] | None = None,
    masses: Iterable[MachineUnbalanceMass | Mapping] = (),
    probes: Iterable[Probe | Mapping] = (),
    n_output: int = 2001,
    method: Literal["modal", "direct"] = "modal",
    n_modes: int = 20,
    steps_per_output: int = 4,
):
    """Time response of the machine to unbalance at a constant drive speed or on a linear ramp
    (``rotaflex system transient``).

    Parameters
    ----------
    machine : Machine
    duration : float
        Simulated time [s].
    speed_rpm, speed : (float, float)
        Drive speed at the start and the end [rpm] or [rad/s] (one of them; equal: constant);
        every rotor turns at its ratio.
    masses : iterable of MachineUnbalanceMass or mapping
        The ``[[transient.mass]]`` tables: ``rotor`` (name), ``node`` or ``position`` [m],
        ``magnitude`` m e [kg m], ``phase_deg`` [deg] (the rotor's angle at t = 0).
    probes : iterable of Probe or mapping
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
    SystemTransientResult
        ``.dataset`` (``displacement`` [m] per probe and axis, ``speed`` and ``rotor_speed``
        [rad/s] vs ``time`` [s]), ``.summary()`` (largest radial displacement and the drive
        speed there), ``.plot_model()``, ``.plot()`` (time response and orbits).

    Examples
    --------
    >>> from rotaflex.rotor.fe import Bearing, Disk, Rotor, Shaft
    >>> from rotaflex.system.study import DriveSpec, Machine
    >>> brg = dict(kxx=1e7, kyy=1e7, cxx=2e3, cyy=2e3)
    >>> r = Rotor(shaft=(Shaft(outer_diameter=0.05, length=0.8, elements=4),),
    ...           disk=(Disk(node=2, mass=20.0, Id=0.1, Ip=0.2),),
    ...           bearing=(Bearing(node=0, **brg), Bearing(node=4, **brg)))
    >>> m = Machine(rotors={"r": r}, drive=DriveSpec(rotor="r", node=0))
    >>> t = transient_response(m, duration=0.1, speed_rpm=(3000, 3000), n_output=101,
    ...                        masses=[{"rotor": "r", "node": 2, "magnitude": 1e-4}])
    >>> t.dataset["displacement"].shape  # (time, probe, axis)
    (101, 1, 2)
    """
    table = {
        "speed_rpm": speed_in_rpm(speed_rpm, speed, "transient", pair=True),
        "duration": float(duration),
        "n_output": n_output,
        "method": method,
        "n_modes": n_modes,
        "steps_per_output": steps_per_output,
        "mass": _tables(masses, "transient.mass"),
    }
    plist = _tables(probes, "transient.probes")
    return _run(machine, "transient", {**table, **({"probes": plist} if plist else {})})
