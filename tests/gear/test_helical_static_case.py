"""``gear static`` of a helical pair end to end (the example at fewer angles), the helical
outputs with units, the CLI's one-line refusals, and the tiny mode of the STE benchmark."""

import importlib.util
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from rotaflex.gear.cases.static import run_static

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "gear" / "helical_pair.toml"


@pytest.fixture(scope="module")
def result():
    cfg = tomllib.loads(EXAMPLE.read_text())
    cfg.pop("domain")
    cfg["analysis"]["n_angles"] = 60
    return run_static(cfg)


def test_helical_static_outputs(result):
    s = result.summary()
    for key, unit in (
        ("geometry_overlap_ratio", "1"),
        ("geometry_total_contact_ratio", "1"),
        ("geometry_base_helix_angle_deg", "deg"),
        ("geometry_axial_pitch", "m"),
        ("geometry_pinion_lead", "m"),
        ("axial_force", "N"),
        ("normal_force", "N"),
        ("tilting_moment_pinion", "N m"),
        ("iso_c_gamma_beta", "N/(mm um)"),
    ):
        assert s[key]["unit"] == unit, key
    # axial force from the slices' transverse force equals T tan(beta_w) / r_w1 (ISO formulas)
    assert s["axial_force"]["value"] == pytest.approx(s["axial_force_check"]["value"], rel=1e-12)
    beta_b = math.radians(s["geometry_base_helix_angle_deg"]["value"])
    assert s["normal_force"]["value"] == pytest.approx(s["force"]["value"] / math.cos(beta_b), rel=1e-12)
    # tilting moments of the axial force at the working pitch radii r_w = a z / (z1 + z2)
    a = s["geometry_center_distance"]["value"]
    for name, z in (("pinion", 20), ("wheel", 40)):
        moment = s["axial_force"]["value"] * a * z / 60
        assert s[f"tilting_moment_{name}"]["value"] == pytest.approx(moment, rel=1e-12)
    ds = result.dataset
    # every slice load of one tooth pair is >= 0 and the crowned face carries most at mid-face
    ll = ds["line_load"].values
    assert ll.min() >= 0.0 and ll.shape[1] == 20
    per_z = ll.sum(axis=0)
    assert per_z[9] > per_z[0] and per_z[10] > per_z[-1]
    # the load per unit length over a mesh cycle averages to F / (eps_alpha b) on the contact lines:
    # sum over the sweep of one tooth = the cycle sum of all pairs (mean over samples)
    n_cyc = ds.sizes["cycle"]
    total = ll.sum() * (0.02 / 20) / n_cyc  # sum_j f_j over all pairs, cycle mean [N]
    assert total == pytest.approx(s["force"]["value"], rel=1e-6)
    assert set(result.plot()) >= {"line_load", "mesh_stiffness_ste"}


def test_bench_tiny_mode_meets_the_cost_bound():
    spec = importlib.util.spec_from_file_location("bench_helical_ste", ROOT / "benchmarks" / "bench_helical_ste.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    out = mod.run(tiny=True, repeat=1)
    assert out["ratio"] <= 3.0 and np.isfinite(out["spur_s"])


@pytest.mark.parametrize(
    "old, new, key",
    [
        ('hand = "left"', 'hand = "right"', "wheel.hand"),
        ("helix_angle_deg = 15.0\nhand", "helix_angle_deg = 45.0\nhand", "pinion.helix_angle_deg"),
        ("slices = 20", "slices = 400", "pinion.face_width"),
    ],
)
def test_cli_refuses_bad_helical_input_in_one_line(tmp_path, old, new, key):
    import os
    import subprocess
    import sys

    text = EXAMPLE.read_text()
    assert old in text
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace(old, new, 1))
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    out = subprocess.run(
        [sys.executable, "-m", "rotaflex", "gear", "static", str(bad), "--out", str(tmp_path / "o"), "-q"],
        capture_output=True,
        text=True,
        env=env,
    )
    assert out.returncode == 2, out.stderr
    lines = [ln for ln in out.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and key in lines[0]
