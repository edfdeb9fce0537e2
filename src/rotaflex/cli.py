"""Command line: ``rotaflex reproduce|rotor|floating|gear|sweep|docs ...``. Parses, checks, calls, saves.

Every expected failure is one line on stderr: exit status 2 for bad input (the dotted field, the
value as typed, what is allowed; also a missing or unknown option), 1 when the computation
failed, a result failed its own checks or an output could not be written, 130 when interrupted
(SIGINT, Ctrl-C), 143 when terminated (SIGTERM). Output directories and input files are checked
before any computation starts, and a run holds its output directory until it ends.
"""

import gc
import inspect
import os
import signal
import sys
import threading
import time
from collections.abc import Callable
from pathlib import Path
from typing import Annotated, Any

import typer

from rotaflex.cli_startup import blas_threads_at_load, collection_paused, defer_unused_numpy, plain_coercion
from rotaflex.core.domains import CASES, COMMANDS, LISTINGS, REPRODUCE
from rotaflex.core.errors import ConvergenceError, DivergenceError, InputError, SingularityError

#: plain help and error text: typer's rich formatter costs ~0.3 s of imports (rich, markdown_it) on
#: every ``--help`` and usage error, more than the whole start-up budget (issue 25: <= 0.2 s)
PLAIN = {"rich_markup_mode": None}
plain_coercion()  # str/int/bool/Path parameters without typer's pydantic adapters (~0.11 s a verb)


app = typer.Typer(
    **PLAIN,
    add_completion=False,
    no_args_is_help=True,
    pretty_exceptions_enable=False,
    help="Dynamics of rotating and flexible machine elements (rotors, floating bodies, gears).",
)

Out = Annotated[
    str,
    typer.Option(
        "--out", "-o", help="Output directory; its parent must exist. An earlier result there is replaced as a whole."
    ),
]
Quiet = Annotated[bool, typer.Option("--quiet", "-q", help="No progress output.")]
Debug = Annotated[bool, typer.Option("--debug", help="Show tracebacks on error.")]
Format = Annotated[str, typer.Option("--format", help="Figure file format: png, svg or pdf.")]
Dpi = Annotated[int, typer.Option("--dpi", help="Resolution of PNG figures [dots per inch].")]
NoFigures = Annotated[bool, typer.Option("--no-figures", help="Skip figures.")]

#: most local worker processes a sweep may start
MAX_JOBS = 1024
#: files that mark a directory as an earlier output of a command (never replace anything else)
RESULT_MARKERS = ("result.nc", "summary.json")
SWEEP_MARKERS = ("sweep.json", "sweep.nc", "cases", ".mp")
REPORT_MARKERS = ("report.md", "checks.json", "index.html", *REPRODUCE)


def _version(value: bool) -> None:
    if value:
        import rotaflex

        typer.echo(f"rotaflex {rotaflex.__version__}")
        raise typer.Exit()


@app.callback()
def _root(
    version: Annotated[
        bool, typer.Option("--version", callback=_version, is_eager=True, help="Print the version and exit.")
    ] = False,
    max_memory: Annotated[
        str | None,
        typer.Option(
            "--max-memory",
            help="Largest memory a run may plan to use, e.g. 16GiB or 500MB (default 8GiB, or "
            "ROTAFLEX_MAX_MEMORY); larger runs are refused before they start.",
        ),
    ] = None,
) -> None:
    """Dynamics of rotating and flexible machine elements (rotors, floating bodies, gears)."""
    from rotaflex.core.limits import set_max_memory

    try:  # not through guarded(): its logging setup belongs to the command and its --debug
        set_max_memory(max_memory)
    except InputError as exc:
        typer.echo(f"error: {exc}", err=True)
        raise typer.Exit(2) from None
    if max_memory is not None:  # sweep workers (other processes) read the environment
        os.environ["ROTAFLEX_MAX_MEMORY"] = max_memory


# -- signals --------------------------------------------------------------------------------------
class Terminated(KeyboardInterrupt):
    """SIGTERM, raised like Ctrl-C so that every ``finally`` and ``except KeyboardInterrupt`` runs."""


