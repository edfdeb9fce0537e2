"""3-D geometrically exact (Simo-Reissner) beams clamped to a reference frame.

:class:`ExactBeam3D` is frozen model data beside the planar
:class:`~rotaflex.floating.exact_beam.ExactBeam`: beams (straight, or circular arcs) meshed
into 2-node elements (kinematics, strains and the element in
:mod:`rotaflex.floating.exact_kernels3d`), the root clamps to the reference frame. Statics is the
planar driver :func:`rotaflex.floating.exact_beam.solve_static` (Newton with adaptive load
stepping), which reaches the body through :meth:`ExactBeam3D.residual`,
:meth:`~ExactBeam3D.constrain` and :meth:`~ExactBeam3D.advance` (the multiplicative rotation
update).

DOFs: state ``q`` holds 7 numbers per node (position [m], section quaternion) and the frame's
7; increments (Newton corrections, the rows of the residual and the tangent) 6 per node
(``dx``, spatial spin ``dth``) and the frame's 6. Section axes: ``e1`` along the beam, ``e2``
and ``e3`` the principal axes of ``EI2`` and ``EI3``.

Example
-------
>>> b = cantilever3d(1.0, 10, ea=1e8, ga=1e8, gj=1.0, ei2=1.0, ei3=1.0)
>>> loads = PointLoads3D.build(b, [(1.0, 0.0, 0.0)], ["force"], ["inertial"], [(0.0, -1.0, 0.0)])
>>> q = solve_static(b, loads).q
>>> round(float(-q[7 * 10 + 1]), 2)  # tip deflection / L at P L^2 / EI = 1 (elastica 0.30)
0.3
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rotaflex.core.errors import InputError
from rotaflex.floating import exact_kernels3d as ek3
from rotaflex.floating.exact_beam import MAX_ELEMENTS, solve_static
from rotaflex.rotation import quaternion_from_matrix, quaternion_to_matrix

__all__ = ["ExactBeam3D", "PointLoads3D", "arc3d", "assemble3d", "cantilever3d", "solve_static", "straight3d"]

#: section stiffness keys in kernel order
STIFFNESS_KEYS = ("ea", "ga2", "ga3", "gj", "ei2", "ei3")


@dataclass(frozen=True)
class ExactBeam3D:
    """Beams of 2-node Simo-Reissner elements and the reference frame they are clamped to.

    Attributes
    ----------
    nodes : (nn, 3) reference node positions in frame axes [m].
    quats : (nn, 4) reference section rotations (unit quaternions, frame axes).
    conn : (ne, 2) int element nodes.
    stiffness : (ne, 6) ``EA, GA2, GA3`` [N], ``GJ, EI2, EI3`` [N m^2].
    rho_a : (ne,) mass per length [kg/m].
    rho_i : (ne, 3) rotary inertia per length about the section axes ``e1, e2, e3`` [kg m]
        (default ``rho_a (EI2 + EI3, EI2, EI3) / EA``: the section whose ``I / A`` these
        stiffnesses imply).
    clamps : (nc, 8) rows ``(node, rx, ry, rz, a0, a1, a2, a3)``: the node is clamped at ``r``
        [m] of the frame with section rotation ``R_F R(a)``.
    beam_of, arclength, lengths : which beam a node belongs to, its distance from the beam's
        first node [m], and the beam lengths [m].
    """

    nodes: np.ndarray
    quats: np.ndarray
    conn: np.ndarray
    stiffness: np.ndarray
    rho_a: np.ndarray
    clamps: np.ndarray
    beam_of: np.ndarray
    arclength: np.ndarray
    lengths: tuple[float, ...]
    rho_i: np.ndarray | None = None
    #: constraint equations per clamp (position and rotation)
    clamp_size = 6

    @property
    def n_nodes(self) -> int:
        return len(self.nodes)

    @property
    def n_dof(self) -> int:
        """Increments: 6 per node, then the frame's 6."""
        return 6 * self.n_nodes + 6

    @property
    def frame_dof(self) -> int:
        return 6 * self.n_nodes

    @property
    def length(self) -> float:
        """Longest beam [m]."""
        return float(max(self.lengths))

    def reference_state(self) -> np.ndarray:
        """State ``q`` (7 nn + 7,) of the undeformed body, the frame at the origin unrotated."""
        q = np.zeros(7 * self.n_nodes + 7)
        blocks = q.reshape(-1, 7)
        blocks[:-1, :3] = self.nodes
        blocks[:-1, 3:] = self.quats
        blocks[-1, 3] = 1.0
        return q

    def reference_lengths(self) -> np.ndarray:
        return np.linalg.norm(self.nodes[self.conn[:, 1]] - self.nodes[self.conn[:, 0]], axis=1)

    def rotary_inertia(self) -> np.ndarray:
        """(ne, 3) rotary inertia per length about ``e1, e2, e3`` [kg m]."""
        if self.rho_i is not None:
            return np.asarray(self.rho_i, dtype=float)
        st = self.stiffness
        return self.rho_a[:, None] * np.column_stack([st[:, 4] + st[:, 5], st[:, 4], st[:, 5]]) / st[:, :1]

    def mass_matrix(self) -> np.ndarray:
        """Mass (n, n) in increment layout [kg, kg m^2]: consistent ``rho A`` on the
        translations (linear shape functions, ``L0 / 6 [[2, 1], [1, 2]]``) and the rotary
        inertia lumped, ``L0 / 2`` of each element to each of its nodes, in section axes (the
        rotational equations are written with the material angular velocity)."""
        n = self.n_dof
        M = np.zeros((n, n))
        L0 = self.reference_lengths()
        ri = self.rotary_inertia()
        for e, (a, b) in enumerate(self.conn):
            m = self.rho_a[e] * L0[e] / 6.0
            for k in range(3):
                ia, ib = 6 * a + k, 6 * b + k
                M[ia, ia] += 2 * m
                M[ib, ib] += 2 * m
                M[ia, ib] += m
                M[ib, ia] += m
                M[6 * a + 3 + k, 6 * a + 3 + k] += 0.5 * L0[e] * ri[e, k]
                M[6 * b + 3 + k, 6 * b + 3 + k] += 0.5 * L0[e] * ri[e, k]
        return M

    def reference_strains(self) -> tuple[np.ndarray, np.ndarray]:
        """``Gamma0``, ``K0`` (ne, 3) of the reference configuration (its stress-free strains)."""
        out = np.zeros((len(self.conn), 6))
        z = np.zeros((len(self.conn), 3))
        ek3.element_strains(self.reference_state(), self.conn, self.reference_lengths(), z, z, out)
        return out[:, :3].copy(), out[:, 3:].copy()

    def clamp_table(self) -> np.ndarray:
        """Clamps as the kernel's ``(node, frame block, rx, ry, rz, a0..a3)`` rows."""
        out = np.zeros((len(self.clamps), 9))
        out[:, 0] = self.clamps[:, 0]
        out[:, 1] = self.n_nodes
        out[:, 2:] = self.clamps[:, 1:]
        return out

    def residual(self, loads, q, lam_scale, want_k=True, v=None, eta=0.0, kv=0.0):
        """``f_int - lam f_ext`` (n,), its tangent (n, n) and the strain energy [J] at ``q``;
        ``lam_scale``: one factor for all loads or one per load and the distributed load last;
        ``want_k``: False, True (the analytic tangent) or 2 (central differences of the
        internal force, the check). Kelvin-Voigt damping (``eta`` [s] > 0): ``v`` the
        velocities (6 per block, rotations material) and ``kv`` the integrator's d velocity /
        d increment (:func:`rotaflex.floating.exact_kernels3d.internal`)."""
        n = self.n_dof
        f, K = np.zeros(n), np.zeros((n, n)) if want_k else np.zeros((1, 1))
        fe, Ke = np.zeros(n), np.zeros((n, n)) if want_k else np.zeros((1, 1))
        lam = np.broadcast_to(np.asarray(lam_scale, dtype=float), (len(loads.node) + 1,)).copy()
        gam0, kap0 = self._ref
        vel = np.zeros(n) if v is None else np.asarray(v, dtype=float)
        # one integer type for the kernel's tangent switch (a bool would compile a second variant)
        mode = int(want_k)
        L0 = self._lengths
        energy = ek3.internal(q, vel, self.conn, L0, gam0, kap0, self.stiffness, float(eta), float(kv), f, K, mode)
        ek3.external(q, lam, loads.node, loads.kind, loads.frame, loads.amp, self.n_nodes, loads.dist, fe, Ke, mode > 0)
        return f - fe, K + Ke, energy

    @property
    def _ref(self):
        # the reference strains, computed once per body (the dataclass is frozen: cache in __dict__)
        if "_ref_cache" not in self.__dict__:
            object.__setattr__(self, "_ref_cache", self.reference_strains())
        return self.__dict__["_ref_cache"]

    @property
    def _lengths(self):
        # the reference lengths, computed once per body (3 % of a 3-D step when recomputed)
        if "_lengths_cache" not in self.__dict__:
            object.__setattr__(self, "_lengths_cache", self.reference_lengths())
        return self.__dict__["_lengths_cache"]

    def constrain(self, q, clamp, g, G):
        """Clamp gaps and Jacobian (:func:`rotaflex.floating.exact_kernels3d.constraints`)."""
        ek3.constraints(q, clamp, g, G)

    def advance(self, q, free, dx):
        """Apply the Newton correction ``dx`` on the free increments: positions add, section
        rotations turn by ``exp(dth~)`` (multiplicative update)."""
        full = np.zeros(self.n_dof)
        full[free] = dx
        ek3.advance(q, full)

    def node_positions(self, q) -> np.ndarray:
        """(nn, 3) node positions [m] of a state."""
        return np.asarray(q)[: 7 * self.n_nodes].reshape(-1, 7)[:, :3]

    def node_rotations(self, q) -> np.ndarray:
        """(nn, 3, 3) section rotation matrices of a state."""
        return quaternion_to_matrix(np.asarray(q)[: 7 * self.n_nodes].reshape(-1, 7)[:, 3:])

    def locate(self, point, where: str) -> tuple[int, int, float]:
        """Material point (undeformed, frame axes) as ``(node a, node b, xi)`` on the chords."""
        p = np.asarray(point, dtype=float)
        best = (np.inf, 0, 0, 0.0)
        for a, b in self.conn:
            d = self.nodes[b] - self.nodes[a]
            xi = float(np.clip(np.dot(p - self.nodes[a], d) / np.dot(d, d), 0.0, 1.0))
            dist = float(np.linalg.norm(self.nodes[a] + xi * d - p))
            if dist < best[0]:
                best = (dist, int(a), int(b), xi)
        if best[0] > 1e-6 * self.length:
            raise InputError(where, list(p), "a point on the beam axis (undeformed, body axes)")
        return best[1], best[2], best[3]


