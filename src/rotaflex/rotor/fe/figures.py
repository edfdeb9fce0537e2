"""Figures of the FE rotor: model sketch, Campbell diagram, Bode plot, orbits (matplotlib, Agg)."""

from __future__ import annotations

import numpy as np

from rotaflex.core.units import rad_s_to_rpm
from rotaflex.rotor.fe.modal import STABILITY_TOL
from rotaflex.rotor.fe.model import Rotor

HZ = 1 / (2 * np.pi)


def model_figure(rotor: Rotor):
    """Shaft profile (outer and inner radius), disks, bearings (triangles) and node numbers."""
    from rotaflex.core.plotting import new_figure

    fig, ax = new_figure()  # first, so that bench_startup --phases counts matplotlib's import as such
    from matplotlib.patches import Polygon, Rectangle

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
    stations = [  # from the stations alone: no bearing tables are needed to draw the supports
        (rotor.station(b.node, b.position, "bearing"), rotor.station(b.to_node, b.to_position, "bearing", False))
        for b in rotor.bearing
    ]
    for node, other in stations:
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


def campbell_figure(
    speed,
    wd,
    logdec,
    *,
    forward=None,
    lines=(("1X", 1.0),),
    marks=(),
    bands=(),
    frequency_limit_hz=None,
    colour=None,
    colour_label="",
    speed_label="spin speed [rpm]",
    marks_note="o: critical speed [rpm]",
):
    """Campbell diagram over a log-decrement panel, both against speed [rpm]: the one drawing
    of every Campbell dataset (:func:`rotaflex.rotor.fe.results.campbell_dataset`), FE rotor
    and machine alike.

    Top: damped frequencies [Hz] of the tracked modes, each labelled at its last speed (unless
    coloured by ``colour``); with ``forward`` (s, t) forward fractions, forward whirl solid and
    backward dashed. The excitation ``lines`` ``omega = factor Omega``, labelled where they
    leave the axes (at the right end beside the modes' labels, close labels spread apart, as
    the rotor's diagram always did: no second draw to measure them); ``marks`` circled.
    Bottom: each mode's logarithmic decrement with the 0 (stability) and 0.1 (API 617 Level II
    acceptance) lines; unstable points crossed in the top panel.

    Parameters
    ----------
    speed : ndarray (s,)
        Speeds [rad/s].
    wd, logdec : ndarray (s, t)
        Damped natural frequencies [rad/s] and logarithmic decrements [-] of the tracks.
    forward : ndarray (s, t), optional
        Forward fraction [-] (>= 0.5: forward whirl); None: no whirl sense (all solid).
    lines : iterable of (label, factor) or (label, factor, colour, linestyle)
        Excitation lines; factor [-] is the frequency per unit speed. Default style: black dotted.
    marks : iterable of dict
        Points ``{"speed" [rad/s], "frequency" [rad/s]}`` circled (crossings, critical speeds);
        those with ``"labelled": True`` get their speed [rpm] written beside them (skipped where
        it would overprint the one before).
    bands : iterable of (lo, hi)
        Operating ranges [rad/s], shaded on both panels with API 684's largest separation
        margins (16 % below the minimum, 26 % above the maximum speed) hatched beside them.
    frequency_limit_hz : float, optional
        Modes whose frequency stays above it [Hz] are left out, and the frequency axis stops there.
    colour : ndarray (s, t), optional
        A per-point quantity (e.g. a machine's mesh strain-energy fraction) drawn as coloured
        points over the tracks, with a colour bar labelled ``colour_label``.
    speed_label, marks_note : str
        The speed axis' label and what the circles mean (in the title).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from rotaflex.core.plotting import new_figure, shade_operating_bands

    fig, (ax, al) = new_figure(2, 1, sharex=True, figsize=(8.4, 7.6), height_ratios=(2.2, 1))
    speed = np.asarray(speed)
    rpm = rad_s_to_rpm(speed)
    f_all = wd * HZ
    shown = [
        k for k in range(wd.shape[1]) if frequency_limit_hz is None or np.nanmin(f_all[:, k]) <= frequency_limit_hz
    ]
    top = np.nanmax(f_all[:, shown]) * 1.08 if shown else 1.0
    if frequency_limit_hz is not None:  # the frequency axis is the range asked for
        top = frequency_limit_hz
    shade_operating_bands((ax, al), bands, margins=True)
    labels = []
    ld_top = 0.2
    for k in shown:
        f, color = f_all[:, k], f"C{k % 10}"
        fw = np.ones(f.shape, bool) if forward is None else forward[:, k] >= 0.5
        ax.plot(rpm, np.where(fw, f, np.nan), "-", color=color, lw=1.3)
        ax.plot(rpm, np.where(~fw, f, np.nan), "--", color=color, lw=1.3)
        al.plot(rpm, np.where(fw, logdec[:, k], np.nan), "-", color=color, lw=1.2)
        al.plot(rpm, np.where(~fw, logdec[:, k], np.nan), "--", color=color, lw=1.2)
        bad = logdec[:, k] < -2 * np.pi * STABILITY_TOL
        if np.any(bad):
            ax.plot(rpm[bad], f[bad], "x", color="r")
        ld_top = max(ld_top, float(np.nanmax(logdec[:, k])) if np.any(np.isfinite(logdec[:, k])) else 0.0)
        if colour is None and np.isfinite(f[-1]) and f[-1] <= top:  # coloured: points tell the modes apart
            sense = "" if forward is None else (" FW" if fw[-1] else " BW")
            labels.append([f[-1], f"{k}{sense} {f[-1]:.0f} Hz", color])
    if colour is not None and shown:
        vmax = max(0.05, float(np.nanmax(colour)))
        for k in shown:
            sc = ax.scatter(rpm, f_all[:, k], c=colour[:, k], s=6, cmap="viridis", vmin=0, vmax=vmax, zorder=3)
        fig.colorbar(sc, ax=ax, label=colour_label)
    for line in lines:
        name, h = line[0], float(line[1])
        c, ls = line[2:4] if len(line) > 2 else ("k", ":")
        ax.plot(rpm, h * speed * HZ, ls, color=c, lw=0.9)
        if h * speed[-1] * HZ < top * 0.97:  # ends at the right: labelled beside the modes
            labels.append([h * speed[-1] * HZ, str(name), c])
        else:  # leaves through the top: labelled there, left of the line
            yh = top * 0.97
            ax.annotate(str(name), (rad_s_to_rpm(yh / (h * HZ)), yh), fontsize=7, color=c, ha="right", va="bottom")
    last = -np.inf
    for c in sorted(marks, key=lambda c: c["speed"]):
        if c["frequency"] * HZ > top:
            continue
        ax.plot(rad_s_to_rpm(c["speed"]), c["frequency"] * HZ, "o", mfc="none", mec="k", ms=7)
        if c.get("labelled") and rad_s_to_rpm(c["speed"]) > last * 1.04:  # skip labels that would overprint
            last = rad_s_to_rpm(c["speed"])
            ax.annotate(
                f"{last:.0f}", (last, c["frequency"] * HZ), fontsize=7, xytext=(4, -10), textcoords="offset points"
            )
    ax.set_ylim(0, top)
    ax.set_xlim(rpm[0], rpm[-1] * 1.22)  # room right of the data for the labels
    ax.set_ylabel("damped natural frequency [Hz]")
    whirl = "solid: forward, dashed: backward whirl" if forward is not None else ""
    ax.set_title(f"Campbell diagram ({'; '.join(t for t in (whirl, marks_note, 'x: unstable') if t)})", fontsize=9)
    ax.grid(alpha=0.3)
    al.axhline(0.0, color="k", lw=1.4, label="0: stability limit")  # black: C3 is a mode's red
    al.axhline(0.1, color="k", lw=0.9, ls="-.", label="0.1: API 617 Level II")
    ld_min = min(-0.05, float(np.nanmin(logdec[:, shown]))) if shown else -0.05
    cap = 2.0  # a few well-damped modes would otherwise squash the ones near zero
    al.set_ylim(max(ld_min * 1.1, -cap), min(ld_top * 1.1, cap))
    al.set_ylabel("log decrement [-]" + (f" (axis cut at {cap:g})" if ld_top * 1.1 > cap else ""))
    al.set_xlabel(speed_label)
    al.grid(alpha=0.3)
    handles, names = ax.get_legend_handles_labels()
    h2, n2 = al.get_legend_handles_labels()
    keep = [i for i, n in enumerate(n2) if n not in names]
    # below the axes: a legend inside would hide modes wherever it sits
    fig.legend(
        handles + [h2[i] for i in keep], names + [n2[i] for i in keep], loc="outside lower center", ncol=4, fontsize=8
    )
    gap = 0.035 * top  # labels at the right end: close ones spread apart upwards (no extra draw)
    labels.sort(key=lambda t: t[0])
    for i in range(1, len(labels)):
        labels[i][0] = max(labels[i][0], labels[i - 1][0] + gap)
    for y, text, color in labels:
        ax.annotate(
            text,
            (rpm[-1], y),
            xytext=(3, 0),
            textcoords="offset points",
            fontsize=7,
            color=color,
            va="center",
            annotation_clip=False,
        )
    return fig


def bode_figure(speed, amplitude: dict, phase: dict, peaks=()):
    """Amplitude [um] (linear) and phase [deg] vs speed [rpm] per labelled curve; peaks marked."""
    from rotaflex.core.plotting import new_figure

    fig, (a1, a2) = new_figure(2, 1, sharex=True)
    rpm = rad_s_to_rpm(np.asarray(speed))
    for name, amp in amplitude.items():
        a1.plot(rpm, np.asarray(amp) * 1e6, label=name)
        a2.plot(rpm, np.degrees(np.unwrap(phase[name])), label=name)
    for p in peaks:
        a1.axvline(rad_s_to_rpm(p["speed"]), color="0.6", lw=0.6)
        a1.annotate(
            f"{rad_s_to_rpm(p['speed']):.0f} rpm",
            (rad_s_to_rpm(p["speed"]), 0),
            fontsize=7,
            xytext=(3, 3),
            textcoords="offset points",
        )
    a1.set_ylabel("amplitude [\u00b5m]")
    a1.set_ylim(bottom=0)
    a2.set_ylabel("phase [deg]")
    a2.set_xlabel("spin speed [rpm]")
    a1.legend(fontsize=8)
    a1.grid(alpha=0.3)
    a2.grid(alpha=0.3)
    return fig


def unbalance_bode_figure(ds, peaks=(), bands=(), limit=None):
    """Unbalance response per probe: peak-to-peak x, y and orbit major axis [um] (linear), phases.

    ``limit`` [m]: the vibration limit (peak-to-peak) drawn as a line; ``bands`` [(lo, hi) rad/s]
    shaded; peaks marked with their speed and amplification factor.
    """
    from rotaflex.core.plotting import new_figure, shade_operating_bands

    fig, (a1, a2) = new_figure(2, 1, sharex=True, figsize=(8.4, 7.0), height_ratios=(2, 1))
    rpm = rad_s_to_rpm(ds["speed"].values)
    um = 1e6
    shade_operating_bands((a1, a2), bands, alpha=0.12)
    for j, p in enumerate(ds["probe"].values):
        X = ds["x_real"].values[:, j] + 1j * ds["x_imag"].values[:, j]
        Y = ds["y_real"].values[:, j] + 1j * ds["y_imag"].values[:, j]
        c = f"C{j % 10}"
        a1.plot(rpm, 2 * ds["major_axis"].values[:, j] * um, "-", color=c, lw=1.8, label=f"node {p}: major axis")
        a1.plot(rpm, 2 * np.abs(X) * um, "--", color=c, lw=1.0, label=f"node {p}: x")
        a1.plot(rpm, 2 * np.abs(Y) * um, ":", color=c, lw=1.2, label=f"node {p}: y")
        if "probe_amplitude" in ds:
            for a_i, ang in enumerate(ds["angle"].values):
                a1.plot(
                    rpm,
                    2 * ds["probe_amplitude"].values[:, j, a_i] * um,
                    "-.",
                    color=c,
                    lw=0.7,
                    label=f"node {p}: probe {ang:g} deg",
                )
        a2.plot(rpm, np.degrees(np.unwrap(np.angle(X))), "--", color=c, lw=1.0, label=f"node {p}: x")
        a2.plot(rpm, np.degrees(np.unwrap(np.angle(Y))), ":", color=c, lw=1.2, label=f"node {p}: y")
    if limit is not None:
        a1.axhline(limit * um, color="r", lw=1.2, label=f"API 617 limit {limit * um:.1f} \u00b5m p-p")
    a1.set_ylim(0, a1.get_ylim()[1] * 1.15)  # head room for the peak tags
    span = float(np.ptp(rpm)) or 1.0
    taken: list[list[tuple[float, float]]] = []  # per row of tags: the speed ranges they cover
    for p in sorted(peaks, key=lambda p: p["speed"]):
        x = rad_s_to_rpm(p["speed"])
        a1.axvline(x, color="0.5", lw=0.6)
        kind = p.get("kind", "resonance")
        tag = f"AF {p['af']:.1f}" if kind == "resonance" else kind.replace("half-power band", "band")
        probe = f", node {p['probe']}" if "probe" in p else ""
        right = kind == "rising at the range end"
        # a tag is about a third of the axis wide: close peaks go to the next row down
        cover = (x - 0.32 * span, x) if right else (x, x + 0.32 * span)
        row = next((i for i, r in enumerate(taken) if all(b < cover[0] or a > cover[1] for a, b in r)), len(taken))
        taken += [[]] * (row + 1 - len(taken))
        taken[row] = [*taken[row], cover]
        a1.annotate(
            f"{x:.0f} rpm{probe}\n{tag}",
            (x, a1.get_ylim()[1]),
            fontsize=7,
            ha="right" if right else "left",
            va="top",
            xytext=(-3 if right else 3, -3 - 22 * row),
            textcoords="offset points",
        )
    a1.set_ylabel("amplitude, peak-to-peak [\u00b5m]")
    a2.set_ylabel("phase [deg] (lag < 0)")
    a2.set_xlabel("spin speed [rpm]")
    a1.grid(alpha=0.3)
    a2.grid(alpha=0.3)
    a1.set_title(
        "unbalance response, peak-to-peak (solid: orbit major axis; dashed: x; dotted: y)\n"
        "tags: speed, governing probe (largest response) and AF of each peak",
        fontsize=8,
    )
    # outside the axes, on the right: inside it would hide a probe's curve somewhere
    fig.legend(*a1.get_legend_handles_labels(), loc="outside right upper", fontsize=7)
    return fig


def orbit_figure(ds, peaks=()):
    """Orbits of every probe [um] over one revolution at each peak's speed (one panel per peak,
    at most 4; without peaks, at the speed of the largest response of any probe)."""
    from rotaflex.core.plotting import new_figure

    X = ds["x_real"].values + 1j * ds["x_imag"].values  # (speed, probe)
    Y = ds["y_real"].values + 1j * ds["y_imag"].values
    major = ds["major_axis"].values
    speed = ds["speed"].values
    if peaks:
        picks = [(int(np.argmin(np.abs(speed - p["speed"]))), p.get("probe")) for p in peaks][:4]
    else:
        i, j = np.unravel_index(int(np.argmax(major)), major.shape)
        picks = [(int(i), int(ds["probe"].values[j]))]
    fig, axes = new_figure(1, len(picks), squeeze=False, figsize=(3.4 * len(picks) + 1.6, 3.9))
    th = np.exp(1j * np.linspace(0, 2 * np.pi, 181))
    for ax, (i, gov) in zip(axes[0], picks, strict=True):
        for j, p in enumerate(ds["probe"].values):
            x, y = (X[i, j] * th).real * 1e6, (Y[i, j] * th).real * 1e6
            ax.plot(x, y, color=f"C{j % 10}", lw=1.8 if p == gov else 1.0, label=f"node {p}")
            ax.plot(x[0], y[0], "o", color=f"C{j % 10}", ms=3)  # the rotor's 0 deg mark at t = 0
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel("x [\u00b5m]")
        ax.set_title(
            f"{rad_s_to_rpm(speed[i]):.0f} rpm (nearest sample)" + (f"\nnode {gov} governs" if gov is not None else ""),
            fontsize=8,
        )
        ax.grid(alpha=0.3)
        ax.axhline(0, color="k", lw=0.4)
        ax.axvline(0, color="k", lw=0.4)
    axes[0, 0].set_ylabel("y [\u00b5m]")
    fig.legend(*axes[0, 0].get_legend_handles_labels(), loc="outside right upper", fontsize=7)
    fig.suptitle("unbalance orbits at the response peaks (dot: t = 0)", fontsize=9)
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
            if "deflection_curve" in ds:
                axes[0].plot(zc, ds["deflection_curve"].sel(axis=ax_name).values * 1e6, "-", color=color)
                axes[0].plot(z, d * 1e6, "o", ms=3, color=color, label=f"{ax_name} ({plane}), o: nodes")
            else:
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
    per_pair = ds["pair_unit"].values if "pair_unit" in ds.coords else None
    if per_pair is not None:  # pairs of different units: each in the legend
        unit = ""
    kind = ds.attrs.get("kind", "receptance")
    f = ds["frequency_hz"].values
    fig, (a1, a2) = new_figure(2, 1, sharex=True, figsize=(7.4, 6.0))
    fig2, ax = new_figure(figsize=(6.0, 5.6))
    Hs = ds["H_real"].values + 1j * ds["H_imag"].values  # (frequency, pair)
    # the Nyquist axes in a prefixed unit (um/N, not 0.00005 m/N: long tick labels collide)
    big = float(np.nanmax(np.abs(Hs))) if Hs.size and np.isfinite(Hs).any() else 1.0
    k = int(np.clip(np.floor(np.log10(big) / 3) * 3, -12, 0)) if big > 0 else 0
    nq_unit = {0: "", -3: "m", -6: "\u00b5", -9: "n", -12: "p"}[k] + unit if unit else f"1e{k}, unit in the legend"
    for j, lab in enumerate(ds["pair"].values):
        H = Hs[:, j]
        lab = lab if per_pair is None else f"{lab} [{per_pair[j]}]"
        a1.semilogy(f, np.abs(H), color=f"C{j}", label=str(lab))
        a2.plot(f, np.degrees(np.angle(H)), color=f"C{j}", label=str(lab))
        ax.plot(H.real / 10.0**k, H.imag / 10.0**k, color=f"C{j}", label=str(lab))
    a1.set_ylabel(f"|{kind}| [{unit or 'unit in the legend'}]")
    a2.set_ylabel("phase [deg]")
    a2.set_yticks([-180, -90, 0, 90, 180])
    a2.set_xlabel("excitation frequency [Hz]")
    a1.set_title(f"FRF at {float(ds.attrs.get('speed_rpm', 0)):g} rpm (label: output / input DOF and node)")
    for a in (a1, a2):
        a.grid(alpha=0.3, which="both")
        a.legend(fontsize=8)
    ax.set_xlabel(f"Re H [{nq_unit}]")
    ax.set_ylabel(f"Im H [{nq_unit}]")
    ax.set_title("Nyquist plot")
    ax.axhline(0, color="k", lw=0.5)
    ax.axvline(0, color="k", lw=0.5)
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    return {"frf_bode": fig, "frf_nyquist": fig2}


def mode_shapes_figure(ds):
    """Each mode in both bending planes: x(z) and y(z) at the instant of largest deflection, and
    the orbit envelope +-a(z) (semi-major axis); title with frequency, damping and whirl sense."""
    from rotaflex.core.plotting import new_figure

    nm = ds.sizes["mode"]
    ncol = 2 if nm > 1 else 1
    nrow = (nm + ncol - 1) // ncol
    fig, axes = new_figure(nrow, ncol, squeeze=False, sharex=True, figsize=(9.0, 2.3 * nrow + 0.6))
    z = ds["z"].values
    sh = ds["shape_real"].values + 1j * ds["shape_imag"].values  # (mode, node, dof)
    th = np.linspace(0, np.pi, 73)
    for k in range(nm):
        ax = axes.flat[k]
        X, Y = sh[k, :, 0], sh[k, :, 1]
        a = 0.5 * (np.abs(X + 1j * Y) + np.abs(X - 1j * Y))
        scale = np.max(a) or 1.0
        e = np.exp(1j * th)[:, None]
        t = int(np.argmax(np.sum((X * e).real ** 2 + (Y * e).real ** 2, 1)))
        ax.fill_between(z, -a / scale, a / scale, color="0.85", label="orbit envelope")
        ax.plot(z, (X * e[t]).real / scale, "-o", ms=2.5, color="tab:blue", label="x (x-z plane)")
        ax.plot(z, (Y * e[t]).real / scale, "-s", ms=2.5, color="tab:red", label="y (y-z plane)")
        ax.axhline(0, color="k", lw=0.4)
        f = float(ds["damped_frequency"][k]) / (2 * np.pi)
        zeta, whirl = float(ds["damping_ratio"][k]), ds["whirl"].values[k]
        ax.set_title(f"mode {int(ds['mode'].values[k])}: {f:.2f} Hz, \u03b6 = {zeta:.3g}, {whirl} whirl", fontsize=8)
        ax.set_ylim(-1.15, 1.15)
        ax.tick_params(labelsize=7)
        ax.grid(alpha=0.3)
    for ax in list(axes.flat)[nm:]:
        ax.set_visible(False)
    # below the panels: inside one it would hide the shape where the mode is largest
    fig.legend(*axes.flat[0].get_legend_handles_labels(), loc="outside lower center", ncol=3, fontsize=7)
    for ax in axes[-1]:
        ax.set_xlabel("z [m]")
    fig.suptitle(
        f"mode shapes at {rad_s_to_rpm(float(ds['speed'])):.0f} rpm (normalised to the largest orbit)", fontsize=9
    )
    return fig


def ucs_bearing_line(label: str, el, ratio: float = 1.0) -> list:
    """The UCS figure's stiffness line of a bearing element (``[]`` for a computed kind, a seal
    or magnetic bearing, which has no table): ``[(label, speeds [rad/s] or None, kxx, kyy)]``,
    a whirl table at its lowest frequency; ``ratio``: the rotor's speed per drive speed (a
    machine's map is drawn against the drive speed)."""
    if getattr(el, "k", None) is None:
        return []
    k = el.k if el.k.ndim == 3 else el.k[:, 0]
    speeds = None if el.speeds is None else np.asarray(el.speeds) / ratio
    return [(label, speeds, k[:, 0, 0], k[:, 1, 1])]


