"""Steady-state gear dynamics of the paper's pair: elastic-tooth window model vs lumped model.

Used by ``rotaflex reproduce gear`` (one FigureEntry). The paper stops at one engagement; this
entry checks the continuous-meshing model built on its FE teeth (docs/gear-steady-state.md):

* massless teeth without corner contact = the lumped torsional model driven by ``gear
  static``'s mesh-stiffness table (two codes, one physics);
* a slow roll of a relieved pair = ``gear static``'s loaded transmission error;
* the default model's resonance (light load, heavy damping, no contact loss) at the lumped
  model's;
* the energy balance with damping and tooth modes.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np

from rotaflex.core.report import Check, FigureEntry
from rotaflex.gear.pair import paper

E, NU = paper.YOUNGS_MODULUS, paper.POISSON_RATIO
RHO = 7800.0


def _system(table, g, zeta=0.07, drive="motor"):
    from rotaflex.gear.models.chain import TorsionalSystem

    return TorsionalSystem(
        mesh=table,
        teeth=(g.teeth, g.teeth),
        base_radius=(g.base_radius,) * 2,
        inertia=(paper.DISK_INERTIA,) * 2,
        mesh_damping_ratio=zeta,
        drive=drive,
        motor_slope=0.5 if drive == "motor" else 0.0,
    )


def _peak(speeds, y):
    i = int(np.clip(np.argmax(y), 1, len(y) - 2))
    a, b, c = y[i - 1 : i + 2]
    return speeds[i] + 0.5 * (a - c) / (a - 2 * b + c) * (speeds[1] - speeds[0])


def comparison(dom: Path, *, fast: bool = False) -> FigureEntry:
    """Run the checks and draw K_v and DTE vs speed of both models."""
    import xarray as xr

    from rotaflex.core.plotting import new_figure, save_figure
    from rotaflex.gear.models import chain as tor
    from rotaflex.gear.models.mesh_stiffness import loaded_mesh_table, mesh_table_from_static
    from rotaflex.gear.models.window import build_window_model
    from rotaflex.gear.pair.geometry import ProfileRelief, center_distance_no_backlash
    from rotaflex.gear.pair.tooth_mesh import build_tooth_mesh
    from rotaflex.gear.solvers import window_run as wr
    from rotaflex.gear.solvers.steady_driver import sweep_steady
    from rotaflex.gear.static.loaded_te import loaded_te, pair_line
    from rotaflex.gear.static.tooth_analysis import mesh_stiffness

    g = paper.geometry()
    a = center_distance_no_backlash(g, g)
    mesh = build_tooth_mesh(g)
    torque = paper.TORQUE
    force = torque / g.base_radius
    line = pair_line(g, g, mesh, mesh, a, force, (E, NU, E, NU))
    lumped = _system(mesh_table_from_static(mesh_stiffness(g, g, E, NU, torque=torque), g.teeth), g)
    own = _system(loaded_mesh_table(line, force), g)
    window = build_window_model(own, line, (mesh, mesh), (RHO, RHO))
    # the K_v / DTE sweeps are drawn, not checked (the checks are the runs below): fast mode
    # draws them every 2,000 rpm
    speeds = np.linspace(2000.0, 22000.0, 11 if fast else 40)
    sw = {
        "lumped (gear static table)": sweep_steady(lumped, torque, speeds).dataset,
        "elastic teeth, massless": sweep_steady(window, torque, speeds).dataset,
    }
    if not fast:
        sw["elastic teeth, 3 tooth modes"] = sweep_steady(
            build_window_model(own, line, (mesh, mesh), (RHO, RHO), n_modes=3), torque, speeds
        ).dataset

    # slow roll of a relieved pair vs its loaded static TE
    s_a = line.s_start
    r0 = math.sqrt(g.base_radius**2 + (s_a + g.base_pitch) ** 2)
    gr = dataclasses.replace(g, tip_relief=ProfileRelief(6e-6, r0))
    mr = build_tooth_mesh(gr)
    lr = pair_line(gr, gr, mr, mr, a, force, (E, NU, E, NU))
    slow = build_window_model(
        _system(loaded_mesh_table(lr, force), g, drive="constant_speed"), lr, (mr, mr), (RHO, RHO), corner_contact=False
    )
    h = wr.simulate(slow, tor.OperatingPoint(100.0, torque), 3)
    spc = h["spc"]
    static = loaded_te(lr, s_a + np.arange(spc) / spc * gr.base_pitch, force)["te"]
    roll_err = float(np.abs(h["dte"][2 * spc : 3 * spc] - static).max() / static.mean())

    # light load, heavy damping: no contact loss, resonance of the default model vs lumped
    light = 5.0
    ll = pair_line(g, g, mesh, mesh, a, light / g.base_radius, (E, NU, E, NU))
    lin_l = _system(mesh_table_from_static(mesh_stiffness(g, g, E, NU, torque=light), g.teeth), g, zeta=0.25)
    lin_w = build_window_model(
        _system(loaded_mesh_table(ll, light / g.base_radius), g, zeta=0.25), ll, (mesh, mesh), (RHO, RHO)
    )
    sp = np.arange(11000.0, 20001.0, 500.0 if not fast else 1000.0)
    up = ("up",)
    dl, dw = (
        sweep_steady(lin_l, light, sp, directions=up).dataset,
        sweep_steady(lin_w, light, sp, directions=up).dataset,
    )
    plain = build_window_model(
        _system(loaded_mesh_table(ll, light / g.base_radius), g, zeta=0.25),
        ll,
        (mesh, mesh),
        (RHO, RHO),
        corner_contact=False,
    )
    same = sweep_steady(plain, light, sp, directions=up).dataset
    kv_same = float(np.abs(same.dynamic_factor / dl.dynamic_factor - 1).max())
    peak_l, peak_w = _peak(sp, dl.dte_h1.values[0]), _peak(sp, dw.dte_h1.values[0])
    loss = float(max(dl.contact_loss_fraction.max(), dw.contact_loss_fraction.max()))

    # energy with damping, tooth modes and corner contact
    toothed = build_window_model(own, line, (mesh, mesh), (RHO, RHO), n_modes=2)
    op = tor.OperatingPoint(10000.0, torque)
    _, st = wr.steady_state(toothed, op)
    eb = wr.energy_balance(toothed, op, wr.simulate(toothed, op, 10, steps_per_cycle=1600, state=st))
    energy = abs(eb["residual"]) / eb["dissipated"]

    fig, ax = new_figure(2, 1, sharex=True, figsize=(6.8, 7.0))
    for i, (name, ds) in enumerate(sw.items()):
        for d, ls in (("up", "-"), ("down", "--")):
            one = ds.sel(direction=d)
            lab = f"{name}, {d}"
            ax[0].plot(speeds, one.dynamic_factor, ls=ls, color=f"C{i}", marker=".", label=lab)
            ax[1].plot(speeds, one.dte_pp * 1e6, ls=ls, color=f"C{i}", marker=".", label=lab)
    f_n = float(tor.natural_frequencies(lumped)["frequency"][0])
    for a_ in ax:
        for hh in (1, 2):
            a_.axvline(60 * f_n / (hh * g.teeth), color="gray", ls=":", lw=1)
        a_.grid(alpha=0.3)
    ax[0].set_ylabel("dynamic factor [-]")
    ax[1].set(xlabel="pinion speed [rpm]", ylabel="DTE peak-to-peak [um]")
    ax[0].legend(fontsize=7)
    fig.suptitle(f"Paper pair, 22.25 N m, zeta 0.07 (mesh mode {f_n:.0f} Hz: dotted 1x, 2x)")
    image = dom / "gear_steady_elastic_teeth.png"
    save_figure(fig, image)
    data = xr.concat(list(sw.values()), dim="model").assign_coords(model=list(sw))
    data.drop_attrs().to_netcdf(dom / "gear_steady_elastic_teeth.nc")
    checks = [
        Check(
            "light load: massless teeth without corner contact vs lumped model from gear static: max |K_v ratio - 1|",
            kv_same,
            "",
            "< 5e-3",
            kv_same < 5e-3,
            "same physics through two codes (per-pair window vs one mesh-stiffness table)",
        ),
        Check(
            "slow roll (100 rpm) of a 6 um tip-relieved pair vs gear static's loaded TE: max error / mean TE",
            roll_err,
            "",
            "< 5e-3",
            roll_err < 5e-3,
        ),
        Check(
            "light load (5 N m, zeta 0.25), default elastic teeth vs lumped: DTE 1x resonance peak ratio - 1",
            abs(peak_w / peak_l - 1),
            "",
            "< 0.03 and no contact loss",
            abs(peak_w / peak_l - 1) < 0.03 and loss == 0.0,
            f"peaks {peak_w:.0f} / {peak_l:.0f} rpm",
        ),
        Check(
            "energy balance, 2 tooth modes, corner contact, 10,000 rpm: |residual| / dissipated",
            energy,
            "",
            "< 0.01",
            energy < 0.01,
        ),
    ]
    return FigureEntry(
        label="Steady state (beyond the paper)",
        caption="K_v and DTE vs speed of the paper's pair: FE teeth in a travelling window vs the lumped model",
        image="gear/gear_steady_elastic_teeth.png",
        data="gear/gear_steady_elastic_teeth.nc",
        description=(
            "Continuation sweeps up and down. The window model carries the FE tooth pairs of gear static "
            "(premature tip-corner contact; massless teeth, and 3 tooth modes in full mode); the lumped "
            "model the mesh-stiffness table. See docs/gear-steady-state.md."
        ),
        checks=checks,
    )
