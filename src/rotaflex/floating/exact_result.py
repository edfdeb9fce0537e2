"""The ``FloatingResult`` of an exact-beam run: the modal body's variables where they apply.

Variables (``solution`` is ``exact`` or ``static``): the reference frame's ``position``,
``quaternion``, ``rotation_matrix``, ``euler_123``, ``velocity``, ``angular_velocity`` (the hub or
prescribed frame; for a free beam the centre-of-mass frame turned by the mass-weighted best fit
of the nodes to their reference positions), ``point_position`` and ``point_deflection`` of the
output points, ``energy`` (kinetic + strain), ``momentum``, ``angular_momentum``, and the exact
body's own: ``node_position``, ``node_angle``, ``node_deflection``, ``work_of_loads``,
``work_of_drive``, ``energy_balance`` and ``deflection_to_length``.
"""

from __future__ import annotations

import json

import numpy as np

from rotaflex.floating.exact_beam import ExactBeam


def frame_motion(beam: ExactBeam, Q: np.ndarray, V: np.ndarray):
    """Origin (T, 2), angle (T,), origin velocity (T, 2) and rate (T,) of the reference frame.

    A clamped body uses its frame DOFs; a free beam the centre of mass ``c`` and the angle
    ``atan2(sum m r0 x xi, sum m r0 . xi)`` (``r0``, ``xi``: reference and current node
    positions about their centres of mass; lumped masses = row sums of the consistent mass).
    """
    n = beam.n_nodes
    if len(beam.clamps):
        return Q[:, 3 * n : 3 * n + 2], Q[:, 3 * n + 2], V[:, 3 * n : 3 * n + 2], V[:, 3 * n + 2]
    m = beam.mass_matrix()[0 : 3 * n : 3].sum(axis=1)
    xy = np.stack([Q[:, 0 : 3 * n : 3], Q[:, 1 : 3 * n : 3]], axis=-1)
    vxy = np.stack([V[:, 0 : 3 * n : 3], V[:, 1 : 3 * n : 3]], axis=-1)
    c0 = m @ beam.nodes / m.sum()
    r0 = beam.nodes - c0
    c = np.einsum("k,tka->ta", m, xy) / m.sum()
    cv = np.einsum("k,tka->ta", m, vxy) / m.sum()
    xi = xy - c[:, None, :]
    s = np.einsum("k,tk->t", m, r0[:, 0] * xi[..., 1] - r0[:, 1] * xi[..., 0])
    co = np.einsum("k,tk->t", m, r0[:, 0] * xi[..., 0] + r0[:, 1] * xi[..., 1])
    # the fit gives the angle modulo 2 pi; the integrated section angles are continuous, so
    # take the branch nearest their mass-weighted mean (right however coarse the output times)
    th = np.einsum("k,tk->t", m, Q[:, 2 : 3 * n : 3]) / m.sum()
    phi = np.arctan2(s, co)
    phi = phi + 2 * np.pi * np.round((th - phi) / (2 * np.pi))
    # rigid-fit spin: sum m xi x v / sum m |xi|^2
    w = np.einsum("k,tk->t", m, xi[..., 0] * (vxy - cv[:, None])[..., 1] - xi[..., 1] * (vxy - cv[:, None])[..., 0])
    w = w / np.einsum("k,tk->t", m, (xi**2).sum(axis=-1))
    cph, sph = np.cos(phi), np.sin(phi)
    origin = c - np.stack([cph * c0[0] - sph * c0[1], sph * c0[0] + cph * c0[1]], axis=-1)
    return origin, phi, cv, w


def _body_axes(origin, phi, xy):
    """Inertial points ``xy`` (T, k, 2) in frame axes (T, k, 2)."""
    d = xy - origin[:, None, :]
    c, s = np.cos(phi)[:, None], np.sin(phi)[:, None]
    return np.stack([c * d[..., 0] + s * d[..., 1], -s * d[..., 0] + c * d[..., 1]], axis=-1)