def ucs_figure(ds, bearings=()):
    """Critical speeds [rpm] vs isotropic bearing stiffness, with each bearing's kxx, kyy overlaid.

    ``bearings``: (label, speeds [rad/s] or None, kxx, kyy) per bearing; constant coefficients
    are vertical lines, tabulated ones curves k(speed); where they cross a critical-speed line
    is where that bearing puts the critical.
    """
    from rotaflex.core.plotting import new_figure

    fig, ax = new_figure(figsize=(7.4, 5.2))
    crit = rad_s_to_rpm(ds["critical_speed"].values)
    for k in range(ds.sizes["mode"]):
        ax.loglog(ds["stiffness"], crit[:, k], color=f"C{k}", lw=1.5, label=f"critical {k}")
    lo, hi = np.nanmin(crit), np.nanmax(crit)
    drawn: dict[float, str] = {}
    for label, sp, kxx, kyy in bearings:
        for kk, ls, axis in ((kxx, "--", "kxx"), (kyy, ":", "kyy")):
            kk = np.atleast_1d(kk)
            if sp is None or kk.size == 1:
                if float(kk[0]) in drawn:  # equal bearings: one line
                    continue
                drawn[float(kk[0])] = label
                ax.axvline(kk[0], color="k", ls=ls, lw=0.9, label=f"{label} {axis} = {kk[0]:.3g} N/m")
            else:
                ax.plot(kk, rad_s_to_rpm(np.asarray(sp)), ls, color="k", lw=1.0, label=f"{label} {axis}(speed)")
    ax.set_ylim(lo * 0.7, hi * 1.3)
    ax.set_xlabel("bearing stiffness [N/m]")
    ax.set_ylabel("undamped critical speed [rpm]")
    ax.set_title("undamped critical speed map with the bearings' stiffness", fontsize=9)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7, loc="upper left")
    return fig


