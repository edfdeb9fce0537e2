"""Sweeps over a TOML config: the domain picked by its ``domain`` key, keys varied on a grid."""

from __future__ import annotations

import functools
import json
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from rotaflex.core.errors import InputError, shown
from rotaflex.sweep._worker import run_module_case
from rotaflex.sweep.runner import SweepResult, run_sweep
from rotaflex.sweep.spec import Case, grid_cases, parse_vary


def plan(config: Mapping[str, Any], vary: Sequence[str] | Mapping[str, Sequence[Any]]) -> tuple[str, str, list[Case]]:
    """Validate a config sweep before anything runs.

    Parameters
    ----------
    config : dict
        Parsed TOML with a top-level ``domain`` key.
    vary : list of str or dict
        ``--vary`` specifications (``"KEY=START:STOP:N"``, ``"KEY=v1,v2"``) or a mapping
        key -> values.

    Returns
    -------
    domain : str
    module : str
        The domain's ``run_case`` module (imported once here to fail early).
    cases : list of Case
        Each case's data is the config *without* the ``domain`` key.

    Raises
    ------
    InputError
        Missing/unknown domain, malformed vary spec, repeated key, key not in the config, or -
        when the domain's case module has a ``validate_config(config)`` hook - a case whose
        values the domain rejects.
    """
    from rotaflex.core.domains import CASES, case_module, check_domain

    if not isinstance(config, Mapping):
        raise InputError("config", config, "a TOML table")
    domain = config.get("domain")
    if domain is None:
        raise InputError("domain", "<missing>", "a top-level domain = one of " + ", ".join(CASES))
    check_domain(domain)
    try:
        module = case_module(domain)
    except ImportError as exc:
        raise InputError("domain", domain, f"an installed domain ({exc})") from None
    typed: dict[str, list[str]] = {}  # the values as written in a list spec, echoed in errors
    if isinstance(vary, Mapping):
        axes = {k: list(v) for k, v in vary.items()}
    else:
        axes = {}
        for spec in vary:
            key, values = parse_vary(spec)
            if key in axes:
                raise InputError(f"--vary {key}", spec, "each key varied once")
            axes[key] = values
            rhs = spec.split("=", 1)[1]
            if "," in rhs or ":" not in rhs:
                typed[key] = [t.strip() for t in rhs.split(",")]
    body = {k: v for k, v in config.items() if k != "domain"}
    cases = grid_cases(body, axes, defaults=_schema_defaults(module))
    validate = getattr(module, "validate_config", None)
    if validate is not None:  # optional domain hook: every case's values checked up front
        for case in cases:
            try:
                validate(case.data)
            except InputError as exc:
                value = exc.value
                if exc.field in typed and exc.field in case.params:
                    i = _index_of(axes[exc.field], case.params[exc.field])
                    if i is not None and i < len(typed[exc.field]):
                        value = _Typed(typed[exc.field][i])
                params = ", ".join(f"{k}={shown(v, 24)}" for k, v in case.params.items())
                raise InputError(exc.field, value, f"{exc.allowed} (case {params})") from None
    return domain, CASES[domain], cases


class _Typed(str):
    """A value shown exactly as the user typed it (no quotes in the message)."""

    def __repr__(self) -> str:
        return str(self)


def _index_of(values: list, value) -> int | None:
    for i, v in enumerate(values):
        try:
            if v == value:
                return i
        except Exception:  # noqa: BLE001 - incomparable values: not this one
            continue
    return None


def _schema_defaults(module):
    """``key -> default`` from the domain's ``SCHEMA`` (and ``ALTERNATIVES`` root tables), so a
    sweep may vary any schema key; None if the domain has no schema."""
    schema = getattr(module, "SCHEMA", None)
    if schema is None:
        return None
    from rotaflex.core.schema import default_of

    alternatives = getattr(module, "ALTERNATIVES", {})

    def lookup(key: str):
        table, _, rest = key.partition(".")
        if table in alternatives and rest:
            return default_of(alternatives[table], rest)
        return default_of(schema, key)

    return lookup


def _schema_units(module_name: str) -> dict[str, str]:
    """Units of every key of the domain's schema (for the sweep's dimension coordinates)."""
    import importlib

    from rotaflex.core.schema import entries

    module = importlib.import_module(module_name)
    roots = [("", getattr(module, "SCHEMA", None)), *getattr(module, "ALTERNATIVES", {}).items()]
    return {
        f"{table + '.' if table else ''}{e.key}": e.unit
        for table, schema in roots
        if schema is not None
        for e in entries(schema)
    }


def sweep_config(
    config: Mapping[str, Any], vary, out_dir: str | Path | None, executor: Any = None, **kwargs: Any
) -> SweepResult:
    """Sweep a domain config: :func:`plan`, then :func:`run_sweep` with the domain's ``run_case``.

    Extra keyword arguments go to :func:`run_sweep` (``progress``, ``max_retries``, ...).

    Examples
    --------
    >>> from rotaflex.core.config import load_toml                     # doctest: +SKIP
    >>> res = sweep_config(load_toml("rotor.toml"), ["spin.omega=0:100:11"], "out/sweep")
    """
    domain, module, cases = plan(config, vary)
    kwargs.setdefault("units", _schema_units(module))
    attrs = {"base_config": json.dumps(dict(config), sort_keys=True, default=str), **kwargs.pop("attrs", {})}
    return run_sweep(
        functools.partial(run_module_case, module),
        cases,
        executor,
        out_dir=out_dir,
        domain=domain,
        attrs=attrs,
        **kwargs,
    )
