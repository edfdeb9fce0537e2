"""Reproduce Lee & Jang, spur-gear dynamic contact: Fig. 8-11 (contact force vs rotation angle).

The paper's curves did not survive, only the captions; the checks are physical: the quasi-static
limit (single-pair force = tau_0 / r_b, ramps of Fig. 7), energy balance, constraint residuals
at the paper's tolerances, and separation / re-impact without blow-up in the rattling cases.
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np

from rotaflex.core.report import Check, FigureEntry, Section
from rotaflex.core.units import rad_s_to_rpm, rpm_to_rad_s

CASES = (
    ("fig8", "Fig. 8", "Variations of the contact force (4,000 rpm)", (4000.0, 4000.0)),
    ("fig9", "Fig. 9", "Variations of the contact force (20,000 rpm)", (20000.0, 20000.0)),
    (
        "fig10",
        "Fig. 10",
        "Variations of the contact force (4,000 rpm for gear A and 4,040 rpm for gear B)",
        (4000.0, 4040.0),
    ),
    (
        "fig11",
        "Fig. 11",
        "Variations of the contact force (20,000 rpm for gear A and 20,200 rpm for gear B)",
        (20000.0, 20200.0),
    ),
)


#: shortest separation counted in the comparison with the lumped model [s]: well above the
#: tooth vibration period (~7 us, 140 kHz), well below the mesh-spring period (~150 us)
MIN_SEPARATION = 20e-6
#: contact-surface smoothing used when the paper's point-contact surfaces chatter
#: (docs/gear-dynamics.md, "Smoothed contact surfaces")
SMOOTHING = 12
#: ``--fast`` runs Fig. 10/11 with this driver only: the one the full run picks of A/B for both
#: figures (Fig. 10: 3 re-contacts with A driving, 4 with B; Fig. 11: with A driving the teeth
#: never touch, with B they touch once), so the fast checks test the run the report draws
FAST_DRIVER = "B"
#: speed of the quasi-static run [rpm] (key: fast mode); the run's cost goes as 1 / speed. At
#: 1,500 rpm the single-pair mean force is 0.5 % off tau_0/r_b (2.7 % at 2,000 rpm, too close to
#: the 3 % criterion; 0.2 % at 1,000 rpm), coarse mesh, measured 2026-11-26
QUASI_STATIC_RPM = {False: 500.0, True: 1500.0}


def _smoothed_rerun(ds, preset: str):
    """The same case with ``[mesh] contact_smoothing = SMOOTHING``."""
    from rotaflex.gear.cases.simulate import run_case

    rpm = rad_s_to_rpm(ds["angular_velocity"].isel(time=0).values)
    return run_case(
        {
            "operation": {"speed_rpm": [float(v) for v in rpm], "driver": ds.attrs.get("driver", "A")},
            "mesh": {"preset": preset, "contact_smoothing": SMOOTHING},
        }
    ).dataset


def _energy_checks(ds, preset: str, tol: float = 0.02):
    """Energy check of the paper's scheme; if it fails, the smoothed-surface run as well.

    Returns (checks, smoothed dataset or None). A failure of the paper's point-contact surfaces
    (chatter of the contact point on the indented mesh at several times the nominal load) is a
    finding about the method: it is reported as a claim, and the smoothed run is verified.
    """
    checks = _common_checks(ds, tol)
    bal = float(ds["energy_balance_error"])
    if bal < tol:
        return checks, None
    sm = _smoothed_rerun(ds, preset)
    bal_s = float(sm["energy_balance_error"])
    checks[0] = Check(
        "paper's scheme (point contact on splines of the deformed flank nodes): energy balance",
        bal,
        "",
        f"< {tol:g}",
        False,
        "the contact point chatters between the rims of the "
        "point-load indentation at 6-7 x the nominal load (docs/gear-dynamics.md)",
        claim=True,
    )
    checks.insert(
        1,
        Check(
            f"energy balance with contact_smoothing = {SMOOTHING} (same case)",
            bal_s,
            "",
            f"< {tol:g}",
            bal_s < tol,
            f"peak {float(sm['peak_contact_force']):.1f} N vs {float(ds['peak_contact_force']):.1f} "
            "N with the paper's surfaces; the force is spread over the fitted flank nodes",
        ),
    )
    return checks, sm


def _run(speeds, preset, span_deg=None, every=10, driver=None):
    from rotaflex.gear.cases.simulate import run_case

    cfg = {"operation": {"speed_rpm": list(speeds)}, "mesh": {"preset": preset}, "output": {"every": every}}
    if driver is not None:
        cfg["operation"]["driver"] = driver
    if span_deg is not None:
        cfg["operation"]["span_deg"] = span_deg
    return run_case(cfg)


def _separations(force: np.ndarray, time: np.ndarray, threshold: float, min_gap: float = 0.0) -> tuple[int, int]:
    """Number of contact losses and re-contacts after the first loaded contact.

    Separations shorter than ``min_gap`` [s] (a closed contact "flickering" through tooth
    vibration) are merged with the contact around them.
    """
    on = force > threshold
    if not np.any(on):
        return 0, 0
    first = int(np.argmax(on))
    on, t = on[first:], time[first:]
    trans = np.diff(on.astype(int))
    lost = regained = 0
    for d in np.flatnonzero(trans == -1):
        ups = np.flatnonzero(trans[d:] == 1)
        if ups.size == 0:  # separated until the end
            lost += 1
        elif t[d + ups[0]] - t[d] >= min_gap:
            lost += 1
            regained += 1
    return lost, regained


def _common_checks(ds, tol_energy=0.02) -> list[Check]:
    tol = 1e-12
    dt = float(ds["dt"])
    bal = float(ds["energy_balance_error"])
    return [
        Check(
            "energy balance |E_kin + E_strain - W_ext + D - E_0| / max E_strain",
            bal,
            "",
            f"< {tol_energy:g}",
            bal < tol_energy,
            "D = energy removed by the constraint passes at impacts (velocity pass; on a step "
            "where a contact closes also the displacement pass). The drift comes "
            "from the one-sided convergence to the 1e-12 m tolerance (|p| * tol per step).",
        ),
        Check(
            "tie residual after each step (max)",
            float(ds["max_tie_residual"]),
            "m",
            "<= 1e-12 m",
            float(ds["max_tie_residual"]) <= tol * (1 + 1e-6),
        ),
        Check(
            "velocity constraint error (max)",
            float(ds["residual_velocity"].max()),
            "m/s",
            f"<= 1e-12/dt = {tol / dt:.3g}",
            float(ds["residual_velocity"].max()) <= tol / dt * (1 + 1e-6),
        ),
        Check(
            "acceleration constraint error (max)",
            float(ds["residual_acceleration"].max()),
            "m/s^2",
            f"<= 1e-12/dt^2 = {tol / dt**2:.4g}",
            float(ds["residual_acceleration"].max()) <= tol / dt**2 * (1 + 1e-6),
        ),
    ]


def _lumped(preset: str):
    """Lumped torsional model of the same meshes (:mod:`rotaflex.gear.models.lumped`) and the angles."""
    from rotaflex.core.config import from_mapping
    from rotaflex.gear.cases.simulate import GearCaseConfig, build
    from rotaflex.gear.models.lumped import lumped_pair
    from rotaflex.gear.pair.geometry import contact_angles

    cfg = from_mapping(GearCaseConfig, {"mesh": {"preset": preset}})
    geo, _, model = build(cfg)
    ths, th2 = contact_angles(geo, geo)
    mat = cfg.material
    pair = lumped_pair(model, youngs_modulus=mat.youngs_modulus, poisson_ratio=mat.poisson_ratio, theta_s=ths)
    return pair, th2, ths, cfg.operation.torque


def _lumped_checks(ds, lumped, rattling: bool) -> tuple[list[Check], dict, str]:
    """Compare a run with the lumped model (same driver, same speeds); checks + curve."""
    from rotaflex.gear.models.lumped import simulate_lumped

    pair, th2, ths, torque = lumped
    drv = ds.attrs.get("driver", "A")
    other = "B" if drv == "A" else "A"
    w0 = ds["angular_velocity"].isel(time=0)
    speeds = (rad_s_to_rpm(float(w0.sel(gear=drv))), rad_s_to_rpm(float(w0.sel(gear=other))))
    # identical gears: "B drives" is the lumped pair with the driver as its first inertia
    lr = simulate_lumped(
        pair, speeds=rpm_to_rad_s(speeds), torque=torque, theta_2=th2, theta_s=ths, span=ths, n_output=20001
    )
    nominal = float(ds["nominal_force"])
    ang = ds["rotation_angle"].sel(gear=drv).values
    f = ds["contact_force"].values
    fl = np.interp(ang, lr["angle_A"], lr["contact_force"])
    peak, peak_l = float(f.max()), float(lr["contact_force"].max())
    rms = float(np.sqrt(np.mean((f - fl) ** 2)))
    rel = abs(peak / peak_l - 1.0) if peak_l > 0 else (0.0 if peak < 0.01 * nominal else 1.0)
    checks = [
        Check(
            "peak contact force vs lumped torsional model of the same meshes",
            rel,
            "",
            "< 0.15",
            rel < 0.15,
            f"FE {peak:.1f} N, lumped {peak_l:.1f} N; RMS difference {rms:.1f} N "
            f"({rms / nominal * 100:.1f} % of tau_0/r_b). The lumped model has rigid teeth inertia "
            "(no ~140 kHz tooth vibration), see docs/gear-dynamics.md",
        )
    ]
    if rattling:
        thr = 0.01 * nominal
        fe = _separations(f, ds["time"].values, thr, MIN_SEPARATION)
        lu = _separations(lr["contact_force"], lr["time"], thr, MIN_SEPARATION)
        ok = abs(fe[0] - lu[0]) <= 1 and abs(fe[1] - lu[1]) <= 1
        checks.append(
            Check(
                "separations / re-contacts vs lumped model",
                f"{fe[0]} / {fe[1]}",
                "",
                f"lumped {lu[0]} / {lu[1]}, +-1 each",
                ok,
                "same counting on both histories: force below 1 % of tau_0/r_b for "
                f"at least {MIN_SEPARATION * 1e6:g} us (shorter gaps are tooth "
                "vibration, which the lumped model does not have)",
            )
        )
    curve = {
        "angle": np.degrees(np.interp(lr["time"], ds["time"].values, ds["rotation_angle"].sel(gear="A").values)),
        "force": lr["contact_force"],
    }
    return checks, curve, f" Lumped model: peak {peak_l:.1f} N, RMS difference {rms:.1f} N."


def _figure(ds, path: Path, title: str, lumped_curve=None, smoothed=None):
    from rotaflex.core.plotting import new_figure, save_figure

    fig, ax = new_figure()
    ang = np.degrees(ds["rotation_angle"].sel(gear="A").values)
    if lumped_curve is not None:
        ax.plot(
            lumped_curve["angle"],
            lumped_curve["force"],
            color="0.6",
            lw=1.6,
            label="lumped torsional model (same meshes)",
        )
    ax.plot(ang, ds["contact_force"].values, lw=0.8, label="contact force (this work)")
    if smoothed is not None:
        ax.plot(
            np.degrees(smoothed["rotation_angle"].sel(gear="A").values),
            smoothed["contact_force"].values,
            "--",
            lw=0.8,
            label=f"with contact_smoothing = {SMOOTHING}",
        )
    ax.plot(ang, ds["nominal_force_ramp"].values, "k--", lw=0.8, label="quasi-static tau_driver/r_b")
    ax.set_xlabel("rotation angle of gear A from start of contact [deg]")
    ax.set_ylabel("contact force [N]")
    ax.set_title(title, fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    save_figure(fig, path)


def _quasi_static(dom: Path, rpm: float, fig8=None) -> list[FigureEntry]:
    """The quasi-static run at ``rpm`` (coarse mesh) and its entries; with ``fig8`` (the Fig. 8
    run) also that run's fillet-stress entry."""
    from rotaflex.reproduce import gear_post

    # quasi-static limit: low speed, coarse mesh, up to the middle of the single-pair zone
    qs = _run((rpm, rpm), "coarse", span_deg=10.53, every=20)
    ds = qs.dataset
    nominal = float(ds["nominal_force"])
    ang = ds["rotation_angle"].sel(gear="A").values
    th2 = float(ds["theta_2"])
    f = ds["contact_force"].values
    ramp = ds["nominal_force_ramp"].values
    zone = ang > th2
    mean_single = float(np.mean(f[zone]))
    rel = abs(mean_single / nominal - 1.0)
    dev = float(np.sqrt(np.mean((f[ang > 0.2 * th2] - ramp[ang > 0.2 * th2]) ** 2))) / nominal
    qs.to_netcdf(dom / "quasi_static.nc")
    entries = [gear_post.quasi_static_entry(qs, dom, "coarse")]
    if fig8 is not None:
        entries.append(gear_post.root_stress_entry(fig8, dom, "Fig. 8"))
    _figure(ds, dom / "quasi_static.png", f"quasi-static check, {rpm:g} rpm, coarse mesh")
    qchecks = [
        Check(
            f"single-pair zone mean force / (tau_0/r_b) - 1 at {rpm:g} rpm",
            rel,
            "",
            "< 0.03",
            rel < 0.03,
            f"mean {mean_single:.1f} N vs {nominal:.1f} N over {math.degrees(th2):.2f}-"
            f"{math.degrees(ang[-1]):.2f} deg; residual dynamics at the mesh frequency",
        ),
        Check(
            "RMS(force - tau_A(theta)/r_b) / (tau_0/r_b) over the ramp (Fig. 7)",
            dev,
            "",
            "< 0.1",
            dev < 0.1,
            "the force follows the torque ramp of Fig. 7",
        ),
    ] + _common_checks(ds)
    entries.insert(
        0,
        FigureEntry(
            label="Quasi-static limit",
            caption="(not in the paper) low-speed run: the contact force must follow tau_A(theta)/r_b of Fig. 7",
            image="gear/quasi_static.png",
            data="gear/quasi_static.nc",
            description=f"{rpm:g} rpm, coarse mesh, {int(ds['steps'])} steps.",
            checks=qchecks,
        ),
    )
    return entries


