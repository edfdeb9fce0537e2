"""Time simulation of rotor-disk and free rigid-body models with ``scipy.integrate.solve_ivp``.

``scipy.integrate`` and the symbolic derivation (sympy) are imported by :func:`simulate`, not by
this module: ``rotaflex.rotor`` is imported by every rotor verb (``campbell`` too), and those
two cost ~1 s of start-up that only a time simulation needs.
"""

from __future__ import annotations

import json
import logging
import time as _time
from dataclasses import asdict

import numpy as np

from rotaflex.core.config import budget
from rotaflex.rotation.quaternion import (
    quaternion_from_euler,
    quaternion_rates_from_body,
    quaternion_to_matrix,
    rates_from_quaternion,
)
from rotaflex.rotor.model import FreeBody, RotorModel
from rotaflex.rotor.result import RotorResult
from rotaflex.rotor.symbolic import PARAMETERS, EOMSpec, compiled

log = logging.getLogger(__name__)


def spec_of(model: RotorModel | FreeBody) -> EOMSpec:
    """The symbolic-derivation key of a model."""
    f = model.formulation
    spin = None if isinstance(model, FreeBody) else f.spin_index
    if f.parameterisation == "quaternion_spherical":
        return EOMSpec("quaternion_spherical", "123", "right-handed", f.energy, f.expansion, 0)
    return EOMSpec("euler", f.sequence, f.convention, f.energy, f.expansion, spin)


def polar_axis(model: RotorModel) -> int:
    """Body axis (0, 1, 2) of the prescribed spin: x for the spherical quaternion."""
    f = model.formulation
    return 0 if f.parameterisation == "quaternion_spherical" else int(f.sequence[f.spin_index]) - 1


def body_inertia(model: RotorModel | FreeBody) -> np.ndarray:
    """Principal inertias about body x, y, z [kg m^2]."""
    if isinstance(model, FreeBody):
        return np.array(model.inertia)
    if model.disk.inertia is not None:
        return np.array(model.disk.inertia)
    J = np.full(3, model.disk.diametral_inertia)
    J[polar_axis(model)] = model.disk.polar_inertia
    return J


def parameter_vector(model: RotorModel | FreeBody) -> np.ndarray:
    J = body_inertia(model)
    values = dict(
        zip(("J1", "J2", "J3"), J, strict=False),
        m=1.0,
        k=0.0,
        k_tilt=0.0,
        Omega=0.0,
        phi0=0.0,
        tau1=0.0,
        tau2=0.0,
        tau3=0.0,
    )
    if isinstance(model, RotorModel):
        values.update(
            m=model.disk.mass,
            k=model.support.stiffness,
            k_tilt=model.support.tilt_stiffness,
            Omega=model.motion.spin_speed,
            phi0=model.motion.initial_spin_angle,
        )
    else:
        values.update(tau1=model.torque[0], tau2=model.torque[1], tau3=model.torque[2])
    return np.array([values[name] for name in PARAMETERS])


#: steps per period of the fastest motion that an explicit method needs at tight tolerances
#: (DOP853 at rtol 1e-9 took 20-40 on the paper's rotor cases); used only for the estimate
STEPS_PER_PERIOD = 40
#: right-hand-side evaluations per step (DOP853: 12; implicit methods use more, with Jacobians)
EVALS_PER_STEP = 12
#: wall time of one right-hand-side evaluation [s] (measured 20-60 us for the generated code)
EVAL_SECONDS = 40e-6


def fastest_rate(model: RotorModel | FreeBody) -> float:
    """Largest angular frequency of the motion [rad/s], an upper estimate used for step budgets.

    Spin, initial rates, support natural frequencies, all scaled by the inertia ratio (the
    gyroscopic whirl of a disk runs up to J_max/J_min times the spin).
    """
    J = body_inertia(model)
    ratio = float(np.max(J) / np.min(J))
    if isinstance(model, FreeBody):
        rates = [float(np.max(np.abs(model.initial_body_rate)))]
        torque = float(np.max(np.abs(model.torque)))
        rates.append(np.sqrt(torque / float(np.min(J))))  # rate reached in 1 s under the torque, order
    else:
        mo, su = model.motion, model.support
        rates = [
            abs(mo.spin_speed),
            float(np.max(np.abs(mo.initial_tilt_rate))),
            np.sqrt(su.stiffness / model.disk.mass),
            np.sqrt(su.tilt_stiffness / float(np.min(J))),
        ]
    return ratio * max(rates)


