"""``rotaflex gear simulate``: validated configuration -> dynamic contact run -> GearResult.

TOML layout (all tables optional; defaults are the paper's data, section 4)::

    domain = "gear"
    [gear]       module, teeth, pressure_angle_deg, face_width, tip_radius, root_radius
    [material]   youngs_modulus, poisson_ratio, density
    disk_inertia = 2.965e-4
    [operation]  speed_rpm = [4000, 4000], torque, theta_2_deg, theta_s_deg, span_deg,
                 driver = "A" | "B"
    [mesh]       preset = "default" | "coarse" | "fine", n_points
    [solver]     method = "paper_rk4" | "reduced_hht", dt (default per method), tolerance,
                 accel_n, max_iter, multipliers = "iterative" | "direct", restitution,
                 modes, hht_alpha
    [output]     every, vtu_snapshots, root_stress
    [model]      teeth_per_gear = 1 | 2 | 3, start_angle_deg, mesh_window_deg
                 (2-3: several contact pairs, constant torques; :mod:`rotaflex.gear.multitooth`;
                 paper_rk4 with iterative multipliers, driver A only)

Driver: gear A turns counter-clockwise about the origin, B clockwise about (0, a). The driver
gets the drive torque (in its running direction), the other gear the load torque (against its
running direction), each ramped with its own gear's rotation as in Fig. 7. ``driver = "B"`` is run
as the mirror image (reflection about y = a/2 maps a counter-clockwise driver at the origin onto
a clockwise driver at (0, a)): the kernel simulates the driver as its gear A, and the outputs are
relabelled (gear axes swapped, contact points mirrored), which is exact for identical gears.
"""

from __future__ import annotations

import json
import math
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Literal

import numpy as np

from rotaflex.core.config import from_mapping, param
from rotaflex.core.errors import InputError
from rotaflex.core.result import Result, register_result


@dataclass(frozen=True)
class GearConfig:
    """Both gears (identical, as in the paper)."""

    module: float = param(3.175e-3, unit="m", gt=0.0, doc="module")
    teeth: int = param(28, gt=5, doc="number of teeth")
    pressure_angle_deg: float = param(20.0, unit="deg", gt=5.0, lt=45.0)
    face_width: float = param(6.35e-3, unit="m", gt=0.0)
    tip_radius: float = param(0.047625, unit="m", gt=0.0)
    root_radius: float = param(0.04048, unit="m", gt=0.0)

    def geometry(self):
        from rotaflex.gear.geometry import GearGeometry

        return GearGeometry(
            module=self.module,
            teeth=self.teeth,
            face_width=self.face_width,
            pressure_angle_deg=self.pressure_angle_deg,
            tip_radius=self.tip_radius,
            root_radius=self.root_radius,
        )


@dataclass(frozen=True)
class MaterialConfig:
    youngs_modulus: float = param(210e9, unit="Pa", gt=0.0)
    poisson_ratio: float = param(0.3, gt=0.0, lt=0.5)
    density: float = param(7800.0, unit="kg/m^3", gt=0.0)


@dataclass(frozen=True)
class OperationConfig:
    """Initial speeds, torque and the angles of Fig. 7."""

    speed_rpm: tuple[float, float] = param(
        (4000.0, 4000.0), unit="rpm", gt=0.0, doc="initial speeds of gear A (driver), gear B"
    )
    torque: float = param(22.25, unit="N m", ge=0.0, doc="tau_0 of Fig. 7")
    theta_2_deg: float | None = param(None, unit="deg", gt=0.0, doc="two-pair zone (default from involute geometry)")
    theta_s_deg: float | None = param(
        None, unit="deg", gt=0.0, doc="single-tooth contact angle (default from geometry)"
    )
    span_deg: float | None = param(None, unit="deg", gt=0.0, doc="rotation of the driver simulated (default theta_s)")
    driver: Literal["A", "B"] = param("A", doc="gear that gets the drive torque; the other gets the load torque")


