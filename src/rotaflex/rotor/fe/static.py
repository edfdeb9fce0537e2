"""Static analysis: deflection under gravity and point loads, bearing reactions, shear and moment.

The static problem is ``K(Omega) q = f`` with the full stiffness (shaft plus bearings, the
bearings' coefficients at the spin speed ``speed``; cross-coupled terms included). Gravity
loads are the consistent nodal loads ``f = M r g``: ``r`` is the rigid translation of every
node in the gravity direction, and since the shaft element represents a rigid translation
exactly (``N_w r = 1``, ``N_r r = 0``) this is ``int rho A N_w^T g dz`` plus ``m g`` of every disk
and point mass. The interdependent Timoshenko element is exact for such loads at the nodes.

Bearing reactions are the forces the bearings exert on the rotor, ``F_b = -K_b (q_n - q_m)``
(``m``: the other node of a bearing between two nodes, else ground). Shear force and bending
moment along the shaft then follow by statics from everything to the left of a cut at z (the
reactions, point loads, disk and point-mass weights, and the distributed shaft weight
``rho A(z) g``, integrated by Simpson's rule per sub-interval, exact for a linear taper):

    V(z) = sum_{z_i < z} F_i + int_{z_0}^{z} w(s) ds,
    M(z) = sum_{z_i < z} F_i (z - z_i) + int_{z_0}^{z} w(s) (z - s) ds

per bending plane (``x``: x-z plane, ``y``: y-z plane). With y up and gravity -y, a simply
supported beam has V > 0 right of the left support and M > 0 (sagging) at midspan; at the
free right end both return to zero (a check of equilibrium, reported as ``end_moment``).

The analysis is three pieces, so that a machine (:mod:`rotaflex.system.static`) solves its own
``K q = f`` and takes each rotor's outputs from the same code: :func:`applied_loads` (the
consistent weight and point forces), the solve, and :func:`static_state` (reactions and
diagrams of a rotor at a displacement, with the forces and couples of other bodies on it).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rotaflex.core.errors import InputError
from rotaflex.rotor.fe.layout import NDOF_NODE

# The rotor arrives as an argument (a rotaflex.rotor.fe.model.Rotor) and is not imported: the
# model resolves ``load = "static"`` through bearings/static_load.py, which calls this module,
# so this module sits below the model.

#: standard gravity [m/s^2]
STANDARD_GRAVITY = 9.80665


@dataclass(frozen=True)
class StaticData:
    """Static solution.

    Attributes
    ----------
    q : ndarray (n_dof,)
        Displacements [m] and rotations [rad] at the nodes.
    reactions : ndarray (n_bearing, 2)
        Force of each bearing on the rotor, (F_x, F_y) [N] (in ``rotor.bearing`` order).
    z : ndarray (c,)
        Cut positions [m]; at a node with a point force the cut appears twice (left and right limit).
    shear, moment : ndarray (c, 2)
        Shear force [N] and bending moment [N m] at the cuts in the x-z and y-z planes.
    stress : ndarray (c,)
        Largest bending stress |M| (d_o / 2) / I at the cut [Pa].
    load_total : ndarray (2,)
        Sum of the applied loads (weights and point loads) (F_x, F_y) [N].
    external : ndarray (n_nodes, 4) or None
        Forces and moments (F_x, F_y [N], M_x, M_y [N m]) on the rotor from the other bodies of
        a machine (gear meshes, couplings); None for a rotor alone.
    """

    q: np.ndarray
    reactions: np.ndarray
    z: np.ndarray
    shear: np.ndarray
    moment: np.ndarray
    stress: np.ndarray
    load_total: np.ndarray
    external: np.ndarray | None = None

    @property
    def bearing_loads(self) -> np.ndarray:
        """Magnitude of each bearing's static load |F_b| [N], shape (n_bearing,)."""
        return np.hypot(self.reactions[:, 0], self.reactions[:, 1])

    def deflection(self, rotor) -> np.ndarray:
        """Node translations (n_nodes, 2): x and y [m]."""
        return self.q[: rotor.n_rotor_dof].reshape(rotor.n_nodes, NDOF_NODE)[:, :2]


def default_speed(rotor) -> float:
    """Spin speed [rad/s] a static analysis uses by default: 0, or the lowest speed every bearing table covers."""
    lows = [el.speeds[0] for _, _, el in rotor.bearings if el.speeds is not None]
    return float(max(lows)) if lows else 0.0


