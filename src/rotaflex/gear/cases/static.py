"""``rotaflex gear static``: static analysis of a spur pair as specified on a drawing.

config (TOML) -> :class:`StaticConfig` (the pair's ``[pinion]``/``[wheel]`` tables, shared with
the dynamic config) -> FE tooth data of each gear (:mod:`rotaflex.gear.static.loaded_te`) -> loaded
static transmission error, mesh stiffness, load sharing and fillet stress over one mesh cycle and
the whole engagement, with and without the profile reliefs; single-tooth compliances (with a
mesh-refinement study); ISO 6336-1 c' and c_gamma_alpha -> :class:`StaticResult`.
"""

from __future__ import annotations

import dataclasses
import json
import time
from typing import Literal

import numpy as np

from rotaflex.core.config import from_mapping, param
from rotaflex.core.errors import InputError
from rotaflex.core.limits import require
from rotaflex.core.result import Result, register_result
from rotaflex.core.units import rad_to_deg
from rotaflex.gear.cases.simulate_config import without
from rotaflex.gear.pair.drawing import SUMMARY_UNITS, GearSpec, PairSpec, pair_meshes
from rotaflex.gear.pair.lead import FaceConfig
from rotaflex.gear.pair.tooth_mesh import COARSE, DEFAULT, build_tooth_mesh
from rotaflex.gear.static.loaded_te import loaded_te, pair_line
from rotaflex.gear.static.tooth_analysis import iso6336_stiffness, weber_contact_compliance

__all__ = ["StaticConfig", "SCHEMA", "run_static", "StaticResult", "gear_meshes", "MESH_PRESETS"]

#: tooth-mesh presets (keyword sets of build_tooth_mesh); "fine" = 2 x DEFAULT
MESH_PRESETS = {
    "coarse": COARSE,
    "default": DEFAULT,
    "fine": {k: 2 * v for k, v in DEFAULT.items()},
}


@dataclasses.dataclass(frozen=True)
class LoadConfig:
    """Transmitted (design) torque."""

    torque: float = param(unit="N m", gt=0.0, doc="design torque on the gear named by torque_on")
    torque_on: Literal["pinion", "wheel"] = param(
        "pinion", doc="the gear 'torque' acts on; the other carries it times the tooth ratio"
    )


@dataclasses.dataclass(frozen=True)
class StaticMeshConfig:
    """FE tooth mesh and the number of positions over a mesh cycle."""

    preset: Literal["coarse", "default", "fine"] = param("default", doc="tooth mesh")
    n_radii: int = param(9, ge=4, le=40, doc="FE load cases per tooth over the active profile")


@dataclasses.dataclass(frozen=True)
class AnalysisConfig:
    """Which static quantities to compute."""

    n_angles: int = param(240, ge=20, le=5000, doc="roll-angle samples per mesh cycle")
    compliance_diameters_pinion: tuple[float, ...] = param(
        (),
        unit="m",
        gt=0.0,
        doc="diameters for the single-tooth compliance table (default: 5 points over the active profile)",
    )
    compliance_diameters_wheel: tuple[float, ...] = param((), unit="m", gt=0.0)
    refinement: tuple[int, ...] = param(
        (1, 2), ge=1, le=4, doc="mesh refinement factors of the compliance study (x preset)"
    )


@dataclasses.dataclass(frozen=True)
class StaticConfig:
    """Root schema of ``rotaflex gear static`` (the pair keys are those of :class:`PairSpec`)."""

    pinion: GearSpec = param(
        doc='gear 1; top-level pair = "lee_jang" gives both (the paper\'s pair), keys written here override it'
    )
    wheel: GearSpec = param(doc="gear 2")
    load: LoadConfig = param(doc="design load")
    center_distance: float | None = param(None, unit="m", gt=0.0)
    backlash: float | None = param(None, unit="m", ge=0.0, doc="normal backlash")
    driver: Literal["pinion", "wheel"] = param("pinion")
    mesh: StaticMeshConfig = param(StaticMeshConfig())
    analysis: AnalysisConfig = param(AnalysisConfig())
    face: FaceConfig = param(FaceConfig())

    @property
    def sliced(self) -> bool:
        """The face width in slices: a helical pair, lead modifications or a misalignment."""
        return self.pair.sliced or self.face.misalignment != 0.0

    @property
    def pair(self) -> PairSpec:
        """The checked :class:`PairSpec`."""
        return PairSpec(
            pinion=self.pinion,
            wheel=self.wheel,
            center_distance=self.center_distance,
            backlash=self.backlash,
            driver=self.driver,
        ).check()


