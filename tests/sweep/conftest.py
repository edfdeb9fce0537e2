import json
import subprocess
import time

import pytest
from sweep_helpers import PY, env_with_src, stop


@pytest.fixture
def selftest_domain(monkeypatch):
    from rotaflex.core import domains

    monkeypatch.setitem(domains.CASES, "selftest", "rotaflex.sweep._selftest_case")


def _scheduler_address(sched_file, proc, timeout=60.0):
    """Address from the scheduler file once it is complete.

    The scheduler creates the file before it has written it, so an empty or half-written
    file is waited out rather than parsed.
    """
    deadline = time.monotonic() + timeout
    while True:
        try:
            return json.loads(sched_file.read_text())["address"]
        except (FileNotFoundError, json.JSONDecodeError, KeyError):
            pass
        if time.monotonic() > deadline or proc.poll() is not None:
            raise RuntimeError("dask scheduler did not start")
        time.sleep(0.2)


@pytest.fixture(scope="module")
def dask_cluster(tmp_path_factory):
    """A real ``dask scheduler`` and two ``dask worker`` processes (nanny, 1 thread), 127.0.0.1."""
    tmp = tmp_path_factory.mktemp("dask")
    sched_file = tmp / "scheduler.json"
    dask = [PY, "-m", "distributed.cli.dask_scheduler"]
    procs = []
    try:
        procs.append(
            subprocess.Popen(
                [
                    *dask,
                    "--host",
                    "127.0.0.1",
                    "--port",
                    "0",
                    "--no-dashboard",
                    "--scheduler-file",
                    str(sched_file),
                ],
                # give up on a task at its first worker death: rotaflex's own retry is tested
                env={**env_with_src(), "DASK_DISTRIBUTED__SCHEDULER__ALLOWED_FAILURES": "0"},
                cwd=tmp,
                stdout=subprocess.DEVNULL,
                stderr=subprocess.DEVNULL,
            )
        )
        address = _scheduler_address(sched_file, procs[0])
        for i in range(2):
            procs.append(
                subprocess.Popen(
                    [
                        PY,
                        "-m",
                        "distributed.cli.dask_worker",
                        address,
                        "--nthreads",
                        "1",
                        "--nworkers",
                        "1",
                        "--host",
                        "127.0.0.1",
                        "--no-dashboard",
                        "--local-directory",
                        str(tmp / f"w{i}"),
                        "--death-timeout",
                        "60",
                    ],
                    env=env_with_src(),
                    cwd=tmp,
                    stdout=subprocess.DEVNULL,
                    stderr=subprocess.DEVNULL,
                )
            )
        from distributed import Client

        with Client(address, timeout=30) as client:
            client.wait_for_workers(2, timeout=60)
        yield address
    finally:
        for p in reversed(procs):
            stop(p)
