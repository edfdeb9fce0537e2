"""Linear bearing or seal: 2x2 stiffness, damping and mass, constant or tabulated over spin speed
and whirl frequency.

Tables are interpolated per coefficient along each axis in turn (whirl frequency first, then spin
speed): ``"linear"`` (piecewise linear, the default) or ``"pchip"`` (the monotone piecewise cubic
Hermite interpolant of Fritsch & Carlson (1980) with the derivative rule of Fritsch & Butland
(1984), as ``scipy.interpolate.PchipInterpolator``; tested against it). Outside a table the
``extrapolation`` policy applies: ``"refuse"`` (the default: the assembly reports every table
concerned), ``"hold"`` (the end values) or ``"linear"`` (the straight line of the end slope: the
last interval's secant for linear tables, the end derivative for pchip).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass, field

import numpy as np

from rotaflex.core.errors import InputError
from rotaflex.core.units import rad_s_to_rpm, rpm_to_rad_s
from rotaflex.rotor.fe.bearings.fluid_film import fluid_film_table

COEFFICIENTS = ("kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy")
MASS_COEFFICIENTS = ("mxx", "mxy", "myx", "myy")
INTERPOLATIONS = ("linear", "pchip")
EXTRAPOLATIONS = ("refuse", "hold", "linear")
#: plausibility bounds of the coefficients: far beyond any support of a real machine
MAX_BEARING = {"k": 1e15, "c": 1e12, "m": 1e9}  # N/m, N s/m, kg
#: a requested point this close to a table end (relative, plus 1e-12 absolute) is inside the table
RANGE_TOL = 1e-12


def flat(v) -> list[float]:
    """The numbers of a coefficient as typed (a number, a list, or rows of lists)."""
    rows = v if isinstance(v, (tuple, list)) else (v,)
    return [float(y) for x in rows for y in (x if isinstance(x, (tuple, list)) else (x,))]


def pchip_slopes(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Node derivatives (n, ...) of the monotone cubic interpolant of ``y`` (n, ...) over ``x`` (n,).

    Interior: zero where the neighbouring secants differ in sign or one is zero, else their
    weighted harmonic mean (w1 = 2 h_k + h_(k-1), w2 = h_k + 2 h_(k-1)); ends: the three-point
    non-centred formula, set to zero if its sign differs from the end secant's and limited to
    three times the end secant when the secants change sign (Fritsch & Butland 1984).
    """
    h = np.diff(x).reshape((-1,) + (1,) * (y.ndim - 1))
    m = np.diff(y, axis=0) / h
    if x.size == 2:
        return np.concatenate([m, m])
    d = np.zeros_like(y)
    w1, w2 = 2 * h[1:] + h[:-1], h[1:] + 2 * h[:-1]
    flat = (np.sign(m[1:]) != np.sign(m[:-1])) | (m[1:] == 0) | (m[:-1] == 0)
    with np.errstate(divide="ignore", invalid="ignore"):
        hmean = (w1 / m[:-1] + w2 / m[1:]) / (w1 + w2)
        d[1:-1] = np.where(flat, 0.0, 1.0 / hmean)
    for end, (h0, h1, m0, m1) in ((0, (h[0], h[1], m[0], m[1])), (-1, (h[-1], h[-2], m[-1], m[-2]))):
        e = ((2 * h0 + h1) * m0 - h0 * m1) / (h0 + h1)
        e = np.where(np.sign(e) != np.sign(m0), 0.0, e)
        e = np.where((np.sign(m0) != np.sign(m1)) & (np.abs(e) > np.abs(3 * m0)), 3 * m0, e)
        d[end] = e
    return d


