"""Registry of the domains the CLI, the reproduce report and the sweeps know about.

Hook contract of a domain's case module (the ``CASES`` entry):

``run_case(config: dict, *, progress: bool = False) -> Result``
    Validate a parsed TOML config (without the ``domain`` key) and simulate it. Required.
``validate_config(config: dict) -> None``
    Optional. Check a config completely *without running it*, raising
    :class:`~rotaflex.core.errors.InputError` (field, value as typed, what is allowed) for
    anything ``run_case`` would refuse, including size/step budgets. A sweep calls it for every
    planned case before any case runs, and the CLI calls it before a single run starts.
``SCHEMA``
    Optional. The root config dataclass (fields declared with
    :func:`rotaflex.core.config.param`); used for ``rotaflex <domain> template``, the generated
    config reference, and the defaults of sweep keys not written in the base file.

Each reproduce target provides a module with ``run(out_dir: Path, *, fast: bool, progress: bool)
-> Section``; it may report per-case progress through :func:`rotaflex.core.report.step`.

Per-domain CLI verbs are data in :data:`COMMANDS`: domain -> verb -> ``"module:function"``, the
function having the signature of ``run_case``; ``rotaflex <domain> <verb> CONFIG --out DIR``
runs it like ``simulate``.

Validation of a verb (used by ``rotaflex sweep`` with a top-level ``verb = "..."`` key): the
module holding the verb's function may define ``validate_config(config)`` (contract as above)
and ``SCHEMA``; without ``validate_config`` the config is checked against ``SCHEMA``; with
neither, nothing is checked up front (``simulate``: only ``validate_config``). For
``simulate`` that module is the case module.

Continuation (``rotaflex sweep --continuation KEY``): a verb function that accepts an
``initial_state`` keyword (None: its usual start) and whose Result has a ``final_state()``
method (picklable data, also available from the Result loaded back from ``result.nc``) can run
a chain of cases, each starting from the previous case's final state.
"""

from __future__ import annotations

import importlib
from types import ModuleType
from typing import Any

#: domain name -> module with ``run_case``
CASES: dict[str, str] = {
    "rotor": "rotaflex.rotor.case",
    "gear": "rotaflex.gear.cases.simulate",
    "floating": "rotaflex.floating.case",
    "rotor_fe": "rotaflex.rotor.fe.case",  # finite-element rotor analyses; `analysis` key selects one
    "system": "rotaflex.system.case",  # geared rotor systems (FE rotors + gear meshes); `analysis` selects
}

#: domain -> verb -> "module:function" with ``fn(config: dict, *, progress=False) -> Result``;
#: the CLI adds ``rotaflex <domain> <verb> CONFIG --out DIR`` for each
COMMANDS: dict[str, dict[str, str]] = {
    "rotor": {
        "modal": "rotaflex.rotor.fe.case:run_modal",
        "campbell": "rotaflex.rotor.fe.case:run_campbell",
        "ucs": "rotaflex.rotor.fe.case:run_ucs",
        "unbalance": "rotaflex.rotor.fe.case:run_unbalance",
        "transient": "rotaflex.rotor.fe.case:run_transient",
        "static": "rotaflex.rotor.fe.case:run_static",
        "frf": "rotaflex.rotor.fe.case:run_frf",
        "stability": "rotaflex.rotor.fe.case:run_stability",
    },
    "gear": {
        "static": "rotaflex.gear.cases.static:run_static",
        "steady": "rotaflex.gear.cases.steady:run_torsional",
    },
    "system": {
        "modal": "rotaflex.system.case:run_modal",
        "campbell": "rotaflex.system.case:run_campbell",
        "response": "rotaflex.system.case:run_response",
        "steady": "rotaflex.system.case:run_steady",
        "torsional": "rotaflex.system.case:run_torsional",
        "startup": "rotaflex.system.case:run_startup",
        "unbalance": "rotaflex.system.case:run_unbalance",
        "frf": "rotaflex.system.case:run_frf",
        "stability": "rotaflex.system.case:run_stability",
        "static": "rotaflex.system.case:run_static",
        "ucs": "rotaflex.system.case:run_ucs",
        "transient": "rotaflex.system.case:run_transient",
    },
}

#: domain -> verb -> "module:function" with ``fn() -> str``: verbs that print a listing and
#: read no config (``rotaflex gear methods``)
LISTINGS: dict[str, dict[str, str]] = {
    "gear": {"methods": "rotaflex.gear.solvers.registry:methods_table"},
}

#: reproduce target -> module with ``run``; "all" runs every entry in this order
REPRODUCE: dict[str, str] = {
    "rotor": "rotaflex.reproduce.rotor",
    "gear": "rotaflex.reproduce.gear",
    "floating": "rotaflex.reproduce.floating",
    "geared_rotor": "rotaflex.reproduce.geared_rotor",  # FE rotors coupled through a gear mesh
    "sweep": "rotaflex.reproduce.sweep",  # keep last: sweeps every domain above
}