def fluid_film_figure(ds):
    """Fluid-film bearing tables (``ff_*`` variables of a result) vs speed: the 8 coefficients,
    eccentricity ratio and attitude angle; colour per coefficient, line style per bearing, one
    legend outside the panels (inside, it would hide a curve somewhere)."""
    from matplotlib.lines import Line2D

    from rotaflex.core.plotting import new_figure

    fig, axes = new_figure(2, 2, sharex=True, figsize=(10.0, 7.2))
    colors = {"xx": "tab:blue", "xy": "tab:orange", "yx": "tab:green", "yy": "tab:red"}
    # the cross terms drawn wide under narrow: equal ones (c_xy = c_yx) stay both visible
    width = {"xx": 1.5, "xy": 3.2, "yx": 1.3, "yy": 1.5}
    styles = ("-", "--", ":", "-.")
    handles = [Line2D([], [], color=c, lw=width[ij], label=f"{ij}") for ij, c in colors.items()]
    for b, name in enumerate(ds["fluid_film"].values):
        t = ds.isel(fluid_film=b)
        rpm, ls = t["ff_speed_rpm"].values, styles[b % len(styles)]
        load = np.hypot(float(t["ff_load_x"]), float(t["ff_load_y"]))
        for ij, color in colors.items():
            alpha = 0.55 if ij == "xy" else 1.0
            axes[0, 0].plot(rpm, t[f"ff_k{ij}"].values / 1e6, ls, color=color, lw=width[ij], alpha=alpha)
            axes[0, 1].plot(rpm, t[f"ff_c{ij}"].values / 1e3, ls, color=color, lw=width[ij], alpha=alpha)
        axes[1, 0].plot(rpm, t["ff_eccentricity_ratio"].values, ls, color="k")
        axes[1, 1].plot(rpm, t["ff_attitude_angle"].values, ls, color="k")
        handles.append(Line2D([], [], color="k", ls=ls, label=f"{name} ({load:.4g} N)"))
    labels = ("stiffness k_ij [MN/m]", "damping c_ij [kN s/m]", "eccentricity ratio e/c [-]", "attitude angle [deg]")
    for ax, lab in zip(axes.flat, labels, strict=True):
        ax.set_ylabel(lab)
        ax.grid(alpha=0.3)
    for ax in axes[1]:
        ax.set_xlabel("speed [rpm]")
    axes[0, 0].axhline(0, color="k", lw=0.5)
    axes[0, 1].axhline(0, color="k", lw=0.5)
    fig.legend(handles=handles, loc="outside lower center", ncol=len(handles), fontsize=8)
    fig.suptitle(
        "fluid-film bearing coefficients (linearised about the static equilibrium); colour: ij, style: bearing",
        fontsize=10,
    )
    return fig


