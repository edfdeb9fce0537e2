"""Contact point of a helical mesh at the centroid of the load over the face (docs/geared-rotor.md,
"Helical meshes", "Contact point off mid-face").

References: symmetry (a modification symmetric about mid-face keeps the resultant there, a
mirrored one mirrors it), two inputs that open the same gap (a helix slope deviation f_Hb and a
misalignment f_Hb / b), the centroid of a trapezoidal load ``b/6 (w2 - w1)/(w1 + w2)`` from the
end loads of the gear package's own slice solution, and the moments ``r x F`` written by hand.
"""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest

from rotaflex.core.errors import InputError
from rotaflex.gear import pair_from_mapping
from rotaflex.gear.static.helical import face_model, slice_positions, sliced_te
from rotaflex.system.assembly import matrices
from rotaflex.system.face_load import PHASES, face_line
from rotaflex.system.helical import static_outputs, static_state, tilting_moments
from rotaflex.system.model import Gearbox

BETA, MN = 15.0, 3.0e-3
B = 0.02  # face width [m]
T = 100.0  # pinion torque [N m]
MIS = 2e-5  # misalignment of the trapezoid case [rad]: gap 1.5 um over b, approach ~5 um


def _gear(teeth: int, hand: str, width: float) -> dict:
    return {"teeth": teeth, "module": MN, "face_width": width, "helix_angle_deg": BETA, "hand": hand}


def _config(width: float = B, k_mean: float = 2.0e8, rotation: str = "ccw", **mesh) -> dict:
    """Two one-element steel rotors on bearings at both ends, a thrust bearing at node 0, the
    gears at node 1 (mid-face = the node), harmonic mesh table, pinion held at constant speed,
    load torque 2 T on the output (T on the pinion)."""
    pair = pair_from_mapping({"pinion": _gear(20, "right", width), "wheel": _gear(40, "left", width)})

    def rotor(name, x):
        return {
            "name": name,
            "center": [x, 0.0],
            "shaft": [{"outer_diameter": 0.05, "length": 0.1, "elements": 1}],
            "disk": [{"node": 1, "mass": 5.0, "Id": 5e-3, "Ip": 1e-2}],
            "bearing": [{"node": 0, "kxx": 2e8, "kyy": 2e8, "kzz": 1e8}, {"node": 1, "kxx": 2e8, "kyy": 2e8}],
        }

    m = {
        "pinion_rotor": "in",
        "pinion_node": 1,
        "wheel_rotor": "out",
        "wheel_node": 1,
        "source": "harmonic",
        "k_mean": k_mean,
        "torque": T,
        "blanks": False,
        "pinion": _gear(20, "right", width),
        "wheel": _gear(40, "left", width),
    }
    m.update(copy.deepcopy(mesh))
    return {
        "rotor": [rotor("in", 0.0), rotor("out", pair.working_center_distance)],
        "gear_mesh": [m],
        "drive": {"rotor": "in", "node": 0, "kind": "constant_speed", "rotation": rotation},
        "load": {"rotor": "out", "node": 0, "torque": 2 * T},
    }


def _with_lead(cfg: dict, gear: str, **lead) -> dict:
    cfg["gear_mesh"][0][gear]["lead"] = lead
    return cfg


def _offset(cfg: dict) -> float:
    return Gearbox.from_mapping(cfg).meshes[0].offset


def test_unmodified_pair_keeps_the_mid_face_contact():
    plain = Gearbox.from_mapping(_config())
    mid = Gearbox.from_mapping(_config(contact_point="mid_face"))
    assert plain.meshes[0].offset == 0.0
    g0, g1 = matrices(plain).g, matrices(mid).g
    assert np.array_equal(g0, g1)  # bit-identical: the default is mid-face without modifications
    # asked for, the centroid of an unmodified face is mid-face up to the cycle sampling
    cen = Gearbox.from_mapping(_config(contact_point="load_centroid"))
    assert abs(cen.meshes[0].offset) < 1e-12 * B  # round-off (measured 1e-17 b)
    assert np.max(np.abs(matrices(cen).g - g0)) < 1e-12 * B


