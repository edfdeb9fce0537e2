"""Issue 32, part 3: no silent nonsense, no late refusal.

An input that makes the answer meaningless is refused up front with a bound that is argued
physically (exit 2, the key as written), and an answer that fails its own checks is reported as
``failed_check`` (exit 1, one line on stderr). The bounds are checked against closed forms.
"""

import math

import numpy as np
import pytest
from _cli import edited, verb_on

from rotaflex.rotor.fe.bounds import max_frequency_hz, max_speed
from rotaflex.rotor.fe.case_config import parse

GEARBOX = "system/gearbox.toml"
FRISWELL = "rotor/fe_friswell_5_9_1.toml"


def _set(path, value):
    def edit(d):
        node = d
        for k in path[:-1]:
            node = node.setdefault(k, {}) if isinstance(k, str) else node[k]
        node[path[-1]] = value

    return edit


REFUSED = [
    ("system modal", GEARBOX, ("modal", "speed_rpm"), 1e300, "modal.speed_rpm = 1e+300"),
    ("system campbell", GEARBOX, ("campbell", "speed_rpm"), [0.0, 1e20], "campbell.speed_rpm = [0.0, 1e+20]"),
    ("system campbell", GEARBOX, ("campbell", "speed_rpm"), [0.0, 1e300], "campbell.speed_rpm[1] = 1e+300"),
    ("system steady", GEARBOX, ("gear_mesh", 0, "unloaded_te_pp"), 1.0, "gear_mesh[0].unloaded_te_pp = 1.0"),
    ("rotor modal", FRISWELL, ("modal", "speed_rpm"), 1e300, "modal.speed_rpm = 1e+300"),
    ("rotor frf", FRISWELL, ("frf", "frequency_hz"), [1.0, 1e20], "frf.frequency_hz = [1.0, 1e+20]"),
    ("rotor frf", FRISWELL, ("frf", "frequency_hz"), [1.0, 1e300], "frf.frequency_hz[1] = 1e+300"),
    ("rotor static", FRISWELL, ("static", "load"), [{"node": 2, "fy": -1e300}], "static.load[0].fy = -1e+300"),
    ("rotor modal", FRISWELL, ("modal", "speed_rpm"), 1e20, "modal.speed_rpm = 1e+20"),
]


@pytest.mark.parametrize(("verb", "rel", "path", "value", "start"), REFUSED, ids=[r[4] for r in REFUSED])
def test_refused_up_front(capsys, tmp_path, verb, rel, path, value, start):
    code, line = verb_on(capsys, tmp_path, verb, edited(rel, _set(path, value)))
    assert code == 2 and line.startswith("error: " + start), line


def test_speed_bound_is_the_rim_at_the_bar_wave_speed():
    """Friswell 5.9.1: steel shaft, largest radius that of the 350 mm disk (a disk given by mass
    and Ip counts as the solid disk r = sqrt(2 Ip / m)); the bound is sqrt(E / rho) / r."""
    rotor, _ = parse(edited(FRISWELL, lambda d: None), "modal")
    e = rotor.elements
    c = math.sqrt(e["E"][0] / e["rho"][0])
    radii = [rotor.elements["do_l"].max() / 2]
    for d in rotor.disk:
        radii.append(d.outer_diameter / 2 if d.outer_diameter else math.sqrt(2 * d.Ip / d.mass))
    assert max_speed(rotor) == pytest.approx(c / max(radii), rel=1e-12)
    assert 4000 < c < 6000  # steel's bar wave speed, ~5,100 m/s
    assert max_frequency_hz(rotor) == pytest.approx(c / e["L"].min(), rel=1e-12)


def test_static_load_beyond_linear_theory_is_failed_check(capsys, tmp_path):
    """1e25 N on a node (1e300 N is refused up front as no machine's force): the answer's slopes
    are far beyond small-rotation theory -> exit 1, one line, the result kept."""
    code, line = verb_on(
        capsys, tmp_path, "rotor static", edited(FRISWELL, _set(("static", "load"), [{"node": 2, "fy": -1e25}]))
    )
    assert code == 1 and line.startswith("error: failed_check: check 'small slopes' failed"), line
    assert (tmp_path / "o" / "result.nc").exists()


