"""Impossible values and broken files refused at the config boundary, as one line naming the field."""

import numpy as np
import pytest

from rotaflex.cli import main
from rotaflex.core.errors import InputError
from rotaflex.floating.modes_file import load_modes
from rotaflex.rotor.case import model_from_config


# -- rigid-body inertias: I_a + I_b >= I_c for every ordering (a lamina is the equality) -----------
@pytest.mark.parametrize(
    "disk, field",
    [
        ({"polar_inertia": 2.5, "diametral_inertia": 1.0}, "disk.polar_inertia"),
        ({"polar_inertia": 0.0201, "diametral_inertia": 0.01}, "disk.polar_inertia"),
        ({"inertia": [1.0, 1.0, 2.5]}, "disk.inertia"),
        ({"inertia": [5.0, 1.0, 2.0]}, "disk.inertia"),  # the largest need not come last
    ],
)
def test_disk_inertias_that_no_rigid_body_has_are_refused(disk, field):
    with pytest.raises(InputError) as info:
        model_from_config({"disk": {"mass": 1.0, **disk}})
    assert info.value.field == field and "\n" not in str(info.value)


@pytest.mark.parametrize(
    "disk",
    [
        {"polar_inertia": 0.02, "diametral_inertia": 0.01},  # thin disk: I_p = 2 I_d exactly, in decimals
        {"polar_inertia": 0.1 + 0.2, "diametral_inertia": 0.15},  # above 2 * 0.15 by round-off only
        {"polar_inertia": 0.5, "diametral_inertia": 1.0},  # a long cylinder
        {"inertia": [1.0, 2.0, 3.0]},  # a lamina in the x-y plane
    ],
)
def test_rigid_body_inertias_including_the_lamina_limit_are_accepted(disk):
    model_from_config({"disk": {"mass": 1.0, **disk}})


def test_free_body_inertias_are_checked_too():
    with pytest.raises(InputError) as info:
        model_from_config({"free_body": {"inertia": [1.0, 1.0, 2.5]}})
    assert info.value.field == "free_body.inertia"
    model_from_config({"free_body": {"inertia": [1.0, 1.0, 2.0]}})


def test_cli_names_the_inertia_in_one_line(tmp_path, capsys):
    cfg = tmp_path / "c.toml"
    cfg.write_text("[disk]\nmass = 1.0\npolar_inertia = 3.0\ndiametral_inertia = 1.0\n")
    with pytest.raises(SystemExit) as info:
        main(["rotor", "simulate", str(cfg), "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err.strip().splitlines()
    assert info.value.code == 2 and len(err) == 1 and err[0].startswith("error: disk.polar_inertia = 3.0")


# -- broken modes files -------------------------------------------------------------------------
@pytest.fixture
def modes_npz(tmp_path):
    n = 4
    path = tmp_path / "good.npz"
    np.savez(path, masses=np.ones(n), points=np.zeros((n, 3)), shapes=np.ones((n, 3, 2)))
    return path


@pytest.mark.parametrize("keep", [0.0, 0.02, 0.3, 0.6, 0.97])
def test_truncated_or_empty_npz_is_one_line(tmp_path, modes_npz, keep):
    data = modes_npz.read_bytes()
    bad = tmp_path / "bad.npz"
    bad.write_bytes(data[: int(keep * len(data))])
    with pytest.raises(InputError) as info:
        load_modes(bad)
    assert info.value.field == "body.file.path" and "\n" not in str(info.value)
    assert ("empty" if keep == 0 else "truncated") in str(info.value)


def test_a_bare_npy_under_an_npz_name_is_one_line(tmp_path):
    bad = tmp_path / "bad.npz"
    with open(bad, "wb") as f:
        np.save(f, np.ones(3))
    with pytest.raises(InputError, match="not an archive of named arrays"):
        load_modes(bad)


def test_cli_with_a_truncated_modes_file(tmp_path, modes_npz, capsys):
    (tmp_path / "m.npz").write_bytes(modes_npz.read_bytes()[:100])
    cfg = tmp_path / "c.toml"
    cfg.write_text('domain = "floating"\n[body]\ntype = "file"\n[body.file]\npath = "m.npz"\n')
    with pytest.raises(SystemExit) as info:
        main(["floating", "simulate", str(cfg), "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err.strip().splitlines()
    assert info.value.code == 2 and len(err) == 1 and err[0].startswith("error: body.file.path = "), err