#: exit status per signal (128 + its number, as a shell reports a death by that signal)
SIGNAL_EXIT = {signal.SIGINT: 130, signal.SIGTERM: 143}
#: the signal received during this command (0: none); read after the command to catch an
#: interrupt that a library swallowed (an exception raised in a weakref callback is only printed)
_received = 0
#: code whose frames must never see an exception appear: compiled numba kernels call back into
#: Python (numba.core.serialize) and treat an exception there as impossible (SIGSEGV); h5py's
#: object teardown likewise; weakref/__del__ callbacks only print exceptions (and so does the
#: import system's module-lock callback, ``cb`` in ``<frozen importlib._bootstrap>``; the rest of
#: an import is a safe point, so an interrupt is not held back until the run has written its output)
_UNSAFE = tuple(f"{os.sep}{m}{os.sep}" for m in ("numba", "llvmlite", "h5py", "h5netcdf", "netCDF4")) + (
    f"{os.sep}weakref.py",
)
#: the command runs in a process of its own (the console script), not inside a caller's
_standalone = False
#: seconds between attempts to deliver a deferred interrupt
_RETRY = 0.02


def _at_safe_point(frame) -> bool:
    while frame is not None:
        name = frame.f_code.co_filename
        code = frame.f_code.co_name
        if name.endswith(_UNSAFE[-1]) or code == "__del__" or (code == "cb" and name.startswith("<frozen importlib")):
            return False
        if any(u in name for u in _UNSAFE[:-1]):
            return False
        frame = frame.f_back
    return True


def _on_signal(signum, frame) -> None:
    """Record the signal; raise it as KeyboardInterrupt at the next safe point.

    Inside a compiled kernel the handler cannot run at all (the interpreter runs it when the
    kernel returns); inside numba's or h5py's Python helpers it retries every 20 ms (SIGALRM)
    until the stack is clear of them, so that an open HDF5 file is closed by its own code and
    a kernel's callback never fails.
    """
    global _received
    if signum != signal.SIGALRM:
        _received = _received or signum
    if not _received:
        return
    if not _at_safe_point(frame):
        signal.setitimer(signal.ITIMER_REAL, _RETRY)
        return
    signal.setitimer(signal.ITIMER_REAL, 0)
    raise Terminated() if _received == signal.SIGTERM else KeyboardInterrupt()


def _install_signals() -> dict:
    """Install :func:`_on_signal` for SIGINT, SIGTERM and the retry timer; return the old handlers."""
    global _received
    _received = 0
    old = {}
    if threading.current_thread() is not threading.main_thread():  # handlers only from there
        return old
    for sig in (signal.SIGINT, signal.SIGTERM, signal.SIGALRM):
        if signal.getsignal(sig) is signal.SIG_IGN:  # e.g. started with nohup / in the background
            continue
        old[sig] = signal.signal(sig, _on_signal)
    return old


def _interrupt_exit() -> None:
    """One line and the exit status for the signal received (SIGINT when none was recorded)."""
    _quiet_shutdown()
    if _received == signal.SIGTERM:
        typer.echo("terminated (SIGTERM)", err=True)
        raise typer.Exit(SIGNAL_EXIT[signal.SIGTERM])
    typer.echo("interrupted", err=True)
    raise typer.Exit(SIGNAL_EXIT[signal.SIGINT])


def _quiet_shutdown() -> None:
    """After Ctrl-C, errors of half-stopped process pools during interpreter exit (Python 3.11's
    concurrent.futures wakes a pool whose pipe is already closed; its manager thread can fail
    on the terminated workers) are noise, not news: the one-line message says what happened."""
    sys.unraisablehook = lambda _unraisable: None
    threading.excepthook = lambda _args: None


