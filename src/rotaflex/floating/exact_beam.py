"""Planar geometrically exact (Reissner) beams clamped to a reference frame, and their statics.

:class:`ExactBeam` is frozen model data: straight beams meshed into 2-node elements
(kinematics and element in :mod:`rotaflex.floating.exact_kernels`), the consistent mass
(translation ``rho A`` and rotary inertia ``rho I``, linear shape functions), root clamps to a
reference frame and, optionally, the rigid hub that frame belongs to. :func:`solve_static` finds
the equilibrium under loads by Newton's method with adaptive load stepping; the dynamics is in
:mod:`rotaflex.floating.exact_solve`.

DOFs: ``(x, y, theta)`` of every node (inertial), then the reference frame's ``(X, Y, phi)``.
In the planar description the mass matrix is constant in these inertial coordinates (Simo &
Vu-Quoc 1986): all the geometric nonlinearity sits in the internal forces.

Example
-------
>>> b = cantilever(1.0, 10, ea=1e6, ga=1e6, ei=1.0, rho_a=1.0)
>>> loads = PointLoads.build(b, [(1.0, 0.0)], ["force"], ["inertial"], [(0.0, -1.0)])
>>> q = solve_static(b, loads).q
>>> round(float(-q[3 * 10 + 1]), 2)  # tip deflection / L at P L^2 / EI = 1 (elastica 0.30)
0.3
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from rotaflex.core.errors import ConvergenceError, InputError
from rotaflex.floating import exact_kernels as ek

log = logging.getLogger(__name__)

#: most elements of one exact body (dense tangent: memory and time grow like elements^2 and ^3)
MAX_ELEMENTS = 400


class LoadSteppingError(ConvergenceError):
    """Newton's method could not follow the load: names the load fraction reached."""

    def __init__(self, fraction: float, residual: float, tolerance: float):
        RuntimeError.__init__(
            self,
            f"static equilibrium: Newton load stepping stopped at load fraction {fraction:.4g} "
            f"(residual {residual:.3e} > tolerance {tolerance:.3e}); the load may exceed a limit "
            "point (buckling, snap-through) or need more elements",
        )
        self.what, self.time, self.residual, self.tolerance = "load stepping", float("nan"), residual, tolerance
        self.fraction = fraction


