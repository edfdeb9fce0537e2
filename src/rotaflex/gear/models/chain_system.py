"""The torsional chain as data and its linear analysis (below the chain's dynamics and the steady loop).

:class:`TorsionalSystem` (inertias, shafts, mesh table, bearings, drive), :class:`OperatingPoint`,
the chain arrays of an operating point (:class:`Chain`, :func:`build_chain`) and the linear
torsional analysis (:func:`natural_frequencies`, :func:`resonance_speeds_rpm`). The model and
its equations are described in :mod:`rotaflex.gear.models.chain`, which re-exports every name
here; this module exists so that the steady loop
(:mod:`rotaflex.gear.solvers.steady_loop`), which needs the natural frequencies, sits below
the chain's ``steady_state`` that calls it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from rotaflex.core.config import param
from rotaflex.core.errors import InputError
from rotaflex.core.units import rpm_to_rad_s
from rotaflex.gear.kernels.chain import ChainArgs
from rotaflex.gear.models.mesh_stiffness import DEFAULT_DAMPING_RATIO, MeshTable, mesh_damping

__all__ = ["Chain", "OperatingPoint", "TorsionalSystem", "build_chain", "natural_frequencies", "resonance_speeds_rpm"]


# ------------------------------------------------------------------------------- the system
@dataclass(frozen=True)
class TorsionalSystem:
    """Torsional model data (SI). ``inf`` shaft stiffness = rigid shaft (inertias merged)."""

    mesh: MeshTable
    teeth: tuple = param((28, 28), doc="teeth (pinion, wheel)")
    base_radius: tuple = param((0.041772, 0.041772), unit="m", doc="(r_b1, r_b2)")
    inertia: tuple = param((2.965e-4, 2.965e-4), unit="kg m^2", doc="(J_1, J_2) of the gears")
    motor_inertia: float = param(0.0, unit="kg m^2", ge=0.0)
    load_inertia: float = param(0.0, unit="kg m^2", ge=0.0)
    input_shaft_stiffness: float = param(math.inf, unit="N m/rad", gt=0.0)
    input_shaft_damping: float = param(0.0, unit="N m s/rad", ge=0.0)
    output_shaft_stiffness: float = param(math.inf, unit="N m/rad", gt=0.0)
    output_shaft_damping: float = param(0.0, unit="N m s/rad", ge=0.0)
    mesh_damping_ratio: float = param(DEFAULT_DAMPING_RATIO, ge=0.0, doc="zeta of c_m = 2 zeta sqrt(k_mean m_red)")
    backlash: float = param(-1.0, unit="m", doc="back-side contact after this gap; < 0: none")
    drive: Literal["constant_speed", "motor"] = param("constant_speed")
    motor_slope: float = param(0.0, unit="N m s/rad", ge=0.0, doc="torque-speed slope of the motor (drive = 'motor')")
    bearing_stiffness: tuple = param(
        (math.inf, math.inf), unit="N/m", doc="(pinion, wheel) support stiffness along the line of action; inf: rigid"
    )
    bearing_damping: tuple = param((0.0, 0.0), unit="N s/m", doc="(pinion, wheel) support damping")
    gear_mass: tuple = param((0.0, 0.0), unit="kg", doc="(pinion, wheel) masses moving with the gear centres")

    def __post_init__(self):
        z1, z2 = self.teeth
        r1, r2 = self.base_radius
        if abs(z1 / z2 - r1 / r2) > 1e-6 * z1 / z2:
            raise InputError("base_radius", self.base_radius, f"in the teeth ratio {z1}:{z2}")
        if self.drive == "motor" and self.motor_slope <= 0.0:
            raise InputError("motor_slope", self.motor_slope, "> 0 with drive = 'motor'")
        if math.isfinite(self.output_shaft_stiffness) and self.load_inertia <= 0.0:
            raise InputError("load_inertia", self.load_inertia, "> 0 with an elastic output shaft")
        if self.drive == "motor" and math.isfinite(self.input_shaft_stiffness) and self.motor_inertia <= 0.0:
            raise InputError("motor_inertia", self.motor_inertia, "> 0 with drive = 'motor' and an elastic input shaft")
        for i, name in enumerate(("pinion", "wheel")):
            k, c, m = self.bearing_stiffness[i], self.bearing_damping[i], self.gear_mass[i]
            if not k > 0.0:
                raise InputError(f"bearing_stiffness[{i}]", k, f"> 0 N/m ({name}; inf: rigid)")
            if not (math.isfinite(c) and c >= 0.0):
                raise InputError(f"bearing_damping[{i}]", c, f">= 0 N s/m ({name})")
            if math.isfinite(k) and not (math.isfinite(m) and m > 0.0):
                raise InputError(f"gear_mass[{i}]", m, f"> 0 kg with a finite {name} bearing stiffness")

    @property
    def reduced_mass(self) -> float:
        """m_red of the gear pair along the line of action [kg]."""
        (j1, j2), (r1, r2) = self.inertia, self.base_radius
        return j1 * j2 / (j1 * r2**2 + j2 * r1**2)

    @property
    def mesh_damping(self) -> float:
        """c_m [N s/m]."""
        return mesh_damping(self.mesh.mean_stiffness, self.inertia, self.base_radius, self.mesh_damping_ratio)


@dataclass(frozen=True)
class OperatingPoint:
    """Pinion speed and output torque."""

    speed_rpm: float = param(4000.0, unit="rpm", gt=0.0, doc="pinion (mean) speed")
    torque: float = param(22.25, unit="N m", gt=0.0, doc="output torque on the wheel side")
    ramp_cycles: float = param(0.0, ge=0.0, doc="start-up torque ramp; 0: start from statics")

    @property
    def omega(self) -> float:
        """Pinion speed [rad/s]."""
        return rpm_to_rad_s(self.speed_rpm)


@dataclass
class Chain:
    jinv: np.ndarray
    inertia: np.ndarray
    ks: np.ndarray
    cs: np.ndarray
    torque: np.ndarray
    slope: np.ndarray
    nominal: np.ndarray
    presc: np.ndarray
    ip: int
    iw: int
    names: list = field(default_factory=list)
    kg: np.ndarray | None = None
    cg: np.ndarray | None = None
    iy1: int = -1
    iy2: int = -1

    def args(self, ramp_time: float) -> ChainArgs:
        """The kernel's chain arguments."""
        c = self
        return ChainArgs(c.jinv, c.ks, c.cs, c.torque, c.slope, c.nominal, c.presc, float(ramp_time), c.kg, c.cg)

    def add_strain_and_dissipation(self, th: np.ndarray, om: np.ndarray, energy: np.ndarray, diss: np.ndarray):
        """Add the shafts' strain energy and dissipation ``c_s domega^2`` and the bearings'
        ``k_b y^2 / 2`` and ``c_b y'^2`` of histories ``th`` [rad], ``om`` [rad/s] to ``energy``
        [J] and ``diss`` [W] (returns new arrays)."""
        for i in range(len(self.inertia) - 1):
            energy = energy + 0.5 * self.ks[i] * (th[:, i] - th[:, i + 1]) ** 2
            diss = diss + self.cs[i] * (om[:, i] - om[:, i + 1]) ** 2
        energy = energy + 0.5 * th**2 @ self.kg
        diss = diss + om**2 @ self.cg
        return energy, diss

    def drive_power(self, op, teeth: int, th, om, t, force, rb1: float) -> np.ndarray:
        """Power [W] into the chain from drive and load: at a speed-controlled node the torque
        that holds its speed (shaft and, at the pinion, mesh ``r_b1 F``), elsewhere the applied
        torque (ramped over ``op.ramp_cycles`` mesh cycles) plus the torque-speed slope term."""
        c = self
        p_in = np.zeros(len(t))
        ramp = op.ramp_cycles * 2 * np.pi / (op.omega * teeth)
        scale = np.clip(t / ramp, 0.0, 1.0) if ramp > 0 else np.ones(len(t))
        for i in range(len(c.inertia)):
            if c.presc[i]:
                # torque the speed control applies to keep node i at its speed
                tq = np.zeros(len(t))
                if i + 1 < len(c.inertia):
                    tq += c.ks[i] * (th[:, i] - th[:, i + 1]) + c.cs[i] * (om[:, i] - om[:, i + 1])
                if i == c.ip:
                    tq += rb1 * force
                p_in += tq * om[:, i]
            else:
                p_in += (scale * c.torque[i] + c.slope[i] * (c.nominal[i] - om[:, i])) * om[:, i]
        return p_in