def _stiffness(values: dict, where: str) -> np.ndarray:
    for key in STIFFNESS_KEYS + ("rho_a",):
        val = values[key]
        if not (np.isfinite(val) and val > 0):
            raise InputError(f"{where}.{key}", val, "a number > 0")
    return np.array([values[k] for k in STIFFNESS_KEYS], dtype=float)


def _mesh_count(n_el, where):
    if isinstance(n_el, bool) or int(n_el) != n_el or not 1 <= n_el <= MAX_ELEMENTS:
        raise InputError(f"{where}.elements", n_el, f"a whole number from 1 to {MAX_ELEMENTS}")
    return int(n_el)


def _piece(nodes, frames, s, n_el, sections):
    """Nodes, section quaternions, connectivity, stiffness rows, rho_a and arclength of one beam."""
    quats = quaternion_from_matrix(frames)
    # one sign convention along the beam (q and -q are the same rotation)
    for i in range(1, len(quats)):
        if np.dot(quats[i], quats[i - 1]) < 0:
            quats[i] = -quats[i]
    conn = np.column_stack([np.arange(n_el), np.arange(1, n_el + 1)])
    stiff, rho = sections
    return nodes, quats, conn, np.tile(stiff, (n_el, 1)), np.full(n_el, rho), s


def straight3d(length, n_el, *, ea, ga, gj, ei2, ei3, rho_a=1.0, start=(0.0, 0.0, 0.0), frame=None, where="body.exact"):
    """One straight uniform beam along the section axis ``e1 = frame[:, 0]`` from ``start``.

    ``ga``: one shear stiffness or ``(GA2, GA3)`` [N]; ``frame``: (3, 3) section axes at the
    root (columns ``e1, e2, e3``; default the identity: along x, ``EI2`` about y, ``EI3`` about z).
    Raises :class:`InputError` naming ``where.<key>``.
    """
    ga2, ga3 = np.broadcast_to(np.asarray(ga, dtype=float), (2,))
    vals = dict(ea=ea, ga2=ga2, ga3=ga3, gj=gj, ei2=ei2, ei3=ei3, rho_a=rho_a)
    stiff = _stiffness(vals, where)
    if not (np.isfinite(length) and length > 0):
        raise InputError(f"{where}.length", length, "a number > 0")
    n_el = _mesh_count(n_el, where)
    F = np.eye(3) if frame is None else np.asarray(frame, dtype=float)
    s = np.linspace(0.0, length, n_el + 1)
    nodes = np.asarray(start, dtype=float) + s[:, None] * F[:, 0]
    return _piece(nodes, np.broadcast_to(F, (n_el + 1, 3, 3)), s, n_el, (stiff, float(rho_a)))