@dataclass(frozen=True)
class ExactBeam:
    """Straight planar Reissner beams (one or more) and the reference frame they are clamped to.

    Attributes
    ----------
    nodes : (nn, 2) reference node positions in frame axes [m].
    angles : (nn,) reference section angles in frame axes [rad].
    conn : (ne, 2) int element nodes.
    stiffness : (ne, 3) ``EA`` [N], ``GA`` [N] (shear, with its shear coefficient), ``EI`` [N m^2].
    rho_a, rho_i : (ne,) mass [kg/m] and rotary inertia [kg m] per length.
    clamps : (nc, 4) rows ``(node, rx, ry, alpha)``: the node is clamped at ``(rx, ry)`` [m] of
        the frame with section angle ``phi + alpha`` [rad].
    beam_of : (nn,) int which beam a node belongs to; ``arclength`` (nn,) its distance from the
        beam's first node [m]; ``lengths`` per beam [m].
    hub_mass, hub_inertia : rigid hub carrying the frame [kg], [kg m^2] about its centre (the
        frame origin); 0 if the frame's motion is given (fixed or prescribed).
    hub_radius : points within this distance of the origin are on the rigid hub [m].
    """

    nodes: np.ndarray
    angles: np.ndarray
    conn: np.ndarray
    stiffness: np.ndarray
    rho_a: np.ndarray
    rho_i: np.ndarray
    clamps: np.ndarray
    beam_of: np.ndarray
    arclength: np.ndarray
    lengths: tuple[float, ...]
    hub_mass: float = 0.0
    hub_inertia: float = 0.0
    hub_radius: float = 0.0
    lumped: bool = False
    #: constraint equations per clamp (planar: x, y, angle)
    clamp_size = 3

    @property
    def n_nodes(self) -> int:
        return len(self.nodes)

    def residual(self, loads, q, lam_scale, want_k=True):
        """:func:`residual` of this body (the static driver calls it through the body)."""
        return residual(self, loads, q, lam_scale, want_k)

    def constrain(self, q, clamp, g, G):
        """Clamp gaps ``g`` and Jacobian ``G`` (:func:`rotaflex.floating.exact_kernels.constraints`)."""
        ek.constraints(q, clamp, g, G)

    def advance(self, q, free, dx):
        """Add the Newton correction ``dx`` to the free DOFs of ``q`` in place."""
        q[free] += dx

    @property
    def n_dof(self) -> int:
        """Node DOFs then the frame's ``X, Y, phi``."""
        return 3 * self.n_nodes + 3

    @property
    def frame_dof(self) -> int:
        return 3 * self.n_nodes

    @property
    def length(self) -> float:
        """Longest beam [m] (the length deflections are measured against)."""
        return float(max(self.lengths))

    def reference_state(self) -> np.ndarray:
        """``q`` of the undeformed body with the frame at the origin."""
        q = np.zeros(self.n_dof)
        q[0 : 3 * self.n_nodes : 3] = self.nodes[:, 0]
        q[1 : 3 * self.n_nodes : 3] = self.nodes[:, 1]
        q[2 : 3 * self.n_nodes : 3] = self.angles
        return q

    def clamp_table(self) -> np.ndarray:
        """Clamps as the kernel's ``(node, frame DOF, rx, ry, alpha, 0)`` rows."""
        out = np.zeros((len(self.clamps), 6))
        for i, (c, rx, ry, al) in enumerate(self.clamps):
            out[i] = (c, self.frame_dof, rx, ry, al, 0.0)
        return out

    def mass_matrix(self) -> np.ndarray:
        """Consistent mass (n, n) [kg, kg m^2]: ``rho A`` on x, y and ``rho I`` on theta with
        linear shape functions (``L0 / 6 [[2, 1], [1, 2]]``), the hub on the frame DOFs; with
        ``lumped`` its row sums on the diagonal (``L0 / 2`` to each node: the errors of soft
        one-point stiffness and lumped inertia cancel in the higher modes, docs/floating.md)."""
        n = self.n_dof
        M = np.zeros((n, n))
        for e, (a, b) in enumerate(self.conn):
            le = float(np.hypot(*(self.nodes[b] - self.nodes[a])))
            for j, rho in ((0, self.rho_a[e]), (1, self.rho_a[e]), (2, self.rho_i[e])):
                ia, ib = 3 * a + j, 3 * b + j
                m = rho * le / 6.0
                M[ia, ia] += 2 * m
                M[ib, ib] += 2 * m
                M[ia, ib] += m
                M[ib, ia] += m
        if self.lumped:
            M = np.diag(M.sum(axis=1))
        d = self.frame_dof
        M[d, d] = M[d + 1, d + 1] = self.hub_mass
        M[d + 2, d + 2] = self.hub_inertia
        return M

    def reference_lengths(self) -> np.ndarray:
        d = self.nodes[self.conn[:, 1]] - self.nodes[self.conn[:, 0]]
        return np.hypot(d[:, 0], d[:, 1])

    def locate(self, point, where: str) -> tuple[int, int, float]:
        """Material point (frame axes, undeformed) as ``(node a, node b, xi)``: the point is
        ``(1 - xi) a + xi b``; ``a = b = -1`` for a point on the rigid hub."""
        p = np.asarray(point, dtype=float)[:2]
        if float(np.linalg.norm(p)) <= self.hub_radius and self.hub_radius > 0:
            return -1, -1, 0.0
        best = (np.inf, 0, 0, 0.0)
        for a, b in self.conn:
            d = self.nodes[b] - self.nodes[a]
            xi = float(np.clip(np.dot(p - self.nodes[a], d) / np.dot(d, d), 0.0, 1.0))
            dist = float(np.linalg.norm(self.nodes[a] + xi * d - p))
            if dist < best[0]:
                best = (dist, int(a), int(b), xi)
        if best[0] > 1e-6 * self.length:
            raise InputError(
                where, list(np.asarray(point, dtype=float)), "a point on the beam axis (undeformed, body axes)"
            )
        return best[1], best[2], best[3]


