"""Tilting-pad journal bearing: rigid pads on frictionless line pivots, no pad inertia.

Each pad k spans ``pad_arc`` with its pivot at theta_k (a fraction ``pivot_offset`` of the arc
from the leading edge, in the spin sense). Its film, in units of the pad clearance C_p, is

    H = 1 - ex cos theta - ey sin theta - d sin(theta - theta_k) - m cos(theta - theta_k)

with d = R delta / C_p the pad tilt and m = 1 - C_b / C_p the preload (C_b the assembled
clearance). The film is the finite-length Reynolds equation of :mod:`.reynolds` on the pad
(P = 0 at its edges and ends, Swift-Stieber cavitation). The pad tilts freely: its moment about
the pivot, -int int P sin(theta - theta_k), vanishes (a 1-D Newton solve per pad); the journal
is in equilibrium when the pads' forces balance the reaction (2-D Newton with the pads kept in
moment equilibrium, stiffness from the perturbation solution). The 3 x 3 (x, y, tilt)
stiffness and damping of each pad are reduced to the journal at synchronous whirl (whirl
frequency = spin speed), Z = K + i C omega, Z_r = Z_jj - Z_jd Z_dj / Z_dd, the usual practice
for pad inertia neglected; the 8 coefficients are the sum over the pads.
"""

from __future__ import annotations

import numpy as np

from rotaflex.core.errors import InputError
from rotaflex.core.units import rad_s_to_rpm
from rotaflex.rotor.fe.bearings.reynolds import ReynoldsGrid, solve_general


class PadSet:
    """Pads of one bearing (grids built once) with warm-start state (tilts, cavitated sets)."""

    def __init__(self, l_over_d, pads, arc, pivot_offset, first_pivot, preload, n_theta, n_z):
        self.pivots = first_pivot + 2 * np.pi / pads * np.arange(pads)
        n_pad = max(16, int(round(n_theta * arc / (2 * np.pi))))
        self.grids = [
            ReynoldsGrid(l_over_d, n_pad, n_z, (p - pivot_offset * arc, p + (1 - pivot_offset) * arc))
            for p in self.pivots
        ]
        self.m = preload
        self.tilt = np.zeros(pads)
        self.active = [None] * pads

    def pad(self, k, ex, ey, p_cav):
        """Solution of pad k in moment equilibrium about its pivot.

        The moment M(d) is >= 0 below the equilibrium tilt (no film, or the centre of pressure
        behind the pivot) and < 0 above it (a larger tilt closes the trailing edge, d > 0 opens
        the leading one): Newton on d, kept inside a bracket grown upwards until M < 0 and then
        bisected when a Newton step leaves it; contact (H <= 0) counts as above.
        """
        phase = np.array([0.0, np.pi / 2, self.pivots[k] + np.pi / 2, self.pivots[k]])
        d, lo, hi = self.tilt[k], -np.inf, np.inf
        best = None
        for _ in range(200):
            try:
                s = solve_general(self.grids[k], [ex, ey, d, self.m], phase, 3, p_cav, self.active[k])
            except ValueError:  # the pad touches the journal
                hi = d
                d = 0.5 * (lo + hi) if np.isfinite(lo) else d - 0.1
                continue
            self.active[k] = s.active
            best = s
            moment, load = s.Q[2], np.abs(s.Q[:2]).sum()
            if load > 0 and abs(moment) <= 1e-10 * load:
                break
            if moment < 0:
                hi = d
            else:
                lo = d
            newton = d + moment / s.k[2, 2] if load > 0 and s.k[2, 2] > 0 else np.nan  # dM/dd = -k_dd
            if lo < newton < hi:
                d = newton
            elif np.isfinite(lo) and np.isfinite(hi):
                d = 0.5 * (lo + hi)
            else:
                d = d + 0.1 if np.isinf(hi) else d - 0.1
            if hi - lo < 1e-14:
                break
        if best is None:
            raise ValueError("no pad tilt without contact")
        self.tilt[k] = d
        return best

    def state(self, ex, ey, p_cav):
        """Journal force (2,), static reduced stiffness (2, 2) and the pad solutions."""
        F, K, sols = np.zeros(2), np.zeros((2, 2)), []
        for k in range(len(self.grids)):
            s = self.pad(k, ex, ey, p_cav)
            sols.append(s)
            F += s.Q[:2]
            if s.k[2, 2] > 0:
                K += s.k[:2, :2] - np.outer(s.k[:2, 2], s.k[2, :2]) / s.k[2, 2]
            else:
                K += s.k[:2, :2]
        return F, K, sols

    def reduced(self, sols):
        """K and B (dimensionless, 2 x 2) reduced at synchronous whirl, summed over the pads."""
        Z = np.zeros((2, 2), complex)
        for s in sols:
            z = s.k + 1j * s.b
            Z += z[:2, :2] - (np.outer(z[:2, 2], z[2, :2]) / z[2, 2] if abs(z[2, 2]) > 0 else 0)
        return Z.real, Z.imag


def tilting_pad_equilibrium(pads: PadSet, target, e0, p_cav, where, speed):
    """Journal position e (2,) with sum of pad forces = target (dimensionless), by Newton."""
    e = np.asarray(e0, float)
    try:
        F, K, sols = pads.state(*e, p_cav)
    except ValueError:  # the start touches a pad: reported as no equilibrium below
        F = None
    scale = np.hypot(*target)
    for _ in range(60 if F is not None else 0):
        r = F - target
        if np.hypot(*r) < 1e-9 * scale:
            return e, sols
        step = np.linalg.solve(K, r)  # dF/de = -K
        for _ in range(40):
            e_try = e + step
            if np.hypot(*e_try) < 1 + pads.m + 1.0:  # loose bound; contact is caught by the film check
                try:
                    F_try, K_try, s_try = pads.state(*e_try, p_cav)
                except ValueError:
                    step *= 0.5
                    continue
                if np.hypot(*(F_try - target)) < np.hypot(*r):
                    break
            step *= 0.5
        else:
            break
        e, F, K, sols = e_try, F_try, K_try, s_try
    raise InputError(
        where,
        float(round(rad_s_to_rpm(speed), 3)),
        f"a speed at which the pads carry the load (no journal equilibrium found at {rad_s_to_rpm(speed):.6g} "
        f"rpm); raise the "
        "speed range, the viscosity or L, or lower the clearance",
    )