def arc3d(radius, angle, n_el, *, ea, ga, gj, ei2, ei3, rho_a=1.0, frame=None, where="body.exact"):
    """A circular arc of ``radius`` [m] over ``angle`` [rad] from the origin: it starts along the
    root's ``e1`` and turns about its ``e3`` (towards ``e2``); nodes on the arc, sections
    tangent to it (the chord elements carry the arc's curvature ``1/R`` about ``e3`` as their
    reference strain)."""
    if not (np.isfinite(radius) and radius > 0):
        raise InputError(f"{where}.bend_radius", radius, "a number > 0")
    ga2, ga3 = np.broadcast_to(np.asarray(ga, dtype=float), (2,))
    stiff = _stiffness(dict(ea=ea, ga2=ga2, ga3=ga3, gj=gj, ei2=ei2, ei3=ei3, rho_a=rho_a), where)
    n_el = _mesh_count(n_el, where)
    F = np.eye(3) if frame is None else np.asarray(frame, dtype=float)
    t = np.linspace(0.0, angle, n_el + 1)
    local = np.column_stack([radius * np.sin(t), radius * (1.0 - np.cos(t)), np.zeros_like(t)])
    c, s_ = np.cos(t), np.sin(t)
    Rz = np.zeros((n_el + 1, 3, 3))
    Rz[:, 0, 0], Rz[:, 0, 1], Rz[:, 1, 0], Rz[:, 1, 1], Rz[:, 2, 2] = c, -s_, s_, c, 1.0
    return _piece(local @ F.T, F @ Rz, radius * t, n_el, (stiff, float(rho_a)))


