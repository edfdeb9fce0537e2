"""Start-up transient of a train from rest: motor torque-speed curve against the load, twist DOFs only.

Equations (torsional model of :func:`rotaflex.system.torsion.torsional_model`, solved coordinates p,
twists ``theta = T p``):

    J p'' + C p' + K p = T^T (e_d s_d tau_m + e_l s_l tau_l)

with the motor torque ``tau_m = T_m(n_d) + A sin(2 w_line t - P s_d theta_d)`` on the drive node
(``T_m``: the ``[drive]`` curve over the drive node's speed n_d = s_d theta_d'; A: the amplitude
of the pulsating torque at twice the slip frequency of a synchronous motor during asynchronous
start, ``2 (w_line - P/2 n_d)``, P poles; ``A = 0`` for an induction motor's curve alone) and
the load torque ``tau_l = -(T_0 + q n_l |n_l|)`` on the load node (n_l = s_l theta_l'); a load's
viscous ``damping`` is in C. The modes of (K, J) below ``max_frequency`` (all by default) are
kept: ``p = Phi eta`` with ``Phi^T J Phi = I``; scipy's Radau integrates ``eta`` with the exact
Jacobian, plus three work integrals (motor, load, dissipation ``p'^T C p'``) that close the
energy balance ``E_kin + E_pot = W_motor - W_load - W_damping``.
"""

from __future__ import annotations

import bisect
import functools
import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

from rotaflex.core.errors import DivergenceError, InputError
from rotaflex.system.model import Gearbox
from rotaflex.system.torsion import TorsionalModel, eigen, n_rigid


@dataclass(frozen=True)
class Motor:
    """Torque-speed curve (``speed`` [rad/s] increasing, ``torque`` [N m], linear between points,
    end values held outside) and the pulsating torque (amplitude [N m], line frequency [rad/s],
    number of poles)."""

    speed: np.ndarray
    torque: np.ndarray
    pulsating: float = 0.0
    line: float = 0.0
    poles: int = 2

    def at(self, n: float) -> tuple[float, float]:
        """Curve torque [N m] and its slope [N m s/rad] at speed n [rad/s] (scalar: called once
        per right-hand side, where numpy's per-call overhead would dominate)."""
        sp, tq = self._table
        if n <= sp[0]:
            return tq[0], 0.0
        if n >= sp[-1]:
            return tq[-1], 0.0
        i = bisect.bisect_right(sp, n) - 1
        slope = (tq[i + 1] - tq[i]) / (sp[i + 1] - sp[i])
        return tq[i] + slope * (n - sp[i]), slope

    @functools.cached_property
    def _table(self) -> tuple[list, list]:
        return [float(x) for x in self.speed], [float(x) for x in self.torque]


@dataclass(frozen=True)
class StartupRun:
    """Histories of a run-up: ``time`` (nt,) [s], ``theta``/``rate`` (nt, n_twist) [rad, rad/s],
    ``motor_torque``/``load_torque`` (nt,) [N m] (magnitudes in the sense of rotation),
    ``work`` (nt, 3) motor, load, damping [J], ``energy`` (nt, 2) kinetic, potential [J],
    ``n_modes`` kept, ``nfev``, ``status`` and ``message`` of the integrator."""

    time: np.ndarray
    theta: np.ndarray
    rate: np.ndarray
    motor_torque: np.ndarray
    load_torque: np.ndarray
    work: np.ndarray
    energy: np.ndarray
    n_modes: int
    nfev: int
    message: str

    @property
    def balance(self) -> np.ndarray:
        """Energy balance residual ``E_kin + E_pot - (W_m - W_l - W_d)`` [J] (nt,)."""
        return self.energy.sum(1) - (self.work[:, 0] - self.work[:, 1] - self.work[:, 2])


def load_torque(n, t0: float, quadratic: float):
    """Load torque [N m] at load speed n [rad/s]: ``t0 + q n |n|``, and its slope."""
    return t0 + quadratic * n * np.abs(n), 2.0 * quadratic * np.abs(n)


