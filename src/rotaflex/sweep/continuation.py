"""Continuation sweeps: the values of one swept key run in order, each case from the last state.

``rotaflex sweep ... --continuation KEY`` turns the grid into *chains*, one per combination of
the other swept keys. A chain runs the values of ``KEY`` upwards (ascending), then downwards
(descending) starting from the top case's final state, so a response with several branches
(e.g. the jump of a gear mesh losing contact near resonance) follows one branch up and another
down; the hysteresis shows in ``sweep.nc`` along the extra dimension ``direction`` = up/down.

The cases of one chain run one after the other (each needs its predecessor's final state);
different chains run in parallel on the workers. Every case is written as it finishes: its
result files by its worker on a local executor (else by the client), its ``case.json`` marker by
the client after the next case of its chain was submitted (the worker computes meanwhile); a case
whose files cannot be written (e.g. its ``summary()`` raises) is recorded as an error, and as
its successor already started from its state, a re-run recomputes from it on.

``split=True`` (``--split-down``) makes the down half a chain of its own that starts from the
verb's own start at the highest value, so up and down run on two workers at once. Physically
this is the same down branch only when the highest value has a single steady state (e.g. far
above a resonance): both starts settle on that one orbit and the down half then follows the
branch it leads to, the hysteresis included. Measured on the paper pair's 40-speed example
(docs/sweep.md): the down K_v within 9.1e-5 of the whole chain's, the contact-loss fraction
identical. Inside a multi-valued band the cold start may pick the other branch: the default
keeps each chain whole.

Resume: a re-run keeps each chain's longest prefix of finished cases and continues from the
final state saved in the ``result.nc`` of the last one; every case after the first missing or
failed case of a chain is recomputed (its starting state may have changed). A case's identity
(its hash) includes its direction and the value of ``KEY`` of its predecessor, so changing the
list of values recomputes from the first changed position on. A case that fails stops its
chain: the rest of the chain is recorded as failed ("not run") and a re-run retries from there.
"""

from __future__ import annotations

import inspect
import logging
from collections import deque
from collections.abc import Callable, Sequence
from concurrent.futures import FIRST_COMPLETED, wait
from concurrent.futures.process import BrokenProcessPool
from pathlib import Path
from typing import Any

from rotaflex.core.errors import InputError
from rotaflex.sweep._worker import Outcome
from rotaflex.sweep.spec import Case, case_id

log = logging.getLogger("rotaflex.sweep")

#: directions of a continuation chain, in run order
DIRECTIONS = ("up", "down")


def continuable(fn: Callable) -> bool:
    """``fn`` takes the ``initial_state`` keyword of a continuation."""
    try:
        return "initial_state" in inspect.signature(fn).parameters
    except (TypeError, ValueError):  # pragma: no cover - builtins
        return False


def check_continuable(fn: Callable, key: str, domain: str, verb: str) -> None:
    """InputError unless ``fn`` (the function of ``rotaflex <domain> <verb>``) takes the
    ``initial_state`` keyword; names the option as typed and the verbs of the domain that can."""
    if continuable(fn):
        return
    from rotaflex.core.domains import COMMANDS, command

    able = [v for v in COMMANDS.get(domain, {}) if continuable(command(domain, v))]
    fix = f'add verb = "{able[0]}" to the file' if able else f"no {domain} verb can"
    raise InputError(
        "--continuation",
        key,
        f"a sweep of a verb that starts from the previous case's state ({domain} {verb} does not; {fix})",
    )


def chain_cases(cases: Sequence[Case], key: str, split: bool = False) -> tuple[list[Case], list[list[str]]]:
    """The cases of a continuation along ``key`` and the chains of case ids in run order.

    Parameters
    ----------
    cases : list of Case
        Grid cases (:func:`~rotaflex.sweep.spec.grid_cases`) whose params include ``key``.
    key : str
        The continued config key: numeric values, at least two.
    split : bool
        Two chains per combination: ``up`` from the verb's own start at the lowest value, and
        ``down`` from the verb's own start at the highest value (instead of from the top ``up``
        case's state), so the halves run on two workers at once. Right only where the response
        at the highest value has one branch (see the module notes).

    Returns
    -------
    cases : list of Case
        Every grid case twice, with ``direction`` = ``"up"`` and ``"down"`` as a last parameter;
        data ``{"config": ..., "continuation": {"key", "direction", "after"}}`` (``after``: the
        predecessor's value of ``key``, None for a chain's first case).
    chains : list of list of str
        Per combination of the other swept keys, the case ids: ``key`` ascending, then
        descending (with ``split``: the ascending and the descending ones as two chains).
    """
    if not cases or key not in cases[0].params:
        swept = ", ".join(cases[0].params) if cases else "none"
        raise InputError("--continuation", key, f"one of the --vary keys ({swept})")
    values = [c.params[key] for c in cases]
    if any(isinstance(v, bool) or not isinstance(v, (int, float)) for v in values):
        raise InputError("--continuation", key, "a key swept over numbers")
    groups: dict[str, list[Case]] = {}
    for c in cases:
        rest = repr([(k, v) for k, v in c.params.items() if k != key])
        groups.setdefault(rest, []).append(c)
    if len(next(iter(groups.values()))) < 2:
        raise InputError("--continuation", key, "a key swept over at least two values")
    out: list[Case] = []
    chains: list[list[str]] = []
    for group in groups.values():
        up = sorted(group, key=lambda c: c.params[key])
        legs = {"up": up, "down": up[::-1]}
        chain: list[str] = []
        prev = None
        for d in DIRECTIONS:
            if split and chain:
                chains.append(chain)
                chain, prev = [], None
            for c in legs[d]:
                data = {"config": c.data, "continuation": {"key": key, "direction": d, "after": prev}}
                case = Case(case_id(len(out), data), {**c.params, "direction": d}, data)
                out.append(case)
                chain.append(case.id)
                prev = c.params[key]
        chains.append(chain)
    # grid order for sweep.nc: all "up" cases, then all "down" ones
    order = {c.id: (DIRECTIONS.index(c.params["direction"]), i) for i, c in enumerate(out)}
    return sorted(out, key=lambda c: order[c.id]), chains


