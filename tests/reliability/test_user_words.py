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