def startup(
    box: Gearbox,
    model: TorsionalModel,
    motor: Motor,
    load: tuple[float, float],
    duration: float,
    n_out: int = 2001,
    max_frequency: float | None = None,
    rtol: float = 1e-6,
) -> StartupRun:
    """Run-up from rest over ``duration`` [s] (see the module docstring).

    ``load`` = (T_0 [N m], q [N m s^2/rad^2]) on the [load] node (none: no load torque);
    ``max_frequency`` [rad/s]: highest mode kept (None: all).
    """
    d = model.index(box, *box.drive)
    sd = float(model.sense[d])
    if box.load is not None:
        li = model.index(box, *box.load)
        sl = float(model.sense[li])
    else:
        li, sl, load = d, sd, (0.0, 0.0)
    w2, phi = eigen(model)
    w = np.sqrt(np.clip(w2, 0.0, None))
    if max_frequency is not None:
        phi, w2 = phi[:, w <= max_frequency], w2[w <= max_frequency]
    B = model.T @ phi  # twists per modal coordinate (n_twist, r)
    r = phi.shape[1]
    Cr = phi.T @ model.C @ phi
    Lam = np.clip(w2, 0.0, None)
    Lam[: n_rigid(model.K)] = 0.0  # the rigid rotation: no restoring torque (not round-off)
    bd, bl = B[d], B[li]
    poles = motor.poles

    t0, q = (float(x) for x in load)
    amp, line = float(motor.pulsating), float(motor.line)

    def torques(t, eta, deta):
        nd, nl = float(sd * (bd @ deta)), float(sl * (bl @ deta))
        tm, sm = motor.at(nd)
        ang = 2.0 * line * t - poles * sd * float(bd @ eta)
        tm = tm + amp * math.sin(ang)
        return nd, nl, tm, sm, t0 + q * nl * abs(nl), 2.0 * q * abs(nl), ang

    def rhs(t, y):
        eta, deta = y[:r], y[r : 2 * r]
        nd, nl, tm, _, tl, _, _ = torques(t, eta, deta)
        f = bd * (sd * tm) - bl * (sl * tl)
        dd = deta @ Cr @ deta
        out = np.empty(2 * r + 3)
        out[:r], out[r : 2 * r] = deta, f - Cr @ deta - Lam * eta
        out[2 * r :] = tm * nd, tl * nl, dd
        return out

    def jac(t, y):
        eta, deta = y[:r], y[r : 2 * r]
        nd, nl, tm, sm, tl, sll, ang = torques(t, eta, deta)
        Jm = np.zeros((2 * r + 3, 2 * r + 3))
        Jm[:r, r : 2 * r] = np.eye(r)
        Jm[r : 2 * r, :r] = -np.diag(Lam) - motor.pulsating * np.cos(ang) * poles * np.outer(bd, bd)
        Jm[r : 2 * r, r : 2 * r] = -Cr + sm * np.outer(bd, bd) - sll * np.outer(bl, bl)
        Jm[2 * r, :r] = -motor.pulsating * np.cos(ang) * poles * sd * bd * nd
        Jm[2 * r, r : 2 * r] = (tm + sm * nd) * sd * bd
        Jm[2 * r + 1, r : 2 * r] = (tl + sll * nl) * sl * bl
        Jm[2 * r + 2, r : 2 * r] = 2.0 * Cr @ deta
        return Jm

    # absolute tolerances from each coordinate's scale: the static modal response to the peak
    # motor torque (the first elastic mode's for the rigid rotation), its rate at the mode's
    # frequency, and the motor's work over the run
    t_max = float(np.max(np.abs(motor.torque))) + motor.pulsating
    w_el = np.sqrt(Lam[Lam > 0].min()) if np.any(Lam > 0) else 1.0
    wk = np.maximum(np.sqrt(Lam), w_el)
    x_scale = np.maximum(np.abs(bd), 1e-3 * np.abs(bd).max()) * t_max / wk**2
    work = t_max * float(motor.speed[-1]) * duration
    atol = 1e-2 * rtol * np.concatenate([x_scale, x_scale * wk, [work] * 3])
    t_eval = np.linspace(0.0, duration, n_out)
    max_step = duration / 200.0
    if motor.pulsating and motor.line:
        max_step = min(max_step, np.pi / (10.0 * motor.line))  # 20 steps per period of 2 w_line
    sol = solve_ivp(
        rhs, (0.0, duration), np.zeros(2 * r + 3), "Radau", t_eval, jac=jac, rtol=rtol, atol=atol, max_step=max_step
    )
    if not sol.success:
        raise DivergenceError("startup transient (Radau)", float(sol.t[-1]), sol.message)
    eta, deta, work = sol.y[:r].T, sol.y[r : 2 * r].T, sol.y[2 * r :].T
    theta, rate = eta @ B.T, deta @ B.T
    tm = np.array([torques(t, e, v)[2] for t, e, v in zip(sol.t, eta, deta, strict=True)])
    tl = load_torque(sl * rate[:, li], *load)[0]
    energy = np.stack([0.5 * np.sum(deta**2, 1), 0.5 * np.sum(Lam * eta**2, 1)], 1)
    return StartupRun(sol.t, theta, rate, tm, tl, work, energy, r, sol.nfev, sol.message)


def check_start(box: Gearbox, motor: Motor, load: tuple[float, float]) -> float:
    """Steady speed [rad/s] of the drive where motor and load torque balance (referred to the
    drive through the speed ratio; viscous load damping included), checked to lie in the curve
    and above standstill; InputError naming the ``[drive]`` curve otherwise."""
    from scipy.optimize import brentq

    rl = box.rotors[box.load[0]].ratio if box.load is not None else 1.0
    c = box.spec.load.damping if box.load is not None and box.spec.load is not None else 0.0
    t0, q = load if box.load is not None else (0.0, 0.0)

    def excess(n):
        return motor.at(n)[0] - rl * (load_torque(rl * n, t0, q)[0] + c * rl * n)

    if excess(motor.speed[0]) <= 0:
        raise InputError(
            "drive.curve_torque", float(motor.torque[0]), f"a starting torque above the load's {rl * t0:.6g} N m"
        )
    if excess(motor.speed[-1]) >= 0:
        raise InputError(
            "drive.curve_torque",
            float(motor.torque[-1]),
            "a curve that falls below the load torque before its last speed (the steady speed inside the table)",
        )
    return float(brentq(excess, motor.speed[0], motor.speed[-1], xtol=1e-12))