@dataclass(frozen=True)
class MeshConfig:
    preset: Literal["default", "coarse", "fine"] = param(
        "default", doc="tooth mesh; 'fine' (2x default) needs dt <= 1.7e-8 s"
    )
    n_points: int = param(61, ge=8, le=1000, doc="spline data points per flank")
    contact_smoothing: int = param(
        0,
        ge=0,
        le=100,
        doc="contact surfaces without the short-wave flank deformation (the point force's own "
        "indentation): uniform intervals of the least-squares cubic fit; 0 = paper's surfaces "
        "(paper_rk4 only)",
    )


#: default time step of paper_rk4 [s]; reduced_hht: REDUCED_STEP_ANGLE / omega_A
DEFAULT_DT = {"paper_rk4": 3e-8}
#: rotation of gear A per step of reduced_hht by default [rad] (1.2e-6 s at 4000 rpm,
#: 2.4e-7 s at 20000 rpm; see docs/gear-dynamics.md for the accuracy behind this choice)
REDUCED_STEP_ANGLE = 5e-4


@dataclass(frozen=True)
class SolverConfig:
    method: Literal["paper_rk4", "reduced_hht"] = param(
        "paper_rk4",
        doc="paper_rk4: the paper's RK4 + multiplier passes; reduced_hht: "
        "Craig-Bampton teeth + implicit HHT-alpha (large steps, docs/gear-dynamics.md)",
    )
    dt: float | None = param(
        None, unit="s", gt=0.0, doc="time step (default 3e-8 s paper_rk4; 5e-4 rad / omega_A reduced_hht)"
    )
    multipliers: Literal["iterative", "direct"] = param(
        "iterative", doc="paper_rk4 passes: the iteration of eq. 19-24 or the direct solve"
    )
    modes: int = param(20, ge=0, le=500, doc="reduced_hht: fixed-interface modes per tooth")
    hht_alpha: float = param(-0.05, ge=-1.0 / 3.0, le=0.0, doc="reduced_hht: HHT alpha")
    tolerance: float = param(
        1e-12, unit="m", gt=0.0, doc="displacement tolerance; velocity/acceleration: tol/dt, tol/dt^2"
    )
    accel_n: int = param(4, ge=1, le=5, doc="acceleration level n of appendix B")
    max_iter: int = param(500, ge=1)
    restitution: float = param(
        0.0,
        ge=0.0,
        le=1.0,
        doc="Newton coefficient e of the contact-point impact law (0 = plastic, the paper's velocity pass)",
    )


@dataclass(frozen=True)
class OutputConfig:
    every: int | None = param(
        None, ge=1, doc="record every n-th step (1 = full rate; default 10 for paper_rk4, 1 for reduced_hht)"
    )
    vtu_snapshots: int = param(0, ge=0, le=1000, doc="number of VTU snapshots")
    root_stress: bool = param(True, doc="record the fillet nodes for root_stress(time, gear)")


@dataclass(frozen=True)
class ModelConfig:
    """Number of elastic teeth per gear (issue 3, part 3)."""

    teeth_per_gear: int = param(
        1,
        ge=1,
        le=3,
        doc="1: the paper's model with the Fig. 7 torque ramps; 2-3: "
        "adjacent teeth, several contact pairs, constant torques",
    )
    start_angle_deg: float = param(
        -0.5, unit="deg", le=0.0, doc="contact angle of the entering pair at t = 0 (2-3 teeth)"
    )
    mesh_window_deg: float = param(
        1.0,
        unit="deg",
        gt=0.0,
        le=5.0,
        doc="pairs are searched from this angle before the start of contact to this angle after its end (2-3 teeth)",
    )