def guarded(fn: Callable[[], Any], debug: bool) -> Any:
    """Run ``fn``; expected failures become one line on stderr and a non-zero exit status.

    Exit status 2: bad input (field, value, what is allowed). Exit status 1: the computation
    failed (no convergence, singular parameterisation) or an output could not be written
    (full disk). 130: interrupted (Ctrl-C), 143: terminated (SIGTERM); also when a library
    swallowed the interrupt and the command went on. ``--debug`` re-raises with traceback.
    """
    import logging  # here, not at the top: ~20 ms that --help and usage errors do not need
    import warnings

    from rotaflex.core.examples import IncompleteInstall
    from rotaflex.core.io import WriteFailed

    logging.basicConfig(level=logging.DEBUG if debug else logging.WARNING, format="%(message)s")
    try:
        with warnings.catch_warnings():  # the outcome is one line: no warning printed before it
            if not debug:  # (a run's own numeric warnings are judged by flag_numeric_warnings)
                warnings.simplefilter("ignore")
            out = fn()
        if _received in SIGNAL_EXIT:
            raise Terminated() if _received == signal.SIGTERM else KeyboardInterrupt()
        return out
    except InputError as exc:
        if debug:
            raise
        typer.echo(f"error: {exc}", err=True)
        raise typer.Exit(2) from None
    except (ConvergenceError, DivergenceError, SingularityError, WriteFailed, IncompleteInstall) as exc:
        if debug:
            raise
        typer.echo(f"error: {exc}", err=True)
        raise typer.Exit(1) from None
    except KeyboardInterrupt:
        if debug:
            raise
        _interrupt_exit()
    except (typer.Exit, typer.Abort):
        raise
    except Exception as exc:  # noqa: BLE001 - a bug: one line, the traceback with --debug
        if debug:
            raise
        text = str(exc).splitlines()[0] if str(exc) else ""
        typer.echo(f"error: internal error {type(exc).__name__}: {text} (rerun with --debug for details)", err=True)
        raise typer.Exit(1) from None


#: warnings that mean a number of the answer is not to be trusted: an ill-conditioned solve
#: (scipy's LinAlgWarning), an overflow or a 0/0 (numpy's RuntimeWarning with these words);
#: printed before the one-line summary they were noise, now they fail the result
NUMERIC_WARNINGS = {"LinAlgWarning": (), "RuntimeWarning": ("overflow", "invalid value")}


class numeric_warnings:
    """Hold the warnings and log records of a run instead of printing them (a context manager
    yielding the list of warnings): the run's outcome is one line; the log records of a run
    that succeeds are printed after it (:func:`flag_numeric_warnings`), else dropped."""

    def __enter__(self) -> list:
        import logging
        import warnings

        self._ctx = warnings.catch_warnings(record=True)
        caught = self._ctx.__enter__()
        warnings.simplefilter("always")
        self.records: list = []
        self._handlers = list(logging.getLogger().handlers)
        for h in self._handlers:
            h.addFilter(self._hold)
        caught.append(self)  # the held records travel with the list
        return caught

    def _hold(self, record) -> bool:
        if not any(r is record for r in self.records):
            self.records.append(record)
        return False

    def __exit__(self, *exc) -> bool:
        self._ctx.__exit__(*exc)
        for h in self._handlers:
            h.removeFilter(self._hold)
        return False

    def release(self) -> None:
        """Print the held log records (once)."""
        records, self.records = self.records, []
        for r in records:
            for h in self._handlers:
                if r.levelno >= h.level:
                    h.handle(r)


def flag_numeric_warnings(result, caught: list) -> None:
    """A successful ``result`` during whose run numpy or scipy warned of a number it could not
    trust becomes ``failed_check`` naming the first such warning (its line, without the path);
    the run's log records are printed if it still succeeds."""

    def numeric(w) -> bool:
        words = NUMERIC_WARNINGS.get(w.category.__name__)
        return words is not None and (not words or any(x in str(w.message) for x in words))

    held = [w for w in caught if isinstance(w, numeric_warnings)]
    caught = [w for w in caught if not isinstance(w, numeric_warnings)]
    bad = [w for w in caught if numeric(w)]
    if bad and getattr(result, "status", None) == "success" and hasattr(result, "failed_check"):
        w = bad[0]
        text = str(w.message).splitlines()[0] if str(w.message) else ""
        where = f"{Path(w.filename).parent.name}/{Path(w.filename).name}:{w.lineno}"
        result.failed_check(
            "numerics", f"{w.category.__name__} in {where}: {text}", "no overflow, 0/0 or singular solve"
        )
    if getattr(result, "status", None) == "success":
        for h in held:
            h.release()


