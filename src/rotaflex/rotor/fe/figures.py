"""Figures of the FE rotor: model sketch, Campbell diagram, Bode plot, orbits (matplotlib, Agg)."""

from __future__ import annotations

import numpy as np

from rotaflex.rotor.fe.modal import STABILITY_TOL
from rotaflex.rotor.fe.model import Rotor

HZ = 1 / (2 * np.pi)
RPM = 30 / np.pi


def model_figure(rotor: Rotor):
    """Shaft profile (outer and inner radius), disks, bearings (triangles) and node numbers."""
    from matplotlib.patches import Polygon, Rectangle

    from rotaflex.core.plotting import new_figure

    fig, ax = new_figure()
    e, z = rotor.elements, rotor.nodes
    for i in range(e["L"].size):
        for sign in (1, -1):
            ro_l, ro_r, ri_l, ri_r = e["do_l"][i] / 2, e["do_r"][i] / 2, e["di_l"][i] / 2, e["di_r"][i] / 2
            ax.add_patch(
                Polygon(
                    [[z[i], sign * ri_l], [z[i + 1], sign * ri_r], [z[i + 1], sign * ro_r], [z[i], sign * ro_l]],
                    closed=True,
                    fc="0.75",
                    ec="0.3",
                    lw=0.6,
                )
            )
    rmax = float(e["do_l"].max()) / 2
    span = z[-1] - z[0]
    for node, d in rotor.disks:
        # disk drawn with a height from its inertia: r = sqrt(2 Ip / m) for a thin solid disk
        rd = np.sqrt(2 * d.Ip / d.mass) if d.mass > 0 and d.Ip > 0 else 2 * rmax
        w = 0.015 * span
        ax.add_patch(Rectangle((z[node] - w / 2, -rd), w, 2 * rd, fc="tab:blue", alpha=0.6))
        rmax = max(rmax, rd)
    for node, _ in rotor.point_masses:
        ax.plot(z[node], 0, "ks", ms=6)
    for node, other, _ in rotor.bearings:
        h = 0.6 * rmax
        y0 = -float(e["do_l"][min(node, e["L"].size - 1)]) / 2
        ax.add_patch(
            Polygon(
                [[z[node], y0], [z[node] - 0.02 * span, y0 - h], [z[node] + 0.02 * span, y0 - h]],
                closed=True,
                fc="tab:orange" if other is None else "tab:green",
                ec="k",
                lw=0.6,
            )
        )
    for j, zz in enumerate(z):
        ax.annotate(str(j), (zz, 1.15 * rmax), ha="center", fontsize=7)
    ax.set_xlim(z[0] - 0.05 * span, z[-1] + 0.05 * span)
    ax.set_ylim(-1.8 * rmax, 1.4 * rmax)
    ax.set_xlabel("axial position z [m]")
    ax.set_ylabel("radius [m]")
    ax.set_title("rotor model: shaft, disks (blue), bearings (orange: to ground), node numbers")
    return fig


def campbell_figure(speed, wd, forward, logdec, harmonics=(1,), critical=()):
    """Damped frequencies [Hz] vs speed [rpm]; forward solid, backward dashed; x: unstable."""
    from rotaflex.core.plotting import new_figure

    fig, ax = new_figure()
    rpm = np.asarray(speed) * RPM
    for k in range(wd.shape[1]):
        f = wd[:, k] * HZ
        fw = forward[:, k] >= 0.5
        ax.plot(rpm, np.where(fw, f, np.nan), "-", color=f"C{k % 10}", lw=1.2)
        ax.plot(rpm, np.where(~fw, f, np.nan), "--", color=f"C{k % 10}", lw=1.2)
        bad = logdec[:, k] < -2 * np.pi * STABILITY_TOL
        if np.any(bad):
            ax.plot(rpm[bad], f[bad], "x", color="r")
    for h in harmonics:
        ax.plot(rpm, h * np.asarray(speed) * HZ, ":k", lw=0.8)
        ax.annotate(f"{h}X", (rpm[-1], h * speed[-1] * HZ), fontsize=8)
    for c in critical:
        ax.plot(c["speed"] * RPM, c["frequency"] * HZ, "o", mfc="none", mec="k")
    ax.set_ylim(0, np.nanmax(wd) * HZ * 1.05)
    ax.set_xlabel("spin speed [rpm]")
    ax.set_ylabel("damped natural frequency [Hz]")
    ax.set_title("Campbell diagram (solid: forward, dashed: backward, o: critical, x: unstable)")
    ax.grid(alpha=0.3)
    return fig


