"""Issue 32, part 2: every refusal names the key as the user wrote it (full path, the user's
table names), the value as typed, and no key the user did not write.

Each case edits an example as a user would and runs the verb through the command line: exit
status 2, exactly one line on stderr, and that line starts with the key path of the file.
"""

import numpy as np
import pytest
from _cli import edited, verb_on

from rotaflex.core.errors import InputError


def _pair_file(d):
    d["gear_mesh"][0]["pair_file"] = "no_such_pair.toml"


def _elements(d):
    d["rotor"][0]["shaft"][0]["elements"] = 100_000_000


def _film_load(d):
    d["bearing"]["left"]["fluid_film"]["load"] = "heavy"


def _harmonic(d):
    d["gear_mesh"][0]["source"] = "harmonic"


def _frf_node(d):
    d["frf"]["pair"] = [{"input_node": 99, "input_direction": "x"}]


CASES = [
    # (verb, example, edit, the line starts with)
    ("system modal", "system/gearbox.toml", _pair_file, "error: gear_mesh[0].pair_file = "),
    ("system modal", "system/gearbox.toml", _elements, "error: rotor[0].shaft[0].elements = 100000000 "),
    ("rotor static", "rotor/fe_fluid_film.toml", _film_load, "error: bearing.left.fluid_film.load = 'heavy' "),
    ("system steady", "system/gearbox.toml", _harmonic, "error: gear_mesh[0].k_mean = '<missing>' "),
    ("rotor frf", "rotor/fe_fluid_film.toml", _frf_node, "error: frf.pair[0].input_node = 99 "),
]


@pytest.mark.parametrize(("verb", "rel", "edit", "start"), CASES, ids=[c[3].split()[1] for c in CASES])
def test_key_as_written(capsys, tmp_path, verb, rel, edit, start):
    code, line = verb_on(capsys, tmp_path, verb, edited(rel, edit))
    assert code == 2
    assert line.startswith(start), line


def test_max_dof_advice_names_the_rotor_table(capsys, tmp_path):
    """The advice to raise max_dof names the key where a system file accepts it (rotor[0].max_dof,
    not a top-level max_dof, which a system file refuses) and that key is then accepted."""
    code, line = verb_on(capsys, tmp_path, "system modal", edited("system/gearbox.toml", _elements))
    assert code == 2 and "raise rotor[0].max_dof " in line

    def top_level(d):
        d["max_dof"] = 10**9

    code, line = verb_on(capsys, tmp_path, "system modal", edited("system/gearbox.toml", top_level))
    assert code == 2 and line.startswith("error: max_dof = ")  # refused: the advice must not say this

    def in_rotor(d):
        d["rotor"][0]["max_dof"] = 4  # accepted as a key, too small for the mesh: refused on the elements

    code, line = verb_on(capsys, tmp_path, "system modal", edited("system/gearbox.toml", in_rotor))
    assert code == 2 and line.startswith("error: rotor[0].shaft[0].elements = 10 "), line


def test_automatic_default_is_not_named_for_a_huge_damping_ratio(capsys, tmp_path):
    """A damping ratio of 1e300 is refused on its own key, not as an automatic step count."""

    def damping(d):
        d["gear_mesh"][0]["damping_ratio"] = 1e300

    code, line = verb_on(capsys, tmp_path, "system steady", edited("system/gearbox.toml", damping))
    assert code == 2 and line.startswith("error: gear_mesh[0].damping_ratio = 1e+300 "), line
    assert "steps_per_cycle" not in line and "automatic" not in line


def test_numpy_values_shown_as_typed():
    """np.float64(0.0) is shown as 0.0: a message shows the number, not numpy's repr."""
    assert str(InputError("a.b", np.float64(0.0), "x")) == "a.b = 0.0 is invalid: expected x"
    assert str(InputError("a.b", [np.int64(3), np.float64(0.5)], "x")) == "a.b = [3, 0.5] is invalid: expected x"
    assert str(InputError("a.b", np.array([1.0, 2.0]), "x")) == "a.b = [1.0, 2.0] is invalid: expected x"


def test_relocated_keeps_paths_of_the_whole_file():
    """Relative keys (a table's own checks) gain the table's path; named tables replace indices."""
    e = InputError("shaft[0].elements", 5, "raise max_dof", ("max_dof",)).relocated("rotor[1]")
    assert e.field == "rotor[1].shaft[0].elements" and "raise rotor[1].max_dof" in str(e)
    e = InputError("bearing[0].fluid_film.viscosity", 0.0, "x").relocated("", {"bearing[0]": "bearing.left"})
    assert e.field == "bearing.left.fluid_film.viscosity"
    assert InputError("rotor[1].x", 1, "y").relocated("rotor[1]").field == "rotor[1].x"  # already absolute


