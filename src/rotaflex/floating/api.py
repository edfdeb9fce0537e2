"""One-call library API: :func:`run` a case file, a config table, or bodies and loads in Python,
optionally with loads computed by a Python callable of time and state (sampled-data control).

Example (a slew controller closing the loop on attitude)::

    from rotaflex.floating import run, uniform_beam, Settings

    def pd(t, state):  # torque about z from the measured attitude and rate
        return [("torque", (0.0, 0.0, -4.0 * (state.euler_123[2] - 1.0)
                            - 6.0 * state.angular_velocity[2]))]

    res = run(body=uniform_beam(4.0, 2.0, 40.0, 4), controller=pd, control_dt=0.02,
              solver=Settings(method="full", t_end=10.0, dt_out=0.02),
              outputs={"tip": (2.0, 0.0, 0.0)})
    res.dataset.attrs["wall_time"], res.dataset.attrs["config"]
"""

from __future__ import annotations

import json
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, replace
from pathlib import Path

import numpy as np

from rotaflex.core.errors import InputError
from rotaflex.floating.body import Body, record
from rotaflex.floating.model import Initial, Load, Prescribed, Settings, load_from


@dataclass(frozen=True)
class State:
    """What a controller sees at a sampling instant (SI; velocities in body axes)."""

    time: float
    position: np.ndarray
    quaternion: np.ndarray
    velocity: np.ndarray
    angular_velocity: np.ndarray
    q: np.ndarray
    p: np.ndarray
    euler_123: np.ndarray


def run(
    config: dict | str | Path | None = None,
    *,
    body: Body | None = None,
    loads=(),
    initial: Initial | None = None,
    solver: Settings | None = None,
    outputs: dict | None = None,
    prescribed: Prescribed | None = None,
    controller: Callable | None = None,
    control_dt: float | None = None,
):
    """Simulate a floating body in one call; returns a ``FloatingResult``.

    Parameters
    ----------
    config : dict or path, optional
        A case (TOML file path or its parsed table, ``domain`` key optional); then every other
        argument must be left out.
    body : Body
        Library path: the body (``uniform_beam``, ``frame_body``, ``point_body``, ``load_modes``).
    loads : sequence of Load or mapping
        Fixed load profiles: ``Load`` objects or tables with its keys (as ``[[loads]]`` in a case
        file); each is checked like a case file's, errors naming ``loads[i].<field>``.
    initial, solver, prescribed
        As in :func:`rotaflex.floating.solve.simulate`; ``solver.method = "both"`` runs both.
    outputs : dict of name -> (3,) point [m]
        Output points (undeformed, body frame).
    controller : callable, optional
        ``controller(t, state) -> [(kind, vector[, point[, frame]]), ...]``: loads from the state
        (:class:`State`) sampled every ``control_dt`` seconds and held constant until the next
        sample (zero-order hold, like a digital controller). Full nonlinear method only.
    control_dt : float
        Sampling period [s] of ``controller`` (default ``solver.dt_out``); must be a multiple of
        ``solver.dt_out``.

    Returns
    -------
    FloatingResult
        ``dataset.attrs["config"]`` holds the resolved inputs (JSON; the body as its name, size,
        frequencies and the parameters it was made from) and ``["wall_time"]`` the wall time [s].
    """
    from rotaflex.floating.result import build_result
    from rotaflex.floating.solve import simulate

    t0 = time.perf_counter()
    if config is not None:
        if body is not None or loads or controller is not None:
            raise InputError("run", "config and body/loads/controller", "one or the other")
        from rotaflex.core.config import load_toml
        from rotaflex.floating.case import resolve_paths, run_case

        cfg = load_toml(config) if isinstance(config, (str, Path)) else dict(config)
        cfg.pop("domain", None)
        if isinstance(config, (str, Path)):  # file paths inside a case file: from its directory
            cfg = resolve_paths(cfg, Path(config).parent)
        return run_case(cfg)
    if body is None:
        raise InputError("run.body", None, "a Body (or a config)")
    loads = tuple(load_from(ld, f"loads[{i}]") for i, ld in enumerate(loads))
    initial = initial or Initial()
    solver = solver or Settings()
    outputs = dict(outputs or {})
    methods = ["full", "perturbation"] if solver.method == "both" else [solver.method]
    if prescribed is not None:
        methods = ["full"]
    resolved = {
        "body": record(body),
        "loads": [asdict(ld) for ld in loads],
        "initial": asdict(initial),
        "solver": asdict(solver),
        "outputs": {k: list(v) for k, v in outputs.items()},
        "prescribed": None if prescribed is None else asdict(prescribed),
    }
    if controller is None:
        sols = [simulate(body, loads, initial, solver, m, prescribed) for m in methods]
    else:
        if methods != ["full"]:
            raise InputError(
                "solver.method",
                solver.method,
                "'full' with a controller (the perturbation split needs loads known in advance)",
            )
        dt = solver.dt_out if control_dt is None else float(control_dt)
        k = dt / solver.dt_out
        if not (dt > 0 and abs(k - round(k)) < 1e-9 and round(k) >= 1):
            raise InputError("control_dt", control_dt, f"a multiple of solver.dt_out = {solver.dt_out:g} s")
        sols = [_closed_loop(body, loads, initial, solver, controller, dt)]
        resolved["controller"] = getattr(controller, "__name__", repr(controller))
        resolved["control_dt"] = dt
    return build_result(
        body,
        sols,
        outputs,
        json.loads(json.dumps(resolved, default=str)),
        time.perf_counter() - t0,
    )