@dataclass(frozen=True)
class GearCaseConfig:
    gear: GearConfig = field(default_factory=GearConfig)
    material: MaterialConfig = field(default_factory=MaterialConfig)
    disk_inertia: float = param(2.965e-4, unit="kg m^2", gt=0.0)
    operation: OperationConfig = field(default_factory=OperationConfig)
    mesh: MeshConfig = field(default_factory=MeshConfig)
    solver: SolverConfig = field(default_factory=SolverConfig)
    output: OutputConfig = field(default_factory=OutputConfig)
    model: ModelConfig = field(default_factory=ModelConfig)

    def __post_init__(self) -> None:
        op = self.operation
        if op.theta_2_deg is not None and op.theta_s_deg is not None:
            if 2 * op.theta_2_deg > op.theta_s_deg:
                raise InputError(
                    "operation.theta_2_deg", op.theta_2_deg, f"<= theta_s_deg / 2 = {op.theta_s_deg / 2:g}"
                )


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
            from rotaflex.gear.multitooth import plot_multi

            return plot_multi(ds)
        figs = {}
        ang = np.degrees(ds["rotation_angle"].sel(gear="A").values)
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

    def save(self, out_dir, *, figures=True):
        paths = super().save(out_dir, figures=figures)
        ds = self.dataset
        if "snapshot_displacement" in ds:
            from types import SimpleNamespace

            from rotaflex.gear.export import write_vtu

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


#: 2x the default tooth mesh (1125 nodes; RK4 limit 1.74e-8 s, see docs/gear-fe.md)
FINE = dict(n_flank=20, n_through=10, n_fillet=4, n_rim=8)


def build(cfg: GearCaseConfig):
    """Geometry, meshes and the assembled two-gear model of a configuration."""
    from rotaflex.gear import dynamics
    from rotaflex.gear.mesh import COARSE, DEFAULT, build_tooth_mesh

    geo = cfg.gear.geometry()
    kw = {"coarse": COARSE, "default": DEFAULT, "fine": FINE}[cfg.mesh.preset]
    mesh = build_tooth_mesh(geo, **kw)
    mat = cfg.material
    model = dynamics.build_model(
        geo,
        geo,
        mesh,
        mesh,
        youngs_modulus=mat.youngs_modulus,
        poisson_ratio=mat.poisson_ratio,
        density=mat.density,
        inertia=(cfg.disk_inertia, cfg.disk_inertia),
        n_points=cfg.mesh.n_points,
    )
    return geo, mesh, model