def _pad3(a):
    return np.concatenate([a, np.zeros(a.shape[:-1] + (1,))], axis=-1)


def datasets(beam: ExactBeam, sol, points: dict):
    """``{name: (dims, values, units, long_name)}`` of one solution (without the solution dim)."""
    n = beam.n_nodes
    Q, V = sol.q, sol.v
    origin, phi, ov, w = frame_motion(beam, Q, V)
    xy = np.stack([Q[:, 0 : 3 * n : 3], Q[:, 1 : 3 * n : 3]], axis=-1)
    node_def = _body_axes(origin, phi, xy) - beam.nodes[None]
    names = list(points)
    pxy = np.zeros((len(Q), len(names), 2))
    pref = np.zeros((len(names), 2))
    for j, name in enumerate(names):
        a, b, xi = beam.locate(points[name], f"outputs.{name}")
        pref[j] = np.asarray(points[name], dtype=float)[:2]
        if a < 0:  # on the rigid hub
            c, s = np.cos(phi), np.sin(phi)
            pxy[:, j] = origin + np.stack([c * pref[j, 0] - s * pref[j, 1], s * pref[j, 0] + c * pref[j, 1]], axis=-1)
        else:
            pxy[:, j] = (1 - xi) * xy[:, a] + xi * xy[:, b]
    pdef = _body_axes(origin, phi, pxy) - pref[None]
    M = beam.mass_matrix()
    P = np.einsum("ij,tj->ti", M, V)
    mom = np.stack([P[:, 0::3].sum(axis=1), P[:, 1::3].sum(axis=1)], axis=-1)
    allxy = np.stack([Q[:, 0::3], Q[:, 1::3]], axis=-1)  # nodes and the frame block
    hz = (allxy[..., 0] * P[:, 1::3] - allxy[..., 1] * P[:, 0::3]).sum(axis=1) + P[:, 2::3].sum(axis=1)
    c, s = np.cos(phi), np.sin(phi)
    vel_body = np.stack([c * ov[:, 0] + s * ov[:, 1], -s * ov[:, 0] + c * ov[:, 1]], axis=-1)
    R = np.zeros((len(phi), 3, 3))
    R[:, 0, 0], R[:, 0, 1], R[:, 1, 0], R[:, 1, 1], R[:, 2, 2] = c, -s, s, c, 1.0
    zeros = np.zeros_like(phi)
    e = sol.energy
    tax = ("time", "axis")
    return {
        "position": (tax, _pad3(origin), "m", "origin of the reference frame (inertial)"),
        "quaternion": (
            ("time", "quat"),
            np.stack([np.cos(phi / 2), zeros, zeros, np.sin(phi / 2)], -1),
            "1",
            "attitude",
        ),
        "rotation_matrix": (("time", "row", "col"), R, "1", "attitude matrix A (body to inertial)"),
        "euler_123": (tax, np.stack([zeros, zeros, phi], -1), "rad", "Euler 1-2-3 angles (planar: about z)"),
        "velocity": (tax, _pad3(vel_body), "m/s", "V_o (body axes)"),
        "angular_velocity": (tax, np.stack([zeros, zeros, w], -1), "rad/s", "w (body axes)"),
        "point_position": (("time", "point", "axis"), _pad3(pxy), "m", "inertial position of output points"),
        "point_deflection": (
            ("time", "point", "axis"),
            _pad3(pdef),
            "m",
            "elastic deflection of output points (body axes)",
        ),
        "momentum": (tax, _pad3(mom), "kg m/s", "linear momentum (inertial)"),
        "angular_momentum": (
            tax,
            np.stack([zeros, zeros, hz], -1),
            "kg m^2/s",
            "angular momentum about the inertial origin",
        ),
        "energy": (("time",), e[:, 0] + e[:, 1], "J", "kinetic + strain energy"),
        "work_of_loads": (("time",), e[:, 2], "J", "work of the applied loads since the start"),
        "work_of_drive": (("time",), e[:, 3], "J", "work of the prescribed motion (or the ground) since the start"),
        "energy_balance": (("time",), sol.balance, "J", "energy - energy(0) - work_of_loads - work_of_drive"),
        "node_position": (("time", "node", "axis"), _pad3(xy), "m", "node positions (inertial)"),
        "node_angle": (("time", "node"), Q[:, 2 : 3 * n : 3], "rad", "section angles (inertial)"),
        "node_deflection": (("time", "node", "axis"), _pad3(node_def), "m", "node deflection (body axes)"),
        "deflection_to_length": (
            ("time",),
            np.linalg.norm(node_def, axis=-1).max(axis=1) / beam.length,
            "1",
            "largest node deflection / longest beam length",
        ),
    }


