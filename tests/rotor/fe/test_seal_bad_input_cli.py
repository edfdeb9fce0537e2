"""Bad seal, magnetic-bearing and Level I input through the CLI (issue: one line naming the key as
written in the TOML, exit 2) for `rotor stability` and `rotor modal`."""

import pytest

RIGID = """
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

STABILITY = """
[stability]
speed_rpm = 3000
machine = "centrifugal_compressor"
n_points = 5

[[stability.stage]]
node = 1
power = 2e5
diameter = 0.3
width = 0.02
"""

LABYRINTH = """
[bearing.eye]
node = 1

[bearing.eye.labyrinth]
teeth = 6
pitch = 4e-3
tooth_height = 4e-3
clearance = 0.2e-3
radius = 0.06
inlet_pressure = 5e5
outlet_pressure = 1e5
inlet_temperature = 300.0
"""

RING = """
[bearing.ring]
node = 1

[bearing.ring.liquid_seal]
radius = 0.05
length = 0.04
clearance = 0.25e-3
inlet_pressure = 2.1e6
outlet_pressure = 1e5
density = 1000.0
viscosity = 1e-3
"""

AMB = """
[bearing.amb]
node = 1

[bearing.amb.magnetic]
k_i = 100.0
k_s = 1e5
sensor_gain = 1e4
p_gain = 0.5
d_gain = 1e-3
"""


def _run(tmp_path, verb, text):
    from typer.testing import CliRunner

    from rotaflex.cli import app

    f = tmp_path / "case.toml"
    f.write_text(text)
    return CliRunner().invoke(app, ["rotor", verb, str(f), "--out", str(tmp_path / "out"), "-q", "--no-figures"])


CASES = {
    "liquid clearance 0": (RING, "clearance = 0.25e-3", "clearance = 0.0", "bearing.ring.liquid_seal.clearance"),
    "liquid clearance < 0": (RING, "clearance = 0.25e-3", "clearance = -1e-4", "bearing.ring.liquid_seal.clearance"),
    "liquid outlet = inlet": (
        RING,
        "outlet_pressure = 1e5",
        "outlet_pressure = 2.1e6",
        "bearing.ring.liquid_seal.outlet_pressure",
    ),
    "labyrinth clearance 0": (LABYRINTH, "clearance = 0.2e-3", "clearance = 0", "bearing.eye.labyrinth.clearance"),
    "labyrinth outlet > inlet": (
        LABYRINTH,
        "outlet_pressure = 1e5",
        "outlet_pressure = 6e5",
        "bearing.eye.labyrinth.outlet_pressure",
    ),
    "labyrinth one tooth": (LABYRINTH, "teeth = 6", "teeth = 1", "bearing.eye.labyrinth.teeth"),
    "AMB negative static stiffness": (AMB, "p_gain = 0.5", "p_gain = 0.05", "bearing.amb.magnetic.p_gain"),
    "AMB loop unstable with its filter": (
        AMB,
        "d_gain = 1e-3",
        "mass = 30.0\nlowpass_hz = 200.0",
        "bearing.amb.magnetic.d_gain",
    ),
}


@pytest.mark.parametrize("verb", ["stability", "modal"])
@pytest.mark.parametrize("case", list(CASES))
def test_bad_element_input_is_one_line_exit_2(tmp_path, case, verb):
    table, good, bad, key = CASES[case]
    assert good in table
    text = RIGID + table.replace(good, bad) + (STABILITY if verb == "stability" else "")
    res = _run(tmp_path, verb, text)
    assert res.exit_code == 2, res.output
    lines = res.output.strip().splitlines()
    assert len(lines) == 1 and key in lines[0], res.output


@pytest.mark.parametrize(
    "cut, key",
    [
        ("speed_rpm = 3000\n", "stability.speed_rpm"),
        ("power = 2e5\n", "stability.stage[0].power"),
    ],
)
def test_level1_without_speed_or_power(tmp_path, cut, key):
    res = _run(tmp_path, "stability", RIGID + STABILITY.replace(cut, ""))
    assert res.exit_code == 2, res.output
    lines = res.output.strip().splitlines()
    assert len(lines) == 1 and key in lines[0], res.output


def test_the_good_cases_run(tmp_path):
    """The same tables unchanged run (exit 0): the refusals above come from the changed key."""
    res = _run(tmp_path, "stability", RIGID + LABYRINTH + RING + AMB + STABILITY)
    assert res.exit_code == 0, res.output
