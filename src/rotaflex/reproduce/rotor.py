"""Yun & Ren (2008), rotor rotation: Fig. 3-13 re-computed from the stated inputs, with checks.

Inputs as printed: I = 1 kg m^2, Omega = 10 rad/s; prescribed motions theta = psi = sin(t)/10
(1-2-3), phi = psi = sin(t)/10 (3-1-3), eps_theta = eps_psi = sin(t)/10 (quaternion); simulations
start from zero angles with 1 rad/s rates. The time window is not printed: we use 0-10 s.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from rotaflex.core.report import Check, FigureEntry, Section, step
from rotaflex.rotation import (
    body_rate_matrix,
    inertial_rate_matrix,
    rates_from_quaternion,
)

I, OMEGA = 1.0, 10.0
J123 = np.diag([2.0, 1.0, 1.0]) * I
J313_PAPER = np.diag([1.0, 2.0, 1.0]) * I  # as printed (eq. 26b): polar moment on y
J313 = np.diag([1.0, 1.0, 2.0]) * I  # consistent: spin theta is about body z
JQ = np.diag([2.0, 1.0, 1.0]) * I  # eq. 30 without the scalar row

CAPTIONS = {
    3: "Kinetic energy in the moving frame: 1-2-3 rotation, truncated and full, and quaternion.",
    4: "Kinetic energy in the inertial frame: 3-1-3 rotation, truncated and full, and quaternion.",
    5: "Angular velocity omega_2 in the moving frame: 1-2-3, 3-1-3 rotations and quaternion.",
    6: "Angular velocity omega_2 in the inertial frame: 1-2-3, 3-1-3 rotations and quaternion.",
    7: "Angular velocity omega_3 in the moving frame: 1-2-3, 3-1-3 rotations and quaternion.",
    8: "Angular velocity omega_3 in the inertial frame: 1-2-3, 3-1-3 rotations and quaternion.",
    9: "Rotation angles of the 1-2-3 rotation from the linear analysis in the moving frame.",
    10: "Rotation angles of the 3-1-3 rotation from the nonlinear analysis in the moving frame.",
    11: "Rotation angles of the 3-1-3 rotation from the linear analysis in the moving frame.",
    12: "Rotation angles of the 3-1-3 rotation from the nonlinear analysis in the inertial frame.",
    13: "Rotation angles by the quaternion in the moving and inertial frames.",
}


def prescribed_kinematics(t: np.ndarray) -> dict[str, np.ndarray]:
    """Angular velocities of the three prescribed motions (body and inertial components)."""
    s, c = np.sin(t) / 10, np.cos(t) / 10
    out = {}
    for name, seq, conv, ang, rate in (
        ("123", "123", "paper", [OMEGA * t, s, s], [OMEGA + 0 * t, c, c]),
        ("123rh", "123", "right-handed", [OMEGA * t, s, s], [OMEGA + 0 * t, c, c]),
        ("313", "313", "right-handed", [s, s, OMEGA * t], [c, c, OMEGA + 0 * t]),
    ):
        ang, rate = np.stack(ang, -1), np.stack(rate, -1)[..., None]
        out[name + "_body"] = (body_rate_matrix(seq, ang, conv) @ rate)[..., 0]
        out[name + "_inertial"] = (inertial_rate_matrix(seq, ang, conv) @ rate)[..., 0]
    # eq. 21-22 with theta = pi/2 + eps, psi = pi + eps, phi = Omega t
    phi, th, ps = OMEGA * t, np.pi / 2 + s, np.pi + s
    e = np.stack(
        [
            np.cos(phi / 2),
            np.sin(phi / 2) * np.sin(th) * np.cos(ps),
            np.sin(phi / 2) * np.sin(th) * np.sin(ps),
            np.sin(phi / 2) * np.cos(th),
        ],
        -1,
    )
    h = 1e-6  # e(t) is explicit: central difference is accurate to ~1e-12 here
    tp, tm = t + h, t - h

    def e_of(tt):
        ss = np.sin(tt) / 10
        ph, th_, ps_ = OMEGA * tt, np.pi / 2 + ss, np.pi + ss
        return np.stack(
            [
                np.cos(ph / 2),
                np.sin(ph / 2) * np.sin(th_) * np.cos(ps_),
                np.sin(ph / 2) * np.sin(th_) * np.sin(ps_),
                np.sin(ph / 2) * np.cos(th_),
            ],
            -1,
        )

    e_dot = (e_of(tp) - e_of(tm)) / (2 * h)
    out["q_body"], out["q_inertial"] = rates_from_quaternion(e, e_dot)
    return out


def _energy(J, w):
    return 0.5 * np.einsum("ti,ij,tj->t", w, J, w)


def _save(
    out: Path,
    n: int,
    curves: dict[str, np.ndarray],
    t: np.ndarray,
    ylabel: str,
    unit: str,
    title: str,
    styles: dict | None = None,
) -> tuple[str, str]:
    step(f"Fig. {n}")
    import xarray as xr

    from rotaflex.core.io import write_netcdf
    from rotaflex.core.plotting import new_figure, save_figure

    d = out / "rotor"
    d.mkdir(parents=True, exist_ok=True)
    fig, ax = new_figure()
    for name, y in curves.items():
        ax.plot(t[: y.size], y, (styles or {}).get(name, "-"), label=name, lw=1.2)
    ax.set_xlabel("time [s]")
    ax.set_ylabel(f"{ylabel} [{unit}]")
    ax.set_title(title, fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    save_figure(fig, d / f"fig{n:02d}.png")
    ds = xr.Dataset(
        {
            k.replace(" ", "_").replace("*", "star").replace("/", "_"): (
                "time",
                np.pad(v, (0, t.size - v.size), constant_values=np.nan),
                {"units": unit, "long_name": k},
            )
            for k, v in curves.items()
        },
        coords={"time": ("time", t, {"units": "s"})},
    )
    write_netcdf(d / f"fig{n:02d}.nc", ds)
    return f"rotor/fig{n:02d}.png", f"rotor/fig{n:02d}.nc"


def _simulate(formulation: dict, inertia=None, t_end=10.0, n_output=2001, spin0=0.0):
    from rotaflex.rotor.case import run_case

    disk = {"mass": 1.0, "polar_inertia": 2 * I, "diametral_inertia": I}
    if inertia is not None:
        disk["inertia"] = list(inertia)
    cfg = {
        "disk": disk,
        "formulation": formulation,
        "motion": {
            "spin_speed": OMEGA,
            "initial_tilt": [0.0, 0.0],
            "initial_tilt_rate": [1.0, 1.0],
            "initial_spin_angle": spin0,
        },
        "solver": {"t_end": t_end, "n_output": n_output, "rtol": 1e-9, "atol": 1e-12},
    }
    return run_case(cfg)


def run(out_dir: str | Path, *, fast: bool = False, progress: bool = False) -> Section:
    """Recompute Fig. 3-13 into ``out_dir/rotor`` and return the report section."""
    out = Path(out_dir)
    t = np.linspace(0.0, 10.0, 1001 if fast else 4001)
    n_out = 1001 if fast else 2001
    figs = _prescribed_figures(out, t)
    figs.append(_fig9(out, n_out))
    figs += _figs_313(out, n_out)
    figs.append(_fig13(out, n_out))
    notes = [
        "3-1-3: the unbounded angles of Fig. 10-12 come from (i) J_313 = diag(1,2,1) as printed, "
        "which makes the spin axis a minimum-inertia axis, and (ii) psi being a precession angle "
        "that winds up. The linearised 3-1-3 equations expand about phi = 0, where 3-1-3 angles "
        "are polar coordinates of the tilt and the expansion is not valid."
    ]
    intro = (
        "Yun & Ren (2008), 'Formulation and analysis of rotor-system rotational motion'. Inputs as printed "
        "(I = 1 kg m^2, Omega = 10 rad/s, prescribed sin(t)/10 motions, zero initial angles and 1 rad/s rates); "
        "the time window is not printed and is taken as 0-10 s. The paper's curves did not survive in the text, "
        "so each figure is judged by its stated claim and by independent checks."
    )
    section = Section("Rotor rotation: Euler angles vs quaternions (Yun & Ren 2008)", intro, figs, [], notes)
    return _with_fe_section(section, out, fast)


def _prescribed_figures(out: Path, t: np.ndarray) -> list[FigureEntry]:
    """Fig. 3-8: energies and angular velocities of the prescribed motions at times ``t`` [s]."""
    w = prescribed_kinematics(t)
    s, c = np.sin(t) / 10, np.cos(t) / 10
    figs: list[FigureEntry] = []

    # ---- Fig. 3: body-frame energy, 1-2-3 truncated (eq. 27a) vs full vs quaternion
    K123s = _energy(J123, w["123_body"])
    K123s_trunc = 0.5 * I * (2 * OMEGA**2 + c**2 + c**2 + 2 * OMEGA * (s * c - s * c))
    Kq_s = _energy(JQ, w["q_body"])
    Kq = _energy(JQ, w["q_inertial"])
    img, data = _save(
        out,
        3,
        {"K*_123 truncated (eq. 27a)": K123s_trunc, "K*_123 full": K123s, "K*_q quaternion": Kq_s},
        t,
        "kinetic energy",
        "J",
        "Fig. 3",
    )
    d3 = float(np.max(np.abs(K123s - Kq_s)) / np.max(Kq_s))
    figs.append(
        FigureEntry(
            "Fig. 3",
            CAPTIONS[3],
            img,
            data,
            "Energies of the prescribed motions (I = 1 kg m^2, Omega = 10 rad/s). Full = 1/2 w*^T J w* "
            "with the paper's eq. 6 map; truncated = eq. 27a.",
            [
                Check(
                    "paper: K*_123 full and K*_q almost equal but not identical",
                    d3,
                    "",
                    "0 < max |K*_123 - K*_q| / max K*_q < 0.05",
                    0 < d3 < 0.05,
                    "relative difference",
                    claim=True,
                ),
                Check(
                    "max |K*_123 truncated - full| / max full",
                    float(np.max(np.abs(K123s_trunc - K123s)) / np.max(K123s)),
                    "",
                    "< 0.01 (second-order truncation of an O(0.1 rad) motion)",
                    float(np.max(np.abs(K123s_trunc - K123s)) / np.max(K123s)) < 0.01,
                ),
            ],
        )
    )

    # ---- Fig. 4: inertial-frame energy, 3-1-3 truncated (eq. 27d) vs full vs quaternion
    K313 = _energy(J313_PAPER, w["313_inertial"])
    K313_trunc = 0.5 * I * (c**2 + OMEGA**2 + c**2)
    K313_consistent = _energy(J313, w["313_body"])
    img, data = _save(
        out,
        4,
        {
            "K_313 truncated (eq. 27d)": K313_trunc,
            "K_313 full (J as printed)": K313,
            "K_q quaternion": Kq,
            "K 3-1-3 with polar J on z (physical)": K313_consistent,
        },
        t,
        "kinetic energy",
        "J",
        "Fig. 4",
    )
    ratio = float(np.mean(K313) / np.mean(Kq))
    figs.append(
        FigureEntry(
            "Fig. 4",
            CAPTIONS[4],
            img,
            data,
            "Paper's inertial-frame energies 1/2 w^T J w. The 3-1-3 curves use J_313 = I diag(1, 2, 1) as "
            "printed, which puts the polar moment on body y although the spin theta is about body z.",
            [
                Check(
                    "paper: 3-1-3 underestimates the energy (mean K_313 / mean K_q)",
                    ratio,
                    "",
                    "< 1",
                    ratio < 1,
                    claim=True,
                    note="holds, but only because J_313 as printed puts the polar moment on the wrong "
                    "axis: with the polar moment on z the ratio is "
                    f"{float(np.mean(K313_consistent) / np.mean(Kq)):.4f}",
                )
            ],
        )
    )

    # ---- Fig. 5-8: angular velocities
    for n, comp, frame in ((5, 1, "body"), (6, 1, "inertial"), (7, 2, "body"), (8, 2, "inertial")):
        curves = {
            "1-2-3 (paper eq. 6/10)": w[f"123_{frame}"][:, comp],
            "3-1-3 (eq. 11)": w[f"313_{frame}"][:, comp],
            "quaternion (eq. 15/16)": w[f"q_{frame}"][:, comp],
        }
        img, data = _save(out, n, curves, t, f"omega_{comp + 1} ({frame})", "rad/s", f"Fig. {n}")
        checks = []
        if n == 5:
            diff = float(np.max(np.abs(w["123_body"] - w["q_body"])[:, 1:]))
            checks.append(
                Check(
                    "paper: 1-2-3 body rates similar to quaternion (max transverse difference)",
                    diff,
                    "rad/s",
                    "< 0.5 rad/s (similar, not equal)",
                    diff < 0.5,
                    "similar magnitude; not equal (different motions are prescribed)",
                    claim=True,
                )
            )
        figs.append(
            FigureEntry(
                f"Fig. {n}", CAPTIONS[n], img, data, "Components of the prescribed motions' angular velocities.", checks
            )
        )
    dq = float(np.max(np.abs(np.linalg.norm(w["q_body"], axis=1) - np.linalg.norm(w["q_inertial"], axis=1))))
    kq_rel = float(np.max(np.abs(Kq_s - Kq)) / np.max(Kq))
    figs[0].checks.append(
        Check(
            "paper: K_q* = K_q (max |K_q* - K_q| / max K_q)",
            kq_rel,
            "",
            "< 1e-9",
            kq_rel < 1e-9,
            claim=True,
            note="close but not exact with body J and inertial components: equality would need R J R^T = J. "
            f"|w*| = |w| holds to {dq:.1e} rad/s; the physical energy (R J R^T) is frame-invariant by construction",
        )
    )
    k123 = float(np.max(np.abs(K123s - _energy(J123, w["123_inertial"]))) / np.max(K123s))
    figs[0].checks.append(
        Check(
            "paper: K*_123 != K_123 (max relative difference)",
            k123,
            "",
            "> 1e-6",
            k123 > 1e-6,
            "the paper's inertial energy is not frame-invariant",
            claim=True,
        )
    )
    return figs


def _fig9(out: Path, n_out: int) -> FigureEntry:
    """Fig. 9: linear 1-2-3 EOM against its closed form, with ``n_out`` output times."""
    # ---- Fig. 9: linear 1-2-3 EOM (paper truncation, paper convention), body frame
    r9 = _simulate({"sequence": "123", "convention": "paper", "expansion": "paper_truncated"}, n_output=n_out)
    r9x = _simulate({"sequence": "123", "expansion": "second_order"}, n_output=n_out)
    r9n = _simulate({"sequence": "123", "expansion": "nonlinear"}, n_output=n_out)
    tt = r9.dataset["time"].values
    q9 = r9.dataset["generalized_coordinate"].values[:, 2:]
    z = (1 + 1j) * (np.exp(2j * OMEGA * tt) - 1) / (2j * OMEGA)  # closed form of the linear EOM
    err9 = float(np.max(np.abs(q9[:, 0] + 1j * q9[:, 1] - z)))
    img, data = _save(
        out,
        9,
        {
            "theta (eq. 34, linear)": q9[:, 0],
            "psi (eq. 34, linear)": q9[:, 1],
            "theta exact 2nd order (right-handed)": r9x.dataset["generalized_coordinate"].values[:, 2],
            "theta nonlinear (right-handed)": r9n.dataset["generalized_coordinate"].values[:, 2],
        },
        tt,
        "angle",
        "rad",
        "Fig. 9",
        {"theta nonlinear (right-handed)": "--"},
    )
    return FigureEntry(
        "Fig. 9",
        CAPTIONS[9],
        img,
        data,
        "Linear 1-2-3 EOM in the body frame (eq. 33-34: theta'' = -2 Omega psi', psi'' = 2 Omega theta'), "
        "initial angles 0, rates 1 rad/s; with the exact second-order and the nonlinear equations for comparison.",
        [
            Check(
                "linear 1-2-3 vs closed form (theta + i psi)",
                err9,
                "rad",
                "< 1e-7",
                err9 < 1e-7,
                "z = z'(0) (exp(2 i Omega t) - 1) / (2 i Omega): periodic, amplitude sqrt(2)/Omega",
            ),
            Check(
                "max |angle| (periodic, bounded)",
                float(np.max(np.abs(q9))),
                "rad",
                "<= sqrt(2)/Omega + 1e-9",
                float(np.max(np.abs(q9))) <= np.sqrt(2) / OMEGA + 1e-9,
            ),
        ],
    )


def _figs_313(out: Path, n_out: int) -> list[FigureEntry]:
    """Fig. 10-12: 3-1-3 EOM with J as printed and with the polar moment on the spin axis."""
    figs: list[FigureEntry] = []
    # ---- Fig. 10-12: 3-1-3
    runs313 = {
        10: ({"sequence": "313", "expansion": "nonlinear"}, "nonlinear, body frame"),
        11: ({"sequence": "313", "expansion": "paper_truncated"}, "linear (paper truncation), body frame"),
        12: (
            {"sequence": "313", "energy": "inertial_paper", "expansion": "nonlinear"},
            "nonlinear, inertial frame (paper energy)",
        ),
    }
    for n, (form, what) in runs313.items():
        rp = _simulate(form, inertia=np.diag(J313_PAPER), n_output=n_out)
        rc = _simulate(form, inertia=np.diag(J313), n_output=n_out)
        tt = rp.dataset["time"].values
        qp = rp.dataset["generalized_coordinate"].values[:, 2:]
        qc = rc.dataset["generalized_coordinate"].values[:, 2:]
        curves = {
            "psi (J as printed)": qp[:, 0],
            "phi (J as printed)": qp[:, 1],
            "psi (polar J on z)": qc[:, 0],
            "phi (polar J on z)": qc[:, 1],
        }
        img, data = _save(
            out, n, curves, tt, "angle", "rad", f"Fig. {n}", {"psi (polar J on z)": "--", "phi (polar J on z)": "--"}
        )
        tilt_p = float(rp.dataset["tilt_angle"].max()) if rp.status != "failed" else np.nan
        tilt_c = float(rc.dataset["tilt_angle"].max()) if rc.status != "failed" else np.nan
        grow = float(np.max(np.abs(qp)))
        figs.append(
            FigureEntry(
                f"Fig. {n}",
                CAPTIONS[n],
                img,
                data,
                f"3-1-3 EOM, {what}; q = [psi (precession), phi (nutation)], spin theta = Omega t; "
                f"with J as printed (diag(1,2,1)) and with the polar moment on the spin axis z (diag(1,1,2)). "
                f"Status: {rp.status} / {rc.status}.",
                [
                    Check(
                        "paper: 3-1-3 angles grow without bound (max |angle|, J as printed)",
                        grow,
                        "rad",
                        "> 1 rad",
                        grow > 1.0,
                        f"max polar-axis tilt (parameterisation-free) {tilt_p:.3g} rad",
                        claim=True,
                    )
                ]
                + (
                    [
                        Check(
                            "max polar-axis tilt, polar J on z (nonlinear)",
                            tilt_c,
                            "rad",
                            "bounded (< 0.5 rad) for a gyroscopic disk",
                            tilt_c < 0.5,
                            "the disk stays near its nominal axis; psi is a precession angle that winds up as the "
                            "disk whirls, so the angle growth is a coordinate effect, not instability",
                        )
                    ]
                    if n != 11
                    else [
                        Check(
                            "linear 3-1-3 tilt (polar J on z) departs from the nonlinear one",
                            tilt_c,
                            "rad",
                            "> 0.5 rad while the nonlinear tilt stays < 0.5 rad",
                            tilt_c > 0.5,
                            "expanding about phi = 0 (where 3-1-3 angles are polar coordinates of the tilt) is "
                            "invalid: the linear 3-1-3 equations are not a small-motion model",
                        )
                    ]
                ),
            )
        )
    return figs


def _fig13(out: Path, n_out: int) -> FigureEntry:
    """Fig. 13: spherical-coordinate quaternion EOM, which stops at its singular instant."""
    # ---- Fig. 13: quaternion EOM (M_q singular whenever phi = 2 k pi)
    spin0 = np.pi / 2
    rb = _simulate({"parameterisation": "quaternion_spherical", "energy": "body"}, n_output=n_out, spin0=spin0)
    ri = _simulate(
        {"parameterisation": "quaternion_spherical", "energy": "inertial_paper"}, n_output=n_out, spin0=spin0
    )
    r0 = _simulate({"parameterisation": "quaternion_spherical"}, n_output=n_out)
    qb, qi = rb.dataset["generalized_coordinate"].values[:, 2:], ri.dataset["generalized_coordinate"].values[:, 2:]
    tb, ti = rb.dataset["time"].values, ri.dataset["time"].values
    import matplotlib

    matplotlib.use("Agg")
    img, data = _save(
        out,
        13,
        {
            "eps_theta (body)": qb[:, 0],
            "eps_psi (body)": qb[:, 1],
            "eps_theta (inertial)": qi[:, 0],
            "eps_psi (inertial)": qi[:, 1],
        },
        tb if tb.size >= ti.size else ti,
        "angle",
        "rad",
        "Fig. 13",
    )
    t_sing = (2 * np.pi - spin0) / OMEGA
    return FigureEntry(
        "Fig. 13",
        CAPTIONS[13],
        img,
        data,
        "Spherical-coordinate quaternion EOM (eq. 38). M_q = 4 sin^2(phi/2) (...) vanishes at phi = 2 k pi, "
        "so the paper's start (phi = 0) is singular: we start at phi = pi/2 and integration stops at the "
        f"first singular instant phi = 2 pi (t = {t_sing:.4f} s).",
        [
            Check(
                "start at phi = 0 refused as singular",
                float(r0.status == "singular"),
                "",
                "status 'singular' at t = 0",
                r0.status == "singular",
                "refused before the first step: M_q is singular at phi = 0",
            ),
            Check(
                "integration stops at the singular time (body energy)",
                float(tb[-1]),
                "s",
                f"within 0.01 s before {t_sing:.4f} s",
                t_sing - 0.01 < tb[-1] <= t_sing + 1e-9,
                "the singular mass matrix is detected by an event, not integrated through",
            ),
        ],
        log=[rb.message, r0.message],
    )


def _with_fe_section(section: Section, out: Path, fast: bool) -> Section:
    """The rotor section with the finite-element rotor-bearing model as its own part (its own
    heading and wall time in the report: it is not about Euler angles or quaternions)."""
    import time

    from rotaflex.core.jit import CompileTimer
    from rotaflex.reproduce.rotor_fe import fe_section

    t0 = time.perf_counter()
    with CompileTimer() as compiling:
        fe = fe_section(out, fast=fast)
    fe.compile_time = compiling.seconds
    fe.wall_time = time.perf_counter() - t0 - compiling.seconds
    section.parts.append(fe)
    return section
