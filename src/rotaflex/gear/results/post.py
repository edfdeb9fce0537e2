"""Post-processing of dynamic gear runs: transmission error, fillet stress, static references.

Definitions
-----------
* Dynamic transmission error (DTE) along the line of action [m]::

      DTE(t) = r_bA theta_A(t) - r_bB theta_B(t)

  with ``theta_g`` the rotation of disk g in its running direction since t = 0 (A counter-
  clockwise, B clockwise). At t = 0 the unloaded teeth touch, so DTE is measured relative to the
  rigid kinematics of that initial position; positive = gear B lags behind A. It contains the
  tooth and contact deflections, the kinematic error of the discretised (quadratic FE edge +
  spline) profiles and, when the teeth separate, the free drift of the disks.
* Fillet (tooth-root) stress [Pa]: surface tangential stress at the fillet point whose tangent
  makes 30 deg with the tooth centreline (ISO 6336-3 critical section), from the FE field of the
  co-rotational elastic displacements ``w = R(theta)^T (x - c) - X`` (eq. 4). At the free
  surface the tangential stress is the non-zero principal stress, so it is also the maximum
  (tension) / minimum (compression) principal stress there. ``side = "loaded"`` is the fillet
  under the working flank (tension), ``"opposite"`` the other one (compression).

Everything is vectorised over the recorded time steps (one einsum per quantity).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = [
    "RootStressProbe",
    "root_stress_probe",
    "root_stress_history",
    "transmission_error",
    "kinematic_transmission_error",
    "static_point_load_te",
    "static_root_stress",
]

#: largest rotation of gear A between contact searches of :func:`kinematic_transmission_error` [rad]
MARCH_STEP = 0.004363323129985824  # 0.25 deg


@dataclass(frozen=True)
class RootStressProbe:
    """Root-stress operators restricted to the nodes they need.

    Attributes
    ----------
    nodes : ndarray of int (k,)
        Global node ids (both gears) whose positions must be recorded.
    gear : ndarray of int (k,)
        Gear of each node.
    xloc : ndarray (k, 2)
        Reference positions of the nodes in their tooth frames [m].
    operator : ndarray (2 gears, 2 sides, 2 k)
        Stress [Pa] per local displacement of the k nodes (rows of the other gear are zero);
        sides ordered (loaded, opposite).
    angle : float
        Tangent angle of the fillet point [rad] (30 deg: ISO 6336-3).
    """

    nodes: np.ndarray
    gear: np.ndarray
    xloc: np.ndarray
    operator: np.ndarray
    angle: float


def root_stress_probe(model, youngs_modulus, poisson_ratio, angle: float | None = None) -> RootStressProbe:
    """Build the fillet-stress operators of both teeth of a :class:`GearPairModel`
    (``youngs_modulus`` [Pa] and ``poisson_ratio``: one value or one per gear).

    The fillet under the model's working flank (``model.sig`` > 0: left) is the loaded
    (tension) side. ``angle``: tangent angle of the fillet point [rad] (default 30 deg).
    """
    from rotaflex.gear.static.tooth_analysis import ROOT_STRESS_ANGLE, root_stress_operator

    angle = ROOT_STRESS_ANGLE if angle is None else angle

    nodes, gear, ops = [], [], []
    off = 0
    for g, mesh in enumerate(model.meshes):
        order = (0, 1) if model.sig[g] > 0 else (1, 0)  # operator rows are (left, right)
        e_g, nu_g = (float(np.broadcast_to(v, (2,))[g]) for v in (youngs_modulus, poisson_ratio))
        s = root_stress_operator(mesh, e_g, nu_g, angle)[list(order)]
        cols = np.nonzero(np.any(s != 0.0, axis=0))[0]
        nd = np.unique(cols // 2)
        nodes.append(nd + off)
        gear.append(np.full(nd.size, g))
        sub = np.stack([s[:, 2 * nd], s[:, 2 * nd + 1]], axis=2).reshape(2, -1)
        ops.append(sub)
        off += mesh.n_nodes
    k = sum(n.size for n in nodes)
    op = np.zeros((2, 2, 2 * k))
    start = 0
    for g in range(2):
        n2 = 2 * nodes[g].size
        op[g, :, start : start + n2] = ops[g]
        start += n2
    nodes_all = np.concatenate(nodes).astype(np.int64)
    return RootStressProbe(
        nodes=nodes_all,
        gear=np.concatenate(gear).astype(np.int64),
        xloc=model.xloc[nodes_all].copy(),
        operator=op,
        angle=float(angle),
    )


def root_stress_history(model, probe: RootStressProbe, positions: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """Fillet stress histories [Pa], shape (nt, 2 gears, 2 sides (loaded, opposite)).

    Parameters
    ----------
    positions : ndarray (nt, k, 2)
        Recorded global positions of ``probe.nodes`` [m].
    phi : ndarray (nt, 2)
        Disk angles of the kernel (counter-clockwise positive, 0 at t = 0) [rad].
    """
    ang = model.theta0[None, :] + np.asarray(phi)  # (nt, 2)
    a = ang[:, probe.gear]  # (nt, k)
    c, s = np.cos(a), np.sin(a)
    d = positions - model.centres[probe.gear][None, :, :]
    w = np.empty_like(positions)
    w[..., 0] = c * d[..., 0] + s * d[..., 1] - probe.xloc[None, :, 0]
    w[..., 1] = -s * d[..., 0] + c * d[..., 1] - probe.xloc[None, :, 1]
    return np.einsum("gsj,tj->tgs", probe.operator, w.reshape(w.shape[0], -1))


def transmission_error(theta_a, theta_b, rb_a: float, rb_b: float) -> np.ndarray:
    """DTE ``r_bA theta_A - r_bB theta_B`` [m] (rotations in running directions, see module)."""
    return rb_a * np.asarray(theta_a) - rb_b * np.asarray(theta_b)


def kinematic_transmission_error(model, theta_a) -> np.ndarray:
    """Unloaded TE [m] of the discretised rigid teeth at rotations ``theta_a`` of gear A [rad].

    For each angle, gear B is turned (rigidly) until its flank spline touches A's; returns
    ``r_bA theta_A - r_bB theta_B`` at touching. Zero for exact involutes; for the FE-edge +
    spline profiles it is the profile discretisation error along the line of action.
    """
    from rotaflex.gear.models.fe_pair import _flank_points
    from rotaflex.gear.pair.contact_geometry import search

    rb = [g.base_radius for g in model.geometry]
    x0 = model.reference_positions().reshape(-1, 2)
    targets = np.atleast_1d(np.asarray(theta_a, dtype=float))
    out = np.zeros(targets.size)
    # march from the start of contact in steps <= MARCH_STEP so the search stays on its branch
    order = np.argsort(targets)
    tb = 0.0
    ta_prev = 0.0
    start = (0.3, 0.99)

    def touch(ta, tb, start):
        for _ in range(30):
            x = x0.copy()
            for g, ang in ((0, ta), (1, -tb)):
                sel = model.gid == g
                c, s = math.cos(ang), math.sin(ang)
                d = x0[sel] - model.centres[g]
                x[sel] = model.centres[g] + np.column_stack([c * d[:, 0] - s * d[:, 1], s * d[:, 0] + c * d[:, 1]])
            pts = _flank_points(model, x.ravel())
            pair = search(pts[0], pts[1], model.sig[0], model.sig[1], start=start)
            start = (pair.a, pair.b)
            if abs(pair.gap) < 1e-15:
                break
            tb -= pair.gap / rb[1]  # B turning on (clockwise) closes an open gap
        return tb, start

    for i in order:
        ta_goal = targets[i]
        n_sub = max(1, int(math.ceil(abs(ta_goal - ta_prev) / MARCH_STEP)))
        for ta in np.linspace(ta_prev, ta_goal, n_sub + 1)[1:]:
            tb += (ta - ta_prev) * rb[0] / rb[1]
            tb, start = touch(ta, tb, start)
            ta_prev = ta
        out[i] = rb[0] * ta_goal - rb[1] * tb
    return out


def _edge_load(mesh, flank_nodes_local, nedge, s, force_vec):
    from rotaflex.gear.kernels.contact import flank_weights

    nodes = np.empty(3, np.int64)
    w = np.empty(3)
    flank_weights(np.asarray(flank_nodes_local, np.int64), int(nedge), float(s), nodes, w)
    f = np.zeros(2 * mesh.n_nodes)
    f[2 * nodes] += w * force_vec[0]
    f[2 * nodes + 1] += w * force_vec[1]
    return f, nodes, w


def _local_flank(model, g):
    off = 0 if g == 0 else model.meshes[0].n_nodes
    n = 2 * int(model.nedge[g]) + 1
    return model.flank[g, :n] - off


def static_point_load_te(model, youngs_modulus, poisson_ratio, force, param_a, param_b, normal_local) -> float:
    """Static deflection TE [m] of the dynamic model's own contact load (point force on the
    quadratic flank edges, root nodes fixed) under a normal ``force`` [N].

    ``param_a``/``param_b``: flank spline parameters of the contact point on A and B;
    ``normal_local``: (2, 2) unit load directions into each tooth, in the tooth frames.
    Returns the approach of the two contact points along the normal (sum of both teeth).
    """
    from rotaflex.gear.static.tooth_analysis import solve_static

    te = 0.0
    for g, s in ((0, param_a), (1, param_b)):
        mesh = model.meshes[g]
        d = np.asarray(normal_local[g], dtype=float)
        f, nodes, w = _edge_load(mesh, _local_flank(model, g), model.nedge[g], s, force * d)
        u = solve_static(mesh, f, youngs_modulus, poisson_ratio)
        te += float(d @ (w @ u.reshape(-1, 2)[nodes]))
    return te


def static_root_stress(
    model, youngs_modulus, poisson_ratio, force, param, normal_local, gear: int = 0, angle: float | None = None
) -> np.ndarray:
    """Static fillet stress [Pa] (loaded, opposite) of tooth ``gear`` under the dynamic model's
    point load of ``force`` [N] along ``normal_local`` (tooth frame) at flank parameter ``param``
    (``angle``: the fillet point's tangent angle [rad], default 30 deg).
    """
    from rotaflex.gear.static.tooth_analysis import ROOT_STRESS_ANGLE, root_stress_operator, solve_static

    angle = ROOT_STRESS_ANGLE if angle is None else angle

    mesh = model.meshes[gear]
    f, _, _ = _edge_load(
        mesh, _local_flank(model, gear), model.nedge[gear], param, force * np.asarray(normal_local, dtype=float)
    )
    u = solve_static(mesh, f, youngs_modulus, poisson_ratio)
    s = root_stress_operator(mesh, youngs_modulus, poisson_ratio, angle) @ u
    return s if model.sig[gear] > 0 else s[::-1]
