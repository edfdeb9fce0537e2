"""``gear steady`` (lumped) of a helical pair: the axial mesh force against ISO formulas, the
helical mesh's smaller dynamic response than the spur pair of the same transverse section (same
mean stiffness, far smaller fluctuation), the overlap ratio in the output, refusals."""

import copy
import math
import tomllib
from pathlib import Path

import pytest

from rotaflex.core.errors import InputError
from rotaflex.gear.cases.steady import run_torsional

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "gear" / "helical_pair.toml"
BETA = math.radians(15.0)


def _cfg(speed, **over):
    cfg = tomllib.loads(EXAMPLE.read_text())
    cfg.pop("domain")
    cfg.pop("sweep")
    cfg["operation"]["speed_rpm"] = speed
    cfg["steady"] = {"tol": 1e-4, "eval_cycles": 10, "max_cycles": 300}
    for g in ("pinion", "wheel"):
        cfg[g].pop("lead", None)
    cfg.update(over)
    return cfg


def _spur_of_the_same_transverse_section(cfg):
    """The spur pair whose gears are the helical pair's transverse sections (m_t, alpha_t,
    coefficients x cos(beta)); the face model then has one slice position per cycle."""
    spur = copy.deepcopy(cfg)
    at = math.atan(math.tan(math.radians(20.0)) / math.cos(BETA))
    an, c = math.radians(20.0), math.cos(BETA)
    for g in ("pinion", "wheel"):
        d = spur[g]
        d.pop("helix_angle_deg")
        d.pop("hand")
        d.update(
            module=d["module"] / c,
            pressure_angle_deg=math.degrees(at),
            addendum_coef=c,
            dedendum_coef=1.25 * c,
            profile_shift=d.get("profile_shift", 0.0) * c,
            rack_tip_radius_coef=0.38 * (1 - math.sin(an)) / (1 - math.sin(at)) * c,
        )
    return spur


def test_axial_force_and_quasi_static_point():
    res = run_torsional(_cfg(2000.0))
    ds = res.dataset
    # quasi-static: the mean axial mesh force is T tan(beta_w) / r_w (ISO 21771 written out here)
    torque = 80.0
    mt = 2e-3 / math.cos(BETA)
    at = math.atan(math.tan(math.radians(20.0)) / math.cos(BETA))
    inv = math.tan(at) - at + 2 * math.tan(math.radians(20.0)) * 0.2 / 60
    awt = at
    for _ in range(60):  # Newton on inv(alpha_wt)
        awt -= (math.tan(awt) - awt - inv) / math.tan(awt) ** 2
    a = 0.5 * 60 * mt * math.cos(at) / math.cos(awt)
    rw1 = a * 20 / 60
    bw = math.atan(math.tan(BETA) * rw1 / (0.5 * 20 * mt))
    expected = torque * math.tan(bw) / rw1
    assert float(ds["axial_force_static"]) == pytest.approx(expected, rel=1e-9)
    assert float(ds["axial_mesh_force"].mean()) == pytest.approx(expected, rel=2e-3)
    eps_b = 0.02 * math.sin(BETA) / (math.pi * 2e-3)
    assert float(ds["overlap_ratio"]) == pytest.approx(eps_b, rel=1e-12)


def test_helical_mesh_responds_less_than_the_spur_pair_of_its_transverse_section():
    speed = 36000.0  # near the mesh resonance of both (same mean stiffness)
    hel = run_torsional(_cfg(speed)).dataset
    spur = run_torsional(_spur_of_the_same_transverse_section(_cfg(speed))).dataset
    assert float(hel["mean_mesh_stiffness"]) == pytest.approx(float(spur["mean_mesh_stiffness"]), rel=0.01)
    assert float(hel["dynamic_factor"]) - 1 < 0.6 * (float(spur["dynamic_factor"]) - 1)
    assert float(hel["dte_pp"]) < 0.6 * float(spur["dte_pp"])
    assert "axial_mesh_force" not in spur


def test_elastic_teeth_refuses_a_helical_pair():
    cfg = _cfg(2000.0)
    cfg["model"] = {"method": "elastic_teeth"}
    with pytest.raises(InputError) as err:
        run_torsional(cfg)
    assert err.value.field == "pinion.helix_angle_deg"


def test_iso_kv_input_takes_the_helical_terms():
    from rotaflex.gear.cases.steady import build_system
    from rotaflex.gear.cases.steady_config import checked
    from rotaflex.gear.cases.steady_output import iso_data

    cfg = checked(_cfg(20000.0))
    sys, eps = build_system(cfg)
    iso = iso_data(cfg, sys, eps, 0.02)
    eps_b = 0.02 * math.sin(BETA) / (math.pi * 2e-3)
    assert iso.eps_gamma == pytest.approx(eps + eps_b, rel=1e-12)
    # c' of ISO 6336-1 with virtual teeth z_n = z / (cos^2(beta_b) cos(beta)), x_n, cos(beta)
    bb = math.asin(math.sin(BETA) * math.cos(math.radians(20.0)))
    zn = 1 / (math.cos(bb) ** 2 * math.cos(BETA))
    z1, z2, x1 = 20 * zn, 40 * zn, 0.2
    q = 0.04723 + 0.15551 / z1 + 0.25791 / z2 - 0.00635 * x1 - 0.11654 * x1 / z1 + 0.00529 * x1**2
    c_prime = 1 / q * 0.8 * 0.975 * math.cos(BETA)  # N/(mm um); F_t/b > 100 N/mm here
    assert iso.c_single == pytest.approx(c_prime * 1e9, rel=1e-12)
    assert iso.c_gamma_alpha == pytest.approx(c_prime * 1e9 * (0.75 * eps + 0.25), rel=1e-12)