def datasets3d(beam, sol, points: dict):
    """:func:`datasets` of a 3-D exact beam (:class:`~rotaflex.floating.exact_beam3d.ExactBeam3D`)
    clamped to a frame at the origin (fixed or turning about it): node and point positions,
    deflections from the reference positions in frame axes, section quaternions
    (``node_quaternion`` instead of ``node_angle``), strain energy; a static solution has zero velocities."""
    from rotaflex.floating.exact_case3d import points as reference_points
    from rotaflex.rotation import euler_from_quaternion, quaternion_to_matrix

    n = beam.n_nodes
    T = len(sol.q)
    blocks = sol.q.reshape(T, -1, 7)
    xyz, quat = blocks[:, :n, :3], blocks[:, :n, 3:]
    frame_q = blocks[:, n, 3:]
    refs = reference_points(beam, points)
    names = list(refs)
    pxyz = np.zeros((T, len(names), 3))
    pref = np.zeros((len(names), 3))
    for j, name in enumerate(names):
        a, b, xi = beam.locate(refs[name], f"outputs.{name}")
        pref[j] = refs[name]
        pxyz[:, j] = (1 - xi) * xyz[:, a] + xi * xyz[:, b]
    # deflections in the reference frame's axes (it turns about its origin when prescribed)
    RF = quaternion_to_matrix(frame_q)
    node_def = np.einsum("tji,tkj->tki", RF, xyz) - beam.nodes[None]
    pdef = np.einsum("tji,tkj->tki", RF, pxyz) - pref[None]
    zeros3 = np.zeros((T, 3))
    # the frame's angular velocity (material = body axes); a static solution has none
    dyn = sol.v.shape[-1] == beam.n_dof
    w_frame = sol.v.reshape(T, -1, 6)[:, n, 3:] if dyn else zeros3
    e = sol.energy
    tax = ("time", "axis")
    out = {
        "position": (tax, blocks[:, n, :3], "m", "origin of the reference frame (inertial)"),
        "quaternion": (("time", "quat"), frame_q, "1", "attitude of the reference frame"),
        "rotation_matrix": (("time", "row", "col"), quaternion_to_matrix(frame_q), "1", "attitude matrix A"),
        "euler_123": (tax, euler_from_quaternion("123", frame_q), "rad", "Euler 1-2-3 angles of the frame"),
        "velocity": (tax, zeros3, "m/s", "V_o (body axes; the origin is held)"),
        "angular_velocity": (tax, w_frame, "rad/s", "w (body axes)"),
        "point_position": (("time", "point", "axis"), pxyz, "m", "inertial position of output points"),
        "point_deflection": (("time", "point", "axis"), pdef, "m", "deflection of output points (frame axes)"),
        "energy": (("time",), e[:, 0] + e[:, 1], "J", "kinetic + strain energy"),
        "work_of_loads": (("time",), e[:, 2], "J", "work of the applied loads since the start"),
        "work_of_drive": (("time",), e[:, 3], "J", "work of the clamps (ground or prescribed frame) since the start"),
        "energy_balance": (("time",), sol.balance, "J", "energy - energy(0) - work_of_loads - work_of_drive"),
        "node_position": (("time", "node", "axis"), xyz, "m", "node positions (inertial)"),
        "node_quaternion": (("time", "node", "quat"), quat, "1", "section rotations (inertial, scalar first)"),
        "node_deflection": (("time", "node", "axis"), node_def, "m", "node deflection (frame axes)"),
        "deflection_to_length": (
            ("time",),
            np.linalg.norm(node_def, axis=-1).max(axis=1) / beam.length,
            "1",
            "largest node deflection / longest beam length",
        ),
    }
    hub = getattr(sol, "hub", None)  # a free hub (rotaflex.floating.exact_solve3d.HubSolution)
    if hub is not None:
        out["hub_angle"] = (("time",), hub[:, 0], "rad", "hub angle about the slew axis (unwrapped)")
        out["hub_rate"] = (("time",), hub[:, 1], "rad/s", "hub angular rate about the slew axis")
        out["hub_torque"] = (("time",), hub[:, 2], "N m", "applied torque on the hub about the slew axis")
    return out


