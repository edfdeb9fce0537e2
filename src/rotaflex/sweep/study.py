"""Sweeps over a TOML config: the domain picked by its ``domain`` key, keys varied on a grid."""

from __future__ import annotations

import functools
import json
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from rotaflex.core.errors import InputError
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
    from rotaflex.core.domains import CASES, case_module

    domain = config.get("domain")
    if domain is None:
        raise InputError("domain", "<missing>", "a top-level domain = one of " + ", ".join(CASES))
    try:
        module = case_module(domain)
    except ImportError as exc:
        raise InputError("domain", domain, f"an installed domain ({exc})") from None
    if isinstance(vary, Mapping):
        axes = {k: list(v) for k, v in vary.items()}
    else:
        axes = {}
        for spec in vary:
            key, values = parse_vary(spec)
            if key in axes:
                raise InputError(f"--vary {key}", spec, "each key varied once")
            axes[key] = values
    body = {k: v for k, v in config.items() if k != "domain"}
    cases = grid_cases(body, axes)
    validate = getattr(module, "validate_config", None)
    if validate is not None:  # optional domain hook: every case's values checked up front
        for case in cases:
            try:
                validate(case.data)
            except InputError as exc:
                raise InputError(exc.field, exc.value, f"{exc.allowed} (case {case.params})") from None
    return domain, CASES[domain], cases


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
    attrs = {"base_config": json.dumps(dict(config), sort_keys=True, default=str)}
    return run_sweep(
        functools.partial(run_module_case, module),
        cases,
        executor,
        out_dir=out_dir,
        domain=domain,
        attrs=attrs,
        **kwargs,
    )
