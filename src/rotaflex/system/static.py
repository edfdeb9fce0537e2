"""``rotaflex system static``: the static state of a machine under gravity, point loads and load torque.

One solve on the machine's solved coordinates (:mod:`.assembly`: shafts, bearings at each
rotor's speed, flexible couplings, rigid couplings as constraints, the mean mesh stiffness)

    K p = T^T (f_gravity + f_points + f_torque + sum_m g_m k_m e_m),    q = T p,

with every rotor's gravity and point loads from rotor/fe's
:func:`~rotaflex.rotor.fe.static.applied_loads`, the transmitted torque of
:func:`~.assembly.load_vector` and the mean unloaded TE ``e_m`` as
:func:`~.helical.static_state` takes them; the mesh forces are ``F_m = k_m (g_m^T q - e_m)``.
The drive node's twist is held (the drive's reaction torque; under a torque drive the drive
torque balances the load, so holding it only removes the rigid twist).

Each rotor's outputs are then rotor/fe's :func:`~rotaflex.rotor.fe.static.static_state` of
its own displacements: bearing reactions, shear, moment and stress at the cuts, with the
forces and moments of the other bodies (gear meshes, couplings, rigid or flexible) as point
forces and couples at the nodes that carry them. Those are what the rotor's own equations leave
unbalanced there, ``K_r q_r - f_r`` (K_r: the rotor's shaft and bearings, f_r: its applied
loads), so the rotor verb's equilibrium check (applied + reactions + external = 0) is a check
of the machine solve.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from rotaflex.core.errors import InputError
from rotaflex.rotor.fe.bearings.static_load import iterate_journal_loads, with_loads
from rotaflex.rotor.fe.layout import bearing_path
from rotaflex.rotor.fe.static import applied_loads, default_speed, gravity_vector, static_state
from rotaflex.system.model import Gearbox

__all__ = ["MachineStatic", "machine_static", "static_result"]


@dataclass(frozen=True)
class MachineStatic:
    """Static state of a machine.

    Attributes
    ----------
    speed : float
        Drive speed [rad/s] of the bearing coefficients (each rotor at its ratio).
    q : ndarray (n_dof,)
        Full DOF vector [m, rad].
    mesh_force : ndarray (n_mesh,)
        Static transverse mesh forces [N] (along the line of action, + pushing the gears apart).
    rotors : list of StaticData
        Per rotor, rotor/fe's static answer; ``external`` holds the mesh and coupling forces
        and moments on it.
    box : Gearbox
        The machine solved: the input one, or with the converged journal loads in place of
        ``load = "static"``.
    iterations : int
        Static solves of the film-load iteration (0: no ``load = "static"`` bearing).
    """

    speed: float
    q: np.ndarray
    mesh_force: np.ndarray
    rotors: list
    box: Gearbox
    iterations: int = 0


def _interaction_nodes(box: Gearbox) -> list[set[int]]:
    """Per rotor, the nodes on which another body acts: gear nodes and coupling hubs."""
    out = [set() for _ in box.rotors]
    for m in box.meshes:
        for r, node in (m.driver, m.driven):
            out[r].add(node)
    for cp in box.couplings:
        for r, node in (cp.a, cp.b):
            out[r].add(node)
    return out


def default_drive_speed(box: Gearbox) -> float:
    """Drive speed [rad/s] of a static analysis by default: the lowest at which every rotor's
    bearing tables are covered (rotor/fe's :func:`~rotaflex.rotor.fe.static.default_speed` of
    each rotor over its ratio; 0 with constant coefficients)."""
    return max(default_speed(pr.rotor) / pr.ratio for pr in box.rotors)


def machine_static(
    box: Gearbox,
    *,
    gravity: float,
    direction=(0.0, -1.0),
    loads=(),
    speed: float,
    tol: float = 1e-10,
    max_iter: int = 50,
) -> MachineStatic:
    """Static state of ``box``.

    Fluid-film bearings with ``load = "static"`` are iterated as the rotor verb iterates them
    (:mod:`rotaflex.rotor.fe.bearings.static_load`): journal loads -> coefficients at the
    rotor's speed -> the machine's static state -> reactions, from each rotor's own resolution
    (:attr:`~rotaflex.rotor.fe.model.Rotor.resolved`), until no journal load changes by more
    than ``tol`` times the largest load on its rotor (weights, point loads, mesh and coupling
    forces); the answer is the state with each film's table over its own speed range at the
    converged loads (interpolated at the rotor's speed, as in the rotor verb).

    Parameters
    ----------
    box : Gearbox
    gravity : float
        Acceleration of gravity [m/s^2] (0: loads and torque only).
    direction : (float, float)
        Direction of gravity in the machine's x-y plane (default -y).
    loads : sequence of (rotor index, node, F_x [N], F_y [N])
        Point forces.
    speed : float
        Drive speed [rad/s] of the bearing coefficients.
    tol, max_iter : float, int
        Convergence of the film loads: relative change, solves allowed.

    Returns
    -------
    MachineStatic

    Examples
    --------
    >>> # box = Gearbox.from_toml("examples/system/motor_coupling_pump.toml")
    >>> # s = machine_static(box, gravity=9.80665, speed=155.0)
    >>> # s.rotors[1].reactions  # force of each pump bearing on the pump [N]
    """
    g = gravity_vector(gravity, direction)
    film = {r: pr.rotor.static_load_bearings for r, pr in enumerate(box.rotors) if pr.rotor.static_load_bearings}
    if not film:
        return _solve(box, g, loads, speed)
    if not speed > 0:
        raise InputError(
            "static.speed_rpm", 0.0, "a drive speed > 0 [rpm]: a film bearing (load = static) carries no load at rest"
        )
    start = {r: box.rotors[r].rotor.resolved.bearing for r in film}  # each rotor's own resolution
    current = {
        r: np.array([start[r][i].fluid_film.load if i in idx else (0.0, 0.0) for i in range(len(start[r]))])
        for r, idx in film.items()
    }

    def trial(cur, cut=True):
        """The box with the journal loads ``cur``; ``cut``: each film's table at the rotor's speed only."""
        rotors = list(box.rotors)
        for r, idx in film.items():
            pr = rotors[r]
            at = abs(pr.ratio * speed) if cut else None
            rotors[r] = dataclasses.replace(pr, rotor=with_loads(pr.rotor, cur[r], idx, at))
        return dataclasses.replace(box, rotors=tuple(rotors))

    def solve(cur):
        s = _solve(trial(cur), g, loads, speed)
        st = {r: s.rotors[r] for r in film}
        return (
            {r: -x.reactions for r, x in st.items()},
            {r: max(float(np.hypot(*x.load_total)), float(np.abs(x.external[:, :2]).sum())) for r, x in st.items()},
        )

    paths = {r: _film_path(box, r) for r in film}
    current, it, _ = iterate_journal_loads(solve, current, film, paths, speed, tol, max_iter)
    # as the rotor verb: the films' full tables at the converged loads
    return dataclasses.replace(_solve(trial(current, cut=False), g, loads, speed), iterations=it)


def _film_path(box: Gearbox, r: int):
    """Config key of rotor r's bearing i's film load (for the errors)."""
    return lambda i: f"rotor[{r}].{bearing_path(i, box.rotors[r].rotor.bearing[i])}.fluid_film.load"


def _solve(box: Gearbox, g: np.ndarray, loads, speed: float) -> MachineStatic:
    """One static solve of ``box`` with its bearings as they are (gravity ``g`` [m/s^2])."""
    from rotaflex.system.assembly import load_vector, matrices, system_matrices

    # the drive node's twist held: a constant-speed drive's reaction; a torque drive's balanced torque
    held = dataclasses.replace(box, drive_kind="constant_speed")
    mats = matrices(held)
    K = system_matrices(held, speed, mats)[2]
    f = load_vector(box)
    own = []
    for r, pr in enumerate(box.rotors):
        off, nl, _ = box.layout[r]
        fr, point = applied_loads(pr.rotor, g, [(n, fx, fy) for k, n, fx, fy in loads if k == r])
        f[off : off + nl] += fr
        own.append((fr, point))
    e = np.array([m.gear.table.unloaded_te.mean() for m in box.meshes])
    if len(box.meshes):
        f = f + mats.g.T @ (mats.k_mean * e)
    q = mats.expand(np.linalg.solve(K, mats.project(f)))
    mesh_force = mats.k_mean * (mats.g @ q - e) if len(box.meshes) else np.zeros(0)
    out = []
    for r, (pr, (fr, point), nodes) in enumerate(zip(box.rotors, own, _interaction_nodes(box), strict=True)):
        off, nl, _ = box.layout[r]
        w = abs(pr.ratio * speed)
        qr = q[off : off + nl]
        residual = (pr.rotor.KC(w)[0][0] @ qr - fr)[: pr.rotor.n_rotor_dof].reshape(-1, 4)
        external = np.zeros((pr.rotor.n_nodes, 4))
        for n in nodes:
            external[n] = residual[n]
        out.append(static_state(pr.rotor, qr, point, g, w, external=external))
    return MachineStatic(float(speed), q, mesh_force, out, box)


def _stack(parts: list, names: list[str]):
    """One dataset of the per-rotor datasets of rotor/fe's
    :func:`~rotaflex.rotor.fe.verbs.static_dataset`: nodes, cuts and bearings of all rotors one
    after the other along ``node``, ``cut`` and ``bearing``, each tagged with its rotor."""
    import xarray as xr

    data = {}
    for v in parts[0].data_vars:
        dims = parts[0][v].dims
        data[v] = (dims, np.concatenate([p[v].values for p in parts]), parts[0][v].attrs)
    coords = {"axis": ["x", "y"]}
    for dim in ("node", "cut", "bearing"):
        coords[f"{dim}_rotor"] = (
            dim,
            np.concatenate([[nm] * p.sizes[dim] for p, nm in zip(parts, names, strict=True)]),
        )
    coords["node_index"] = ("node", np.concatenate([np.arange(p.sizes["node"]) for p in parts]))
    return xr.Dataset(data, coords=coords)


def static_result(config: dict, box: Gearbox, spec, speed: float, t0: float):
    """Static state of ``box`` under ``spec`` ([static]) at drive ``speed`` [rad/s] as a
    :class:`~rotaflex.system.results.SystemStaticResult`: per rotor the rotor verb's dataset,
    summary entries (prefixed ``<rotor>_``) and equilibrium check; the mesh forces. ``config``
    and ``t0`` (``time.perf_counter`` at the start) go into the summary. The verb is
    :func:`rotaflex.system.case.run_static`, which reads the case and calls this."""
    from rotaflex.core.result import summary_attrs
    from rotaflex.core.units import rad_s_to_rpm
    from rotaflex.rotor.fe.verbs import check_static, static_dataset
    from rotaflex.system import helical
    from rotaflex.system.results import SystemStaticResult

    loads = []
    for i, ld in enumerate(spec.load):
        r = box.rotor_index(ld.rotor, f"static.load[{i}].rotor")
        loads.append((r, box.rotors[r].rotor.station(ld.node, ld.position, f"static.load[{i}]"), ld.fx, ld.fy))
    s = machine_static(box, gravity=spec.gravity, direction=spec.gravity_direction, loads=loads, speed=speed)
    names = [pr.name for pr in box.rotors]
    parts, extra, msgs = [], {"drive_speed_rpm": {"value": rad_s_to_rpm(speed), "unit": "rpm"}}, []
    for pr, st in zip(s.box.rotors, s.rotors, strict=True):
        ds_r, ex, msg = static_dataset(pr.rotor, st)
        ds_r["external_force"] = (("node", "axis"), st.external[:, :2], {"units": "N", "long_name": _EXT})
        ds_r["external_moment"] = (("node", "axis"), st.external[:, 2:], {"units": "N m", "long_name": _EXT})
        parts.append(ds_r)
        extra.update({f"{pr.name}_{k}": v for k, v in ex.items()})
        msgs.append(f"{pr.name}: {msg}")
    ds = _stack(parts, names)
    if len(box.meshes):
        ds["mesh_force"] = ("mesh", s.mesh_force, {"units": "N", "long_name": "static transverse mesh force"})
        for j, F in enumerate(s.mesh_force):
            extra[f"mesh{j}_force"] = {"value": float(F), "unit": "N", "long_name": "along the line of action"}
        msgs.append("mesh forces [N]: " + ", ".join(f"{F:.4g}" for F in s.mesh_force))
    if s.iterations:
        extra["film_load_iterations"] = {"value": s.iterations, "unit": "", "long_name": "static solves"}
    helical.dataset_static(box, ds, extra, speed)
    ds.attrs.update(summary_attrs(config, t0, extra, "; ".join(msgs)))
    res = SystemStaticResult(ds)
    for pr, st in zip(box.rotors, s.rotors, strict=True):
        if res.dataset.attrs["status"] == "success":
            check_static(res, st, pr.name)
    return res


_EXT = "force (moment) of gear meshes and couplings on the rotor"
