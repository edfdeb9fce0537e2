"""Fluid-film bearing part of ``rotaflex reproduce rotor`` (called from :mod:`.rotor_fe`).

Figures: load-normalised coefficients of a plain L/D = 0.5 bearing vs eccentricity (finite-length
Reynolds solution, short-bearing closed form, Someya's table) and the oil-whip onset of a rigid
rotor on two short bearings vs the closed-form threshold.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from rotaflex.core.report import Check, FigureEntry
from rotaflex.core.units import rad_s_to_rpm, rpm_to_rad_s


def _load_frame(k, b, force):
    """K and B (dimensionless, per unit force) in Someya's frame: x along the load, y at +90 deg."""
    W = np.hypot(*force)
    x = -force / W
    Q = np.stack([x, np.array([-x[1], x[0]])], 1)
    return Q.T @ k @ Q / W, Q.T @ b @ Q / W


def _coefficient_entry(out: Path, rel: Path) -> FigureEntry:
    from rotaflex.core.plotting import new_figure, save_figure
    from rotaflex.rotor.fe.bearings import literature as lit
    from rotaflex.rotor.fe.bearings.fluid_film import short_film
    from rotaflex.rotor.fe.bearings.reynolds import ReynoldsGrid, solve_film

    grid = ReynoldsGrid(0.5, 72, 12)
    eps = np.linspace(0.1, 0.9, 33)
    fin, sho, S_fin = [], [], []
    for e in eps:
        s = solve_film(grid, e)
        fin.append(_load_frame(s.k, s.b, s.force))
        S_fin.append(1 / (6 * np.pi * np.hypot(*s.force)))
        F, k, b = short_film(e, 0.5)
        sho.append(_load_frame(k, b, F))
    fin, sho = np.array(fin), np.array(sho)  # (n, 2 [K, B], 2, 2)
    fig, axes = new_figure(1, 2, figsize=(10, 3.8))
    names = ["xx", "xy", "yx", "yy"]
    for j, ax in enumerate(axes):
        for n in range(4):
            (line,) = ax.plot(eps, fin[:, j].reshape(-1, 4)[:, n], label=names[n])
            ax.plot(eps, sho[:, j].reshape(-1, 4)[:, n], ":", color=line.get_color())
            ref = [r[3 + j][n] for r in lit.SOMEYA_LD05]
            ax.plot([r[1] for r in lit.SOMEYA_LD05], ref, "o", color=line.get_color())
        ax.set_xlabel("eccentricity ratio")
        ax.set_ylabel(["K c / W", "C c omega / W"][j])
        ax.set_ylim(-3, 20)
    axes[0].legend(fontsize=8, title="solid: finite, dotted: short, o: Someya", title_fontsize=7)
    save_figure(fig, out / "fluid_film_coefficients.png")

    # checks: short model vs the published closed form; finite model vs Someya and Raimondi-Boyd
    d_short = 0.0
    for e in (0.1, 0.3, 0.5, 0.7, 0.9):
        F, k, b = short_film(e, 0.5)
        a_ref, b_ref = lit.ocvirk_coefficients(e)
        K, B = _load_frame(k, b, F)
        # published frame (u, v) = (-y, x) in Someya's frame
        P = np.array([[0.0, -1.0], [1.0, 0.0]])
        d_short = max(d_short, np.abs(P @ K @ P.T - a_ref).max() / np.abs(a_ref).max())
        d_short = max(d_short, np.abs(P @ B @ P.T - b_ref).max() / np.abs(b_ref).max())
    d_someya, d_S = 0.0, 0.0
    for S, e, _, kref, cref in lit.SOMEYA_LD05:
        s = solve_film(grid, e)
        K, B = _load_frame(s.k, s.b, s.force)
        d_S = max(d_S, abs(1 / (6 * np.pi * np.hypot(*s.force)) / S - 1))
        if e >= 0.7:
            d_someya = max(d_someya, np.abs(K.ravel() - kref).max() / max(np.abs(kref)))
            d_someya = max(d_someya, np.abs(B.ravel() - cref).max() / max(np.abs(cref)))
    g1 = ReynoldsGrid(1.0, 72, 12)
    d_rb = max(
        abs(1 / (6 * np.pi * np.hypot(*solve_film(g1, e, derivatives=False).force)) / S - 1)
        for e, S, _ in lit.RAIMONDI_BOYD_LD1
    )
    return FigureEntry(
        "Fluid-film bearing coefficients",
        "(not in the paper) Plain cylindrical journal bearing, L/D = 0.5: load-normalised stiffness and damping "
        "vs eccentricity ratio from the finite-length Reynolds equation (72 x 12 grid, Swift-Stieber cavitation), "
        "the short-bearing closed form (Ocvirk, half-Sommerfeld film) and Someya's (1989) table for a "
        "two-axial-groove bearing of the same L/D.",
        str(rel / "fluid_film_coefficients.png"),
        "",
        "x along the static load, y at +90 deg in the spin sense. Someya's bearing has two axial grooves, so the "
        "coefficients are compared at eps >= 0.7 only, where the film lies in the loaded half.",
        [
            Check("short model vs published Ocvirk coefficients (max relative)", d_short, "", "< 1e-9", d_short < 1e-9),
            Check("finite model S vs Someya L/D = 0.5, eps 0.5-0.9 (max relative)", d_S, "", "< 0.02", d_S < 0.02),
            Check("finite model K, C vs Someya, eps 0.7-0.9 (max / largest)", d_someya, "", "< 0.10", d_someya < 0.10),
            Check("finite model S vs Raimondi & Boyd L/D = 1 (max relative)", d_rb, "", "< 0.03", d_rb < 0.03),
        ],
    )


