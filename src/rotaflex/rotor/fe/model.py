"""FE rotor model: frozen data built from ``[[shaft]]``, ``[[disk]]``, ``[[bearing]]`` tables.

Shaft sections are laid end to end along z (each from ``start`` or the previous section's end,
to ``end`` or ``start + length``) and split into ``elements`` equal Timoshenko elements. Nodes
sit at the element ends and are numbered 0, 1, ... from the left. Disks, point masses and
bearings sit at a station given by ``node`` or by ``position`` (an axial coordinate that must
coincide with a node). All values are SI; bearing tables are keyed by ``speed_rpm`` and
converted to rad/s once, here.
"""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

import numpy as np

from rotaflex.core.config import from_mapping, load_toml, param
from rotaflex.core.errors import InputError
from rotaflex.core.units import rad_s_to_rpm
from rotaflex.rotor.fe.bearings import registry
from rotaflex.rotor.fe.bearings.fluid_film import FluidFilm
from rotaflex.rotor.fe.bearings.labyrinth import Labyrinth
from rotaflex.rotor.fe.bearings.liquid_seal import LiquidSeal
from rotaflex.rotor.fe.bearings.magnetic import Magnetic
from rotaflex.rotor.fe.bearings.static_load import resolve_static_loads
from rotaflex.rotor.fe.elements import BearingElement, DiskElement, PointMassElement, shaft_matrices
from rotaflex.rotor.fe.elements.bearing import COEFFICIENTS, MASS_COEFFICIENTS, MAX_BEARING, flat
from rotaflex.rotor.fe.layout import NDOF_NODE, bearing_path, table_key
from rotaflex.rotor.fe.materials import Material, material

#: plausibility bounds of the inputs (SI). Lengths beyond them are almost always millimetres typed
#: as metres; moduli and coefficients beyond them overflow the assembly or its conditioning.
MAX_DIAMETER = {"shaft": 5.0, "disk": 25.0}  # m (large turbine-generator bodies ~2 m, hydro rotors ~20 m)
MAX_LENGTH = 200.0  # m, whole shaft
# Pa, kg/m^3: open below (a soft link or a massless shaft is a legitimate idealisation) and capped
# far above any solid (diamond 1.2e12 Pa, osmium 22.6e3 kg/m^3), where a "rigid" section stays solvable
MODULUS_RANGE = (0.0, 1e20)
DENSITY_RANGE = (0.0, 1e6)


#: default largest model (1000 shaft elements): a dense 8000-state eigenproblem takes minutes
DEFAULT_MAX_DOF = 4004
RIGID_FACTOR = 1e8  #: stiffness of a rigid section relative to the model's stiffest other part


def _not_mm(where: str, value: float, limit: float) -> None:
    """InputError if a length [m] exceeds ``limit``: it looks like millimetres."""
    if value is not None and value > limit:
        raise InputError(
            where,
            value,
            f"a length in metres <= {limit:g} m; {value:g} m looks like millimetres "
            f"(write {value / 1000:g} for {value:g} mm)",
        )


@dataclass(frozen=True)
class Shaft:
    """A shaft section of constant or linearly tapered, solid or hollow, circular section."""

    outer_diameter: float = param(unit="m", gt=0, doc="outer diameter at the left end")
    inner_diameter: float = param(0.0, unit="m", ge=0, doc="inner diameter at the left end (0: solid)")
    outer_diameter_right: float | None = param(None, unit="m", gt=0, doc="outer diameter at the right end (taper)")
    inner_diameter_right: float | None = param(None, unit="m", ge=0, doc="inner diameter at the right end")
    length: float | None = param(None, unit="m", gt=0, doc="section length (or give end)")
    start: float | None = param(None, unit="m", doc="axial start (default: previous section's end, or 0)")
    end: float | None = param(None, unit="m", doc="axial end (or give length)")
    elements: int = param(1, ge=1, doc="number of equal elements the section is split into")
    material: str = param("steel", doc="material name (steel, aluminium, titanium or a [material.<name>])")
    E: float | None = param(None, unit="Pa", gt=0, doc="Young's modulus (overrides the material)")
    G: float | None = param(None, unit="Pa", gt=0, doc="shear modulus (overrides the material)")
    rho: float | None = param(None, unit="kg/m^3", gt=0, doc="density (overrides the material)")
    shear_coefficient: float | None = param(None, gt=0, doc="Timoshenko kappa (default: Cowper's value)")
    rigid: bool = param(False, doc="rigid section: keeps its mass, stiffness set 1e8 x the model's stiffest other part")
    layer: str = param("", doc="coaxial layer: '' is the main shaft (sets the nodes); another name lies on its nodes")
    stiffness: bool = param(True, doc="the section adds its stiffness (false: a mass-only layer)")
    mass: bool = param(True, doc="the section adds its mass, rotary and polar inertia (false: stiffness only)")
    rayleigh_alpha: float = param(0.0, unit="1/s", ge=0, doc="Rayleigh damping alpha M of the section")
    rayleigh_beta: float = param(0.0, unit="s", ge=0, doc="Rayleigh damping beta K of the section")


