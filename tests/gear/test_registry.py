"""The method registry: one name per method, one call contract, the schemas offer what it holds."""

import math
import typing

import pytest
from typer.testing import CliRunner

from rotaflex.cli import app
from rotaflex.gear.cases.simulate_config import SolverConfig
from rotaflex.gear.cases.steady import ModelSpec
from rotaflex.gear.models.chain import OperatingPoint, TorsionalSystem
from rotaflex.gear.models.mesh_stiffness import harmonic_mesh
from rotaflex.gear.solvers.registry import METHODS, Method

RB, J, K = 0.04177, 2.965e-4, 1.9e8  # the paper pair's base radius [m], disk inertia [kg m^2], k [N/m]


def _choices(schema, name):
    return set(typing.get_args(typing.get_type_hints(schema)[name]))


def test_the_four_methods_are_registered_with_what_a_user_needs_to_choose():
    assert set(METHODS) == {"paper_rk4", "reduced_hht", "lumped", "elastic_teeth"}
    for name, m in METHODS.items():
        assert isinstance(m, Method) and m.name == name
        assert m.models and m.cost and m.verbs


def test_config_schemas_offer_exactly_the_registered_methods_of_their_verb():
    simulate = {n for n, m in METHODS.items() if "simulate" in m.verbs}
    steady = {n for n, m in METHODS.items() if "steady" in m.verbs}
    assert _choices(SolverConfig, "method") == simulate == {"paper_rk4", "reduced_hht"}
    assert _choices(ModelSpec, "method") == steady == {"lumped", "elastic_teeth"}


def test_lumped_through_the_registry_matches_the_undamped_closed_form_static_deflection():
    # one mesh stiffness, no TE, pinion at constant speed: the steady DTE is the static
    # deflection F/k = T/(r_b k) (a closed form the solver does not compute itself)
    sys = TorsionalSystem(mesh=harmonic_mesh(K, (), ()), base_radius=(RB, RB), inertia=(J, J))
    torque = 300.0
    res, state = METHODS["lumped"](sys, {"op": OperatingPoint(speed_rpm=3000.0, torque=torque), "tol": 1e-8})
    assert res.status == "success"
    assert res.dataset["dte_mean"].item() == pytest.approx(torque / RB / K, rel=1e-6)
    # settings as keywords are the same call
    res2, _ = METHODS["lumped"](sys, op=OperatingPoint(speed_rpm=3000.0, torque=torque), tol=1e-8)
    assert res2.dataset["dte_mean"].item() == res.dataset["dte_mean"].item()
    assert math.isfinite(state.theta[0])


def test_gear_methods_lists_every_method_with_its_verbs():
    res = CliRunner().invoke(app, ["gear", "methods"])
    assert res.exit_code == 0, res.output
    for name, m in METHODS.items():
        assert f"{name}\n" in res.output
        assert m.models in res.output
    assert res.output.count("verbs:") == len(METHODS)