def check_domain(domain: Any, field: str = "domain") -> str:
    """``domain`` if it names a registered domain, else an InputError (also for non-strings)."""
    from rotaflex.core.errors import InputError

    if not isinstance(domain, str) or domain not in CASES:
        raise InputError(field, domain, "a string, one of " + ", ".join(repr(d) for d in CASES))
    return domain


def case_module(domain: Any) -> ModuleType:
    """The ``run_case`` module of ``domain`` (raises InputError for an unknown domain)."""
    return importlib.import_module(CASES[check_domain(domain)])


def schema_of(domain: str) -> type | None:
    """The domain's root config dataclass (``SCHEMA`` of its case module), or None."""
    return getattr(case_module(domain), "SCHEMA", None)


def validate(domain: str, config: dict) -> None:
    """Run the domain's ``validate_config`` hook on ``config`` (no-op if it has none)."""
    hook = getattr(case_module(domain), "validate_config", None)
    if hook is not None:
        hook(config)


def resolve_paths(domain: str, config: dict, base) -> dict:
    """``config`` with the file paths it names made relative to ``base`` (the case file's
    directory), through the domain's ``resolve_paths`` hook (unchanged if it has none)."""
    hook = getattr(case_module(domain), "resolve_paths", None)
    return config if hook is None else hook(config, base)


def split_config(config: dict, *, domain: str | None = None, verb: str | None = None) -> tuple[str, dict]:
    """The domain of a parsed config (from ``domain`` or its ``domain`` key) and the body.

    If both are given they must agree. With ``verb``, a top-level ``verb`` key (as a sweep's
    base file has) must name that verb and is dropped from the body.
    """
    from rotaflex.core.errors import InputError

    if not isinstance(config, dict):
        raise InputError("config", config, "a TOML table")
    cfg_domain = config.get("domain")
    if domain is None:
        if cfg_domain is None:
            raise InputError("domain", "<missing>", "a top-level key, one of " + ", ".join(repr(d) for d in CASES))
        domain = check_domain(cfg_domain)
    elif cfg_domain is not None and cfg_domain != domain:
        raise InputError("domain", cfg_domain, f"{domain!r} for 'rotaflex {domain} ...'")
    if verb is not None and "verb" in config:
        if config["verb"] != verb:
            raise InputError("verb", config["verb"], f"{verb!r} for 'rotaflex {domain} {verb}' (or no verb key)")
        config = {k: v for k, v in config.items() if k != "verb"}
    return domain, {k: v for k, v in config.items() if k != "domain"}


def run_config(config: dict, *, domain: str | None = None, progress: bool = False):
    """Simulate a parsed config with its domain's ``run_case``.

    The domain comes from ``domain`` or the config's top-level ``domain`` key; if both are
    given they must agree.
    """
    domain, body = split_config(config, domain=domain)
    return case_module(domain).run_case(body, progress=progress)


def command_target(domain: Any, verb: Any, field: str = "verb") -> str:
    """``"module:function"`` of ``rotaflex <domain> <verb>`` (``simulate``: the case module's
    ``run_case``); InputError naming ``field`` for a verb the domain does not have."""
    from rotaflex.core.errors import InputError

    domain = check_domain(domain)
    verbs = ["simulate", *COMMANDS.get(domain, {})]
    if not isinstance(verb, str) or verb not in verbs:
        raise InputError(field, verb, f"a verb of the {domain} domain, one of " + ", ".join(map(repr, verbs)))
    return f"{CASES[domain]}:run_case" if verb == "simulate" else COMMANDS[domain][verb]


def resolve(target: str):
    """The function of a ``"module:function"`` target."""
    module, _, name = target.partition(":")
    return getattr(importlib.import_module(module), name)


def command(domain: str, verb: str):
    """The function registered for ``rotaflex <domain> <verb>`` (``simulate``: ``run_case``)."""
    return resolve(command_target(domain, verb))


def command_module(domain: str, verb: str) -> ModuleType:
    """The module holding the function of ``rotaflex <domain> <verb>``."""
    return importlib.import_module(command_target(domain, verb).partition(":")[0])


def validate_command(domain: str, verb: str, config: dict) -> None:
    """Check ``config`` for ``rotaflex <domain> <verb>`` without running it: the verb module's
    ``validate_config``, else (verbs other than ``simulate``, whose case modules may combine
    several root tables) its ``SCHEMA`` (:func:`rotaflex.core.config.from_mapping`)."""
    module = command_module(domain, verb)
    hook = getattr(module, "validate_config", None)
    if hook is not None:
        hook(config)
    elif verb != "simulate" and getattr(module, "SCHEMA", None) is not None:
        from rotaflex.core.config import from_mapping

        from_mapping(module.SCHEMA, config)
