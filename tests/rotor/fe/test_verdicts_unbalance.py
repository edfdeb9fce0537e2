"""Unbalance verdicts from every probe, API unbalance over the planes of a mode, maxima at the
range end (issue 37 item 2, issue 38 item 4)."""

import json
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from rotaflex.cli import app
from rotaflex.core.result import load_result
from rotaflex.rotor.fe.model import Bearing, Disk, Rotor, Shaft
from rotaflex.rotor.fe.response import peaks, unbalance_response

RAD_PER_RPM = np.pi / 30
ROOT = Path(__file__).resolve().parents[3]

# a symmetric rotor: 1.2 m, 60 mm steel shaft in 12 elements, three equal 25 kg wheels at
# nodes 3, 6, 9 (0.3, 0.6, 0.9 m), equal bearings at both ends
THREE_WHEELS = """
[[shaft]]
outer_diameter = 0.06
length = 1.2
elements = 12
[[disk]]
node = 3
mass = 25.0
Id = 0.2
Ip = 0.4
[[disk]]
node = 6
mass = 25.0
Id = 0.2
Ip = 0.4
[[disk]]
node = 9
mass = 25.0
Id = 0.2
Ip = 0.4
[[bearing]]
node = 0
kxx = 2e7
kyy = 2e7
cxx = 2e3
cyy = 2e3
[[bearing]]
node = 12
kxx = 2e7
kyy = 2e7
cxx = 2e3
cyy = 2e3
[unbalance]
speed_rpm = [500, 12000]
n_speeds = 200
operating_range_rpm = [3000, 9000]
api_unbalance = true
probes = [3, 6, 9]
"""


def _run(tmp_path: Path, text: str, name: str = "c") -> dict:
    case = tmp_path / f"{name}.toml"
    case.write_text(text)
    out = tmp_path / name
    res = CliRunner().invoke(app, ["rotor", "unbalance", str(case), "--out", str(out), "-q", "--no-figures"])
    assert res.exit_code == 0, res.output
    return json.loads((out / "summary.json").read_text()) | {"_output": res.output, "_dir": str(out)}


def _hand_shares():
    """Mass lumped to each plane by hand: a uniform element's mass splits half to each end node
    (rigid translation); nodes 0-4 are nearest the plane at node 3, 5-7 the middle plane,
    8-12 the plane at node 9: 4.5, 3 and 4.5 elements of shaft, plus one wheel each."""
    m_el = 7810.0 * np.pi * 0.06**2 / 4 * 0.1  # the default steel (Friswell et al. Example 5.9.1)
    return np.array([25 + 4.5 * m_el, 25 + 3 * m_el, 25 + 4.5 * m_el]), 75 + 12 * m_el


def test_three_equal_wheels_share_the_weight_symmetrically(tmp_path):
    s = _run(tmp_path, THREE_WHEELS)
    planes = s["unbalance_planes"]["value"]
    share, total = _hand_shares()
    np.testing.assert_allclose([p["mass_share_kg"] for p in planes], share, rtol=1e-12)
    U = np.array([p["magnitude_g_mm"] for p in planes])
    # in phase: U = 6350 W / N with W the whole rotor (API 617 4.8.2.7), by mass share; N = 9000 rpm
    np.testing.assert_allclose(U, 6350 * share / 9000, rtol=1e-12)
    assert U.sum() == pytest.approx(6350 * total / 9000, rel=1e-12)
    assert U[0] == pytest.approx(U[2], rel=1e-12)  # was 71 / 71 / 142: the middle wheel given to one bearing


def test_first_mode_arrangement_concentrates_the_unbalance_at_the_antinode(tmp_path):
    s = _run(tmp_path, THREE_WHEELS + 'arrangement = "mode"\narrangement_mode = 0\n')
    planes = s["unbalance_planes"]["value"]
    U = np.array([p["magnitude_g_mm"] for p in planes])
    _, total = _hand_shares()
    assert U.sum() == pytest.approx(6350 * total / 9000, rel=1e-12)  # one lobe: the whole weight
    assert U[1] > U[0] and U[0] == pytest.approx(U[2], rel=1e-9)
    assert all(abs(p["phase_deg"]) < 0.1 for p in planes)  # in phase with the first bending mode


def test_second_mode_arrangement_gives_each_half_its_weight(tmp_path):
    s = _run(tmp_path, THREE_WHEELS + 'arrangement = "mode"\narrangement_mode = 1\n')
    planes = s["unbalance_planes"]["value"]
    U = np.array([p["magnitude_g_mm"] for p in planes])
    _, total = _hand_shares()
    # API: two unbalances 180 deg apart, each with the load of its half (here half the rotor)
    np.testing.assert_allclose(U[[0, 2]], 6350 * total / 2 / 9000, rtol=1e-9)
    assert U[1] == 0.0  # the middle wheel sits on the mode's node line
    assert abs(abs(planes[2]["phase_deg"] - planes[0]["phase_deg"]) - 180) < 1e-6
    # the 1e-13 um round-off at the middle probe (a node line) does not make criticals
    assert "e-1" not in s["_output"].split("peaks [rpm]:")[1].split(";")[0]


