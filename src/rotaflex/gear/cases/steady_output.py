"""What a ``gear steady`` point writes besides the solver's metrics: the model data behind the
numbers (linear resonance, mesh force and stiffness, inertias), the ISO 6336-1 method B K_v at the
operating speed, and the final state a continuation starts from.
"""

from __future__ import annotations

from rotaflex.core.units import rpm_to_rad_s
from rotaflex.gear.cases.steady_config import TorsionalCaseConfig
from rotaflex.gear.models.chain import OperatingPoint, TorsionalSystem, iso_input, natural_frequencies
from rotaflex.gear.static.iso6336_kv import iso_kv

__all__ = ["helical_extras", "iso_data", "iso_tip_relief", "node_names", "point_extras"]


def iso_tip_relief(cfg) -> float:
    """ISO's single C_a [m]: as given, else the larger drawing tip relief of the pair in use."""
    if cfg.iso.tip_relief is not None:
        return cfg.iso.tip_relief
    if cfg.pinion is None or not cfg.model.relief:
        return 0.0
    return max((g.tip_relief.amount for g in (cfg.pinion, cfg.wheel) if g.tip_relief is not None), default=0.0)


def iso_data(cfg, sys: TorsionalSystem, eps: float, face_width: float):
    """ISO 6336-1 method B input of the case: ISO's F_t at the wheel's reference circle and, with
    ``iso.stiffness = "iso"``, ISO's own c' and c_gamma_alpha (blank factor C_R of the drawing)."""
    from rotaflex.gear.static.tooth_analysis import iso6336_stiffness

    g1, g2 = cfg.gear.geometry() if cfg.pair is None else cfg.pair.gears
    iso = cfg.iso
    stiff = {}
    if iso.stiffness == "iso":
        pair = cfg.pair
        c_r = 1.0 if pair is None else 0.5 * (pair.pinion.blank_factor() + pair.wheel.blank_factor())
        load = iso.application_factor * cfg.operation.torque / g2.pitch_radius / (face_width * 1e3)  # N/mm
        helix = {}
        if pair is not None and pair.helical:
            helix = {"helix_angle": pair.pinion.helix_angle, "base_helix_angle": pair.base_helix_angle}
        c = iso6336_stiffness(g1, g2, load_per_width=load, eps_alpha=eps, c_r=c_r, **helix)
        stiff = {"c_single": c["c_single"] * 1e9, "c_gamma_alpha": c["c_gamma"] * 1e9}  # N/(mm um) -> N/m^2
    return iso_input(
        sys,
        cfg.operation.torque,
        face_width,
        eps,
        reference_radius=g2.pitch_radius,
        f_pb_eff=iso.f_pb_eff,
        f_f_eff=iso.f_f_eff,
        tip_relief=iso_tip_relief(cfg),
        application_factor=iso.application_factor,
        overlap_ratio=0.0 if cfg.pair is None else cfg.pair.overlap_ratio,
        **stiff,
    )


