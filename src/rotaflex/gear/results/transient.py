"""Results of ``rotaflex gear simulate``: the dataset builder and the figures.

:func:`build_dataset` turns a :class:`rotaflex.gear.solvers.registry.SolverOutput` into an xarray
Dataset with units (per-pair variables carry a ``pair`` dimension when there are several
contact pairs), adds the transmission error and the fillet stress, relabels a run with
``driver = "B"`` (simulated as the mirror image, :func:`mirror_driver_b`), and runs the result's
own checks (energy balance, tie residual): a result that fails one has status
``"failed_check"`` and names the check.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from rotaflex.core.result import Result, register_result
from rotaflex.core.units import rad_to_deg
from rotaflex.gear.models.fe_pair import torque_ramp


@register_result
class GearResult(Result):
    """Dynamic contact of a spur-gear pair (one elastic tooth per gear)."""

    kind = "gear"

    def summary(self):
        ds = self.dataset
        out = super().summary()
        keep = {k: out[k] for k in ("status", "wall_time")}
        for name in (
            "peak_contact_force",
            "mean_single_pair_force",
            "nominal_force",
            "dynamic_factor",
            "energy_balance_error",
            "energy_balance_abs",
            "steps",
            "time_per_step",
            "impacts",
            "max_tie_residual",
            "dte_peak_to_peak",
            "root_stress_peak",
            "mean_total_force",
            "teeth_per_gear",
        ):
            if name in ds:
                keep[name] = {"value": ds[name].item(), "unit": ds[name].attrs.get("units", "")}
        return keep

    def plot(self):
        from rotaflex.core.plotting import new_figure

        ds = self.dataset
        if "pair" in ds.dims:
            return plot_multi(ds)
        figs = {}
        ang = rad_to_deg(ds["rotation_angle"].sel(gear="A").values)
        fig, ax = new_figure()
        ax.plot(ang, ds["contact_force"].values, lw=0.8, label="contact force")
        ax.plot(ang, ds["nominal_force_ramp"].values, "k--", lw=0.8, label="quasi-static tau_driver / r_b")
        ax.set_xlabel("rotation angle of gear A [deg]")
        ax.set_ylabel("contact force [N]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
        figs["contact_force"] = fig
        figs.update(history_figures(ds, "normal gap [um]"))
        if "transmission_error" in ds:
            figs["transmission_error"] = line_figure(
                ang,
                ds["transmission_error"].values * 1e6,
                ANGLE_LABEL,
                "DTE r_bA theta_A - r_bB theta_B [um] (> 0: B lags)",
            )
        if "root_stress" in ds:
            fig, ax = new_figure()
            for g in ("A", "B"):
                ax.plot(ang, ds["root_stress"].sel(gear=g).values / 1e6, lw=0.8, label=f"gear {g}, loaded fillet")
                ax.plot(
                    ang,
                    ds["root_stress_opposite"].sel(gear=g).values / 1e6,
                    lw=0.8,
                    ls="--",
                    label=f"gear {g}, opposite fillet",
                )
            ax.set_xlabel("rotation angle of gear A [deg]")
            ax.set_ylabel("fillet tangential stress, 30-deg point [MPa]")
            ax.grid(alpha=0.3)
            ax.legend(fontsize=8)
            figs["root_stress"] = fig
        return figs

    def write_extra(self, out_dir: Path) -> list[Path]:
        """VTU snapshots of the deformed teeth (one file per snapshot), if recorded."""
        paths: list[Path] = []
        ds = self.dataset
        if "snapshot_displacement" in ds:
            from types import SimpleNamespace

            from rotaflex.gear.results.export import write_vtu

            mesh = SimpleNamespace(
                nodes=ds["reference_position"].values, elements=ds["element_nodes"].values.astype(np.int64)
            )
            for k in range(ds.sizes["snapshot"]):
                paths.append(
                    write_vtu(
                        Path(out_dir) / f"snapshot_{k:04d}.vtu",
                        mesh,
                        displacement=ds["snapshot_displacement"].values[k],
                    )
                )
        return paths


ANGLE_LABEL = "rotation angle of gear A [deg]"


def line_figure(x, y, xlabel: str, ylabel: str):
    """One-panel line plot (y may have several columns) with the project's style."""
    from rotaflex.core.plotting import new_figure

    fig, ax = new_figure()
    ax.plot(x, y, lw=0.8)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(alpha=0.3)
    return fig