def build_chain(sys: TorsionalSystem, op: OperatingPoint) -> Chain:
    """Nodes after merging rigid shafts; pinion-side nodes turn at Omega, wheel side at Omega i."""
    (j1, j2), (r1, r2) = sys.inertia, sys.base_radius
    w1 = op.omega
    w2 = w1 * r1 / r2
    t_out = op.torque
    t_in = t_out * r1 / r2
    motor = sys.drive == "motor"
    nodes = []  # (name, J, torque, slope, nominal, prescribed)
    if math.isfinite(sys.input_shaft_stiffness):
        nodes.append(
            ["motor", sys.motor_inertia, t_in if motor else 0.0, sys.motor_slope if motor else 0.0, w1, not motor]
        )
        nodes.append(["pinion", j1, 0.0, 0.0, w1, False])
    else:
        nodes.append(
            ["pinion", j1 + sys.motor_inertia, t_in if motor else 0.0, sys.motor_slope if motor else 0.0, w1, not motor]
        )
    ip = len(nodes) - 1
    if math.isfinite(sys.output_shaft_stiffness):
        nodes.append(["wheel", j2, 0.0, 0.0, w2, False])
        nodes.append(["load", sys.load_inertia, -t_out, 0.0, w2, False])
    else:
        nodes.append(["wheel", j2 + sys.load_inertia, -t_out, 0.0, w2, False])
    iw = ip + 1
    lateral = {}
    for i, name in enumerate(("pinion", "wheel")):
        if math.isfinite(sys.bearing_stiffness[i]):
            lateral[i] = len(nodes)
            nodes.append([f"{name}_lateral", sys.gear_mass[i], 0.0, 0.0, 0.0, False])
    n = len(nodes)
    kg, cg = np.zeros(n), np.zeros(n)
    for i, node in lateral.items():
        kg[node], cg[node] = sys.bearing_stiffness[i], sys.bearing_damping[i]
    ks = np.zeros(max(n - 1, 1))
    cs = np.zeros(max(n - 1, 1))
    if ip == 1:
        ks[0], cs[0] = sys.input_shaft_stiffness, sys.input_shaft_damping
    if math.isfinite(sys.output_shaft_stiffness):
        ks[iw], cs[iw] = sys.output_shaft_stiffness, sys.output_shaft_damping
    inertia = np.array([v[1] for v in nodes], dtype=float)
    presc = np.array([v[5] for v in nodes], dtype=np.bool_)
    jinv = np.where(presc | (inertia <= 0), 0.0, 1.0 / np.where(inertia > 0, inertia, 1.0))
    return Chain(
        jinv,
        inertia,
        ks,
        cs,
        np.array([v[2] for v in nodes], dtype=float),
        np.array([v[3] for v in nodes], dtype=float),
        np.array([v[4] for v in nodes], dtype=float),
        presc,
        ip,
        iw,
        [v[0] for v in nodes],
        kg,
        cg,
        lateral.get(0, -1),
        lateral.get(1, -1),
    )


