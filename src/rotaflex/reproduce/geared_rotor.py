"""Geared rotor section of ``rotaflex reproduce``: the example gearbox (two FE shafts, four
bearings, a 20/40 spur pair), its Campbell diagram with mesh modes, DTE and bearing forces vs
speed, the lumped-model limit and ROSS's multi-rotor documentation example."""

from __future__ import annotations

import copy
import math
from pathlib import Path

import numpy as np

from rotaflex.core.report import Check, FigureEntry, Section, step
from rotaflex.core.units import rpm_to_rad_s

#: the example files this section reads (shipped inside the package; checked before a run starts)
NEEDS = ("system/gearbox.toml", "system/ross_two_shaft.toml")
#: ROSS documentation, ``rs.MultiRotor`` docstring: first damped natural frequency at speed 0 [rad/s]
ROSS_MULTIROTOR_WD0 = 74.160244


def _example(name: str) -> dict:
    from rotaflex.core.config import load_toml
    from rotaflex.core.examples import example_path

    return load_toml(example_path(f"system/{name}"))


def lumped_limit(cfg: dict) -> tuple[np.ndarray, np.ndarray]:
    """The example pair on one rigid, light element per shaft pinned at node 1, the gear at node 0
    on a bearing acting along the line of action only: (FE frequencies, closed form) [rad/s].

    Closed form of gear steady's ``[bearings]`` model (two twists, two centre motions along the
    line of action): ``M = diag(J1, J2, m1, m2)``, ``K = diag(0, 0, kb1, kb2) + k g g^T``,
    ``g = (r_b1, r_b2, 1, -1)``; m_i includes the disks' tilt inertia about the pin (Id / L^2 per disk).
    """
    from rotaflex.system.modal import modal
    from rotaflex.system.model import Gearbox

    cfg = copy.deepcopy(cfg)
    L, mass, Id, J, kb, kperp = 0.05, (0.8, 1.6), 1e-4, (2e-3, 8e-3), (3e7, 5e7), 4e10
    m = cfg["gear_mesh"][0]
    m.update(pinion_node=0, wheel_node=0, blanks=False, damping_ratio=0.0, source="harmonic", k_mean=4e8)
    box0 = Gearbox.from_mapping({**cfg, "load": {**cfg["load"], "node": 0}, "drive": {**cfg["drive"], "node": 0}})
    alpha = box0.meshes[0].gear.pressure_angle
    n = np.array([math.sin(alpha), math.cos(alpha)])  # ccw driving pinion, wheel along +x (docs)
    t = np.array([-n[1], n[0]])
    for i, r in enumerate(cfg["rotor"]):
        r["shaft"] = [{"outer_diameter": 0.03, "length": L, "elements": 1, "E": 2e15, "G": 8e14, "rho": 1e-3}]
        kk = kb[i] * np.outer(n, n) + kperp * np.outer(t, t)
        r["bearing"] = [
            {"node": 0, "kxx": kk[0, 0], "kxy": kk[0, 1], "kyx": kk[1, 0], "kyy": kk[1, 1]},
            {"node": 1, "kxx": 1e11, "kyy": 1e11},
        ]
        r["disk"] = [{"node": 0, "mass": mass[i], "Id": Id, "Ip": J[i]}, {"node": 1, "mass": 1.0, "Id": Id, "Ip": 1e-6}]
    cfg["drive"] = {**cfg["drive"], "node": 0, "kind": "torque"}
    cfg["load"] = {**cfg["load"], "node": 0, "inertia": 0.0, "damping": 0.0}
    box = Gearbox.from_mapping(cfg)
    k = box.meshes[0].k_mean
    r1, r2 = box.meshes[0].gear.base_radius
    g = np.array([r1, r2, 1.0, -1.0])
    Kl = np.diag([0.0, 0.0, kb[0], kb[1]]) + k * np.outer(g, g)
    Ml = np.diag([J[0] + 1e-6, J[1] + 1e-6, mass[0] + 2 * Id / L**2, mass[1] + 2 * Id / L**2])
    ref = np.sqrt(np.clip(np.sort(np.linalg.eigvals(np.linalg.solve(Ml, Kl)).real), 0, None))[1:]
    w = modal(box, 0.0, 8).wn[0]
    return np.array([w[np.argmin(np.abs(w - x))] for x in ref]), ref


