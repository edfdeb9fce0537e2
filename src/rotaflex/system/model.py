"""Geared rotor system: FE rotors placed in the gearbox plane and joined by gear meshes (frozen data).

A config holds ``[[rotor]]`` tables (each an FE rotor of :mod:`rotaflex.rotor.fe` with its
``[[rotor.shaft]]``, ``[[rotor.disk]]``, ``[[rotor.bearing]]`` and a ``center`` in the gearbox
plane), ``[[gear_mesh]]`` tables joining a node of one rotor to a node of another through a
gear pair (the ``[pinion]``/``[wheel]`` tables of ``gear static``, inline or from a pair file),
a ``[drive]`` and a ``[load]``. Shafts are parallel to z; centres are (x, y) [m]. Speeds are
given in rpm for the drive rotor and converted once, here; every other rotor's speed and sense
of rotation follow from the gear ratios (external meshes reverse the sense).

Conventions (derived in docs/geared-rotor.md): every node of a rotor with ``torsion = true``
carries a twist ``theta_z`` (positive about +z) besides the lateral ``[x, y, theta_x,
theta_y]`` of :mod:`rotaflex.rotor.fe`. For a mesh whose driving gear d turns in the sense
``s_d`` (+1: counter-clockwise seen from +z) and drives gear f, the line of action is the unit
vector ``n = R(gamma) (sin alpha', s_d cos alpha')`` (gamma: direction from the driver's centre to
the driven gear's centre, alpha': working pressure angle) and the mesh deflection is

    delta = (u_d - u_f) . n + s_d (r_bd theta_d + r_bf theta_f) - e(phi)

(u: lateral displacement of the gear node); the mesh force ``F = k delta + c delta'`` acts as
``+F n`` on the driven gear and ``-F n`` on the driver.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import typing
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import numpy as np

from rotaflex.core.config import from_mapping, load_toml, param
from rotaflex.core.errors import InputError
from rotaflex.gear import PairSpec
from rotaflex.gear.models.mesh_stiffness import DEFAULT_DAMPING_RATIO, mesh_damping
from rotaflex.gear.pair.lead import FaceConfig
from rotaflex.rotor.fe.model import ROTOR_KEYS, Bearing, Disk, Material, PointMass, Rotor, Shaft
from rotaflex.system.coupling import CouplingElement, CouplingSpec
from rotaflex.system.coupling import element as coupling_element

#: keys of a [[gear_mesh]] table that describe the gear pair (passed to pair_from_mapping)
PAIR_KEYS = ("pinion", "wheel", "center_distance", "backlash", "driver")


@dataclass(frozen=True)
class RotorSpec:
    """One FE rotor of the gearbox: the rotor tables of ``rotaflex rotor`` plus its placement."""

    name: str = param(doc="label used by [[gear_mesh]], [drive] and [load]")
    center: tuple[float, float] = param(unit="m", doc="(x, y) of the shaft axis in the gearbox plane")
    shaft: tuple[Shaft, ...] = param()
    speed_rpm: float | None = param(None, unit="rpm", gt=0, doc="nominal speed (checked against the gear ratios)")
    rotation: Literal["ccw", "cw"] | None = param(None, doc="sense seen from +z (default: from the drive)")
    torsion: bool = param(True, doc="give every node a twist DOF (needed under a gear)")
    disk: tuple[Disk, ...] = param(())
    point_mass: tuple[PointMass, ...] = param(())
    bearing: tuple[Bearing, ...] = param(())
    material: dict[str, Material] = param({})
    free: bool = param(False, doc="allow lateral rigid-body modes (rotor/fe's free)")


#: the [pinion]/[wheel] table type of gear static, taken from the gear package's PairSpec (so the
#: template of ``rotaflex system`` lists a pair's keys under [[gear_mesh]] without a copy here)
GearTable = typing.get_type_hints(PairSpec)["pinion"]


@dataclass(frozen=True)
class MeshSpec:
    """A gear mesh joining two rotors (pair keys: [pinion]/[wheel] tables or ``pair_file``)."""

    pinion_rotor: str = param(doc="name of the rotor carrying the pinion")
    wheel_rotor: str = param(doc="name of the rotor carrying the wheel")
    pinion_node: int | None = param(None, ge=0, doc="node of the pinion (or pinion_position)")
    pinion_position: float | None = param(None, unit="m")
    wheel_node: int | None = param(None, ge=0)
    wheel_position: float | None = param(None, unit="m")
    pair_file: str | None = param(None, doc="TOML file with the [pinion]/[wheel] tables (instead of inline)")
    source: Literal["loaded_te", "static_fe", "iso6336", "harmonic", "contact_pattern"] = param(
        "iso6336", doc="mesh stiffness / TE table (rotaflex.gear.gear_mesh)"
    )
    torque: float | None = param(None, unit="N m", gt=0, doc="pinion torque of the table (default: from [load])")
    table_points: int = param(256, ge=8, le=4096)
    mesh_preset: Literal["coarse", "default", "fine"] = param("default")
    k_mean: float | None = param(None, unit="N/m", gt=0, doc="harmonic source: mean stiffness")
    k_harmonics: tuple[float, ...] = param((), unit="N/m", doc="harmonic source: cosine amplitudes")
    te_harmonics: tuple[float, ...] = param((), unit="m", doc="harmonic source: TE sine amplitudes")
    k_pair: float | None = param(None, unit="N/m", gt=0, doc="contact_pattern source: one pair's stiffness")
    unloaded_te_pp: float = param(0.0, unit="m", ge=0, doc="contact_pattern source: TE peak-to-peak")
    stiffness: Literal["mean", "varying"] = param("varying", doc="time-domain runs: k(phi) or its mean")
    damping_ratio: float = param(
        DEFAULT_DAMPING_RATIO, ge=0, le=1, doc="c_m = 2 zeta sqrt(k_mean m_red); <= 1 (critical)"
    )
    back_contact: bool = param(True, doc="back-flank contact after the backlash in time-domain runs")
    blanks: bool = param(True, doc="add the gear blanks as disks on their nodes")
    # the pair, as in `gear static` (read by rotaflex.gear.pair_from_mapping, here for the template)
    pinion: GearTable | None = param(None, doc="the pinion as gear static's [pinion] (or pair_file)")
    wheel: GearTable | None = param(None, doc="the wheel as gear static's [wheel] (or pair_file)")
    center_distance: float | None = param(None, unit="m", gt=0, doc="working centre distance (default: no backlash)")
    backlash: float | None = param(None, unit="m", ge=0, doc="normal backlash (alternative to center_distance)")
    driver: Literal["pinion", "wheel"] = param("pinion", doc="gear that drives (must be on the drive side)")
    contact_point: Literal["mid_face", "load_centroid"] | None = param(
        None,
        doc="helical: resultant at mid-face or at the load distribution's centroid (default: centroid "
        "with lead modifications or a misalignment, else mid-face)",
    )
    face: FaceConfig | None = param(
        None, doc="helical: gear static's [face] (slices, coupling, misalignment) for the contact point"
    )


@dataclass(frozen=True)
class DriveSpec:
    """Motor: constant speed (an infinitely stiff speed control) or a torque balancing the load."""

    rotor: str = param(doc="rotor name")
    node: int | None = param(None, ge=0)
    position: float | None = param(None, unit="m")
    kind: Literal["constant_speed", "torque"] = param("constant_speed")
    inertia: float = param(0.0, unit="kg m^2", ge=0, doc="motor rotor inertia added at the node")
    rotation: Literal["ccw", "cw"] = param("ccw", doc="sense of rotation seen from +z")
    curve_speed_rpm: tuple[float, ...] = param((), unit="rpm", ge=0, doc="startup: motor curve speeds (increasing)")
    curve_torque: tuple[float, ...] = param((), unit="N m", doc="startup: motor torque at curve_speed_rpm")
    pulsating_torque: float = param(0.0, unit="N m", ge=0, doc="startup: synchronous motor, 2x slip frequency")
    line_frequency_hz: float = param(50.0, unit="Hz", gt=0, doc="startup: supply frequency of the motor")
    poles: int = param(2, ge=2, doc="startup: motor poles (synchronous speed 120 f / poles rpm)")


@dataclass(frozen=True)
class LoadSpec:
    """Load: a constant torque resisting the rotation, and an inertia."""

    rotor: str = param()
    node: int | None = param(None, ge=0)
    position: float | None = param(None, unit="m")
    torque: float = param(0.0, unit="N m", ge=0)
    inertia: float = param(0.0, unit="kg m^2", ge=0)
    damping: float = param(0.0, unit="N m s/rad", ge=0, doc="torque-speed slope of the load (viscous)")
    quadratic: float = param(0.0, unit="N m s^2/rad^2", ge=0, doc="startup: load torque + q Omega^2 (pump, fan)")


@dataclass(frozen=True)
class GearboxSpec:
    """Model tables of a gearbox config (analysis tables are read by the verbs)."""

    rotor: tuple[RotorSpec, ...] = param()
    gear_mesh: tuple[MeshSpec, ...] = param(())
    coupling: tuple[CouplingSpec, ...] = param(())
    drive: DriveSpec | None = param(None)
    load: LoadSpec | None = param(None)


MODEL_KEYS = tuple(f.name for f in dataclasses.fields(GearboxSpec))


@dataclass(frozen=True)
class PlacedRotor:
    """An FE rotor in the gearbox: model, centre [m], sense (+1 ccw), speed per drive speed."""

    name: str
    rotor: Rotor
    center: np.ndarray
    sense: int
    ratio: float
    torsion: bool
    axial: bool = False  # an axial DOF w per node (rotors carrying a helical mesh)


@dataclass(frozen=True)
class MeshElement:
    """A built mesh: the two gear stations, the gear mesh data and the line of action.

    ``driver``/``driven`` are (rotor index, node); ``normal`` is the line of action n (force on
    the driven gear +F n); ``sense`` is s_d; ``radius`` = (r_bd, r_bf); ``backlash`` [m] along n.
    Helical meshes: ``helix`` is the base helix angle beta_b [rad], ``axial_sign`` sigma (the flank
    normal is ``cos(beta_b) n + sigma sin(beta_b) e_z``), ``arms`` the vectors (x, y) [m] from the
    driver's and the driven gear's centre to the pitch point (docs/geared-rotor.md, "Helical
    meshes"), ``offset`` the axial position z_c [m] of the contact from mid-face (the load
    distribution's centroid, :mod:`.face_load`); 0, 0, (), 0 for spur meshes.
    """

    gear: Any  # rotaflex.gear.GearMesh
    driver: tuple[int, int]
    driven: tuple[int, int]
    pinion_is_driver: bool
    normal: np.ndarray
    sense: int
    radius: tuple[float, float]
    damping: float
    backlash: float
    spec: MeshSpec
    helix: float = 0.0
    axial_sign: int = 0
    arms: tuple = ()
    offset: float = 0.0

    @property
    def k_mean(self) -> float:
        return self.gear.mean_stiffness


@dataclass(frozen=True)
class Gearbox:
    """Geared rotor system (frozen, SI): placed rotors, meshes, drive and load.

    Build with :meth:`from_mapping` / :meth:`from_toml`. ``rotors[i].ratio`` is rotor i's speed
    per unit drive-rotor speed; the drive rotor has ratio 1.
    """

    rotors: tuple[PlacedRotor, ...]
    meshes: tuple[MeshElement, ...]
    drive: tuple[int, int] | None
    drive_kind: str
    load: tuple[int, int] | None
    load_torque: float
    spec: GearboxSpec = field(repr=False)
    couplings: tuple[CouplingElement, ...] = ()

    @classmethod
    def from_mapping(cls, data: Mapping[str, Any], base: str | Path | None = None) -> Gearbox:
        """Build from parsed TOML (model keys only; ``base``: directory of relative pair files)."""
        data = {k: v for k, v in data.items() if k in MODEL_KEYS}
        rotors_raw = data.get("rotor")
        if not isinstance(rotors_raw, list) or not rotors_raw:
            raise InputError("rotor", "<missing>" if rotors_raw is None else rotors_raw, "one or more [[rotor]] tables")
        pairs = []
        meshes_raw = data.get("gear_mesh", [])
        if not isinstance(meshes_raw, list):
            raise InputError("gear_mesh", meshes_raw, "[[gear_mesh]] tables")
        meshes_clean = []
        for i, m in enumerate(meshes_raw):
            if not isinstance(m, Mapping):
                raise InputError(f"gear_mesh[{i}]", m, "a table")
            pairs.append(_pair(m, f"gear_mesh[{i}]", base, _centres_apart(rotors_raw, m)))
            meshes_clean.append({k: v for k, v in m.items() if k not in PAIR_KEYS})
        rotor_specs, rotor_models = [], []
        for i, r in enumerate(rotors_raw):
            if not isinstance(r, Mapping):
                raise InputError(f"rotor[{i}]", r, "a table")
            where = f"rotor[{i}]"
            model = Rotor.from_mapping({k: v for k, v in r.items() if k in ROTOR_KEYS}, where)
            rotor_models.append(model)
            plain = dataclasses.asdict(model)  # the rotor tables as the FE reader normalised them
            rotor_specs.append({**r, **{k: plain[k] for k in ROTOR_KEYS if k in r}})
        spec = from_mapping(GearboxSpec, {**data, "rotor": rotor_specs, "gear_mesh": meshes_clean})
        return _build(spec, rotor_models, pairs)

    @classmethod
    def from_toml(cls, path: str | Path) -> Gearbox:
        """Read the model tables of a gearbox TOML file."""
        return cls.from_mapping(load_toml(path), Path(path).parent)

    # -- derived ---------------------------------------------------------------------------
    @functools.cached_property
    def layout(self) -> list[tuple[int, int, int]]:
        """Per rotor (offset, n lateral DOFs, n torsional DOFs) in the global DOF vector; a rotor
        with axial DOFs (:attr:`PlacedRotor.axial`) has its n_nodes axial DOFs after its twists."""
        out, off = [], 0
        for pr in self.rotors:
            nl, nt = pr.rotor.n_dof, pr.rotor.n_nodes if pr.torsion else 0
            out.append((off, nl, nt))
            off += nl + nt + (pr.rotor.n_nodes if pr.axial else 0)
        return out

    @property
    def n_dof(self) -> int:
        off, nl, nt = self.layout[-1]
        return off + nl + nt + (self.rotors[-1].rotor.n_nodes if self.rotors[-1].axial else 0)

    @property
    def axial(self) -> bool:
        """True when a rotor carries axial DOFs (a helical mesh)."""
        return any(pr.axial for pr in self.rotors)

    def axial_dof(self, rotor: int, node: int) -> int:
        """Global index of the axial displacement w of a node (after the rotor's twists; only
        rotors carrying a helical mesh have it)."""
        off, nl, nt = self.layout[rotor]
        if not self.rotors[rotor].axial:
            raise InputError(f"rotor[{rotor}]", self.rotors[rotor].name, "a rotor carrying a helical gear mesh")
        return off + nl + nt + node

    def rotor_index(self, name: str | None, key: str) -> int:
        """Index of the rotor called ``name`` (None: the only rotor of a one-rotor machine).

        Raises
        ------
        InputError
            Naming ``key`` (the config key as the user wrote it) and the machine's rotor names.
        """
        names = [pr.name for pr in self.rotors]
        if name is None and len(names) == 1:
            return 0
        if name not in names:
            raise InputError(key, "<missing>" if name is None else name, "one of " + ", ".join(map(repr, names)))
        return names.index(name)

    def lateral_dof(self, rotor: int, node: int, axis: int = 0) -> int:
        """Global index of lateral DOF ``axis`` (0 x, 1 y, 2 theta_x, 3 theta_y) of a node."""
        return self.layout[rotor][0] + 4 * node + axis

    def torsion_dof(self, rotor: int, node: int) -> int:
        """Global index of the twist of a node (the rotor must have torsion)."""
        off, nl, nt = self.layout[rotor]
        if not nt:
            raise InputError(f"rotor[{rotor}].torsion", False, "true for a twist DOF")
        return off + nl + node

    def speeds(self, drive_speed: float) -> np.ndarray:
        """Signed spin speeds [rad/s] of the rotors (+: counter-clockwise) at a drive speed [rad/s]."""
        return np.array([pr.sense * pr.ratio * drive_speed for pr in self.rotors])

    def mesh_frequency(self, mesh: int, drive_speed: float) -> float:
        """Mesh angular frequency ``z_p |Omega_p|`` [rad/s] of a mesh at a drive speed [rad/s]."""
        m = self.meshes[mesh]
        rp = m.driver[0] if m.pinion_is_driver else m.driven[0]
        return m.gear.teeth[0] * self.rotors[rp].ratio * drive_speed

    def with_mesh_stiffness(self, factor: float) -> Gearbox:
        """Copy with every mesh's stiffness table scaled by ``factor`` (0: meshes removed)."""
        if factor == 0:
            return dataclasses.replace(self, meshes=())
        out = []
        for m in self.meshes:
            t = m.gear.table
            table = dataclasses.replace(t, stiffness=t.stiffness * factor)
            out.append(dataclasses.replace(m, gear=dataclasses.replace(m.gear, table=table)))
        return dataclasses.replace(self, meshes=tuple(out))

    def to_mapping(self) -> dict[str, Any]:
        return dataclasses.asdict(self.spec)


def _centres_apart(rotors_raw, m: Mapping) -> tuple[float, str] | None:
    """Distance [m] between the centres of a mesh's two rotors and the key of the wheel rotor's
    ``center`` (None when a rotor or its centre is not there: the build names what is missing)."""
    centre = {}
    for j, r in enumerate(rotors_raw):
        if isinstance(r, Mapping) and isinstance(r.get("center"), (list, tuple)) and len(r["center"]) == 2:
            centre.setdefault(r.get("name"), (j, np.asarray(r["center"], float)))
    p, w = centre.get(m.get("pinion_rotor")), centre.get(m.get("wheel_rotor"))
    if p is None or w is None or not np.all(np.isfinite(p[1])) or not np.all(np.isfinite(w[1])):
        return None
    return float(np.hypot(*(w[1] - p[1]))), f"rotor[{w[0]}].center"


def _pair(m: Mapping, where: str, base, centres: tuple[float, str] | None = None):
    """The PairSpec of a [[gear_mesh]] table: inline pair keys or ``pair_file``.

    ``centres`` (distance of the two rotors' centres [m], the wheel rotor's ``center`` key): the
    working centre distance when the pair gives neither ``center_distance`` nor ``backlash``,
    so the rotor centres alone place the pair (one fact, written once).
    """
    from rotaflex.gear import pair_from_mapping

    inline = {k: v for k, v in m.items() if k in PAIR_KEYS}
    path = m.get("pair_file")
    if path is not None:
        if not isinstance(path, str):
            raise InputError(f"{where}.pair_file", path, "a path to a TOML file with [pinion]/[wheel]")
        p = Path(path)
        if not p.is_absolute() and base is not None:
            p = Path(base) / p
        cfg = load_toml(p, f"{where}.pair_file", path)
        inline = {**{k: v for k, v in cfg.items() if k in PAIR_KEYS}, **inline}
    if "pinion" not in inline or "wheel" not in inline:
        raise InputError(f"{where}.pinion", "<missing>", "[pinion] and [wheel] tables (or pair_file)")
    if centres is not None and "center_distance" not in inline and "backlash" not in inline:
        try:
            return _system_pair(pair_from_mapping({**inline, "center_distance": centres[0]}, where), where)
        except InputError as err:  # the user wrote the centres, not a centre distance: name those
            if not err.field.endswith("center_distance"):
                raise
            raise InputError(centres[1], f"{centres[0]:.6g} m from the pinion's rotor", err.allowed) from None
    return _system_pair(pair_from_mapping(inline, where), where)


def _system_pair(pair, where: str):
    """A pair the geared-rotor model takes: spur without lead modifications, or helical (lead
    modifications move its contact point, :mod:`.face_load`)."""
    return pair if pair.helical else pair.spur_only("system", where)


def _contact_offset(m: MeshSpec, pair, gm, where: str) -> float:
    """Axial offset z_c [m] of a mesh's contact from mid-face: 0 at ``contact_point =
    "mid_face"`` (the default without lead modifications and misalignment), else the centroid of
    the sliced face's load at the mesh's mean load (:mod:`.face_load`)."""
    mode, f = m.contact_point, m.face or FaceConfig()
    if not pair.helical:
        if mode == "load_centroid":
            raise InputError(f"{where}.contact_point", mode, "'mid_face' or omitted for a spur pair (helical only)")
        if m.face is not None:
            raise InputError(f"{where}.face", "a table", "omitted for a spur pair (helical meshes only)")
        return 0.0
    if mode is None:
        mode = "load_centroid" if f.misalignment or _lead(pair) else "mid_face"
    if mode == "mid_face":
        return 0.0
    from rotaflex.gear.static.helical import face_model
    from rotaflex.system.face_load import contact_offset, face_line

    try:
        face = face_model(pair, f.slices, f.coupling_length_coef, f.misalignment, where=f"{where}.face")
    except InputError as err:  # the gear package names the pair's keys: put them under the mesh
        raise err.relocated(where) from None
    return contact_offset(face_line(pair, gm, face, m.source, m.mesh_preset), face)


def _lead(pair) -> bool:
    """True when a gear of the pair has an active lead modification."""
    return any(g.lead is not None and g.lead.active for g in (pair.pinion, pair.wheel))


def _station(rotor: Rotor, node, position, where, keys=("node", "position")) -> int:
    return rotor.station(node, position, where, True, keys)


def _build(spec: GearboxSpec, models: list[Rotor], pairs: list) -> Gearbox:
    """Resolve names, stations, senses, speed ratios, line of action; check the geometry."""
    from rotaflex.gear import gear_mesh

    names = [r.name for r in spec.rotor]
    for i, n in enumerate(names):
        if n in names[:i]:
            raise InputError(f"rotor[{i}].name", n, "a name not used by another rotor")

    def index(name, where):
        if name not in names:
            raise InputError(where, name, "a rotor name, one of " + ", ".join(map(repr, names)))
        return names.index(name)

    models = list(models)
    if spec.drive is None:
        raise InputError("drive", "<missing>", "a [drive] table (rotor, node, kind)")
    d_r = index(spec.drive.rotor, "drive.rotor")
    d_n = _station(models[d_r], spec.drive.node, spec.drive.position, "drive")
    load = None
    if spec.load is not None:
        l_r = index(spec.load.rotor, "load.rotor")
        load = (l_r, _station(models[l_r], spec.load.node, spec.load.position, "load"))
    # mesh stations and the rotor graph
    stations = []
    for i, m in enumerate(spec.gear_mesh):
        w = f"gear_mesh[{i}]"
        rp, rw = index(m.pinion_rotor, f"{w}.pinion_rotor"), index(m.wheel_rotor, f"{w}.wheel_rotor")
        if rp == rw:
            raise InputError(f"{w}.wheel_rotor", m.wheel_rotor, "a rotor other than the pinion's")
        npn = _station(models[rp], m.pinion_node, m.pinion_position, w, ("pinion_node", "pinion_position"))
        nwh = _station(models[rw], m.wheel_node, m.wheel_position, w, ("wheel_node", "wheel_position"))
        for r, key in ((rp, "pinion"), (rw, "wheel")):
            if not spec.rotor[r].torsion:
                raise InputError(
                    f"{w}.{key}_node",
                    npn if key == "pinion" else nwh,
                    f"a node with a torsional DOF (rotor {names[r]!r} has torsion = false)",
                )
        stations.append((rp, npn, rw, nwh))
    joints = [_coupling_stations(spec, models, i, index) for i in range(len(spec.coupling))]
    # speeds and senses by walking the meshes and couplings from the drive rotor
    sense = {d_r: 1 if spec.drive.rotation == "ccw" else -1}
    ratio = {d_r: 1.0}
    toward = {}  # mesh -> True if power flows pinion -> wheel
    frontier = [d_r]
    while frontier:
        r = frontier.pop()
        for (ra, _), (rb, _) in joints:  # a coupling: the same speed and sense on both sides
            if r in (ra, rb) and (other := rb if r == ra else ra) not in ratio:
                ratio[other], sense[other] = ratio[r], sense[r]
                frontier.append(other)
        for i, (rp, _, rw, _) in enumerate(stations):
            if i in toward or r not in (rp, rw):
                continue
            other = rw if r == rp else rp
            z = pairs[i].wheel.teeth / pairs[i].pinion.teeth
            rat = ratio[r] / z if r == rp else ratio[r] * z
            toward[i] = r == rp
            if other in ratio:
                if abs(ratio[other] - rat) > 1e-9 * rat or sense[other] != -sense[r]:
                    raise InputError(
                        f"gear_mesh[{i}]", names[other], "a gear train without loops of conflicting ratios"
                    )
                continue
            ratio[other], sense[other] = rat, -sense[r]
            frontier.append(other)
    for i, r in enumerate(spec.rotor):
        if i not in ratio:
            raise InputError(
                f"rotor[{i}].name", r.name, "a rotor joined to the drive rotor by gear meshes or couplings"
            )
    _check_speeds(spec, ratio, sense, d_r, names)
    # load torque -> default pinion torque of each mesh's table
    t_load = spec.load.torque if spec.load is not None else 0.0
    built = []
    for i, (m, pair, (rp, npn, rw, nwh)) in enumerate(zip(spec.gear_mesh, pairs, stations, strict=True)):
        w = f"gear_mesh[{i}]"
        want = "pinion" if toward[i] else "wheel"
        if pair.driver != want:
            raise InputError(
                f"{w}.driver", pair.driver, f"{want!r}: the [drive] rotor {names[d_r]!r} turns the {want} of this pair"
            )
        torque = m.torque
        if torque is None:
            if load is None or t_load <= 0 or load[0] not in (rp, rw):
                raise InputError(f"{w}.torque", "<missing>", "a pinion torque [N m] > 0 (or a [load] on this mesh)")
            # the load torque seen at the pinion through this mesh (rigid gears, no losses)
            torque = t_load if load[0] == rp else t_load / (pair.wheel.teeth / pair.pinion.teeth)
        _check_te(m, pair, w)
        gm = gear_mesh(
            pair,
            torque,
            source=m.source,
            table_points=m.table_points,
            mesh_preset=m.mesh_preset,
            k_mean=m.k_mean,
            k_harmonics=m.k_harmonics,
            te_harmonics=m.te_harmonics,
            k_pair=m.k_pair,
            unloaded_te_pp=m.unloaded_te_pp,
            where=w,
        )
        cp, cw = np.asarray(spec.rotor[rp].center, float), np.asarray(spec.rotor[rw].center, float)
        dist = float(np.hypot(*(cw - cp)))
        a = gm.center_distance
        if abs(dist - a) > 1e-6 * a:
            raise InputError(
                f"rotor[{rw}].center",
                list(spec.rotor[rw].center),
                f"a centre {a:.6g} m from rotor {names[rp]!r} (the working centre distance of "
                f"gear_mesh[{i}]; the centres are {dist:.6g} m apart)",
            )
        d, f = ((rp, npn), (rw, nwh)) if toward[i] else ((rw, nwh), (rp, npn))
        rb = gm.base_radius if toward[i] else gm.base_radius[::-1]
        s = sense[d[0]]
        cd, cf = np.asarray(spec.rotor[d[0]].center, float), np.asarray(spec.rotor[f[0]].center, float)
        gam = math.atan2(*(cf - cd)[::-1])
        alpha = gm.pressure_angle
        loc = np.array([math.sin(alpha), s * math.cos(alpha)])
        rot = np.array([[math.cos(gam), -math.sin(gam)], [math.sin(gam), math.cos(gam)]])
        c_m = mesh_damping(gm.mean_stiffness, gm.inertia, gm.base_radius, m.damping_ratio)
        backlash = pair.normal_backlash_at(a) if m.back_contact else -1.0
        if m.blanks:
            for r, node, k, key in ((rp, npn, 0, "pinion"), (rw, nwh, 1, "wheel")):
                mass = gm.mass[k]
                if mass is None:
                    raise InputError(
                        f"{w}.{key}.blank.inertia",
                        gm.inertia[k],
                        "a blank given by geometry (for its mass) or blanks = false with a [[rotor.disk]]",
                    )
                ip = gm.inertia[k]
                disk = Disk(node=node, mass=mass, Id=0.5 * ip, Ip=ip)  # thin disk: Id = Ip / 2
                models[r] = dataclasses.replace(models[r], disk=(*models[r].disk, disk))
        helical = _helical_terms(pair, toward[i], s, gam, rb, alpha) if pair.helical else {}
        offset = _contact_offset(m, pair, gm, w)
        if offset:
            helical["offset"] = offset
        built.append(
            MeshElement(gm, d, f, toward[i], rot @ loc, s, (float(rb[0]), float(rb[1])), c_m, backlash, m, **helical)
        )
    couplings = []
    for i, (c, (a, b)) in enumerate(zip(spec.coupling, joints, strict=True)):
        for (r, node), part in ((a, c.split), (b, 1.0 - c.split)):  # the coupling's mass on its hubs
            if part * (c.mass + c.Ip + c.Id) > 0:
                hub = Disk(node=node, mass=part * c.mass, Id=part * c.Id, Ip=part * c.Ip)
                models[r] = dataclasses.replace(models[r], disk=(*models[r].disk, hub))
        torsion = spec.rotor[a[0]].torsion and spec.rotor[b[0]].torsion
        couplings.append(coupling_element(c, a, b, torsion, c.name or f"coupling{i}"))
    extra = [((d_r, d_n), spec.drive.inertia), (load, spec.load.inertia if spec.load else 0.0)]
    for st, j in extra:  # motor and load inertias as polar-only disks
        if st is not None and j:
            models[st[0]] = dataclasses.replace(
                models[st[0]], disk=(*models[st[0]].disk, Disk(node=st[1], mass=0.0, Id=0.0, Ip=j))
            )
    if spec.drive is not None and not spec.rotor[d_r].torsion:
        raise InputError("drive.rotor", spec.drive.rotor, "a rotor with torsion = true")
    if load is not None and not spec.rotor[load[0]].torsion and spec.load.torque > 0:
        raise InputError("load.rotor", spec.load.rotor, "a rotor with torsion = true (a load torque twists it)")
    axial = _axial_rotors(spec, built, names)
    placed = tuple(
        PlacedRotor(r.name, models[i], np.asarray(r.center, float), sense[i], ratio[i], r.torsion, i in axial)
        for i, r in enumerate(spec.rotor)
    )
    return Gearbox(placed, tuple(built), (d_r, d_n), spec.drive.kind, load, t_load, spec, tuple(couplings))


def _helical_terms(pair, pinion_drives: bool, s_d: int, gamma: float, rb, alpha: float) -> dict:
    """MeshElement fields of a helical mesh: base helix angle, axial sign, pitch-point arms.

    The flank normal at the contact is ``N = cos(beta_b) n - h_d s_d sin(beta_b) e_z`` (h_d = +1
    for a right-hand driver): N is normal to the helix through the contact, whose tangent is
    ``e_z + h_d tan(beta) / r e_z x r_P`` (derivation in docs/geared-rotor.md).
    """
    hand = (pair.pinion if pinion_drives else pair.wheel).hand
    u = np.array([math.cos(gamma), math.sin(gamma)])  # driver centre -> driven centre
    r_wd, r_wf = rb[0] / math.cos(alpha), rb[1] / math.cos(alpha)  # operating pitch radii
    return {
        "helix": float(pair.base_helix_angle),
        "axial_sign": -(1 if hand == "right" else -1) * s_d,
        "arms": (r_wd * u, -r_wf * u),
    }


def _axial_rotors(spec: GearboxSpec, built, names) -> set[int]:
    """Rotors carrying a helical mesh (they get axial DOFs); each needs a thrust support."""
    out = {}
    for i, m in enumerate(built):
        if m.helix > 0:
            for r, _ in (m.driver, m.driven):
                out.setdefault(r, i)
    for r, i in out.items():
        if not any(b.kzz > 0 for b in spec.rotor[r].bearing):
            raise InputError(
                f"rotor[{r}].bearing[].kzz",
                "<missing>",
                f"an axial (thrust) stiffness > 0 [N/m] on a bearing of rotor {names[r]!r}: it carries the "
                f"helical gear_mesh[{i}], whose axial force needs an axial support",
            )
    return set(out)


def _coupling_stations(spec: GearboxSpec, models, i: int, index) -> tuple[tuple[int, int], tuple[int, int]]:
    """Hub stations (rotor, node) of ``[[coupling]]`` i, checked: two rotors on one axis, a
    torsional stiffness where both rotors twist, no stiffness keys on a rigid coupling."""
    c, w = spec.coupling[i], f"coupling[{i}]"
    ra, rb = index(c.rotor_a, f"{w}.rotor_a"), index(c.rotor_b, f"{w}.rotor_b")
    if ra == rb:
        raise InputError(f"{w}.rotor_b", c.rotor_b, "a rotor other than rotor_a")
    na = _station(models[ra], c.node_a, c.position_a, w, ("node_a", "position_a"))
    nb = _station(models[rb], c.node_b, c.position_b, w, ("node_b", "position_b"))
    ca, cb = np.asarray(spec.rotor[ra].center, float), np.asarray(spec.rotor[rb].center, float)
    if np.hypot(*(ca - cb)) > 1e-9 * max(1.0, float(np.hypot(*ca))):
        raise InputError(
            f"rotor[{rb}].center", list(spec.rotor[rb].center), f"{list(ca)}: a coupling joins rotors on one axis"
        )
    torsion = (spec.rotor[ra].torsion, spec.rotor[rb].torsion)
    if c.rigid:
        for key in ("torsional_stiffness", "lateral_stiffness", "angular_stiffness"):
            if getattr(c, key):
                raise InputError(
                    f"{w}.{key}", getattr(c, key), "no stiffness on a rigid coupling (rigid = false for springs)"
                )
        if torsion[0] != torsion[1]:
            raise InputError(f"rotor[{rb}].torsion", torsion[1], f"{torsion[0]}: a rigid coupling joins like rotors")
    elif all(torsion) and c.torsional_stiffness is None:
        raise InputError(
            f"{w}.torsional_stiffness", "<missing>", "a torsional stiffness [N m/rad] > 0 (or rigid = true)"
        )
    return (ra, na), (rb, nb)


def _check_te(m: MeshSpec, pair, where: str) -> None:
    """Refuse a transmission error larger than a tenth of the module: the worst accuracy grade of
    ISO 1328-1 (grade 11 at module 3 mm: total profile deviation ~0.1 mm, 0.03 module) stays well
    below it, and an error of a whole module would move the contact off the working flank."""
    limit = 0.1 * min(g.module for g in pair.gears)
    for key, value, te in (
        ("unloaded_te_pp", m.unloaded_te_pp, m.unloaded_te_pp),
        ("te_harmonics", list(m.te_harmonics), 2 * sum(abs(x) for x in m.te_harmonics)),
    ):
        if not te <= limit:
            raise InputError(
                f"{where}.{key}", value, f"a transmission error (peak-to-peak) of at most {limit:.4g} m (0.1 module)"
            )


def _check_speeds(spec, ratio, sense, d_r, names) -> None:
    """Given rotor speeds and senses must agree with the gear ratios and the drive's sense."""
    given = [(i, r.speed_rpm) for i, r in enumerate(spec.rotor) if r.speed_rpm is not None]
    if given:
        i0, s0 = given[0]
        base = s0 / ratio[i0]
        for i, s in given[1:]:
            want = base * ratio[i]
            if abs(s - want) > 1e-6 * want:
                raise InputError(
                    f"rotor[{i}].speed_rpm",
                    s,
                    f"{want:.6g} rpm: rotor {names[i0]!r} turns at {s0:g} rpm and the gear ratios fix the rest",
                )
    for i, r in enumerate(spec.rotor):
        if r.rotation is not None and (1 if r.rotation == "ccw" else -1) != sense[i]:
            want = "ccw" if sense[i] > 0 else "cw"
            raise InputError(
                f"rotor[{i}].rotation", r.rotation, f"{want!r}: set by the drive's sense and the external meshes"
            )


def drive_speed_rpm(box: Gearbox) -> float | None:
    """Nominal drive-rotor speed [rpm] from the rotors' ``speed_rpm`` (None if none given)."""
    for pr, r in zip(box.rotors, box.spec.rotor, strict=True):
        if r.speed_rpm is not None:
            return r.speed_rpm / pr.ratio
    return None


__all__ = ["Gearbox", "GearboxSpec", "MeshElement", "PlacedRotor", "drive_speed_rpm"]
