"""Stability: the closed-form threshold of a rigid rotor with cross-coupled stiffness, API 617 Level I/II."""

import numpy as np
import pytest
from scipy.optimize import brentq

from rotaflex.rotor.fe import Bearing, Disk, Rotor, Shaft
from rotaflex.rotor.fe.modal import modal

# rigid rotor: 0.4 m x 0.1 m rigid shaft, a 60 kg disk at mid-span, two isotropic supports
K_SUP, C_SUP = 2.0e7, 4.0e3  # N/m, N s/m in total (half at each end)


def rigid_rotor(q: float) -> Rotor:
    """The rigid rotor with a cross-coupled stiffness q (kxy = q, kyx = -q) at the disk."""
    return Rotor(
        shaft=(Shaft(outer_diameter=0.1, length=0.4, elements=2, rigid=True),),
        disk=(Disk(node=1, mass=60.0, Id=0.6, Ip=1.0),),
        bearing=(
            Bearing(node=0, kxx=K_SUP / 2, kyy=K_SUP / 2, cxx=C_SUP / 2, cyy=C_SUP / 2),
            Bearing(node=2, kxx=K_SUP / 2, kyy=K_SUP / 2, cxx=C_SUP / 2, cyy=C_SUP / 2),
            Bearing(node=1, kxy=q, kyx=-q),
        ),
    )


def closed_form_forward(m: float, k: float, c: float, q: float) -> complex:
    """Forward-whirl root of m s^2 + c s + (k - i q) = 0 (z = x + i y, force f = i q z)."""
    roots = np.roots([m, c, k - 1j * q])
    return complex(roots[np.argmax(roots.imag)])


def fe_forward(q: float, m: float) -> complex:
    """The FE eigenvalue nearest the closed-form forward root (the translational mode)."""
    lam = modal(rigid_rotor(q), 0.0).eigenvalue[0]
    ref = closed_form_forward(m, K_SUP, C_SUP, q)
    return complex(lam[np.argmin(np.abs(lam - ref))])


def test_rigid_rotor_threshold_is_c_omega_n():
    """Unstable from q_0 = c omega_n; log dec below it as the closed form (Lund 1974; Childs 1993 ch. 3)."""
    m = rigid_rotor(0.0).mass
    wn = np.sqrt(K_SUP / m)
    for q in (0.0, 0.25, 0.5, 0.9, 1.2):
        qq = q * C_SUP * wn
        lam, ref = fe_forward(qq, m), closed_form_forward(m, K_SUP, C_SUP, qq)
        delta, delta_ref = -2 * np.pi * lam.real / lam.imag, -2 * np.pi * ref.real / ref.imag
        # the rigid section is a 1e8 penalty: frequencies within ~1e-7, log dec ~1e-6 absolute
        assert abs(lam - ref) < 1e-6 * abs(ref)
        assert delta == pytest.approx(delta_ref, abs=1e-5)
        assert (delta < 0) == (q > 1)
    q0 = brentq(lambda q: fe_forward(q, m).real, 0.5 * C_SUP * wn, 2 * C_SUP * wn, xtol=1e-6)
    assert q0 == pytest.approx(C_SUP * wn, rel=1e-6)


def test_level1_threshold_of_the_rigid_rotor_is_c_omega_n():
    """Level I's Q_0 (Brent on the first forward mode's log dec, Q at mid-span) is the closed form."""
    from rotaflex.rotor.fe.stability import StabilitySpec, Stage, level1

    rotor = rigid_rotor(0.0)
    wn = np.sqrt(K_SUP / rotor.mass)
    spec = StabilitySpec(speed_rpm=3000.0, stage=(Stage(power=2e5, diameter=0.3, width=0.02),), n_points=5)
    res = level1(rotor, spec)
    assert res.q0 == pytest.approx(C_SUP * wn, rel=1e-5)
    ref = closed_form_forward(rotor.mass, K_SUP, C_SUP, res.q_a)
    assert res.log_dec_a == pytest.approx(-2 * np.pi * ref.real / ref.imag, abs=1e-5)
    # Q_A = B T / (D H) (rho_d/rho_s) with T = P / Omega: 3 * 2e5 / (3000 pi/30) / (0.3 * 0.02)
    assert res.q_a == pytest.approx(3 * 2e5 / (3000 * np.pi / 30) / (0.3 * 0.02), rel=1e-12)


