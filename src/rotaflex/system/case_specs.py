"""Settings tables of the machine verbs (``[modal]``, ``[campbell]``, ... of a system case) and the
case schema: one dataclass per analysis, listed once in :data:`ANALYSES`.

Speeds are the drive rotor's, in rpm (``speed_rpm``); :mod:`.case` converts them once.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

from rotaflex.core.config import param
from rotaflex.rotor.fe.case_config import FRFPair, FRFSpec, PointLoad, StaticSpec, UCSSpec, UnbalanceMass
from rotaflex.system.coupling import CouplingSpec
from rotaflex.system.model import DriveSpec, LoadSpec, MeshSpec, RotorSpec
from rotaflex.system.size import DEFAULT_MAX_STEPS
from rotaflex.system.stability import MachineStabilitySpec


@dataclass(frozen=True)
class Probe:
    """A node whose lateral orbit is reported."""

    rotor: str = param(doc="rotor name")
    node: int = param(ge=0)


@dataclass(frozen=True)
class ModalSpec:
    """Coupled modes at one drive speed (mean mesh stiffness)."""

    speed_rpm: float | None = param(None, unit="rpm", ge=0, doc="drive speed (default: the nominal one)")
    n_modes: int = param(12, ge=1, le=200)


@dataclass(frozen=True)
class CampbellSpec:
    """Campbell diagram over drive speeds with mesh-order and 1X lines."""

    speed_rpm: tuple[float, float] = param((0.0, 6000.0), unit="rpm", ge=0, doc="drive speed range")
    n_speeds: int = param(50, ge=2, le=2000)
    n_modes: int = param(12, ge=1, le=200)
    harmonics: tuple[float, ...] = param((1.0, 2.0, 3.0), gt=0, doc="mesh orders drawn and crossed")
    reduce: bool = param(True, doc="solve in a reduced basis (modes + load shapes); false: all DOFs")


@dataclass(frozen=True)
class ResponseSpec:
    """Linear response to the TE harmonics vs drive speed (frequency domain)."""

    speed_rpm: tuple[float, float] = param((100.0, 6000.0), unit="rpm", gt=0)
    n_speeds: int = param(500, ge=2, le=100000)
    harmonics: int = param(3, ge=1, le=50, doc="TE harmonics of the mesh frequency")
    excitation: Literal["loaded_te", "unloaded_te"] = param("loaded_te")
    probes: tuple[Probe, ...] = param((), doc="orbit nodes (default: the gear nodes)")
    cutoff: float | None = param(2.0, gt=0, doc="keep modes below cutoff x highest excitation (none: all DOFs)")


@dataclass(frozen=True)
class SteadySpec:
    """Nonlinear steady state at one drive speed (time domain, contact loss)."""

    speed_rpm: float | None = param(None, unit="rpm", gt=0, doc="drive speed (default: the nominal one)")
    steps_per_cycle: int = param(0, ge=0, le=100000, doc="RK4 steps per mesh cycle (0: automatic)")
    min_cycles: int = param(20, ge=1)
    max_cycles: int = param(400, ge=1, le=1000000)
    eval_cycles: int = param(10, ge=2, le=10000)
    tol: float = param(1e-5, gt=0, doc="periodicity: cycle-to-cycle DTE change / static deflection")
    cutoff: float = param(4.0, gt=0, doc="keep modes below cutoff x the highest mesh harmonic")
    harmonics: int = param(3, ge=1, doc="mesh harmonics the basis must carry")
    stiffness: Literal["mesh", "mean", "varying"] = param("mesh", doc="mesh: each [[gear_mesh]]'s own setting")
    max_steps: int = param(
        DEFAULT_MAX_STEPS, ge=1, doc="refuse a run that may take more RK4 steps ((max_cycles + eval_cycles) x steps)"
    )


@dataclass(frozen=True)
class ExcitationSpec:
    """One excitation of the torsional interference diagram."""

    kind: Literal["shaft", "mesh", "fixed"] = param(doc="shaft: order x rotor speed; mesh: x tooth-passing; fixed")
    order: float = param(1.0, gt=0, doc="multiple of the base frequency (2 with a line frequency: 2x line)")
    rotor: str | None = param(None, doc="shaft: rotor name")
    mesh: int | None = param(None, ge=0, doc="mesh: index of the [[gear_mesh]] (0 = first)")
    frequency_hz: float | None = param(None, unit="Hz", gt=0, doc="fixed: base frequency (e.g. the line frequency)")
    name: str | None = param(None, doc="label (default from kind and order)")


@dataclass(frozen=True)
class TorsionalSpec:
    """Torsional natural frequencies, interference diagram and API 684 separation margins."""

    n_modes: int = param(8, ge=1, le=200)
    operating_speed_rpm: tuple[float, float] | None = param(
        None, unit="rpm", gt=0, doc="drive speed [min, max continuous] (default: the nominal speed)"
    )
    speed_rpm: tuple[float, float] | None = param(
        None, unit="rpm", ge=0, doc="diagram range (default: 0 to 1.25 x the operating maximum)"
    )
    margin: float = param(0.10, ge=0, lt=1, doc="required separation (API 684: 10 %)")
    excitation: tuple[ExcitationSpec, ...] = param((), doc="default: 1X, 2X of each rotor, 1x, 2x of each mesh")


@dataclass(frozen=True)
class StartupSpec:
    """Run-up from rest with the [drive] torque-speed curve against the [load]."""

    duration: float = param(5.0, unit="s", gt=0)
    n_out: int = param(2001, ge=2, le=1_000_000, doc="samples written")
    max_frequency_hz: float | None = param(None, unit="Hz", gt=0, doc="highest torsional mode kept (none: all)")
    rtol: float = param(1e-6, gt=0, lt=1e-2, doc="relative tolerance of the Radau integrator")


@dataclass(frozen=True)
class MachineUnbalanceMass(UnbalanceMass):
    """An unbalance u = m e on one rotor of the machine: the keys of rotor unbalance plus rotor."""

    rotor: str | None = param(None, doc="rotor name (default: the only rotor)")


@dataclass(frozen=True)
class UnbalanceSpec:
    """Steady unbalance response vs drive speed (each rotor's unbalance at its own 1X)."""

    speed_rpm: tuple[float, float] = param((100.0, 6000.0), unit="rpm", gt=0, doc="drive speed range")
    n_speeds: int = param(500, ge=2, le=100000)
    probes: tuple[Probe, ...] = param((), doc="orbit nodes (default: the unbalance nodes)")
    operating_speed_rpm: float | None = param(None, unit="rpm", gt=0, doc="drive operating speed (margins from it)")
    operating_range_rpm: tuple[float, float] | None = param(
        None, unit="rpm", gt=0, doc="[minimum, maximum] continuous drive speed (API margins below/above the band)"
    )
    operating_bands_rpm: tuple[tuple[float, float], ...] = param(
        (), unit="rpm", gt=0, doc="several operating bands of the drive speed (instead of operating_range_rpm)"
    )
    mass: tuple[MachineUnbalanceMass, ...] = param(())


@dataclass(frozen=True)
class MachineTransientSpec:
    """Time response of a machine (rotor transient's keys; probes and masses per rotor; no
    large-rotation disks: a machine's rotors are linear)."""

    speed_rpm: tuple[float, float] = param((0.0, 0.0), unit="rpm", ge=0, doc="drive speed at start and end (ramp)")
    duration: float = param(1.0, unit="s", gt=0)
    n_output: int = param(2001, ge=2)
    method: Literal["modal", "direct"] = param("modal")
    n_modes: int = param(20, ge=1, doc="modes kept by the modal method")
    steps_per_output: int = param(4, ge=1, doc="Newmark steps per output interval (direct method)")
    probes: tuple[Probe, ...] = param((), doc="orbit nodes (default: the unbalance nodes)")
    mass: tuple[MachineUnbalanceMass, ...] = param(())


@dataclass(frozen=True)
class MachineDOF:
    """A DOF of the machine: rotor, node and direction."""

    node: int = param(ge=0)
    rotor: str | None = param(None, doc="rotor name (default: the only rotor)")
    direction: Literal["x", "y", "theta_x", "theta_y", "twist"] = param(
        "x", doc="force (x, y) or moment (theta_*, twist) at an input; the response DOF at an output"
    )


@dataclass(frozen=True)
class MachineFRFSpec(FRFSpec):
    """FRFs of a machine at one drive speed: the rotor verb's keys, DOFs as (rotor, node, direction)."""

    speed_rpm: float = param(0.0, unit="rpm", ge=0, doc="drive speed (every rotor at its ratio)")
    pair: tuple[FRFPair, ...] = param((), doc="rotor verb only; a machine takes inputs and outputs")
    inputs: tuple[MachineDOF, ...] = param((), doc="DOFs of the unit forces (moments)")
    outputs: tuple[MachineDOF, ...] = param((), doc="response DOFs (default: the inputs)")


@dataclass(frozen=True)
class MachineStaticLoad(PointLoad):
    """A static point force on one rotor of the machine: the rotor verb's keys plus rotor."""

    rotor: str | None = param(None, doc="rotor name (default: the only rotor)")


@dataclass(frozen=True)
class MachineStaticSpec(StaticSpec):
    """Static state of the machine: the rotor verb's keys, loads per rotor, the [load] torque."""

    speed_rpm: float | None = param(
        None, unit="rpm", ge=0, doc="drive speed of the bearing coefficients (default: nominal, else tables' lowest)"
    )
    load: tuple[MachineStaticLoad, ...] = param(())


@dataclass(frozen=True)
class MachineUCSSpec(UCSSpec):
    """Undamped critical speed map of a machine: the rotor verb's keys, the swept bearings' rotors,
    the rotor whose 1X defines the critical speeds and the speed of the other bearings."""

    rotors: tuple[str, ...] = param((), doc="rotors whose bearings get the swept stiffness (default: all)")
    rotor: str | None = param(None, doc="critical speeds: a frequency equals this rotor's 1X (default: the drive)")
    speed_rpm: float | None = param(
        None, unit="rpm", ge=0, doc="drive speed of the other bearings' kxx, kyy (default: the nominal one)"
    )


ANALYSES = {
    "modal": ModalSpec,
    "campbell": CampbellSpec,
    "response": ResponseSpec,
    "steady": SteadySpec,
    "torsional": TorsionalSpec,
    "startup": StartupSpec,
    "unbalance": UnbalanceSpec,
    "frf": MachineFRFSpec,
    "stability": MachineStabilitySpec,
    "static": MachineStaticSpec,
    "ucs": MachineUCSSpec,
    "transient": MachineTransientSpec,
}


#: the verbs' names, as ``analysis`` of a sweep case takes them (one list: :data:`ANALYSES`)
ANALYSIS_NAMES = tuple(ANALYSES)


@dataclass(frozen=True)
class SystemCase:
    """Gearbox case file: rotors, gear meshes, drive, load, and one table per analysis.

    Each [[gear_mesh]] also takes the pair keys of ``gear static`` ([pinion], [wheel],
    center_distance, backlash, driver) or a ``pair_file``.
    """

    rotor: tuple[RotorSpec, ...] = param()
    gear_mesh: tuple[MeshSpec, ...] = param(())
    coupling: tuple[CouplingSpec, ...] = param(())
    drive: DriveSpec | None = param(None)
    load: LoadSpec | None = param(None)
    analysis: Literal[ANALYSIS_NAMES] | None = param(None)
    modal: ModalSpec = field(default_factory=ModalSpec)
    campbell: CampbellSpec = field(default_factory=CampbellSpec)
    response: ResponseSpec = field(default_factory=ResponseSpec)
    steady: SteadySpec = field(default_factory=SteadySpec)
    torsional: TorsionalSpec = field(default_factory=TorsionalSpec)
    startup: StartupSpec = field(default_factory=StartupSpec)
    unbalance: UnbalanceSpec = field(default_factory=UnbalanceSpec)
    frf: MachineFRFSpec = field(default_factory=MachineFRFSpec)
    stability: MachineStabilitySpec = field(default_factory=MachineStabilitySpec)
    static: MachineStaticSpec = field(default_factory=MachineStaticSpec)
    ucs: MachineUCSSpec = field(default_factory=MachineUCSSpec)
    transient: MachineTransientSpec = field(default_factory=MachineTransientSpec)


SCHEMA = SystemCase