def estimated_steps(model: RotorModel | FreeBody) -> float:
    """Estimated integration steps for ``model.solver.t_end`` (at least 1)."""
    w = fastest_rate(model)
    return max(1.0, model.solver.t_end * w / (2 * np.pi) * STEPS_PER_PERIOD)


def check_budget(model: RotorModel | FreeBody) -> None:
    """Refuse a run whose estimated steps exceed ``solver.max_steps`` (InputError naming the
    field that drives the estimate, with the estimated wall time)."""
    steps = estimated_steps(model)
    s = model.solver
    if steps <= s.max_steps:
        return
    seconds = steps * EVALS_PER_STEP * EVAL_SECONDS
    prefix = "free_body." if isinstance(model, FreeBody) else ""
    field, value = f"{prefix}solver.t_end", s.t_end
    if isinstance(model, RotorModel) and abs(model.motion.spin_speed) * s.t_end > 1e6:
        if abs(model.motion.spin_speed) >= 1e4:
            field, value = "motion.spin_speed", model.motion.spin_speed
    budget(
        field,
        value,
        steps,
        s.max_steps,
        f"integration steps (solver.max_steps; this run would take ~{_duration(seconds)}; "
        "shorten t_end or raise max_steps)",
    )


def _duration(seconds: float) -> str:
    for unit, size in (("days", 86400.0), ("h", 3600.0), ("min", 60.0)):
        if seconds >= size:
            return f"{seconds / size:.3g} {unit}"
    return f"{seconds:.3g} s"


class _StepBudget(Exception):
    """Raised from the right-hand side when a run exceeds its evaluation budget."""

    def __init__(self, t: float):
        self.t = t


class _Progress:
    """A tqdm bar over simulated time, updated from the right-hand side at most 200 times."""

    def __init__(self, t_end: float, enabled: bool, max_evals: float = float("inf")):
        self.t_end, self.bar, self.shown = t_end, None, 0.0
        self.evals, self.max_evals = 0, max_evals
        self.t_over = None  # time of the first evaluation past the budget
        if enabled:  # a bar on a terminal, one line per update in a log
            from rotaflex.core.progress import Progress

            self.bar = Progress(t_end, "simulating", "s")

    def __call__(self, t: float) -> None:
        self.evals += 1
        if self.evals > self.max_evals and self.t_over is None:
            self.t_over = t  # the budget event stops the run at the end of this step
        if self.evals > 2 * self.max_evals:
            raise _StepBudget(t)  # last resort if one step alone runs away
        if self.bar is not None and t - self.shown >= self.t_end / 200:
            self.bar.update(min(t, self.t_end))
            self.shown = t

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()


def simulate(model: RotorModel | FreeBody, *, progress: bool = False):
    """Integrate a rotor-disk or free-body model.

    Parameters
    ----------
    model : RotorModel or FreeBody
    progress : bool
        Show a progress bar over simulated time.

    Returns
    -------
    RotorResult
        ``status`` is "success", "singular" (the mass matrix became singular: the run stops at
        that time and ``message`` says when and how singular) or "failed" (integrator failure).
    """
    check_budget(model)
    if not (isinstance(model, FreeBody) and model.formulation.parameterisation == "quaternion"):
        compiled(spec_of(model))  # derive/load the equations first: not counted as solver time
    _import_solver_modules()  # nor are imports: the first run of a process paid ~0.3 s for them
    t0 = _time.perf_counter()
    solver = model.solver
    p = parameter_vector(model)
    t_eval = np.linspace(0.0, solver.t_end, solver.n_output)
    # the estimate can be low (stiff or chaotic motion): stop at 4x the budget rather than hang
    bar = _Progress(solver.t_end, progress, max_evals=4 * EVALS_PER_STEP * solver.max_steps)
    try:
        if isinstance(model, FreeBody) and model.formulation.parameterisation == "quaternion":
            sol, outputs = _integrate_newton_euler(model, p, t_eval, bar)
        else:
            sol, outputs = _integrate_lagrange(model, p, t_eval, bar)
    finally:
        bar.close()
    ds = outputs
    ds.attrs.update(
        status=sol["status"],
        message=sol["message"],
        nfev=int(sol["nfev"]),
        wall_time=_time.perf_counter() - t0,
        config=json.dumps({"kind": type(model).__name__, **asdict(model)}),
        formulation=repr(spec_of(model))
        if not (isinstance(model, FreeBody) and model.formulation.parameterisation == "quaternion")
        else "unit quaternion, Newton-Euler",
    )
    return RotorResult(ds)


def _import_solver_modules() -> None:
    """Import what the solve and its dataset use, before the solver clock starts."""
    import scipy.integrate  # noqa: F401

    from rotaflex.core.result import freeze_imports, import_xarray

    import_xarray()
    freeze_imports()


