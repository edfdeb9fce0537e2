"""Registry of the domains the CLI, the reproduce report and the sweeps know about.

Each simulation domain provides a module with ``run_case(config: dict, *, progress=False)
-> Result`` that validates a parsed TOML config and simulates it. Each reproduce target provides
a module with ``run(out_dir: Path, *, fast: bool, progress: bool) -> Section``.
"""

from __future__ import annotations

import importlib
from types import ModuleType

#: domain name -> module with ``run_case``
CASES: dict[str, str] = {
    "rotor": "rotaflex.rotor.case",
    "gear": "rotaflex.gear.case",
    "floating": "rotaflex.floating.case",
    "rotor_fe": "rotaflex.rotor.fe.case",  # finite-element rotor analyses; `analysis` key selects one
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
    },
}

#: reproduce target -> module with ``run``; "all" runs every entry in this order
REPRODUCE: dict[str, str] = {
    "rotor": "rotaflex.reproduce.rotor",
    "gear": "rotaflex.reproduce.gear",
    "floating": "rotaflex.reproduce.floating",
    "sweep": "rotaflex.reproduce.sweep",  # keep last: sweeps every domain above
}


def case_module(domain: str) -> ModuleType:
    """The ``run_case`` module of ``domain`` (raises InputError for an unknown domain)."""
    from rotaflex.core.errors import InputError

    if domain not in CASES:
        raise InputError("domain", domain, "one of " + ", ".join(CASES))
    return importlib.import_module(CASES[domain])


def run_config(config: dict, *, domain: str | None = None, progress: bool = False):
    """Simulate a parsed config with its domain's ``run_case``.

    The domain comes from ``domain`` or the config's top-level ``domain`` key; if both are
    given they must agree.
    """
    from rotaflex.core.errors import InputError

    cfg_domain = config.get("domain")
    if domain is None:
        if cfg_domain is None:
            raise InputError("domain", "<missing>", "one of " + ", ".join(CASES))
        domain = cfg_domain
    elif cfg_domain is not None and cfg_domain != domain:
        raise InputError("domain", cfg_domain, f"{domain!r} for 'rotaflex {domain} simulate'")
    body = {k: v for k, v in config.items() if k != "domain"}
    return case_module(domain).run_case(body, progress=progress)