def test_default_tool_round_adapts_to_a_25_degree_rack():
    """Pressure angle 25 deg (allowed) was refused as ``pinion.rack_tip_radius_coef = 0.38``, a
    key the user never wrote. The default now becomes the full round of the rack tip, which
    for the ISO 53 rack (dedendum 1.25 m) is rho/m = (pi/4 - 1.25 tan a) cos a / (1 - sin a)."""
    import math

    from rotaflex.gear.pair.drawing import pair_from_mapping

    gear = {"module": 2e-3, "face_width": 0.02, "pressure_angle_deg": 25.0}
    pair = pair_from_mapping({"pinion": {**gear, "teeth": 20}, "wheel": {**gear, "teeth": 40}})
    a = math.radians(25.0)
    full = (math.pi / 4 - 1.25 * math.tan(a)) * math.cos(a) / (1 - math.sin(a))
    for g in pair.gears:
        assert g.rack_tip_radius_coef == pytest.approx(full, rel=1e-9)
    with pytest.raises(InputError) as err:  # written by the user: still refused, on that key
        pair_from_mapping(
            {"pinion": {**gear, "teeth": 20, "rack_tip_radius_coef": 0.38}, "wheel": {**gear, "teeth": 40}}
        )
    assert err.value.field == "pinion.rack_tip_radius_coef"
    gear20 = {**gear, "pressure_angle_deg": 20.0}  # 20 deg: the ISO 53 value, unchanged
    pair = pair_from_mapping({"pinion": {**gear20, "teeth": 20}, "wheel": {**gear20, "teeth": 40}})
    assert pair.gears[0].rack_tip_radius_coef == 0.38


def test_centre_distance_below_base_circles_names_it(capsys, tmp_path):
    """Was internal ValueError: math domain error (acos of more than 1)."""

    def close(d):
        d["gear_mesh"][0]["center_distance"] = 0.05
        d["rotor"][1]["center"] = [0.05, 0.0]

    code, line = verb_on(capsys, tmp_path, "system modal", edited("system/gearbox.toml", close))
    assert code == 2 and line.startswith("error: gear_mesh[0].center_distance = 0.05 is invalid: expected >= 0.09 m")


@pytest.mark.parametrize(
    ("path", "value", "start"),
    [
        (("slew", "duration"), 1e-300, "slew.duration = 1e-300"),
        (("body", "hub", "appendages", 0, "thickness"), 1e300, "body.hub.appendages[0].thickness = 1e+300"),
        (("body", "hub", "mass"), float("nan"), "body.hub.mass = nan"),
    ],
)
def test_floating_extremes_refused(capsys, tmp_path, path, value, start):
    """Were ZeroDivisionError / OverflowError: a quantity with a unit must lie within 1e-30..1e30 SI."""

    def edit(d):
        node = d
        for k in path[:-1]:
            node = node[k]
        node[path[-1]] = value

    code, line = verb_on(capsys, tmp_path, "floating simulate", edited("floating/hub_appendage_slew.toml", edit))
    assert code == 2 and line.startswith("error: " + start), line


def test_failed_run_is_one_line_on_stderr(capsys, tmp_path):
    """A run that fails (a slew of 1e-29 s: the integrator stops) prints one line on stderr
    (the library's log line is not printed beside it), exit 1, the result kept."""

    def edit(d):
        d["slew"]["duration"] = 1e-29

    code, line = verb_on(capsys, tmp_path, "floating simulate", edited("floating/hub_appendage_slew.toml", edit))
    assert code == 1 and line.startswith("error: failed: "), line
    assert (tmp_path / "o" / "result.nc").exists()


def test_continuation_refusal_names_the_option_not_an_internal_target(capsys, tmp_path):
    """Was ``--continuation = 'rotaflex.system.case:run_case'``: now the key as typed and the fix."""
    from _cli import dump, run

    def no_verb(d):
        d["domain"] = "system"

    path = tmp_path / "g.toml"
    path.write_text(dump(edited("system/gearbox.toml", no_verb)))
    args = ["sweep", path, "--out", tmp_path / "o", "--vary", "steady.speed_rpm=2000:3000:3"]
    code, _, err = run(capsys, *args, "--continuation", "steady.speed_rpm", "-q")
    assert code == 2 and len(err.strip().splitlines()) == 1, err
    assert err.startswith("error: --continuation = 'steady.speed_rpm' is invalid"), err
    assert 'add verb = "steady"' in err and "rotaflex." not in err
