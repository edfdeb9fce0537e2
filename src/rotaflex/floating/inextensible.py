"""Inextensible (geometrically exact) kinematics of a planar cantilever beam's modal deflection.

The linear floating-frame model puts a material point at ``(s, v(s))`` in the body frame, with
``v = Phi q`` and the bending energy ``EI/2 int v''^2``; the centrifugal geometric stiffness
restores the first-order effect of the beam's foreshortening. For a beam clamped to a
prescribed moving frame this module keeps the Ritz field ``v(s) = Phi(s) q`` but places the
material point exactly on the inextensible curve with that deflection:

    x(s) = s + u(s),   u(s) = int_0^s (sqrt(1 - v'^2) - 1) ds',   y(s) = v(s)

and uses the exact curvature ``kappa = v'' / sqrt(1 - v'^2)`` in the bending energy
``EI/2 int kappa^2 ds``. Nothing is linearised, so the centrifugal stiffening, the reduced
moment arm of the hub's angular acceleration and the Coriolis coupling of the shortening
all follow from the kinematics (the geometric stiffness term must then be left out: it would
count the stiffening twice). It removes the linear model's O((u/L)^2) relative error on the
spin-up beam (docs/floating.md).

Quadrature: ``u``, its gradient and its second derivative along ``p`` at the body's mass
points are cumulative sums over panels between consecutive mass points (and load cuts, where
the curvature of attachment shapes jumps), 4 Gauss points per panel; the bending terms use
the body's own quadrature, exact for ``K_b`` in the linear limit.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: Gauss points per panel of the cumulative shortening integral
PANEL_POINTS = 4


@dataclass(frozen=True, eq=False)
class InextensibleBeam:
    """Quadrature data of a planar cantilever beam for the inextensible kinematics (SI).

    Parameters
    ----------
    panel_slopes : ndarray (P, n)
        Mode slopes ``Phi'`` [1/m per modal unit] at the panel Gauss points.
    panel_weights : ndarray (P,)
        Their weights [m].
    panel_end : ndarray (N,)
        For each mass point, the number of panel Gauss points from the root to it (panels are
        contiguous, so ``u`` at the point is a cumulative sum up to that index).
    slopes, curvatures : ndarray (Q, n)
        ``Phi'`` and ``Phi''`` at the bending quadrature points.
    weights : ndarray (Q,)
        Bending quadrature weights [m].
    ei : float
        Bending stiffness [N m^2] (of the deflection plane, body y).
    root : float
        Body x of the clamped root [m].
    slope_fn : callable
        ``slope_fn(x (P,)) -> (P, n)`` mode slopes at arbitrary stations, for output points.
    """

    panel_slopes: np.ndarray
    panel_weights: np.ndarray
    panel_end: np.ndarray
    slopes: np.ndarray
    curvatures: np.ndarray
    weights: np.ndarray
    ei: float
    root: float
    slope_fn: object

    def packed(self) -> tuple:
        """Arrays for the compiled right-hand side."""
        return (
            self.panel_slopes,
            self.panel_weights,
            self.panel_end.astype(np.int64),
            self.slopes,
            self.curvatures,
            self.weights,
            np.array([self.ei]),
        )

    def shortening_rate(self, x: np.ndarray, q: np.ndarray, p: np.ndarray) -> np.ndarray:
        """Axial velocity ``du/dt`` [m/s] (T, P) of the stations ``x`` for states ``q``, ``p`` (T, n)."""
        x = np.asarray(x, dtype=float)
        g, gw = np.polynomial.legendre.leggauss(64)
        q, p = np.atleast_2d(q), np.atleast_2d(p)
        out = np.zeros((q.shape[0], x.size))
        for j, xj in enumerate(x):
            if xj <= self.root:
                continue
            S = self.slope_fn(self.root + 0.5 * (g + 1.0) * (xj - self.root))
            v1, r1 = q @ S.T, p @ S.T
            out[:, j] = (-v1 * r1 / np.sqrt(1.0 - v1 * v1)) @ (0.5 * gw * (xj - self.root))
        return out

    def bending_energy(self, q: np.ndarray) -> np.ndarray:
        """Exact bending energy ``EI/2 int v''^2 / (1 - v'^2)`` [J] (T,) for states ``q`` (T, n)."""
        q = np.atleast_2d(q)
        v1, v2 = q @ self.slopes.T, q @ self.curvatures.T
        return 0.5 * self.ei * (v2 * v2 / (1.0 - v1 * v1)) @ self.weights

    def shortening(self, x: np.ndarray, q: np.ndarray) -> np.ndarray:
        """Axial displacement ``u(x)`` [m] (T, P) of the stations ``x`` (P,) for states ``q`` (T, n).

        Raises ValueError where a slope reaches 1 (the deflection folds back: no inextensible
        curve has it).
        """
        x = np.asarray(x, dtype=float)
        g, gw = np.polynomial.legendre.leggauss(64)
        out = np.zeros((np.atleast_2d(q).shape[0], x.size))
        for j, xj in enumerate(x):
            if xj <= self.root:
                continue
            s = self.root + 0.5 * (g + 1.0) * (xj - self.root)
            v1 = np.atleast_2d(q) @ self.slope_fn(s).T  # (T, 64)
            c2 = 1.0 - v1 * v1
            if np.any(c2 <= 0.0):
                raise ValueError("slope |v'| >= 1: the deflection has no inextensible curve")
            out[:, j] = (np.sqrt(c2) - 1.0) @ (0.5 * gw * (xj - self.root))
        return out


def build(xq: np.ndarray, wq: np.ndarray, cuts: np.ndarray, slope_fn, curvature_fn, ei: float) -> InextensibleBeam:
    """Quadrature data from the body's Gauss points ``xq`` (weights ``wq``) on ``[cuts[0], cuts[-1]]``.

    ``slope_fn`` / ``curvature_fn`` map stations (P,) to ``Phi'`` / ``Phi''`` (P, n) of the
    deflection plane; ``cuts`` are the root, the load points and the free end.
    """
    bounds = np.unique(np.concatenate([cuts, xq]))
    g, gw = np.polynomial.legendre.leggauss(PANEL_POINTS)
    a, b = bounds[:-1], bounds[1:]
    xp = (a[:, None] + 0.5 * (g[None] + 1.0) * (b - a)[:, None]).ravel()
    wp = (0.5 * gw[None] * (b - a)[:, None]).ravel()
    # the mass point xq[k] is bounds[i]: the panels before it hold i * PANEL_POINTS points
    end = np.searchsorted(bounds, xq) * PANEL_POINTS
    return InextensibleBeam(
        panel_slopes=slope_fn(xp),
        panel_weights=wp,
        panel_end=end,
        slopes=slope_fn(xq),
        curvatures=curvature_fn(xq),
        weights=np.asarray(wq, dtype=float),
        ei=float(ei),
        root=float(cuts[0]),
        slope_fn=slope_fn,
    )