def straight(length, n_el, *, ea, ga, ei, rho_a, rho_i=None, start=(0.0, 0.0), angle=0.0, where="body.exact"):
    """Nodes, connectivity and section data of one straight uniform beam (before clamping).

    ``rho_i`` [kg m] defaults to ``rho_a EI / EA`` (the rotary inertia of the section whose
    ``I / A`` these stiffnesses imply). Raises :class:`InputError` naming ``where.<key>``.
    """
    for key, val in (("ea", ea), ("ga", ga), ("ei", ei), ("rho_a", rho_a), ("length", length)):
        if not (np.isfinite(val) and val > 0):
            raise InputError(f"{where}.{key}", val, "a number > 0")
    if rho_i is not None and not (np.isfinite(rho_i) and rho_i >= 0):
        raise InputError(f"{where}.rho_i", rho_i, "a number >= 0")
    if isinstance(n_el, bool) or int(n_el) != n_el or not 1 <= n_el <= MAX_ELEMENTS:
        raise InputError(f"{where}.elements", n_el, f"a whole number from 1 to {MAX_ELEMENTS}")
    n_el = int(n_el)
    s = np.linspace(0.0, length, n_el + 1)
    d = np.array([np.cos(angle), np.sin(angle)])
    nodes = np.asarray(start, dtype=float)[:2] + s[:, None] * d
    conn = np.column_stack([np.arange(n_el), np.arange(1, n_el + 1)])
    stiff = np.tile([ea, ga, ei], (n_el, 1)).astype(float)
    ri = rho_a * ei / ea if rho_i is None else rho_i
    return nodes, np.full(n_el + 1, float(angle)), conn, stiff, np.full(n_el, float(rho_a)), np.full(n_el, float(ri)), s


def assemble(pieces, clamped, *, hub_mass=0.0, hub_inertia=0.0, hub_radius=0.0, lumped=False) -> ExactBeam:
    """One :class:`ExactBeam` from :func:`straight` pieces; ``clamped[i]``: clamp piece i's first
    node to the frame where it is."""
    nodes, angles, conn, stiff, ra, ri, beam_of, arc, clamps, lengths = [], [], [], [], [], [], [], [], [], []
    off = 0
    for i, (nd, an, cn, st, rha, rhi, s) in enumerate(pieces):
        nodes.append(nd)
        angles.append(an)
        conn.append(cn + off)
        stiff.append(st)
        ra.append(rha)
        ri.append(rhi)
        beam_of.append(np.full(len(nd), i))
        arc.append(s)
        lengths.append(float(s[-1]))
        if clamped[i]:
            clamps.append((off, nd[0, 0], nd[0, 1], an[0]))
        off += len(nd)
    return ExactBeam(
        nodes=np.vstack(nodes),
        angles=np.concatenate(angles),
        conn=np.vstack(conn).astype(np.int64),
        stiffness=np.vstack(stiff),
        rho_a=np.concatenate(ra),
        rho_i=np.concatenate(ri),
        clamps=np.array(clamps, dtype=float).reshape(-1, 4),
        beam_of=np.concatenate(beam_of),
        arclength=np.concatenate(arc),
        lengths=tuple(lengths),
        hub_mass=float(hub_mass),
        hub_inertia=float(hub_inertia),
        hub_radius=float(hub_radius),
        lumped=bool(lumped),
    )


def cantilever(length, n_el, *, ea, ga, ei, rho_a, rho_i=None, where="body.exact") -> ExactBeam:
    """A straight beam along x from the origin, clamped there to the frame."""
    return assemble([straight(length, n_el, ea=ea, ga=ga, ei=ei, rho_a=rho_a, rho_i=rho_i, where=where)], [True])


