"""Trains of three rotors, pair files and the gear package's mesh sources."""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest

from rotaflex.system.modal import modal
from rotaflex.system.model import Gearbox


def _three(make, angle=0.0):
    """in (20 teeth) -> mid (40 | 20 teeth) -> out (40 teeth); the second mesh turns by 90 deg."""
    cfg = make(angle=angle)
    mid = copy.deepcopy(cfg["rotor"][1])
    mid["name"] = "mid"
    out = copy.deepcopy(cfg["rotor"][1])
    out["name"] = "out"
    a = 0.0901
    c = np.array(mid["center"])
    d = np.array([-math.sin(angle), math.cos(angle)])  # 90 deg from the first centre line
    out["center"] = list(c + a * d)
    cfg["rotor"] = [cfg["rotor"][0], mid, out]
    m1 = cfg["gear_mesh"][0]
    m1["wheel_rotor"] = "mid"
    m2 = copy.deepcopy(m1)
    m2.update(pinion_rotor="mid", pinion_node=2, wheel_rotor="out", wheel_node=3, torque=200.0)
    m1["torque"] = 100.0
    cfg["gear_mesh"] = [m1, m2]
    cfg["load"]["rotor"] = "out"
    return cfg


def test_three_rotor_train_speeds_senses_and_invariance(make):
    box = Gearbox.from_mapping(_three(make))
    assert box.speeds(100.0) == pytest.approx([100.0, -50.0, 25.0])
    assert box.mesh_frequency(0, 100.0) == pytest.approx(2000.0)
    assert box.mesh_frequency(1, 100.0) == pytest.approx(1000.0)  # 20 teeth at 50 rad/s
    w0 = modal(box, 300.0, 14).wd[0]
    w1 = modal(Gearbox.from_mapping(_three(make, angle=1.1)), 300.0, 14).wd[0]
    np.testing.assert_allclose(w1, w0, rtol=1e-9)
    # without meshes the train falls apart into its three rotors: the coupling raises frequencies
    w_free = modal(box.with_mesh_stiffness(0.0), 300.0, 14).wd[0]
    assert not np.allclose(w_free, w0, rtol=1e-3)


def test_pair_file_relative_to_the_case(make, tmp_path):
    from rotaflex.system.case import resolve_paths

    cfg = make()
    mesh = cfg["gear_mesh"][0]
    lines = [f"center_distance = {mesh.pop('center_distance')}"]
    for key in ("pinion", "wheel"):
        g = mesh.pop(key)
        lines += [f"[{key}]", f"teeth = {g['teeth']}", f"module = {g['module']}", f"face_width = {g['face_width']}"]
        lines += [f"blank = {{ kind = 'solid', bore_diameter = {g['blank']['bore_diameter']} }}"]
    (tmp_path / "pair.toml").write_text("\n".join(lines) + "\n")
    mesh["pair_file"] = "pair.toml"
    box = Gearbox.from_mapping(resolve_paths(cfg, tmp_path))
    ref = Gearbox.from_mapping(make())
    np.testing.assert_allclose(modal(box, 0.0, 6).wd[0], modal(ref, 0.0, 6).wd[0], rtol=1e-12)


@pytest.mark.parametrize("source", ["iso6336", "contact_pattern"])
def test_gear_package_sources(make, source):
    cfg = make()
    m = cfg["gear_mesh"][0]
    m["source"] = source
    m.pop("k_mean")
    if source == "contact_pattern":
        m.update(k_pair=2.5e8, unloaded_te_pp=4e-6)
    box = Gearbox.from_mapping(cfg)
    mesh = box.meshes[0]
    assert 5e7 < mesh.k_mean < 5e9
    assert mesh.gear.torque == pytest.approx(50.0)  # 100 N m load on the 40-tooth wheel, 20-tooth pinion
    if source == "contact_pattern":
        # mean of single/double contact: k_pair (1 + (eps - 1)) = k_pair eps
        assert mesh.k_mean == pytest.approx(2.5e8 * mesh.gear.contact_ratio, rel=5e-3)  # 1/256 cycle steps