def history_figures(ds, gap_label: str) -> dict:
    """Energy-balance and gap figures shared by the one- and multi-tooth results."""
    ang = rad_to_deg(ds["rotation_angle"].sel(gear="A").values)
    return {
        "energy_balance": line_figure(
            ds["time"].values * 1e3,
            ds["energy_balance"].values,
            "time [ms]",
            "E_kin + E_strain - W_ext + D_impact - E_0 [J]",
        ),
        "gap": line_figure(ang, ds["gap"].values * 1e6, ANGLE_LABEL, gap_label),
    }


def add_constraint_histories(add, r, tie_multipliers, balance) -> None:
    """Tie multipliers, energies, energy balance and constraint residuals per record.

    Shared by the one- and multi-tooth results; ``add(name, dims, values, units, long_name)``
    stores one variable.
    """
    add("tie_multiplier", ("time", "tie"), tie_multipliers, "N", "tie-constraint multipliers (disk-frame components)")
    add("strain_energy", ("time",), r["strain_energy"], "J", "strain energy of the teeth")
    add("kinetic_energy", ("time",), r["kinetic_energy"], "J", "kinetic energy")
    add("external_work", ("time",), r["external_work"], "J", "external work")
    add(
        "velocity_pass_loss",
        ("time",),
        r["velocity_pass_loss"],
        "J",
        "energy removed by the velocity pass (and by the displacement pass on steps where "
        "the contact closes): impact loss",
    )
    add("energy_balance", ("time",), balance, "J", "E_kin + E_strain - W_ext + D_velocity_pass - E_0")
    for k, name in enumerate(("displacement", "velocity", "acceleration")):
        add(
            f"residual_{name}",
            ("time",),
            r[("res_disp", "res_vel", "res_acc")[k]],
            ("m", "m/s", "m/s^2")[k],
            f"largest {name} constraint error since last record",
        )
        add(
            f"iterations_{name}",
            ("time",),
            r[("iter_disp", "iter_vel", "iter_acc")[k]],
            "1",
            f"most iterations of the {name} pass since last record",
        )
    add("tie_residual", ("time",), r["tie_residual"], "m", "largest tie error after the step")
    add("impact_count", ("time",), r["impacts"], "1", "impacts so far")


def run_scalars(out, r, balance, *, peak, mean_single, nominal, rb, th2, ths) -> dict:
    """Summary scalars (name -> (value, unit)) shared by the one- and multi-tooth results."""
    n = len(balance)
    e_ref = max(float(np.max(r["strain_energy"])) if n else 0.0, 1e-300)
    bal_abs = float(np.max(np.abs(balance))) if n else 0.0
    return {
        "peak_contact_force": (peak, "N"),
        "mean_single_pair_force": (mean_single, "N"),
        "nominal_force": (nominal, "N"),
        "dynamic_factor": (peak / nominal if nominal > 0 else float("nan"), "1"),
        "energy_balance_abs": (bal_abs, "J"),
        "energy_balance_error": (bal_abs / e_ref, "1"),
        "steps": (out.steps, "1"),
        "time_per_step": (out.wall_time / max(out.steps, 1), "s"),
        "impacts": (float(r["impacts"][-1]) if n else 0.0, "1"),
        "max_tie_residual": (float(np.max(r["tie_residual"])) if n else 0.0, "m"),
        "base_radius": (rb, "m"),
        "theta_2": (th2, "rad"),
        "theta_s": (ths, "rad"),
        "dt": (out.dt, "s"),
        "solver_wall_time": (out.wall_time, "s"),
    }


def run_message(ds) -> str:
    """One line for the CLI: peak force, dynamic factor, DTE, energy balance, cost."""
    parts = [
        f"peak contact force {float(ds['peak_contact_force']):.1f} N (dynamic factor {float(ds['dynamic_factor']):.3f})"
    ]
    if "dte_peak_to_peak" in ds:
        parts.append(f"DTE peak-to-peak {float(ds['dte_peak_to_peak']) * 1e6:.2f} um")
    if "root_stress_peak" in ds:
        parts.append(f"fillet stress peak {float(ds['root_stress_peak']) / 1e6:.1f} MPa")
    parts.append(f"energy balance {float(ds['energy_balance_error']) * 100:.2f} %")
    parts.append(f"{int(ds['steps'])} steps in {float(ds['solver_wall_time']):.1f} s")
    return ", ".join(parts)