def bode_figure(speed, amplitude: dict, phase: dict, peaks=()):
    """Amplitude [m] (log) and phase [deg] vs speed [rpm] per probe."""
    from rotaflex.core.plotting import new_figure

    fig, (a1, a2) = new_figure(2, 1, sharex=True)
    rpm = np.asarray(speed) * RPM
    for name, amp in amplitude.items():
        a1.semilogy(rpm, amp, label=name)
        a2.plot(rpm, np.degrees(np.unwrap(phase[name])), label=name)
    for p in peaks:
        a1.axvline(p["speed"] * RPM, color="0.6", lw=0.6)
    a1.set_ylabel("amplitude [m]")
    a2.set_ylabel("phase [deg]")
    a2.set_xlabel("spin speed [rpm]")
    a1.legend(fontsize=8)
    a1.grid(alpha=0.3)
    a2.grid(alpha=0.3)
    return fig


def static_figure(ds):
    """Deflection [um], shear force [N] and bending moment [N m] along the shaft, bearings marked."""
    from rotaflex.core.plotting import new_figure

    fig, axes = new_figure(3, 1, sharex=True, figsize=(7.4, 7.5))
    z, zc = ds["z"].values, ds["z_cut"].values
    zb = z[ds["bearing_node"].values] if ds.sizes.get("bearing", 0) else np.array([])
    styles = {"x": ("tab:blue", "x-z plane"), "y": ("tab:red", "y-z plane")}
    for ax_name, (color, plane) in styles.items():
        d = ds["deflection"].sel(axis=ax_name).values
        V = ds["shear"].sel(axis=ax_name).values
        M = ds["moment"].sel(axis=ax_name).values
        if np.any(d) or np.any(V):
            axes[0].plot(z, d * 1e6, "o-", ms=3, color=color, label=f"{ax_name} ({plane})")
            axes[1].plot(zc, V, color=color, label=f"V_{ax_name} ({plane})")
            axes[2].plot(zc, M, color=color, label=f"M ({plane})")
    for ax, lab in zip(axes, ("deflection [\u00b5m]", "shear force [N]", "bending moment [N m]"), strict=True):
        ax.axhline(0, color="k", lw=0.5)
        for zz in zb:
            ax.axvline(zz, color="tab:orange", lw=0.8, ls="--")
        ax.set_ylabel(lab)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, loc="best")
    axes[2].set_xlabel("axial position z [m] (dashed: bearings)")
    loads = ", ".join(
        f"{n} {np.hypot(*ds['reaction'].isel(bearing=i).values):.4g} N" for i, n in enumerate(ds["bearing_name"].values)
    )
    axes[0].set_title(f"static analysis; bearing loads: {loads}", fontsize=9)
    return fig


def frf_figures(ds) -> dict:
    """Bode (|H| log, phase) and Nyquist (Re, Im) of each FRF pair."""
    from rotaflex.core.plotting import new_figure

    unit = ds["amplitude"].attrs.get("units", "")
    kind = ds.attrs.get("kind", "receptance")
    f = ds["frequency_hz"].values
    fig, (a1, a2) = new_figure(2, 1, sharex=True, figsize=(7.4, 6.0))
    fig2, ax = new_figure(figsize=(6.0, 5.6))
    for j, lab in enumerate(ds["pair"].values):
        H = ds["H_real"].values[:, j] + 1j * ds["H_imag"].values[:, j]
        a1.semilogy(f, np.abs(H), color=f"C{j}", label=str(lab))
        a2.plot(f, np.degrees(np.angle(H)), color=f"C{j}", label=str(lab))
        ax.plot(H.real, H.imag, color=f"C{j}", label=str(lab))
    a1.set_ylabel(f"|{kind}| [{unit}]")
    a2.set_ylabel("phase [deg]")
    a2.set_yticks([-180, -90, 0, 90, 180])
    a2.set_xlabel("excitation frequency [Hz]")
    a1.set_title(f"FRF at {float(ds.attrs.get('speed_rpm', 0)):g} rpm (label: output / input DOF and node)")
    for a in (a1, a2):
        a.grid(alpha=0.3, which="both")
        a.legend(fontsize=8)
    ax.set_xlabel(f"Re H [{unit}]")
    ax.set_ylabel(f"Im H [{unit}]")
    ax.set_title("Nyquist plot")
    ax.axhline(0, color="k", lw=0.5)
    ax.axvline(0, color="k", lw=0.5)
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    return {"frf_bode": fig, "frf_nyquist": fig2}