@dataclass(frozen=True)
class Disk:
    """Rigid disk given by inertias (mass, Id, Ip) or by geometry (width, diameters, material)."""

    node: int | None = param(None, ge=0, doc="node number (or give position)")
    position: float | None = param(None, unit="m", doc="axial position of a node")
    mass: float | None = param(None, unit="kg", ge=0)
    Id: float | None = param(None, unit="kg m^2", ge=0, doc="diametral moment of inertia")
    Ip: float | None = param(None, unit="kg m^2", ge=0, doc="polar moment of inertia")
    width: float | None = param(None, unit="m", gt=0)
    outer_diameter: float | None = param(None, unit="m", gt=0)
    inner_diameter: float = param(0.0, unit="m", ge=0)
    material: str = param("steel")
    rho: float | None = param(None, unit="kg/m^3", gt=0, doc="density (overrides the material)")
    rayleigh_alpha: float = param(0.0, unit="1/s", ge=0, doc="Rayleigh damping alpha M of the disk")


@dataclass(frozen=True)
class PointMass:
    """Lumped translational mass at a node."""

    mass: float = param(unit="kg", gt=0)
    node: int | None = param(None, ge=0)
    position: float | None = param(None, unit="m")


@dataclass(frozen=True)
class Pedestal:
    """A support off the shaft: a mass on springs and dampers to ground, between a bearing and ground."""

    mass: float = param(unit="kg", gt=0, doc="pedestal mass (both directions)")
    mass_y: float | None = param(None, unit="kg", gt=0, doc="mass in y if it differs from x")
    kxx: float = param(0.0, unit="N/m", doc="stiffness to ground in x")
    kyy: float = param(0.0, unit="N/m", doc="stiffness to ground in y")
    cxx: float = param(0.0, unit="N s/m", doc="damping to ground in x")
    cyy: float = param(0.0, unit="N s/m", doc="damping to ground in y")


#: a coefficient is a number, a list over speed_rpm (or over whirl_hz), or rows over speed of lists over whirl_hz
Coefficient = tuple[float | tuple[float, ...], ...]


@dataclass(frozen=True)
class Bearing:
    """Linear bearing or seal (each coefficient a number or a list over ``speed_rpm`` and/or
    ``whirl_hz``), or a fluid-film journal bearing whose coefficients are computed (``fluid_film``
    sub-table, docs/fluid-film-bearings.md); optionally on a ``pedestal``."""

    node: int | None = param(None, ge=0, doc="node number (or give position)")
    position: float | None = param(None, unit="m")
    to_node: int | None = param(None, ge=0, doc="second node for a support between two nodes (default: ground)")
    to_position: float | None = param(None, unit="m")
    kxx: Coefficient = param((0.0,), unit="N/m")
    kxy: Coefficient = param((0.0,), unit="N/m")
    kyx: Coefficient = param((0.0,), unit="N/m")
    kyy: Coefficient = param((0.0,), unit="N/m")
    cxx: Coefficient = param((0.0,), unit="N s/m")
    cxy: Coefficient = param((0.0,), unit="N s/m")
    cyx: Coefficient = param((0.0,), unit="N s/m")
    cyy: Coefficient = param((0.0,), unit="N s/m")
    mxx: float = param(0.0, unit="kg", doc="mass coefficient (constant)")
    mxy: float = param(0.0, unit="kg")
    myx: float = param(0.0, unit="kg")
    myy: float = param(0.0, unit="kg")
    kzz: float = param(
        0.0,
        unit="N/m",
        ge=0,
        le=MAX_BEARING["k"],
        doc="axial (thrust) stiffness, constant (axial DOFs, docs/geared-rotor.md)",
    )
    czz: float = param(0.0, unit="N s/m", ge=0, le=MAX_BEARING["c"], doc="axial (thrust) damping, constant")
    speed_rpm: tuple[float, ...] | None = param(None, unit="rpm", ge=0, doc="speeds of tabulated coefficients")
    whirl_hz: tuple[float, ...] | None = param(
        None, unit="Hz", ge=0, doc="whirl frequencies of coefficients tabulated over frequency (frequency dependent)"
    )
    interpolation: Literal["linear", "pchip"] = param("linear", doc="table interpolation (pchip: monotone cubic)")
    extrapolation: Literal["refuse", "hold", "linear"] = param(
        "refuse", doc="outside a table: refuse, hold the end values, or extend the end slope"
    )
    name: str = param("", doc="label")
    fluid_film: FluidFilm | None = param(None, doc="plain journal bearing: coefficients computed (no k/c keys)")
    pedestal: Pedestal | None = param(None, doc="support mass on springs between the bearing and ground")
    magnetic: Magnetic | None = param(None, doc="active magnetic bearing: K(w), C(w) (docs/stability.md)")
    labyrinth: Labyrinth | None = param(None, doc="gas labyrinth seal: bulk-flow K, k, C, c (docs/stability.md)")
    liquid_seal: LiquidSeal | None = param(None, doc="liquid annular seal: K, k, C, c, M (docs/stability.md)")

    def __post_init__(self):
        for key in COEFFICIENTS:  # Python callers may pass plain numbers
            v = getattr(self, key)
            if np.isscalar(v):
                object.__setattr__(self, key, (float(v),))
        for key in ("speed_rpm", "whirl_hz"):
            if getattr(self, key) is not None and np.isscalar(getattr(self, key)):
                object.__setattr__(self, key, (float(getattr(self, key)),))


