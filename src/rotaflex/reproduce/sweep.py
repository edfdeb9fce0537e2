"""Reproduce target ``sweep``: a small parameter study per registered domain, with checks.

For every domain in :data:`rotaflex.core.domains.CASES` that has a sweep example (a
``sweep_example(fast) -> (config, {key: values})`` function in its case module, or an entry of
:data:`EXAMPLES` here) the same sweep is run twice into ``out_dir/sweep/<domain>/``: serially in
this process and on a local process pool, then once more on the pool to test resume. Checks:
pool results identical to serial ones, nothing recomputed on resume, no failed case, and the
domain's physics check against a closed form where one exists (rotor: the linear peak tilt of a
free response vs spin).
"""

from __future__ import annotations

import functools
import importlib
import json
import logging
import time
from pathlib import Path
from typing import Any

import numpy as np

from rotaflex.core.report import Check, FigureEntry, Section
from rotaflex.core.report import step as report_step

log = logging.getLogger("rotaflex.sweep")


def _rotor_example(fast: bool) -> tuple[dict[str, Any], dict[str, list[Any]]]:
    config = {
        "disk": {"mass": 1.0, "polar_inertia": 2.0, "diametral_inertia": 1.0},
        "support": {"stiffness": 1.0e4, "tilt_stiffness": 100.0},
        "motion": {"spin_speed": 10.0, "initial_tilt_rate": [0.05, 0.05]},
        "solver": {"t_end": 1.0 if fast else 2.0, "n_output": 801},
    }
    n = 7 if fast else 25
    return config, {"motion.spin_speed": [float(v) for v in np.linspace(0.0, 60.0, n)]}


def _gear_example(fast: bool) -> tuple[dict[str, Any], dict[str, list[Any]]]:
    from rotaflex.gear.pair import paper

    config = {
        "operation": {"speed_rpm": [paper.SPEED_RPM] * 2, "torque": paper.TORQUE},
        "mesh": {"preset": "coarse"},
        "output": {"every": 50},
    }
    # the cost of a case goes as 1 / speed (the span is the contact angle): fast mode runs three
    # speeds from 15,000 rpm (10,000 rpm alone took as long as 15,000 and 20,000 together)
    speeds = [15000.0, 17500.0, 20000.0] if fast else [float(v) for v in np.linspace(1000.0, 20000.0, 20)]
    return config, {"operation.speed_rpm": speeds}


def _floating_example(fast: bool) -> tuple[dict[str, Any], dict[str, list[Any]]]:
    config = {
        "body": {
            "type": "beam",
            "beam": {"length": 4.0, "rho_a": 2.0, "ei": 40.0, "n_modes": 4, "support": "free-free"},
        },
        "loads": [
            {
                "kind": "torque",
                "vector": [0.0, 0.0, 5.0],
                "point": [0.0, 0.0, 0.0],
                "frame": "body",
                "profile": "bang-bang",
                "start": 0.0,
                "duration": 4.0,
            }
        ],
        "solver": {"method": "full", "t_end": 10.0, "dt_out": 0.02},
        "outputs": {"tip": [2.0, 0.0, 0.0]},
    }
    n = 4 if fast else 13
    return config, {"loads[0].duration": [float(v) for v in np.linspace(2.0, 8.0, n)]}


#: the example files this section reads (the geared-rotor sweep hook reads the example gearbox)
NEEDS = ("system/gearbox.toml",)

#: domain -> built-in sweep example (used when the domain's case module has no ``sweep_example``)
EXAMPLES = {"rotor": _rotor_example, "gear": _gear_example, "floating": _floating_example}

_CAPTIONS = {
    "floating": (
        "Floating beam slew-time sweep (not in the paper)",
        "Peak elastic tip deflection of a free-free beam slewed by a bang-bang torque "
        "against the slew (torque) duration.",
    ),
    "gear": (
        "Gear speed sweep (not in the paper)",
        "Dynamic factor (peak contact force / static tau / r_b) against the initial speed of "
        "both gears, coarse tooth mesh, single-tooth contact span; mesh-frequency harmonics "
        "meeting the estimated torsional natural frequency marked.",
    ),
    "rotor": (
        "Rotor spin sweep (not in the paper)",
        "Whirl frequencies of the disk on a tilt spring and the peak tilt of a free response "
        "against spin, each spin speed one case of the sweep.",
    ),
}