SCHEMA = StaticConfig

#: tables and keys only ``gear simulate`` reads: a file may carry both verbs' tables
#: (examples/gear/unequal_shifted_relief.toml); ``gear static`` ignores these
DYNAMIC_ONLY = {
    "operation": None,
    "solver": None,
    "output": None,
    "model": None,
    "mesh": ("n_points", "contact_smoothing"),
    # gear steady's tables
    "mesh_stiffness": None,
    "train": None,
    "bearings": None,
    "steady": None,
    "sweep": None,
    "iso": None,
}


def _with_load(config: dict) -> dict:
    """``config`` with a [load] table: as written, or from ``[operation] torque`` and
    ``torque_on`` of a file shared with the dynamic verbs (``torque_on`` required there: the
    dynamic verbs' defaults differ)."""
    op = config.get("operation")
    if "load" in config or not isinstance(op, dict) or "torque" not in op:
        return config
    if "torque_on" not in op:
        raise InputError(
            "operation.torque_on", None, "'pinion' or 'wheel' when [operation] torque is gear static's load (no [load])"
        )
    return {**config, "load": {"torque": op["torque"], "torque_on": op["torque_on"]}}


def gear_meshes(pair: PairSpec, preset: str | dict = "default", refine: int = 1, *, relief: bool = True):
    """Tooth meshes (pinion, wheel) for a ``MESH_PRESETS`` key or keyword set, refined ``refine``
    times (see :func:`rotaflex.gear.pair.drawing.pair_meshes`)."""
    kw = MESH_PRESETS[preset] if isinstance(preset, str) else dict(preset)
    return pair_meshes(pair, {k: refine * v for k, v in kw.items()}, relief=relief)


def _compliance_study(cfg: StaticConfig, pair: PairSpec, force: float, tick=lambda: None) -> dict:
    """Single-tooth compliances at chosen radii for each refinement level (``tick()`` after each
    gear and level: one FE mesh and its load cases)."""
    from rotaflex.gear.static.tooth_analysis import tooth_compliance

    g1, g2 = pair.gears
    out = {}
    for name, g, mate, spec, diam in (
        ("pinion", g1, g2, pair.pinion, cfg.analysis.compliance_diameters_pinion),
        ("wheel", g2, g1, pair.wheel, cfg.analysis.compliance_diameters_wheel),
    ):
        if diam:
            radii = 0.5 * np.asarray(diam)
            bad = (radii < g.form_radius) | (radii > g.tip_radius_)
            if np.any(bad):
                raise InputError(
                    f"analysis.compliance_diameters_{name}",
                    list(diam),
                    f"diameters between the form diameter {2 * g.form_radius:.6g} "
                    f"and the tip diameter {2 * g.tip_radius_:.6g} m",
                )
        else:
            radii = np.linspace(
                g.form_radius + 0.15 * (g.tip_radius_ - g.form_radius),
                g.tip_radius_ - 0.05 * (g.tip_radius_ - g.form_radius),
                5,
            )
        e, nu = spec.elastic
        rows = []
        for k in cfg.analysis.refinement:
            kw = {key: k * v for key, v in MESH_PRESETS[cfg.mesh.preset].items()}
            m = build_tooth_mesh(g, **kw, **spec.mesh_options())
            c = tooth_compliance(m, radii, e, nu, force=force, mate=mate)
            # local contact term of this tooth: half of Weber's formula with equal depths
            local = weber_contact_compliance(force, g.face_width, e, nu, c.arm, c.arm, c.half_width) / 2.0
            rows.append((c.structural, c.load_point, c.structural + local))
            tick()
        out[name] = (radii, np.array(rows))  # (level, 3, n)
    return out


#: refinement levels of the compliance study (each level <= 4 x the preset by the schema, so one
#: FE tooth mesh has at most 5,504 elements; the number of levels is what is unbounded)
MAX_REFINEMENT_LEVELS = 8
#: diameters per gear of the compliance table (one FE load case each)
MAX_COMPLIANCE_POINTS = 1_000