@dataclass(frozen=True)
class Rotor:
    """Rotor-bearing FE model (frozen). Build from TOML with :meth:`from_toml` or directly.

    Parameters
    ----------
    shaft : tuple of Shaft
        Sections end to end along z, left to right.
    disk, point_mass, bearing : tuples of Disk, PointMass, Bearing
    material : dict of Material
        User materials by name (``[material.<name>]`` with E, G, rho).
    free : bool
        Allow rigid-body modes (a free-free rotor). Without it a singular stiffness is an error.

    Examples
    --------
    >>> rotor = Rotor(shaft=(Shaft(outer_diameter=0.05, length=1.5, elements=6),),
    ...               disk=(Disk(position=0.5, mass=32.6, Id=0.178, Ip=0.329),),
    ...               bearing=(Bearing(node=0, kxx=1e6, kyy=1e6), Bearing(node=6, kxx=1e6, kyy=1e6)))
    >>> rotor.n_dof
    28
    """

    shaft: tuple[Shaft, ...] = param()
    disk: tuple[Disk, ...] = param(())
    point_mass: tuple[PointMass, ...] = param(())
    bearing: tuple[Bearing, ...] = param(())
    material: dict[str, Material] = param({})
    free: bool = param(False, doc="allow rigid-body modes (free-free rotor)")
    max_dof: int = param(
        DEFAULT_MAX_DOF, ge=4, doc="refuse models with more lateral DOFs (4 per node); raise it deliberately"
    )

    # -- construction ----------------------------------------------------------------------
    @classmethod
    def from_mapping(cls, data: Mapping[str, Any], where: str = "") -> Rotor:
        """Build from a parsed TOML mapping (keys ``shaft``, ``disk``, ``bearing``, ...)."""
        if not isinstance(data, Mapping):
            raise InputError(where or "config", data, "a table")
        data = dict(data)
        prefix = f"{where}." if where else ""
        rename = {}  # errors name the user's tables: bearing.left, not bearing[0]
        for key in ("shaft", "disk", "point_mass", "bearing"):
            v = data.get(key)
            if isinstance(v, Mapping):  # [bearing.left] named tables: sweepable by dotted key
                data[key] = [{**({"name": k} if key == "bearing" else {}), **t} for k, t in v.items()]
                rename.update({f"{prefix}{key}[{i}]": f"{prefix}{table_key(key, k)}" for i, k in enumerate(v)})
        if isinstance(data.get("bearing"), list):
            data["bearing"] = [
                {k: ([v] if k in COEFFICIENTS and isinstance(v, (int, float)) else v) for k, v in b.items()}
                if isinstance(b, Mapping)
                else b
                for b in data["bearing"]
            ]
        try:
            return from_mapping(cls, data, where)
        except InputError as exc:
            raise exc.relocated("", rename) from None

    @classmethod
    def from_toml(cls, path: str | Path) -> Rotor:
        """Read the rotor tables of a TOML file (other top-level tables are ignored)."""
        cfg = load_toml(path)
        return cls.from_mapping({k: v for k, v in cfg.items() if k in ROTOR_KEYS})

    def __post_init__(self):
        if not self.shaft:
            raise InputError("shaft", "<missing>", "at least one [[shaft]] section")
        self._check_size()
        # validate now (load = "static" is resolved here under standard gravity, see `resolved`)
        _ = self.nodes, self.elements, self.layer_elements, self.disks, self.point_masses, self.bearings
        if not self.free:
            self._check_supported()

    @property
    def static_load_bearings(self) -> list[int]:
        """Indices of the fluid-film bearings whose load is ``"static"`` (from the static analysis)."""
        return [i for i, b in enumerate(self.bearing) if b.fluid_film is not None and b.fluid_film.load == "static"]

    @functools.cached_property
    def resolved(self) -> Rotor:
        """This rotor with every ``load = "static"`` replaced by the converged static bearing load
        under standard gravity along -y (:func:`rotaflex.rotor.fe.bearings.static_load.resolve_static_loads`
        for other loads); the rotor itself when there is none."""
        if not self.static_load_bearings:
            return self
        return resolve_static_loads(self).rotor

    def _check_size(self) -> None:
        """Refuse, before anything is assembled, a mesh beyond ``max_dof`` or the memory limit."""
        from rotaflex.core.limits import require_memory

        counts = [s.elements if not s.layer else 0 for s in self.shaft]
        i = int(np.argmax(counts))
        n_dof = NDOF_NODE * (sum(counts) + 1) + 2 * sum(b.pedestal is not None for b in self.bearing)
        if not n_dof <= self.max_dof:
            raise InputError(
                f"shaft[{i}].elements",
                counts[i],
                f"a value needing at most {self.max_dof:.3g} lateral DOFs (this needs ~{n_dof:.3g}; raise max_dof "
                "if you mean it (dense solvers: time grows as DOFs^3))",
                ("max_dof",),
            )
        # assembly holds M, K, G, Kst and the speed-dependent K, C copies: ~8 dense n x n arrays
        require_memory(f"shaft[{i}].elements", counts[i], 8 * 8.0 * n_dof**2, "the assembled matrices")

    # -- geometry ----------------------------------------------------------------------------
    def _mat(self, name: str, where: str) -> Material:
        return material(name, where, self.material)

    @functools.cached_property
    def sections(self) -> list[tuple[float, float]]:
        """(start, end) [m] of each main-layer shaft section, validated to be contiguous."""
        out, prev = [], None
        for i, s in self._main:
            where = f"shaft[{i}]"
            start = s.start if s.start is not None else (prev if prev is not None else 0.0)
            if prev is not None and abs(start - prev) > 1e-9 * max(1.0, abs(prev)):
                what = "overlaps" if start < prev else "leaves a gap after"
                raise InputError(
                    f"{where}.start",
                    start,
                    f"{prev:g} m: the section {what} the previous one (sections must be contiguous, left to right)",
                )
            end = self._span(i, s, start)
            out.append((float(start), float(end)))
            prev = end
        return out

    @property
    def _main(self) -> list[tuple[int, Shaft]]:
        """(index, section) of the main layer (``layer = ""``): these set the nodes."""
        main = [(i, s) for i, s in enumerate(self.shaft) if not s.layer]
        if not main:
            raise InputError("shaft[0].layer", self.shaft[0].layer, '"" on at least one section (the main shaft)')
        return main

    def _span(self, i: int, s: Shaft, start: float) -> float:
        """End [m] of section ``i`` starting at ``start``, its lengths and diameters validated."""
        where = f"shaft[{i}]"
        if s.end is not None and s.length is not None and abs(s.end - start - s.length) > 1e-9:
            raise InputError(f"{where}.length", s.length, f"end - start = {s.end - start:g} m")
        if s.end is None and s.length is None:
            raise InputError(f"{where}.length", "<missing>", "a length [m] > 0 or an end position")
        for key in ("outer_diameter", "inner_diameter", "outer_diameter_right", "inner_diameter_right"):
            _not_mm(f"{where}.{key}", getattr(s, key), MAX_DIAMETER["shaft"])
        for key in ("length", "start", "end"):
            v = getattr(s, key)
            _not_mm(f"{where}.{key}", None if v is None else abs(v), MAX_LENGTH)
        end = s.end if s.end is not None else start + s.length
        if end <= start:
            raise InputError(f"{where}.end", end, f"> start = {start:g} m")
        for side in ("", "_right"):
            do, di = getattr(s, "outer_diameter" + side), getattr(s, "inner_diameter" + side)
            do = s.outer_diameter if do is None else do
            di = s.inner_diameter if di is None else di
            if di >= do:
                raise InputError(f"{where}.inner_diameter{side}", di, f"< outer diameter {do:g} m")
        return end

    def _properties(self, i: int, s: Shaft) -> tuple[float, float, float]:
        """E, G [Pa], rho [kg/m^3] of section ``i``, validated."""
        m = self._mat(s.material, f"shaft[{i}].material")
        E, G, rho = s.E or m.E, s.G or m.G, s.rho or m.rho
        for key, v, (lo, hi), unit in (
            ("E", E, MODULUS_RANGE, "Pa"),
            ("G", G, MODULUS_RANGE, "Pa"),
            ("rho", rho, DENSITY_RANGE, "kg/m^3"),
        ):
            if not lo <= v <= hi:
                field = f"shaft[{i}].{key}" if getattr(s, key) else f"material.{s.material}.{key}"
                raise InputError(
                    field,
                    v,
                    f"{lo:g} .. {hi:g} {unit} (a stiff section's E may exceed any solid's, up to this cap)",
                )
        return E, G, rho

    @staticmethod
    def _columns(cols: dict[str, list], s: Shaft, props, L: np.ndarray, t: np.ndarray) -> None:
        """Append the elements of section ``s`` (lengths ``L``, element ends at fractions ``t``) to ``cols``."""
        E, G, rho = props
        do_r = s.outer_diameter if s.outer_diameter_right is None else s.outer_diameter_right
        di_r = s.inner_diameter if s.inner_diameter_right is None else s.inner_diameter_right
        do = s.outer_diameter + (do_r - s.outer_diameter) * t
        di = s.inner_diameter + (di_r - s.inner_diameter) * t
        n = L.size
        cols["L"] += list(L)
        cols["do_l"] += list(do[:-1])
        cols["do_r"] += list(do[1:])
        cols["di_l"] += list(di[:-1])
        cols["di_r"] += list(di[1:])
        cols["E"] += [E] * n
        cols["G"] += [G] * n
        cols["rho"] += [rho] * n
        cols["kappa"] += [s.shear_coefficient if s.shear_coefficient else np.nan] * n
        cols["alpha"] += [s.rayleigh_alpha] * n
        cols["beta"] += [s.rayleigh_beta] * n
        cols["stiff"] += [s.stiffness] * n
        cols["massive"] += [s.mass] * n

    _KEYS = ("L", "do_l", "di_l", "do_r", "di_r", "E", "G", "rho", "kappa", "alpha", "beta", "stiff", "massive")

    @functools.cached_property
    def elements(self) -> dict[str, np.ndarray]:
        """Per-element arrays of the main layer: length, diameters (left/right), E, G, rho, kappa
        (nan: Cowper's value), Rayleigh alpha and beta, and whether it adds stiffness and mass."""
        cols: dict[str, list] = {k: [] for k in self._KEYS}
        for (i, s), (a, b) in zip(self._main, self.sections, strict=True):
            n = s.elements
            self._columns(cols, s, self._properties(i, s), np.full(n, (b - a) / n), np.arange(n + 1) / n)
        out = {k: np.asarray(v, bool if k in ("stiff", "massive") else float) for k, v in cols.items()}
        rigid = np.concatenate([[s.rigid] * s.elements for _, s in self._main])
        if rigid.any():
            self._make_rigid(out, rigid)
        return out

    @functools.cached_property
    def layer_elements(self) -> dict[str, np.ndarray]:
        """Per-element arrays of the coaxial layers (keys of :attr:`elements` plus ``index``, the
        main element each lies on). A layer section spans whole main elements: its start and end
        are nodes, and its diameters follow its own taper at the nodes in between."""
        cols: dict[str, list] = {k: [] for k in (*self._KEYS, "index")}
        z = self.nodes
        tol = 1e-6 * (z[-1] - z[0])
        for i, s in enumerate(self.shaft):
            if not s.layer:
                continue
            where = f"shaft[{i}]"
            if s.start is None:
                raise InputError(f"{where}.start", "<missing>", "the axial start [m] of a layer section (a node)")
            if s.rigid:
                raise InputError(f"{where}.rigid", True, "false on a layer section (rigid sections: main layer)")
            end = self._span(i, s, s.start)
            ends = []
            for key, v in (("start", s.start), ("end" if s.end is not None else "length", end)):
                j = int(np.argmin(np.abs(z - v)))
                if abs(z[j] - v) > tol:
                    shown = ", ".join(f"{x:g}" for x in z[:12]) + (" ..." if z.size > 12 else "")
                    raise InputError(f"{where}.{key}", getattr(s, key), f"a layer section ends at nodes [m]: {shown}")
                ends.append(j)
            span = ends[1] - ends[0]
            if s.elements not in (1, span):
                raise InputError(
                    f"{where}.elements", s.elements, f"{span} (a layer uses the main shaft's elements) or omitted"
                )
            t = (z[ends[0] : ends[1] + 1] - z[ends[0]]) / (z[ends[1]] - z[ends[0]])
            self._columns(cols, s, self._properties(i, s), np.diff(z[ends[0] : ends[1] + 1]), t)
            cols["index"] += list(range(ends[0], ends[1]))
        return {
            k: np.asarray(v, bool if k in ("stiff", "massive") else int if k == "index" else float)
            for k, v in cols.items()
        }

    def _make_rigid(self, e: dict[str, np.ndarray], rigid: np.ndarray) -> None:
        """Stiffen the elements of rigid sections in place (their mass stays).

        A penalty: the element's bending stiffness 12 E I / L^3 is set to RIGID_FACTOR = 1e8 times
        the stiffest other part of the model (bearing coefficients, flexible elements). The
        penalty error falls as 1/factor and the round-off of the eigenproblem grows as
        factor x 1e-16, so 1e8 (about 1/sqrt(machine epsilon)) balances the two: the rigid-body
        frequencies of a rigid rotor on springs come out to ~1e-8 (tested).
        """
        I = np.pi / 64 * (((e["do_l"] + e["do_r"]) / 2) ** 4 - ((e["di_l"] + e["di_r"]) / 2) ** 4)
        k_el = 12 * e["E"] * I / e["L"] ** 3
        ref = [float(np.max(k_el[~rigid]))] if (~rigid).any() else []
        for b in self.bearing:
            ref += [abs(float(v)) for key in ("kxx", "kxy", "kyx", "kyy") for v in flat(getattr(b, key))]
        k_ref = max(ref) if ref and max(ref) > 0 else 1e8
        E = RIGID_FACTOR * k_ref * e["L"] ** 3 / (12 * I)
        e["E"] = np.where(rigid, E, e["E"])
        e["G"] = np.where(rigid, E / 2.6, e["G"])  # Poisson 0.3: shear as stiff as bending

    @functools.cached_property
    def nodes(self) -> np.ndarray:
        """Axial node positions z [m], shape (n_nodes,)."""
        L = self.elements["L"]
        return self.sections[0][0] + np.concatenate([[0.0], np.cumsum(L)])

    @property
    def n_nodes(self) -> int:
        return int(self.nodes.size)

    @property
    def n_rotor_dof(self) -> int:
        """Lateral DOFs of the shaft's nodes (4 per node); pedestal DOFs follow them."""
        return NDOF_NODE * self.n_nodes

    @property
    def n_dof(self) -> int:
        """All DOFs: the shaft's nodes', then x and y of each pedestal (:attr:`pedestals`)."""
        return NDOF_NODE * self.n_nodes + 2 * len(self.pedestals)

    def station(
        self,
        node: int | None,
        position: float | None,
        where: str,
        required: bool = True,
        keys: tuple[str, str] = ("node", "position"),
    ) -> int | None:
        """Node number of a station given by ``node`` or ``position`` (InputError if it is no node)."""
        kn, kp = keys
        if node is not None and position is not None:
            raise InputError(f"{where}.{kp}", position, f"either {kn} or {kp}, not both")
        if node is not None:
            if node >= self.n_nodes:
                raise InputError(f"{where}.{kn}", node, f"an existing node 0..{self.n_nodes - 1}")
            return int(node)
        if position is not None:
            j = int(np.argmin(np.abs(self.nodes - position)))
            tol = 1e-6 * (self.nodes[-1] - self.nodes[0])
            if abs(self.nodes[j] - position) > tol:
                shown = ", ".join(f"{z:g}" for z in self.nodes[:12]) + (" ..." if self.n_nodes > 12 else "")
                raise InputError(f"{where}.{kp}", position, f"the position of a node [m]: {shown}")
            return j
        if required:
            raise InputError(f"{where}.{kn}", "<missing>", f"a node number or a {kp} [m]")
        return None

    @functools.cached_property
    def disks(self) -> list[tuple[int, DiskElement]]:
        out = []
        for i, d in enumerate(self.disk):
            where = f"disk[{i}]"
            n = self.station(d.node, d.position, where)
            if d.mass is not None:
                if d.Id is None or d.Ip is None:
                    raise InputError(
                        f"{where}.{'Id' if d.Id is None else 'Ip'}",
                        "<missing>",
                        "a moment of inertia [kg m^2] >= 0 (with mass)",
                    )
                el = DiskElement(d.mass, d.Id, d.Ip)
            else:
                _not_mm(f"{where}.outer_diameter", d.outer_diameter, MAX_DIAMETER["disk"])
                _not_mm(f"{where}.inner_diameter", d.inner_diameter, MAX_DIAMETER["disk"])
                _not_mm(f"{where}.width", d.width, MAX_LENGTH)
                if d.width is None or d.outer_diameter is None:
                    raise InputError(
                        f"{where}.mass", "<missing>", "mass, Id and Ip, or width and outer_diameter (geometry)"
                    )
                if d.inner_diameter >= d.outer_diameter:
                    raise InputError(f"{where}.inner_diameter", d.inner_diameter, f"< {d.outer_diameter:g} m")
                rho = d.rho or self._mat(d.material, f"{where}.material").rho
                el = DiskElement.from_geometry(d.width, d.outer_diameter, d.inner_diameter, rho)
            out.append((n, el))
        return out

    @functools.cached_property
    def point_masses(self) -> list[tuple[int, PointMassElement]]:
        return [
            (self.station(p.node, p.position, f"point_mass[{i}]"), PointMassElement(p.mass))
            for i, p in enumerate(self.point_mass)
        ]

    @functools.cached_property
    def bearings(self) -> list[tuple[int, int | None, BearingElement]]:
        """(node, other node or None for ground, element) per bearing."""
        if self.static_load_bearings:
            return self.resolved.bearings
        out = []
        for i, b in enumerate(self.bearing):
            where = bearing_path(i, b)
            n = self.station(b.node, b.position, where)
            m = self.station(b.to_node, b.to_position, where, False, ("to_node", "to_position"))
            if m == n:
                raise InputError(f"{where}.to_node", m, "a node other than the bearing's own node")
            if b.pedestal is not None and m is not None:
                raise InputError(f"{where}.pedestal", "<table>", "no pedestal on a bearing between two nodes")
            for k in MASS_COEFFICIENTS:
                if not abs(getattr(b, k)) <= MAX_BEARING["m"]:
                    raise InputError(
                        f"{where}.{k}", getattr(b, k), f"a finite mass of magnitude <= {MAX_BEARING['m']:g} kg"
                    )
            if registry.kind_of(b, where) is not None:
                out.append((n, m, registry.element(b, where)))
                continue
            out.append((n, m, BearingElement.from_table(b, where)))
        return out

    @functools.cached_property
    def pedestals(self) -> list[tuple[int, Pedestal]]:
        """The (bearing index, pedestal) pairs of the bearings on pedestals, in the order of their
        DOFs; pedestal p has x at ``n_rotor_dof + 2 p`` and y after it."""
        return [(i, b.pedestal) for i, b in enumerate(self.bearing) if b.pedestal is not None]

    @property
    def frequency_dependent(self) -> bool:
        """True when a bearing's coefficients depend on the whirl frequency (modal solves iterate)."""
        return any(el.frequency_dependent for _, _, el in self.bearings)

    def check_speeds(self, speeds, key: str) -> None:
        """Refuse spin speeds [rad/s] outside any coefficient table whose extrapolation is ``"refuse"``.

        The message names ``key`` (the analysis key the user must change, e.g.
        ``campbell.speed_rpm``) and lists every table concerned with its name and range.
        """
        speeds = np.atleast_1d(np.asarray(speeds, float))
        bad = [t for _, _, el in self.bearings for t in el.out_of_range(speeds)]
        if bad:
            rpm = np.round(rad_s_to_rpm(speeds), 6)
            shown = float(rpm[0]) if rpm.size == 1 else [float(rpm.min()), float(rpm.max())]
            raise InputError(
                key,
                shown,
                f"speeds within every coefficient table ({'; '.join(bad)}), "
                'or extrapolation = "hold" or "linear" on those bearings',
            )

    # -- assembly -------------------------------------------------------------------------
    @functools.cached_property
    def _base(self) -> dict[str, np.ndarray]:
        """Speed-independent global matrices: M, K (shaft), G (per rad/s), Kst (per rad/s^2) and
        C (Rayleigh damping of shaft sections and disks), on all DOFs (pedestals included)."""
        n = self.n_dof
        out = {key: np.zeros((n, n)) for key in ("M", "K", "G", "Kst", "C")}
        for e, first in ((self.elements, None), (self.layer_elements, "index")):
            if not e["L"].size:
                continue
            keys = ("L", "do_l", "di_l", "do_r", "di_r", "E", "G", "rho", "kappa")
            mats = shaft_matrices(*(e[k] for k in keys))
            left = np.arange(e["L"].size) if first is None else e[first]
            idx = NDOF_NODE * left[:, None] + np.arange(8)[None, :]
            on = {"M": e["massive"], "G": e["massive"], "Kst": e["massive"], "K": e["stiff"]}
            for key, local in mats.items():
                local = local * on[key][:, None, None]
                mats[key] = local
                np.add.at(out[key], (idx[:, :, None], idx[:, None, :]), local)
            damp = e["alpha"][:, None, None] * mats["M"] + e["beta"][:, None, None] * mats["K"]
            np.add.at(out["C"], (idx[:, :, None], idx[:, None, :]), damp)
        for (node, el), d in zip(self.disks, self.disk, strict=True):
            s = slice(NDOF_NODE * node, NDOF_NODE * node + 4)
            out["M"][s, s] += el.M()
            out["G"][s, s] += el.G()
            out["Kst"][s, s] += el.Kst()
            out["C"][s, s] += d.rayleigh_alpha * el.M()
        for node, el in self.point_masses:
            s = slice(NDOF_NODE * node, NDOF_NODE * node + 4)
            out["M"][s, s] += el.M()
        for b, ends in zip(self.bearing, self.bearing_dofs, strict=True):  # mass coefficients: constant
            _couple(out["M"][None], np.array([[[b.mxx, b.mxy], [b.myx, b.myy]]], float), *ends)
        for p, (_, ped) in enumerate(self.pedestals):
            j = self.n_rotor_dof + 2 * p + np.arange(2)
            out["M"][j, j] += [ped.mass, ped.mass if ped.mass_y is None else ped.mass_y]
        return out

    @functools.cached_property
    def bearing_dofs(self) -> list[tuple[np.ndarray, np.ndarray | None]]:
        """The DOFs (x, y) of both ends of each bearing (its node's; and the other node's, its
        pedestal's or None for the ground). From the schema, so the mass assembly needs no element."""
        ped = {i: p for p, (i, _) in enumerate(self.pedestals)}
        out = []
        for i, b in enumerate(self.bearing):
            where = bearing_path(i, self.bearing[i])
            a = NDOF_NODE * self.station(b.node, b.position, where) + np.arange(2)
            other = self.station(b.to_node, b.to_position, where, False, ("to_node", "to_position"))
            if i in ped:
                out.append((a, self.n_rotor_dof + 2 * ped[i] + np.arange(2)))
            else:
                out.append((a, None if other is None else NDOF_NODE * other + np.arange(2)))
        return out

    @property
    def M(self) -> np.ndarray:
        """Global mass matrix (n_dof, n_dof)."""
        return self._base["M"]

    @property
    def K_shaft(self) -> np.ndarray:
        """Global stiffness of the shaft alone (no bearings) (n_dof, n_dof)."""
        return self._base["K"]

    @property
    def G(self) -> np.ndarray:
        """Global gyroscopic matrix per unit spin speed (skew-symmetric); force -Omega G q'."""
        return self._base["G"]

    @property
    def Kst(self) -> np.ndarray:
        """Global matrix multiplying the spin acceleration (run-up); force -Omega' Kst q."""
        return self._base["Kst"]

    @property
    def C_rayleigh(self) -> np.ndarray:
        """Rayleigh damping sum(alpha M_e + beta K_e) of the shaft sections and disks (n_dof, n_dof)."""
        return self._base["C"]

    def KC(self, speeds, whirl=None, key: str = "speed") -> tuple[np.ndarray, np.ndarray]:
        """Stiffness and damping (n_speed, n_dof, n_dof) at spin speeds [rad/s]: :meth:`MKC` without M."""
        return self.MKC(speeds, whirl, key)[1:]

    def MKC(self, speeds, whirl=None, key: str = "speed", include=None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Mass, stiffness and damping (n_speed, n_dof, n_dof) at spin speeds [rad/s].

        The one assembly of the bearing elements: every analysis takes its matrices from here.
        Bearings are interpolated at ``speeds`` and, for frequency-dependent ones, at the whirl
        frequencies ``whirl`` [rad/s] (same shape; None: synchronous, whirl = speed). M is
        :attr:`M` plus each element's ``mass(speed)`` (a liquid seal's added mass; the constant
        mass coefficients of a table bearing are already in :attr:`M`). K and C include the
        Rayleigh damping and the pedestals' springs and dampers. A speed outside a table whose
        extrapolation is ``"refuse"`` raises :class:`InputError` naming ``key``. ``include``: one
        flag per bearing (None: all), the bearings left out contribute nothing (stability's
        element contributions).
        """
        speeds = np.atleast_1d(np.asarray(speeds, float))
        self.check_speeds(speeds, key)
        include = [True] * len(self.bearing) if include is None else include
        shape = (speeds.size, self.n_dof, self.n_dof)
        M = np.broadcast_to(self._base["M"], shape).copy()
        K = np.broadcast_to(self._base["K"], shape).copy()
        C = np.broadcast_to(self._base["C"], shape).copy()
        for keep, (_, _, el), (a, b) in zip(include, self.bearings, self.bearing_dofs, strict=True):
            if not keep:
                continue
            kb, cb = el.coefficients(speeds, whirl)
            _couple(K, kb, a, b)
            _couple(C, cb, a, b)
            if not isinstance(el, BearingElement):  # a table's mass coefficients are in _base
                _couple(M, el.mass(speeds), a, b)
        for p, (_, ped) in enumerate(self.pedestals):
            j = self.n_rotor_dof + 2 * p + np.arange(2)
            K[:, j, j] += [ped.kxx, ped.kyy]
            C[:, j, j] += [ped.cxx, ped.cyy]
        return M, K, C

    def _check_supported(self) -> None:
        """Refuse a model whose bearings leave a rigid-body motion of the shaft unrestrained.

        A connected elastic shaft has exactly four zero-energy motions (translation and tilt in
        each plane), so the supports suffice iff the bearing stiffness projected on them,
        R^T K_b R (4 x 4, columns scaled to unit length), is non-singular. Judging this on the
        projection, not on the whole stiffness, keeps a very stiff shaft on soft bearings from
        being mistaken for a free one.
        """
        Kb = np.zeros((1, self.n_dof, self.n_dof))
        for (_, _, el), ends in zip(self.bearings, self.bearing_dofs, strict=True):  # each table at its first point
            speed = 0.0 if el.speeds is None else el.speeds[0]
            whirl = None if el.whirls is None else el.whirls[:1]
            _couple(Kb, el.coefficients(speed, whirl)[0], *ends)
        for p, (_, ped) in enumerate(self.pedestals):
            j = self.n_rotor_dof + 2 * p + np.arange(2)
            Kb[0, j, j] += [ped.kxx, ped.kyy]
        Kb = Kb[0]
        z = self.nodes - self.nodes.mean()
        nr = self.n_rotor_dof
        R = np.zeros((self.n_dof, 4))
        R[0:nr:NDOF_NODE, 0] = R[1:nr:NDOF_NODE, 1] = 1.0
        R[0:nr:NDOF_NODE, 2], R[3:nr:NDOF_NODE, 2] = z, 1.0  # tilt in x-z: x = z theta_y
        R[1:nr:NDOF_NODE, 3], R[2:nr:NDOF_NODE, 3] = z, -1.0  # tilt in y-z: y = -z theta_x
        for p, (i, _) in enumerate(self.pedestals):  # a pedestal moves with its bearing's node
            node = self.bearings[i][0]
            R[nr + 2 * p : nr + 2 * p + 2] = R[NDOF_NODE * node : NDOF_NODE * node + 2]
        R /= np.linalg.norm(R, axis=0)
        sv = np.linalg.svd(R.T @ Kb @ R, compute_uv=False)
        if not sv[-1] > 1e-9 * sv[0]:
            grounded = sum(other is None for _, other, _ in self.bearings)
            raise InputError(
                "free",
                False,
                "true for a model with rigid-body modes: the bearings do not restrain every rigid "
                f"motion of the shaft ({grounded} bearing(s) to ground; two at different stations are needed)",
            )

    @property
    def mass(self) -> float:
        """Total mass [kg] (sum of translational inertia in x)."""
        nr = self.n_rotor_dof  # pedestals stand on the ground, not on the bearings
        return float(self.M[0:nr:NDOF_NODE, 0:nr:NDOF_NODE].sum())

    def to_mapping(self) -> dict[str, Any]:
        """Plain data (for provenance)."""
        return dataclasses.asdict(self)


def _couple(A: np.ndarray, block: np.ndarray, a: np.ndarray, b: np.ndarray | None) -> None:
    """Add a 2x2 connection ``block`` (n, 2, 2) between DOFs ``a`` and ``b`` (None: ground) to ``A`` (n, N, N)."""
    A[:, a[:, None], a] += block
    if b is not None:
        A[:, b[:, None], b] += block
        A[:, a[:, None], b] -= block
        A[:, b[:, None], a] -= block


ROTOR_KEYS = ("shaft", "disk", "point_mass", "bearing", "material", "free", "max_dof")