def test_anticipated_cross_coupling_si_equals_the_us_form():
    """q_A in SI (C = 9.55: W, m, rpm -> N/m) = the standard's US form (C = 63: hp, in, rpm -> klbf/in)."""
    from rotaflex.rotor.fe.stability import StabilitySpec, Stage, anticipated_cross_coupling

    hp, inch, klbf_in = 745.699872, 0.0254, 4448.2216152605 / 0.0254
    for machine, b, rho in (("centrifugal_compressor", 3.0, 1.4), ("turbine", 1.5, 1.0)):
        st = Stage(power=5e6, diameter=0.45, width=0.018, density_ratio=1.4)
        q = anticipated_cross_coupling(StabilitySpec(machine=machine, stage=(st,)), 9000.0)[0]
        us = b * (5e6 / hp) * 63.0 * rho / ((0.45 / inch) * (0.018 / inch) * 9000.0) * klbf_in
        assert q == pytest.approx(us, rel=2e-3)  # 63 is 63.025 rounded


RIGID_TOML = """
[[shaft]]
outer_diameter = 0.1
length = 0.4
elements = 2
rigid = true

[[disk]]
node = 1
mass = 60.0
Id = 0.6
Ip = 1.0

[bearing.left]
node = 0
kxx = 1e7
kyy = 1e7
cxx = 2e3
cyy = 2e3

[bearing.right]
node = 2
kxx = 1e7
kyy = 1e7
cxx = 2e3
cyy = 2e3
"""

STAGES = """
[stability]
speed_rpm = 3000
machine = "centrifugal_compressor"
mean_density = 10.0
n_points = 5

[[stability.stage]]
node = 1
power = 2e5
diameter = 0.3
width = 0.02
"""


def _cli(tmp_path, text):
    from typer.testing import CliRunner

    from rotaflex.cli import app

    f = tmp_path / "case.toml"
    f.write_text(text)
    return CliRunner().invoke(app, ["rotor", "stability", str(f), "--out", str(tmp_path / "out"), "-q"])


def test_stability_verb_writes_the_report(tmp_path):
    """`rotor stability` on the rigid rotor: Q_0 = c omega_n in summary.json, verdict.md and the figures."""
    import json

    res = _cli(tmp_path, RIGID_TOML + STAGES)
    assert res.exit_code == 0, res.output
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    m = rigid_rotor(0.0).mass
    assert s["Q_0"]["value"] == pytest.approx(C_SUP * np.sqrt(K_SUP / m), rel=1e-5)
    # no seals: Level II's full model is Level I's model at Q_A
    assert s["level2_log_dec"]["value"] == pytest.approx(s["log_dec_at_QA"]["value"], rel=1e-9)
    assert s["level1_verdict"]["value"] in ("Level II required", "Level II not required")
    out = tmp_path / "out"
    assert "Q_0 / Q_A" in (out / "verdict.md").read_text()
    assert {"level1.png", "level2.png", "csr_map.png", "result.nc"} <= {p.name for p in out.iterdir()}


@pytest.mark.parametrize(
    "cut, field",
    [("speed_rpm = 3000\n", "stability.speed_rpm"), ("[[stability.stage]]", "stability.stage")],
)
def test_level1_without_speed_or_power_is_refused(tmp_path, cut, field):
    """Level I without the MCS or without the stages (power): one line naming the key, exit 2."""
    text = STAGES.replace(cut, "") if cut.startswith("speed") else STAGES.split(cut)[0]
    res = _cli(tmp_path, RIGID_TOML + text)
    assert res.exit_code == 2
    assert field in res.output and len(res.output.strip().splitlines()) == 1


def test_stage_without_power_names_the_key(tmp_path):
    res = _cli(tmp_path, RIGID_TOML + STAGES.replace("power = 2e5\n", ""))
    assert res.exit_code == 2 and "stability.stage[0].power" in res.output


def test_level1_split_over_the_stages():
    """Q split over two stages at the bearings' nodes (equal q_A,i): the translational mode sees the same
    total cross-coupling, so Q_0 = c omega_n again (location = "stages")."""
    from rotaflex.rotor.fe.stability import StabilitySpec, Stage, level1

    rotor = rigid_rotor(0.0)
    st = [Stage(power=1e5, diameter=0.3, width=0.02, node=n) for n in (0, 2)]
    spec = StabilitySpec(speed_rpm=3000.0, stage=tuple(st), location="stages", n_points=3)
    assert level1(rotor, spec).q0 == pytest.approx(C_SUP * np.sqrt(K_SUP / rotor.mass), rel=1e-5)