def test_symmetric_crowning_keeps_mid_face_and_mirrored_slope_mirrors_the_offset():
    crowned = _offset(_with_lead(_config(), "pinion", crowning=10e-6))
    relieved = _offset(_with_lead(_config(), "wheel", end_relief=5e-6, end_relief_length=0.004))
    # symmetric gaps: the resultant stays at mid-face (round-off, measured 2e-17 b)
    assert abs(crowned) < 1e-12 * B and abs(relieved) < 1e-12 * B
    plus = _offset(_with_lead(_config(), "pinion", slope_deviation=8e-6))
    minus = _offset(_with_lead(_config(), "wheel", slope_deviation=-8e-6))
    # f_Hb > 0 removes material towards +z: the gap grows towards +z, the load moves to -z
    assert plus < -0.02 * B
    assert abs(plus + minus) < 1e-12 * B  # mirrored gap, mirrored offset (round-off)


def test_slope_deviation_and_misalignment_of_the_same_gap_give_the_same_offset():
    f_hb = 8e-6
    slope = _offset(_with_lead(_config(), "pinion", slope_deviation=f_hb))
    tilt = _offset(_config(face={"misalignment": f_hb / B}))
    assert slope == pytest.approx(tilt, rel=1e-9, abs=1e-12)


def test_end_relief_with_a_slope_keeps_the_slope_side_and_pulls_the_load_inwards():
    """End relief at both ends (no crowning) added to a slope deviation: the relief unloads both
    ends, most where the load is highest (-z), so the offset keeps the slope's sign but is
    smaller in magnitude."""
    slope = _offset(_with_lead(_config(), "pinion", slope_deviation=8e-6))
    both = _offset(_with_lead(_config(), "pinion", end_relief=5e-6, end_relief_length=0.004, slope_deviation=8e-6))
    assert slope < both < 0.0


def test_pure_misalignment_centroid_matches_the_trapezoid_of_the_gear_side_end_loads():
    """eps_beta = 2 (b = 2 pi m_n / sin beta), independent slices (coupling length 0): a linear
    gap in full contact gives a near-linear load; its centroid is b/6 (w2 - w1)/(w1 + w2) with
    the end loads w1 (z = -b/2), w2 (z = +b/2) extrapolated from the gear package's own slice
    loads (sliced_te) averaged over the mesh cycle."""
    width = 2 * math.pi * MN / math.sin(math.radians(BETA))
    face = {"misalignment": MIS, "coupling_length_coef": 0.0}
    cfg = _config(width, k_mean=2e8 * width / B, face=face)
    box = Gearbox.from_mapping(cfg)
    pair = pair_from_mapping({"pinion": _gear(20, "right", width), "wheel": _gear(40, "left", width)})
    assert pair.overlap_ratio == pytest.approx(2.0, rel=1e-12)
    fm = face_model(pair, 20, 0.0, MIS)
    line = face_line(pair, box.meshes[0].gear, fm, "harmonic")
    s = line.s_start + (np.arange(4 * PHASES) + 0.5) / (4 * PHASES) * line.base_pitch  # a finer cycle
    load = sliced_te(line, fm, s)["load"].sum(axis=1).mean(axis=0)  # per slice [N], cycle mean
    z = slice_positions(width, 20)
    assert load.min() > 0.5 * load.max()  # full contact
    fit = np.polyfit(z, load, 1)
    assert np.max(np.abs(load - np.polyval(fit, z))) < 0.02 * load.mean()  # linear: measured 0.25 %
    w1 = load[0] - 0.5 * (load[1] - load[0])
    w2 = load[-1] + 0.5 * (load[-1] - load[-2])
    closed = width / 6 * (w2 - w1) / (w1 + w2)
    zc = box.meshes[0].offset
    assert zc < 0  # the gap grows with z (misalignment > 0): load towards -z
    assert zc == pytest.approx(closed, rel=1e-2)  # measured 0.32 % (0.25 % of it: the slices' midpoint sum, 1/N^2)


