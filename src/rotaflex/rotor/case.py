"""``rotaflex rotor simulate``: TOML case -> model -> simulation -> RotorResult.

Hooks for the CLI and the sweeps (see :mod:`rotaflex.core.domains`): ``run_case``,
``validate_config`` (everything ``run_case`` checks, without running) and ``SCHEMA``.
"""

from __future__ import annotations

from rotaflex.core.config import from_mapping
from rotaflex.core.errors import InputError
from rotaflex.rotor.model import FreeBody, RotorModel
from rotaflex.rotor.result import RotorResult
from rotaflex.rotor.simulate import check_budget, simulate

#: root config of a rotor-disk case; a ``[free_body]`` table (:class:`FreeBody`) is the alternative
SCHEMA = RotorModel
#: alternative root tables: table name -> dataclass (for templates and the config reference)
ALTERNATIVES = {"free_body": FreeBody}

__all__ = ["ALTERNATIVES", "SCHEMA", "RotorResult", "model_from_config", "run_case", "sweep_figures", "validate_config"]


def model_from_config(config: dict) -> RotorModel | FreeBody:
    """A ``[free_body]`` table gives a FreeBody; otherwise the tables form a RotorModel."""
    if "free_body" in config:
        extra = [k for k in config if k != "free_body"]
        if extra:
            raise InputError(extra[0], config[extra[0]], "nothing beside [free_body] in a free-body case")
        return from_mapping(FreeBody, config["free_body"], "free_body")
    return from_mapping(RotorModel, config)


def validate_config(config: dict) -> None:
    """Check a rotor config without simulating: fields, ranges and the step budget."""
    check_budget(model_from_config(config))


def sweep_figures(ds) -> dict:
    """Domain hook of :mod:`rotaflex.sweep.figures`: the Campbell diagram of a spin sweep."""
    from rotaflex.rotor.sweep_figures import rotor_figures

    return rotor_figures(ds)


def run_case(config: dict, *, progress: bool = False) -> RotorResult:
    """Validate a parsed rotor config and simulate it."""
    return simulate(model_from_config(config), progress=progress)