def interpolate(x: np.ndarray, y: np.ndarray, xi: np.ndarray, method: str, extrapolation: str) -> np.ndarray:
    """Values (m, ...) of the table ``y`` (n, ...) over increasing ``x`` (n,) at ``xi`` (m,).

    ``method``: ``"linear"`` or ``"pchip"``; ``extrapolation``: ``"hold"`` or ``"linear"``
    outside [x_0, x_(n-1)] (``"refuse"`` is checked by the caller; treated as ``"hold"`` here).
    """
    xi = np.asarray(xi, float)
    if x.size == 1:
        return np.broadcast_to(y[0], xi.shape + y.shape[1:]).copy()
    xc = np.clip(xi, x[0], x[-1])
    k = np.clip(np.searchsorted(x, xc, side="right") - 1, 0, x.size - 2)
    h = (x[k + 1] - x[k]).reshape((-1,) + (1,) * (y.ndim - 1))
    t = ((xc - x[k]).reshape(h.shape)) / h
    y0, y1 = y[k], y[k + 1]
    if method == "pchip":
        d = pchip_slopes(x, y)
        d0, d1 = d[k], d[k + 1]
        out = (
            (2 * t**3 - 3 * t**2 + 1) * y0
            + (t**3 - 2 * t**2 + t) * h * d0
            + (-2 * t**3 + 3 * t**2) * y1
            + (t**3 - t**2) * h * d1
        )
        slope_lo, slope_hi = d[0], d[-1]
    else:
        # np.interp's arithmetic (slope times offset, exact at the nodes), so results match it bitwise
        out = (y1 - y0) / h * (xc - x[k]).reshape(h.shape) + y0
        at_node = (xc == x[k]).reshape(h.shape)
        out = np.where(at_node, y0, np.where((xc >= x[-1]).reshape(h.shape), y[-1], out))
        slope_lo = (y[1] - y[0]) / (x[1] - x[0])
        slope_hi = (y[-1] - y[-2]) / (x[-1] - x[-2])
    if extrapolation == "linear":
        shape = (-1,) + (1,) * (y.ndim - 1)
        below, above = np.minimum(xi - x[0], 0.0).reshape(shape), np.maximum(xi - x[-1], 0.0).reshape(shape)
        out = out + below * slope_lo + above * slope_hi
    return out


def outside(x: np.ndarray | None, xi: np.ndarray) -> np.ndarray:
    """True where ``xi`` lies outside the table abscissae ``x`` (never for no table)."""
    xi = np.asarray(xi, float)
    if x is None or x.size == 1:
        return np.zeros(xi.shape, bool)
    lo, hi = x[0], x[-1]
    return (xi < lo * (1 - RANGE_TOL) - RANGE_TOL) | (xi > hi * (1 + RANGE_TOL) + RANGE_TOL)


class ElementMatrices(ABC):
    """The element contract's matrices at one speed, from :meth:`coefficients` and :meth:`mass`
    (docs/architecture.md): what every bearing kind shares."""

    @abstractmethod
    def coefficients(self, speed, whirl=None) -> tuple[np.ndarray, np.ndarray]:
        """Stiffness and damping (n, 2, 2) [N/m, N s/m] at spin speeds ``speed`` [rad/s] (n,)
        and whirl frequencies ``whirl`` [rad/s] (None: synchronous)."""

    @abstractmethod
    def mass(self, speed) -> np.ndarray:
        """Mass coefficients (n, 2, 2) [kg] at the spin speeds ``speed`` [rad/s]."""

    def outputs(self, speed) -> dict:
        """The kind's own results over speed [dict of xarray.DataArray]: none."""
        return {}

    @property
    def speed_independent(self) -> bool:
        """True when the matrices are the same at every spin speed (one assembly serves all)."""
        return False

    def K(self, speed: float = 0.0) -> np.ndarray:
        """Stiffness (2, 2) [N/m] at ``speed`` [rad/s] (synchronous whirl)."""
        return self.coefficients(speed)[0][0]

    def C(self, speed: float = 0.0) -> np.ndarray:
        """Damping (2, 2) [N s/m] at ``speed`` [rad/s] (synchronous whirl)."""
        return self.coefficients(speed)[1][0]

    def M(self, speed: float = 0.0) -> np.ndarray:
        """Mass (2, 2) [kg] on the translations at ``speed`` [rad/s]."""
        return self.mass(speed)[0]

    def G(self) -> np.ndarray:
        """Gyroscopic (2, 2): zero."""
        return np.zeros((2, 2))