def _check_size(cfg: StaticConfig) -> None:
    """Refuse list lengths beyond the limits above (the other sizes are bounded by the schema:
    ``analysis.n_angles`` <= 5,000, ``mesh.n_radii`` <= 40, presets and refinement <= 4)."""
    a = cfg.analysis
    n = len(a.refinement)
    require(
        "analysis.refinement",
        list(a.refinement),
        n,
        MAX_REFINEMENT_LEVELS,
        "refinement levels",
        "fixed (gear static MAX_REFINEMENT_LEVELS)",
    )
    for name in ("pinion", "wheel"):
        diam = getattr(a, f"compliance_diameters_{name}")
        require(
            f"analysis.compliance_diameters_{name}",
            f"{len(diam)} diameters",
            len(diam),
            MAX_COMPLIANCE_POINTS,
            "diameters",
            "fixed (gear static MAX_COMPLIANCE_POINTS)",
        )


#: units of the ISO 6336-1 entries of the static summary (the others are factors, "1")
ISO_UNITS = {"q": "mm um/N", "k_single": "N/m", "k_gamma": "N/m", "k_gamma_beta": "N/m"}


@register_result
class StaticResult(Result):
    """Static pair analysis (dims ``cycle``, ``engagement``, ``gear``, ``radius``, ``level``)."""

    kind = "gear_static"

    def summary(self):
        out = super().summary()
        geo = json.loads(self.dataset.attrs.get("pair_geometry", "{}"))
        iso = geo.pop("iso", {})
        for key, val in geo.items():
            out[f"geometry_{key}"] = {"value": val, "unit": SUMMARY_UNITS[key]}
        for key, val in iso.items():  # ISO 6336-1 factors and stiffnesses of c', c_gamma
            out[f"geometry_iso_{key}"] = {"value": val, "unit": ISO_UNITS.get(key, "1")}
        return out

    def plot(self):
        from rotaflex.core.plotting import new_figure

        ds = self.dataset
        figs = {}
        x = rad_to_deg(ds["cycle"].values)
        fig, ax = new_figure(2, 1, sharex=True)
        ax[0].plot(x, ds["mesh_stiffness"] * 1e-6, label="with relief")
        ax[0].plot(x, ds["mesh_stiffness_unrelieved"] * 1e-6, "--", label="without relief")
        ax[0].set_ylabel("mesh stiffness [N/um]")
        ax[0].legend()
        ax[1].plot(x, ds["ste"] * 1e6, label="with relief")
        ax[1].plot(x, ds["ste_unrelieved"] * 1e6, "--", label="without relief")
        ax[1].set_ylabel("loaded STE along LoA [um]")
        ax[1].set_xlabel(f"{ds.attrs['driver']} roll angle over one mesh cycle [deg]")
        figs["mesh_stiffness_ste"] = fig
        xe = rad_to_deg(ds["engagement"].values)
        fig, ax = new_figure(2, 1, sharex=True)
        ax[0].plot(xe, ds["load_share"], label="with relief")
        ax[0].plot(xe, ds["load_share_unrelieved"], "--", label="without relief")
        ax[0].set_ylabel("load share of one pair [-]")
        ax[0].legend()
        for i, gname in enumerate(ds["gear"].values):
            ax[1].plot(xe, ds["fillet_stress"][:, i] * 1e-6, label=str(gname))
        ax[1].set_ylabel("tension-side fillet stress [MPa]")
        ax[1].set_xlabel(f"{ds.attrs['driver']} roll angle over one pair's engagement [deg]")
        ax[1].legend()
        figs["load_share_fillet_stress"] = fig
        if "line_load" in ds:  # sliced face: load per unit length over face width and roll angle
            fig, ax = new_figure(1, 1)
            mesh = ax.pcolormesh(
                ds["z"].values * 1e3,
                rad_to_deg(ds["tooth_roll"].values),
                ds["line_load"].values * 1e-3,
                shading="nearest",
            )
            fig.colorbar(mesh, ax=ax, label="load per unit length of contact line [N/mm]")
            ax.set_xlabel("axial position from mid-face [mm]")
            ax.set_ylabel("pinion roll angle of the mid-face contact [deg]")
            figs["line_load"] = fig
        return figs


def _ptp(x):
    return float(np.max(x) - np.min(x))


def load_config(config: dict) -> StaticConfig:
    """The validated :class:`StaticConfig` of a parsed TOML mapping: the other verbs' tables
    dropped, [load] from [operation] of a shared file, the torque on the pinion (SI, once)."""
    from rotaflex.gear.cases.pair_config import refuse_other_layout, with_pair_preset

    config = with_pair_preset({k: v for k, v in config.items() if k != "domain"}, "static")
    refuse_other_layout(config, "static")
    config = _with_load(config)
    cfg = from_mapping(StaticConfig, without(config, DYNAMIC_ONLY))
    _check_size(cfg)
    if cfg.load.torque_on == "wheel":
        g1, g2 = cfg.pair.gears
        load = dataclasses.replace(cfg.load, torque=cfg.load.torque * g1.teeth / g2.teeth, torque_on="pinion")
        cfg = dataclasses.replace(cfg, load=load)
    return cfg