def run_case(config: dict, *, progress: bool = False) -> GearResult:
    """Validate ``config`` (see module docstring), simulate, and wrap the histories."""
    from rotaflex.gear import dynamics
    from rotaflex.gear.geometry import contact_angles

    cfg = from_mapping(GearCaseConfig, config)
    if cfg.mesh.contact_smoothing > 0 and (cfg.model.teeth_per_gear > 1 or cfg.solver.method != "paper_rk4"):
        raise InputError(
            "mesh.contact_smoothing",
            cfg.mesh.contact_smoothing,
            "0 unless solver.method = 'paper_rk4' with teeth_per_gear = 1",
        )
    if cfg.model.teeth_per_gear > 1:
        from rotaflex.gear.multitooth import run_multi_case

        return run_multi_case(cfg, progress=progress)
    t_wall = time.perf_counter()
    geo, mesh, model = build(cfg)
    ths, th2 = contact_angles(geo, geo)
    op = cfg.operation
    if op.theta_s_deg is not None:
        ths = math.radians(op.theta_s_deg)
    if op.theta_2_deg is not None:
        th2 = math.radians(op.theta_2_deg)
    if 2 * th2 > ths:
        raise InputError("operation.theta_2_deg", math.degrees(th2), f"<= theta_s / 2 = {math.degrees(ths) / 2:g} deg")
    span = math.radians(op.span_deg) if op.span_deg is not None else ths
    # the kernel's gear A is always the driver (driver = "B": mirror image, see module doc)
    speeds = tuple(op.speed_rpm) if op.driver == "A" else tuple(op.speed_rpm[::-1])
    sol = cfg.solver
    if sol.method == "reduced_hht" and sol.restitution > 0.0:
        raise InputError(
            "solver.restitution", sol.restitution, "0 with method = 'reduced_hht' (its impact law is plastic)"
        )
    probe = None
    # reduced_hht eliminates the fillet nodes' FE field (Craig-Bampton): no root stress there
    if cfg.output.root_stress and sol.method == "paper_rk4":
        from rotaflex.gear.post import root_stress_probe

        probe = root_stress_probe(model, cfg.material.youngs_modulus, cfg.material.poisson_ratio)
    bar = None
    cb = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=1, unit="step", desc="gear")

        def cb(done, total):
            bar.total = total
            bar.n = done
            bar.refresh()

    if sol.dt is not None:
        dt = sol.dt
    elif sol.method == "reduced_hht":
        dt = REDUCED_STEP_ANGLE / (op.speed_rpm[0] * math.pi / 30)
    else:
        dt = DEFAULT_DT[sol.method]
    every = cfg.output.every or (1 if sol.method == "reduced_hht" else 10)
    try:
        if sol.method == "reduced_hht":
            from rotaflex.gear import reduced

            red = reduced.build_reduced(model, sol.modes)
            out = reduced.simulate_reduced(
                red,
                speeds_rpm=speeds,
                torque=op.torque,
                theta_2=th2,
                theta_s=ths,
                span=span,
                dt=dt,
                alpha=sol.hht_alpha,
                tol=sol.tolerance,
                max_iter=min(sol.max_iter, 100),
                record_every=every,
                snapshots=cfg.output.vtu_snapshots,
                progress=cb,
            )
        else:
            out = dynamics.simulate(
                model,
                speeds_rpm=speeds,
                torque=op.torque,
                theta_2=th2,
                theta_s=ths,
                span=span,
                dt=dt,
                tol=sol.tolerance,
                n_accel=sol.accel_n,
                max_iter=sol.max_iter,
                record_every=every,
                snapshots=cfg.output.vtu_snapshots,
                progress=cb,
                restitution=sol.restitution,
                multipliers=sol.multipliers,
                smoothing=cfg.mesh.contact_smoothing,
                record_nodes=None if probe is None else probe.nodes,
            )
    finally:
        if bar is not None:
            bar.close()
    ds = to_dataset(out, model, geo, op.torque, th2, ths)
    if probe is not None:
        add_root_stress(ds, out, model, probe)
    if op.driver == "B":
        ds = mirror_driver_b(ds, model.centre_distance)
    add_transmission_error(ds, geo.base_radius, geo.base_radius)
    ds.attrs["driver"] = op.driver
    ds.attrs.update(
        status="success",
        message=run_message(ds),
        wall_time=time.perf_counter() - t_wall,
        config=json.dumps(asdict(cfg)),
    )
    return GearResult(ds)


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
    ang = np.degrees(ds["rotation_angle"].sel(gear="A").values)
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


