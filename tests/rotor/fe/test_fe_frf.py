"""Frequency response functions and the direct critical-speed solve, vs closed forms and second formulations."""

import json
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from rotaflex.rotor.fe.critical import critical_speeds
from rotaflex.rotor.fe.frf import dof_index, frf, half_power
from rotaflex.rotor.fe.modal import campbell, modal
from rotaflex.rotor.fe.model import Bearing, Disk, Rotor, Shaft
from rotaflex.rotor.fe.ucs import ucs_map

RPM = np.pi / 30
EXAMPLE = Path(__file__).resolve().parents[3] / "examples" / "rotor" / "fe_api684.toml"


def test_single_dof_receptance_closed_form():
    """Disk at the middle of a rigid light shaft on two equal bearings: x-translation is a 1-DOF oscillator."""
    m, k, c = 20.0, 2e6, 400.0
    r = Rotor(
        shaft=(Shaft(outer_diameter=0.05, length=0.4, elements=2, rigid=True, rho=1e-3),),
        disk=(Disk(node=1, mass=m, Id=0.5, Ip=0.2),),
        bearing=(Bearing(node=0, kxx=k / 2, kyy=k / 2, cxx=c / 2, cyy=c / 2),) * 1
        + (Bearing(node=2, kxx=k / 2, kyy=k / 2, cxx=c / 2, cyy=c / 2),),
    )
    m_tot = r.mass  # the shaft adds a little mass (rho = 1e-3)
    w = np.linspace(10, 1000, 400)
    H = frf(r, w, 0.0, [dof_index(r, 1, "x")]).H[:, 0, 0]
    exact = 1 / (k - m_tot * w**2 + 1j * c * w)
    assert np.max(np.abs(H - exact) / np.abs(exact)) < 1e-6
    mob = frf(r, w, 0.0, [dof_index(r, 1, "x")], kind="mobility").H[:, 0, 0]
    assert np.allclose(mob, 1j * w * H, rtol=1e-12)


def _rotor(kxx=2e6, kyy=3e6, kxy=0.0, c=60.0):
    return Rotor(
        shaft=(Shaft(outer_diameter=0.05, length=1.2, elements=6),),
        disk=(Disk(node=2, mass=20.0, Id=0.1, Ip=0.2), Disk(node=4, mass=30.0, Id=0.15, Ip=0.3)),
        bearing=tuple(
            Bearing(node=n, kxx=kxx, kyy=kyy, kxy=kxy, kyx=kxy, cxx=c, cyy=c) for n in (0, 6)
        ),  # symmetric cross-coupling
    )


def test_frf_peaks_at_modal_frequencies_with_modal_damping():
    r = _rotor(kxx=2e6, kyy=2e6, c=600.0)
    md = modal(r, 0.0, 4)  # isotropic, non-rotating: modes 0 and 2 are x-z modes of their pairs
    for mode in (0, 2):
        wd, zeta = md.wd[0, mode], md.damping_ratio[0, mode]
        w = np.linspace(wd * (1 - 8 * zeta), wd * (1 + 8 * zeta), 4001)
        amp = np.abs(frf(r, w, 0.0, [dof_index(r, 4, "x")]).H[:, 0, 0])
        (p,) = half_power(w, amp)
        # peak of |H| vs omega_d: O(zeta^2), plus the residual of the other modes, which moves the
        # weak second peak (receptance 100 x smaller than the first) by 0.8 %
        assert p["frequency"] == pytest.approx(wd, rel=1e-4 if mode == 0 else 1e-2)
        assert p["zeta"] == pytest.approx(zeta, rel=0.03)  # half-power width / (2 omega) = zeta + O(zeta^2)