def run(out_dir: str | Path, *, fast: bool = False, progress: bool = False) -> Section:
    from rotaflex.core.plotting import save_figure
    from rotaflex.system.case import run_campbell, run_response, run_steady
    from rotaflex.system.modal import campbell, modal
    from rotaflex.system.model import Gearbox
    from rotaflex.system.response import forced_response
    from rotaflex.system.results import system_figure

    out = Path(out_dir) / "geared_rotor"
    out.mkdir(parents=True, exist_ok=True)
    rel = Path("geared_rotor")
    cfg = _example("gearbox.toml")
    box = Gearbox.from_mapping(cfg)
    figs: list[FigureEntry] = []

    step("model")
    save_figure(system_figure(box), out / "model.png")
    ross = Gearbox.from_mapping(_example("ross_two_shaft.toml"))
    w_ross = float(modal(ross, 0.0, 2).wd[0, 0])
    d_ross = abs(w_ross - ROSS_MULTIROTOR_WD0) / ROSS_MULTIROTOR_WD0
    m = box.meshes[0]
    figs.append(
        FigureEntry(
            "Example gearbox",
            "(not in the papers) examples/system/gearbox.toml: input shaft 40 mm and output shaft 50 mm, 10 "
            "Timoshenko elements each, four isotropic bearings, a 20/40 spur pair of module 3 mm at the shaft "
            "middles (line of action drawn as the force on the driven gear), motor at constant speed, load torque "
            "200 N m.",
            str(rel / "model.png"),
            "",
            f"Line of action n = ({m.normal[0]:.4f}, {m.normal[1]:.4f}) = (sin a', cos a') for a ccw pinion driving "
            f"a wheel on +x, a' = {math.degrees(m.gear.pressure_angle):.3f} deg. ROSS's MultiRotor documentation "
            f"example (examples/system/ross_two_shaft.toml) gives {w_ross:.6f} rad/s here for ROSS's "
            f"{ROSS_MULTIROTOR_WD0} rad/s.",
            [
                Check(
                    "ROSS MultiRotor docs example: first damped frequency at 0 rpm (relative difference)",
                    d_ross,
                    "",
                    "< 1e-4 (gear base radii differ by < 0.5 %)",
                    d_ross < 1e-4,
                )
            ],
        )
    )

    step("Campbell diagram")
    n_sp = 20 if fast else 50
    cres = run_campbell({**cfg, "campbell": {**cfg["campbell"], "n_speeds": n_sp}})
    cres.to_netcdf(out / "campbell.nc")
    save_figure(cres.plot()["campbell"], out / "campbell.png")
    sp = cres.dataset["speed"].values
    # the all-DOF solves cost most of this section: five speeds, in fast mode the first and the
    # last only (the basis is taken at the middle speed, so the ends are where it is least exact)
    at = np.array([0, n_sp - 1]) if fast else np.arange(0, n_sp, max(1, n_sp // 5))
    cf = campbell(box, sp[at], cres.dataset.sizes["mode"], reduce=False)
    red = np.sort(cres.dataset["damped_frequency"].values[at], 1)
    d_red = float(np.max(np.abs(red - np.sort(cf.modes.wd, 1)) / np.sort(cf.modes.wd, 1)))
    me = cres.dataset["mesh_energy"].values
    kmesh = int(np.argmax(me[0]))
    figs.append(
        FigureEntry(
            "Campbell diagram with mesh modes",
            "(not in the papers) Damped natural frequencies of the coupled lateral-torsional system vs input "
            "speed, coloured by the mesh strain-energy fraction; mesh orders 1-3 (red) and each shaft's 1X "
            "(dotted); circles: crossings of mesh orders with modes holding > 5 % mesh energy.",
            str(rel / "campbell.png"),
            str(rel / "campbell.nc"),
            f"Mesh mode (largest mesh energy {100 * me[0, kmesh]:.0f} %): "
            f"{cres.dataset['damped_frequency'].values[0, kmesh] / (2 * np.pi):.0f} Hz.",
            [
                Check(
                    "reduced-basis Campbell vs all-DOF solve (max relative frequency difference)",
                    d_red,
                    "",
                    "< 1e-3",
                    d_red < 1e-3,
                    f"all-DOF solves at {at.size} of the {n_sp} speeds",
                )
            ],
            log=[cres.message],
        )
    )

    step("TE response vs speed")
    n_sp = 150 if fast else 500
    rres = run_response({**cfg, "response": {**cfg["response"], "n_speeds": n_sp}})
    rres.to_netcdf(out / "response.nc")
    save_figure(rres.plot()["response"], out / "response.png")
    f_dyn = rres.dataset["mesh_force"].values[0].sum(-1)  # (speed,), over the harmonics
    speeds = rres.dataset["speed"].values[:: max(1, n_sp // 25)]
    a = forced_response(box, speeds, harmonics=3)
    b = forced_response(box, speeds, harmonics=3, cutoff=None)
    d_resp = float(np.max(np.abs(a.bearing_force - b.bearing_force)) / np.max(np.abs(b.bearing_force)))
    # linear vs nonlinear time domain at a small TE (no contact loss), one speed
    small = copy.deepcopy(cfg)
    small["gear_mesh"][0].update(source="harmonic", k_mean=m.k_mean, te_harmonics=[1e-8])
    sres = run_steady({**small, "steady": {"speed_rpm": 3000.0, "stiffness": "mean", "tol": 1e-9, "max_cycles": 6000}})
    f = sres.dataset["mesh_force"].values[:, 0]
    spc = int(sres.dataset.attrs["samples_per_cycle"])
    n = (f.size - 1) // spc * spc
    h1 = 2 * abs(np.fft.rfft(f[-n - 1 : -1])[n // spc]) / n
    lin = forced_response(
        Gearbox.from_mapping(small), [rpm_to_rad_s(3000)], harmonics=1, excitation="unloaded_te", cutoff=None
    )
    d_lin = abs(h1 - abs(lin.mesh_force[0, 0, 0])) / abs(lin.mesh_force[0, 0, 0])
    figs.append(
        FigureEntry(
            "DTE, dynamic mesh force and bearing forces vs speed",
            "(not in the papers) Linear response to the first three harmonics of the loaded static TE "
            "(contact-pattern mesh: single/double contact, 5 um TE), all four bearings.",
            str(rel / "response.png"),
            str(rel / "response.nc"),
            f"Largest dynamic mesh force (sum of the harmonic amplitudes) {f_dyn.max():.4g} N at "
            f"{rres.dataset['speed_rpm'].values[np.argmax(f_dyn)]:.0f} rpm.",
            [
                Check(
                    "reduced-basis bearing forces vs all-DOF solve (max difference / peak)",
                    d_resp,
                    "",
                    "< 1e-3",
                    d_resp < 1e-3,
                ),
                Check(
                    "time-domain steady state (10 nm TE, mean stiffness) vs linear response: first mesh harmonic "
                    "of the mesh force (relative)",
                    d_lin,
                    "",
                    "< 2e-3",
                    d_lin < 2e-3,
                ),
            ],
            log=[rres.message],
        )
    )

    step("lumped-model limit")
    w_fe, w_ref = lumped_limit(cfg)
    d_l = float(np.max(np.abs(w_fe - w_ref) / w_ref))
    st = run_steady(cfg)
    sm = st.summary()
    for key in ("dynamic_factor", "contact_loss_fraction", "energy_balance_error", "period_cycles"):
        sm[key]["value"] = float(sm[key]["value"])
    sec = Section(
        "Geared rotor systems (FE shafts and bearings coupled through the gear mesh)",
        "Two FE rotors (rotor/fe) placed in the gearbox plane and joined by a spur mesh from the gear package's "
        "mesh interface; coupled lateral-torsional modes, TE response and the nonlinear steady state. "
        "Conventions and the verification table: docs/geared-rotor.md.",
        figs,
        [
            Check(
                "bearings along the line of action only: coupled FE model vs the lumped 2-inertia + 2-mass "
                "closed form (max relative difference)",
                d_l,
                "",
                "< 1e-4",
                d_l < 1e-4,
                "FE vs closed form [rad/s]: "
                + ", ".join(f"{a_:.3f} vs {b_:.3f}" for a_, b_ in zip(w_fe, w_ref, strict=True)),
            ),
            Check(
                "example gearbox steady state at 3000 rpm: energy balance |E - E0 - int P| / scale",
                sm["energy_balance_error"]["value"],
                "",
                "< 2e-3 (256 steps per mesh cycle on a mesh table with stiffness steps; second order)",
                sm["energy_balance_error"]["value"] < 2e-3,
                f"dynamic factor {sm['dynamic_factor']['value']:.3f}, contact loss "
                f"{100 * sm['contact_loss_fraction']['value']:.2f} % of the time, period "
                f"{int(sm['period_cycles']['value'])} mesh cycle(s)",
            ),
        ],
    )
    return sec
