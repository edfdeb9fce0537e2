"""Sweeps over a TOML config: the domain picked by its ``domain`` key, keys varied on a grid.

The verb is ``simulate`` unless the config has a top-level ``verb`` key naming another verb of
the domain (:data:`rotaflex.core.domains.COMMANDS`, e.g. ``verb = "steady"`` for the gear
steady-state model); the verb's own checks validate every case before any runs. With
``continuation=KEY`` the cases run as chains along that key (:mod:`.continuation`).
"""

from __future__ import annotations

import functools
import importlib
import json
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from rotaflex.core.errors import InputError, shown
from rotaflex.sweep._worker import run_target
from rotaflex.sweep.runner import SweepResult, run_sweep
from rotaflex.sweep.spec import Case, check_key, grid_cases, parse_vary


@dataclass
class Study:
    """A planned sweep (:func:`plan_study`).

    Attributes
    ----------
    domain, verb : str
    target : str
        ``"module:function"`` of the verb (run on the workers).
    cases : list of Case
        Grid cases; with a continuation each twice (``direction`` up/down), data
        ``{"config", "continuation"}`` (:func:`~rotaflex.sweep.continuation.chain_cases`).
    chains : list of list of str or None
        Case ids per continuation chain in run order.
    continuation : str or None
        The continued key.
    """

    domain: str
    verb: str
    target: str
    cases: list[Case]
    chains: list[list[str]] | None = None
    continuation: str | None = None

    @property
    def module(self) -> str:
        return self.target.partition(":")[0]


#: top-level keys of a sweep's base config that are not part of the case config
TOP_KEYS = ("domain", "verb")


def plan(config: Mapping[str, Any], vary: Sequence[str] | Mapping[str, Sequence[Any]]) -> tuple[str, str, list[Case]]:
    """Validate a config sweep before anything runs: ``(domain, module, cases)`` of
    :func:`plan_study` (module: the verb's module, e.g. the domain's ``run_case`` module)."""
    st = plan_study(config, vary)
    return st.domain, st.module, st.cases


def plan_study(
    config: Mapping[str, Any],
    vary: Sequence[str] | Mapping[str, Sequence[Any]],
    continuation: str | None = None,
    split_down: bool = False,
) -> Study:
    """Validate a config sweep before anything runs.

    Parameters
    ----------
    config : dict
        Parsed TOML with a top-level ``domain`` key and optionally ``verb`` (default
        ``"simulate"``; another verb of the domain's ``COMMANDS``, e.g. ``"steady"``).
    vary : list of str or dict
        ``--vary`` specifications (``"KEY=START:STOP:N"``, ``"KEY=v1,v2"``) or a mapping
        key -> values.
    continuation : str, optional
        A swept numeric key to run as continuation chains, up then down
        (:mod:`rotaflex.sweep.continuation`); the verb must accept ``initial_state``.
    split_down : bool
        Run each down chain from the verb's own start at the highest value, as a chain of its
        own next to the up chain (see :func:`~rotaflex.sweep.continuation.chain_cases`).

    Returns
    -------
    Study
        Each case's config is the base config *without* the ``domain`` and ``verb`` keys.

    Raises
    ------
    InputError
        Missing/unknown domain or verb, malformed vary spec, repeated key, key not in the
        config, a case whose values the verb rejects (its module's ``validate_config``, else
        its ``SCHEMA``; see :func:`rotaflex.core.domains.validate_command`), or a continuation
        the verb or the grid cannot do.
    """
    from rotaflex.core.domains import CASES, check_domain, command_target, resolve, validate_command

    if not isinstance(config, Mapping):
        raise InputError("config", config, "a TOML table")
    domain = config.get("domain")
    if domain is None:
        raise InputError("domain", "<missing>", "a top-level domain = one of " + ", ".join(CASES))
    check_domain(domain)
    verb = config.get("verb", "simulate")
    target = command_target(domain, verb)
    try:
        fn = resolve(target)
        module = importlib.import_module(target.partition(":")[0])
    except ImportError as exc:
        raise InputError("domain", domain, f"an installed domain ({exc})") from None
    typed: dict[str, list[str]] = {}  # the values as written in a list spec, echoed in errors
    if isinstance(vary, Mapping):
        for k in vary:
            check_key(k)
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
    if "verb" in axes:
        raise InputError("--vary verb", axes["verb"], "a key inside the domain's config, not 'verb'")
    body = {k: v for k, v in config.items() if k not in TOP_KEYS}
    if split_down and continuation is None:
        raise InputError("--split-down", True, "only together with --continuation KEY")
    if continuation is not None:
        _check_continuation_base(body, continuation)
    cases = grid_cases(body, axes, defaults=_schema_defaults(module))
    # every case's values checked up front by the verb's own checks
    for case in cases:
        try:
            validate_command(domain, verb, case.data)
        except InputError as exc:
            value = exc.value
            if exc.field in typed and exc.field in case.params:
                i = _index_of(axes[exc.field], case.params[exc.field])
                if i is not None and i < len(typed[exc.field]):
                    value = _Typed(typed[exc.field][i])
            params = ", ".join(f"{k}={shown(v, 24)}" for k, v in case.params.items())
            raise InputError(exc.field, value, f"{exc.allowed} (case {params})") from None
    study = Study(domain, verb, target, cases)
    if continuation is not None:
        from rotaflex.sweep.continuation import chain_cases, check_continuable

        check_continuable(fn, continuation, domain, verb)
        study.cases, study.chains = chain_cases(cases, continuation, split_down)
        study.continuation = continuation
    return study