def _figure_options(fmt: str, dpi: int) -> None:
    from rotaflex.core.plotting import FORMATS

    if fmt not in FORMATS:
        raise InputError("--format", fmt, "one of " + ", ".join(FORMATS))
    if not 10 <= dpi <= 2400:
        raise InputError("--dpi", dpi, "an integer from 10 to 2400")


def _limit_threads():
    """One BLAS/OpenMP thread (:func:`rotaflex.core.threads.limit_blas_threads`)."""
    from rotaflex.core.threads import limit_blas_threads

    return limit_blas_threads()


@app.command()
def reproduce(
    target: Annotated[str, typer.Argument(help="Domain to reproduce: " + ", ".join([*REPRODUCE, "all"]))],
    out: Out,
    fast: Annotated[bool, typer.Option("--fast", help="Shorter/coarser runs (for smoke tests).")] = False,
    jobs: Annotated[
        int | None,
        typer.Option(
            "--jobs",
            "-j",
            help="Worker processes running sections at once (default: one per core; 0: serial here).",
        ),
    ] = None,
    fmt: Format = "png",
    dpi: Dpi = 150,
    quiet: Quiet = False,
    debug: Debug = False,
) -> None:
    """Re-run the papers' numerical examples; write figures, data, report.md and index.html.

    Exit status: 0 when it ran (failed checks are in the report), 1 when a section raised,
    2 on bad input, 130 if interrupted (the worker processes are stopped).
    """

    def go():
        from rotaflex.core import plotting
        from rotaflex.core.io import check_out_dir, claim_out_dir
        from rotaflex.reproduce import reproduce as run_reproduce

        if target not in REPRODUCE and target != "all":
            raise InputError("target", target, "one of " + ", ".join([*REPRODUCE, "all"]))
        if jobs is not None and not 0 <= jobs <= MAX_JOBS:
            raise InputError("--jobs", jobs, f"an integer from 0 to {MAX_JOBS} (0 = serial in this process)")
        _figure_options(fmt, dpi)
        out_dir = check_out_dir(out, marker=REPORT_MARKERS)
        plotting.configure(fmt=fmt, dpi=dpi)
        names = list(REPRODUCE) if target == "all" else [target]
        t0 = time.perf_counter()
        tty = sys.stderr.isatty()
        say = None if quiet else (lambda m: typer.echo(m, err=True))
        with claim_out_dir(out_dir), _limit_threads():
            report = run_reproduce(names, out_dir, fast=fast, progress=say or False, bars=not quiet and tty, jobs=jobs)
        typer.echo(
            f"{report['passed']}/{report['checks']} checks passed in "
            f"{time.perf_counter() - t0:.1f} s; report: {out_dir / 'report.md'}"
        )
        if report["passed"] < report["checks"]:
            typer.echo("some checks did not pass: see the report", err=True)

    guarded(go, debug)