def _controller_loads(out, t) -> list[Load]:
    """The controller's ``[(kind, vector[, point[, frame]]), ...]`` as checked constant loads."""
    loads = []
    for i, item in enumerate(out or ()):
        where = f"controller(t={t:g})[{i}]"
        if isinstance(item, (str, bytes)) or not 2 <= len(item) <= 4:
            raise InputError(where, item, "a tuple (kind, vector[, point[, frame]])")
        keys = ("kind", "vector", "point", "frame")
        loads.append(load_from(dict(zip(keys, item, strict=False)), where))
    return loads


def _state(t: float, ini: Initial, n_modes: int, euler_123) -> State:
    """What the controller sees at time ``t`` [s] when the body is in state ``ini``."""
    e = np.asarray(ini.quaternion, float)

    def modal(vals):
        return np.asarray(vals, float) if len(vals) else np.zeros(n_modes)

    return State(
        t,
        np.asarray(ini.position, float),
        e / np.linalg.norm(e),
        np.asarray(ini.velocity, float),
        np.asarray(ini.angular_velocity, float),
        modal(ini.modal_displacement),
        modal(ini.modal_velocity),
        np.asarray(euler_123, float),
    )


def _closed_loop(body, loads, initial, solver, controller, dt):
    """Zero-order-hold loop: integrate ``dt`` at a time with the controller's loads held."""
    from rotaflex.floating.solve import Solution, simulate
    from rotaflex.rotation.quaternion import euler_from_quaternion

    t, ini, parts = 0.0, initial, []
    t_end = solver.t_end
    while t < t_end - 1e-12 * t_end:
        t1 = min(t + dt, t_end)
        last = parts[-1] if parts else None
        # Euler angles: at t = 0 those of the initial attitude (the integrator's branch: nearest
        # zero); later the previous period's, unwrapped step by step
        eul = euler_from_quaternion("123", np.asarray(ini.quaternion, float)) if last is None else last.euler_123[-1]
        state = _state(t, ini, body.n_modes, eul)
        held = _controller_loads(controller(t, state), t)
        seg = simulate(body, loads + tuple(held), ini, replace(solver, t_end=t1), "full", t_start=t)
        if last is not None:  # same instant: the angles differ by whole turns only
            shift = np.round((last.euler_123[-1] - seg.euler_123[0]) / (2 * np.pi)) * 2 * np.pi
            seg.euler_123 = seg.euler_123 + shift
        parts.append(seg)
        if seg.status != "success":
            break
        ini = replace(
            ini,
            position=tuple(seg.position[-1]),
            quaternion=tuple(seg.quaternion[-1]),
            velocity=tuple(seg.velocity[-1]),
            angular_velocity=tuple(seg.angular_velocity[-1]),
            modal_displacement=tuple(seg.q[-1]),
            modal_velocity=tuple(seg.p[-1]),
        )
        t = t1

    def cat(name):
        arrs = [getattr(s, name) for s in parts]
        return np.concatenate([arrs[0]] + [a[1:] for a in arrs[1:]])

    sol = Solution(
        "full",
        cat("time"),
        cat("position"),
        cat("quaternion"),
        cat("velocity"),
        cat("angular_velocity"),
        cat("q"),
        cat("p"),
    )
    sol.euler_123 = cat("euler_123")
    sol.min_stiffness = cat("min_stiffness")
    sol.geometric = parts[0].geometric
    sol.kinematics = parts[0].kinematics
    sol.nstep = sum(s.nstep for s in parts)
    sol.nfev = sum(s.nfev for s in parts)
    sol.wall_time = sum(s.wall_time for s in parts)
    bad = [s for s in parts if s.status != "success"]
    sol.status = bad[0].status if bad else "success"
    sol.message = bad[0].message if bad else f"closed loop, {len(parts)} control periods"
    return sol
