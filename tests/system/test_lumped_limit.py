"""Rigid shafts and rigid bearings: the system's nonlinear steady state is the torsional mesh
model of ``gear steady`` (run through its CLI target with a config dict, on the same table)."""

from __future__ import annotations

import copy
from pathlib import Path

import pytest

from rotaflex.core.config import load_toml
from rotaflex.core.domains import command_target, resolve
from rotaflex.system.assembly import matrices
from rotaflex.system.case import run_steady
from rotaflex.system.model import Gearbox

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "system" / "gearbox.toml"
TE = 2e-7  # m, unloaded TE peak-to-peak (small: the stiffness steps dominate, as on a K_v curve)


def rigid_example() -> dict:
    """The example gearbox with shafts 1000x stiffer, bearings at 1e12 N/m, no backlash (centre
    distance 90 mm, back flank off), no load inertia or damping: the output rotor turns as one body
    (its rigid-body twist inertia is the sum of its torsional mass matrix) against the mesh."""
    cfg = load_toml(EXAMPLE)
    for r in cfg["rotor"]:
        for s in r["shaft"]:
            s["E"], s["G"] = 2.1e14, 8.1e13
        for b in r["bearing"]:
            b.update(kxx=1e12, kyy=1e12, cxx=0.0, cyy=0.0)
    cfg["rotor"][1]["center"] = [0.09, 0.0]
    m = cfg["gear_mesh"][0]
    m.update(center_distance=0.09, back_contact=False, unloaded_te_pp=TE)
    cfg["load"].update(damping=0.0, inertia=0.0)
    for k in ("modal", "campbell", "response"):
        cfg.pop(k)
    return cfg


def gear_steady_config(box: Gearbox) -> dict:
    """The same pair, table (contact pattern, 256 points) and damping in gear steady's lumped
    model: pinion at constant speed (rigid input shaft), wheel + the rest of the output rotor as
    gear inertia + load inertia (rigid output shaft), the same gear inertias for c_m."""
    mats = matrices(box)
    off, nl, nt = box.layout[1]
    j_out = float(mats.M[off + nl : off + nl + nt, off + nl : off + nl + nt].sum())
    j1, j2 = box.meshes[0].gear.inertia
    return {
        "gear": {"module": 3e-3, "teeth": [20, 40], "pressure_angle_deg": 20.0, "face_width": 0.025},
        "mesh": {
            "source": "contact_pattern",
            "pair_stiffness": 2.5e8,
            "unloaded_te_pp": TE,
            "damping_ratio": 0.07,
            "table_points": 256,
        },
        "train": {"inertia": [j1, j2], "load_inertia": j_out - j2, "drive": "constant_speed"},
        "operation": {"torque": 200.0},
        "steady": {"steps_per_cycle": 256, "tol": 1e-6, "max_cycles": 400},
    }


@pytest.mark.parametrize("rpm", [3000.0, 7300.0, 10000.0])
def test_rigid_limit_gives_gear_steady_dynamic_factor(rpm):
    """K_v (max mesh force / static) at 0.4x, 0.97x (mesh resonance at ~7500 rpm) and 1.3x the
    resonance speed, within 1 %: measured 0.2 %, 0.75 %, 0.2 %. The residual is not zero because
    the systems differ on purpose by what the limit removes: shafts and bearings ~2000x stiffer
    than the mesh (not infinitely), the lateral DOFs, and the two integrators' steady-state
    detection (each run stops at its own periodicity test, near resonance with contact loss)."""
    cfg = rigid_example()
    box = Gearbox.from_mapping({k: v for k, v in cfg.items() if k != "steady"})
    g = gear_steady_config(box)
    g["operation"]["speed_rpm"] = rpm
    lumped = resolve(command_target("gear", "steady"))(copy.deepcopy(g)).summary()
    assert lumped["mean_mesh_stiffness"]["value"] == pytest.approx(box.meshes[0].k_mean, rel=1e-12)
    cfg["steady"] = {"speed_rpm": rpm, "tol": 1e-6, "max_cycles": 400}
    s = run_steady(cfg).summary()
    assert s["dynamic_factor"]["value"] == pytest.approx(lumped["dynamic_factor"]["value"], rel=1e-2)
    assert lumped["dynamic_factor"]["value"] > 1.3  # a dynamic response, not the static limit