def _solve_stacked(Ms: np.ndarray, fs: np.ndarray) -> np.ndarray:
    """``M_i^-1 f_i`` for every output sample at once; NaN where ``M_i`` is singular."""
    with np.errstate(all="ignore"):
        try:
            return np.linalg.solve(Ms, fs[..., None])[..., 0]
        except np.linalg.LinAlgError:  # a singular sample (a run stopped at a singularity)
            out = np.full(fs.shape, np.nan)
            for i, (M, f) in enumerate(zip(Ms, fs, strict=True)):
                try:
                    out[i] = np.linalg.solve(M, f)
                except np.linalg.LinAlgError:
                    pass
            return out


def _mass_measure(M_rot: np.ndarray, J_max: float) -> float:
    """det of the rotational mass block relative to the inertia scale (0 = singular)."""
    n = M_rot.shape[0]
    return float(np.linalg.det(M_rot)) / J_max**n


def _integrate_lagrange(model, p, t_eval, bar):
    from scipy.linalg.lapack import dgesv

    ns = compiled(spec_of(model))
    n = ns["N_DOF"]
    all_fn, mass_rhs = ns["_all"], ns["_mass_rhs"]  # mass_rhs: M and f only (no attitude outputs)
    n_trans = 2 if isinstance(model, RotorModel) else 0
    J_max = float(np.max(body_inertia(model)))
    tol = model.solver.singular_tolerance

    # the generated code is scalar arithmetic: on Python floats it runs 3x faster than on the
    # numpy scalars that unpacking arrays gives (3.4 us against 11 us a call), same IEEE results
    p_floats = p.tolist()

    def equations(fn, t, y):
        try:
            return fn(float(t), y.tolist(), p_floats)
        except OverflowError:  # a float power beyond 1e308: numpy scalars give inf instead
            return fn(t, y, p)

    diagonal = [k * (n + 1) for k in range(n)] if ns["MASS_DIAGONAL"] else None

    def rhs(t, y):  # called ~4000 times a run: no work beyond the equations and one solve
        bar(t)
        yl = y.tolist()
        try:
            M, f = mass_rhs(float(t), yl, p_floats)
        except OverflowError:  # as in equations()
            M, f = mass_rhs(t, y, p)
        if diagonal is not None:  # LAPACK's dgesv divides by the pivots here: same bits (tested)
            m = [M[k] for k in diagonal]
            if 0 in m:
                raise np.linalg.LinAlgError("Singular matrix")
            return np.array(yl[n:] + [fk / mk for fk, mk in zip(f, m, strict=True)])
        _, _, qdd, info = dgesv(np.array(M).reshape(n, n), f)  # LAPACK directly: np.linalg.solve costs 5x more
        if info > 0:
            raise np.linalg.LinAlgError("Singular matrix")
        return np.concatenate((y[n:], qdd))

    def singular(t, y):
        M = np.array(equations(mass_rhs, t, y)[0]).reshape(n, n)
        return _mass_measure(M[n_trans:, n_trans:], J_max) - tol

    singular.terminal, singular.direction = True, -1

    if isinstance(model, RotorModel):
        mo = model.motion
        y0 = np.array([*mo.initial_displacement, *mo.initial_tilt, *mo.initial_velocity, *mo.initial_tilt_rate])
    else:
        f = model.formulation
        from rotaflex.rotation.euler import euler_rates_from_body

        rates = euler_rates_from_body(f.sequence, model.initial_angles, model.initial_body_rate)
        y0 = np.array([*model.initial_angles, *rates])

    measure0 = singular(0.0, y0) + tol
    if measure0 < tol:
        status, message = (
            "singular",
            (
                f"mass matrix singular at t = 0: relative det {measure0:.3e} "
                f"< {tol:g}; choose another initial attitude/spin angle"
            ),
        )
        sol_t, sol_y, nfev = np.array([0.0]), y0[:, None], 0
    else:
        sol = _solve(rhs, y0, model.solver, t_eval, bar, events=singular)
        sol_t, sol_y, nfev = sol.t, sol.y, sol.nfev
        if sol.status == 1:
            t_s = float(sol.t_events[0][0])
            status = "singular"
            message = (
                f"mass matrix became singular at t = {t_s:.6g} s (relative det < {tol:g}); integration stopped there"
            )
            # keep the exact event state as the last sample
            sol_t = np.append(sol_t, t_s)
            sol_y = np.hstack([sol_y, sol.y_events[0][0][:, None]])
        elif sol.status == 0:
            status, message = "success", f"integrated to t = {t_eval[-1]:g} s ({sol.nfev} evaluations)"
        else:
            status, message = "failed", sol.message
    q, qd = sol_y[:n].T, sol_y[n:].T
    # output only, not the time loop: the samples' tuples are turned into arrays once
    samples = [equations(all_fn, ti, yi) for ti, yi in zip(sol_t, sol_y.T, strict=False)]
    Ms, fs, e, e_dot = (np.array([s[k] for s in samples], float) for k in range(4))
    qdd = _solve_stacked(Ms.reshape(-1, n, n), fs)
    ds = _dataset(model, sol_t, q, qd, e, e_dot, ns["COORDINATES"], p)
    ds["generalized_acceleration"] = (
        ("time", "coordinate"),
        qdd,
        _mixed(ns["COORDINATES"], " s-2", "generalized accelerations"),
    )
    return {"status": status, "message": message, "nfev": nfev}, ds


