"""`gear static`: identical gears reproduce static.mesh_stiffness exactly, swap symmetry, load
sharing, one-cycle means, the tip-relief prediction, ISO 6336-1 inputs, CLI."""

import copy
import json
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from rotaflex.cli import app
from rotaflex.gear.cases.simulate_config import GearConfig
from rotaflex.gear.cases.static import run_static
from rotaflex.gear.pair.tooth_mesh import COARSE, build_tooth_mesh
from rotaflex.gear.static.tooth_analysis import mesh_stiffness

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "gear" / "unequal_shifted_relief.toml"
PAPER = GearConfig()  # defaults: the paper data of gear/paper.py
PAPER_GEAR = {
    "teeth": PAPER.teeth,
    "module": PAPER.module,
    "face_width": PAPER.face_width,
    "pressure_angle_deg": PAPER.pressure_angle_deg,
    "tip_radius": PAPER.tip_radius,
    "root_radius": PAPER.root_radius,
}


def _coarse(cfg, n_angles=240, refinement=(1,)):
    cfg = copy.deepcopy(cfg)
    cfg["mesh"] = {"preset": "coarse", "n_radii": 9}
    cfg["analysis"] = {"n_angles": n_angles, "refinement": list(refinement)}
    return cfg


def _example(**drop):
    cfg = tomllib.loads(EXAMPLE.read_text())
    for gear in drop.get("no_relief", ()):
        cfg[gear].pop("tip_relief", None)
    return cfg


def test_identical_paper_gears_reproduce_static_mesh_stiffness_exactly():
    cfg = _coarse({"pinion": PAPER_GEAR, "wheel": PAPER_GEAR, "load": {"torque": 22.25}}, n_angles=200)
    ds = run_static(cfg).dataset
    g = PAPER.geometry()
    m = build_tooth_mesh(g, **COARSE)
    ref = mesh_stiffness(g, g, 210e9, 0.3, torque=22.25, n_angles=200, mesh1=m, mesh2=m)
    assert np.array_equal(ds["ste_engagement"].values, ref.transmission_error)
    assert np.array_equal(ds["pair_stiffness"].values, ref.pair_stiffness)
    assert np.array_equal(ds["load_share"].values, ref.load_share)
    assert np.array_equal(ds["engagement"].values, ref.angle)
    assert ds["force"].item() == ref.force


@pytest.fixture(scope="module")
def example_static():
    """gear static of the shipped example on the coarse mesh (pinion driving), shared by the
    swap, ISO 6336 and wheel-driving tests."""
    return run_static(_coarse(_example())).dataset


def test_swapping_pinion_and_wheel_swaps_the_results(example_static):
    base = _coarse(_example())
    sw = copy.deepcopy(base)
    sw["pinion"], sw["wheel"] = base["wheel"], base["pinion"]
    sw["load"]["torque"] = base["load"]["torque"] * 2.0  # same normal load (ratio 2, r_b2 = 2 r_b1)
    a, b = example_static, run_static(sw).dataset
    for key in ("force", "single_pair_stiffness_max", "load_share_max"):
        assert a[key].item() == pytest.approx(b[key].item(), rel=1e-9), key
    # the swapped pair runs the same line of action from the other end: mirrored samples
    for key in ("ste_engagement", "load_share", "pair_stiffness", "relief_gap"):
        assert np.allclose(a[key].values, b[key].values[::-1], rtol=1e-9, atol=0), key
    # one-cycle statistics: same function, cycle grids offset by a fraction of a sample
    for key in ("ste_mean", "mesh_stiffness_mean"):
        assert a[key].item() == pytest.approx(b[key].item(), rel=5e-3), key
    assert a["fillet_stress_max_pinion"].item() == pytest.approx(b["fillet_stress_max_wheel"].item(), rel=1e-9)
    assert np.allclose(a["tooth_compliance"].values, b["tooth_compliance"].values[::-1], rtol=1e-12)


def test_load_sharing_sums_to_the_load_and_one_cycle_mean_is_the_integral():
    cfg = _coarse(_example(), n_angles=2000)
    ds = run_static(cfg).dataset
    assert np.allclose(ds["total_share"].values, 1.0, atol=1e-12)
    assert ds["load_share"].max() == pytest.approx(1.0, abs=1e-12)  # single-pair zone
    # unrelieved: the one-cycle mean of the mesh stiffness is (1/p_b) x the integral of one
    # pair's stiffness over its whole engagement (each pair passes through the cycle once)
    x = ds["engagement"].values  # pinion roll angle
    k = ds["pair_stiffness"].values
    roll_cycle = ds["cycle"].values[1] * ds.sizes["cycle"]  # p_b / r_b1
    integral = np.sum(0.5 * (k[1:] + k[:-1]) * np.diff(x))
    assert ds["mesh_stiffness_mean_unrelieved"].item() == pytest.approx(integral / roll_cycle, rel=5e-4)