@app.command()
def examples(
    pattern: Annotated[
        str, typer.Argument(help="Glob over the shipped examples, e.g. 'system/*' or 'gear/4000rpm.toml'.")
    ] = "*",
    to: Annotated[
        Path | None, typer.Option("--to", help="Copy the matching examples into this folder (never overwrites).")
    ] = None,
    debug: Debug = False,
) -> None:
    """List the example cases shipped with rotaflex, or copy them out to run and edit."""

    def go():
        from rotaflex.core.examples import copy_examples, examples_dir, match_examples

        if to is None:
            names = match_examples(pattern)
            typer.echo(f"# in {examples_dir()}")
            typer.echo("\n".join(names))
            return
        written = copy_examples(to, pattern)
        typer.echo(f"copied {len(written)} example file(s) to {to}")

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
            help="KEY=START:STOP:N or KEY=v1,v2,...; KEY is any dotted config key. Repeat for a grid.",
        ),
    ],
    jobs: Annotated[
        int | None, typer.Option("--jobs", "-j", help="Local worker processes (default: one per core; 0: serial here).")
    ] = None,
    scheduler: Annotated[
        str | None,
        typer.Option(
            "--scheduler",
            help="Dask scheduler address tcp://host:port (a TRUSTED cluster: results are unpickled), or dask-local.",
        ),
    ] = None,
    retries: Annotated[int, typer.Option("--retries", help="Re-runs of a case whose worker died.", min=0)] = 2,
    continuation: Annotated[
        str | None,
        typer.Option(
            "--continuation",
            help="A swept numeric KEY run in order, up then down, each case from the previous one's final "
            "state (verbs that accept it, e.g. gear steady); adds the direction dimension.",
        ),
    ] = None,
    split_down: Annotated[
        bool,
        typer.Option(
            "--split-down",
            help="With --continuation: start the down half from its own run at the highest value, in "
            "parallel with the up half (right only if the response there has one branch; docs/sweep.md).",
        ),
    ] = False,
    no_figures: NoFigures = False,
    fmt: Format = "png",
    dpi: Dpi = 150,
    quiet: Quiet = False,
    debug: Debug = False,
) -> None:
    """Run CONFIG for every combination of the --vary values; resume in DIR if re-run.

    A top-level verb = "..." key in CONFIG sweeps that verb of the domain (default simulate).
    Writes DIR/cases/<id>/ per case, DIR/sweep.nc (swept keys as dimensions), DIR/summary.csv,
    DIR/figures/. Every case is validated before any runs. Exit status 1 if any case failed,
    130 if interrupted.
    """

    def go():
        from contextlib import nullcontext

        from tqdm.contrib.logging import logging_redirect_tqdm

        from rotaflex.core import plotting
        from rotaflex.core.config import load_toml
        from rotaflex.core.io import check_out_dir, claim_out_dir
        from rotaflex.core.provenance import provenance
        from rotaflex.sweep import plan_study, sweep_config
        from rotaflex.sweep.backends import executor_for, mp_temp_dir

        _figure_options(fmt, dpi)
        if jobs is not None and not 0 <= jobs <= MAX_JOBS:
            raise InputError("--jobs", jobs, f"an integer from 0 to {MAX_JOBS} (0 = serial in this process)")
        out_dir = check_out_dir(out, marker=SWEEP_MARKERS, inputs=(config,))
        cfg = load_toml(config)
        plan_study(cfg, vary, continuation, split_down)  # validate every case before starting workers
        plotting.configure(fmt=fmt, dpi=dpi)
        if quiet:
            shown: Any = False
        elif sys.stderr.isatty():
            shown = True
        else:  # a log: one line per finished case instead of bar redraws

            def shown(rec, done, total):
                typer.echo(f"case {done}/{total} {rec.id}: {rec.status}", err=True)

        with (
            claim_out_dir(out_dir),
            # a sweep killed with SIGKILL leaves no pymp-* temporary directory; only in a process of its own:
            # the directory is process-wide and outlives this command (its fork server listens there)
            nullcontext(mp_temp_dir(out_dir) if _standalone else None),
            executor_for(jobs, scheduler) as executor,
            logging_redirect_tqdm(),
            _limit_threads(),
        ):
            try:
                res = sweep_config(
                    cfg,
                    vary,
                    out_dir,
                    executor,
                    progress=shown,
                    max_retries=retries,
                    continuation=continuation,
                    split_down=split_down,
                    figures=not no_figures,
                    attrs=provenance(config),
                )
            except KeyboardInterrupt:
                _quiet_shutdown()
                term = _received == signal.SIGTERM
                typer.echo(
                    f"{'terminated (SIGTERM)' if term else 'interrupted'}: finished cases are in "
                    f"{out_dir / 'cases'}; run the same command again to compute only the missing ones",
                    err=True,
                )
                raise typer.Exit(SIGNAL_EXIT[signal.SIGTERM if term else signal.SIGINT]) from None
        typer.echo(f"{res.summary_text()} -> {out_dir / 'sweep.nc'}")
        for rec in res.failed[:10]:
            line = f"  failed {rec.id} {rec.params}: {rec.status} {rec.error}"
            typer.echo(line.rstrip(), err=True)
        if res.n_failed:
            typer.echo(f"{res.n_failed} of {res.n_cases} cases failed: see {out_dir / 'summary.csv'}", err=True)
            raise typer.Exit(1)

    guarded(go, debug)