def _integrate_newton_euler(model: FreeBody, p, t_eval, bar):
    J = body_inertia(model)
    tau = np.array(model.torque)
    e0 = quaternion_from_euler(model.formulation.sequence, model.initial_angles)

    def rhs(t, y):
        bar(t)
        e, w = y[:4], y[4:]
        norm2 = e @ e
        tau_b = tau if model.torque_frame == "body" else quaternion_to_matrix(e).T @ tau
        # the (1 - |e|^2) e term pulls |e| back to 1 without changing exact solutions
        e_dot = quaternion_rates_from_body(e / np.sqrt(norm2), w) + (1.0 - norm2) * e
        w_dot = (tau_b - np.cross(w, J * w)) / J
        return np.concatenate([e_dot, w_dot])

    s = model.solver
    sol = _solve(rhs, np.concatenate([e0, model.initial_body_rate]), s, t_eval, bar)
    e = sol.y[:4].T / np.linalg.norm(sol.y[:4].T, axis=1, keepdims=True)
    w = sol.y[4:].T
    e_dot = quaternion_rates_from_body(e, w)
    ds = _dataset(model, sol.t, e, e_dot, e, e_dot, ("e0", "e1", "e2", "e3"), p)
    status = "success" if sol.status == 0 else "failed"
    msg = f"integrated to t = {sol.t[-1]:g} s ({sol.nfev} evaluations)" if sol.status == 0 else str(sol.message)
    return {"status": status, "message": msg, "nfev": sol.nfev}, ds


def _solve(rhs, y0, solver, t_eval, bar, events=None):
    """``solve_ivp`` that always returns at least the initial sample and says how it failed.

    A failure before the first output sample (e.g. the first step already below the spacing of
    floating-point numbers) or an exceeded step budget gives ``status = -1`` with the time
    reached in ``message``; the samples integrated so far are kept.
    """
    from types import SimpleNamespace

    from scipy.integrate import solve_ivp

    def budget(t, y):
        # zero at the time the budget ran out, so the run stops there and keeps its samples
        return 1.0 if bar.t_over is None else bar.t_over - t

    budget.terminal = True
    listed = [] if events is None else (list(events) if isinstance(events, (list, tuple)) else [events])
    budget_message = (
        "step budget exceeded: {evals} right-hand-side evaluations reached t = {t:.6g} s "
        f"of {t_eval[-1]:g} s (solver.max_steps = {solver.max_steps}); the motion is faster or "
        "stiffer than estimated: shorten t_end, loosen rtol or raise max_steps"
    )
    try:
        sol = solve_ivp(
            rhs,
            (0.0, t_eval[-1]),
            y0,
            method=solver.method,
            t_eval=t_eval,
            rtol=solver.rtol,
            atol=solver.atol,
            events=[*listed, budget],
        )
    except _StepBudget as exc:
        return SimpleNamespace(
            t=np.array([0.0]),
            y=np.asarray(y0, float)[:, None],
            nfev=bar.evals,
            status=-1,
            message=budget_message.format(evals=bar.evals, t=exc.t),
            t_events=None,
            y_events=None,
        )
    sol.t = np.asarray(sol.t, float)
    sol.y = np.asarray(sol.y, float).reshape(len(y0), -1)
    if sol.status == 1 and len(sol.t_events[-1]):  # the budget event: keep what was integrated
        t_b = float(sol.t_events[-1][0])
        sol.t = np.append(sol.t, t_b)
        sol.y = np.hstack([sol.y, sol.y_events[-1][0][:, None]])
        sol.status = -1
        sol.message = budget_message.format(evals=bar.evals, t=t_b)
    sol.t_events = None if sol.t_events is None else sol.t_events[: len(listed)]
    sol.y_events = None if sol.y_events is None else sol.y_events[: len(listed)]
    if sol.status == -1:
        reached = float(sol.t[-1]) if sol.t.size else 0.0
        sol.message = f"integration failed after t = {reached:.6g} s of {t_eval[-1]:g} s: {sol.message}"
    if sol.t.size == 0 or sol.t[0] != 0.0:  # failed before the first output sample
        sol.t = np.concatenate([[0.0], sol.t])
        sol.y = np.hstack([np.asarray(y0, float)[:, None], sol.y])
    return sol