def gravity_vector(gravity: float, direction) -> np.ndarray:
    """Acceleration of gravity (g_x, g_y) [m/s^2] of a magnitude ``gravity`` [m/s^2] along
    ``direction`` in the x-y plane (normalised here); InputError naming ``static.gravity*``."""
    d = np.asarray(direction, float)
    if d.shape != (2,) or not np.all(np.isfinite(d)) or np.hypot(*d) == 0:
        raise InputError("static.gravity_direction", list(np.atleast_1d(direction)), "[g_x, g_y], not both 0")
    if not (np.isfinite(gravity) and gravity >= 0):
        raise InputError("static.gravity", gravity, "an acceleration >= 0 [m/s^2]")
    return gravity * d / np.hypot(*d)


def applied_loads(rotor, g: np.ndarray, loads=(), key: str = "static.load") -> tuple[np.ndarray, np.ndarray]:
    """Applied static loads of a rotor: the consistent load vector and the concentrated forces.

    Parameters
    ----------
    rotor : Rotor
    g : ndarray (2,)
        Acceleration of gravity (g_x, g_y) [m/s^2] (:func:`gravity_vector`).
    loads : sequence of (node, F_x [N], F_y [N])
        Point forces at nodes.
    key : str
        Config path of the loads for errors (``<key>[i].node``).

    Returns
    -------
    f : ndarray (n_dof,)
        ``M r g`` (shaft, disks, point masses; pedestals excluded) plus the point forces [N, N m].
    point : ndarray (n_nodes, 2)
        Concentrated forces at the nodes [N]: disk and point-mass weights and the point forces.
    """
    nn = rotor.n_nodes
    r = np.zeros(rotor.n_dof)
    nr = rotor.n_rotor_dof  # pedestals (DOFs after the rotor's) stand on the ground: their weight is not carried
    r[0:nr:NDOF_NODE], r[1:nr:NDOF_NODE] = g[0], g[1]
    f = rotor.M @ r
    point = np.zeros((nn, 2))  # concentrated forces at nodes: disk/point-mass weights and loads
    for node, el in rotor.disks:
        point[node] += el.mass * g
    for node, el in rotor.point_masses:
        point[node] += el.mass * g
    for i, (node, fx, fy) in enumerate(loads):
        if not 0 <= node < nn:
            raise InputError(f"{key}[{i}].node", node, f"an existing node 0..{nn - 1}")
        f[NDOF_NODE * node] += fx
        f[NDOF_NODE * node + 1] += fy
        point[node] += (fx, fy)
    return f, point


def static_state(
    rotor, q: np.ndarray, point: np.ndarray, g: np.ndarray, speed: float, n_sub: int = 8, external=None
) -> StaticData:
    """Reactions and shear, moment and stress diagrams of a rotor at a static displacement.

    Parameters
    ----------
    rotor : Rotor
    q : ndarray (n_dof,)
        The rotor's static displacements [m, rad] (its own DOFs, pedestals included).
    point : ndarray (n_nodes, 2)
        Concentrated applied forces [N] (:func:`applied_loads`); not modified.
    g : ndarray (2,)
        Acceleration of gravity [m/s^2] (the shaft's distributed weight).
    speed : float
        Spin speed [rad/s] of the bearing coefficients.
    n_sub : int
        Cuts per element.
    external : ndarray (n_nodes, 4), optional
        Forces and moments (F_x, F_y [N], M_x, M_y [N m]) on the rotor from other bodies of a
        machine (gear meshes, couplings); they enter the diagrams as point forces and couples.

    Returns
    -------
    StaticData
    """
    point = point.copy()
    reactions = np.zeros((len(rotor.bearings), 2))
    for b, (node, other, el) in enumerate(rotor.bearings):
        ia, ib = rotor.bearing_dofs[b]  # the bearing's two ends (ib: other node, pedestal or None)
        u = q[ia] - (q[ib] if ib is not None else 0.0)
        F = -el.coefficients(speed)[0][0] @ u
        reactions[b] = F
        point[node] += F
        if other is not None:
            point[other] -= F
    if external is None:
        z, V, Mb, stress = _diagrams(rotor, point, g, n_sub)
        total = point.sum(0) - reactions.sum(0) + _shaft_weight(rotor) * g
        return StaticData(q, reactions, z, V, Mb, stress, total)
    external = np.asarray(external, float)
    point += external[:, :2]
    z, V, Mb, stress = _diagrams(rotor, point, g, n_sub, external[:, 2:])
    total = point.sum(0) - reactions.sum(0) - external[:, :2].sum(0) + _shaft_weight(rotor) * g
    return StaticData(q, reactions, z, V, Mb, stress, total, external)


