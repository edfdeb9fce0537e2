"""Issue 32, part 3: no silent nonsense, no late refusal.

An input that makes the answer meaningless is refused up front with a bound that is argued
physically (exit 2, the key as written), and an answer that fails its own checks is reported as
``failed_check`` (exit 1, one line on stderr). The bounds are checked against closed forms.
"""

import math

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
    ("system campbell", GEARBOX, ("campbell", "speed_rpm"), [0.0, 1e300], "campbell.speed_rpm = [0.0, 1e+300]"),
    ("system steady", GEARBOX, ("gear_mesh", 0, "unloaded_te_pp"), 1.0, "gear_mesh[0].unloaded_te_pp = 1.0"),
    ("rotor modal", FRISWELL, ("modal", "speed_rpm"), 1e300, "modal.speed_rpm = 1e+300"),
    ("rotor frf", FRISWELL, ("frf", "frequency_hz"), [1.0, 1e300], "frf.frequency_hz = [1.0, 1e+300]"),
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
    """1e300 N on a node: the answer's slopes are far beyond small-rotation theory -> exit 1."""
    code, line = verb_on(
        capsys, tmp_path, "rotor static", edited(FRISWELL, _set(("static", "load"), [{"node": 2, "fy": -1e300}]))
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