def _example(domain: str, fast: bool):
    from rotaflex.core.domains import CASES

    try:
        module = importlib.import_module(CASES[domain])
    except ImportError as exc:
        return None, f"domain {domain!r} is registered but not importable ({exc})"
    hook = getattr(module, "sweep_example", None) or EXAMPLES.get(domain)
    if hook is None:
        return None, f"domain {domain!r} has no sweep example yet (no sweep_example hook)"
    return hook(fast), ""


def _is_timing(name: str) -> bool:
    """Summary scalars that measure run time (not expected to repeat): wall_time, time_per_step."""
    return "wall" in name or "time_per" in name or "cpu_time" in name


def _max_diff(reference, records) -> float:
    """Largest absolute difference of numeric summary scalars between the same cases."""
    by_id = {r.id: r for r in records}
    worst = 0.0
    for ref in reference:
        other = by_id[ref.id]
        if ref.status != other.status:
            return float("inf")
        for name, item in ref.summary.items():
            v, w = item.get("value"), other.summary.get(name, {}).get("value")
            if _is_timing(name) or not isinstance(v, (int, float)) or isinstance(v, bool):
                continue
            if not isinstance(w, (int, float)):
                return float("inf")
            if np.isnan(v) and np.isnan(w):
                continue
            worst = max(worst, abs(float(v) - float(w)))
    return worst


def _rotor_checks(ds) -> list[Check]:
    from rotaflex.rotor.sweep_figures import rotor_reference

    ref = rotor_reference(ds)
    if ref is None or ref["peak_tilt"] is None:
        return []
    sim = np.asarray(ds["max_tilt_angle"].values, float)
    rel = float(np.max(np.abs(sim - ref["peak_tilt"]) / ref["peak_tilt"]))
    return [
        Check(
            "rotor: peak tilt vs spin, simulated vs linear closed form "
            "2 Id r / sqrt((Ip W)^2 + 4 Id k) "
            "(max relative difference over the sweep)",
            rel,
            "",
            "< 1e-2",
            rel < 1e-2,
            "Independent of the rotor code: the free whirl of a disk on a tilt spring; "
            "the residual "
            "comes from output sampling of the peak and the (small) nonlinearity.",
        )
    ]


def _first_figure(result, domain: str) -> list[Path]:
    """``--fast``: draw only the figure the checks go with (the domain's own figure, else the
    first generic panel); the generic panels of every summary scalar are drawn by the full run."""
    from rotaflex.core.plotting import pyplot, save_figure
    from rotaflex.sweep.figures import sweep_figures

    if not any(r.ok for r in result.records):
        return []
    figs = sweep_figures(result.dataset, domain)
    stem = next((s for s in figs if "summary_vs" not in s and "diagnostics_vs" not in s), None)
    stem = stem or next(iter(figs), None)
    for other, fig in figs.items():
        if other != stem:
            pyplot().close(fig)
    return [save_figure(figs[stem], result.out_dir / "figures" / f"{stem}.png")] if stem else []