def test_reciprocity_without_rotation_and_its_breaking_by_gyroscopics():
    r = _rotor(kxy=5e5)
    i, j = dof_index(r, 2, "x"), dof_index(r, 5, "y")
    w = np.linspace(20, 600, 50)
    H = frf(r, w, 0.0, [i, j], [i, j]).H
    assert np.max(np.abs(H[:, 0, 1] - H[:, 1, 0])) < 1e-10 * np.max(np.abs(H[:, 0, 1]))
    Hs = frf(r, w, 6000 * RPM, [i, j], [i, j]).H
    assert np.max(np.abs(Hs[:, 0, 1] - Hs[:, 1, 0])) > 1e-3 * np.max(np.abs(Hs[:, 0, 1]))


def test_direct_forward_criticals_equal_the_ucs_formulation():
    """Isotropic undamped rotor: forward synchronous criticals from the one-plane UCS problem (exact)."""
    k = 5e6
    r = _rotor(kxx=k, kyy=k, c=0.0)
    cs = critical_speeds(r, np.linspace(1.0, 4000.0, 25), 6)
    fw = [c["speed"] for c in cs if c["whirl"] == "forward"]
    ucs = ucs_map(r, [k], 3)[0]
    ucs = ucs[ucs < 4000.0]
    assert len(fw) == len(ucs) >= 2
    assert np.allclose(fw, ucs, rtol=1e-8)


def test_direct_criticals_match_a_fine_campbell_crossing():
    r = _rotor()
    cs = critical_speeds(r, np.linspace(1.0, 2500.0, 20), 4)
    assert {c["whirl"] for c in cs} >= {"forward", "backward"}
    for c in cs:
        s = c["speed"]
        fine = campbell(r, np.linspace(0.995 * s, 1.005 * s, 81), 4)
        near = [x["speed"] for x in fine.critical if x["mode"] == c["mode"]]
        assert near and min(abs(np.array(near) - s)) / s < 1e-6  # interpolation error of the fine grid


def test_cli_frf_and_campbell_direct(tmp_path: Path):
    from rotaflex.cli import app

    # 600 frequencies instead of 3000 (0.49 Hz apart: the half-power bands are still resolved) and
    # low-resolution figures; the FRF values themselves are checked through the library above
    text = EXAMPLE.read_text().replace("n_frequencies = 3000", "n_frequencies = 600")
    assert "n_frequencies = 600" in text
    (tmp_path / "c.toml").write_text(text)
    out = ["--out", str(tmp_path / "f"), "-q", "--dpi", "40"]
    res = CliRunner().invoke(app, ["rotor", "frf", str(tmp_path / "c.toml"), *out])
    assert res.exit_code == 0, res.output
    s = json.loads((tmp_path / "f" / "summary.json").read_text())
    assert s["kind"]["unit"] == "m/N" and any(k.endswith("half_power_damping_ratio") for k in s)
    assert (tmp_path / "f" / "frf_nyquist.png").exists() and (tmp_path / "f" / "frf_bode.png").exists()


def test_each_pair_carries_its_own_unit():
    """A force to a displacement is m/N, a moment to a rotation rad/(N m): a mixed set of pairs
    says so per pair (the arrays' one attribute cannot)."""
    from rotaflex.core.config import load_toml
    from rotaflex.rotor.fe.frf import pair_unit
    from rotaflex.rotor.fe.verbs import run_frf

    assert pair_unit("receptance", "x", "x") == "m/N"
    assert pair_unit("receptance", "theta_x", "theta_y") == "rad/(N m)"
    assert pair_unit("mobility", "x", "theta_x") == "m/(N m s)"
    assert pair_unit("accelerance", "theta_y", "y") == "rad/(N s^2)"
    cfg = load_toml(EXAMPLE)
    cfg["frf"]["n_frequencies"] = 50
    node = cfg["frf"]["pair"][0]["input_node"] if cfg["frf"].get("pair") else 2
    cfg["frf"]["pair"] = [
        {"input_node": node, "input_direction": "x"},
        {"input_node": node, "input_direction": "theta_x", "output_direction": "theta_x"},
    ]
    ds = run_frf(cfg).dataset
    assert list(ds["pair_unit"].values) == ["m/N", "rad/(N m)"]
    assert ds["amplitude"].attrs["units"] == "see pair_unit"
