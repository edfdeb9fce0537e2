"""Outputs: stability tolerance, whirl by orbit (forward/backward/mixed), strict JSON, modal summary."""

import json
from pathlib import Path

import numpy as np
from typer.testing import CliRunner

from rotaflex.cli import app
from rotaflex.rotor.fe.modal import STABILITY_TOL, Modes, campbell, modal
from rotaflex.rotor.fe.model import Bearing, Disk, Rotor, Shaft

EXAMPLES = Path(__file__).resolve().parents[3] / "examples" / "rotor"


def _undamped():
    return Rotor(
        shaft=(Shaft(outer_diameter=0.05, length=1.5, elements=6),),
        disk=(Disk(node=2, mass=32.6, Id=0.178, Ip=0.329), Disk(node=4, mass=65.0, Id=0.5, Ip=0.9)),
        bearing=(Bearing(node=0, kxx=1e6, kyy=2e6), Bearing(node=6, kxx=1e6, kyy=2e6)),
    )


def test_undamped_rotor_is_not_unstable():
    """Conservative gyroscopic system: all eigenvalues on the imaginary axis; round-off is not instability."""
    r = _undamped()
    m = modal(r, 5000 * np.pi / 30)
    assert np.max(np.abs(m.damping_ratio)) < 1e-3 * STABILITY_TOL  # round-off is far below the tolerance
    assert not m.unstable.any()
    c = campbell(r, np.linspace(0, 6000, 25) * np.pi / 30, 8)
    assert c.unstable == []


def test_whirl_forward_backward_mixed_from_orbits():
    # node orbits: X + iY measures the forward radius, X - iY the backward one
    fwd = np.array([1.0, -1j, 0, 0])  # x = cos, y = sin: forward circle
    bwd = np.array([1.0, 1j, 0, 0])
    line = np.array([1.0, 0.0, 0, 0])
    tiny_bwd = 1e-3 * bwd  # below 1 % of the largest orbit: does not vote
    shapes = [
        np.concatenate([fwd, 0.5 * fwd]),
        np.concatenate([bwd, 0.3 * bwd]),
        np.concatenate([fwd, 0.5 * bwd]),
        np.concatenate([fwd, tiny_bwd]),
        np.concatenate([line, 0.5 * line]),
    ]
    m = Modes(np.zeros(1), np.ones((1, 5)) * 1j, np.array(shapes)[None])
    assert list(m.whirl[0]) == ["forward", "backward", "mixed", "forward", "forward"]


def test_modal_summary_has_every_quantity_with_units(tmp_path: Path):
    args = ["rotor", "modal", str(EXAMPLES / "fe_api684.toml"), "--out", str(tmp_path), "-q", "--no-figures"]
    res = CliRunner().invoke(app, args)
    assert res.exit_code == 0, res.output
    s = json.loads((tmp_path / "summary.json").read_text())
    for key, unit in (
        ("mode_0_frequency_hz", "Hz"),
        ("mode_0_damped_frequency_hz", "Hz"),
        ("mode_0_natural_frequency_rpm", "rpm"),
        ("mode_0_damping_ratio", "1"),
        ("mode_0_log_dec", "1"),
        ("speed", "rpm"),
    ):
        assert s[key]["unit"] == unit
    z, ld = s["mode_0_damping_ratio"]["value"], s["mode_0_log_dec"]["value"]
    assert np.isclose(ld, 2 * np.pi * z / np.sqrt(1 - z**2), rtol=1e-9)
    fn, fd = s["mode_0_frequency_hz"]["value"], s["mode_0_damped_frequency_hz"]["value"]
    assert np.isclose(fd, fn * np.sqrt(1 - z**2), rtol=1e-9)
    assert s["mode_0_whirl"]["value"] in ("forward", "backward", "mixed")


def test_summary_is_strict_json_and_n_modes_clamped(tmp_path: Path):
    text = (EXAMPLES / "fe_friswell_5_9_1.toml").read_text().replace("operating_speed_rpm = 3000\n", "")
    text = text.replace("[modal]\nspeed_rpm = 4000\nn_modes = 6", "[modal]\nspeed_rpm = 4000\nn_modes = 100")
    cfg = tmp_path / "c.toml"
    cfg.write_text(text)

    def strict(s):
        raise ValueError(f"not JSON: {s}")

    for verb in ("unbalance", "modal"):
        out = tmp_path / verb
        res = CliRunner().invoke(app, ["rotor", verb, str(cfg), "--out", str(out), "-q", "--no-figures"])
        assert res.exit_code == 0, res.output
        s = json.loads((out / "summary.json").read_text(), parse_constant=strict)
    assert "clamped to 28" in s["note"]["value"] and "mode_27_log_dec" in s


def test_stiff_short_shaft_is_not_taken_for_a_free_one():
    """E = 1e18 (a rigid shaft) on soft bearings: was refused as singular; now its bounce mode is sqrt(2k/m)."""
    k = 1e6
    r = Rotor(
        shaft=(Shaft(outer_diameter=0.1, length=0.3, elements=3, E=1e18, G=4e17),),
        bearing=(Bearing(node=0, kxx=k, kyy=k), Bearing(node=3, kxx=k, kyy=k)),
    )
    m, L = r.mass, 0.3
    w = modal(r, 0.0, 4).wn[0]
    Id = m * L**2 / 12 + m * 0.05**2 / 4  # solid cylinder about its centre
    tilt = np.sqrt(2 * k * (L / 2) ** 2 / Id)
    # penalty error ~1/E and round-off ~E: 2e-5 here (see the rigid = true test for the balanced choice)
    assert np.allclose(w[:2], np.sqrt(2 * k / m), rtol=1e-4)
    assert np.allclose(w[2:4], tilt, rtol=1e-4)


def test_rigid_section_gives_rigid_rotor_frequencies():
    """``rigid = true``: the rigid rotor on springs (translation sqrt(2k/m)) to 1e-7, where E = 1e18 gives 2e-5."""
    k = 1e6
    r = Rotor(
        shaft=(Shaft(outer_diameter=0.1, length=0.3, elements=3, rigid=True),),
        bearing=(Bearing(node=0, kxx=k, kyy=k), Bearing(node=3, kxx=k, kyy=k)),
    )
    w = modal(r, 0.0, 4).wn[0]
    assert np.allclose(w[:2], np.sqrt(2 * k / r.mass), rtol=1e-7)
    Id = r.mass * 0.3**2 / 12 + r.mass * 0.05**2 / 4
    assert np.allclose(w[2:4], np.sqrt(2 * k * 0.15**2 / Id), rtol=1e-6)
