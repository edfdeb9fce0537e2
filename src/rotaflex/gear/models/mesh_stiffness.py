"""The gear mesh as other models see it: mesh stiffness and transmission error over a mesh cycle.

This is the gear package's public interface for machine models (geared rotor systems, the
torsional chain, sweeps). Everything a model outside ``rotaflex.gear`` needs from a gear pair's
mesh comes from :func:`gear_mesh`, which returns a :class:`GearMesh`:

* ``table`` (:class:`MeshTable`): mesh stiffness ``k(phi)`` [N/m] along the line of action and
  unloaded transmission error ``e(phi)`` [m] at phases ``phi = j/n`` of one mesh cycle, where
  ``phi = z_1 theta_1 / (2 pi)`` (pinion angle in mesh cycles, 0 = a pair enters contact);
  ``e > 0`` means the unloaded flanks overlap (more mesh deflection). The mesh deflection is
  ``delta = r_b1 theta_1 - r_b2 theta_2 + (lateral motion of the gear centres along the line of
  action) - e(phi)`` and the mesh force ``F = k(phi) delta + c delta'`` while ``delta > 0``.
* the pair's geometry a machine model needs: teeth, base radii, working pressure angle, centre
  distance, contact ratio, face width, gear blank masses and inertias, which gear drives.

Sources of the table (``source``), each named once here:

``"loaded_te"`` (default)
    FE teeth of both gears along the line of action (:mod:`~.loaded_te`), loaded at the
    operating torque: the loaded stiffness ``sum 1/q`` of the pairs in contact, and the unloaded
    TE that makes the lumped model's static deflection the loaded TE (``gear static``'s numbers).
``"static_fe"``
    The plane-stress FE mesh stiffness of :func:`~.tooth_analysis.mesh_stiffness` (identical materials).
``"iso6336"``
    ISO 6336-1 method B mesh stiffness ``c_gamma_alpha b`` as a constant (no variation, no TE).
``"harmonic"``
    A mean stiffness with cosine harmonics and a TE with sine harmonics, given by the user.
``"contact_pattern"``
    Analytic single/double contact: ``k_pair`` on each pair in contact.

SI throughout; angles in radians.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Literal

import numpy as np

from rotaflex.core.errors import InputError

if TYPE_CHECKING:  # the FE pair data is only needed by the FE sources (scipy.interpolate is slow to import)
    from rotaflex.gear.static.loaded_te import PairLine

__all__ = [
    "SOURCES",
    "GearMesh",
    "MeshTable",
    "contact_pattern_mesh",
    "gear_mesh",
    "harmonic_mesh",
    "loaded_mesh_table",
    "sliced_mesh_table",
    "mesh_table_from_static",
]

#: names of the mesh-table sources :func:`gear_mesh` accepts
SOURCES = ("loaded_te", "static_fe", "iso6336", "harmonic", "contact_pattern")

#: default mesh damping ratio zeta of ``c_m = 2 zeta sqrt(k_mean m_red)``: an engineering default
#: in the range commonly assumed in lumped spur-gear models, not a measured value
#: (docs/gear-steady-state.md); the one default of every gear and machine model
DEFAULT_DAMPING_RATIO = 0.07


def mesh_damping(k_mean: float, inertia, base_radius, damping_ratio: float = DEFAULT_DAMPING_RATIO) -> float:
    """Mesh damping ``c_m = 2 zeta sqrt(k_mean m_red)`` [N s/m] along the line of action.

    ``m_red = J1 J2 / (J1 r_b2^2 + J2 r_b1^2)`` [kg] from the gears' own inertias ``(J1, J2)``
    [kg m^2] and base radii ``(r_b1, r_b2)`` [m]; ``k_mean`` [N/m].

    Examples
    --------
    >>> round(mesh_damping(1e8, (1e-3, 1e-3), (0.05, 0.05)), 6)  # m_red = 0.2 kg
    626.099034
    """
    (j1, j2), (r1, r2) = inertia, base_radius
    m_red = j1 * j2 / (j1 * r2**2 + j2 * r1**2)
    return 2.0 * damping_ratio * math.sqrt(k_mean * m_red)


@dataclass(frozen=True)
class MeshTable:
    """Mesh stiffness and unloaded transmission error over one mesh cycle.

    Attributes
    ----------
    stiffness : ndarray (n,)
        k at phases j/n, j = 0 ... n-1 [N/m] (> 0).
    unloaded_te : ndarray (n,)
        e at the same phases [m]; > 0 means the unloaded flanks overlap (more deflection).
    interpolation : {"cubic", "linear"}
        Periodic cubic spline (smooth tables) or piecewise linear (tables with jumps, e.g. the
        step at the start of two-pair contact, without overshoot).
    static_force : float
        F_0 [N] of a table whose unloaded TE is built as ``e = TE_loaded - F_0 / k``
        (:func:`loaded_mesh_table`); 0 when ``e`` is the flanks' geometry. Its ``-F_0 / k`` part
        steps where ``k`` does, which is no geometry: the steady K_v leaves out the damper's
        answer to that part's rate (docs/gear-steady-state.md).
    """

    stiffness: np.ndarray
    unloaded_te: np.ndarray
    interpolation: Literal["cubic", "linear"] = "cubic"
    static_force: float = 0.0

    def __post_init__(self):
        k = np.asarray(self.stiffness, dtype=float)
        e = np.asarray(self.unloaded_te, dtype=float)
        if k.ndim != 1 or len(k) < 4 or np.any(~np.isfinite(k)) or np.any(k <= 0):
            raise InputError("mesh.stiffness", "array", "a 1-D table of >= 4 values > 0")
        if e.shape != k.shape or np.any(~np.isfinite(e)):
            raise InputError("mesh.unloaded_te", "array", f"{len(k)} finite values")
        if self.interpolation not in ("cubic", "linear"):
            raise InputError("mesh.interpolation", self.interpolation, "'cubic' or 'linear'")
        object.__setattr__(self, "stiffness", k)
        object.__setattr__(self, "unloaded_te", e)

    @property
    def mean_stiffness(self) -> float:
        """One-cycle mean of the interpolated stiffness [N/m] (= mean of the samples for both
        the linear and the uniform periodic cubic interpolant)."""
        return float(np.mean(self.stiffness))

    def coefficients(self, y: np.ndarray) -> np.ndarray:
        """Piecewise-cubic coefficients (4, n) in the local cell variable u in [0, 1)."""
        n = len(y)
        if self.interpolation == "linear":
            return np.stack([y, np.roll(y, -1) - y, np.zeros(n), np.zeros(n)])
        from scipy.interpolate import CubicSpline

        cs = CubicSpline(np.arange(n + 1) / n, np.append(y, y[0]), bc_type="periodic")
        h = 1.0 / n
        return np.stack([cs.c[3], cs.c[2] * h, cs.c[1] * h**2, cs.c[0] * h**3])

    def evaluate(self, phase) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """k, dk/dphi, e, de/dphi at ``phase`` [mesh cycles] (NumPy, for post-processing)."""
        phase = np.asarray(phase, dtype=float)
        out = []
        for y in (self.stiffness, self.unloaded_te):
            c = self.coefficients(y)
            n = c.shape[1]
            x = (phase - np.floor(phase)) * n
            j = np.minimum(x.astype(int), n - 1)
            u = x - j
            out.append(c[0, j] + u * (c[1, j] + u * (c[2, j] + u * c[3, j])))
            out.append(n * (c[1, j] + u * (2 * c[2, j] + 3 * u * c[3, j])))
        return out[0], out[1], out[2], out[3]


def harmonic_mesh(k_mean: float, k_harmonics=(), te_harmonics=(), n: int = 256) -> MeshTable:
    """Smooth table ``k = k_mean + sum a_h cos(2 pi h phi)``, ``e = sum e_h sin(2 pi h phi)``.

    Parameters
    ----------
    k_mean : float
        Mean mesh stiffness [N/m].
    k_harmonics, te_harmonics : sequence of float
        Amplitudes of harmonic h = 1, 2, ... [N/m] and [m].
    n : int
        Table points per cycle.
    """
    ph = np.arange(n) / n
    k = np.full(n, float(k_mean))
    e = np.zeros(n)
    for h, a in enumerate(k_harmonics, start=1):
        k += a * np.cos(2 * np.pi * h * ph)
    for h, a in enumerate(te_harmonics, start=1):
        e += a * np.sin(2 * np.pi * h * ph)
    return MeshTable(k, e, "cubic")


def contact_pattern_mesh(k_pair: float, contact_ratio: float, n: int = 400, unloaded_te: float = 0.0) -> MeshTable:
    """Analytic single/double contact mesh: each pair has stiffness ``k_pair`` over its contact.

    The cycle starts when a pair enters: two pairs for ``0 <= phi < eps - 1``, one after.
    ``unloaded_te`` adds a constant-amplitude triangular TE of that peak-to-peak [m] (as a
    stand-in for profile errors or relief), zero mean, peaking in the single-pair zone.
    Linear interpolation (the stiffness steps are spread over one table cell, 1/n cycle).
    """
    if not 1.0 < contact_ratio < 2.0:
        raise InputError("contact_ratio", contact_ratio, "1 < eps < 2")
    ph = np.arange(n) / n
    k = np.where(ph < contact_ratio - 1.0, 2.0 * k_pair, k_pair)
    tri = 1.0 - 2.0 * np.abs(ph - 0.5)
    e = unloaded_te * (tri - tri.mean())
    return MeshTable(k, e, "linear")


def mesh_table_from_static(ms, teeth: int, n: int = 400, unloaded_te=None) -> MeshTable:
    """One-cycle table from :func:`rotaflex.gear.static.tooth_analysis.mesh_stiffness` output.

    Resamples ``ms.mesh_stiffness`` (over gear A's angle from the start of one pair's contact)
    on the mesh cycle ``2 pi / teeth``; ``unloaded_te`` (optional, same angles) [m].
    """
    cyc = 2 * np.pi / teeth
    ph = np.arange(n) / n * cyc
    k = np.interp(ph, ms.angle, ms.mesh_stiffness)
    e = np.zeros(n) if unloaded_te is None else np.interp(ph, ms.angle, unloaded_te)
    return MeshTable(k, e, "linear")


def loaded_mesh_table(line: PairLine, force: float, n: int = 400):
    """Lumped mesh table of the pair at ``force`` [N]: loaded stiffness ``k(phi)`` (the loaded
    pairs' ``sum 1/q``) and the unloaded TE ``e = TE_loaded - force / k`` that makes the lumped
    model's static deflection the loaded TE of :func:`~.loaded_te.loaded_te` at this load
    (exact without relief; with relief, a linearisation about the design load)."""
    from rotaflex.gear.static.loaded_te import loaded_te

    s = line.s_start + np.arange(n) / n * line.base_pitch
    lt = loaded_te(line, s, force)
    return MeshTable(lt["stiffness"], lt["te"] - force / lt["stiffness"], "linear", float(force))


def sliced_mesh_table(line: PairLine, face, force: float, n: int = 400):
    """Lumped mesh table of a helical or lead-modified pair at ``force`` [N] (transverse, along
    the line of action): the sliced face's tangent stiffness ``k(phi)`` and the unloaded TE
    ``e = TE_loaded - force / k`` (:func:`rotaflex.gear.static.helical.sliced_te`; ``face`` its
    :class:`~rotaflex.gear.static.helical.FaceModel`), as :func:`loaded_mesh_table` for spur pairs."""
    from rotaflex.gear.static.helical import sliced_te

    s = line.s_start + np.arange(n) / n * line.base_pitch
    if force != line.force:
        import dataclasses

        line = dataclasses.replace(line, force=force)
    lt = sliced_te(line, face, s)
    return MeshTable(lt["stiffness"], lt["te"] - force / lt["stiffness"], "linear")


# ------------------------------------------------------------------------ the pair's mesh
@dataclass(frozen=True)
class GearMesh:
    """A gear pair's mesh as a machine model sees it (SI; gear 1 = pinion, gear 2 = wheel).

    Attributes
    ----------
    table : MeshTable
        ``k(phi)`` [N/m] and unloaded TE ``e(phi)`` [m] over one mesh cycle.
    teeth : (int, int)
        Tooth counts (z_1, z_2).
    base_radius : (float, float)
        Base radii r_b1, r_b2 [m].
    pressure_angle : float
        Working (operating) transverse pressure angle alpha' [rad].
    center_distance : float
        Working centre distance a' [m].
    contact_ratio : float
        Transverse contact ratio eps_alpha at a' [1].
    face_width : float
        Common face width b [m].
    mass : (float | None, float | None)
        Gear blank masses [kg] (None: not given by the drawing).
    inertia : (float, float)
        Polar moments of inertia of the gear blanks [kg m^2].
    driver : {"pinion", "wheel"}
        Which gear drives (its drive flank is the loaded one).
    torque : float
        Pinion torque the table was computed at [N m].
    source : str
        One of :data:`SOURCES`.
    """

    table: MeshTable
    teeth: tuple[int, int]
    base_radius: tuple[float, float]
    pressure_angle: float
    center_distance: float
    contact_ratio: float
    face_width: float
    mass: tuple[float | None, float | None]
    inertia: tuple[float, float]
    driver: Literal["pinion", "wheel"]
    torque: float
    source: str

    @property
    def mean_stiffness(self) -> float:
        """Mean mesh stiffness over one mesh cycle [N/m]."""
        return self.table.mean_stiffness

    @property
    def ratio(self) -> float:
        """Gear ratio z_2 / z_1 (wheel speed = pinion speed / ratio)."""
        return self.teeth[1] / self.teeth[0]

    def mesh_frequency(self, pinion_speed: float) -> float:
        """Mesh frequency [Hz] at a pinion speed [rad/s]: ``z_1 Omega_1 / (2 pi)``."""
        return self.teeth[0] * pinion_speed / (2.0 * math.pi)


def gear_mesh(
    pair,
    torque: float,
    *,
    source: str = "loaded_te",
    table_points: int = 400,
    mesh_preset: str = "default",
    n_radii: int = 9,
    relief: bool = True,
    k_mean: float | None = None,
    k_harmonics=(),
    te_harmonics=(),
    k_pair: float | None = None,
    unloaded_te_pp: float = 0.0,
    where: str = "mesh",
) -> GearMesh:
    """The mesh of a drawing pair at a pinion torque: stiffness/TE table and geometry.

    Parameters
    ----------
    pair : rotaflex.gear.pair.drawing.PairSpec
        The checked ``[pinion]/[wheel]`` pair (centre distance or backlash included).
    torque : float
        Torque on the pinion [N m] (> 0); sets the load of ``"loaded_te"`` and ``"static_fe"``
        and ISO 6336's load factor.
    source : str
        One of :data:`SOURCES` (see the module docstring).
    table_points : int
        Phases per mesh cycle in the table.
    mesh_preset : {"coarse", "default", "fine"}
        FE tooth mesh for the FE sources.
    n_radii : int
        FE load cases per tooth (``"loaded_te"``).
    relief : bool
        False: the same gears without their profile reliefs.
    k_mean, k_harmonics, te_harmonics : float, sequence, sequence
        ``"harmonic"`` source: mean stiffness [N/m], cosine amplitudes [N/m], TE sine amplitudes [m].
    k_pair, unloaded_te_pp : float
        ``"contact_pattern"`` source: stiffness of one pair [N/m], TE peak-to-peak [m].
    where : str
        Key path of the table holding these keys in the user's config (``"gear_mesh[0]"``).

    Examples
    --------
    >>> from rotaflex.gear.pair.drawing import pair_from_mapping
    >>> pair = pair_from_mapping({"pinion": {"teeth": 20, "module": 3e-3, "face_width": 0.02},
    ...                           "wheel": {"teeth": 40, "module": 3e-3, "face_width": 0.02}})
    >>> m = gear_mesh(pair, 50.0, source="iso6336")
    >>> m.mean_stiffness > 0  # N/m
    True
    """
    if source not in SOURCES:
        raise InputError(f"{where}.source", source, "one of " + ", ".join(SOURCES))
    if not (math.isfinite(torque) and torque > 0):
        raise InputError(f"{where}.torque", torque, "a pinion torque > 0 [N m]")
    g1, g2 = pair.gears
    if not relief:
        import dataclasses

        g1, g2 = (dataclasses.replace(g, tip_relief=None, root_relief=None) for g in (g1, g2))
    a = pair.working_center_distance
    force = torque / g1.base_radius
    if source == "loaded_te":
        from rotaflex.gear.cases.static import gear_meshes
        from rotaflex.gear.static.loaded_te import pair_line

        (e1, nu1, _), (e2, nu2, _) = pair.pinion.material.values, pair.wheel.material.values
        meshes = gear_meshes(pair, mesh_preset, relief=relief)
        line = pair_line(g1, g2, *meshes, a, force, (e1, nu1, e2, nu2), n_radii)
        if pair.sliced:  # helical or lead-modified: the face in slices ([face] defaults)
            from rotaflex.gear.pair.lead import FaceConfig
            from rotaflex.gear.static.helical import face_model

            f = FaceConfig()
            face = face_model(pair, f.slices, f.coupling_length_coef, f.misalignment)
            table = sliced_mesh_table(line, face, force, table_points)
        else:
            table = loaded_mesh_table(line, force, table_points)
    elif source == "static_fe":
        from rotaflex.gear.static.tooth_analysis import mesh_stiffness

        (e1, nu1, _), (e2, nu2, _) = pair.pinion.material.values, pair.wheel.material.values
        if (e1, nu1) != (e2, nu2):
            raise InputError(f"{where}.source", source, "'loaded_te' for gears of different materials")
        table = mesh_table_from_static(mesh_stiffness(g1, g2, e1, nu1, torque=torque), g1.teeth, table_points)
    elif source == "iso6336":
        from rotaflex.gear.static.tooth_analysis import iso6336_stiffness

        r1 = g1.module * g1.teeth / 2.0  # ISO's F_t is at the reference circle
        load = torque / r1 / (min(g1.face_width, g2.face_width) * 1e3)
        helix = {"helix_angle": pair.pinion.helix_angle, "base_helix_angle": pair.base_helix_angle}
        k = iso6336_stiffness(g1, g2, load, eps_alpha=pair.contact_ratio, **(helix if pair.helical else {}))["k_gamma"]
        table = MeshTable(np.full(table_points, k), np.zeros(table_points), "linear")
    elif source == "harmonic":
        if k_mean is None or not k_mean > 0:
            raise InputError(
                f"{where}.k_mean",
                "<missing>" if k_mean is None else k_mean,
                "a mean mesh stiffness > 0 [N/m] for source 'harmonic'",
            )
        table = harmonic_mesh(k_mean, k_harmonics, te_harmonics, table_points)
    else:
        if k_pair is None or not k_pair > 0:
            raise InputError(
                f"{where}.k_pair",
                "<missing>" if k_pair is None else k_pair,
                "a single-pair stiffness > 0 [N/m] for source 'contact_pattern'",
            )
        table = contact_pattern_mesh(k_pair, pair.contact_ratio, table_points, unloaded_te_pp)
    return GearMesh(
        table=table,
        teeth=(g1.teeth, g2.teeth),
        base_radius=(g1.base_radius, g2.base_radius),
        pressure_angle=pair.operating_pressure_angle,
        center_distance=a,
        contact_ratio=pair.contact_ratio,
        face_width=min(pair.pinion.face_width, pair.wheel.face_width),
        mass=(pair.pinion.mass("pinion"), pair.wheel.mass("wheel")),
        inertia=(pair.pinion.inertia("pinion"), pair.wheel.inertia("wheel")),
        driver=pair.driver,
        torque=float(torque),
        source=source,
    )