def _run_domain(domain: str, example, out_dir: Path, fast: bool, progress: bool):
    from rotaflex.reproduce import section_processes
    from rotaflex.sweep import plan, run_sweep
    from rotaflex.sweep._worker import run_module_case

    config, vary = example
    _, module, cases = plan({"domain": domain, **config}, vary)
    case_fn = functools.partial(run_module_case, module)
    attrs = {"base_config": json.dumps(config, sort_keys=True)}
    root = out_dir / "sweep" / domain
    report_step(f"{domain}: {len(cases)} cases")

    def tick(rec, done, total):
        report_step(f"{domain} case {done}/{total}: {rec.status}")

    from rotaflex.sweep.study import _schema_units

    # units of the swept keys from the schema, so the figures' axes say them (as `rotaflex sweep`)
    kw = dict(domain=domain, attrs=attrs, progress=progress if progress else tick, units=_schema_units(module))
    # serial reference on at most 4 cases spread over the sweep (the pool runs them all); fast
    # mode: the last case only (of the gear speed sweep the cheapest; one case already tells a
    # difference between the pool and this process)
    if fast:
        subset = cases[-1:]
    else:
        subset = cases[:: max(1, len(cases) // 4)][:4]
    t0 = time.perf_counter()
    serial = run_sweep(case_fn, subset, "serial", out_dir=root / "serial", figures=False, **kw)
    t_serial = time.perf_counter() - t0
    # two processes show the pool at work; inside a worker of a parallel `reproduce` only one
    # (section_processes), since the other workers already keep the other cores busy and two
    # more processes would slow every section down (the pool is still a separate process, so
    # the bit-identity check against this process keeps its meaning)
    workers = min(2, section_processes())
    t0 = time.perf_counter()
    pool = run_sweep(case_fn, cases, workers, out_dir=root / "pool", figures=not fast, **kw)
    if fast:
        pool.figures = _first_figure(pool, domain)
    t_pool = time.perf_counter() - t0
    again = run_sweep(case_fn, cases, workers, out_dir=root / "pool", figures=False, **kw)
    diff = _max_diff(serial.records, pool.records)
    checks = [
        Check(
            f"{domain}: failed cases",
            pool.n_failed,
            "",
            "== 0",
            pool.n_failed == 0,
            f"{pool.n_cases} cases on {workers} local process{'es' if workers > 1 else ''}",
        ),
        Check(
            f"{domain}: process pool vs serial ({len(subset)} case{'s' if len(subset) > 1 else ''}), "
            "max abs difference of summary scalars",
            diff,
            "",
            "== 0",
            diff == 0.0,
            "same code, same inputs: results must be bit-identical (run-time measurements such as "
            "wall_time and time_per_step excluded)",
        ),
        Check(
            f"{domain}: cases recomputed when the finished sweep is run again",
            again.n_computed,
            "",
            "== 0",
            again.n_computed == 0,
            "resume reads DIR/cases/<id>/case.json markers",
        ),
    ]
    if domain == "rotor":
        checks += _rotor_checks(pool.dataset)
    rel = lambda p: str(Path(p).relative_to(out_dir))  # noqa: E731
    label, caption = _CAPTIONS.get(domain, (f"{domain} sweep", "Summary scalars vs the swept parameter."))
    first = next((p for p in pool.figures if "summary_vs" not in p.name), None) or (
        pool.figures[0] if pool.figures else None
    )
    desc = (
        f"{pool.n_cases} cases in {t_pool:.1f} s on {workers} process{'es' if workers > 1 else ''} (includes worker "
        f"start-up; {len(subset)} of them serially in {t_serial:.1f} s); swept: "
        f"{', '.join(vary)}. Per-case results in "
        f"`{rel(root / 'pool' / 'cases')}`, table `{rel(root / 'pool' / 'summary.csv')}`."
    )
    figures = []
    if first is not None:
        figures.append(FigureEntry(label, caption, rel(first), rel(root / "pool" / "sweep.nc"), desc, checks))
        for p in pool.figures:
            if p != first:
                figures.append(
                    FigureEntry(
                        f"{domain} sweep: {p.stem}",
                        "Generic panels: every summary scalar vs the swept parameter.",
                        rel(p),
                        rel(root / "pool" / "sweep.nc"),
                    )
                )
    return figures, ([] if figures else checks)


def run(out_dir: Path, *, fast: bool = False, progress: bool = False) -> Section:
    """Run a small sweep of every registered domain that has a sweep example."""
    from rotaflex.core.domains import CASES

    out_dir = Path(out_dir)
    section = Section(
        "Parameter sweeps",
        intro=(
            "Each registered domain's example swept over one parameter with `rotaflex.sweep`: "
            "once serially, once on local worker processes, and once more to check that a "
            "finished sweep is reused rather than recomputed. The combined data set has the "
            "swept parameter as its dimension."
        ),
    )
    if fast:
        section.notes.append(
            "Fast mode: fewer cases per sweep, one of them also run serially, and only each "
            "domain's own figure (the generic panels of every summary scalar come with the full run)."
        )
    for domain in CASES:
        example, why = _example(domain, fast)
        if example is None:
            section.notes.append(why)
            continue
        figures, checks = _run_domain(domain, example, out_dir, fast, progress)
        section.figures += figures
        section.checks += checks
    return section
