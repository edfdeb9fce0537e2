"""Figures of the API 617 stability report: Level I sweep, CSR map, Level II contributions."""

from __future__ import annotations

import numpy as np

from rotaflex.core.plotting import new_figure


def level1_figure(ds):
    """Log dec of the first forward mode vs applied cross-coupling, Q_A and Q_0 marked (API 684 style)."""
    fig, ax = new_figure()
    q, ld = ds["q"].values, ds["log_dec_level1"].values
    qa, q0 = float(ds["q_a"]), float(ds["q_0"])
    ax.plot(q / 1e6, ld, "-o", ms=3, label="first forward mode")
    ax.axhline(0.0, color="k", lw=0.8)
    ax.axhline(0.1, color="0.5", ls=":", lw=0.8, label="log dec 0.1")
    ax.axvline(qa / 1e6, color="C1", ls="--", label=f"Q_A = {qa / 1e6:.3g} MN/m")
    if np.isfinite(q0):
        ax.axvline(q0 / 1e6, color="C3", ls="--", label=f"Q_0 = {q0 / 1e6:.3g} MN/m (Q_0/Q_A = {q0 / qa:.3g})")
    ax.set_xlabel("applied cross-coupled stiffness Q [MN/m]")
    ax.set_ylabel("log decrement [-]")
    ax.set_title("API 617 Level I")
    ax.legend(fontsize=8)
    return fig


def csr_map_figure(csr: float, density: float):
    """The machine's point on the CSR vs mean gas density map (regions A and B)."""
    fig, ax = new_figure()
    rho = np.array([0.0, 16.53, 60.0])
    ax.plot(rho, [2.5, 2.5, 2.0], "k-", label="region A / B boundary")
    ax.plot([density], [csr], "o", color="C3", label=f"machine: {density:.3g} kg/m^3, CSR {csr:.3g}")
    ax.text(30.0, 1.2, "region A", ha="center", alpha=0.5)
    ax.text(30.0, 2.9, "region B", ha="center", alpha=0.5)
    ax.set_xlim(0.0, max(70.0, 1.2 * density))
    ax.set_ylim(0.0, max(3.5, 1.2 * csr))
    ax.set_xlabel("mean gas density [kg/m^3]")
    ax.set_ylabel("CSR = MCS / rigid-support critical speed")
    ax.set_title("API 617 Level I: CSR map")
    ax.legend(fontsize=8)
    return fig


def level2_figure(ds):
    """Log dec of the first forward mode per element combination (Level II)."""
    cases = [str(c) for c in ds["case"].values]
    ld = ds["log_dec_level2"].values
    fig, ax = new_figure()
    y = np.arange(len(cases))
    ax.barh(y, ld, color=["C3" if v < 0.1 else "C0" for v in ld])
    ax.axvline(0.1, color="k", ls=":", lw=0.8)
    ax.set_yticks(y, cases)
    ax.invert_yaxis()
    ax.set_xlabel("log decrement of the first forward mode [-]")
    ax.set_title("API 617 Level II at MCS")
    return fig
