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

import numpy as np

from rotaflex.core.errors import DivergenceError
from rotaflex.gear.kernels.chain import MeshArgs, run_rk4
from rotaflex.gear.models.chain_system import (
    Chain,
    OperatingPoint,
    TorsionalSystem,
    build_chain,
    natural_frequencies,
    resonance_speeds_rpm,
)
from rotaflex.gear.models.mesh_stiffness import MeshTable
from rotaflex.gear.solvers.steady_loop import run_steady
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
    """The lumped chain as a :class:`~rotaflex.gear.solvers.steady_loop.SteadyMethod`."""

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
    :func:`rotaflex.gear.solvers.steady_loop.run_steady` (``tol``, ``min_cycles``,
    ``max_cycles``, ``eval_cycles``, ``fixed_cycles``, ``max_period``, ``steps_per_cycle``,
    ``points_per_period``, ``config``).

    Returns
    -------
    (SteadyStateResult, State)
        The result (histories of the evaluated cycles, metrics, natural frequencies) and the
        final state for continuation.
    """
    return run_steady(ChainSteady(sys, op), op, state=state, **kw)
