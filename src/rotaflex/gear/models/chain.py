"""Torsional gear-train model in the manner of NASA's DANST: steady-state mesh dynamics.

Four rigid inertias in a chain, angles positive in each body's sense of rotation::

    motor (J_m) --k_in, c_in-- pinion (J_1, r_b1, z_1) ==mesh== wheel (J_2, r_b2) --k_out, c_out-- load (J_L)

    J_1 theta_1'' = shaft torque - r_b1 F,    J_2 theta_2'' = r_b2 F - shaft torque,
    F = k(phi) delta + c_m delta'  (delta > 0; 0 when the flanks separate; back side optional),
    delta = r_b1 theta_1 - r_b2 theta_2 - e(phi),   phi = z_1 theta_1 / (2 pi)  [mesh cycles].

* The mesh: time-varying stiffness ``k(phi)`` and unloaded transmission error ``e(phi)`` as
  periodic tables over one mesh cycle (:class:`MeshTable`), from an analytic single/double
  contact model, harmonics, or the static FE analysis (:func:`mesh_table_from_static`).
* Mesh damping ``c_m = 2 zeta sqrt(k_mean m_red)``, ``m_red = J1 J2 / (J1 r_b2^2 + J2 r_b1^2)``
  (the gears' own inertias), acting only while a flank pair is in contact. Default zeta = 0.07:
  an engineering default in the range of mesh damping ratios commonly assumed in lumped
  spur-gear models, not a measured value; see docs/gear-steady-state.md.
* Drive: ``constant_speed`` (the motor turns at exactly the set speed, an infinitely stiff
  speed control) or ``motor``: motor inertia with torque ``T_in + s (Omega - omega_m)``
  (a linear torque-speed characteristic of slope s that fixes the mean speed).
  Load: constant torque ``T_out`` on the load inertia, ``T_in = T_out r_b1 / r_b2``.
* A shaft stiffness of ``inf`` makes the shaft rigid: its two inertias are merged.
* Bearings (optional): the gear centres move along the line of action, ``y_1``, ``y_2``, with
  masses ``m_1``, ``m_2`` on springs/dashpots ``k_b``, ``c_b`` to ground (bearings and shaft
  bending at the gear combined); the mesh deflection gains ``y_1 - y_2`` and the mesh force
  acts on the centres: ``m_1 y_1'' = -k_b1 y_1 - c_b1 y_1' - F``,
  ``m_2 y_2'' = -k_b2 y_2 - c_b2 y_2' + F``. Motion off the line of action is not excited
  (frictionless spur mesh) and is left out.

The equations are integrated by a compiled fixed-step RK4 (:mod:`~.kernels.chain`) with a
whole number of steps per mesh cycle, so the histories sample each mesh cycle identically.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from rotaflex.core.config import param
from rotaflex.core.errors import DivergenceError, InputError
from rotaflex.core.units import rpm_to_rad_s
from rotaflex.gear.kernels.chain import ChainArgs, MeshArgs, run_rk4
from rotaflex.gear.models.mesh_stiffness import DEFAULT_DAMPING_RATIO, MeshTable, mesh_damping
from rotaflex.gear.static.iso6336_kv import IsoKvInput, reduced_mass_per_width

__all__ = [
    "Chain",
    "ChainSteady",
    "OperatingPoint",
    "State",
    "TorsionalSystem",
    "build_chain",
    "continue_from",
    "energy_balance",
    "initial_state",
    "iso_input",
    "natural_frequencies",
    "resonance_speeds_rpm",
    "run_cycles",
    "simulate",
    "steady_state",
]


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


#: pressure angle of the standard basic rack [rad] (20 deg): the reference circle ``r_b2 / cos``
#: of :func:`iso_input` when none is given
STANDARD_PRESSURE_ANGLE = 0.3490658503988659  # 20 deg


def iso_input(
    sys: TorsionalSystem,
    torque: float,
    face_width: float,
    contact_ratio: float,
    *,
    c_single: float | None = None,
    c_gamma_alpha: float | None = None,
    reference_radius: float | None = None,
    f_pb_eff: float = 0.0,
    f_f_eff: float = 0.0,
    tip_relief: float = 0.0,
    application_factor: float = 1.0,
    overlap_ratio: float = 0.0,
) -> IsoKvInput:
    """ISO 6336-1 method B data for the torsional model's pair.

    ``m_red`` from the gears' inertias and base radii; ``K_A F_t / b`` with ISO's nominal
    tangential load at the wheel's *reference* circle, ``F_t = T_out / r_2``
    (``reference_radius``; default ``r_b2 / cos 20 deg``). The stiffnesses [N/m^2] are ISO's own
    when given (``c_single``, ``c_gamma_alpha``, e.g. from
    :func:`rotaflex.gear.static.tooth_analysis.iso6336_stiffness`); otherwise ``c_gamma_alpha = k_mean / b``
    (the model's mean mesh stiffness) and ``c' = c_gamma_alpha / (0.75 eps_alpha + 0.25)``
    (ISO's relation between the two). ``contact_ratio`` is eps_alpha; ISO's C_v coefficients take
    the total contact ratio eps_gamma = eps_alpha + ``overlap_ratio`` (helical pairs).
    """
    c_g = sys.mesh.mean_stiffness / face_width if c_gamma_alpha is None else c_gamma_alpha
    c1 = c_g / (0.75 * contact_ratio + 0.25) if c_single is None else c_single
    r2 = sys.base_radius[1] / np.cos(STANDARD_PRESSURE_ANGLE) if reference_radius is None else reference_radius
    return IsoKvInput(
        z1=int(sys.teeth[0]),
        c_single=c1,
        c_gamma_alpha=c_g,
        m_red=reduced_mass_per_width(sys.inertia, sys.base_radius, face_width),
        load_per_width=application_factor * torque / r2 / face_width,
        eps_gamma=contact_ratio + overlap_ratio,
        f_pb_eff=f_pb_eff,
        f_f_eff=f_f_eff,
        tip_relief=tip_relief,
    )


# ------------------------------------------------------------------------------ integration
@dataclass
class State:
    """Angles [rad], speeds [rad/s] and time [s] of the chain nodes (continuation)."""

    theta: np.ndarray
    omega: np.ndarray
    time: float
    nominal: np.ndarray


def initial_state(sys, op, ch: Chain) -> State:
    """Static equilibrium at mesh phase 0 (or unloaded contact with a ramp), nominal speeds."""
    n = len(ch.inertia)
    th = np.zeros(n)
    r1, r2 = sys.base_radius
    load = 0.0 if op.ramp_cycles > 0 else 1.0
    f0 = load * op.torque / r2
    k0, _, e0, _ = sys.mesh.evaluate(0.0)
    lateral = 0.0
    if ch.iy1 >= 0:
        th[ch.iy1] = -f0 / ch.kg[ch.iy1]
        lateral += th[ch.iy1]
    if ch.iy2 >= 0:
        th[ch.iy2] = f0 / ch.kg[ch.iy2]
        lateral -= th[ch.iy2]
    th[ch.iw] = (lateral - float(e0) - f0 / float(k0)) / r2
    if ch.ip == 1:
        th[0] = f0 * r1 / ch.ks[0]
    if ch.names[ch.iw + 1 : ch.iw + 2] == ["load"]:
        th[ch.iw + 1] = th[ch.iw] - load * op.torque / ch.ks[ch.iw]
    return State(th, ch.nominal.copy(), 0.0, ch.nominal.copy())


def continue_from(state: State, ch: Chain) -> State:
    """Keep angles and vibration velocities, move the mean speeds to the new nominal ones."""
    return State(state.theta.copy(), state.omega - state.nominal + ch.nominal, state.time, ch.nominal.copy())


def _steps_per_cycle(sys, op, steps_per_cycle: int, points_per_period: int) -> int:
    f_mesh = op.omega * sys.teeth[0] / (2 * np.pi)
    f_max = float(np.max(natural_frequencies(sys, op)["frequency"], initial=0.0))
    return int(max(steps_per_cycle, math.ceil(points_per_period * f_max / f_mesh)))


def run_cycles(sys, op, ch, st: State, n_cycles: int, spc: int):
    """Advance ``n_cycles`` mesh cycles in place; histories of those cycles (spc per cycle)."""
    t_mesh = 2 * np.pi / (op.omega * sys.teeth[0])
    dt = t_mesh / spc
    mesh = sys.mesh
    r1, r2 = sys.base_radius
    ramp = op.ramp_cycles * t_mesh
    t, th, om, f, d, dd = run_rk4(
        st.theta,
        st.omega,
        st.time,
        dt,
        n_cycles * spc,
        1,
        ch.args(ramp),
        MeshArgs(
            int(ch.ip),
            int(ch.iw),
            float(r1),
            float(r2),
            float(sys.teeth[0]),
            0.0,
            mesh.coefficients(mesh.stiffness),
            mesh.coefficients(mesh.unloaded_te),
            float(sys.mesh_damping),
            float(sys.backlash),
            int(ch.iy1),
            int(ch.iy2),
        ),
    )
    st.time = float(t[-1])
    if not (np.all(np.isfinite(st.theta)) and np.all(np.isfinite(st.omega))):
        bad = int(np.argmax(~(np.all(np.isfinite(th), axis=1) & np.all(np.isfinite(om), axis=1))))
        raise DivergenceError(
            "torsional mesh model (RK4)", t[bad], f"non-finite state after step {bad}; raise steady.steps_per_cycle"
        )
    return {"time": t, "theta": th, "omega": om, "force": f, "delta": d, "ddelta": dd}


def simulate(
    sys: TorsionalSystem,
    op: OperatingPoint,
    n_cycles: int,
    *,
    steps_per_cycle: int = 100,
    points_per_period: int = 40,
    state: State | None = None,
) -> dict:
    """Integrate ``n_cycles`` mesh cycles; every step is recorded.

    Parameters
    ----------
    steps_per_cycle : int
        Minimum RK4 steps per mesh cycle; raised so that the highest natural period gets
        ``points_per_period`` steps.
    state : State, optional
        Continue from this state (speed changed to ``op``); default: static equilibrium.

    Returns
    -------
    dict
        ``time`` [s], ``theta`` [rad], ``omega`` [rad/s] (per chain node), ``force`` [N],
        ``delta`` [m], ``ddelta`` [m/s], ``dte`` [m], ``spc``, ``state``, ``names``.
    """
    ch = build_chain(sys, op)
    st = initial_state(sys, op, ch) if state is None else continue_from(state, ch)
    spc = _steps_per_cycle(sys, op, steps_per_cycle, points_per_period)
    h = run_cycles(sys, op, ch, st, n_cycles, spc)
    r1, r2 = sys.base_radius
    h.update(dte=r1 * h["theta"][:, ch.ip] - r2 * h["theta"][:, ch.iw], spc=spc, state=st, names=ch.names)
    return h


def energy_balance(sys: TorsionalSystem, op: OperatingPoint, hist: dict) -> dict:
    """Energy bookkeeping of a :func:`simulate` history (NumPy, Simpson's rule in time).

    ``E = sum J omega^2 / 2 + sum k_s dtheta^2 / 2 + k(phi) delta_c^2 / 2`` (delta_c: the
    deflection in contact; with bearings also ``m y'^2 / 2 + k_b y^2 / 2``); power balance
    ``dE/dt = P_drive - T_out omega_L - D + P_par`` with the dissipation
    ``D = sum c_s domega^2 + c_m delta'^2`` (in contact) ``+ sum c_b y'^2`` and the parametric power of the
    time-varying mesh ``P_par = phi' (k'(phi) delta_c^2 / 2 - F e'(phi))``.

    Returns
    -------
    dict
        ``energy_change``, ``work_in`` (net work of drive and load torques), ``dissipated``,
        ``parametric``,
        ``residual`` = change - (in - out - dissipated + parametric) [J].
    """
    from scipy.integrate import simpson

    ch = build_chain(sys, op)
    th, om, t = hist["theta"], hist["omega"], hist["time"]
    r1, _ = sys.base_radius
    phase = sys.teeth[0] * th[:, ch.ip] / (2 * np.pi)
    dphase = sys.teeth[0] * om[:, ch.ip] / (2 * np.pi)
    k, dk, _, de = sys.mesh.evaluate(phase)
    d, dd, f = hist["delta"], hist["ddelta"], hist["force"]
    b = sys.backlash
    dc = np.where(d > 0, d, np.where((b >= 0) & (d < -b), d + b, 0.0))
    contact = dc != 0
    free = ~ch.presc
    kin = 0.5 * np.sum(ch.inertia[free] * om[:, free] ** 2, axis=1)
    pot, diss = ch.add_strain_and_dissipation(th, om, 0.5 * k * dc**2, sys.mesh_damping * dd**2 * contact)
    p_in = ch.drive_power(op, sys.teeth[0], th, om, t, f, r1)
    p_par = dphase * (0.5 * dk * dc**2 - f * de)
    e_tot = kin + pot

    def integral(p):
        return float(simpson(p, x=t))

    out = {
        "energy_change": float(e_tot[-1] - e_tot[0]),
        "work_in": integral(p_in),
        "dissipated": integral(diss),
        "parametric": integral(p_par),
    }
    out["residual"] = out["energy_change"] - (out["work_in"] - out["dissipated"] + out["parametric"])
    return out


# ----------------------------------------------------------------------------- steady state
@dataclass
class ChainSteady:
    """The lumped chain as a :class:`~rotaflex.gear.solvers.steady_driver.SteadyMethod`."""

    system: TorsionalSystem
    op: OperatingPoint
    chain: Chain = field(init=False)
    keep: tuple = ("time", "force", "dte", "force_no_te_rate")
    attrs: dict = field(default_factory=dict)

    def __post_init__(self):
        self.chain = build_chain(self.system, self.op)

    def start(self, state: State | None) -> State:
        sys, op, ch = self.system, self.op, self.chain
        return initial_state(sys, op, ch) if state is None else continue_from(state, ch)

    def steps_per_cycle(self, steps: int, points_per_period: int) -> int:
        return _steps_per_cycle(self.system, self.op, steps, points_per_period)

    def run(self, state: State, n_cycles: int, spc: int) -> dict:
        ch = self.chain
        h = run_cycles(self.system, self.op, ch, state, n_cycles, spc)
        r1, r2 = self.system.base_radius
        h["dte"] = r1 * h["theta"][:, ch.ip] - r2 * h["theta"][:, ch.iw]
        # the mesh force without the damper's answer to the rate of a loaded-TE table's -F0/k
        # part (e = LTE - F0/k steps where k does; no geometry does). 1/k is interpolated as the
        # kernel interpolates e (coefficients linear in the table), so c_m F0 d(1/k)/dt is
        # exactly the part of c_m de/dt that comes from it.
        f = h["force"]
        mesh, z1 = self.system.mesh, self.system.teeth[0]
        fix = np.zeros_like(f)
        if mesh.static_force > 0:
            inv = MeshTable(mesh.stiffness, 1.0 / mesh.stiffness, mesh.interpolation)
            du = inv.evaluate(z1 * h["theta"][:, ch.ip] / (2 * np.pi))[3]  # d(1/k)/dphi
            fix = -self.system.mesh_damping * mesh.static_force * du * z1 * h["omega"][:, ch.ip] / (2 * np.pi)
        h["force_no_te_rate"] = np.where(f != 0.0, f + fix, 0.0)
        return h

    def annotate(self, ds, buf: dict, sl: slice) -> None:
        """Nothing beyond the common variables."""


def steady_state(sys: TorsionalSystem, op: OperatingPoint, *, state: State | None = None, **kw):
    """Run until periodic, then evaluate the last ``eval_cycles`` mesh cycles.

    The procedure, tolerances and keywords of
    :func:`rotaflex.gear.solvers.steady_driver.run_steady` (``tol``, ``min_cycles``,
    ``max_cycles``, ``eval_cycles``, ``fixed_cycles``, ``max_period``, ``steps_per_cycle``,
    ``points_per_period``, ``config``).

    Returns
    -------
    (SteadyStateResult, State)
        The result (histories of the evaluated cycles, metrics, natural frequencies) and the
        final state for continuation.
    """
    from rotaflex.gear.solvers.steady_driver import run_steady

    return run_steady(ChainSteady(sys, op), op, state=state, **kw)