@dataclass(frozen=True)
class PointLoads:
    """Nodal loads in kernel layout (:func:`rotaflex.floating.exact_kernels.external`) plus a
    distributed load fixed in space; ``profile``/``par`` per load for dynamics."""

    node: np.ndarray
    kind: np.ndarray
    frame: np.ndarray
    amp: np.ndarray
    ref: np.ndarray
    profile: np.ndarray
    par: np.ndarray
    dist: np.ndarray

    @staticmethod
    def build(beam: ExactBeam, points, kinds, frames, vectors, profiles=None, pars=None, distributed=(0.0, 0.0)):
        """Loads at material points (split onto the two nodes of their element by the linear
        shape functions). ``kinds``: ``force``/``torque``; ``frames``: ``body``, ``inertial``,
        ``material``; ``vectors``: (fx, fy) [N] or (mz, 0) [N m]; ``distributed``: (wx, wy) [N/m]
        on every element or (ne, 2) one per element, fixed in space (gravity: ``rho_a g``).
        A point on the rigid hub loads the frame DOFs (material frame = body frame there)."""
        codes = {"body": 0, "inertial": 1, "material": 2}
        rows = []
        n = len(points)
        profiles = [0] * n if profiles is None else profiles
        pars = [(0.0, 0.0, 0.0, 0.0)] * n if pars is None else pars
        for i in range(n):
            a, b, xi = beam.locate(points[i], f"loads[{i}].point")
            fr = codes[frames[i]]
            if a < 0:  # on the rigid hub: the frame's DOFs (X, Y, phi) sit like one more node
                a, b, xi, fr = beam.n_nodes, beam.n_nodes, 0.0, 0 if fr == 2 else fr
            for node, w in ((a, 1.0 - xi), (b, xi)):
                if w == 0.0:
                    continue
                ref = beam.angles[node] if fr == 2 else 0.0
                rows.append((node, kinds[i] == "torque", fr, w * np.asarray(vectors[i][:2], dtype=float), ref, i))
        L0 = beam.reference_lengths()
        dist = np.zeros((len(beam.conn), 5))
        dist[:, 0:2] = beam.conn
        dist[:, 2] = L0
        dist[:, 3:5] = np.broadcast_to(np.asarray(distributed, dtype=float)[..., :2], (len(beam.conn), 2))
        idx = [r[5] for r in rows]
        return PointLoads(
            node=np.array([r[0] for r in rows], dtype=np.int64),
            kind=np.array([int(r[1]) for r in rows], dtype=np.int64),
            frame=np.array([r[2] for r in rows], dtype=np.int64),
            amp=np.array([r[3] for r in rows], dtype=float).reshape(-1, 2),
            ref=np.array([r[4] for r in rows], dtype=float),
            profile=np.array([profiles[i] for i in idx], dtype=np.int64),
            par=np.array([pars[i] for i in idx], dtype=float).reshape(-1, 4),
            dist=dist if np.any(dist[:, 3:5]) else np.zeros((0, 5)),
        )


@dataclass
class StaticSolution:
    """Equilibrium ``q`` (n,), the load fractions reached by the steps and the Newton counters."""

    q: np.ndarray
    fractions: np.ndarray
    iterations: int
    strain_energy: float


def residual(beam: ExactBeam, loads: PointLoads, q, lam_scale, want_k=True):
    """``f_int - lam f_ext`` (n,) and its tangent (n, n) at ``q``; ``lam_scale``: one factor for
    all loads or one per load and the distributed load last (nl + 1,)."""
    n = beam.n_dof
    f, K = np.zeros(n), np.zeros((n, n)) if want_k else np.zeros((1, 1))
    fe, Ke = np.zeros(n), np.zeros((n, n)) if want_k else np.zeros((1, 1))
    lam = np.broadcast_to(np.asarray(lam_scale, dtype=float), (len(loads.node) + 1,)).copy()
    kap0 = np.zeros(len(beam.conn))
    energy = ek.internal(q, q, beam.conn, beam.reference_lengths(), kap0, beam.stiffness, 0.0, 0.0, f, K, want_k)
    ek.external(
        q,
        lam,
        loads.node,
        loads.kind,
        loads.frame,
        loads.amp,
        loads.ref,
        beam.frame_dof + 2,
        loads.dist,
        fe,
        Ke,
        want_k,
    )
    return f - fe, K + Ke, energy