def build_exact_result(beam, solutions, points: dict, config: dict | None, wall_time: float, frame: str):
    """A :class:`~rotaflex.floating.result.FloatingResult` of exact-beam solutions (planar
    :class:`ExactBeam` or 3-D :class:`~rotaflex.floating.exact_beam3d.ExactBeam3D`)."""
    import xarray as xr

    from rotaflex.floating.result import FloatingResult

    three_d = not isinstance(beam, ExactBeam)
    parts = [(datasets3d if three_d else datasets)(beam, s, points) for s in solutions]
    data = {}
    for key, (dims, _, unit, ln) in parts[0].items():
        vals = np.stack([p[key][1] for p in parts])
        data[key] = (("solution", *dims), vals, {"units": unit, "long_name": ln})
    ds = xr.Dataset(
        data,
        coords={
            "solution": [s.method for s in solutions],
            "time": ("time", solutions[0].time, {"units": "s", "long_name": "time"}),
            "axis": ["x", "y", "z"],
            "quat": ["e0", "e1", "e2", "e3"],
            "row": ["x", "y", "z"],
            "col": ["x", "y", "z"],
            "point": list(points),
            "node": np.arange(beam.n_nodes),
        },
    )
    bad = [s for s in solutions if s.status != "success"]
    ds.attrs.update(
        {
            "status": bad[0].status if bad else "success",
            "message": " | ".join(f"{s.method}: {s.message}" for s in solutions),
            "wall_time": float(wall_time),
            "config": json.dumps(config or {}),
            "body": f"exact {'3-D' if three_d else 'planar'} beam ({len(beam.conn)} elements, "
            f"{len(beam.lengths)} beam(s))",
            "body_model": "exact",
            "body_length": beam.length,
            "floating_frame": {"fixed": "fixed", "prescribed": "prescribed", "free": "hub"}[frame]
            if len(beam.clamps)
            else "centre of mass, best-fit rotation",
            "geometric_stiffness": 0,
            "kinematics": "geometrically exact (3-D Simo-Reissner beam)"
            if three_d
            else "geometrically exact (planar Reissner beam)",
            "solver_wall_times": json.dumps({s.method: s.wall_time for s in solutions}),
            "connectivity": json.dumps(beam.conn.tolist()),
        }
    )
    return FloatingResult(ds)


def paraview_frames(result, every: int = 1):
    """The node polyline series (:class:`rotaflex.floating.paraview.Frames`) of an exact result."""
    from rotaflex.floating.paraview import Frames

    ds = result.dataset
    sel = ds.isel(solution=0)
    keep = np.arange(0, ds.sizes["time"], every)
    pos = sel["node_position"].values[keep]
    ok = np.isfinite(pos).all(axis=(1, 2))
    keep = keep[ok] if ok.all() else keep[: int(np.argmin(ok))]
    conn = np.array(json.loads(ds.attrs["connectivity"]), dtype=np.int64)
    return Frames(
        time=ds["time"].values[keep],
        positions=sel["node_position"].values[keep],
        displacements=sel["node_deflection"].values[keep],
        cells=[("line", conn)],
    )