SEALS = """
[bearing.lab]
node = 1

[bearing.lab.labyrinth]
teeth = 6
pitch = 4e-3
tooth_height = 4e-3
clearance = 0.2e-3
radius = 0.06
inlet_pressure = 5e5
outlet_pressure = 1e5
inlet_temperature = 300.0
preswirl = 0.5

[bearing.amb]
node = 2

[bearing.amb.magnetic]
k_i = 100.0
k_s = 1e5
sensor_gain = 1e4
p_gain = 0.5
d_gain = 1e-3
lowpass_hz = 2000.0
"""


@pytest.mark.parametrize("verb", ["modal", "campbell", "unbalance", "static", "frf"])
def test_seals_and_ambs_in_the_other_verbs(tmp_path, verb):
    """A labyrinth and an AMB beside linear bearings: every rotor verb runs (coefficients at the spin speed)."""
    from typer.testing import CliRunner

    from rotaflex.cli import app

    tables = {
        "campbell": "[campbell]\nspeed_rpm = [0, 6000]\nn_speeds = 4\nn_modes = 4\n",
        "unbalance": "[unbalance]\nspeed_rpm = [100, 6000]\nn_speeds = 20\n"
        "[[unbalance.mass]]\nnode = 1\nmagnitude = 1e-4\n",
        "frf": "[frf]\nspeed_rpm = 3000\nn_frequencies = 50\n",
    }
    f = tmp_path / "case.toml"
    f.write_text(RIGID_TOML + SEALS + tables.get(verb, ""))
    res = CliRunner().invoke(app, ["rotor", verb, str(f), "--out", str(tmp_path / "out"), "-q", "--no-figures"])
    assert res.exit_code == 0, res.output


@pytest.mark.parametrize("stem", ["compressor_tilting_pad_labyrinth", "amb_rotor", "pump_neck_ring_seals"])
def test_examples_run_the_stability_report(tmp_path, stem):
    """The two examples run as their headers say; the verdicts are consistent with their own numbers."""
    import json
    from pathlib import Path

    from typer.testing import CliRunner

    from rotaflex.cli import app

    example = Path(__file__).resolve().parents[3] / "examples" / "rotor" / f"{stem}.toml"
    res = CliRunner().invoke(app, ["rotor", "stability", str(example), "--out", str(tmp_path), "-q", "--no-figures"])
    assert res.exit_code == 0, res.output
    s = json.loads((tmp_path / "summary.json").read_text())
    if stem.startswith("pump"):  # no Q_A: Level II only, the seals damp the first forward mode
        assert "Q_A" not in s and s["level2_log_dec[all]"]["value"] > s["level2_log_dec[bearings]"]["value"]
    else:
        required = s["Q0_over_QA"]["value"] < 2 or s["log_dec_at_QA"]["value"] < 0.1
        assert required <= (s["level1_verdict"]["value"] == "Level II required")
    assert (s["level2_verdict"]["value"] == "pass") == (s["level2_log_dec"]["value"] >= 0.1)


def test_pump_takes_no_stages(tmp_path):
    res = _cli(tmp_path, RIGID_TOML + STAGES.replace("centrifugal_compressor", "pump"))
    assert res.exit_code == 2 and "stability.stage" in res.output


def test_anticipated_cross_coupling_against_ross():
    """ROSS's Report.stability_level_1 docstring example (petrobras/ross, ross/report.py): D = 0.35 m,
    H = 0.08 m, 10 kW per stage, density ratios 1.11 and 1.14, 1000 rpm -> Q_A = 23022.32142857143 N/m
    with C = 9.55; ours uses C = 60 / (2 pi) = 9.5493."""
    from rotaflex.rotor.fe.stability import C_SI, StabilitySpec, Stage, anticipated_cross_coupling

    st = tuple(Stage(power=1e4, diameter=0.35, width=0.08, density_ratio=r) for r in (1.11, 1.14))
    q = anticipated_cross_coupling(StabilitySpec(stage=st), 1000.0).sum()
    assert q == pytest.approx(23022.32142857143 * C_SI / 9.55, rel=1e-12)