def solve_static(
    beam: ExactBeam,
    loads: PointLoads,
    *,
    q0=None,
    start=None,
    target=None,
    tol=1e-10,
    max_iter=25,
    first_step=0.1,
    min_step=1e-5,
):
    """Static equilibrium under the loads at full value (frame held where ``q0`` has it) by
    Newton's method with adaptive load stepping.

    ``start``/``target``: load factors per load (and the distributed load last, (nl + 1,)) at
    ``q0`` and to reach (default 0 and 1): the path ``start + f (target - start)``, ``f`` 0 -> 1.

    Each step raises the load fraction by ``d`` and iterates to ``|r| <= tol (|f_ext| + ...)``;
    a step that fails is halved, one that converges in <= 6 iterations lets the next grow 1.5x.
    Clamps are kept by Lagrange multipliers, the frame DOFs are fixed.

    Raises
    ------
    LoadSteppingError
        The step fell below ``min_step`` (names the load fraction reached).
    """
    n = beam.n_dof
    clamp = beam.clamp_table()
    nc = clamp.shape[0] * beam.clamp_size
    q = beam.reference_state() if q0 is None else np.array(q0, dtype=float)
    fixed = np.zeros(n, dtype=bool)
    fixed[beam.frame_dof :] = True
    free = np.flatnonzero(~fixed)
    nl = len(loads.node) + 1
    lam0 = np.zeros(nl) if start is None else np.broadcast_to(np.asarray(start, dtype=float), (nl,))
    lam1 = np.ones(nl) if target is None else np.broadcast_to(np.asarray(target, dtype=float), (nl,))
    r_full, _, _ = beam.residual(loads, q, np.maximum(np.abs(lam0), np.abs(lam1)), want_k=False)
    r_int, _, _ = beam.residual(loads, q, 0.0, want_k=False)
    scale = max(float(np.abs(r_full[free]).max()), float(np.abs(r_int[free]).max()), 1e-300)
    lam, d, fractions, iters = 0.0, first_step, [0.0], 0
    last_res = np.inf
    while lam < 1.0:
        nxt = min(1.0, lam + d)
        qt, ok, last_res, it = _newton(
            beam, loads, q.copy(), lam0 + nxt * (lam1 - lam0), clamp, free, nc, tol * scale, max_iter
        )
        iters += it
        if ok:
            q, lam = qt, nxt
            fractions.append(lam)
            d = d * 1.5 if it <= 6 else d
            continue
        d *= 0.5
        if d < min_step:
            raise LoadSteppingError(lam, last_res, tol * scale)
    _, _, energy = beam.residual(loads, q, lam1, want_k=False)
    log.info("static equilibrium in %d load steps, %d Newton iterations", len(fractions) - 1, iters)
    return StaticSolution(q, np.array(fractions), iters, float(energy))


def _newton(beam, loads, q, lam, clamp, free, nc, tol, max_iter):
    """Newton iterations of the bordered system ``[K G^T; G 0]`` at load factors ``lam``."""
    n = beam.n_dof
    nf = len(free)
    g, G = np.zeros(nc), np.zeros((nc, n))
    mult = np.zeros(nc)
    res, step = np.inf, np.inf
    for it in range(1, max_iter + 1):
        r, K, _ = beam.residual(loads, q, lam)
        if nc:
            beam.constrain(q, clamp, g, G)
            r = r + G.T @ mult
        res = float(np.abs(r[free]).max()) if nf else 0.0
        cres = float(np.abs(g).max()) if nc else 0.0
        if not np.isfinite(res):
            return q, False, res, it
        # converged: the residual at its tolerance, or the last correction at round-off level and
        # the residual at the round-off floor of the stiff axial forces (EA / L0 times the
        # round-off of the node coordinates)
        floor = 1e-14 * float(np.abs(np.diag(K)[free]).max()) * max(beam.length, 1.0) if nf else 0.0
        small = step <= 1e-12 * max(beam.length, 1.0) and res <= max(floor, tol)
        if it > 1 and (res <= tol or small) and cres <= 1e-12 * beam.length:
            return q, True, res, it
        A = np.zeros((nf + nc, nf + nc))
        A[:nf, :nf] = K[np.ix_(free, free)]
        if nc:
            A[:nf, nf:] = G[:, free].T
            A[nf:, :nf] = G[:, free]
        try:
            dx = np.linalg.solve(A, -np.concatenate([r[free], g]))
        except np.linalg.LinAlgError:
            return q, False, res, it
        beam.advance(q, free, dx[:nf])
        mult += dx[nf:]
        step = float(np.abs(dx[:nf]).max()) if nf else 0.0
        if np.abs(dx[:nf]).max() > 10.0 * beam.length:
            return q, False, res, it
    return q, False, res, max_iter