def run_link(target: str, data: dict, initial_state: Any = None) -> Any:
    """Worker side of one chain case: the verb on ``data["config"]`` from ``initial_state``."""
    from rotaflex.sweep._worker import run_target

    return run_target(target, data["config"], initial_state=initial_state)


def saved_state(case_dir: Path) -> Any:
    """The ``final_state()`` of a finished case from its ``result.nc`` (None if unreadable)."""
    from rotaflex.core.result import load_result

    try:
        fs = getattr(load_result(case_dir / "result.nc"), "final_state", None)
        return fs() if fs is not None else None
    except Exception as exc:  # noqa: BLE001 - an unreadable state restarts the chain
        log.warning("cannot read the final state of %s (%s): restarting its chain", case_dir.name, exc)
        return None


def drive_chains(
    backend,
    case_fn: Callable,
    chains: list[deque[Case]],
    states: list[Any],
    finish: Callable[[Case, Outcome, int], None],
    max_retries: int,
) -> None:
    """Run the chains: the next case of a chain is submitted when its predecessor finished.

    ``states[i]``: starting state of chain ``i``'s first case (None: the verb's own start).
    A worker death re-runs the case in flight (up to ``max_retries`` times per case; with a
    local pool every case in flight when it broke counts one death).
    """
    ready = deque(i for i, ch in enumerate(chains) if ch)
    inflight: dict[Any, int] = {}
    # finished cases whose files are still to be written: written after the next cases of
    # their chains were submitted, so the workers compute while the client writes; with fewer
    # chains than workers, the spare ones (``backend.writer``) write too, one case each at a time
    unwritten: list[tuple[Case, Outcome, int]] = []
    writing: dict[Any, tuple[Case, Outcome, int]] = {}
    attempts: dict[str, int] = {}
    deaths: dict[str, int] = {}

    def stop_chain(i: int, why: str) -> None:
        for case in chains[i]:
            finish(case, Outcome(None, f"ContinuationStopped: not run, {why}", "", float("nan"), ""), 0)
        chains[i].clear()

    def died(i: int, exc: BaseException) -> None:
        case = chains[i][0]
        deaths[case.id] = deaths.get(case.id, 0) + 1
        if deaths[case.id] > max_retries:
            err = f"WorkerDied: the worker died while running this case {deaths[case.id]} time(s) ({exc!r})"
            finish(case, Outcome(None, err, "", float("nan"), ""), attempts[case.id])
            chains[i].popleft()
            stop_chain(i, f"case {case.id} before it in the continuation failed")
        else:
            log.warning("case %s: worker died (%s); retrying", case.id, type(exc).__name__)
            ready.append(i)

    def collect(fut) -> bool:
        """Handle one finished future; True if the local pool broke."""
        if fut in writing:
            case, outcome, n = writing.pop(fut)
            try:
                written = fut.result()
            except Exception:  # noqa: BLE001 - the writer pool broke: the client writes from now on
                log.warning("the process writing case %s died; writing the cases here", case.id)
                backend.drop_writer()
                finish(case, outcome, n)
                return False
            finish(case, written, n)
            return False
        i = inflight.pop(fut)
        case = chains[i][0]
        try:
            outcome = fut.result()
        except Exception as exc:  # noqa: BLE001 - infrastructure: pool broken, KilledWorker
            died(i, exc)
            return isinstance(exc, BrokenProcessPool)
        state = None
        if not outcome.error:
            fs = getattr(outcome.result, "final_state", None)
            state = fs() if fs is not None else None
            if state is None:
                outcome.error = "TypeError: the result has no final_state() to continue from"
        chains[i].popleft()
        if outcome.error:
            finish(case, outcome, attempts[case.id])
            stop_chain(i, f"case {case.id} before it in the continuation failed")
        else:
            unwritten.append((case, outcome, attempts[case.id]))
            if chains[i]:
                states[i] = state
                ready.append(i)
        return False

    def write_finished(here: bool = False) -> None:
        """Write the finished cases (``here``: in this process, e.g. once the pool broke)."""
        while unwritten:
            writer = getattr(backend, "writer", None)
            if writer is not None and not here and len(writing) < writer._max_workers:
                try:
                    writing[backend.submit_write(unwritten[0][0], unwritten[0][1])] = unwritten[0]
                    unwritten.pop(0)
                    continue
                except BrokenProcessPool:
                    backend.drop_writer()
            finish(*unwritten.pop(0))

    while ready or inflight or writing:
        broken = False
        while ready and len(inflight) < backend.window:
            i = ready.popleft()
            case = chains[i][0]
            try:
                fut = backend.submit(case_fn, case, initial_state=states[i])
            except BrokenProcessPool:
                ready.appendleft(i)
                broken = True
                break
            attempts[case.id] = attempts.get(case.id, 0) + 1
            inflight[fut] = i
        if not broken:
            write_finished()
        if inflight or writing:
            done, _ = wait([*inflight, *writing], return_when=FIRST_COMPLETED)
            for fut in done:
                broken |= collect(fut)
        if broken:  # every other future of the broken pool fails too: collect, then rebuild
            rest, _ = wait([*inflight, *writing])
            for fut in rest:
                collect(fut)
            write_finished(here=True)
            backend.rebuild()
    write_finished(here=True)
    if writing:  # the writer's last cases
        for fut in wait(list(writing))[0]:
            collect(fut)