def coordinate_unit(name: str) -> str:
    """CF unit of a generalized coordinate: translations in m, angles in rad, quaternion 1."""
    if name in ("U", "V"):
        return "m"
    if name.startswith(("e", "eps")):
        return "1"
    return "rad"


def _mixed(coordinates, per: str, long_name: str) -> dict:
    """Attributes of a variable over ``coordinate``: a CF ``units`` string when every coordinate
    has the same unit; otherwise no ``units`` (CF has no mixed units) and the per-coordinate
    units named in ``units_per_coordinate`` (the ``coordinate_units`` coordinate, times ``per``)."""
    units = {coordinate_unit(c) for c in coordinates}
    if len(units) == 1:
        u = units.pop()
        return {"units": (u + per) if u != "1" else (per.strip() or "1"), "long_name": long_name}
    return {"long_name": long_name, "units_per_coordinate": "coordinate_units" + (f" times{per}" if per else "")}


def _dataset(model, t, q, qd, e, e_dot, coordinates, p):
    """Result variables common to every parameterisation (computed from the attitude)."""
    import xarray as xr

    J = body_inertia(model)
    w_body, w_inertial = rates_from_quaternion(e, e_dot)
    R = quaternion_to_matrix(e)
    K_rot = 0.5 * np.einsum("ti,i,ti->t", w_body, J, w_body)
    K_paper = 0.5 * np.einsum("ti,i,ti->t", w_inertial, J, w_inertial)
    H = np.einsum("tij,j,tj->ti", R, J, w_body)
    vars_ = {
        "generalized_coordinate": (
            ("time", "coordinate"),
            q,
            _mixed(coordinates, "", "generalized coordinates q"),
        ),
        "generalized_velocity": (
            ("time", "coordinate"),
            qd,
            _mixed(coordinates, " s-1", "generalized velocities dq/dt"),
        ),
        "quaternion": (("time", "component"), e, {"units": "1", "long_name": "Euler parameters"}),
        "omega_body": (("time", "axis"), w_body, {"units": "rad/s", "long_name": "body-frame angular velocity"}),
        "omega_inertial": (
            ("time", "axis"),
            w_inertial,
            {"units": "rad/s", "long_name": "inertial-frame angular velocity"},
        ),
        "rotational_kinetic_energy": (
            "time",
            K_rot,
            {"units": "J", "long_name": "rotational kinetic energy 1/2 w*^T J w*"},
        ),
        "rotational_energy_paper": (
            "time",
            K_paper,
            {"units": "J", "long_name": "paper's 1/2 w^T J w (body J, inertial w)"},
        ),
        "angular_momentum": (
            ("time", "axis"),
            H,
            {"units": "kg m^2/s", "long_name": "angular momentum (inertial frame)"},
        ),
    }
    K = K_rot.copy()
    if isinstance(model, RotorModel):
        m, k, k_tilt = p[0], p[4], p[5]
        K += 0.5 * m * np.sum(qd[:, :2] ** 2, axis=1)
        polar = polar_axis(model)
        V = 0.5 * k * np.sum(q[:, :2] ** 2, axis=1) + k_tilt * (1.0 - R[:, polar, polar])
        tilt = np.arccos(np.clip(R[:, polar, polar], -1.0, 1.0))
        vars_["potential_energy"] = ("time", V, {"units": "J", "long_name": "support potential energy"})
        vars_["tilt_angle"] = ("time", tilt, {"units": "rad", "long_name": "polar-axis tilt from nominal"})
    vars_["kinetic_energy"] = ("time", K, {"units": "J", "long_name": "kinetic energy"})
    return xr.Dataset(
        vars_,
        coords={
            "time": ("time", t, {"units": "s"}),
            "coordinate": ("coordinate", list(coordinates)),
            "coordinate_units": ("coordinate", [coordinate_unit(c) for c in coordinates]),
            "axis": ("axis", ["x", "y", "z"]),
            "component": ("component", ["e0", "e1", "e2", "e3"]),
        },
    )
