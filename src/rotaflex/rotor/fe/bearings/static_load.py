"""Static loads of fluid-film bearings from the rotor's static analysis (``load = "static"``).

A journal bearing's coefficients depend on the load it carries, and on a rotor with more than
two bearings the load each carries depends on the bearing stiffness. The loads are therefore
found by a fixed-point iteration:

    reactions -> coefficients at a reference speed -> static analysis -> reactions,

started from the applied load shared equally, and stopped when no reaction changes by more than
``tol`` times the total applied load (default 1e-10). On a statically determinate rotor (two
bearings) the reactions follow from equilibrium alone, so the first static analysis already
gives them exactly and the second pass only confirms it. The reference speed is the static
analysis's (``[static].speed_rpm``, default the lowest speed every coefficient table covers);
the bearing table is then computed over its own speed range with the converged load.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from rotaflex.core.errors import InputError
from rotaflex.core.units import rad_s_to_rpm, rpm_to_rad_s
from rotaflex.rotor.fe.layout import bearing_path
from rotaflex.rotor.fe.static import STANDARD_GRAVITY, static_analysis


@dataclass(frozen=True)
class StaticLoads:
    """Outcome of :func:`resolve_static_loads`.

    Attributes
    ----------
    rotor : Rotor
        The rotor with each ``load = "static"`` replaced by the converged ``[Fx, Fy]`` [N].
    loads : ndarray (n_bearing, 2)
        Static load of each bearing's journal on the bearing [N] (= -reaction on the rotor).
    iterations : int
        Static analyses performed.
    change : float
        Last change of any reaction relative to the total applied load [-].
    speed : float
        Reference speed of the coefficients in the iteration [rad/s].
    """

    rotor: object
    loads: np.ndarray
    iterations: int
    change: float
    speed: float


def reference_speed(rotor) -> float:
    """Lowest speed [rad/s] every bearing table (fluid-film ranges included) covers; 0 without tables."""
    lows = []
    for b in rotor.bearing:
        if b.fluid_film is not None:
            lows.append(rpm_to_rad_s(b.fluid_film.speed_rpm[0]))
        elif b.speed_rpm is not None:
            lows.append(rpm_to_rad_s(min(b.speed_rpm)))
    return float(max(lows)) if lows else 0.0


def with_loads(rotor, loads: np.ndarray, idx, speed: float | None):
    """Rotor with explicit loads on the bearings ``idx``; with ``speed``, each such table is cut
    down to two speeds starting at ``speed`` (all the static analysis reads)."""
    bearings = list(rotor.bearing)
    for i in idx:
        ff = replace(bearings[i].fluid_film, load=(float(loads[i, 0]), float(loads[i, 1])))
        if speed is not None:
            ff = replace(ff, speed_rpm=(rad_s_to_rpm(speed), rad_s_to_rpm(speed) * (1 + 1e-6)), n_speeds=2)
        bearings[i] = replace(bearings[i], fluid_film=ff)
    return replace(rotor, bearing=tuple(bearings))


def resolve_static_loads(
    rotor,
    *,
    gravity: float | None = None,
    direction=(0.0, -1.0),
    loads=(),
    speed: float | None = None,
    tol: float = 1e-10,
    max_iter: int = 50,
) -> StaticLoads:
    """Replace every ``load = "static"`` of ``rotor`` by its converged static bearing load.

    Parameters
    ----------
    rotor : Rotor
    gravity : float, optional
        Acceleration of gravity [m/s^2] (default standard gravity).
    direction : (float, float)
        Direction of gravity in the x-y plane (default -y).
    loads : sequence of (node, F_x [N], F_y [N])
        Static point forces (``[[static.load]]``).
    speed : float, optional
        Reference speed [rad/s] of the coefficients (default :func:`reference_speed`).
    tol : float
        Convergence: largest reaction change / total applied load.
    max_iter : int
        Static analyses allowed before the iteration is declared not converged.

    Raises
    ------
    InputError
        Naming ``bearing[i].fluid_film.load`` when a bearing carries no load (a film cannot
        hold a journal at zero load) or the iteration does not converge.
    """
    gravity = STANDARD_GRAVITY if gravity is None else gravity
    idx = rotor.static_load_bearings
    speed = reference_speed(rotor) if speed is None else float(speed)
    nb = len(rotor.bearing)
    d = np.asarray(direction, float)
    g = gravity * d / np.hypot(*d)
    applied = rotor.mass * g + np.sum([(fx, fy) for _, fx, fy in loads], axis=0) if loads else rotor.mass * g
    total = float(np.hypot(*applied))
    if total <= 0:
        i = idx[0]
        raise InputError(
            f"{bearing_path(i, rotor.bearing[i])}.fluid_film.load",
            "static",
            "an explicit [Fx, Fy]: no gravity and no load",
        )
    current = np.tile(applied / nb, (nb, 1))  # journal loads on the bearings [N]; shared equally to start
    for b in range(nb):
        if b not in idx and rotor.bearing[b].fluid_film is not None:
            current[b] = rotor.bearing[b].fluid_film.load

    def solve(cur):
        trial = with_loads(rotor, cur[0], idx, speed)
        s = static_analysis(trial, gravity=gravity, direction=direction, loads=loads, speed=speed)
        return {0: -s.reactions}, {0: total}

    paths = {0: lambda i: f"{bearing_path(i, rotor.bearing[i])}.fluid_film.load"}
    cur, it, change = iterate_journal_loads(solve, {0: current}, {0: idx}, paths, speed, tol, max_iter)
    return StaticLoads(with_loads(rotor, cur[0], idx, None), cur[0], it, change, speed)


def iterate_journal_loads(solve, current: dict, film: dict, paths: dict, speed: float, tol: float, max_iter: int):
    """The fixed point of the journal loads ``load = "static"`` (one rotor or a machine's).

    Parameters
    ----------
    solve : callable
        ``solve(current) -> (loads, scale)``: the static state with the journal loads
        ``current`` ({group: (n_bearing, 2) [N]}) gives each group's new journal loads (minus
        the reactions) and its load scale [N] (the convergence and "unloaded" reference).
    current : dict
        Starting journal loads per group (a rotor); updated in place.
    film : dict
        Indices of each group's ``load = "static"`` bearings.
    paths : dict
        ``paths[group](i)``: the config key of bearing i's load, for the errors.
    speed : float
        Reference speed of the coefficients [rad/s] (for the error message).
    tol, max_iter : float, int
        Convergence (largest change / the group's scale) and static solves allowed.

    Returns
    -------
    (current, iterations, change)

    Raises
    ------
    InputError
        Naming the bearing's load key when the static state leaves it unloaded (a film cannot
        hold an unloaded journal) or the iteration does not converge.
    """
    change, worst = np.inf, None
    for it in range(1, max_iter + 1):
        new, scale = solve(current)
        change = 0.0
        for g, idx in film.items():
            for i in idx:
                if np.hypot(*new[g][i]) <= 1e-9 * scale[g]:
                    raise InputError(
                        paths[g](i),
                        "static",
                        f"an explicit [Fx, Fy]: the static analysis leaves this bearing unloaded "
                        f"({np.hypot(*new[g][i]):.3g} N of {scale[g]:.6g} N), "
                        "and a film cannot hold an unloaded journal",
                    )
            diff = np.abs(new[g][idx] - current[g][idx]).max(axis=1) / scale[g]
            if worst is None or diff.max() > change:
                change, worst = float(diff.max()), (g, idx[int(np.argmax(diff))])
            current[g][idx] = new[g][idx]
        if change <= tol:
            return current, it, change
    g, i = worst
    raise InputError(
        paths[g](i),
        "static",
        f"an explicit [Fx, Fy]: the static-load iteration (reactions -> coefficients at "
        f"{rad_s_to_rpm(speed):.6g} rpm -> "
        f"static analysis) did not converge in {max_iter} passes (last change {change:.3g} of the total load "
        f"at this bearing, tolerance {tol:g})",
    )