def to_dataset(out, model, geo, tau0, th2, ths):
    """Histories of :func:`rotaflex.gear.dynamics.simulate` as an xarray Dataset."""
    import xarray as xr

    r = out.records
    rb = geo.base_radius
    nominal = tau0 / rb
    rot = np.column_stack([r["phi_A"], -r["phi_B"]])
    omega = np.column_stack([r["omega_A"], -r["omega_B"]])
    cp = np.stack([np.column_stack([r["cpA_x"], r["cpA_y"]]), np.column_stack([r["cpB_x"], r["cpB_y"]])], axis=1)
    balance = (
        r["kinetic_energy"] + r["strain_energy"] - r["external_work"] + r["velocity_pass_loss"] - out.initial_energy
    )
    ramp = (
        np.asarray(
            __import__("rotaflex.gear.dynamics", fromlist=["torque_ramp"]).torque_ramp(rot[:, 0], tau0, th2, ths)
        )
        / rb
    )
    ds = xr.Dataset(coords={"time": ("time", r["time"], {"units": "s"}), "gear": ["A", "B"], "xy": ["x", "y"]})

    def add(name, dims, val, units, long):
        ds[name] = (dims, np.asarray(val), {"units": units, "long_name": long})

    add("contact_force", ("time",), r["force"], "N", "contact force (acceleration pass)")
    add("contact_force_displacement_pass", ("time",), r["force_disp"], "N", "contact force of the displacement pass")
    add(
        "contact_force_velocity_pass",
        ("time",),
        r["force_vel"],
        "N",
        "contact force of the velocity pass (impulse / dt at impacts)",
    )
    add("peak_force_interval", ("time",), r["force_peak"], "N", "largest contact force since the previous record")
    add("nominal_force_ramp", ("time",), ramp, "N", "driver torque tau(theta_driver) / r_b (Fig. 7)")
    add("rotation_angle", ("time", "gear"), rot, "rad", "rotation angle (running direction)")
    add("angular_velocity", ("time", "gear"), omega, "rad/s", "angular velocity")
    add(
        "torque",
        ("time", "gear"),
        np.column_stack([r["torque_A"], r["torque_B"]]),
        "N m",
        "external torque (drive on A, load on B)",
    )
    add("gap", ("time",), r["gap"], "m", "normal gap (> 0 open)")
    add("normal_velocity", ("time",), r["normal_velocity"], "m/s", "relative normal velocity (> 0 approaching)")
    add("contact_point", ("time", "gear", "xy"), cp, "m", "contact point")
    add(
        "contact_parameter",
        ("time", "gear"),
        np.column_stack([r["param_a"], r["param_b"]]),
        "1",
        "flank spline parameter of the contact point (0 root, 1 tip)",
    )
    add("contact_case", ("time",), r["contact_case"], "1", "0 flank-flank, 1 tip of B on A, 2 tip of A on B")
    add_constraint_histories(add, r, out.tie_multipliers, balance)
    peak = float(np.max(r["force_peak"])) if len(r["force_peak"]) else 0.0
    single = (rot[:, 0] > th2) & (rot[:, 0] < ths - th2)
    mean_single = float(np.mean(r["force"][single])) if np.any(single) else float("nan")
    scalars = run_scalars(out, r, balance, peak=peak, mean_single=mean_single, nominal=nominal, rb=rb, th2=th2, ths=ths)
    for name, (val, unit) in scalars.items():
        ds[name] = ((), val, {"units": unit})
    if out.snapshots:
        xref = model.reference_positions().reshape(-1, 2)
        offs = np.concatenate([[0], np.cumsum([m.n_nodes for m in model.meshes])])
        elems = np.vstack([m.elements + offs[g] for g, m in enumerate(model.meshes)])
        ds["reference_position"] = (("node", "xy"), xref, {"units": "m"})
        ds["element_nodes"] = (("element", "corner"), elems, {"units": "1"})
        ds["snapshot_time"] = (("snapshot",), [s[0] for s in out.snapshots], {"units": "s"})
        ds["snapshot_displacement"] = (
            ("snapshot", "node", "xy"),
            np.stack([s[1] - xref for s in out.snapshots]),
            {"units": "m"},
        )
    return ds


def add_root_stress(ds, out, model, probe) -> None:
    """``root_stress(time, gear)`` (loaded fillet) and ``root_stress_opposite`` [Pa] in place.

    Surface tangential stress at the 30-degree fillet tangent point (ISO 6336-3) from the
    co-rotational elastic displacements of the recorded fillet-element nodes
    (:func:`rotaflex.gear.post.root_stress_history`, vectorised over the records).
    """
    from rotaflex.gear.post import root_stress_history

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


def mirror_driver_b(ds, centre_distance: float):
    """Relabel a run whose kernel gear A was the driver as ``driver = "B"`` (mirror image).

    Reflection about y = a/2 swaps the gear centres and keeps both running directions, so the
    gear axes are swapped and every y coordinate becomes a - y. Disk-frame tie multipliers keep
    the kernel's tooth frame (mirrored); only their gear blocks are swapped.
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
    if "tie_multiplier" in ds:
        n = ds.sizes["tie"]
        ds["tie_multiplier"].values[...] = np.concatenate(
            [ds["tie_multiplier"].values[:, n // 2 :], ds["tie_multiplier"].values[:, : n // 2]], axis=1
        )
    if "reference_position" in ds:
        nn = ds.sizes["node"] // 2
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