#: verbs with a --speed option: the config key it replaces (rpm, one or several)
SPEED_OPTION = {("rotor", "modal"): "modal.speed_rpm"}


def _command(run: Callable[..., None], speed_key: str | None) -> Callable[..., None]:
    """The typer command of ``run``: the options of every ``rotaflex <domain> <verb>``, written once
    (typer reads them from the signature), with ``--speed`` where the verb has a speed key."""
    P = inspect.Parameter

    def opt(name: str, annotation: Any, default: Any = P.empty) -> inspect.Parameter:
        return P(name, P.POSITIONAL_OR_KEYWORD, default=default, annotation=annotation)

    params = [opt("config", Annotated[Path, typer.Argument(help="TOML case file.")]), opt("out", Out)]
    if speed_key is not None:
        help_ = f"Spin speed [rpm] replacing {speed_key}; repeat for several speeds."
        params.append(opt("speed", Annotated[list[float] | None, typer.Option("--speed", help=help_)], None))
    params += [
        opt("no_figures", NoFigures, False),
        opt("fmt", Format, "png"),
        opt("dpi", Dpi, 150),
        opt("quiet", Quiet, False),
        opt("debug", Debug, False),
    ]

    def command(**options: Any) -> None:
        run(**options)

    command.__signature__ = inspect.Signature(params)
    command.__doc__ = run.__doc__
    return command


def _run_command(domain: str, verb: str) -> Callable[..., None]:
    def run(
        config: Path,
        out: str,
        no_figures: bool = False,
        fmt: str = "png",
        dpi: int = 150,
        quiet: bool = False,
        debug: bool = False,
        speed: list[float] | None = None,
    ) -> None:
        def go():
            blas_threads_at_load()  # first: before anything below imports numpy
            with collection_paused() as resume:
                work(resume)

        def work(resume: Callable[[], None]) -> None:
            from rotaflex.core import plotting
            from rotaflex.core.config import load_toml
            from rotaflex.core.domains import command, resolve_paths, split_config, validate
            from rotaflex.core.io import check_out_dir, claim_out_dir
            from rotaflex.core.provenance import provenance
            from rotaflex.core.report import CompileTimer

            defer_unused_numpy()
            _figure_options(fmt, dpi)
            out_dir = check_out_dir(out, marker=RESULT_MARKERS, inputs=(config,))
            _, body = split_config(load_toml(config), domain=domain, verb=verb)
            body = resolve_paths(domain, body, Path(config).parent)  # paths inside: from the file
            if speed:  # --speed replaces the verb's speed key (one value: a number, as typed in TOML)
                from rotaflex.core.config import set_dotted

                body = set_dotted(body, SPEED_OPTION[(domain, verb)], speed[0] if len(speed) == 1 else list(speed))
            if verb == "simulate":  # other verbs validate their own schema first thing
                validate(domain, body)
            say = None if quiet else (lambda m: typer.echo(m, err=True))
            with claim_out_dir(out_dir):
                with _limit_threads(), CompileTimer(say) as compiling, numeric_warnings() as caught:
                    fn = command(domain, verb)  # the verb's modules: imported with collection paused
                    resume()  # the verb's own objects are collected as usual
                    # bars only on a terminal (a log would get every redraw)
                    result = fn(body, progress=not quiet)  # bar or log lines
                flag_numeric_warnings(result, caught)
                if say and compiling.seconds >= 0.5:
                    say(f"numba kernels compiled in {compiling.seconds:.1f} s (first run only; cached afterwards)")
                # through the dataset and configure(): domain results may override save(out, figures=)
                result.dataset.attrs.update(provenance(config))
                plotting.configure(fmt=fmt, dpi=dpi)
                gc.disable()  # matplotlib's import and the figures: objects kept until the files are written
                paths = result.save(out_dir, figures=not no_figures)
                resume()
            typer.echo(f"{result.status}: {result.message} -> {len(paths)} files in {out_dir}")
            from rotaflex.core.result import completed

            # a finding (e.g. not_periodic) is not a failure; stdout says what was written, stderr why it failed
            if not completed(result.status):
                typer.echo(f"error: {result.status}: {result.message} (result kept in {out_dir})", err=True)
                raise typer.Exit(1)

        guarded(go, debug)

    run.__doc__ = (
        f"Simulate one {domain} case from CONFIG; write result.nc, summary.json, figures."
        if verb == "simulate"
        else f"Run '{verb}' on one {domain} case from CONFIG; write result.nc, summary.json, figures."
    )
    return _command(run, SPEED_OPTION.get((domain, verb)))


