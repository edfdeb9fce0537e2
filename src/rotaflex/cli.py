"""Command line: ``rotaflex reproduce|rotor|floating|gear|sweep ...``. Parses, calls, saves."""

from __future__ import annotations

import logging
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Annotated, Any

import typer

from rotaflex.core.domains import CASES, COMMANDS, REPRODUCE
from rotaflex.core.errors import ConvergenceError, InputError, SingularityError

app = typer.Typer(
    add_completion=False,
    no_args_is_help=True,
    help="Dynamics of rotating and flexible machine elements (rotors, floating bodies, gears).",
)

Out = Annotated[Path, typer.Option("--out", "-o", help="Output directory (created if missing).")]
Quiet = Annotated[bool, typer.Option("--quiet", "-q", help="No progress bars.")]
Debug = Annotated[bool, typer.Option("--debug", help="Show tracebacks on error.")]


def guarded(fn: Callable[[], Any], debug: bool) -> Any:
    """Run ``fn``; expected failures become one line on stderr and a non-zero exit status.

    Exit status 2: bad input (field, value, what is allowed). Exit status 1: the computation
    failed (no convergence, singular parameterisation). ``--debug`` re-raises with traceback.
    """
    logging.basicConfig(level=logging.DEBUG if debug else logging.WARNING, format="%(message)s")
    try:
        return fn()
    except InputError as exc:
        if debug:
            raise
        typer.echo(f"error: {exc}", err=True)
        raise typer.Exit(2) from None
    except (ConvergenceError, SingularityError) as exc:
        if debug:
            raise
        typer.echo(f"error: {exc}", err=True)
        raise typer.Exit(1) from None


@app.command()
def reproduce(
    target: Annotated[str, typer.Argument(help="Domain to reproduce: " + ", ".join([*REPRODUCE, "all"]))],
    out: Out,
    fast: Annotated[bool, typer.Option("--fast", help="Shorter/coarser runs (for smoke tests).")] = False,
    quiet: Quiet = False,
    debug: Debug = False,
) -> None:
    """Re-run the papers' numerical examples; write figures, data, report.md and index.html."""
    from rotaflex.reproduce import reproduce as run_reproduce

    def go():
        if target not in REPRODUCE and target != "all":
            raise InputError("target", target, "one of " + ", ".join([*REPRODUCE, "all"]))
        names = list(REPRODUCE) if target == "all" else [target]
        t0 = time.perf_counter()
        report = run_reproduce(names, out, fast=fast, progress=not quiet)
        typer.echo(
            f"{report['passed']}/{report['checks']} checks passed in "
            f"{time.perf_counter() - t0:.1f} s; report: {out / 'report.md'}"
        )
        if report["passed"] < report["checks"]:
            typer.echo("some checks did not pass: see the report", err=True)

    guarded(go, debug)


