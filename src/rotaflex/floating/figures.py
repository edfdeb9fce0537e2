"""Figures comparing floating-body solutions (matplotlib, Agg)."""

from __future__ import annotations

import numpy as np


def full_vs_perturbation_figure(time_full, euler_full, u_full, time_pert, euler_pert, u_pert, point: str = "tip"):
    """Attitude and elastic deflection of the full and the perturbation solution, and their
    difference.

    The two solutions agree to a few per cent of the deflection, so drawn over each other
    one hides the other: the perturbation solution is drawn as markers over the full one's
    lines, and the bottom panel shows the difference itself.

    Parameters
    ----------
    time_full, time_pert : (n,) and (m,) arrays
        Output times [s].
    euler_full, euler_pert : (n, 3) and (m, 3) arrays
        Euler 1-2-3 angles of the body frame [rad].
    u_full, u_pert : (n, 3) and (m, 3) arrays
        Elastic deflection of the point in the body frame [m]; drawn in mm, the difference in um.
    point : str
        The point's name in the labels.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from rotaflex.core.plotting import legend_outside, new_figure

    fig, ax = new_figure(3, 1, sharex=True, figsize=(8.4, 8.4))
    every = max(1, len(time_pert) // 40)  # markers sparse enough to see the line under them
    for a in range(3):
        c, name = f"C{a}", "xyz"[a]
        ax[0].plot(time_full, euler_full[:, a], c, lw=1.2, label=f"full, angle {a + 1}")
        ax[0].plot(
            time_pert[::every],
            euler_pert[::every, a],
            "o",
            mec=c,
            mfc="none",
            ms=4,
            label=f"perturbation, angle {a + 1}",
        )
        ax[1].plot(time_full, u_full[:, a] * 1e3, c, lw=0.8, label=f"full, u_{name}")
        ax[1].plot(
            time_pert[::every], u_pert[::every, a] * 1e3, "o", mec=c, mfc="none", ms=4, label=f"perturbation, u_{name}"
        )
        diff = np.interp(time_full, time_pert, u_pert[:, a]) - u_full[:, a]
        ax[2].plot(time_full, diff * 1e6, c, lw=0.8, label=f"u_{name}")
    ax[0].set_ylabel("Euler 1-2-3 angles [rad]")
    ax[0].set_title("attitude: full (lines) and perturbation solution (markers)", fontsize=9)
    ax[1].set_ylabel(f"{point} deflection\n(body frame) [mm]")
    ax[1].set_title(f"elastic deflection of the {point}: full (lines) and perturbation (markers)", fontsize=9)
    ax[2].set_ylabel("perturbation − full [µm]")
    ax[2].set_title(f"difference of the {point} deflections (perturbation − full)", fontsize=9)
    ax[2].set_xlabel("time [s]")
    for a in ax:
        a.grid(alpha=0.3)
        legend_outside(a)
    return fig
