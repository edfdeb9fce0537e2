"""The uniform Euler-Bernoulli beam with analytic modes, as a :class:`~rotaflex.floating.body.Body`.

:func:`uniform_beam` builds it from four parts:

* the analytic modes (:func:`beam_roots`, :func:`beam_mode`): free-free or cantilever;
* Gauss quadrature points along the axis (:func:`_quadrature`), with a break at every load
  point so that the attachment shapes below are integrated exactly;
* static attachment shapes of unit forces and moments (:func:`_attachment_deflection`), added to
  the modes of each bending plane and re-diagonalised by Rayleigh-Ritz (:class:`_BeamShapes`);
* the centrifugal and load geometric stiffness from the beam's axial force (:func:`_centrifugal`,
  :func:`_load_geometric_fn`), and the exact inextensible kinematics of a planar cantilever
  (:mod:`rotaflex.floating.inextensible`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from rotaflex.core.errors import InputError
from rotaflex.floating.body import Body, plain


def beam_roots(support: str, n: int) -> np.ndarray:
    """Roots ``beta_i L`` of the free-free (``cos cosh = 1``) or cantilever (``= -1``) equation."""
    sign = 1.0 if support == "free-free" else -1.0

    def f(x):  # cos x cosh x - sign, scaled by exp(-x) for large x
        return np.cos(x) * 0.5 * (1.0 + np.exp(-2.0 * x)) - sign * np.exp(-x)

    out = []
    for i in range(n):
        k = i + 1 if support == "free-free" else i
        out.append(brentq(f, k * np.pi + 0.3, (k + 1) * np.pi - 0.3, xtol=1e-15, rtol=1e-15))
    return np.array(out)


def _beam_coefficients(support: str, bl: float) -> np.ndarray:
    """Coefficients (a1..a4) of ``phi = a1 cos x + a2 sin x + a3 e^(x-bL) + a4 e^(-x)``."""
    em, s, c = np.exp(-bl), np.sin(bl), np.cos(bl)
    if support == "free-free":
        sigma = (1.0 + em * em - 2.0 * c * em) / (1.0 - em * em - 2.0 * s * em)
        a3 = (c - s - em) / (1.0 - em * em - 2.0 * s * em)
        return np.array([1.0, -sigma, a3, 0.5 * (1.0 + sigma)])
    sigma = (1.0 - em * em - 2.0 * s * em) / (1.0 + em * em + 2.0 * c * em)
    a3 = (em + c + s) / (1.0 + em * em + 2.0 * c * em)
    return np.array([-1.0, sigma, a3, 0.5 * (1.0 + sigma)])


def beam_mode(support: str, bl: float, s: np.ndarray, deriv: int = 0) -> np.ndarray:
    """Un-normalised mode ``phi(s)`` (or its ``deriv``-th derivative w.r.t. ``s``), ``s`` in [0, 1]."""
    a = _beam_coefficients(support, bl)
    x = bl * np.asarray(s, dtype=float)
    trig = [(np.cos(x), np.sin(x)), (-np.sin(x), np.cos(x)), (-np.cos(x), -np.sin(x))][deriv]
    ex = np.exp(x - bl)
    emx = np.exp(-x) * (-1.0) ** deriv
    return bl**deriv * (a[0] * trig[0] + a[1] * trig[1] + a[2] * ex + a[3] * emx)


def _check_inputs(length, rho_a, ei, ei_z, n_modes, support, section_radius) -> float:
    """Refuse bad beam parameters; returns the section radius [m] (0 for a line beam)."""
    for name, v in (("body.beam.length", length), ("body.beam.rho_a", rho_a), ("body.beam.ei", ei)):
        if not (np.isfinite(v) and v > 0):
            raise InputError(name, v, "a number > 0")
    if ei_z is not None and not ei_z > 0:
        raise InputError("body.beam.ei_z", ei_z, "a number > 0 [N m^2]")
    if n_modes < 1:
        raise InputError("body.beam.n_modes", n_modes, "an integer >= 1 (a body needs elastic modes)")
    if support not in ("free-free", "cantilever"):
        raise InputError("body.beam.support", support, "'free-free' or 'cantilever'")
    rg = 0.0 if section_radius is None else float(section_radius)
    if not (np.isfinite(rg) and rg >= 0):
        raise InputError("body.beam.section_radius", section_radius, "a radius >= 0 [m]")
    return rg


def _on_axis(pts, where: str, x0: float, x_end: float, length: float) -> np.ndarray:
    """Axial coordinates [m] of points that must lie on the beam axis (InputError otherwise)."""
    pts = np.atleast_2d(np.asarray(pts, dtype=float))
    ss = (pts[:, 0] - x0) / length
    bad = (ss < -1e-9) | (ss > 1 + 1e-9) | (np.hypot(pts[:, 1], pts[:, 2]) > 1e-9 * length)
    if np.any(bad):
        k = int(np.argmax(bad))
        raise InputError(
            where,
            pts[k].tolist(),
            f"a point on the beam axis: y = z = 0 and x in [{x0:g}, {x_end:g}] m",
        )
    return np.clip(pts[:, 0], x0, x_end)


#: largest Gauss rule taken from numpy (bit for bit the rule beams up to 23 modes always had)
_LEGGAUSS_MAX = 200


def _quadrature(x0: float, x_end: float, length: float, att: np.ndarray, nq: int):
    """Composite Gauss rule along the axis with a break at every interior load point:
    attachment shapes are piecewise polynomials there (a moment shape's curvature jumps), and
    the body's mass integrals must stay exact for them. Returns ``(cuts, g, gw, xq, wq)``
    (breaks, the ``nq``-point rule on [-1, 1], points [m] and weights [m])."""
    cuts = np.unique(np.concatenate([[x0, x_end], att]))
    cuts = cuts[np.concatenate([[True], np.diff(cuts) > 1e-9 * length])]
    cuts[-1] = x_end
    if nq <= _LEGGAUSS_MAX:
        g, gw = np.polynomial.legendre.leggauss(nq)
    else:  # numpy's rule is an O(nq^3) eigenproblem: 7.4 s CPU at nq = 976 (120 modes)
        from scipy.special import roots_legendre

        g, gw = roots_legendre(nq)  # O(nq) asymptotic nodes; weights agree with numpy's to 1e-14
    xq = np.concatenate([a + 0.5 * (g + 1.0) * (b - a) for a, b in zip(cuts[:-1], cuts[1:], strict=True)])
    wq = np.concatenate([0.5 * gw * (b - a) for a, b in zip(cuts[:-1], cuts[1:], strict=True)])
    return cuts, g, gw, xq, wq


def _attachment_deflection(support: str, length: float, x0: float, a: float, x, deriv: int, moment: bool = False):
    """Static deflection x EI under a unit transverse force (or, ``moment``, a unit moment
    bending the same plane) at ``a``, and its ``deriv``-th x-derivative; free-free: with inertia
    relief ``q = -rho_a (a0 + alpha x)``; cantilever: clamped at the root."""
    if support == "cantilever":
        if moment:  # EI w'' = H(a - x)
            xc = np.minimum(x, a)
            return [xc * xc / 2.0 + a * (x - xc), xc, (x < a).astype(float)][deriv]
        t = np.clip(a - x, 0.0, None)
        return [(a * a * x - (a**3 - t**3) / 3.0) / 2.0, (a * a - t * t) / 2.0, t][deriv]
    P = np.polynomial.Polynomial
    # relief load per unit force: rho_a (a0 + alpha x) = 1/L + 12 a x / L^3; per unit moment
    # (no resultant force): 12 x / L^3
    q = P([0.0, -12.0 / length**3]) if moment else P([-1.0 / length, -12.0 * a / length**3])
    mom = q.integ(lbnd=x0).integ(lbnd=x0)  # bending moment of the distributed relief load
    t = np.clip(x - a, 0.0, None)
    if moment:  # the couple's own moment: -H(x - a)
        return [
            mom.integ(2, lbnd=x0)(x) - t * t / 2.0,
            mom.integ(lbnd=x0)(x) - t,
            mom(x) - (x > a).astype(float),
        ][deriv]
    return [mom.integ(2, lbnd=x0)(x) + t**3 / 6.0, mom.integ(lbnd=x0)(x) + t * t / 2.0, mom(x) + t][deriv]


@dataclass
class _BeamShapes:
    """Mode shapes of the beam's bending planes: analytic modes plus attachment shapes,
    combined per plane by ``Cs[plane]`` and ordered by frequency as ``cols`` = (axis, plane,
    column) (axis 1: deflection along y, 2: along z)."""

    support: str
    length: float
    x0: float
    x_end: float
    bl: np.ndarray  # beta_i L of the analytic modes
    norm: np.ndarray  # their mass normalisation
    att: np.ndarray  # attachment points (forces first, then moments) [m]
    is_moment: np.ndarray
    rig: np.ndarray  # rigid-body part (a + b x) of each attachment shape (free-free)
    planes: list  # (axis, EI) of each bending plane
    Cs: list | None = None
    cols: list | None = None

    def raw(self, x, deriv, e_i):
        """Columns [elastic modes, attachment shapes] of one bending plane and their x-derivs."""
        ss = (x - self.x0) / self.length
        cols = [
            beam_mode(self.support, b, ss, deriv) / nm / self.length**deriv
            for b, nm in zip(self.bl, self.norm, strict=True)
        ]
        for i, a in enumerate(self.att):
            v = _attachment_deflection(self.support, self.length, self.x0, a, x, deriv, self.is_moment[i])
            v = v - [self.rig[i, 0] + self.rig[i, 1] * x, self.rig[i, 1], 0.0][deriv]
            cols.append(v / e_i)
        return np.column_stack(cols)

    def plane_values(self, x, deriv):
        return [self.raw(x, deriv, e_i) @ self.Cs[p_i] for p_i, (_a, e_i) in enumerate(self.planes)]

    def columns(self, x, deriv):
        """The ``deriv``-th x-derivative of the body's mode columns (in body order) at ``x``."""
        vals = self.plane_values(np.asarray(x, dtype=float), deriv)
        return np.column_stack([vals[p_i][:, c] for (_a, p_i, c) in self.cols])

    def shape_fn(self, pts):
        """Translational and rotational mode shapes (P, 3, n) at points on the axis."""
        x = _on_axis(pts, "point", self.x0, self.x_end, self.length)
        vals, slopes = self.plane_values(x, 0), self.plane_values(x, 1)
        n = len(self.cols)
        Phi = np.zeros((len(x), 3, n))
        Psi = np.zeros((len(x), 3, n))
        for j, (axis, p_i, c) in enumerate(self.cols):
            Phi[:, axis, j] = vals[p_i][:, c]
            if axis == 1:
                Psi[:, 2, j] = slopes[p_i][:, c]  # deflection along y: rotation about z = v'
            else:
                Psi[:, 1, j] = -slopes[p_i][:, c]  # deflection along z: rotation about y = -w'
        return Phi, Psi


def _ritz_planes(sh: _BeamShapes, xq, wq, masses, n_modes: int, rho_a: float):
    """Combine modes and attachment shapes of each plane (Rayleigh-Ritz: mass-orthonormal,
    diagonal stiffness) and order all columns by frequency; sets ``sh.Cs`` and ``sh.cols``,
    returns ``(omegas [rad/s], labels)``."""
    cols, om2, labels, Cs = [], [], [], []
    for p_i, (axis, e_i) in enumerate(sh.planes):
        name = "yz"[axis - 1]
        if len(sh.att):
            from scipy.linalg import eigh

            R0 = sh.raw(xq, 0, e_i)
            Mr = np.einsum("k,ki,kj->ij", masses, R0, R0)
            R2 = sh.raw(xq, 2, e_i)  # exact: the quadrature breaks at every attachment point
            Kr = np.einsum("k,ki,kj->ij", wq * e_i, R2, R2)
            w2, C = eigh(0.5 * (Kr + Kr.T), 0.5 * (Mr + Mr.T))
            sg = np.sign(C[:n_modes].diagonal())
            C[:, :n_modes] *= np.where(sg == 0, 1.0, sg)
        else:
            C = np.eye(n_modes)
            w2 = (sh.bl**2 * np.sqrt(e_i / (rho_a * sh.length**4))) ** 2
        Cs.append(C)
        for j in range(C.shape[1]):
            cols.append((axis, p_i, j))
            om2.append(w2[j])
            labels.append(f"bend_{name}{j + 1}" if j < n_modes else f"attach_{name}{j + 1 - n_modes}")
    order = np.argsort(om2, kind="stable")
    sh.Cs = Cs
    sh.cols = [cols[i] for i in order]
    return np.sqrt(np.array(om2)[order]), tuple(labels[i] for i in order)


def _same_plane(sh: _BeamShapes) -> np.ndarray:
    """1 where two mode columns bend the same plane (geometric stiffness couples only those)."""
    return np.array([[ca[0] == cb[0] for cb in sh.cols] for ca in sh.cols], dtype=float)


def _centrifugal(sh: _BeamShapes, xq, wq, rho_a: float) -> np.ndarray:
    """Unit centrifugal geometric stiffness (3, 3, n, n) from the axial tension of a spin about
    a transverse axis, ``N(x) = rho_a int_x^end xi dxi = rho_a (x_end^2 - x^2) / 2``."""
    n = len(sh.cols)
    tension = rho_a * 0.5 * (sh.x_end**2 - xq**2)
    dphi = sh.columns(xq, 1)
    KG = np.einsum("k,ki,kj->ij", wq * tension, dphi, dphi) * _same_plane(sh)
    G = np.zeros((3, 3, n, n))
    G[1, 1] = G[2, 2] = KG  # axial tension from w_y^2 + w_z^2 only (beam along x)
    return G


def _load_geometric_fn(sh: _BeamShapes, g, gw):
    """``load_geometric(pt, clamped=False) -> (3, n, n)``: geometric stiffness per unit
    body-frame force along x, y, z at ``pt``: the axial force of a unit x force with inertia
    relief (the body floats, so the rigid acceleration F/m loads every section), N(x) = H(a - x)
    - (x_end - x)/L; ``clamped`` (prescribed frame motion: the root carries the load) N(x) =
    H(a - x)."""
    n = len(sh.cols)
    same_plane = _same_plane(sh)
    x0, x_end, length = sh.x0, sh.x_end, sh.length

    def load_geometric(pt, clamped=False):
        relief = 0.0 if clamped else 1.0
        a = float(_on_axis([pt], "point", x0, x_end, length)[0])
        out = np.zeros((3, n, n))
        for xa, xb, step in ((x0, a, 1.0), (a, x_end, 0.0)):
            if xb - xa <= 1e-12 * length:
                continue
            xs = xa + 0.5 * (g + 1.0) * (xb - xa)
            ws = 0.5 * gw * (xb - xa)
            d_s = sh.columns(xs, 1)
            N = step - relief * (x_end - xs) / length
            out[0] += np.einsum("k,ki,kj->ij", ws * N, d_s, d_s) * same_plane
        return out

    return load_geometric


def uniform_beam(
    length: float,
    rho_a: float,
    ei: float,
    n_modes: int,
    *,
    ei_z: float | None = None,
    spatial: bool = False,
    support: str = "free-free",
    n_quad: int | None = None,
    section_radius: float | None = None,
    attachment_points=(),
    moment_points=(),
) -> Body:
    """Uniform Euler-Bernoulli beam along the body x axis with analytic modes.

    Parameters
    ----------
    length : float
        Length L [m] (> 0).
    rho_a : float
        Mass per length [kg/m] (> 0).
    ei : float
        Bending stiffness for deflection along y [N m^2] (> 0).
    n_modes : int
        Number of bending modes per plane (>= 1); rigid modes are excluded.
    ei_z : float, optional
        Bending stiffness for deflection along z [N m^2] (spatial beams; default ``ei``).
    spatial : bool
        False: planar beam deflecting along y only; True: bending in both planes (2 n_modes modes,
        sorted by frequency).
    support : {"free-free", "cantilever"}
        "free-free": body origin at the centre of mass, beam on x in [-L/2, L/2], mean axes.
        "cantilever": root clamped to the body frame at the origin, beam on x in [0, L]
        (tangent frame), as in the Kane-Ryan-Banerjee spin-up beam.
    n_quad : int, optional
        Number of Gauss points (default: 8 per half-wave of the highest mode, at least 48).
    section_radius : float, optional
        Radius of a solid circular section [m] (default 0: a line beam, which has no section
        inertia). If > 0, the rigid-body section inertia ``rho_a L diag(r^2/2, r^2/4, r^2/4)`` is
        added to ``J`` (the elastic model stays Euler-Bernoulli: no rotary inertia in the modes).
        A planar line beam (r = 0) has no inertia about its axis; that rotation is decoupled from
        in-plane motion, so in-plane loads are required. A spatial beam needs r > 0 to be
        simulated (its spin about its own axis would otherwise have no inertia).
    attachment_points : sequence of (3,) floats
        Load points [m] on the beam axis. For each, the static deflection under a unit
        transverse force (free-free: with inertia relief, made mass-orthogonal to the rigid
        modes; cantilever: clamped root) is added in each bending plane, and the set
        ``[modes, attachments]`` is re-diagonalised by Rayleigh-Ritz (stiffness by quadrature of
        ``EI phi'' phi''``), so the modes stay mass-orthonormal with diagonal ``K_b``; the extra
        "pseudo-modes" (labels ``attach_y1`` ...) carry the residual static flexibility of an end
        load that the truncated modal series misses.
    moment_points : sequence of (3,) floats
        Points [m] on the beam axis where moments about the transverse axes are applied: the
        static deflection under a unit concentrated moment (same supports and inertia relief as
        for forces) is added in each bending plane, like ``attachment_points``. Moments about the
        beam axis need none (the beam has no torsion modes).

    Returns
    -------
    Body

    Examples
    --------
    >>> b = uniform_beam(2.0, 1.0, 40.0, 3)
    >>> round(float(b.mass), 6)
    2.0
    """
    rg = _check_inputs(length, rho_a, ei, ei_z, n_modes, support, section_radius)
    bl = beam_roots(support, n_modes)
    nq = n_quad or max(48, int(8 * (n_modes + 2)))
    x0 = -0.5 * length if support == "free-free" else 0.0
    x_end = x0 + length
    att_f = _on_axis(attachment_points, "body.attachment_points", x0, x_end, length) if len(attachment_points) else []
    att_m = _on_axis(moment_points, "body.moment_points", x0, x_end, length) if len(moment_points) else []
    att = np.concatenate([np.asarray(att_f, float), np.asarray(att_m, float)])
    is_moment = np.arange(len(att)) >= len(att_f)
    cuts, g, gw, xq, wq = _quadrature(x0, x_end, length, att, nq)
    s = (xq - x0) / length  # in [0, 1]
    masses = rho_a * wq
    points = np.zeros((len(xq), 3))
    points[:, 0] = xq
    norm = np.array([np.sqrt(rho_a * np.sum(wq * beam_mode(support, b, s) ** 2)) for b in bl])
    # rigid-body part of each attachment shape (free-free: mass-orthogonal projection on 1, x)
    rig = np.zeros((len(att), 2))
    if support == "free-free":
        Mr2 = np.array([[masses.sum(), masses @ xq], [masses @ xq, masses @ xq**2]])
        for i, a in enumerate(att):
            w0 = _attachment_deflection(support, length, x0, a, xq, 0, is_moment[i])
            rig[i] = np.linalg.solve(Mr2, [masses @ w0, masses @ (xq * w0)])
    planes = [(1, ei)] + ([(2, ei_z if ei_z is not None else ei)] if spatial else [])
    sh = _BeamShapes(support, length, x0, x_end, bl, norm, att, is_moment, rig, planes)
    omegas, labels = _ritz_planes(sh, xq, wq, masses, n_modes, rho_a)
    Phi, _ = sh.shape_fn(points)
    inext = None
    if support == "cantilever" and not spatial:
        from rotaflex.floating import inextensible

        inext = inextensible.build(xq, wq, cuts, lambda x: sh.columns(x, 1), lambda x: sh.columns(x, 2), ei)
    frame = (
        "mean axes (origin at the centre of mass, x along the beam)"
        if support == "free-free"
        else "tangent frame clamped at the root (origin at the root, x along the beam)"
    )
    return Body(
        name=f"uniform {'spatial' if spatial else 'planar'} {support} beam, L={length:g} m",
        masses=masses,
        points=points,
        shapes=Phi,
        stiffness=np.diag(omegas**2),
        shape_fn=sh.shape_fn,
        geometric=_centrifugal(sh, xq, wq, rho_a),
        frame=frame,
        length=length,
        mode_labels=labels,
        extra_inertia=rho_a * length * rg**2 * np.diag([0.5, 0.25, 0.25]),
        planar=not spatial,
        load_geometric=_load_geometric_fn(sh, g, gw),
        inextensible=inext,
        params={
            "source": "uniform_beam",
            "length": float(length),
            "rho_a": float(rho_a),
            "ei": float(ei),
            "ei_z": None if ei_z is None else float(ei_z),
            "n_modes_per_plane": int(n_modes),
            "spatial": bool(spatial),
            "support": support,
            "section_radius": rg,
            "n_quad": int(nq),
            "attachment_points": plain([list(p) for p in attachment_points]),
            "moment_points": plain([list(p) for p in moment_points]),
        },
    )
