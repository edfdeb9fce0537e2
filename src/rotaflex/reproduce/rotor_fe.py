"""FE rotor section of ``rotaflex reproduce rotor``: Friswell et al. (2010) Example 5.9.1 model,
Campbell diagram, unbalance Bode plot and a run-up through the first critical speed."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from rotaflex.core.report import Check, FigureEntry, Section
from rotaflex.core.units import rad_s_to_rpm, rpm_to_rad_s

#: ROSS documentation output for the Example 5.9.1 model (6 elements), rad/s
ROSS_0RPM = [86.65811435, 274.31285391, 716.78631221]
ROSS_4000RPM = [85.389467, 87.7958637, 251.78460413, 294.71333087, 600.17936195, 827.07536193]


def _rotor(c: float = 0.0):
    from rotaflex.rotor.fe import Bearing, Disk, Rotor, Shaft

    return Rotor(
        shaft=(Shaft(outer_diameter=0.05, length=1.5, elements=6),),
        disk=(
            Disk(position=0.5, width=0.07, outer_diameter=0.28, inner_diameter=0.05),
            Disk(position=1.0, width=0.07, outer_diameter=0.35, inner_diameter=0.05),
        ),
        bearing=(Bearing(node=0, kxx=1e6, kyy=1e6, cxx=c, cyy=c), Bearing(node=6, kxx=1e6, kyy=1e6, cxx=c, cyy=c)),
    )


def fe_section(out_dir: str | Path, *, fast: bool = False) -> Section:
    """Compute the FE rotor figures into ``out_dir/rotor/fe`` and return them as a section."""
    from rotaflex.core.plotting import save_figure
    from rotaflex.rotor.fe.figures import bode_figure, campbell_figure, model_figure
    from rotaflex.rotor.fe.modal import campbell, modal
    from rotaflex.rotor.fe.response import peaks, unbalance_response
    from rotaflex.rotor.fe.transient import transient
    from rotaflex.rotor.fe.ucs import ucs_map

    out = Path(out_dir) / "rotor" / "fe"
    out.mkdir(parents=True, exist_ok=True)
    rel = Path("rotor") / "fe"
    figs: list[FigureEntry] = []
    r = _rotor()
    w0 = modal(r, 0.0, 6).wn[0][::2]
    m4 = modal(r, rpm_to_rad_s(4000), 6)
    d0 = float(np.max(np.abs(w0 - ROSS_0RPM) / ROSS_0RPM))
    d4 = float(np.max(np.abs(m4.wn[0] - ROSS_4000RPM) / ROSS_4000RPM))
    rows = ["| mode | whirl (ours) | ours at 4000 rpm [rad/s] | ROSS docs [rad/s] |", "|---|---|---|---|"]
    rows += [f"| {k} | {m4.whirl[0, k]} | {m4.wn[0, k]:.4f} | {ROSS_4000RPM[k]:.4f} |" for k in range(6)]
    save_figure(model_figure(r), out / "model.png")
    figs.append(
        FigureEntry(
            "Example 5.9.1 model",
            "(not in the paper) Friswell, Penny, Garvey & Lees (2010), Dynamics of Rotating Machines, Example 5.9.1: "
            "1.5 m shaft, 50 mm, disks at 0.5 m and 1 m, 1 MN/m isotropic bearings; 6 Timoshenko elements.",
            str(rel / "model.png"),
            "",
            "Natural frequencies compared with the ROSS documentation's output for the same model (an independent "
            "Timoshenko FE code). The book's own tabulated values are not compared here: we could not verify "
            "them from a source at hand.\n\n" + "\n".join(rows),
            [
                Check("0 rpm natural frequencies vs ROSS docs (max relative difference)", d0, "", "< 1e-6", d0 < 1e-6),
                Check(
                    "4000 rpm natural frequencies vs ROSS docs (max relative difference)", d4, "", "< 1e-6", d4 < 1e-6
                ),
                Check(
                    "whirl from orbit sense: backward/forward alternate at 4000 rpm",
                    float(list(m4.whirl[0]) == ["backward", "forward"] * 3),
                    "",
                    "= 1",
                    list(m4.whirl[0]) == ["backward", "forward"] * 3,
                ),
            ],
        )
    )

    rd = _rotor(3e3)  # Example 5.9.5 damping, so that the response is bounded
    speeds = np.linspace(0, rpm_to_rad_s(4000), 30 if fast else 80)
    c = campbell(rd, speeds, 6, (1,))
    save_figure(
        campbell_figure(
            speeds,
            c.modes.wd,
            c.modes.log_dec,
            forward=c.modes.forward_fraction,
            marks=[{**x, "labelled": True} for x in c.critical],
        ),
        out / "campbell.png",
    )
    fw = [x["speed"] for x in c.critical if x["whirl"] == "forward"]
    ucs = ucs_map(_rotor(), [1e6], 2)[0]
    cu = campbell(_rotor(), speeds, 6, (1,))
    fw_u = [x["speed"] for x in cu.critical if x["whirl"] == "forward"]
    du = float(np.max(np.abs(np.array(fw_u[:2]) - ucs) / ucs))
    figs.append(
        FigureEntry(
            "Campbell diagram",
            "(not in the paper) Damped natural frequencies vs speed, bearings with 3 kN s/m damping (Example 5.9.5 "
            "values); modes tracked by MAC, 1X line, critical speeds circled.",
            str(rel / "campbell.png"),
            "",
            "Forward 1X critical speeds: " + ", ".join(f"{rad_s_to_rpm(s):.0f} rpm" for s in fw) + ".",
            [
                Check(
                    "undamped Campbell forward 1X crossings vs synchronous UCS eigenproblem",
                    du,
                    "",
                    "< 5e-3 (linear interpolation between speeds)",
                    du < 5e-3,
                ),
                Check(
                    "smallest MAC between consecutive tracked modes, after the first step",
                    float(c.mac_min[2:].min()),
                    "",
                    "> 0.9",
                    float(c.mac_min[2:].min()) > 0.9,
                    "at 0 rpm each forward/backward pair is degenerate (any combination is a mode), so the first "
                    f"step's MAC is {c.mac_min[1]:.2f}, as expected for planar vs circular shapes",
                ),
            ],
        )
    )

    sp = np.linspace(rpm_to_rad_s(100), rpm_to_rad_s(4000), 400 if fast else 1000)
    ub = unbalance_response(rd, sp, [(4, 1e-4, 0.0)])
    amp = {f"node {p} x": np.abs(ub.at(p)[0]) for p in (2, 4)}
    ph = {f"node {p} x": np.angle(ub.at(p)[0]) for p in (2, 4)}
    pk = peaks(sp, ub.major_axis(4), rpm_to_rad_s(3000))
    save_figure(bode_figure(sp, amp, ph, pk), out / "bode.png")
    first = pk[0] if pk else {"speed": np.nan, "af": np.nan, "sm_percent": np.nan}
    dpk = abs(first["speed"] - fw[0]) / fw[0] if fw else np.nan
    figs.append(
        FigureEntry(
            "Unbalance response",
            "(not in the paper) Bode plot at the disk nodes for 1e-4 kg m at the right disk; peaks with the "
            "half-power amplification factor AF = N_c / (N_2 - N_1) and separation margin SM = |N_op - N_c| / N_op "
            "from N_op = 3000 rpm.",
            str(rel / "bode.png"),
            "",
            "; ".join(
                f"peak {rad_s_to_rpm(p['speed']):.0f} rpm: AF {p['af']:.2f}, SM {p['sm_percent']:.1f} %" for p in pk
            ),
            [
                Check(
                    "first response peak vs first forward critical speed (relative)",
                    float(dpk),
                    "",
                    "< 0.02",
                    bool(dpk < 0.02),
                )
            ],
        )
    )

    crit = fw[0]
    t_end = 2.0 if fast else 4.0
    tr = transient(
        rd,
        t_end,
        speed_start=0.3 * crit,
        speed_end=2.0 * crit,
        unbalance=[(4, 1e-4, 0.0)],
        method="modal",
        n_modes=12,
        n_output=2001 if fast else 4001,
    )
    from rotaflex.core.plotting import legend_outside, new_figure

    fig, ax = new_figure()
    radial = np.hypot(tr.q[:, 16], tr.q[:, 17])
    ax.plot(rad_s_to_rpm(tr.speed), radial * 1e6, lw=0.7, label="run-up (time response)")
    ss = unbalance_response(rd, tr.speed[tr.speed > 0], [(4, 1e-4, 0.0)])
    ax.plot(
        rad_s_to_rpm(tr.speed[tr.speed > 0]),
        ss.major_axis(4) * 1e6,
        "--",
        label="steady unbalance response (orbit semi-major axis)",
    )
    ax.axvline(rad_s_to_rpm(crit), color="0.5", lw=0.6)
    ax.set_xlabel("speed [rpm]")
    ax.set_ylabel("radial displacement at node 4 [\u00b5m]")
    legend_outside(ax)
    save_figure(fig, out / "runup.png")
    w_peak = float(tr.speed[np.argmax(radial)])
    figs.append(
        FigureEntry(
            "Run-up through the first critical",
            f"(not in the paper) Linear run-up from {rad_s_to_rpm(0.3 * crit):.0f} to {rad_s_to_rpm(2 * crit):.0f} "
            f"rpm in {t_end:g} s (modal method, 12 modes), with the steady response for comparison.",
            str(rel / "runup.png"),
            "",
            "",
            [
                Check(
                    "run-up peak speed / steady critical speed",
                    w_peak / crit,
                    "",
                    "in (1, 1.2): an accelerating rotor peaks after the critical",
                    1 < w_peak / crit < 1.2,
                )
            ],
            log=[tr.message],
        )
    )
    from rotaflex.reproduce.rotor_fluid_film import fluid_film_entries

    figs += fluid_film_entries(out, rel, fast=fast)
    return Section(
        "FE rotor-bearing model (Timoshenko shaft, disks, bearings)",
        "Finite-element rotor-bearing model on the Example 5.9.1 rotor of Friswell et al. (2010).",
        figs,
    )
