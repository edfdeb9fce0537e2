"""Progress of the rotor FE verbs that sweep speeds, stiffnesses or time (issue 22).

With ``progress=True`` and stderr not a terminal, each verb writes one line per 10 % of its work
(:class:`rotaflex.core.progress.Progress`); without it nothing; and reporting progress does not
change a single number of the result.
"""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

import numpy as np
import pytest

from rotaflex.rotor.fe.case import run_campbell, run_transient, run_ucs, run_unbalance

EXAMPLE = Path(__file__).resolve().parents[3] / "examples" / "rotor" / "fe_friswell_5_9_1.toml"


def _config(**tables) -> dict:
    cfg = tomllib.loads(EXAMPLE.read_text())
    for name, changes in tables.items():
        cfg[name] = {**cfg[name], **changes}
    return cfg


#: verb, runner, its progress name, the example's table shortened to a fast run
CASES = [
    ("campbell", run_campbell, {"n_speeds": 20}),
    ("ucs", run_ucs, {"n_points": 30}),
    ("unbalance", run_unbalance, {"n_speeds": 120}),
    ("transient", run_transient, {"duration": 0.05, "n_output": 51, "method": "modal"}),
    ("transient", run_transient, {"duration": 0.02, "n_output": 41, "method": "direct"}),
]


def _percentages(text: str, desc: str) -> list[int]:
    return [int(p) for p in re.findall(rf"^{desc}: (\d+) % \(", text, flags=re.M)]


@pytest.mark.parametrize(("verb", "run", "table"), CASES, ids=[f"{c[0]}-{c[2].get('method', '')}" for c in CASES])
def test_progress_lines_at_every_tenth_when_not_on_a_terminal(capsys, verb, run, table):
    cfg = _config(**{verb: table})
    quiet = run(cfg, progress=False)
    assert capsys.readouterr().err == ""  # no progress asked: nothing written
    shown = run(cfg, progress=True)
    err = capsys.readouterr().err
    pct = _percentages(err, verb)
    assert "\r" not in err  # lines, not a bar (stderr is captured: not a terminal)
    # every 10 % step is announced, in order, and the run ends at 100 %
    assert {p // 10 for p in pct} >= set(range(1, 11))
    assert pct == sorted(pct) and pct[-1] == 100
    assert len(pct) <= 12  # one line per tenth (plus at most a time-based one or two), not per step
    # the numbers do not depend on whether progress was reported
    for name, var in quiet.dataset.data_vars.items():
        if np.issubdtype(var.dtype, np.number):
            np.testing.assert_array_equal(shown.dataset[name].values, var.values, err_msg=name)


def test_direct_critical_speeds_report_each_crossing(capsys):
    res = run_campbell(_config(campbell={"n_speeds": 20, "critical_solve": "direct"}), progress=True)
    n = len([k for k in res.summary() if k.startswith("critical_") and k.endswith("_rpm")])
    lines = re.findall(r"^critical speeds: (\d+) % \((\d+)/(\d+) crossing\)", capsys.readouterr().err, flags=re.M)
    assert n >= 2 and lines[-1] == ("100", str(n), str(n))  # one root search per crossing listed