# ------------------------------------------------------------------------- linear analysis
def _linear_matrices(sys: TorsionalSystem, op: OperatingPoint):
    ch = build_chain(sys, op)
    n = len(ch.inertia)
    K = np.zeros((n, n))
    for i in range(n - 1):
        k = ch.ks[i]
        K[i : i + 2, i : i + 2] += k * np.array([[1.0, -1.0], [-1.0, 1.0]])
    K += np.diag(ch.kg)
    r1, r2 = sys.base_radius
    g = np.zeros(n)
    g[ch.ip], g[ch.iw] = r1, -r2
    if ch.iy1 >= 0:
        g[ch.iy1] = 1.0
    if ch.iy2 >= 0:
        g[ch.iy2] = -1.0
    K_mesh = sys.mesh.mean_stiffness * np.outer(g, g)
    free = ~ch.presc
    d = np.zeros(n)  # the DTE r_b1 theta_1 - r_b2 theta_2 as a row of the state
    d[ch.ip], d[ch.iw] = r1, -r2
    return ch, K[np.ix_(free, free)], K_mesh[np.ix_(free, free)], ch.inertia[free], g[free], d[free]


def natural_frequencies(sys: TorsionalSystem, op: OperatingPoint | None = None) -> dict:
    """Linear torsional natural frequencies with the mean mesh stiffness.

    Undamped eigenproblem ``K x = omega^2 M x`` of the free (not speed-prescribed) inertias
    and, with bearings, the lateral masses of the gear centres; the mesh as a spring ``k_mean``
    along ``r_b1 theta_1 - r_b2 theta_2 + y_1 - y_2``. The rigid-body mode (drive = 'motor')
    is dropped.

    Returns
    -------
    dict
        ``frequency`` [Hz] (ascending), ``mesh_energy`` (share of the mode's strain energy in
        the mesh spring) [-], ``dte_share`` (the mode's share of the static DTE under a mesh
        force, ``|d.phi g.phi| / w^2`` normalised over the modes; with bearings a mode can move
        the DTE much more than it strains the mesh) [-], ``mesh_mode`` (index of the mode with
        the largest mesh energy share).
    """
    from scipy.linalg import eigh

    ch, K, K_mesh, m, g, d = _linear_matrices(sys, op or OperatingPoint())
    w2, vec = eigh(K + K_mesh, np.diag(m))
    keep = w2 > 1e-9 * np.max(np.abs(w2))
    w2, vec = w2[keep], vec[:, keep]
    energy = np.einsum("im,ij,jm->m", vec, K_mesh, vec) / np.einsum("im,ij,jm->m", vec, K + K_mesh, vec)
    dte = np.abs((d @ vec) * (g @ vec)) / w2
    return {
        "frequency": np.sqrt(w2) / (2 * np.pi),
        "mesh_energy": energy,
        "dte_share": dte / dte.sum() if dte.sum() > 0 else dte,
        "mesh_mode": int(np.argmax(energy)),
    }


def resonance_speeds_rpm(sys: TorsionalSystem, orders=(1, 2, 3), min_mesh_energy=0.05):
    """Pinion speeds [rpm] where mesh order h meets a natural frequency: ``n = 60 f / (h z1)``.

    Only modes with at least ``min_mesh_energy`` of their strain energy in the mesh or of the
    static DTE under a mesh force (``dte_share``, which picks up bearing modes).

    Returns
    -------
    list of (order, mode frequency [Hz], speed [rpm])
    """
    nf = natural_frequencies(sys)
    out = []
    for f, en, de in zip(nf["frequency"], nf["mesh_energy"], nf["dte_share"], strict=True):
        if max(en, de) >= min_mesh_energy:
            out += [(h, float(f), 60.0 * f / (h * sys.teeth[0])) for h in orders]
    return out