def assemble3d(pieces, clamped) -> ExactBeam3D:
    """One :class:`ExactBeam3D` from :func:`straight3d`/:func:`arc3d` pieces; ``clamped[i]``:
    clamp piece i's first node to the frame where it is."""
    nodes, quats, conn, stiff, rho, beam_of, arc, clamps, lengths = [], [], [], [], [], [], [], [], []
    off = 0
    for i, (nd, qu, cn, st, rh, s) in enumerate(pieces):
        nodes.append(nd)
        quats.append(qu)
        conn.append(cn + off)
        stiff.append(st)
        rho.append(rh)
        beam_of.append(np.full(len(nd), i))
        arc.append(s)
        lengths.append(float(s[-1]))
        if clamped[i]:
            clamps.append((off, *nd[0], *qu[0]))
        off += len(nd)
    return ExactBeam3D(
        nodes=np.vstack(nodes),
        quats=np.vstack(quats),
        conn=np.vstack(conn).astype(np.int64),
        stiffness=np.vstack(stiff),
        rho_a=np.concatenate(rho),
        clamps=np.array(clamps, dtype=float).reshape(-1, 8),
        beam_of=np.concatenate(beam_of),
        arclength=np.concatenate(arc),
        lengths=tuple(lengths),
    )


def cantilever3d(length, n_el, *, ea, ga, gj, ei2, ei3, rho_a=1.0, frame=None, where="body.exact") -> ExactBeam3D:
    """A straight beam from the origin along ``frame[:, 0]`` (default x), clamped there."""
    p = straight3d(length, n_el, ea=ea, ga=ga, gj=gj, ei2=ei2, ei3=ei3, rho_a=rho_a, frame=frame, where=where)
    return assemble3d([p], [True])


