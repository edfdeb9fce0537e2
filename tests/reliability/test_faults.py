"""Faults: a kill during saving, a killed sweep client, permissions of written files."""

import json
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from rotaflex.core.result import Result

SRC = str(Path(__file__).resolve().parents[2] / "src")
ENV = {**os.environ, "PYTHONPATH": SRC, "OMP_NUM_THREADS": "1"}


def _result(value: float) -> Result:
    ds = xr.Dataset(
        {"x": ("time", np.full(5, value), {"units": "m"}), "peak": ((), value, {"units": "m"})},
        coords={"time": ("time", np.arange(5.0), {"units": "s"})},
        attrs={"status": "success", "message": "test"},
    )
    return Result(ds)


def _wait_for(pred, timeout=60.0):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if pred():
            return True
        time.sleep(0.05)
    return False


def test_kill_during_saving_keeps_the_previous_directory_complete(tmp_path):
    out = tmp_path / "res"
    _result(1.0).save(out, figures=False)
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    assert set(before) == {"result.nc", "summary.json"}
    # a second save that stalls after result.nc, before summary.json, and is killed there
    script = textwrap.dedent(
        f"""
        import sys, time
        import numpy as np, xarray as xr
        import rotaflex.core.result as r
        real = r.write_json_atomic
        def slow(path, data):
            print("SAVING", flush=True)
            time.sleep(60)
            return real(path, data)
        r.write_json_atomic = slow
        ds = xr.Dataset({{"x": ("time", np.full(5, 2.0), {{"units": "m"}}), "peak": ((), 2.0, {{"units": "m"}})}},
                        coords={{"time": ("time", np.arange(5.0), {{"units": "s"}})}},
                        attrs={{"status": "success", "message": "new"}})
        r.Result(ds).save({str(out)!r}, figures=False)
        """
    )
    proc = subprocess.Popen([sys.executable, "-c", script], env=ENV, stdout=subprocess.PIPE, text=True)
    try:
        assert proc.stdout.readline().strip() == "SAVING"
        tmp_dirs = list(tmp_path.glob(".res.rotaflex-tmp-*"))
        assert tmp_dirs and (tmp_dirs[0] / "result.nc").exists()  # killed mid-set, for real
    finally:
        proc.send_signal(signal.SIGKILL)
        proc.wait()
    after = {p.name: p.read_bytes() for p in out.iterdir()}
    assert after == before  # the previous set, intact and complete, nothing new mixed in
    # the next save cleans the killed save's temporary directory and leaves no .tmp file
    _result(3.0).save(out, figures=False)
    assert json.loads((out / "summary.json").read_text())["peak"]["value"] == 3.0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["res"]
    assert not [p for p in out.iterdir() if ".tmp" in p.name]


def test_failed_save_leaves_the_previous_set(tmp_path):
    out = tmp_path / "res"
    _result(1.0).save(out, figures=False)
    before = {p.name: p.read_bytes() for p in out.iterdir()}

    class Broken(Result):
        def summary(self):
            raise RuntimeError("disk full")

    with pytest.raises(RuntimeError):
        Broken(_result(2.0).dataset).save(out, figures=False)
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["res"]


def test_files_follow_the_umask(tmp_path):
    old = os.umask(0o022)
    try:
        _result(1.0).save(tmp_path / "res", figures=False)
    finally:
        os.umask(old)
    for p in (tmp_path / "res").iterdir():
        assert p.stat().st_mode & 0o777 == 0o644, p
    assert (tmp_path / "res").stat().st_mode & 0o777 == 0o755


def test_provenance_in_saved_result(tmp_path):
    from rotaflex.core.provenance import provenance

    cfg = tmp_path / "c.toml"
    cfg.write_text("x = 1\n")
    _result(1.0).save(tmp_path / "res", figures=False, provenance=provenance(cfg))
    with xr.open_dataset(tmp_path / "res" / "result.nc", engine="h5netcdf") as ds:
        attrs = dict(ds.attrs)
    import hashlib

    assert attrs["input_sha256"] == hashlib.sha256(b"x = 1\n").hexdigest()
    assert attrs["input_file"] == str(cfg) and attrs["rotaflex_version"]
    assert attrs["created_utc"].endswith("Z")


def _children(pid: int) -> set[int]:
    """All descendants of ``pid`` (from /proc)."""
    kids: dict[int, list[int]] = {}
    for d in Path("/proc").iterdir():
        if d.name.isdigit():
            try:
                ppid = int((d / "stat").read_text().rsplit(")", 1)[1].split()[1])
            except (OSError, IndexError, ValueError):
                continue
            kids.setdefault(ppid, []).append(int(d.name))
    out, todo = set(), [pid]
    while todo:
        for c in kids.get(todo.pop(), []):
            out.add(c)
            todo.append(c)
    return out


def _alive(pid: int) -> bool:
    try:
        state = (Path("/proc") / str(pid) / "stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"


@pytest.mark.skipif(not Path("/proc").is_dir(), reason="needs /proc")
@pytest.mark.parametrize("scheduler", [None, "dask-local"])  # None: the local process pool
def test_kill_9_of_a_sweep_client_leaves_no_workers(tmp_path, scheduler):
    helper = Path(__file__).resolve().parents[1] / "sweep" / "selftest_cli.py"
    cfg = tmp_path / "s.toml"
    cfg.write_text(f'domain = "selftest"\nx = 0.0\nsleep = 30.0\nstarted_dir = "{tmp_path / "started"}"\n')
    proc = subprocess.Popen(
        [sys.executable, str(helper), "sweep", str(cfg), "--vary", "x=1,2", "-o", str(tmp_path / "s"), "-j", "2", "-q"]
        + ([] if scheduler is None else ["--scheduler", scheduler]),
        env=ENV,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    try:
        assert _wait_for(lambda: len(list((tmp_path / "started").glob("*"))) >= 2, 120)
        workers = _children(proc.pid)
        assert len(workers) >= 3  # fork server (local) or nannies (dask-local) + 2 workers
    finally:
        proc.kill()
        proc.wait()
    # workers poll the client every second; the fork server exits when its pipe closes
    assert _wait_for(lambda: not any(_alive(p) for p in workers), 20), [p for p in workers if _alive(p)]


@pytest.mark.skipif(not Path("/proc").is_dir(), reason="needs /proc")
def test_ctrl_c_of_a_sweep_is_one_line(tmp_path):
    helper = Path(__file__).resolve().parents[1] / "sweep" / "selftest_cli.py"
    cfg = tmp_path / "s.toml"
    cfg.write_text(f'domain = "selftest"\nx = 0.0\nsleep = 30.0\nstarted_dir = "{tmp_path / "started"}"\n')
    proc = subprocess.Popen(
        [sys.executable, str(helper), "sweep", str(cfg), "--vary", "x=1,2", "-o", str(tmp_path / "s"), "-j", "2", "-q"],
        env=ENV,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )
    try:
        assert _wait_for(lambda: len(list((tmp_path / "started").glob("*"))) >= 2, 120)
        os.killpg(proc.pid, signal.SIGINT)  # what Ctrl-C in a terminal does: the whole group
        _, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    assert proc.returncode == 130
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("interrupted"), err