def point_extras(res, sys: TorsionalSystem, st, cfg: TorsionalCaseConfig, eps: float, face_width: float) -> None:
    """Scalars a speed sweep of single points needs (linear resonance, ISO K_v at this speed)
    and the final state (continuation, also after reading result.nc back)."""
    ds = res.dataset
    op = cfg.operation
    nf = natural_frequencies(sys)
    f_mesh_mode = float(nf["frequency"][nf["mesh_mode"]])
    ds["mesh_natural_frequency"] = ((), f_mesh_mode, {"units": "Hz", "long_name": "linear mesh-mode frequency"})
    ds["resonance_speed"] = (
        (),
        60.0 * f_mesh_mode / sys.teeth[0],
        {"units": "rpm", "long_name": "pinion speed where the mesh frequency meets the mesh mode"},
    )
    # the model data behind the numbers, for checking by hand
    ds["static_mesh_force"] = ((), float(op.torque / sys.base_radius[1]), {"units": "N", "long_name": "T_out / r_b2"})
    ds["mean_mesh_stiffness"] = ((), float(sys.mesh.mean_stiffness), {"units": "N/m", "long_name": "k_mean"})
    ds["reduced_mass"] = ((), float(sys.reduced_mass), {"units": "kg", "long_name": "m_red along the line of action"})
    if cfg.pair is not None:
        pair = cfg.pair
        ds["normal_backlash"] = (
            (),
            float(pair.normal_backlash_at(pair.working_center_distance)),
            {"units": "m", "long_name": "normal backlash j_bn of the drawing pair"},
        )
    for name, j in zip(("pinion", "wheel"), sys.inertia, strict=True):
        ds[f"inertia_{name}"] = ((), float(j), {"units": "kg m^2", "long_name": f"{name} polar inertia used"})
    helical_extras(ds, cfg.pair, op.torque, sys.base_radius[1])
    iso = iso_data(cfg, sys, eps, face_width)
    kv = float(iso_kv(iso, [rpm_to_rad_s(op.speed_rpm)])[0])
    ds["iso_kv"] = ((), kv, {"units": "1", "long_name": "ISO 6336-1 method B K_v"})
    ds["iso_resonance_speed"] = ((), float(iso.resonance_speed_rpm), {"units": "rpm"})
    _say_peak(ds)
    ds.coords["chain_node"] = node_names(sys, cfg)
    ds["state_theta"] = (
        "chain_node",
        st.theta,
        {"units": "rad", "long_name": "final angles (lateral nodes: displacements in m)"},
    )
    ds["state_omega"] = (
        "chain_node",
        st.omega,
        {"units": "rad/s", "long_name": "final speeds (lateral nodes: velocities in m/s)"},
    )
    ds["state_nominal"] = ("chain_node", st.nominal, {"units": "rad/s", "long_name": "final nominal speeds"})
    ds.attrs["state_time"] = st.time
    if hasattr(st, "modal"):
        ds["state_modal"] = ("modal_dof", st.modal, {"units": "sqrt(kg) m", "long_name": "final tooth modal states"})
        ds.attrs["state_n_hi"] = st.n_hi


def _say_peak(ds) -> None:
    """The summary line says what the K_v peak is: an impact on re-contact after contact loss,
    and how far the largest sample (incl. the damper's TE-rate spike) lies above it."""
    kv = float(ds["dynamic_factor"])
    if float(ds.get("peak_is_impact", 0.0)):
        ds.attrs["message"] += f"; K_v {kv:.3f} is an impact (re-contact after contact loss)"
    sampled = float(ds["force_max_sampled"]) / float(ds["static_mesh_force"]) if "force_max_sampled" in ds else kv
    if sampled > 1.01 * kv:
        ds.attrs["message"] += (
            f"; K_v {kv:.3f} from the converged peak (largest sample {sampled:.3f}: the mesh damper's spike "
            "where the tabulated unloaded TE steps, not reported)"
        )


def node_names(sys: TorsionalSystem, cfg: TorsionalCaseConfig) -> list[str]:
    """Chain nodes of the model (motor, pinion, wheel, load as present; lateral nodes)."""
    from rotaflex.gear.models.chain import build_chain

    op = cfg.operation
    return build_chain(sys, OperatingPoint(op.speed_rpm, op.torque)).names


def helical_extras(ds, pair, torque: float, base_radius_out: float) -> None:
    """Axial mesh force of a helical pair into a point's or a sweep's dataset ``ds``.

    The lumped mesh force F acts along the transverse line of action; the flank normal is
    inclined by the base helix angle, so the axial force is ``F tan(beta_b)`` (static: ``T_out
    tan(beta_b) / r_b2 = T_out tan(beta_w) / r_w2``). ``torque`` on the output gear [N m]."""
    if pair is None or not pair.helical:
        return
    import math

    t = math.tan(pair.base_helix_angle)
    ds["axial_force_static"] = (
        (),
        torque / base_radius_out * t,
        {"units": "N", "long_name": "T_out tan(beta_b) / r_b2"},
    )
    if "mesh_force" in ds:
        ds["axial_mesh_force"] = (
            ds["mesh_force"].dims,
            ds["mesh_force"].values * t,
            {"units": "N", "long_name": "axial mesh force F tan(beta_b)"},
        )
    for key in ("force_max", "force_min"):
        if key in ds:
            ds[f"axial_{key}"] = (
                ds[key].dims,
                ds[key].values * t,
                {"units": "N", "long_name": f"axial mesh force ({key} tan(beta_b))"},
            )
    ds["base_helix_angle"] = ((), pair.base_helix_angle, {"units": "rad", "long_name": "base helix angle beta_b"})
    ds["overlap_ratio"] = ((), pair.overlap_ratio, {"units": "1", "long_name": "overlap ratio eps_beta"})
