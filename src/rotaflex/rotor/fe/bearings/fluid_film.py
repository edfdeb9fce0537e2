"""Fluid-film journal bearings (plain 360 deg and tilting-pad): equilibrium and 8 dynamic coefficients.

Conventions (SI): the journal spins about +z (from x towards y); its centre sits at
e = (ex, ey) from the bearing centre; the film force on the journal balances the static
``load`` the journal carries (``reaction = -load``). The linearised film force about the
equilibrium is f = -K [x, y] - C [x', y'], the convention of
:class:`rotaflex.rotor.fe.elements.bearing.BearingElement`.

Dimensionless groups: eccentricity ratio eps = |e| / c; Sommerfeld number
S = mu N L D (R / c)^2 / W with N the speed in rev/s and W = |load| (Raimondi-Boyd);
film forces in units of 6 mu omega R^3 L / c^2, so |Fb| = 1 / (6 pi S);
K = W/c * Kb_W and C = W/(c omega) * Cb_W are the load-normalised coefficients of the
tables of Someya (1989) and Childs (1993).

Two models:
``short``  Ocvirk's short-bearing solution with the half-Sommerfeld (Guembel) film:
           closed-form forces and their exact derivatives (Sommerfeld integrals).
``finite`` the finite-length Reynolds equation by finite differences with the
           Reynolds (Swift-Stieber) cavitation condition, :mod:`.reynolds`.
The plain bearing is rotationally symmetric (no grooves), so the equilibrium is a 1-D root
solve in eps (safeguarded Newton inside a bracket) followed by a rotation that aligns the
film force with the reaction. Tilting pads (``type = "tilting_pad"``, finite model) are in
:mod:`.tilting_pad`.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Literal

import numpy as np

from rotaflex.core.config import param
from rotaflex.core.errors import InputError
from rotaflex.core.units import rad_s_to_rpm, rpm_to_rad_s
from rotaflex.rotor.fe.bearings.reynolds import ReynoldsGrid, solve_film
from rotaflex.rotor.fe.bearings.tilting_pad import PadSet, tilting_pad_equilibrium

EPS_MAX = {"short": 0.995, "finite": 0.97}  #: largest eccentricity ratio the solvers accept
#: thinnest assembled film of a tilting pad [m]: ground journal and pad surfaces are Ra 0.2-0.8 um
MIN_FILM = 1e-6
#: largest Sommerfeld number: the short bearing's eps ~ 0.4 / S (L/D = 0.5), 4e-7 clearances here
MAX_SOMMERFELD = 1e6
#: heaviest lubricant [Pa s]: ISO VG 1500 gear oil is ~1.4 Pa s at 40 C, cold bright stock ~10
MAX_VISCOSITY = 10.0
#: largest coefficient table (speeds) and film grid (nodes of one pad's or the plain film's grid)
MAX_SPEEDS = 10_000
MAX_GRID = 100_000
#: largest film solves per table: speeds x pads x grid nodes (the example: 50 x 1 x 936)
MAX_FILM_WORK = 5e7


def check_film_size(ff: FluidFilm, where: str) -> None:
    """Refuse a table or film grid beyond :data:`MAX_SPEEDS`, :data:`MAX_GRID`, :data:`MAX_FILM_WORK`
    before anything is computed, as every other table is sized (:mod:`rotaflex.core.limits`)."""
    from rotaflex.core.limits import require

    require(f"{where}.n_speeds", ff.n_speeds, ff.n_speeds, MAX_SPEEDS, "table speeds")
    if ff.model == "short":
        return
    grid = ff.n_theta * (ff.n_z + 1)
    key, value = (f"{where}.n_theta", ff.n_theta) if ff.n_theta >= ff.n_z else (f"{where}.n_z", ff.n_z)
    require(key, value, grid, MAX_GRID, "film grid nodes (n_theta x (n_z + 1))")
    pads = ff.pads if ff.type == "tilting_pad" else 1
    work = ff.n_speeds * pads * grid
    if ff.type == "tilting_pad" and pads * grid > MAX_GRID:
        require(f"{where}.pads", ff.pads, pads * grid, MAX_GRID, "film grid nodes over all pads")
    require(f"{where}.n_speeds", ff.n_speeds, work, MAX_FILM_WORK, "film grid nodes x table speeds")


@dataclass(frozen=True)
class FluidFilm:
    """``[bearing.NAME.fluid_film]``: a plain cylindrical or tilting-pad journal bearing (SI units).

    The coefficient table is computed at ``n_speeds`` speeds spread evenly over ``speed_rpm``
    and interpolated linearly in between by the bearing element; an analysis speed outside
    the table is refused.
    """

    diameter: float = param(unit="m", gt=0, doc="journal diameter D")
    length: float = param(unit="m", gt=0, doc="bearing length L")
    clearance: float = param(unit="m", gt=0, doc="radial clearance c (tilting pads: the pad clearance C_p)")
    viscosity: float = param(unit="Pa s", gt=0, doc="dynamic viscosity mu of the lubricant")
    load: tuple[float, float] | Literal["static"] = param(
        unit="N",
        doc='static load [Fx, Fy] the journal puts on the bearing, or "static": from the rotor\'s static analysis',
    )
    speed_rpm: tuple[float, float] = param(unit="rpm", gt=0, doc="speed range of the coefficient table")
    n_speeds: int = param(50, ge=2, doc="speeds in the coefficient table")
    model: Literal["finite", "short"] = param("finite", doc="finite: Reynolds equation (FD); short: Ocvirk")
    cavitation_pressure: float = param(
        0.0, unit="Pa", le=0, doc="cavitation pressure relative to the ambient pressure at the bearing ends"
    )
    n_theta: int = param(72, ge=8, doc="finite model: grid nodes around the circumference")
    n_z: int = param(12, ge=4, doc="finite model: grid intervals along the length (even)")
    type: Literal["plain", "tilting_pad"] = param("plain", doc="plain 360 deg bearing or tilting pads (finite model)")
    pads: int = param(4, ge=2, doc="tilting_pad: number of pads")
    pad_arc_deg: float = param(80.0, unit="deg", gt=0, lt=180, doc="tilting_pad: arc of each pad")
    pivot_offset: float = param(0.5, gt=0, lt=1, doc="tilting_pad: pivot position as a fraction of the arc")
    preload: float = param(0.0, ge=0, lt=1, doc="tilting_pad: m = 1 - C_b / C_p (clearance is C_p)")
    first_pivot_deg: float = param(
        45.0, unit="deg", doc="tilting_pad: angle of the first pivot from +x towards +y (45: load between pads for -y)"
    )

    def validate(self, where: str = "fluid_film") -> None:
        """Raise :class:`InputError` (naming ``where.<key>``) for inconsistent values."""
        if self.n_z % 2:
            raise InputError(f"{where}.n_z", self.n_z, "an even number >= 4")
        if self.clearance >= 0.05 * self.diameter:
            raise InputError(
                f"{where}.clearance", self.clearance, f"a radial clearance < 0.05 D = {0.05 * self.diameter:g} m"
            )
        if self.load != "static" and np.hypot(*self.load) <= 0:
            raise InputError(f"{where}.load", list(self.load), "[Fx, Fy] in N, not both zero")
        if not self.speed_rpm[1] > self.speed_rpm[0]:
            raise InputError(f"{where}.speed_rpm", list(self.speed_rpm), "[start, stop] in rpm with stop > start > 0")
        if self.model == "short" and self.cavitation_pressure != 0:
            raise InputError(f"{where}.cavitation_pressure", self.cavitation_pressure, "0 for the short model")
        if self.type == "tilting_pad" and self.model != "finite":
            raise InputError(f"{where}.model", self.model, '"finite" for tilting pads')
        if self.type == "tilting_pad" and self.pads * self.pad_arc_deg >= 360:
            raise InputError(f"{where}.pad_arc_deg", self.pad_arc_deg, f"pads x arc < 360 deg ({self.pads} pads)")
        if self.type == "tilting_pad" and (1 - self.preload) * self.clearance < MIN_FILM:
            raise InputError(
                f"{where}.preload",
                self.preload,
                f"a preload leaving an assembled clearance (1 - preload) x clearance >= {MIN_FILM:g} m (a thinner film "
                "is below the surface roughness of ground journals and pads, Ra 0.2-0.8 um: no full film)",
            )
        if self.load != "static":
            self.check_sommerfeld(float(np.hypot(*self.load)), where)
        check_film_size(self, where)

    def check_sommerfeld(self, load: float, where: str) -> None:
        """Refuse a journal load so small for the film (Sommerfeld number above :data:`MAX_SOMMERFELD`
        at the top speed) that the journal would sit ~1e-6 clearances from the centre."""
        R, c = self.diameter / 2, self.clearance
        top = rpm_to_rad_s(self.speed_rpm[1])
        S = (
            self.viscosity * top / (2 * np.pi) * self.length * self.diameter * (R / c) ** 2 / load
            if load > 0
            else np.inf
        )
        if not S <= MAX_SOMMERFELD:
            heavy = self.viscosity > MAX_VISCOSITY
            key, value = (
                ("viscosity", self.viscosity) if heavy else ("load", list(self.load) if self.load != "static" else load)
            )
            raise InputError(
                f"{where}.{key}",
                value,
                f"a film with Sommerfeld number mu N L D (R/c)^2 / W <= {MAX_SOMMERFELD:g} at the top speed (here "
                f"{S:.3g}: the journal would sit within ~{0.4 / S:.1g} clearances of the centre, an unloaded film); "
                + (f"lubricating oils have mu <= {MAX_VISCOSITY:g} Pa s" if heavy else "a larger journal load"),
            )

    @property
    def speeds(self) -> np.ndarray:
        """Table speeds [rad/s]."""
        return rpm_to_rad_s(np.linspace(self.speed_rpm[0], self.speed_rpm[1], self.n_speeds))


@dataclass(frozen=True)
class FluidFilmTable:
    """Equilibrium and coefficients of one bearing over speed (arrays over ``speed``).

    Attributes
    ----------
    speed : (n,) [rad/s]
    eccentricity : (n,) eccentricity ratio eps [-]
    attitude : (n,) attitude angle between the load line and the line of centres [rad]
    position : (n, 2) journal centre relative to the bearing centre [m]
    sommerfeld : (n,) S = mu N L D (R/c)^2 / W [-]
    k : (n, 2, 2) stiffness [N/m];  c : (n, 2, 2) damping [N s/m]
    """

    speed: np.ndarray
    eccentricity: np.ndarray
    attitude: np.ndarray
    position: np.ndarray
    sommerfeld: np.ndarray
    k: np.ndarray
    c: np.ndarray

    def to_dataset(self):
        """The table as an ``xarray.Dataset`` over ``speed`` with units (e.g. to save as NetCDF)."""
        import xarray as xr

        data = {
            "speed_rpm": ("speed", rad_s_to_rpm(self.speed), {"units": "rpm"}),
            "eccentricity_ratio": ("speed", self.eccentricity, {"units": "1"}),
            "attitude_angle": ("speed", np.degrees(self.attitude), {"units": "deg"}),
            "journal_x": ("speed", self.position[:, 0], {"units": "m"}),
            "journal_y": ("speed", self.position[:, 1], {"units": "m"}),
            "sommerfeld": ("speed", self.sommerfeld, {"units": "1", "long_name": "mu N L D (R/c)^2 / W"}),
        }
        for i, a in enumerate("xy"):
            for j, b in enumerate("xy"):
                data[f"k{a}{b}"] = ("speed", self.k[:, i, j], {"units": "N/m"})
                data[f"c{a}{b}"] = ("speed", self.c[:, i, j], {"units": "N s/m"})
        return xr.Dataset(data, coords={"speed": ("speed", self.speed, {"units": "rad/s"})})


# -- short bearing (closed form) --------------------------------------------------------------
def short_film(eps: float, l_over_d: float):
    """Dimensionless force, -dF/de and -dF/de' of the short bearing, journal on +x.

    Pressure p = 3 mu / h^3 (z^2 - L^2/4) (omega dh/dtheta + 2 dh/dt) kept where positive
    (half-Sommerfeld film theta in (pi, 2 pi) from the line of centres at equilibrium). The
    integrals I_sc = -2 eps/(1-eps^2)^2, I_ss = pi / (2 (1-eps^2)^1.5) and
    I_cc = pi (1 + 2 eps^2) / (2 (1-eps^2)^2.5) give the radial and tangential forces; the
    moving film boundary does not enter the first-order coefficients since p = 0 there.
    Units as :func:`.reynolds.solve_film`.
    """
    q = 1 - eps * eps
    a = (2 * l_over_d) ** 2 / 12  # (L/R)^2 / 12: the short-bearing factor in these units
    i_sc, i_ss, i_cc = -2 * eps / q**2, np.pi / (2 * q**1.5), np.pi * (1 + 2 * eps * eps) / (2 * q**2.5)
    fr, ft = a * eps * i_sc, a * eps * i_ss
    dfr = -a * 4 * eps * (1 + eps * eps) / q**3  # d(eps I_sc)/d eps
    dft = a * np.pi * (1 + 2 * eps * eps) / (2 * q**2.5)  # d(eps I_ss)/d eps
    # columns: radial (x) and tangential (y) displacement; a tangential step rotates the force
    dF = np.array([[dfr, -ft / eps], [dft, fr / eps]])
    dFv = a * np.array([[-2 * i_cc, -2 * i_sc], [-2 * i_sc, -2 * i_ss]])
    return np.array([fr, ft]), -dF, -dFv


# -- equilibrium ------------------------------------------------------------------------------
class _Film:
    """Dimensionless film of one bearing as a function of eps (journal on +x), with warm starts."""

    def __init__(self, ff: FluidFilm):
        self.ff, self.ld = ff, ff.length / ff.diameter
        self.grid = ReynoldsGrid(self.ld, ff.n_theta, ff.n_z) if ff.model == "finite" else None
        self.active = None
        self.evaluations = 0

    def __call__(self, eps: float, p_cav: float):
        self.evaluations += 1
        if self.grid is None:
            return short_film(eps, self.ld)
        s = solve_film(self.grid, eps, 0.0, p_cav, self.active)
        self.active = s.active
        return s.force, s.k, s.b


def _solve_eps(film: _Film, target: float, p_cav: float, eps0: float, where: str, speed: float):
    """eps with |F(eps)| = target: Newton on log|F| in u = log eps inside a shrinking bracket.

    |F| grows monotonically from 0 (eps = 0, where log|F| ~ log eps: Newton exact) to infinity
    (eps -> 1). Bisection in u is the fallback when a Newton step leaves the bracket. The upper
    end EPS_MAX is evaluated only when an iterate would pass it, and then decides whether a root
    exists.
    """
    top = np.log(EPS_MAX[film.ff.model])
    lo, hi, hi_checked = np.log(1e-12), top, False
    u = np.log(min(max(eps0, 1e-9), EPS_MAX[film.ff.model]))
    for _ in range(100):
        eps = float(np.exp(u))
        F, k, b = film(eps, p_cav)
        mag = np.hypot(*F)
        g = np.log(mag / target)
        if abs(g) < 1e-9:
            return eps, F, k, b
        if g > 0:
            hi = u
        else:
            lo = u
            if u == top:
                raise InputError(
                    where,
                    float(round(rad_s_to_rpm(speed), 3)),
                    f"a speed at which the film carries the load: at {rad_s_to_rpm(speed):.6g} rpm the film "
                    f"carries at most "
                    f"{mag / target * 100:.3g} % of it (eccentricity ratio {eps:g}); raise the speed range, the "
                    "viscosity or L, or lower the clearance",
                )
        dg = -eps * (F @ k[:, 0]) / mag**2  # d log|F| / d log eps, along the line of centres
        step = u - g / dg if dg > 0 else np.nan
        if not step < hi and not hi_checked and hi == top:
            u, hi_checked = top, True  # test the capacity at the largest eccentricity once
            continue
        u = step if lo < step < hi else 0.5 * (lo + hi)
        if hi - lo < 1e-12:
            break
    raise RuntimeError(f"{where}: equilibrium iteration did not converge at {rad_s_to_rpm(speed):.6g} rpm")


def coefficients_from_reaction(ff: FluidFilm, reaction, speeds=None, where: str = "fluid_film") -> FluidFilmTable:
    """Equilibrium and coefficients at ``speeds`` for a given bearing reaction.

    Parameters
    ----------
    ff : FluidFilm
    reaction : array (2,)
        Static force of the film on the journal [N] (the bearing reaction, = -load); the
        static analysis of the rotor supplies it.
    speeds : array or None
        Spin speeds [rad/s] (default: the table speeds of ``ff``).
    where : str
        Dotted config path for error messages.
    """
    ff.validate(where)
    speeds = ff.speeds if speeds is None else np.atleast_1d(np.asarray(speeds, float))
    R, L, c, mu = ff.diameter / 2, ff.length, ff.clearance, ff.viscosity
    reaction = np.asarray(reaction, float)
    W = float(np.hypot(*reaction))
    ff.check_sommerfeld(W, where)  # a load from the static analysis, checked like a given one
    film = _Film(ff)
    n = speeds.size
    shapes = {"eps": n, "att": n, "pos": (n, 2), "S": n, "k": (n, 2, 2), "c": (n, 2, 2)}
    out = {key: np.zeros(shape) for key, shape in shapes.items()}
    if ff.type == "tilting_pad":
        return _tilting_pad_table(ff, reaction, speeds, where, out)
    eps = None
    for m, w in enumerate(speeds):
        if w <= 0:
            raise InputError(f"{where}.speed_rpm", float(round(rad_s_to_rpm(w), 6)), "speeds > 0 (no film at rest)")
        unit = 6 * mu * w * R**3 * L / c**2  # force unit [N]
        p_cav = ff.cavitation_pressure * c**2 / (6 * mu * w * R**2)
        if eps is None:  # first speed: start from the short-bearing equilibrium (closed form, cheap)
            eps = _solve_eps(_Film(replace(ff, model="short")), W / unit, 0.0, 0.5, where, w)[0]
        if m >= 2:  # start from the log eps (log S) line through the last two speeds
            t = np.log(w / speeds[m - 1]) / np.log(speeds[m - 1] / speeds[m - 2])
            eps = out["eps"][m - 1] * (out["eps"][m - 1] / out["eps"][m - 2]) ** t
        eps, F, k, b = _solve_eps(film, W / unit, p_cav, eps, f"{where}.speed_rpm", w)
        # rotate the solution (journal on +x) so that the film force points along the reaction
        psi = np.arctan2(reaction[1], reaction[0]) - np.arctan2(F[1], F[0])
        Q = np.array([[np.cos(psi), -np.sin(psi)], [np.sin(psi), np.cos(psi)]])
        out["k"][m] = unit / c * Q @ k @ Q.T
        out["c"][m] = unit / (c * w) * Q @ b @ Q.T
        out["eps"][m] = eps
        out["pos"][m] = eps * c * Q[:, 0]
        out["att"][m] = np.arccos(np.clip(-(Q[:, 0] @ reaction) / W, -1, 1))  # journal vs load direction
        out["S"][m] = mu * (w / (2 * np.pi)) * L * 2 * R * (R / c) ** 2 / W
    return FluidFilmTable(speeds, out["eps"], out["att"], out["pos"], out["S"], out["k"], out["c"])


def _tilting_pad_table(ff: FluidFilm, reaction, speeds, where, out) -> FluidFilmTable:
    R, L, c, mu = ff.diameter / 2, ff.length, ff.clearance, ff.viscosity
    W = float(np.hypot(*reaction))
    pads = PadSet(
        ff.length / ff.diameter,
        ff.pads,
        np.radians(ff.pad_arc_deg),
        ff.pivot_offset,
        np.radians(ff.first_pivot_deg),
        ff.preload,
        ff.n_theta,
        ff.n_z,
    )
    e = -0.3 * (1 - ff.preload) * reaction / W  # start below the centre, inside every preloaded pad
    for m, w in enumerate(speeds):
        if w <= 0:
            raise InputError(f"{where}.speed_rpm", float(round(rad_s_to_rpm(w), 6)), "speeds > 0 (no film at rest)")
        unit = 6 * mu * w * R**3 * L / c**2
        p_cav = ff.cavitation_pressure * c**2 / (6 * mu * w * R**2)
        e, sols = tilting_pad_equilibrium(pads, reaction / unit, e, p_cav, f"{where}.speed_rpm", w)
        kb, bb = pads.reduced(sols)
        out["k"][m], out["c"][m] = unit / c * kb, unit / (c * w) * bb
        out["eps"][m], out["pos"][m] = np.hypot(*e), e * c
        out["att"][m] = np.arccos(np.clip(-(e @ reaction) / (np.hypot(*e) * W), -1, 1))
        out["S"][m] = mu * (w / (2 * np.pi)) * L * 2 * R * (R / c) ** 2 / W
    return FluidFilmTable(speeds, out["eps"], out["att"], out["pos"], out["S"], out["k"], out["c"])


def fluid_film_table(ff: FluidFilm, where: str = "fluid_film") -> FluidFilmTable:
    """Table over ``ff.speeds`` for the explicit ``ff.load`` (reaction = -load).

    ``load = "static"`` is resolved by the rotor (:func:`.static_load.resolve_static_loads`),
    which replaces it by the converged load before the table is computed.
    """
    if ff.load == "static":
        raise InputError(f"{where}.load", "static", "[Fx, Fy] in N here (the rotor resolves 'static' first)")
    return coefficients_from_reaction(ff, -np.asarray(ff.load, float), None, where)
