"""Sections run in worker processes give the report of a serial run, in the requested order.

The sections here are small modules written for the test (a partial sum of the alternating
harmonic series, checked against ln 2 with the alternating-series error bound), so that the
pool, the progress queue and the error path are exercised in about a second.
"""

import json
import math
import os
import subprocess
import sys

import pytest

from rotaflex.core.domains import REPRODUCE
from rotaflex.core.errors import InputError
from rotaflex.reproduce import MEASURED_FAST_S, estimate, reproduce, schedule, workers_for

SECTION = """
import math
import os

from rotaflex.core.errors import InputError
from rotaflex.core.report import Check, Section, step
from rotaflex.reproduce import section_processes

N = {n}


def run(out_dir, *, fast=False, progress=False):
    step(f"summing {{N}} terms in process {{os.getpid()}}; pools of {{section_processes()}}")
    if N < 0:
        raise InputError("stub.n", N, "a positive number of terms")
    s = math.fsum((-1) ** (k + 1) / k for k in range(1, N + 1))
    err = abs(s - math.log(2))
    check = Check(f"|S_N - ln 2|, N = {{N}}", err, "", "<= 1/(N+1)", err <= 1 / (N + 1), "alternating series")
    return Section("{title}", checks=[check])
"""


@pytest.fixture
def sections(tmp_path, monkeypatch):
    """Register stub sections alpha, beta, gamma (and broken); gamma is expected longest."""
    mods = tmp_path / "mods"
    mods.mkdir()
    for name, n in (("alpha", 10), ("beta", 1000), ("gamma", 100), ("broken", -1)):
        (mods / f"_stub_section_{name}.py").write_text(SECTION.format(n=n, title=f"Stub {name}"))
        monkeypatch.setitem(REPRODUCE, name, f"_stub_section_{name}")
    # the workers import the stubs by name: they start with this process's sys.path
    monkeypatch.syspath_prepend(str(mods))
    monkeypatch.setitem(MEASURED_FAST_S, "gamma", 50.0)  # queued first, reported last
    return tmp_path


def _run(tmp_path, names, jobs, label):
    lines = []
    out = tmp_path / label
    report = reproduce(names, out, fast=True, progress=lines.append, jobs=jobs)
    checks = json.loads((out / "checks.json").read_text())
    return report, checks, lines


def test_parallel_gives_the_serial_checks_in_the_requested_order(sections):
    names = ["alpha", "beta", "gamma"]
    assert schedule(names, True, 2) == [["gamma"], ["alpha", "beta"]]
    serial, serial_checks, serial_lines = _run(sections, names, 0, "serial")
    parallel, parallel_checks, lines = _run(sections, names, 2, "parallel")
    assert parallel["checks"] == serial["checks"] == 3 and parallel["passed"] == 3
    assert parallel_checks == serial_checks
    assert list(parallel_checks) == ["Stub alpha", "Stub beta", "Stub gamma"]
    # progress lines came from other processes, each section's step before its done line
    pids = {int(m.split("process ")[1].split(";")[0]) for m in lines if "summing" in m}
    assert len(pids) >= 1 and os.getpid() not in pids
    assert all(f"process {os.getpid()}" in m for m in serial_lines if "summing" in m)
    # a section's own pool (the sweep section's) gets one process in a worker, every core here
    assert all(m.endswith("pools of 1") for m in lines if "summing" in m)
    assert all(m.endswith(f"pools of {os.cpu_count()}") for m in serial_lines if "summing" in m)
    for i, name in enumerate(names, 1):
        mine = [m for m in lines if m.startswith(f"[{i}/3 {name}] ")]
        assert [m.split("] ", 1)[1].split(" ")[0] for m in mine] == ["starting", "summing", "done"]
        assert "(CPU " in mine[-1] and mine[-1].endswith("1/1 checks pass")


def test_a_section_error_in_a_worker_is_raised_as_in_serial(sections):
    with pytest.raises(InputError) as serial:
        reproduce(["alpha", "broken"], sections / "serial", fast=True, jobs=0)
    with pytest.raises(InputError) as parallel:
        reproduce(["alpha", "broken"], sections / "parallel", fast=True, jobs=2)
    assert str(parallel.value) == str(serial.value) == "stub.n = -1 is invalid: expected a positive number of terms"
    assert "raise InputError" in str(parallel.value.__cause__)  # the worker's traceback, for --debug


def test_the_alternating_series_bound_holds():
    # the stubs' criterion, independent of the pool: |S_N - ln 2| <= 1/(N+1)
    for n in (10, 100, 1000):
        s = math.fsum((-1) ** (k + 1) / k for k in range(1, n + 1))
        assert abs(s - math.log(2)) <= 1 / (n + 1)


def test_workers_one_per_core_at_most_one_per_section():
    assert workers_for(None, 5) == min(os.cpu_count() or 1, 5)
    assert workers_for(8, 3) == 3
    assert workers_for(0, 5) == workers_for(1, 5) == 1
    with pytest.raises(InputError, match="jobs = -1"):
        workers_for(-1, 5)


def test_estimate_follows_the_parallel_schedule():
    names = list(MEASURED_FAST_S)
    lanes = schedule(names, True, 2)
    # gear alone takes longer than all the others together, so it has a core to itself
    assert MEASURED_FAST_S["gear"] > sum(MEASURED_FAST_S.values()) - MEASURED_FAST_S["gear"]
    assert lanes[0] == ["gear"] and sorted(lanes[1]) == sorted(set(names) - {"gear"})
    line = estimate(names, True, load=0.0, cores=2, workers=2)
    assert f"about {MEASURED_FAST_S['gear']:.0f} s on 2 cores with --fast" in line
    assert "(2 sections at a time)" in line


def test_cli_refuses_negative_jobs(tmp_path):
    proc = subprocess.run(
        [sys.executable, "-m", "rotaflex", "reproduce", "all", "--fast", "--jobs", "-1", "--out", tmp_path / "r"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == 2
    assert proc.stderr.strip().splitlines() == [
        "error: --jobs = -1 is invalid: expected an integer from 0 to 1024 (0 = serial in this process)"
    ]
