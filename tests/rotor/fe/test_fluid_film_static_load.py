"""Fluid-film bearings loaded by the rotor's static analysis (``load = "static"``)."""

from __future__ import annotations

import numpy as np
import pytest

from rotaflex.core.errors import InputError
from rotaflex.rotor.fe import Bearing, Disk, Rotor, Shaft
from rotaflex.rotor.fe.bearings import FluidFilm, coefficients_from_reaction
from rotaflex.rotor.fe.bearings.static_load import reference_speed, resolve_static_loads
from rotaflex.rotor.fe.case import parse
from rotaflex.rotor.fe.static import static_analysis

G = 9.80665
RHO = 7810.0  # steel of rotaflex.rotor.fe.materials (Friswell et al. 2010)
D, LENGTH = 0.06, 1.2
DISKS = ((0.3, 0.3, 0.05), (0.9, 0.35, 0.05))  # (position [m], outer diameter [m], width [m]), bore D


def film(load="static", model="short"):
    return FluidFilm(
        diameter=D, length=0.03, clearance=60e-6, viscosity=0.02, load=load, speed_rpm=(1000.0, 6000.0), n_speeds=6,
        model=model, n_theta=36, n_z=6,
    )  # fmt: skip


def rotor(supports, loads=None, model="short"):
    """20-element rotor on fluid-film bearings at ``supports`` [m] (loads: explicit, else "static")."""
    bearings = tuple(
        Bearing(position=z, fluid_film=film("static" if loads is None else loads[i], model))
        for i, z in enumerate(supports)
    )
    disks = tuple(Disk(position=z, outer_diameter=do, inner_diameter=D, width=w) for z, do, w in DISKS)
    return Rotor(shaft=(Shaft(outer_diameter=D, length=LENGTH, elements=20),), disk=disks, bearing=bearings)


def weights():
    """(position [m], weight [N]) of the shaft (at its middle) and of each disk, from the geometry."""
    out = [(LENGTH / 2, RHO * np.pi / 4 * D**2 * LENGTH * G)]
    out += [(z, RHO * np.pi / 4 * (do**2 - D**2) * w * G) for z, do, w in DISKS]
    return out


def lever_rule(za, zb, extra=()):
    """Upward reactions [N] of supports at za < zb under the weights (and extra downward point forces)."""
    items = weights() + list(extra)
    rb = sum(w * (z - za) for z, w in items) / (zb - za)
    return sum(w for _, w in items) - rb, rb


@pytest.mark.parametrize("supports", [(0.0, 1.2), (0.12, 1.08)])
def test_two_bearings_lever_rule_in_one_pass(supports):
    r = rotor(supports)
    res = resolve_static_loads(r)
    ra, rb = lever_rule(*supports)
    # the journal loads on the bearings act downwards: -reaction
    np.testing.assert_allclose(res.loads[:, 1], [-ra, -rb], rtol=1e-10)
    np.testing.assert_allclose(res.loads[:, 0], 0.0, atol=1e-10 * (ra + rb))
    assert res.iterations == 2  # the first static analysis is exact; the second confirms it
    # the coefficients equal those of the bearing given the lever-rule load explicitly
    explicit = rotor(supports, loads=[(0.0, -ra), (0.0, -rb)])
    for (_, _, a), (_, _, b) in zip(r.bearings, explicit.bearings, strict=True):
        np.testing.assert_allclose(a.k, b.k, rtol=1e-8)
        np.testing.assert_allclose(a.c, b.c, rtol=1e-8)


def test_finite_model_two_bearings_matches_explicit_load():
    r = rotor((0.0, 1.2), model="finite")
    ra, rb = lever_rule(0.0, 1.2)
    explicit = rotor((0.0, 1.2), loads=[(0.0, -ra), (0.0, -rb)], model="finite")
    for (_, _, a), (_, _, b) in zip(r.bearings, explicit.bearings, strict=True):
        np.testing.assert_allclose(a.k, b.k, rtol=1e-8)
        np.testing.assert_allclose(a.c, b.c, rtol=1e-8)
    # and those are the bearing's own table for the lever-rule reaction (the left bearing)
    table = coefficients_from_reaction(film(model="finite"), (0.0, ra))
    np.testing.assert_allclose(r.bearings[0][2].k, table.k, rtol=1e-8)


def test_three_bearings_converge_to_equilibrium():
    r = rotor((0.0, 0.6, 1.2))
    res = resolve_static_loads(r)
    weight = sum(w for _, w in weights())
    assert res.iterations > 2  # statically indeterminate: the loads depend on the film stiffness
    assert abs(res.loads[:, 1].sum() + weight) < 1e-9 * weight
    assert abs(res.loads[:, 0].sum()) < 1e-9 * weight
    # a fixed point: the static analysis of the resolved rotor gives back the loads it was given
    s = static_analysis(res.rotor, speed=res.speed)
    np.testing.assert_allclose(-s.reactions, res.loads, atol=1e-8 * weight)
    # and they differ from the lever rule of the outer pair and from an equal share
    assert np.all(np.abs(res.loads[:, 1]) > 0.05 * weight)
    assert res.speed == reference_speed(r) == 1000.0 * np.pi / 30


def test_iteration_that_does_not_converge_names_the_bearing():
    with pytest.raises(InputError, match=r"bearing\[\d\]\.fluid_film\.load.*did not converge in 2 passes"):
        resolve_static_loads(rotor((0.0, 0.6, 1.2)), max_iter=2)


def test_static_point_load_from_config_moves_the_loads():
    cfg = {
        "shaft": [{"outer_diameter": D, "length": LENGTH, "elements": 20}],
        "disk": [{"position": z, "outer_diameter": do, "inner_diameter": D, "width": w} for z, do, w in DISKS],
        "bearing": {
            "a": {"node": 0, "fluid_film": {**_film_keys(), "load": "static"}},
            "b": {"node": 20, "fluid_film": {**_film_keys(), "load": "static"}},
        },
        "static": {"load": [{"position": 0.6, "fy": -500.0}]},
        "modal": {"speed_rpm": 3000.0},
    }
    r, _ = parse(cfg, "modal")
    ra, rb = lever_rule(0.0, 1.2, extra=[(0.6, 500.0)])
    loads = [b.fluid_film.load for b in r.bearing]
    np.testing.assert_allclose([ld[1] for ld in loads], [-ra, -rb], rtol=1e-10)


def _film_keys():
    f = film()
    return {k: getattr(f, k) for k in ("diameter", "length", "clearance", "viscosity", "model")} | {
        "speed_rpm": list(f.speed_rpm),
        "n_speeds": f.n_speeds,
    }


def test_explicit_load_still_works_and_bad_load_is_refused():
    cfg = {"shaft": [{"outer_diameter": D, "length": LENGTH, "elements": 4}]}
    explicit = {"node": 0, "fluid_film": {**_film_keys(), "load": [0.0, -200.0]}}
    ok = {**cfg, "bearing": [explicit, {"node": 4, "kxx": 1e8, "kyy": 1e8}]}
    r = Rotor.from_mapping(ok)
    assert r.bearing[0].fluid_film.load == (0.0, -200.0) and not r.static_load_bearings
    bad = {**cfg, "bearing": [{"node": 0, "fluid_film": {**_film_keys(), "load": "gravity"}}]}
    with pytest.raises(InputError, match=r"bearing\[0\]\.fluid_film\.load = 'gravity'.*an array or one of 'static'"):
        Rotor.from_mapping(bad)
    with pytest.raises(InputError, match=r"no gravity and no load"):
        resolve_static_loads(rotor((0.0, 1.2)), gravity=0.0)