def _template_command(domain: str) -> Callable[..., None]:
    verbs = ", ".join(["simulate", *COMMANDS.get(domain, {})])

    # the help names this domain's verbs, so the option is a default value (evaluated here), not
    # an annotation (a string under ``from __future__ import annotations``)
    def template(
        debug: Debug = False,
        verb: str = typer.Option("simulate", "--verb", help=f"The verb whose config to print: {verbs}."),
        out: str | None = typer.Option(None, "--out", "-o", help="Write to this file instead of stdout."),
    ) -> None:
        def go():
            _print_or_write(domain_template(domain, verb), out)

        guarded(go, debug)

    template.__doc__ = f"Print a commented {domain} config with every key, default, unit and allowed range."
    return template


def _listing_command(target: str) -> Callable[..., None]:
    def listing(debug: Debug = False) -> None:
        def go():
            from rotaflex.core.domains import resolve

            typer.echo(resolve(target)(), nl=False)

        guarded(go, debug)

    listing.__doc__ = "Print what is registered (no config): " + target.rpartition(":")[2].replace("_", " ") + "."
    return listing


def domain_template(domain: str, verb: str = "simulate") -> str:
    """The generated TOML template of ``rotaflex <domain> <verb>`` (InputError for an unknown
    verb or a module without ``SCHEMA``)."""
    from rotaflex.core.domains import case_module, command_module, command_target
    from rotaflex.core.schema import template

    command_target(domain, verb, field="--verb")  # an unknown verb is named as the option
    module = case_module(domain) if verb == "simulate" else command_module(domain, verb)
    schema = getattr(module, "SCHEMA", None)
    if schema is None:
        raise InputError("domain", domain, "a domain whose case module exposes SCHEMA (not yet for this one)")
    if verb != "simulate" and schema is getattr(case_module(domain), "SCHEMA", None):
        verb = ""  # the verb reads the domain's own case file
    text = template(schema, domain, verb="" if verb == "simulate" else verb)
    for table, alt in getattr(module, "ALTERNATIVES", {}).items():
        body = template(alt, domain, table=table).split("\n", 4)[-1]  # skip the header lines
        text += "\n# ---- alternatively, a [" + table + "] case (nothing else beside it):\n"
        text += "".join(
            f"# {line}\n" if line and not line.startswith("#") else f"{line}\n" for line in body.split("\n")
        )
    return text


docs_app = typer.Typer(**PLAIN, no_args_is_help=True, help="Generated documentation.")
app.add_typer(docs_app, name="docs")


def config_reference() -> str:
    """The Markdown config reference of every domain that exposes ``SCHEMA``."""
    import importlib

    from rotaflex.core.domains import command_module
    from rotaflex.core.schema import reference_markdown

    schemas = {}
    for domain, modname in CASES.items():
        try:
            module = importlib.import_module(modname)
        except ImportError:  # pragma: no cover - a domain not installed
            continue
        if getattr(module, "SCHEMA", None) is None:
            continue
        roots = [("Top-level tables", "", module.SCHEMA)]
        roots += [(f"`[{t}]` case", t, alt) for t, alt in getattr(module, "ALTERNATIVES", {}).items()]
        by_schema: dict = {}  # verbs with their own schema, grouped (rotor modal, campbell, ...)
        for verb in COMMANDS.get(domain, {}):
            vs = getattr(command_module(domain, verb), "SCHEMA", None)
            if vs is not None and vs is not module.SCHEMA:
                by_schema.setdefault(vs, []).append(verb)
        for vs, verbs in by_schema.items():
            roots.append((f"`rotaflex {domain} {'|'.join(verbs)}`", "", vs))
        schemas[domain] = roots
    return reference_markdown(schemas)