@dataclass(frozen=True)
class PointLoads3D:
    """Nodal loads in the layout of :func:`rotaflex.floating.exact_kernels3d.external` plus a
    distributed load fixed in space; ``profile``/``par`` per load (time profiles)."""

    node: np.ndarray
    kind: np.ndarray
    frame: np.ndarray
    amp: np.ndarray
    profile: np.ndarray
    par: np.ndarray
    dist: np.ndarray

    @staticmethod
    def build(beam: ExactBeam3D, points, kinds, frames, vectors, profiles=None, pars=None, distributed=(0, 0, 0)):
        """Loads at material points (split onto their element's two nodes by the linear shape
        functions). ``kinds``: ``force``/``torque``; ``frames``: ``body`` (the reference frame),
        ``inertial`` (fixed direction) or ``material`` (follows the section: given in frame axes
        at the undeformed state, turned with the section from there); ``vectors``: (3,) [N] or
        [N m]; ``distributed``: (3,) [N/m] on every element or (ne, 3), fixed in space."""
        codes = {"body": 0, "inertial": 1, "material": 2}
        n = len(points)
        profiles = [0] * n if profiles is None else profiles
        pars = [(0.0, 0.0, 0.0, 0.0)] * n if pars is None else pars
        rows = []
        for i in range(n):
            a, b, xi = beam.locate(points[i], f"loads[{i}].point")
            fr = codes[frames[i]]
            vec = np.asarray(vectors[i], dtype=float)[:3]
            for node, w in ((a, 1.0 - xi), (b, xi)):
                if w == 0.0:
                    continue
                # a follower load is stored in section axes: R_node^T at the reference state
                amp = quaternion_to_matrix(beam.quats[node]).T @ vec if fr == 2 else vec
                rows.append((node, kinds[i] == "torque", fr, w * amp, i))
        L0 = beam.reference_lengths()
        dist = np.zeros((len(beam.conn), 6))
        dist[:, 0:2] = beam.conn
        dist[:, 2] = L0
        dist[:, 3:6] = np.broadcast_to(np.asarray(distributed, dtype=float), (len(beam.conn), 3))
        idx = [r[4] for r in rows]
        return PointLoads3D(
            node=np.array([r[0] for r in rows], dtype=np.int64),
            kind=np.array([int(r[1]) for r in rows], dtype=np.int64),
            frame=np.array([r[2] for r in rows], dtype=np.int64),
            amp=np.array([r[3] for r in rows], dtype=float).reshape(-1, 3),
            profile=np.array([profiles[i] for i in idx], dtype=np.int64),
            par=np.array([pars[i] for i in idx], dtype=float).reshape(-1, 4),
            dist=dist if np.any(dist[:, 3:6]) else np.zeros((0, 6)),
        )