def run(out_dir: Path, *, fast: bool = False, progress: bool = False) -> Section:
    """Run the four cases of the paper (coarse mesh in fast mode) and the quasi-static check."""
    t0 = time.perf_counter()
    out_dir = Path(out_dir)
    dom = out_dir / "gear"
    dom.mkdir(parents=True, exist_ok=True)
    preset = "coarse" if fast else "default"
    figures = []
    from rotaflex.core.report import step
    from rotaflex.reproduce import gear_post

    fig8 = None
    lumped = _lumped(preset)
    references = {}
    for stem, label, caption, speeds in CASES:
        step(f"{label}: {speeds[0]:g} / {speeds[1]:g} rpm")
        drv_note = ""
        if speeds[0] != speeds[1] and fast:
            # fast mode: only the driver the full run draws (FAST_DRIVER, its pick of A/B)
            res = _run(speeds, preset, driver=FAST_DRIVER)
            drv_note = (
                f" Fast mode: driver {FAST_DRIVER} only, the one the full run draws of A/B (more "
                "re-contacts, then more separations); the full run also runs the other driver."
            )
        elif speeds[0] != speeds[1]:
            # the paper does not say which gear drives: run both, draw the one that rattles
            runs = gear_post.run_both_drivers(speeds, preset)
            drv = gear_post.pick_rattling(runs)
            res = runs[drv][0]
            other = "B" if drv == "A" else "A"
            runs[other][0].to_netcdf(dom / f"{stem}_driver{other}.nc")
            drv_note = (
                f" Drawn: driver {drv} (more re-contacts); data of driver {other} in "
                f"gear/{stem}_driver{other}.nc. " + gear_post.driver_summary(runs) + "."
            )
        else:
            res = _run(speeds, preset)
        ds = res.dataset
        if stem == "fig8":
            fig8 = res
        if speeds[0] == speeds[1]:
            references[speeds[0]] = res
        res.to_netcdf(dom / f"{stem}.nc")
        lchecks, lcurve, lnote = _lumped_checks(ds, lumped, speeds[0] != speeds[1])
        echecks, smoothed = _energy_checks(ds, preset)
        _figure(
            ds,
            dom / f"{stem}.png",
            f"{speeds[0]:g} / {speeds[1]:g} rpm, {preset} mesh, driver {ds.attrs.get('driver', 'A')}",
            lcurve,
            smoothed,
        )
        nominal = float(ds["nominal_force"])
        peak = float(ds["peak_contact_force"])
        checks = echecks + lchecks
        desc = (
            f"{ds.sizes['time']} records of {int(ds['steps'])} RK4 steps (dt = 3e-8 s), "
            f"solver {float(ds['solver_wall_time']):.1f} s "
            f"({float(ds['time_per_step']) * 1e6:.0f} us/step). Peak {peak:.1f} N, dynamic "
            f"factor {peak / nominal:.3f}." + lnote
        )
        if speeds[0] != speeds[1]:
            thr = 0.01 * nominal
            lost, regained = _separations(ds["contact_force"].values, ds["time"].values, thr)
            checks.append(
                Check(
                    "rattling: contact losses after first loaded contact", lost, "", ">= 1 (teeth separate)", lost >= 1
                )
            )
            checks.append(
                Check(
                    "paper (text under Fig. 10/11): the teeth re-contact after a separation (rattling)",
                    regained,
                    "",
                    ">= 1 (teeth re-impact)",
                    regained >= 1,
                    f"{int(ds['impacts'])} steps with a plastic impact (velocity "
                    "pass stopping an approaching contact faster than 1e-12/dt). "
                    f"Gear {ds.attrs.get('driver', 'A')} drives (chosen of A/B as "
                    "the run with more re-contacts; the paper does not say).",
                    claim=True,
                )
            )
            desc += f" Contact lost {lost} times, regained {regained} times." + drv_note
        figures.append(
            FigureEntry(
                label=label,
                caption=caption,
                image=f"gear/{stem}.png",
                data=f"gear/{stem}.nc",
                description=desc,
                checks=checks,
            )
        )
    figures += _quasi_static(dom, QUASI_STATIC_RPM[fast], fig8)
    from rotaflex.reproduce.gear_methods import methods_entry

    figures.append(methods_entry(references, dom, preset, fast=fast))
    from rotaflex.reproduce.gear_teeth import comparison

    # fast mode: Fig. 8 (4000 rpm, coarse mesh) is the single-tooth run the comparison needs
    figures.append(comparison(dom, fast=fast, single=references.get(4000.0) if fast else None))
    from rotaflex.reproduce import gear_steady

    figures.append(gear_steady.comparison(dom, fast=fast))
    intro = (
        "Lee & Jang, dynamic contact of spur gears: two identical 28-tooth gears, one elastic "
        "8-node FE tooth per gear on a rigid disk, RK4 with dt = 3e-8 s, three constraint passes "
        "per step with the accelerated multiplier iteration. The paper's curves were lost; we "
        "check physics instead. Contact force = acceleration-pass value (the paper's choice). "
        + ("Fast mode: coarse tooth mesh." if fast else "Default tooth mesh.")
    )
    sec = Section(
        title="Spur-gear dynamic contact (Lee & Jang)",
        intro=intro,
        figures=figures,
        notes=[
            "NASA TM-105326's curve in Fig. 8 is not reproduced (no data).",
            "Single-tooth model with the torque ramps of Fig. 7; the two-pair zones are not modelled directly.",
            "Fig. 10/11: the paper does not say which gear drives; both choices are "
            "run and the one with more re-contacts is drawn (see each figure; --fast runs "
            f"driver {FAST_DRIVER}, the full run's choice, only). "
            "Fig. 11 (20,000/20,200 rpm) does not rattle with either driver: with A "
            "driving the faster B runs away at once (the ramped torques remove only "
            "~16 of the 21 rad/s within theta_s); with B driving, B hits A at once, "
            "the pair bounces through the tooth compliance (one contact, one "
            "separation) and does not meet again within theta_s. The lumped "
            "torsional model of the same meshes gives the same sequence. Scaling: "
            "the separation speed grows with the speed difference (5x from Fig. 10 "
            "to 11) while the torque that closes the gap does not, and theta_s lasts "
            "5x shorter, so a re-impact within theta_s is ~25x less likely than at "
            "4,000/4,040 rpm. The paper's claim is listed as a failed check.",
        ],
    )
    sec.wall_time = time.perf_counter() - t0
    return sec