def _print_or_write(text: str, out: str | None) -> None:
    """``text`` to stdout, or to the file ``out`` (checked first, written atomically)."""
    if out is None:
        typer.echo(text, nl=False)
        return
    from rotaflex.core.io import check_out_file, write_text_atomic

    write_text_atomic(check_out_file(out), text)


@docs_app.command("config-reference")
def _config_reference_cmd(
    out: Annotated[str | None, typer.Option("--out", "-o", help="Write to this file instead of stdout.")] = None,
    debug: Debug = False,
) -> None:
    """Print (or write) docs/config-reference.md, generated from the config schemas."""
    guarded(lambda: _print_or_write(config_reference(), out), debug)


for _domain in CASES:
    _sub = typer.Typer(**PLAIN, no_args_is_help=True, help=f"{_domain.capitalize()} cases.")
    _sub.command("simulate")(_run_command(_domain, "simulate"))
    _sub.command("template")(_template_command(_domain))
    for _verb in COMMANDS.get(_domain, {}):
        _sub.command(_verb)(_run_command(_domain, _verb))
    for _verb, _target in LISTINGS.get(_domain, {}).items():
        _sub.command(_verb)(_listing_command(_target))
    app.add_typer(_sub, name=_domain)


def main(argv: list[str] | None = None) -> int:
    """Console-script entry point: usage errors are one line too (no boxed usage text).

    SIGINT and SIGTERM are delivered as an exception at the next safe point (never inside a
    compiled kernel's or h5py's own code) and end with status 130 / 143. From the command
    line (``argv`` None) a failed or interrupted command then leaves with ``os._exit`` once its
    output is flushed: the interpreter's teardown of h5py and numba objects after an
    interrupted or failed write could crash (SIGSEGV) and replace the exit status.
    """
    global _standalone
    _standalone = argv is None
    old = _install_signals()
    try:
        code = _main(argv)
    finally:
        for sig, handler in old.items():
            signal.signal(sig, handler)
        signal.setitimer(signal.ITIMER_REAL, 0)
    if argv is None and code != 0:
        _hard_exit(code)
    sys.exit(code)


def _hard_exit(code: int) -> None:
    """Flush what is buffered, then end the process without interpreter teardown."""
    try:
        # what multiprocessing's exit hook does (pool queues' semaphores unlinked), else its
        # resource tracker warns of leaked semaphores after a stopped sweep
        mp_util = sys.modules.get("multiprocessing.util")
        if mp_util is not None:
            mp_util._exit_function()
        logging = sys.modules.get("logging")
        if logging is not None:
            logging.shutdown()
        sys.stdout.flush()
        sys.stderr.flush()
    except Exception:  # noqa: BLE001, S110 - a closed pipe: nothing more to say
        pass
    os._exit(code)


def _main(argv: list[str] | None) -> int:
    try:  # recent typer vendors click
        from typer._click import exceptions as click
    except ImportError:  # pragma: no cover
        from click import exceptions as click

    try:
        code = app(args=argv, prog_name="rotaflex", standalone_mode=False)
    except click.NoArgsIsHelpError:  # the help text is already printed
        code = 0
    except click.UsageError as exc:
        hint = f" (see '{exc.ctx.command_path} --help')" if exc.ctx else ""
        typer.echo(f"error: {exc.format_message()}{hint}", err=True)
        code = 2
    except click.ClickException as exc:
        typer.echo(f"error: {exc.format_message()}", err=True)
        code = exc.exit_code
    except (typer.Abort, KeyboardInterrupt):  # an interrupt outside a command (while importing)
        code = SIGNAL_EXIT[signal.SIGTERM] if _received == signal.SIGTERM else SIGNAL_EXIT[signal.SIGINT]
        typer.echo("terminated (SIGTERM)" if code == 143 else "interrupted", err=True)
    return code if isinstance(code, int) else 0


if __name__ == "__main__":  # pragma: no cover
    main()