def histories(out, model, geo, tau0, th2, ths):
    """Histories of a run as an xarray Dataset (the one builder for any number of pairs).

    Per-pair variables carry a ``pair`` dimension when the model has several pairs; with one
    pair (one tooth per gear, the paper's model with the Fig. 7 ramps) it is dropped, and the
    pair-sum variables (total force, load share, pair angle) are omitted.
    """
    import xarray as xr

    r = out.records
    pr = out.pair_records
    rb = geo.base_radius
    nominal = tau0 / rb
    force = pr["force"]
    npair = force.shape[1]
    multi = npair > 1
    rot = np.column_stack([r["phi_A"], -r["phi_B"]])
    psi = np.asarray(getattr(model, "pair_psi", None) if multi else [0.0], dtype=float)
    pair_angle = psi[None, :] + rot[:, :1]
    balance = (
        r["kinetic_energy"] + r["strain_energy"] - r["external_work"] + r["velocity_pass_loss"] - out.initial_energy
    )
    coords = {"time": ("time", r["time"], {"units": "s"}), "gear": ["A", "B"], "xy": ["x", "y"]}
    if multi:
        coords["pair"] = np.arange(npair)
    ds = xr.Dataset(coords=coords)

    def add(name, dims, val, units, long):
        ds[name] = (dims, np.asarray(val), {"units": units, "long_name": long})

    def per_pair(val):
        return val if multi else val[:, 0]

    pdim = ("pair",) if multi else ()
    add(
        "contact_force",
        ("time", *pdim),
        per_pair(force),
        "N",
        "contact force" + (" of each pair" if multi else "") + " (acceleration pass)",
    )
    add(
        "contact_force_displacement_pass",
        ("time", *pdim),
        per_pair(pr["force_disp"]),
        "N",
        "contact force of the displacement pass",
    )
    add(
        "contact_force_velocity_pass",
        ("time", *pdim),
        per_pair(pr["force_vel"]),
        "N",
        "contact force of the velocity pass (impulse / dt at impacts)",
    )
    add(
        "peak_force_interval",
        ("time", *pdim),
        per_pair(pr["force_peak"]),
        "N",
        "largest contact force since the previous record",
    )
    if multi:
        total = force.sum(axis=1)
        with np.errstate(invalid="ignore", divide="ignore"):
            share = np.where(total[:, None] > 0, force / total[:, None], np.nan)
        add("total_contact_force", ("time",), total, "N", "sum of the pair forces")
        add("load_share", ("time", "pair"), share, "1", "pair force / sum of pair forces")
        add(
            "pair_angle",
            ("time", "pair"),
            pair_angle,
            "rad",
            "contact angle of each pair (rotation of A since its geometric start of contact)",
        )
        add(
            "fig7_ramp_force",
            ("time", "pair"),
            torque_ramp(pair_angle, tau0, th2, ths) / rb,
            "N",
            "force of the pair implied by the Fig. 7 torque ramps, tau(angle)/r_b",
        )
        add("nominal_force_ramp", ("time",), np.full(len(total), nominal), "N", "tau_0 / r_b (constant torques)")
    else:
        add(
            "nominal_force_ramp",
            ("time",),
            np.asarray(torque_ramp(rot[:, 0], tau0, th2, ths)) / rb,
            "N",
            "driver torque tau(theta_driver) / r_b (Fig. 7)",
        )
    add("rotation_angle", ("time", "gear"), rot, "rad", "rotation angle (running direction)")
    add(
        "angular_velocity",
        ("time", "gear"),
        np.column_stack([r["omega_A"], -r["omega_B"]]),
        "rad/s",
        "angular velocity",
    )
    add(
        "torque",
        ("time", "gear"),
        np.column_stack([r["torque_A"], r["torque_B"]]),
        "N m",
        "external torque (drive on A, load on B)",
    )
    # a pair outside its mesh window is not searched (contact case -1): no gap
    gap = np.where(pr["contact_case"] >= 0, pr["gap"], np.nan)
    add(
        "gap",
        ("time", *pdim),
        per_pair(gap),
        "m",
        "normal gap (> 0 open" + ("; NaN: pair out of mesh)" if multi else ")"),
    )
    add(
        "normal_velocity",
        ("time", *pdim),
        per_pair(pr["normal_velocity"]),
        "m/s",
        "relative normal velocity (> 0 approaching)",
    )
    cp = np.stack(
        [np.stack([pr["cpA_x"], pr["cpA_y"]], axis=-1), np.stack([pr["cpB_x"], pr["cpB_y"]], axis=-1)], axis=2
    )
    add("contact_point", ("time", *pdim, "gear", "xy"), per_pair(cp), "m", "contact point")
    add(
        "contact_parameter",
        ("time", *pdim, "gear"),
        per_pair(np.stack([pr["param_a"], pr["param_b"]], axis=-1)),
        "1",
        "flank spline parameter of the contact point (0 root, 1 tip)",
    )
    add(
        "contact_case",
        ("time", *pdim),
        per_pair(pr["contact_case"]),
        "1",
        "0 flank-flank, 1 tip of B on A, 2 tip of A on B" + (", -1 out of mesh (not searched)" if multi else ""),
    )
    add_constraint_histories(add, r, out.tie_multipliers, balance)
    peak = float(np.max(pr["force_peak"])) if len(force) else 0.0
    if multi:
        single = zone_pairs(pair_angle, ths) == 1
        load = force.sum(axis=1)
    else:
        single = (rot[:, 0] > th2) & (rot[:, 0] < ths - th2)
        load = force[:, 0]
    mean_single = float(np.mean(load[single])) if np.any(single) else float("nan")
    scalars = run_scalars(out, r, balance, peak=peak, mean_single=mean_single, nominal=nominal, rb=rb, th2=th2, ths=ths)
    if multi:
        scalars.update(
            {
                "mean_total_force": (float(np.mean(load)) if len(load) else float("nan"), "N"),
                "teeth_per_gear": (npair, "1"),
                "preload_beta": (float(model.preload["beta"]) if model.preload else 0.0, "rad"),
            }
        )
    for name, (val, unit) in scalars.items():
        ds[name] = ((), val, {"units": unit})
    if multi and model.preload:
        ds["preload_force"] = (("pair",), model.preload["force"], {"units": "N"})
    if out.snapshots:
        add_snapshots(ds, out, model)
    return ds