@dataclass(frozen=True)
class BearingElement(ElementMatrices):
    """Bearing between a node's translations and ground (or another node's translations).

    The force on the rotor is f = -K [x, y] - C [x', y'] - M [x'', y''] with
    K = [[kxx, kxy], [kyx, kyy]] and C, M likewise; K and C may depend on the spin speed Omega
    and on the whirl frequency omega (``frequency_dependent``).

    Parameters
    ----------
    k, c : ndarray (ns, 2, 2), or (ns, nw, 2, 2) with a whirl table
        Stiffness [N/m] and damping [N s/m] at each tabulated speed (and whirl frequency).
    speeds : ndarray (ns,) or None
        Spin speeds of the table [rad/s]; None for coefficients independent of speed (ns = 1).
    name : str
        Dotted config path (``bearing.left``), used in error messages.
    m : ndarray (2, 2)
        Mass coefficients [kg] (constant).
    whirls : ndarray (nw,) or None
        Whirl frequencies of the table [rad/s]; None: independent of whirl frequency.
    interpolation : {"linear", "pchip"}
    extrapolation : {"refuse", "hold", "linear"}
    """

    k: np.ndarray
    c: np.ndarray
    speeds: np.ndarray | None = None
    name: str = "bearing"
    table: object = field(default=None, compare=False, repr=False)  #: FluidFilmTable of a fluid-film bearing
    m: np.ndarray = field(default_factory=lambda: np.zeros((2, 2)))
    whirls: np.ndarray | None = None
    interpolation: str = "linear"
    extrapolation: str = "refuse"

    @classmethod
    def constant(
        cls, kxx=0.0, kyy=0.0, kxy=0.0, kyx=0.0, cxx=0.0, cyy=0.0, cxy=0.0, cyx=0.0, name: str = "bearing"
    ) -> BearingElement:
        """Speed-independent coefficients [N/m, N s/m]."""
        return cls(np.array([[[kxx, kxy], [kyx, kyy]]], float), np.array([[[cxx, cxy], [cyx, cyy]]], float), None, name)

    @property
    def speed_independent(self) -> bool:
        """True for a single-row table (no speeds)."""
        return self.speeds is None

    @property
    def static_load_dependent(self) -> bool:
        """A fluid-film bearing's coefficients depend on its static load."""
        return self.table is not None

    @property
    def frequency_dependent(self) -> bool:
        """True when the coefficients depend on the whirl frequency (a table over it)."""
        return self.whirls is not None

    def out_of_range(self, speed, whirl=None) -> list[str]:
        """Descriptions of the tables ``speed`` (and ``whirl``) [rad/s] leave under ``extrapolation = "refuse"``."""
        if self.extrapolation != "refuse":
            return []
        out = []
        if np.any(outside(self.speeds, speed)):
            out.append(f"{self.name} {rad_s_to_rpm(self.speeds[0]):g}..{rad_s_to_rpm(self.speeds[-1]):g} rpm")
        if whirl is not None and np.any(outside(self.whirls, whirl)):
            hz = 1 / (2 * np.pi)
            out.append(f"{self.name}.whirl_hz {self.whirls[0] * hz:g}..{self.whirls[-1] * hz:g} Hz")
        return out

    def coefficients(self, speed, whirl=None) -> tuple[np.ndarray, np.ndarray]:
        """Stiffness and damping (n, 2, 2) at spin speeds ``speed`` [rad/s] (n,) and whirl
        frequencies ``whirl`` [rad/s] (n,; None: synchronous, ``whirl = speed``).

        Raises :class:`InputError` naming this table when a point lies outside it under
        ``extrapolation = "refuse"`` (the rotor assembly checks all tables first and names the
        analysis key instead).
        """
        speed = np.atleast_1d(np.asarray(speed, float))
        whirl = speed if whirl is None else np.broadcast_to(np.asarray(whirl, float), speed.shape)
        bad = self.out_of_range(speed, whirl if self.frequency_dependent else None)
        if bad:
            if "whirl_hz" in bad[-1]:  # a whirl frequency of a mode is outside: the table must grow
                key, value = (
                    f"{self.name}.whirl_hz",
                    round(float(whirl[outside(self.whirls, whirl)][0]) / (2 * np.pi), 6),
                )
            else:
                key, value = (
                    f"{self.name}.speed_rpm",
                    round(rad_s_to_rpm(float(speed[outside(self.speeds, speed)][0])), 6),
                )
            raise InputError(key, value, f"requested points within the coefficient table ({'; '.join(bad)})")
        k, c = self.k, self.c
        if self.frequency_dependent:
            k, c = self._along_whirl(k, whirl), self._along_whirl(c, whirl)  # (ns, n, 2, 2)
            if self.speeds is None:
                return k[0], c[0]
            pick = np.arange(speed.size)
            return self._along_speed(k, speed)[pick, pick], self._along_speed(c, speed)[pick, pick]
        if self.speeds is None:
            return (
                np.broadcast_to(k[0], (speed.size, 2, 2)).copy(),
                np.broadcast_to(c[0], (speed.size, 2, 2)).copy(),
            )
        return self._along_speed(k, speed), self._along_speed(c, speed)

    def _along_speed(self, y: np.ndarray, speed: np.ndarray) -> np.ndarray:
        return interpolate(self.speeds, y, speed, self.interpolation, self.extrapolation)

    def _along_whirl(self, y: np.ndarray, whirl: np.ndarray) -> np.ndarray:
        """(ns, nw, 2, 2) -> (ns, n, 2, 2) at the whirl frequencies ``whirl`` (n,)."""
        moved = np.moveaxis(y, 1, 0)  # (nw, ns, 2, 2)
        return np.moveaxis(interpolate(self.whirls, moved, whirl, self.interpolation, self.extrapolation), 0, 1)

    def mass(self, speed=0.0) -> np.ndarray:
        """Mass coefficients (n, 2, 2) [kg] at the spin speeds ``speed`` [rad/s] (constant)."""
        speed = np.atleast_1d(np.asarray(speed, float))
        return np.broadcast_to(self.m, (speed.size, 2, 2)).copy()

    @classmethod
    def from_table(cls, b, where: str = "bearing") -> BearingElement:
        """The element of a linear bearing: coefficients constant or tabulated over speed and/or whirl
        frequency, validated (shapes, strictly increasing abscissae, finite magnitudes; any sign).

        ``b`` is a :class:`rotaflex.rotor.fe.model.Bearing` without ``fluid_film``; ``where`` its config path.
        """
        ns = 1 if b.speed_rpm is None else len(b.speed_rpm)
        nw = 1 if b.whirl_hz is None else len(b.whirl_hz)
        for key, axis in (("speed_rpm", b.speed_rpm), ("whirl_hz", b.whirl_hz)):
            if axis is not None and np.any(np.diff(axis) <= 0):
                raise InputError(f"{where}.{key}", list(axis), "strictly increasing values")
        if b.speed_rpm is not None and b.whirl_hz is not None:
            shape, text = (ns, nw), f"a number or {ns} rows (one per speed_rpm) of {nw} values (one per whirl_hz)"
        elif b.whirl_hz is not None:
            shape, text = (nw,), f"a number or {nw} values (one per whirl_hz)"
        else:
            shape, text = (ns,), f"a number or {ns} values (one per speed_rpm)"
        tab = {}
        for k in COEFFICIENTS:
            v = getattr(b, k)
            try:
                arr = np.asarray(v, float)
            except ValueError:  # ragged rows
                raise InputError(f"{where}.{k}", v, text) from None
            if arr.size == 1:
                arr = arr.reshape(())
            elif arr.shape != shape:
                if b.speed_rpm is None and b.whirl_hz is None:
                    raise InputError(f"{where}.speed_rpm", "<missing>", "a list of speeds for tabulated coefficients")
                raise InputError(f"{where}.{k}", list(v), text)
            if not np.all(np.abs(arr) <= MAX_BEARING[k[0]]):
                unit = "N/m" if k[0] == "k" else "N s/m"
                raise InputError(f"{where}.{k}", flat(v), f"finite values of magnitude <= {MAX_BEARING[k[0]]:g} {unit}")
            tab[k] = (
                np.broadcast_to(arr, shape).reshape(ns, nw) if b.whirl_hz is not None else np.broadcast_to(arr, (ns,))
            )
        kk = np.stack([np.stack([tab["kxx"], tab["kxy"]], -1), np.stack([tab["kyx"], tab["kyy"]], -1)], -2)
        cc = np.stack([np.stack([tab["cxx"], tab["cxy"]], -1), np.stack([tab["cyx"], tab["cyy"]], -1)], -2)
        return cls(
            kk,
            cc,
            None if b.speed_rpm is None else rpm_to_rad_s(np.asarray(b.speed_rpm, float)),
            where,
            m=np.array([[b.mxx, b.mxy], [b.myx, b.myy]], float),
            whirls=None if b.whirl_hz is None else np.asarray(b.whirl_hz, float) * 2 * np.pi,
            interpolation=b.interpolation,
            extrapolation=b.extrapolation,
        )

    @classmethod
    def from_fluid_film(cls, bearing, where: str = "bearing") -> BearingElement:
        """Speed-tabulated element of a ``[bearing.NAME.fluid_film]`` table (coefficient keys refused).

        ``bearing`` is a :class:`rotaflex.rotor.fe.model.Bearing` whose ``fluid_film`` is set.
        """
        for key in COEFFICIENTS:
            if any(np.ravel(getattr(bearing, key))):
                raise InputError(f"{where}.{key}", list(getattr(bearing, key)), "no coefficients with fluid_film")
        if bearing.speed_rpm is not None:
            raise InputError(f"{where}.speed_rpm", list(bearing.speed_rpm), "fluid_film.speed_rpm instead")
        table = fluid_film_table(bearing.fluid_film, f"{where}.fluid_film")
        m = np.array([[bearing.mxx, bearing.mxy], [bearing.myx, bearing.myy]], float)
        return cls(
            table.k,
            table.c,
            table.speed,
            f"{where}.fluid_film",
            table,
            m=m,
            interpolation=bearing.interpolation,
            extrapolation=bearing.extrapolation,
        )


class ComputedBearing(ElementMatrices):
    """Base of the bearing kinds whose coefficients are computed at any speed (seals, magnetic
    bearings): the element contract of docs/architecture.md with no speed table.

    Subclasses set ``name`` and implement :meth:`coefficients`; :meth:`mass` is zero unless overridden.
    """

    speeds = None  #: no table: any speed >= 0 is accepted
    whirls = None  #: no whirl-frequency table: any whirl frequency is accepted
    table = None  #: no fluid-film table
    frequency_dependent = False
    static_load_dependent = False
    name = "bearing"

    def out_of_range(self, speed, whirl=None) -> list[str]:
        """No table to leave: computed at any speed and whirl frequency."""
        return []

    def mass(self, speed) -> np.ndarray:
        """Added mass (n_speed, 2, 2) [kg]: zero."""
        return np.zeros((np.atleast_1d(speed).size, 2, 2))