def test_every_probe_counts_and_the_governing_one_is_named(tmp_path):
    """The fluid-film example's second critical is largest at the first disk (node 6): with the
    probes listed either way round the same peaks are reported, with node 6 governing it."""
    text = (ROOT / "examples" / "rotor" / "fe_fluid_film.toml").read_text().replace("n_speeds = 50", "n_speeds = 24")
    a = _run(tmp_path, text, "a")
    b = _run(tmp_path, text.replace("probes = [6, 14]", "probes = [14, 6]"), "b")
    keys = [k for k in a if k.startswith("peak_")]
    assert keys and keys == [k for k in b if k.startswith("peak_")]
    for k in keys:
        assert a[k]["value"] == b[k]["value"] or (a[k]["value"] != a[k]["value"])  # nan == nan aside
    ds = load_result(Path(a["_dir"]) / "result.nc").dataset
    for i in range(len([k for k in keys if k.endswith("_speed_rpm")])):
        rpm, probe = a[f"peak_{i}_speed_rpm"]["value"], a[f"peak_{i}_probe"]["value"]
        j = int(np.argmin(np.abs(ds["speed_rpm"].values - rpm)))
        near = ds["major_axis"].isel(speed=slice(max(j - 2, 0), j + 3)).max("speed")
        assert int(near.idxmax("probe")) == probe  # the governing probe has the largest response there
    governing = {a[f"peak_{i}_probe"]["value"] for i in range(2)}
    assert governing == {6, 14}  # the old code rated every peak from the first probe alone


def _jeffcott(m=10.0, k=1e6, c=200.0):
    return Rotor(
        shaft=(Shaft(outer_diameter=0.05, length=0.2, elements=1, rigid=True, rho=1e-6),),
        disk=(Disk(node=0, mass=m / 2, Id=1.0, Ip=0.5), Disk(node=1, mass=m / 2, Id=1.0, Ip=0.5)),
        bearing=(
            Bearing(node=0, kxx=k / 2, kyy=k / 2, cxx=c / 2, cyy=c / 2),
            Bearing(node=1, kxx=k / 2, kyy=k / 2, cxx=c / 2, cyy=c / 2),
        ),
    )


def test_a_maximum_at_the_range_end_is_reported_with_its_value():
    m, k, c, u = 10.0, 1e6, 200.0, 1e-4
    wn = np.sqrt(k / m)

    def closed(w):  # |X| of u W^2 / (k - m W^2 + i c W), u split over the two disks
        return u * w**2 / np.abs(k - m * w**2 + 1j * c * w)

    r = _jeffcott(m, k, c)
    below = np.linspace(0.2 * wn, 0.8 * wn, 301)  # the critical above the range
    amp = unbalance_response(r, below, [(0, u / 2, 0.0), (1, u / 2, 0.0)]).major_axis(0)
    assert peaks(below, amp) == []  # the old answer: nothing
    (end,) = peaks(below, amp, range_end=True)
    assert end["kind"] == "rising at the range end"
    assert end["speed"] == below[-1] and end["amplitude"] == pytest.approx(closed(below[-1]), rel=1e-9)
    # the peak inside, its upper half-power point beyond the range end (zeta = 0.01: band +- 1 %)
    cut = np.linspace(0.5 * wn, 1.005 * wn, 2001)
    amp = unbalance_response(r, cut, [(0, u / 2, 0.0), (1, u / 2, 0.0)]).major_axis(0)
    assert peaks(cut, amp) == []
    (pk,) = peaks(cut, amp, range_end=True)
    nc = wn / np.sqrt(1 - 2 * (c / (2 * np.sqrt(k * m))) ** 2)  # peak of w^2 / |...|: wn / sqrt(1 - 2 zeta^2)
    assert pk["kind"] == "half-power band beyond the range" and np.isnan(pk["af"]) and np.isfinite(pk["n1"])
    assert pk["speed"] == pytest.approx(nc, rel=1e-6) and pk["amplitude"] == pytest.approx(closed(nc), rel=1e-6)


def test_range_end_through_the_cli_rated_with_the_largest_margin(tmp_path):
    text = THREE_WHEELS.replace("speed_rpm = [500, 12000]", "speed_rpm = [500, 1800]").replace(
        "operating_range_rpm = [3000, 9000]", "operating_range_rpm = [1000, 1600]"
    )
    s = _run(tmp_path, text)
    assert s["peak_0_speed_rpm"]["kind"] == "rising at the range end"
    assert s["peak_0_speed_rpm"]["value"] == pytest.approx(1800)
    ds = load_result(Path(s["_dir"]) / "result.nc").dataset
    assert s["peak_0_amplitude"]["value"] == pytest.approx(float(ds["major_axis"].isel(speed=-1).max()), rel=1e-12)
    # unknown AF: rated as AF -> inf, 26 % above 1600 rpm required; 1800 rpm is 12.5 % above
    assert s["peak_0_required_separation_margin"]["value"] == pytest.approx(26.0)
    assert s["peak_0_meets_api684_margin"]["value"] == 0.0
    assert "rising at the range end" in s["_output"]