def add_snapshots(ds, out, model) -> None:
    """Reference positions, element connectivity and the displacement snapshots (VTU output)."""
    xref = model.reference_positions().reshape(-1, 2)
    node0 = getattr(model, "tooth_node0", None)
    if node0 is None:
        offs = np.concatenate([[0], np.cumsum([m.n_nodes for m in model.meshes])])
        elems = np.vstack([m.elements + offs[g] for g, m in enumerate(model.meshes)])
    else:
        elems = np.vstack([model.meshes[g].elements + node0[g, j] for g in range(2) for j in range(node0.shape[1])])
    ds["reference_position"] = (("node", "xy"), xref, {"units": "m"})
    ds["element_nodes"] = (("element", "corner"), elems, {"units": "1"})
    ds["snapshot_time"] = (("snapshot",), [s[0] for s in out.snapshots], {"units": "s"})
    ds["snapshot_displacement"] = (
        ("snapshot", "node", "xy"),
        np.stack([s[1] - xref for s in out.snapshots]),
        {"units": "m"},
    )


def add_root_stress(ds, out, model, probe) -> None:
    """``root_stress(time, gear)`` (loaded fillet) and ``root_stress_opposite`` [Pa] in place.

    Surface tangential stress at the 30-degree fillet tangent point (ISO 6336-3) from the
    co-rotational elastic displacements of the recorded fillet-element nodes
    (:func:`rotaflex.gear.results.post.root_stress_history`, vectorised over the records).
    """
    from rotaflex.gear.results.post import root_stress_history

    r = out.records
    phi = np.column_stack([r["phi_A"], r["phi_B"]])
    sig = root_stress_history(model, probe, out.node_positions, phi)  # (nt, gear, side)
    ds["root_stress"] = (
        ("time", "gear"),
        sig[:, :, 0],
        {
            "units": "Pa",
            "long_name": "tangential stress at the loaded-flank fillet, 30-deg tangent point (ISO 6336-3); tension > 0",
        },
    )
    ds["root_stress_opposite"] = (
        ("time", "gear"),
        sig[:, :, 1],
        {"units": "Pa", "long_name": "tangential stress at the opposite fillet, 30-deg point"},
    )
    peak = float(np.max(sig[:, :, 0])) if sig.size else 0.0
    ds["root_stress_peak"] = ((), peak, {"units": "Pa", "long_name": "largest loaded-fillet stress (records)"})