def static_analysis(
    rotor,
    *,
    gravity: float = STANDARD_GRAVITY,
    direction=(0.0, -1.0),
    loads=(),
    speed: float | None = None,
    n_sub: int = 8,
) -> StaticData:
    """Static deflection, bearing reactions, shear force and bending moment.

    The solve ``K q = f`` of :func:`applied_loads`; the outputs :func:`static_state` (which
    the machine's static analysis, :mod:`rotaflex.system.static`, calls per rotor).

    Parameters
    ----------
    rotor : Rotor
        A supported rotor (``free = false``).
    gravity : float
        Acceleration of gravity [m/s^2] (0: point loads only).
    direction : (float, float)
        Direction of gravity in the x-y plane (normalised here); default (0, -1): -y.
    loads : sequence of (node, F_x [N], F_y [N])
        Point forces at nodes.
    speed : float, optional
        Spin speed [rad/s] at which the bearing coefficients are taken (default
        :func:`default_speed`).
    n_sub : int
        Cuts per element for the shear and moment diagrams.

    Returns
    -------
    StaticData
        ``reactions`` (n_bearing, 2) [N] are the forces of the bearings on the rotor; their
        magnitudes (``bearing_loads``) are the static loads a fluid-film bearing carries.

    Examples
    --------
    >>> from rotaflex.rotor.fe.model import Rotor, Shaft, Bearing
    >>> r = Rotor(shaft=(Shaft(outer_diameter=0.05, length=1.0, elements=4),),
    ...           bearing=(Bearing(node=0, kxx=1e9, kyy=1e9), Bearing(node=4, kxx=1e9, kyy=1e9)))
    >>> s = static_analysis(r)
    >>> bool(abs(s.reactions[0, 1] - r.mass * 9.80665 / 2) < 1e-6)
    True
    """
    if rotor.free:
        raise InputError("free", True, "false for a static analysis (a free rotor has no supports to react loads)")
    g = gravity_vector(gravity, direction)
    speed = default_speed(rotor) if speed is None else float(speed)
    K = rotor.KC(speed)[0][0]
    f, point = applied_loads(rotor, g, loads)
    q = np.linalg.solve(K, f)
    return static_state(rotor, q, point, g, speed, n_sub)


def _shaft_weight(rotor) -> float:
    """Shaft mass alone [kg], coaxial layers included (exact for a linear taper: the area is quadratic in z)."""
    out = 0.0
    for e in (rotor.elements, rotor.layer_elements):
        a_l = np.pi / 4 * (e["do_l"] ** 2 - e["di_l"] ** 2)
        a_r = np.pi / 4 * (e["do_r"] ** 2 - e["di_r"] ** 2)
        dm, dim_ = (e["do_l"] + e["do_r"]) / 2, (e["di_l"] + e["di_r"]) / 2
        a_m = np.pi / 4 * (dm**2 - dim_**2)
        out += float(np.sum(e["massive"] * e["rho"] * e["L"] * (a_l + 4 * a_m + a_r) / 6))
    return out


def _mass_per_length(rotor, t: np.ndarray) -> np.ndarray:
    """Mass per length [kg/m] at the fractions ``t`` of each main element (ne, t.size): the main
    section's plus that of the coaxial layers on it (mass-only layers included)."""
    out = np.zeros((rotor.elements["L"].size, t.size))
    for e, rows in ((rotor.elements, None), (rotor.layer_elements, "index")):
        do = e["do_l"][:, None] + (e["do_r"] - e["do_l"])[:, None] * t
        di = e["di_l"][:, None] + (e["di_r"] - e["di_l"])[:, None] * t
        w = (e["massive"] * e["rho"])[:, None] * np.pi / 4 * (do**2 - di**2)
        np.add.at(out, np.arange(w.shape[0]) if rows is None else e[rows], w)
    return out