@app.command()
def sweep(
    config: Annotated[Path, typer.Argument(help="TOML case file with a top-level domain key.")],
    out: Out,
    vary: Annotated[
        list[str],
        typer.Option(
            "--vary",
            "--param",
            "-p",
            help="KEY=START:STOP:N or KEY=v1,v2,...; KEY is a dotted config path. Repeat for a grid.",
        ),
    ],
    jobs: Annotated[
        int | None, typer.Option("--jobs", "-j", help="Local worker processes (default: one per core; 0: serial here).")
    ] = None,
    scheduler: Annotated[
        str | None, typer.Option("--scheduler", help="Dask scheduler address tcp://host:port, or dask-local.")
    ] = None,
    retries: Annotated[int, typer.Option("--retries", help="Re-runs of a case whose worker died.", min=0)] = 2,
    no_figures: Annotated[bool, typer.Option("--no-figures", help="Skip PNG figures.")] = False,
    quiet: Quiet = False,
    debug: Debug = False,
) -> None:
    """Run CONFIG for every combination of the --vary values; resume in DIR if re-run.

    Writes DIR/cases/<id>/ per case, DIR/sweep.nc (swept keys as dimensions), DIR/summary.csv,
    DIR/figures/. Exit status 1 if any case failed, 130 if interrupted.
    """
    from tqdm.contrib.logging import logging_redirect_tqdm

    from rotaflex.core.config import load_toml
    from rotaflex.sweep import plan, sweep_config
    from rotaflex.sweep.backends import executor_for

    def go():
        cfg = load_toml(config)
        plan(cfg, vary)  # validate everything before starting workers
        with executor_for(jobs, scheduler) as executor, logging_redirect_tqdm():
            try:
                res = sweep_config(
                    cfg, vary, out, executor, progress=not quiet, max_retries=retries, figures=not no_figures
                )
            except KeyboardInterrupt:
                typer.echo(
                    f"interrupted: finished cases are in {out / 'cases'}; run the same "
                    "command again to compute only the missing ones",
                    err=True,
                )
                raise typer.Exit(130) from None
        typer.echo(f"{res.summary_text()} -> {out / 'sweep.nc'}")
        for rec in res.failed[:10]:
            line = f"  failed {rec.id} {rec.params}: {rec.status} {rec.error}"
            typer.echo(line.rstrip(), err=True)
        if res.n_failed:
            typer.echo(f"{res.n_failed} of {res.n_cases} cases failed: see {out / 'summary.csv'}", err=True)
            raise typer.Exit(1)

    guarded(go, debug)


def _simulate_command(domain: str) -> Callable[..., None]:
    def simulate(
        config: Annotated[Path, typer.Argument(help="TOML case file.")],
        out: Out,
        no_figures: Annotated[bool, typer.Option("--no-figures", help="Skip PNG figures.")] = False,
        quiet: Quiet = False,
        debug: Debug = False,
    ) -> None:
        from rotaflex.core.config import load_toml
        from rotaflex.core.domains import run_config

        def go():
            result = run_config(load_toml(config), domain=domain, progress=not quiet)
            paths = result.save(out, figures=not no_figures)
            typer.echo(f"{result.status}: {result.message} -> {len(paths)} files in {out}")
            if result.status != "success":
                raise typer.Exit(1)

        guarded(go, debug)

    simulate.__doc__ = f"Simulate one {domain} case from CONFIG; write result.nc, summary.json, figures."
    return simulate


def _verb_command(domain: str, verb: str, target: str) -> Callable[..., None]:
    def command(
        config: Annotated[Path, typer.Argument(help="TOML case file.")],
        out: Out,
        no_figures: Annotated[bool, typer.Option("--no-figures", help="Skip PNG figures.")] = False,
        quiet: Quiet = False,
        debug: Debug = False,
    ) -> None:
        import importlib

        from rotaflex.core.config import load_toml

        def go():
            module, func = target.split(":")
            cfg = {k: v for k, v in load_toml(config).items() if k != "domain"}
            result = getattr(importlib.import_module(module), func)(cfg, progress=not quiet)
            paths = result.save(out, figures=not no_figures)
            typer.echo(f"{result.status}: {result.message} -> {len(paths)} files in {out}")
            if result.status != "success":
                raise typer.Exit(1)

        guarded(go, debug)

    command.__doc__ = f"{domain.capitalize()} {verb} from CONFIG; write result.nc, summary.json, figures."
    return command


_subs: dict[str, typer.Typer] = {}
for _domain in CASES:
    _sub = typer.Typer(no_args_is_help=True, help=f"{_domain.capitalize()} cases.")
    _sub.command("simulate")(_simulate_command(_domain))
    app.add_typer(_sub, name=_domain)
    _subs[_domain] = _sub
for _domain, _verbs in COMMANDS.items():
    if _domain not in _subs:
        _subs[_domain] = typer.Typer(no_args_is_help=True, help=f"{_domain.capitalize()} cases.")
        app.add_typer(_subs[_domain], name=_domain)
    for _verb, _target in _verbs.items():
        _subs[_domain].command(_verb)(_verb_command(_domain, _verb, _target))


def main() -> None:
    """Console-script entry point."""
    app(prog_name="rotaflex")


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