def add_transmission_error(ds, rb_a: float, rb_b: float) -> None:
    """``transmission_error(time)`` = r_bA theta_A - r_bB theta_B [m] and its peak-to-peak.

    Rotations in the running directions since t = 0, where the unloaded teeth touch: the DTE is
    relative to the rigid kinematics of that position; positive = gear B lags behind A.
    """
    rot = ds["rotation_angle"].values
    dte = rb_a * rot[:, 0] - rb_b * rot[:, 1]
    ds["transmission_error"] = (
        ("time",),
        dte,
        {
            "units": "m",
            "long_name": "dynamic transmission error r_bA theta_A - r_bB theta_B "
            "along the line of action (> 0: B lags), relative to t = 0",
        },
    )
    p2p = float(np.ptp(dte)) if dte.size else 0.0
    ds["dte_peak_to_peak"] = ((), p2p, {"units": "m", "long_name": "peak-to-peak transmission error"})


def mirror_driver_b(ds, centre_distance: float, first: tuple[int, int] | None = None):
    """Relabel a run whose kernel gear A was the driver as ``driver = "B"`` (mirror image).

    Reflection about y = a/2 swaps the gear centres and keeps both running directions, so the
    gear axes are swapped and every y coordinate becomes a - y. Disk-frame tie multipliers keep
    the kernel's tooth frame (mirrored); only their gear blocks are swapped. ``first``: the
    number of tie columns and of nodes of the kernel's gear A (default: half of each; the gears
    of a drawing pair may have different tie supports).
    """
    swap = [1, 0]
    for name in list(ds.data_vars):
        if "gear" in ds[name].dims:
            attrs = ds[name].attrs
            ds[name] = ds[name].isel(gear=swap).assign_coords(gear=["A", "B"])
            ds[name].attrs.update(attrs)
    cp = ds["contact_point"].values.copy()
    cp[..., 1] = centre_distance - cp[..., 1]
    ds["contact_point"].values[...] = cp
    ds["torque"].attrs["long_name"] = "external torque (load on A, drive on B)"
    n_tie, n_node = (ds.sizes.get("tie", 0) // 2, ds.sizes.get("node", 0) // 2) if first is None else first
    if "tie_multiplier" in ds:
        n = n_tie
        ds["tie_multiplier"].values[...] = np.concatenate(
            [ds["tie_multiplier"].values[:, n:], ds["tie_multiplier"].values[:, :n]], axis=1
        )
    if "reference_position" in ds:
        nn = n_node
        for name in ("reference_position", "snapshot_displacement"):
            v = ds[name].values
            v = np.concatenate([v[..., nn:, :], v[..., :nn, :]], axis=-2)
            if name == "reference_position":
                v[..., 1] = centre_distance - v[..., 1]
            else:
                v[..., 1] = -v[..., 1]
            ds[name].values[...] = v
    ds.attrs["mirrored"] = "driver B: simulated as the mirror image (kernel gear A = B)"
    return ds


def mirror_direction(ds) -> None:
    """Relabel a forward run as ``direction = "reverse"`` in place (mirror image about x = 0).

    Reflection about the line of centres turns gear A's counter-clockwise rotation into a
    clockwise one and makes the other flanks the working ones; for teeth symmetric about their
    centre line (the profile reliefs are applied to both flanks) the reverse run is exactly
    this mirror image. Rotations, speeds, torques and forces are in the running directions and
    do not change; every x coordinate changes sign. Disk-frame tie multipliers stay in the
    (mirrored) tooth frame.
    """
    for name in ("contact_point", "reference_position", "snapshot_displacement"):
        if name in ds:
            v = ds[name].values.copy()
            v[..., 0] = -v[..., 0]
            ds[name].values[...] = v
    ds.attrs["mirrored_direction"] = "reverse: simulated as the mirror image about x = 0 (forward run)"


def zone_pairs(pair_angle: np.ndarray, theta_s: float) -> np.ndarray:
    """Number of pairs nominally in contact (contact angle in [0, theta_s]) per record."""
    return np.sum((pair_angle >= 0.0) & (pair_angle <= theta_s), axis=1)


def plot_multi(ds) -> dict:
    """Figures of a multi-tooth result: pair forces vs the Fig. 7 ramps, load share, energy."""
    from rotaflex.core.plotting import new_figure

    figs = {}
    ang = rad_to_deg(ds["rotation_angle"].sel(gear="A").values)
    fig, ax = new_figure()
    for j in ds["pair"].values:
        (line,) = ax.plot(ang, ds["contact_force"].sel(pair=j).values, lw=0.8, label=f"pair {j}")
        ax.plot(ang, ds["fig7_ramp_force"].sel(pair=j).values, "--", lw=0.7, color=line.get_color())
    ax.plot(ang, ds["total_contact_force"].values, "k", lw=0.6, label="sum")
    ax.axhline(float(ds["nominal_force"]), color="grey", lw=0.5)
    ax.set_xlabel("rotation angle of gear A [deg]")
    ax.set_ylabel("contact force [N] (dashed: Fig. 7 ramps)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    figs["contact_force"] = fig
    figs["load_share"] = line_figure(ang, ds["load_share"].values, ANGLE_LABEL, "load share of each pair [-]")
    figs.update(history_figures(ds, "normal gap of each pair [um]"))
    return figs


def build_dataset(out, model, geo, run, probe=None):
    """Dataset of a run (``run``: :class:`rotaflex.gear.cases.simulate_config.Run`) with its checks.

    ``probe``: the fillet-stress operator of the recorded nodes (one tooth per gear), or None.
    """
    from rotaflex.gear.cases.simulate_config import MAX_ENERGY_BALANCE_ERROR, MAX_TIE_RESIDUAL

    ds = histories(out, model, geo, run.torque, run.theta_2, run.theta_s)
    if probe is not None:
        add_root_stress(ds, out, model, probe)
    # base radii and tooth counts of gears A, B (kernel order: driver first)
    rb = [g.base_radius for g in model.geometry]
    teeth = [g.teeth for g in model.geometry]
    if run.driver == "B":
        fe = getattr(model, "base", model)  # the FE arrays (of the reduced model too)
        first = (2 * int(np.count_nonzero(fe.tie_gear == 0)), int(np.count_nonzero(fe.gid == 0)))
        ds = mirror_driver_b(ds, model.centre_distance, first)
        rb, teeth = rb[::-1], teeth[::-1]
    if run.direction == "reverse":
        mirror_direction(ds)
    if run.teeth_per_gear == 1:
        add_transmission_error(ds, rb[0], rb[1])
    ds["gear_base_radius"] = (("gear",), np.array(rb, dtype=float), {"units": "m", "long_name": "base radius"})
    ds["gear_ratio"] = ((), teeth[1] / teeth[0], {"units": "1", "long_name": "z_B / z_A"})
    ds.attrs["driver"] = run.driver
    ds.attrs["direction"] = run.direction
    failed = []
    ebe = float(ds["energy_balance_error"])
    if not ebe <= MAX_ENERGY_BALANCE_ERROR:
        failed.append(f"energy balance: error {ebe:.3g} > {MAX_ENERGY_BALANCE_ERROR:g} of the peak strain energy")
    tres = float(ds["max_tie_residual"])
    if not tres <= MAX_TIE_RESIDUAL:
        failed.append(f"constraint residual: tie error {tres:.3g} m > {MAX_TIE_RESIDUAL:g} m")
    if failed:
        ds.attrs.update(status="failed_check", message="failed check: " + "; ".join(failed))
    else:
        ds.attrs.update(status="success", message=run_message(ds))
    return ds