def run_static(config: dict, *, progress: bool = False) -> StaticResult:
    """Static analysis of the pair in ``config`` (parsed TOML, no ``domain`` key).

    ``progress``: report the stages (tooth meshes and FE load cases of the pair, without the
    reliefs, the loaded TE, each gear and level of the compliance study) through
    :class:`rotaflex.core.progress.Progress`: a bar on a terminal, one line per stage in a log.
    """
    from rotaflex.core.progress import Progress

    t0 = time.perf_counter()
    cfg = load_config(config)
    with Progress(_stages(cfg), "gear static", "stage", enabled=progress) as bar:
        done = [0]

        def tick():
            done[0] += 1
            bar.update(done[0])

        return _run(cfg, config, t0, tick)


def _stages(cfg: StaticConfig) -> int:
    """Stages reported by :func:`run_static`: the pair's FE load cases, the unrelieved pair's
    (when a gear has a relief), the loaded TE, and one per gear and level of the compliance study."""
    relieved = any(r is not None for g in (cfg.pinion, cfg.wheel) for r in (g.tip_relief, g.root_relief))
    return 1 + int(relieved) + 1 + 2 * len(cfg.analysis.refinement)


def _refinement_changes(study: dict) -> dict:
    """Dataset variables: the largest relative change of each compliance measure between the
    last two mesh refinement levels, per gear (none with a single level)."""
    out = {}
    for gname, (_radii, rows) in study.items():
        if rows.shape[0] > 1:
            ch = np.abs(rows[-1] - rows[-2]) / np.abs(rows[-1])  # (measure, n)
            for i, mname in enumerate(("structural", "load_point", "with_contact")):
                long_name = (
                    f"max relative change of the {mname} compliance between the last two refinement levels ({gname})"
                )
                out[f"refinement_change_{gname}_{mname}"] = (
                    (),
                    float(ch[i].max()),
                    {"units": "1", "long_name": long_name},
                )
    return out


