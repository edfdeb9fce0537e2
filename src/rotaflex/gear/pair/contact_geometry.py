"""Contact geometry between two tooth surfaces given as cubic splines (section 2, appendix A).

Each tooth surface (the flank of the FE tooth, root -> tip) is interpolated by a natural cubic
spline through ``n_points`` data points (61 in the paper) placed uniformly in the FE edge
parameter; the points move with the nodes, so the splines are rebuilt from the current nodal
positions whenever the contact is searched. The contact pair (C^A, C^B) is the pair of minimum
normal distance:

* interior contact: the common-normal pair, found by a secant iteration on
  ``F(a) = P_B'(b(a)) . n_A(a)`` where ``b(a)`` is the normal projection of ``P_A(a)`` on B;
* if that pair lies beyond the tip of B (start of contact) the tip corner of B is projected
  on A and A's normal is used; beyond the tip of A (end of contact) the corner of A is
  projected on B and B's normal is used.

The signed normal separation ``h`` (> 0 open) gives the paper's penetration ``s = -h``. Its rate
is the relative normal velocity of the two material points, ``s_dot = n . (v_A - v_B)``
(eq. 9-13), and its second rate adds the sliding terms of appendix A (the contact point runs
along both curved surfaces; see :func:`rotaflex.gear.kernels.contact.sliding_terms`).

This module is a thin NumPy front end over the compiled kernels, used by tests and tools.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class ContactPair:
    """Result of a contact search.

    Attributes
    ----------
    a, b : float
        Spline parameters (0 = root end, 1 = tip end) of C^A and C^B.
    gap : float
        Signed normal separation h [m] (> 0 open, < 0 penetration; the paper's s = -h).
    normal : ndarray (2,)
        Unit normal pointing from A into B.
    case : str
        ``"interior"``, ``"tip_B"`` (tip corner of B on A's flank) or ``"tip_A"``.
    point_a, point_b : ndarray (2,)
        The two contact points [m].
    """

    a: float
    b: float
    gap: float
    normal: np.ndarray
    case: str
    point_a: np.ndarray
    point_b: np.ndarray


_CASES = ("interior", "tip_B", "tip_A")


def spline(points: np.ndarray) -> np.ndarray:
    """Second derivatives (M, 2) of the natural cubic spline through ``points`` (M, 2)."""
    from rotaflex.gear.kernels.contact import spline_second

    p = np.ascontiguousarray(points, dtype=float)
    m = np.empty_like(p)
    spline_second(p, m)
    return m


def spline_point(points: np.ndarray, s: float, m: np.ndarray | None = None) -> np.ndarray:
    """(3, 2) array: value, first and second derivative of the spline at parameter ``s``."""
    from rotaflex.gear.kernels.contact import spline_eval

    p = np.ascontiguousarray(points, dtype=float)
    m = spline(p) if m is None else m
    out = np.empty((3, 2))
    spline_eval(p, m, float(s), out)
    return out


def search(
    points_a: np.ndarray,
    points_b: np.ndarray,
    sig_a: float = 1.0,
    sig_b: float = 1.0,
    start: tuple[float, float] = (0.5, 0.5),
) -> ContactPair:
    """Minimum-normal-distance pair between surfaces A and B.

    Parameters
    ----------
    points_a, points_b : ndarray (M, 2)
        Spline data points of each surface [m], ordered root -> tip.
    sig_a, sig_b : float
        +1 when the outward normal is the tangent turned by +90 degrees, else -1.
    start : (float, float)
        Initial guess of the parameters (a, b).
    """
    from rotaflex.gear.kernels.contact import contact_search

    pa = np.ascontiguousarray(points_a, dtype=float)
    pb = np.ascontiguousarray(points_b, dtype=float)
    res = np.zeros(8)
    contact_search(pa, spline(pa), pb, spline(pb), float(sig_a), float(sig_b), start[0], start[1], res)
    if res[7] == 0.0:
        raise RuntimeError("contact search failed: no common normal between the surfaces")
    ea = spline_point(pa, res[0])
    eb = spline_point(pb, res[1])
    return ContactPair(
        a=float(res[0]),
        b=float(res[1]),
        gap=float(res[2]),
        normal=res[3:5].copy(),
        case=_CASES[int(res[5])],
        point_a=ea[0].copy(),
        point_b=eb[0].copy(),
    )


def normal_rates(
    points_a: np.ndarray,
    vel_a: np.ndarray,
    points_b: np.ndarray,
    vel_b: np.ndarray,
    sig_a: float = 1.0,
    sig_b: float = 1.0,
    start: tuple[float, float] = (0.5, 0.5),
) -> dict:
    """Gap rate and the sliding part of its second rate for surfaces moving with ``vel_*``.

    Returns a dict with ``pair`` (:class:`ContactPair`), ``s_dot`` = n . (v_A - v_B) at the
    contact points (positive = approaching), ``sliding`` = h_s such that
    ``s_ddot = n . (acc_A - acc_B) + h_s``, and the parameter rates ``a_dot``, ``b_dot``.
    """
    from rotaflex.gear.kernels.contact import contact_search, sliding_terms

    pa = np.ascontiguousarray(points_a, dtype=float)
    pb = np.ascontiguousarray(points_b, dtype=float)
    va = np.ascontiguousarray(vel_a, dtype=float)
    vb = np.ascontiguousarray(vel_b, dtype=float)
    ma, mb, mva, mvb = spline(pa), spline(pb), spline(va), spline(vb)
    res = np.zeros(8)
    contact_search(pa, ma, pb, mb, float(sig_a), float(sig_b), start[0], start[1], res)
    pair = search(pa, pb, sig_a, sig_b, start)
    n = res[3:5]
    sdot = float(n @ (spline_point(va, res[0], mva)[0] - spline_point(vb, res[1], mvb)[0]))
    rates = np.zeros(4)
    hs, _, _ = sliding_terms(pa, ma, va, mva, pb, mb, vb, mvb, float(sig_a), float(sig_b), res, rates)
    return {
        "pair": pair,
        "s_dot": sdot,
        "sliding": float(hs),
        "a_dot": float(rates[0]),
        "b_dot": float(rates[1]),
        "n_dot": rates[2:4].copy(),
    }