def _check_continuation_base(body: Mapping[str, Any], continuation: str) -> None:
    """Refuse, before any case runs, a continuation base file that keeps its own ``[sweep]`` table.

    With one, the verb runs that table's inner sweep in every case (e.g. ``gear steady`` over
    ``sweep.speeds_rpm``), and such a result has no single final state to continue from: every
    case would fail after running.
    """
    inner = body.get("sweep")
    if isinstance(inner, Mapping) and any(v not in (None, "", [], (), {}) for v in inner.values()):
        raise InputError(
            "sweep",
            {k: v for k, v in inner.items() if v not in (None, "", [], (), {})},
            f"no [sweep] table in the base file of --continuation {continuation} (each case would run "
            "that inner sweep, which has no final state to continue from): remove the table",
        )


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
    config: Mapping[str, Any],
    vary,
    out_dir: str | Path | None,
    executor: Any = None,
    *,
    continuation: str | None = None,
    split_down: bool = False,
    **kwargs: Any,
) -> SweepResult:
    """Sweep a domain config: :func:`plan_study`, then :func:`run_sweep` with the verb's function.

    ``continuation``: a swept key to run as up/down continuation chains (see
    :mod:`rotaflex.sweep.continuation`); ``split_down``: see :func:`plan_study`. Extra keyword
    arguments go to :func:`run_sweep` (``progress``, ``max_retries``, ...).

    Examples
    --------
    >>> from rotaflex.core.config import load_toml                     # doctest: +SKIP
    >>> res = sweep_config(load_toml("rotor.toml"), ["spin.omega=0:100:11"], "out/sweep")
    """
    study = plan_study(config, vary, continuation, split_down)
    kwargs.setdefault("units", _schema_units(study.module))
    attrs = {
        "base_config": json.dumps(dict(config), sort_keys=True, default=str),
        "verb": study.verb,
        "continuation": study.continuation or "",
        **kwargs.pop("attrs", {}),
    }
    if study.chains is None:
        case_fn = functools.partial(run_target, study.target)
    else:
        from rotaflex.sweep.continuation import run_link

        case_fn = functools.partial(run_link, study.target)
    return run_sweep(
        case_fn,
        study.cases,
        executor,
        out_dir=out_dir,
        domain=study.domain,
        attrs=attrs,
        chains=study.chains,
        **kwargs,
    )