def test_tip_relief_cancelling_the_loaded_ste_lowers_its_peak_to_peak_as_predicted():
    """Prediction: with pair compliance q(s), both tips relieved linearly from the single-pair
    zone boundaries (s_A + p_b on the pinion, s_E - p_b on the wheel) by C = F q at that
    boundary, the two pairs of a two-pair zone have gaps summing to ~C, so
    delta = (F + k_in e_in + k_out e_out) / (k_in + k_out) ~ F q: the loaded STE stays at the
    single-pair level and its peak-to-peak drops from ptp0 to the single-pair-zone variation
    F (q_max - q_min) (with constant pair stiffness: to zero)."""
    plain = _coarse(_example(no_relief=("pinion", "wheel")), n_angles=2000)
    ds0 = run_static(plain).dataset
    geo = json.loads(ds0.attrs["pair_geometry"])
    force = ds0["force"].item()
    m = 2e-3
    rb1, rb2 = 0.5 * m * 20 * math.cos(math.radians(20)), 0.5 * m * 40 * math.cos(math.radians(20))
    pb = math.pi * m * math.cos(math.radians(20))
    length = geo["center_distance"] * math.sin(math.radians(geo["operating_pressure_angle_deg"]))
    ra1, ra2 = 0.5 * m * 20 + 1.25 * m, 0.5 * m * 40 + 1.1 * m
    s_e = math.sqrt(ra1**2 - rb1**2)
    s_a = length - math.sqrt(ra2**2 - rb2**2)
    x = ds0["engagement"].values
    s = s_a + rb1 * x
    q = 1.0 / ds0["pair_stiffness"].values
    single = (s >= s_e - pb) & (s <= s_a + pb)
    c1 = force * np.interp(s_a + pb, s, q)  # pinion tip relief, starts at s_A + p_b
    c2 = force * np.interp(s_e - pb, s, q)  # wheel tip relief, starts at s_E - p_b
    d1 = 2 * math.sqrt(rb1**2 + (s_a + pb) ** 2)
    d2 = 2 * math.sqrt(rb2**2 + (length - (s_e - pb)) ** 2)
    rel = copy.deepcopy(plain)
    rel["pinion"]["tip_relief"] = {"amount": c1, "start_diameter": d1}
    rel["wheel"]["tip_relief"] = {"amount": c2, "start_diameter": d2}
    ds = run_static(rel).dataset
    ptp0 = ds["ste_ptp_unrelieved"].item()
    assert ptp0 == pytest.approx(ds0["ste_ptp"].item(), rel=1e-12)
    predicted_ptp = force * (q[single].max() - q[single].min())
    predicted_drop = ptp0 - predicted_ptp
    measured_drop = ptp0 - ds["ste_ptp"].item()
    # measured (coarse mesh, F = 4257 N, C = 9.48 / 9.83 um): ptp0 4.27 um -> 1.06 um;
    # predicted drop 3.77 um, measured 3.21 um. The idealisation overestimates the drop because
    # the two pairs of a two-pair zone sit near the tips, where q > q(boundary).
    assert measured_drop == pytest.approx(predicted_drop, rel=0.2)
    assert ds["ste_ptp"].item() < 0.25 * ptp0
    # and the mean STE rises to the single-pair level F q (loaded pairs carry more)
    assert ds["ste_mean"].item() == pytest.approx(force * q[single].mean(), rel=0.05)


def test_iso6336_inputs_use_the_reference_circle_load(example_static):
    ds = example_static
    # F_t = T1 / r1 at the reference circle; b = 20 mm -> 80 / 0.02 / 20 = 200 N/mm
    assert ds["iso_load_per_width"].item() == pytest.approx(200.0, rel=1e-12)
    assert ds["iso_load_factor"].item() == 1.0
    # c'_th = 1/q' with the shift terms of ISO 6336-1 method B (x1 = 0.25, x2 = 0.1, z 20/40)
    z1, z2, x1, x2 = 20, 40, 0.25, 0.1
    q = (
        0.04723
        + 0.15551 / z1
        + 0.25791 / z2
        - 0.00635 * x1
        - 0.11654 * x1 / z1
        - 0.00193 * x2
        - 0.24188 * x2 / z2
        + 0.00529 * x1**2
        + 0.00182 * x2**2
    )
    assert ds["iso_c_th"].item() == pytest.approx(1 / q, rel=1e-12)
    cb = 1 + 0.5 * (1.2 - 1.25)  # h_fP / m = 1.25, alpha = 20 deg
    # C_R: solid pinion 1; rimmed wheel (web 8 mm of b = 20 mm, rim 6 mm = 3 m):
    # 1 + ln(0.4) / (5 exp(3 / 5)); the pair uses the mean of both
    c_r = 0.5 * (1.0 + 1.0 + math.log(0.4) / (5 * math.exp(0.6)))
    assert ds["iso_C_R"].item() == pytest.approx(c_r, rel=1e-12)
    assert ds["iso_c_prime"].item() == pytest.approx(0.8 * cb * c_r / q, rel=1e-12)
    eps = json.loads(ds.attrs["pair_geometry"])["contact_ratio"]
    assert ds["iso_c_gamma_alpha"].item() == pytest.approx(0.8 * cb * c_r / q * (0.75 * eps + 0.25), rel=1e-12)