def _run(cfg: StaticConfig, config: dict, t0: float, tick) -> StaticResult:
    """:func:`run_static` after the config is read; ``tick()`` after each stage."""
    import xarray as xr

    pair = cfg.pair
    g1, g2 = pair.gears
    a = pair.working_center_distance
    e1, nu1 = pair.pinion.elastic
    e2, nu2 = pair.wheel.elastic
    elastic = (e1, nu1, e2, nu2)
    force = cfg.load.torque / g1.base_radius
    n_r = cfg.mesh.n_radii
    relieved = any(r is not None for g in (g1, g2) for r in (g.tip_relief, g.root_relief))
    m1, m2 = gear_meshes(pair, cfg.mesh.preset)
    line = pair_line(g1, g2, m1, m2, a, force, elastic, n_r)
    tick()
    if relieved:
        u1, u2 = gear_meshes(pair, cfg.mesh.preset, relief=False)
        h1 = dataclasses.replace(g1, tip_relief=None, root_relief=None)
        h2 = dataclasses.replace(g2, tip_relief=None, root_relief=None)
        line0 = pair_line(h1, h2, u1, u2, a, force, elastic, n_r)
        tick()
    else:
        line0 = line
    pb = line.base_pitch
    n = cfg.analysis.n_angles
    # one mesh cycle: reference pair over one base pitch from its start of contact
    s_cyc = line.s_start + pb * np.arange(n) / n
    # whole engagement of the reference pair (same grid as static.mesh_stiffness)
    g_len = line.s_end - line.s_start
    ang = np.linspace(0.0, g_len / g1.base_radius, n)
    s_eng = line.s_start + g1.base_radius * ang
    cyc, cyc0 = loaded_te(line, s_cyc), loaded_te(line0, s_cyc)
    hel = None
    if cfg.sliced:  # face width in slices over the same transverse FE data
        from rotaflex.gear.cases.static_helical import sliced_results

        hel = sliced_results(cfg, pair, line, line0, s_cyc, s_eng)
        cyc, cyc0 = hel.cyc, hel.cyc0
        eng_te, share, share0, stress, total_share = hel.eng_te, hel.share, hel.share0, hel.stress, hel.total_share
        pair_k, pair_name = hel.pair_stiffness, "stiffness of one tooth pair (sum of its slices)"
    else:
        eng, eng0 = loaded_te(line, s_eng), loaded_te(line0, s_eng)
        share = eng["share"][:, 2]
        share0 = eng0["share"][:, 2]
        stress = line.fillet_stress(s_eng, eng["pair_load"][:, 2])
        eng_te, total_share = eng["te"], eng["share"].sum(axis=1)
        pair_k, pair_name = 1.0 / line.compliance(s_eng), "stiffness of one tooth pair"
    tick()
    # roll angle of the driving gear in its direction of motion (wheel driving: the contact
    # runs from the pinion tip to its root)
    if cfg.driver == "pinion":
        x_cyc, x_eng = (s_cyc - line.s_start) / g1.base_radius, ang
        flip = slice(None)
    else:
        x_cyc = (s_cyc - line.s_start) / g2.base_radius
        x_eng = (s_eng - line.s_start) / g2.base_radius
        flip = slice(None, None, -1)

    # ISO 6336-1: F_t at the reference circle, K_A = 1, per face width (N/mm)
    b = min(g1.face_width, g2.face_width)
    ft_b = cfg.load.torque / g1.pitch_radius / (b * 1e3)
    # C_R: mean of the two blanks' factors (one value per pair enters c')
    c_r = 0.5 * (pair.pinion.blank_factor() + pair.wheel.blank_factor())
    iso = iso6336_stiffness(
        g1,
        g2,
        load_per_width=ft_b,
        eps_alpha=pair.contact_ratio,
        c_r=c_r,
        **({"helix_angle": pair.pinion.helix_angle, "base_helix_angle": pair.base_helix_angle} if pair.helical else {}),
    )
    study = _compliance_study(cfg, pair, force, tick)

    def v(dims, data, units, long_name):
        return (dims, np.asarray(data, dtype=float), {"units": units, "long_name": long_name})

    data = {
        "ste": v("cycle", cyc["te"][flip], "m", "loaded static transmission error (LoA)"),
        "ste_unrelieved": v("cycle", cyc0["te"][flip], "m", "loaded STE without relief"),
        "mesh_stiffness": v("cycle", cyc["stiffness"][flip], "N/m", "mesh stiffness"),
        "mesh_stiffness_unrelieved": v("cycle", cyc0["stiffness"][flip], "N/m", "mesh stiffness without relief"),
        "ste_engagement": v("engagement", eng_te[flip], "m", "loaded STE"),
        "load_share": v("engagement", share[flip], "1", "load share of the reference pair"),
        "load_share_unrelieved": v("engagement", share0[flip], "1", "load share without relief"),
        "total_share": v("engagement", total_share[flip], "1", "sum of all pairs' load shares"),
        "pair_stiffness": v("engagement", pair_k[flip], "N/m", pair_name),
        "relief_gap": v("engagement", line.gap(s_eng)[flip], "m", "unloaded relief gap"),
        "fillet_stress": v(
            ("engagement", "gear"), stress[flip], "Pa", "tension-side fillet stress (30-deg tangent point)"
        ),
        "tooth_radius": v(
            ("gear", "fe_case"), [line.tooth1.radius, line.tooth2.radius], "m", "contact radius of the FE load cases"
        ),
        "tooth_compliance": v(
            ("gear", "fe_case"),
            [line.tooth1.compliance, line.tooth2.compliance],
            "m/N",
            "structural single-tooth compliance",
        ),
    }
    for gname, (radii, rows) in study.items():
        data[f"compliance_radius_{gname}"] = v(f"radius_{gname}", radii, "m", f"{gname} compliance radii")
        data[f"compliance_{gname}"] = v(
            ("level", "measure", f"radius_{gname}"), rows, "m/N", f"{gname} single-tooth compliance"
        )
    scal = {
        "force": (force, "N", "design normal load T / r_b1"),
        "ste_mean": (float(np.mean(cyc["te"])), "m", "one-cycle mean STE"),
        "ste_ptp": (_ptp(cyc["te"]), "m", "STE peak-to-peak"),
        "ste_mean_unrelieved": (float(np.mean(cyc0["te"])), "m", "one-cycle mean STE, no relief"),
        "ste_ptp_unrelieved": (_ptp(cyc0["te"]), "m", "STE peak-to-peak, no relief"),
        "mesh_stiffness_mean": (float(np.mean(cyc["stiffness"])), "N/m", "one-cycle mean mesh stiffness"),
        "mesh_stiffness_ptp": (_ptp(cyc["stiffness"]), "N/m", "mesh stiffness peak-to-peak"),
        "mesh_stiffness_mean_unrelieved": (
            float(np.mean(cyc0["stiffness"])),
            "N/m",
            "one-cycle mean mesh stiffness, no relief",
        ),
        "mesh_stiffness_ptp_unrelieved": (_ptp(cyc0["stiffness"]), "N/m", "mesh stiffness peak-to-peak, no relief"),
        "single_pair_stiffness_max": (
            float(np.max(1.0 / line0.compliance(s_eng))),
            "N/m",
            "max stiffness of one tooth pair",
        ),
        "fillet_stress_max_pinion": (float(stress[:, 0].max()), "Pa", "max pinion fillet stress"),
        "fillet_stress_max_wheel": (float(stress[:, 1].max()), "Pa", "max wheel fillet stress"),
        "load_share_max": (float(share.max()), "1", "max load share of one pair"),
        "iso_c_prime": (iso["c_single"], "N/(mm um)", "ISO 6336-1 c'"),
        "iso_c_gamma_alpha": (iso["c_gamma"], "N/(mm um)", "ISO 6336-1 c_gamma_alpha"),
        "iso_c_th": (iso["c_th"], "N/(mm um)", "ISO 6336-1 c'_th"),
        "iso_C_R": (iso["C_R"], "1", "ISO 6336-1 gear blank factor (mean of both gears)"),
        "iso_load_per_width": (ft_b, "N/mm", "F_t / b at the reference circle"),
        "iso_load_factor": (iso["load_factor"], "1", "(F_t b^-1 / 100)^0.25 if < 100 N/mm"),
        "fe_mesh_stiffness_mean_per_width": (
            float(np.mean(cyc0["stiffness"])) / (b * 1e3) / 1e6,
            "N/(mm um)",
            "FE one-cycle mean, no relief, per b",
        ),
        "fe_single_pair_max_per_width": (
            float(np.max(1.0 / line0.compliance(s_eng))) / (b * 1e3) / 1e6,
            "N/(mm um)",
            "FE single-pair max, no relief, per b",
        ),
    }
    coords = {}
    if hel is not None:
        scal.update(hel.scalars)
        scal["iso_c_gamma_beta"] = (iso["c_gamma_beta"], "N/(mm um)", "ISO 6336-1 c_gamma_beta = 0.85 c_gamma_alpha")
        scal["axial_force_check"] = (
            cfg.load.torque
            * np.tan(pair.working_helix_angle)
            / (g1.base_radius / np.cos(pair.operating_pressure_angle)),
            "N",
            "T tan(beta_w) / r_w1",
        )
        for key, (dims, val, unit, name) in hel.data.items():
            data[key] = v(dims, val[flip] if dims == "cycle" else val, unit, name)
        coords = {k: (k, val, {"units": unit, "long_name": name}) for k, (val, unit, name) in hel.coords.items()}
    for key, (val, unit, name) in scal.items():
        data[key] = ((), float(val), {"units": unit, "long_name": name})
    lv = np.array(cfg.analysis.refinement)
    data.update(_refinement_changes(study))
    ds = xr.Dataset(
        data,
        coords={
            "cycle": ("cycle", x_cyc, {"units": "rad", "long_name": "roll angle (one cycle)"}),
            "engagement": ("engagement", x_eng, {"units": "rad", "long_name": "roll angle"}),
            "gear": ["pinion", "wheel"],
            "level": ("level", lv, {"long_name": "mesh refinement factor"}),
            "measure": ["structural", "load_point", "with_contact"],
            **coords,
        },
    )
    geo = pair.summary()
    geo["iso"] = {k: iso[k] for k in ("q", "C_M", "C_R", "C_B", "eps_alpha", "k_single", "k_gamma")}
    if hel is not None:
        geo["iso"]["k_gamma_beta"] = iso["k_gamma_beta"]
    ds.attrs.update(
        status="success",
        message=(
            f"STE mean {np.mean(cyc['te']) * 1e6:.3f} um, p-p {_ptp(cyc['te']) * 1e6:.3f} um"
            f" (no relief {_ptp(cyc0['te']) * 1e6:.3f} um); mesh stiffness mean "
            f"{np.mean(cyc['stiffness']):.4g} N/m; eps_alpha {pair.contact_ratio:.4f}"
        ),
        wall_time=time.perf_counter() - t0,
        config=json.dumps(config, default=str),
        pair_geometry=json.dumps(geo, default=float),
        driver=cfg.driver,
    )
    return StaticResult(ds)