def _diagrams(rotor, point: np.ndarray, g: np.ndarray, n_sub: int, couple: np.ndarray | None = None):
    """Shear, moment and stress at cuts: n_sub + 1 per element, both limits at each node.

    ``couple`` (n_nodes, 2): point moments (M_x, M_y) [N m] at the nodes. The diagram's moment
    is minus the moment about the cut of everything left of it in the x-z plane (about +y) and
    plus it in the y-z plane (about +x), so a couple adds ``-M_y`` and ``+M_x`` right of its node.
    """
    e, zn = rotor.elements, rotor.nodes
    ne = e["L"].size
    t = np.linspace(0.0, 1.0, n_sub + 1)
    z = zn[:-1, None] + e["L"][:, None] * t[None, :]  # (ne, n_sub + 1)
    do = e["do_l"][:, None] + (e["do_r"] - e["do_l"])[:, None] * t
    di = e["di_l"][:, None] + (e["di_r"] - e["di_l"])[:, None] * t
    inertia = np.pi / 64 * (do**4 - di**4)  # the main section's: stress on it (layers share no moment here)
    w = _mass_per_length(rotor, t)  # at the cuts [kg/m]
    # Simpson per sub-interval: area is quadratic in z, so w and w s are integrated exactly
    zm = 0.5 * (z[:, 1:] + z[:, :-1])
    wm = _mass_per_length(rotor, 0.5 * (t[1:] + t[:-1]))
    h = np.diff(z, axis=1)
    m0 = h / 6 * (w[:, :-1] + 4 * wm + w[:, 1:])  # mass of each sub-interval
    m1 = h / 6 * (w[:, :-1] * z[:, :-1] + 4 * wm * zm + w[:, 1:] * z[:, 1:])  # first moment
    c0 = np.concatenate([[0.0], np.cumsum(m0)])
    c1 = np.concatenate([[0.0], np.cumsum(m1)])
    # cumulative distributed mass up to each cut, per element row
    idx = np.arange(ne)[:, None] * n_sub + np.arange(n_sub + 1)[None, :]
    cm0, cm1 = c0[idx], c1[idx]
    # point forces strictly left of each cut; a node's own force counts at its element's first cut
    pf = np.concatenate([[[0.0, 0.0]], np.cumsum(point, 0)])  # pf[k] = sum of forces at nodes < k
    pm = np.concatenate([[[0.0, 0.0]], np.cumsum(point * zn[:, None], 0)])
    # element e's cuts count the forces at nodes <= e (at t = 1: the left limit at node e + 1)
    left_inc = np.broadcast_to(np.arange(ne)[:, None] + 1, z.shape)
    F = pf[left_inc]  # (ne, n_sub + 1, 2)
    Fz = pm[left_inc]
    V = F + cm0[..., None] * g
    M = F * z[..., None] - Fz + (cm0 * z - cm1)[..., None] * g
    if couple is not None:
        pc = np.concatenate([[[0.0, 0.0]], np.cumsum(couple, 0)])[left_inc]  # (ne, n_sub + 1, (M_x, M_y))
        M = M + np.stack([-pc[..., 1], pc[..., 0]], -1)
    stress = np.hypot(M[..., 0], M[..., 1]) * (do / 2) / inertia
    return z.ravel(), V.reshape(-1, 2), M.reshape(-1, 2), stress.ravel()


def deflection_curve(rotor, q: np.ndarray, n_sub: int = 8) -> np.ndarray:
    """Deflection (c, 2) [m] at the cuts of :func:`static_analysis` (``n_sub + 1`` per element).

    Interpolated within each element by its own interdependent Timoshenko shape functions
    (``N_w`` of the element, plane by plane: x with theta_y, y with -theta_x), so the curve is
    the element's displacement field, not a straight line between nodes.
    """
    from rotaflex.rotor.fe.elements.shaft import _section, _shape, cowper_shear_coefficient

    e = rotor.elements
    t = np.linspace(0.0, 1.0, n_sub + 1)
    dm, dim_ = (e["do_l"] + e["do_r"]) / 2, (e["di_l"] + e["di_r"]) / 2
    A, I = _section(dm, dim_)
    kappa = np.where(np.isnan(e["kappa"]), cowper_shear_coefficient(dim_ / dm, e["E"] / (2 * e["G"]) - 1), e["kappa"])
    phi = 12 * e["E"] * I / (kappa * e["G"] * A * e["L"] ** 2)
    nw = _shape(t, phi, e["L"])[0]  # (ne, n_sub + 1, 4)
    Q = q[: rotor.n_rotor_dof].reshape(rotor.n_nodes, NDOF_NODE)
    qx = np.stack([Q[:-1, 0], Q[:-1, 3], Q[1:, 0], Q[1:, 3]], -1)  # x-z plane: (x, theta_y)
    qy = np.stack([Q[:-1, 1], -Q[:-1, 2], Q[1:, 1], -Q[1:, 2]], -1)  # y-z plane: (y, -theta_x)
    return np.stack([np.einsum("ngi,ni->ng", nw, qx).ravel(), np.einsum("ngi,ni->ng", nw, qy).ravel()], -1)
