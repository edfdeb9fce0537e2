"""``rotaflex rotor modal|campbell|ucs|unbalance|transient CONFIG.toml``: TOML -> analysis -> Result.

A config holds the rotor tables (``[[shaft]]``, ``[[disk]]``, ``[[point_mass]]``,
``[[bearing]]``, ``[material.<name>]``, ``free``) and one table per analysis (``[modal]``,
``[campbell]``, ``[ucs]``, ``[unbalance]``, ``[transient]``); each verb reads its own table
(defaults when absent). Speeds are given in rpm (``speed_rpm``) and converted to rad/s once,
where the config is read. For sweeps, ``analysis = "campbell"`` (etc.) at top level selects the
analysis of :func:`run_case` (domain ``rotor_fe``).

This module is the entry point of the verbs; the parts live beside it:
:mod:`~rotaflex.rotor.fe.case_config` (schema, parsing, size limits),
:mod:`~rotaflex.rotor.fe.case_output` (what every verb does around its analysis),
:mod:`~rotaflex.rotor.fe.verbs_modal` (modal, campbell, ucs),
:mod:`~rotaflex.rotor.fe.verbs_response` (unbalance, transient) and
:mod:`~rotaflex.rotor.fe.verbs` (static, frf).
"""

from __future__ import annotations

from dataclasses import asdict

from rotaflex.core.errors import InputError
from rotaflex.core.result import freeze_imports, import_xarray
from rotaflex.rotor.fe.case_config import (
    ANALYSES,
    MAX_POINTS,
    MAX_STEPS,
    SCHEMA,
    FECase,
    clamp_modes,
    parse,
)
from rotaflex.rotor.fe.case_output import add_fluid_film_tables, pinned
from rotaflex.rotor.fe.verbs_modal import DOFS, run_campbell, run_modal, run_ucs
from rotaflex.rotor.fe.verbs_response import run_transient, run_unbalance

import_xarray()  # xarray's deferred work now, not inside the analyses' timers
freeze_imports()  # nor full garbage collections walking every imported object

__all__ = [
    "ANALYSES",
    "DOFS",
    "MAX_POINTS",
    "MAX_STEPS",
    "RUNNERS",
    "SCHEMA",
    "FECase",
    "add_fluid_film_tables",
    "clamp_modes",
    "parse",
    "run_campbell",
    "run_case",
    "run_frf",
    "run_modal",
    "run_stability",
    "run_static",
    "run_transient",
    "run_ucs",
    "run_unbalance",
    "schema_dict",
    "validate_config",
]


@pinned
def run_static(config: dict, *, progress: bool = False):
    """Static deflection, bearing reactions, shear force and bending moment (``[static]``)."""
    from rotaflex.rotor.fe.verbs import run_static as _run

    return _run(config, progress=progress)


@pinned
def run_frf(config: dict, *, progress: bool = False):
    """Frequency response functions of ``[frf]`` (receptance, mobility or accelerance)."""
    from rotaflex.rotor.fe.verbs import run_frf as _run

    return _run(config, progress=progress)


@pinned
def run_stability(config: dict, *, progress: bool = False):
    """API 617 Level I and Level II stability (``[stability]``), docs/stability.md."""
    from rotaflex.rotor.fe.verbs_stability import run_stability as _run

    return _run(config, progress=progress)


RUNNERS = {
    "static": run_static,
    "frf": run_frf,
    "modal": run_modal,
    "campbell": run_campbell,
    "ucs": run_ucs,
    "unbalance": run_unbalance,
    "transient": run_transient,
    "stability": run_stability,
}


def run_case(config: dict, *, progress: bool = False):
    """Sweep entry point (domain ``rotor_fe``): runs the analysis named by ``analysis``."""
    name = config.get("analysis")
    if name not in RUNNERS:
        raise InputError("analysis", name if name is not None else "<missing>", "one of " + ", ".join(RUNNERS))
    return RUNNERS[name](config, progress=progress)


def validate_config(config: dict) -> None:
    """Sweep hook: reject a bad case before any worker starts."""
    name = config.get("analysis")
    if name not in RUNNERS:
        raise InputError("analysis", name if name is not None else "<missing>", "one of " + ", ".join(RUNNERS))
    parse(config, name)


def schema_dict() -> dict:
    """Defaults of the analysis tables (for generated templates)."""
    return {k: asdict(v()) for k, v in ANALYSES.items()}