def _whip_entry(out: Path, rel: Path, fast: bool) -> FigureEntry:
    from rotaflex.core.plotting import new_figure, save_figure
    from rotaflex.rotor.fe import Bearing, Disk, Rotor, Shaft
    from rotaflex.rotor.fe.bearings import FluidFilm
    from rotaflex.rotor.fe.bearings import literature as lit
    from rotaflex.rotor.fe.modal import campbell

    m, D, L, c, mu = 50.0, 0.05, 0.0125, 50e-6, 0.01
    ff = FluidFilm(D, L, c, mu, (0.0, -m * lit.G_ACC), (4000.0, 20000.0), n_speeds=321, model="short")
    rotor = Rotor(
        shaft=(Shaft(outer_diameter=D, length=0.3, elements=2, E=2e14, G=8e13, rho=1.0),),
        disk=(Disk(node=1, mass=2 * m - 5.9e-4, Id=0.01, Ip=0.02),),
        bearing=(Bearing(node=0, fluid_film=ff), Bearing(node=2, fluid_film=ff)),
    )
    speeds = rpm_to_rad_s(np.linspace(4000, 20000, 81 if fast else 161))
    cb = campbell(rotor, speeds, 4)
    w_th = lit.rigid_rotor_whip_threshold(m, D, L, c, mu, (rpm_to_rad_s(4000), rpm_to_rad_s(20000)))
    growth = [lit.rigid_rotor_growth(w, m, D, L, c, mu) for w in speeds]
    onset = min((u["speed"] for u in cb.unstable), default=np.nan)
    d = abs(onset / w_th - 1)
    # the flexible Jeffcott rotor: 0.6 m x 60 mm massless shaft (midspan stiffness with shear)
    E, kappa, ds, ls = 2.1e11, 0.9, 0.06, 0.6
    Gs, area, inertia = E / 2.6, np.pi * ds**2 / 4, np.pi * ds**4 / 64
    ks = 1 / (ls**3 / (48 * E * inertia) + ls / (4 * kappa * Gs * area))
    jeff = Rotor(
        shaft=(Shaft(outer_diameter=ds, length=ls, elements=4, E=E, G=Gs, rho=1.0, shear_coefficient=kappa),),
        disk=(Disk(node=2, mass=2 * m - area * ls, Id=0.01, Ip=0.02),),
        bearing=(Bearing(node=0, fluid_film=ff), Bearing(node=4, fluid_film=ff)),
    )
    cj = campbell(jeff, speeds, 4)
    wj = lit.rigid_rotor_whip_threshold(m, D, L, c, mu, (rpm_to_rad_s(4000), rpm_to_rad_s(20000)), shaft_stiffness=ks)
    dj = abs(min((u["speed"] for u in cj.unstable), default=np.nan) / wj - 1)
    fig, ax = new_figure()
    sigma = -cb.modes.log_dec * cb.modes.wd / (2 * np.pi)  # real part of the eigenvalue
    for k in range(sigma.shape[1]):
        ax.plot(rad_s_to_rpm(speeds), sigma[:, k], lw=1, label=f"FE mode {k}")
    ax.plot(rad_s_to_rpm(speeds), growth, "k:", label="closed form (4x4, published coefficients)")
    ax.axhline(0, color="0.5", lw=0.6)
    ax.axvline(
        rad_s_to_rpm(w_th), color="r", lw=0.8, ls="--", label=f"closed-form threshold {rad_s_to_rpm(w_th):.0f} rpm"
    )
    ax.set_xlabel("speed [rpm]")
    ax.set_ylabel("real part of eigenvalue [1/s]")
    ax.set_ylim(-400, 100)
    ax.legend(fontsize=7)
    save_figure(fig, out / "oil_whip.png")
    return FigureEntry(
        "Oil-whip onset on short bearings (rigid and Jeffcott rotors)",
        "(not in the paper) A 100 kg rigid rotor (stiff 0.3 m shaft, central disk) on two short journal bearings "
        "(D = 50 mm, L = 12.5 mm, c = 50 um, 0.01 Pa s, load m g each): real parts of the FE Campbell eigenvalues "
        "with the fluid-film coefficient table vs the 4x4 rigid-rotor equations with the published short-bearing "
        "coefficients.",
        str(rel / "oil_whip.png"),
        "",
        f"Onset reported by the Campbell stability check: {rad_s_to_rpm(onset):.0f} rpm; closed form: "
        f"{rad_s_to_rpm(w_th):.0f} rpm. "
        f"The same bearings under a flexible Jeffcott rotor (0.6 m x 60 mm shaft, k_s = {ks:.3g} N/m): closed form "
        f"{rad_s_to_rpm(wj):.0f} rpm.",
        [
            Check("rigid rotor: FE onset speed vs closed-form threshold (relative)", d, "", "< 0.005", bool(d < 0.005)),
            Check("Jeffcott rotor: FE onset vs closed-form threshold (relative)", dj, "", "< 0.005", bool(dj < 0.005)),
        ],
    )


def fluid_film_entries(out: Path, rel: Path, *, fast: bool = False) -> list[FigureEntry]:
    """Figures and checks of the fluid-film bearings, written into ``out``."""
    return [_coefficient_entry(out, rel), _whip_entry(out, rel, fast)]