def _probe_name(p) -> str:
    """A probe's label: ``node 4`` (a rotor's node number) or the machine's ``pump:5``."""
    return f"node {p}" if isinstance(p, (int, np.integer)) else str(p)


def transient_figures(ds):
    """Time response (x of every probe over time, the (drive) speed below) and orbits (y over x)
    of a transient dataset (``displacement`` (time, probe, axis), ``speed`` [rad/s]): the
    figures of ``rotor transient`` and ``system transient``. Displacements in um."""
    from rotaflex.core.plotting import new_figure

    um = 1e6

    fig, (a1, a2) = new_figure(2, 1, sharex=True)
    for p in ds["probe"].values:
        a1.plot(ds["time"], ds["displacement"].sel(probe=p, axis="x") * um, lw=0.6, label=f"{_probe_name(p)} x")
    a1.set_ylabel("x [\u00b5m]")
    a1.legend(fontsize=8)
    a2.plot(ds["time"], rad_s_to_rpm(ds["speed"]))
    a2.set_ylabel("speed [rpm]")
    a2.set_xlabel("time [s]")
    fig2, ax = new_figure()
    for p in ds["probe"].values:
        ax.plot(
            ds["displacement"].sel(probe=p, axis="x") * um,
            ds["displacement"].sel(probe=p, axis="y") * um,
            lw=0.5,
            label=_probe_name(p),
        )
    ax.set_aspect("equal")
    ax.set_xlabel("x [\u00b5m]")
    ax.set_ylabel("y [\u00b5m]")
    ax.legend(fontsize=8)
    return fig, fig2