def test_cli_gear_static_writes_result_and_rejects_bad_input(tmp_path):
    text = EXAMPLE.read_text().replace('preset = "default"', 'preset = "coarse"')
    text = text.replace("refinement = [1, 2]", "refinement = [1]")
    cfg = tmp_path / "pair.toml"
    cfg.write_text(text)
    out = tmp_path / "out"
    r = CliRunner().invoke(app, ["gear", "static", str(cfg), "--out", str(out), "--quiet"])
    assert r.exit_code == 0, r.output
    assert (out / "result.nc").exists() and (out / "mesh_stiffness_ste.png").exists()
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"]["value"] == "success"
    assert summary["ste_ptp"]["value"] < summary["ste_ptp_unrelieved"]["value"]
    from rotaflex.core.result import load_result

    assert type(load_result(out / "result.nc")).__name__ == "StaticResult"
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace("teeth = 40", "teeth = 40\nmodule_mm = 2"))
    r = CliRunner().invoke(app, ["gear", "static", str(bad), "--out", str(out)])
    assert r.exit_code == 2
    assert "wheel.module_mm" in r.output and len(r.output.strip().splitlines()) == 1


def test_wheel_driving_runs_the_same_contact_in_reverse(example_static):
    wheel = _coarse(_example())
    wheel["driver"] = "wheel"
    a, b = example_static, run_static(wheel).dataset
    assert np.array_equal(a["ste_engagement"].values, b["ste_engagement"].values[::-1])
    assert np.array_equal(a["load_share"].values, b["load_share"].values[::-1])
    # roll angle of the driving wheel = pinion roll / ratio
    assert b["engagement"].values[-1] == pytest.approx(a["engagement"].values[-1] / 2, rel=1e-12)


def test_compliance_diameters_outside_the_flank_name_the_field():
    from rotaflex.core.errors import InputError

    cfg = _coarse(_example())
    cfg["analysis"]["compliance_diameters_wheel"] = [0.04, 0.081]
    with pytest.raises(InputError, match="analysis.compliance_diameters_wheel"):
        run_static(cfg)


def test_unequal_materials_reduce_to_the_identical_formulas_and_scale_with_e():
    from rotaflex.gear.static.loaded_te import contact_compliance, contact_half_width
    from rotaflex.gear.static.tooth_analysis import hertz_half_width, weber_contact_compliance

    e, nu, b = 210e9, 0.3, 0.02
    e2 = e * (1 + 1e-12)  # forces the general (unequal-material) branch
    assert contact_half_width(4e3, b, e, nu, e2, nu, 0.01, 0.02) == pytest.approx(
        hertz_half_width(4e3, b, e, nu, 0.01, 0.02), rel=1e-9
    )
    assert contact_compliance(4e3, b, e, nu, e2, nu, 1e-3, 2e-3, 1e-4) == pytest.approx(
        weber_contact_compliance(4e3, b, e, nu, 1e-3, 2e-3, 1e-4), rel=1e-9
    )
    steel = _coarse(_example(no_relief=("pinion", "wheel")))
    alu = copy.deepcopy(steel)
    alu["wheel"]["material"] = {"name": "aluminium", "poisson_ratio": 0.3}
    a, b_ = run_static(steel).dataset, run_static(alu).dataset
    # linear plane-stress FE at fixed nu: tooth compliance ~ 1/E (the Hertz patch width, which
    # changes with E*, moves it slightly)
    ratio = b_["tooth_compliance"].values[1] / a["tooth_compliance"].values[1]
    assert ratio == pytest.approx(np.full(ratio.size, 3.0), rel=0.01)
    assert np.allclose(b_["tooth_compliance"].values[0], a["tooth_compliance"].values[0], rtol=0.01)
    assert b_["ste_mean"].item() > 1.5 * a["ste_mean"].item()