def test_ill_conditioned_solve_is_failed_check_without_warnings(capsys, tmp_path):
    """A disk of 1e30 kg: the mass matrix is singular to machine precision. scipy's warning is not
    printed; the result is failed_check (exit 1) naming it."""

    def heavy(d):
        d["disk"][0].update(mass=1e30, Id=1e30, Ip=1e30)

    code, line = verb_on(capsys, tmp_path, "rotor modal", edited(FRISWELL, heavy))
    assert code == 1 and "check 'numerics' failed: LinAlgWarning" in line, line


FILM = "rotor/fe_fluid_film.toml"
PADS = "rotor/fe_fluid_film_tilting_pad.toml"


def _film(key, value, names=("left",)):
    def edit(d):
        for name in names:
            d["bearing"][name]["fluid_film"][key] = value

    return edit


FILM_REFUSED = [
    (FILM, _film("viscosity", 1e12), "bearing.left.fluid_film.viscosity = 1000000000000.0"),
    (FILM, _film("load", [0.0, -1e-300]), "bearing.left.fluid_film.load = [0.0, -1e-300]"),
    (FILM, _film("n_speeds", 1_000_000), "bearing.left.fluid_film.n_speeds = 1000000"),
    (FILM, _film("n_theta", 10_000_000), "bearing.left.fluid_film.n_theta = 10000000"),
    (FILM, _film("n_z", 1_000_000), "bearing.left.fluid_film.n_z = 1000000"),
]


@pytest.mark.parametrize(("rel", "edit", "start"), FILM_REFUSED, ids=[r[2].split(" =")[0] for r in FILM_REFUSED])
def test_fluid_film_refused_before_computing(capsys, tmp_path, rel, edit, start):
    """Was an internal RuntimeError (1e12 Pa s, 1e-300 N) or ran until killed (1e6 speeds, 1e7
    grid nodes); now refused in well under a second, before any film is solved."""
    import time

    t0 = time.perf_counter()
    code, line = verb_on(capsys, tmp_path, "rotor static", edited(rel, edit))
    assert code == 2 and line.startswith("error: " + start), line
    assert time.perf_counter() - t0 < 10


def test_tilting_pad_preload_refused_on_the_preload(capsys, tmp_path):
    """Preload 0.999 of an 80 um pad clearance leaves 80 nm: below the roughness of the surfaces.
    Was internal ValueError; now the preload is named (exit 2)."""
    code, line = verb_on(capsys, tmp_path, "rotor static", edited(PADS, _film("preload", 0.999, ("left", "right"))))
    assert code == 2 and line.startswith("error: bearing.left.fluid_film.preload = 0.999 "), line


def test_tilting_pad_high_preload_runs(capsys, tmp_path):
    """Preload 0.9 (8 um assembled clearance) is physical: it runs (was internal ValueError: the
    equilibrium search started outside the preloaded pads)."""
    from _cli import dump, run

    path = tmp_path / "case.toml"
    path.write_text(dump(edited(PADS, _film("preload", 0.9, ("left", "right")))))
    code, out, err = run(capsys, "rotor", "static", path, "--out", tmp_path / "o", "-q", "--no-figures")
    assert code == 0 and err == "", err


def test_fluid_film_tables_of_different_lengths_are_padded(capsys, tmp_path):
    """docs: a shorter table is padded with NaN (was internal AlignmentError)."""
    import xarray as xr
    from _cli import dump, run

    path = tmp_path / "case.toml"
    path.write_text(dump(edited(FILM, _film("n_speeds", 20, ("right",)))))
    code, _, err = run(capsys, "rotor", "static", path, "--out", tmp_path / "o", "-q")
    assert code == 0 and err == "", err
    with xr.open_dataset(tmp_path / "o" / "result.nc") as ds:
        rpm = ds["ff_speed_rpm"].sel(fluid_film="right").values
        assert ds.sizes["ff_speed"] == 50
        assert np.all(np.isfinite(rpm[:20])) and np.all(np.isnan(rpm[20:]))
        assert rpm[0] == pytest.approx(500) and rpm[19] == pytest.approx(12000)  # the table's own range
        assert np.all(np.isfinite(ds["ff_speed_rpm"].sel(fluid_film="left").values))