@pytest.mark.parametrize("rotation", ["ccw", "cw"])
def test_tilting_moments_and_generalised_forces_by_hand(rotation):
    cfg = _with_lead(_config(rotation=rotation), "pinion", slope_deviation=8e-6)
    box = Gearbox.from_mapping(cfg)
    m = box.meshes[0]
    zc = m.offset
    assert zc < -0.02 * B
    q, F = static_state(box, 100.0)
    pair = pair_from_mapping({"pinion": _gear(20, "right", B), "wheel": _gear(40, "left", B)})
    rb1, rb2 = (g.base_radius for g in pair.gears)
    alpha = pair.operating_pressure_angle
    assert F[0] == pytest.approx(T / rb1, rel=1e-10)
    s = 1 if rotation == "ccw" else -1
    n = np.array([math.sin(alpha), s * math.cos(alpha)])  # line of action (driver at the origin)
    fa = -s * F[0] * math.tan(pair.base_helix_angle)  # on the wheel: right-hand driver, sigma = -s
    # driven gear (wheel, centre at +x): contact at (-r_w2, 0, z_c) from its centre, force F (n + fa/F e_z)
    r_w1, r_w2 = rb1 / math.cos(alpha), rb2 / math.cos(alpha)
    for k, r in ((1, np.array([-r_w2, 0.0, zc])), (0, np.array([r_w1, 0.0, zc]))):
        force = np.array([F[0] * n[0], F[0] * n[1], fa]) * (1 if k == 1 else -1)
        hand = np.cross(r, force)[:2]
        np.testing.assert_allclose(tilting_moments(box, F)[0, k], hand, rtol=1e-12, atol=1e-9)
        # the part from the offset is the transverse force's moment, magnitude F z_c = F_n cos(beta_b) z_c
        axial_only = np.cross(r * [1, 1, 0], force)[:2]
        assert np.hypot(*(hand - axial_only)) == pytest.approx(F[0] * abs(zc), rel=1e-12)
    # the same moments are the generalised forces -F g on the gears' tilt DOFs
    g = matrices(box).g[0]
    for k, (rot, node) in enumerate((m.driver, m.driven)):
        dofs = [box.lateral_dof(rot, node, a) for a in (2, 3)]
        np.testing.assert_allclose(-F[0] * g[dofs], tilting_moments(box, F)[0, k], rtol=1e-12)


def test_static_outputs_report_the_offset():
    box = Gearbox.from_mapping(_with_lead(_config(), "pinion", slope_deviation=8e-6))
    data, _, extra = static_outputs(box, 100.0)
    assert data["contact_offset"][1][0] == box.meshes[0].offset
    assert extra["mesh0_contact_offset"]["value"] == box.meshes[0].offset
    plain, _, extra0 = static_outputs(Gearbox.from_mapping(_config()), 100.0)
    assert "contact_offset" not in plain and "mesh0_contact_offset" not in extra0


def test_spur_pair_refuses_the_load_centroid():
    cfg = _config(contact_point="load_centroid")
    for g in ("pinion", "wheel"):
        cfg["gear_mesh"][0][g].pop("helix_angle_deg")
        cfg["gear_mesh"][0][g].pop("hand")
    spur = {k: cfg["gear_mesh"][0][k] for k in ("pinion", "wheel")}
    cfg["rotor"][1]["center"][0] = pair_from_mapping(spur).working_center_distance
    with pytest.raises(InputError, match=r"gear_mesh\[0\]\.contact_point"):
        Gearbox.from_mapping(cfg)


def test_too_many_slices_for_the_face_are_refused_naming_the_mesh_key():
    with pytest.raises(InputError, match=r"^gear_mesh\[0\]\.pinion\.face_width .*gear_mesh\[0\]\.face\.slices"):
        Gearbox.from_mapping(_config(face={"slices": 400, "misalignment": 1e-5}))


def test_cli_unknown_contact_point_exits_2_naming_the_key(tmp_path):
    from pathlib import Path

    from typer.testing import CliRunner

    from rotaflex.cli import app

    root = Path(__file__).resolve().parents[2]
    text = (root / "examples/system/helical_gearbox.toml").read_text()
    cfg = tmp_path / "bad.toml"
    cfg.write_text(text.replace('driver = "pinion"', 'driver = "pinion"\ncontact_point = "edge"'))
    r = CliRunner().invoke(app, ["system", "modal", str(cfg), "--out", str(tmp_path / "o"), "-q", "--no-figures"])
    assert r.exit_code == 2
    lines = [ln for ln in r.output.strip().splitlines() if ln]
    assert len(lines) == 1 and "gear_mesh[0].contact_point" in lines[0], r.output
