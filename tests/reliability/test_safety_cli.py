"""The command line under stress: concurrent runs on one --out, a full disk, SIGINT/SIGTERM while
an HDF5 file is open and inside a compiled kernel, unsafe --out values of every writing verb.

Each command runs in a subprocess with a real signal where a signal is the point. Expected:
exit 2 and one line for bad input, 1 and one line for a failed run, 130/143 for an interrupt,
and the earlier result intact.
"""

import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

from rotaflex.cli import main

ROOT = Path(__file__).resolve().parents[2]
ENV = {**os.environ, "PYTHONPATH": str(ROOT / "src"), "OMP_NUM_THREADS": "1"}
HELPER = ROOT / "tests" / "sweep" / "selftest_cli.py"

#: a subprocess: the selftest domain registered, ``PATCH`` run, then the CLI with argv
_PRELUDE = """
import sys
from rotaflex.core import domains
domains.CASES.setdefault("selftest", "rotaflex.sweep._selftest_case")
{patch}
from rotaflex.cli import main
sys.argv = ["rotaflex", *sys.argv[1:]]
main()
"""


def _cli(args, patch="", **kw) -> subprocess.Popen:
    code = _PRELUDE.format(patch=textwrap.dedent(patch))
    return subprocess.Popen(
        [sys.executable, "-c", code, *map(str, args)],
        env=ENV,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        **kw,
    )


def _run(args, patch="", timeout=120):
    proc = _cli(args, patch)
    out, err = proc.communicate(timeout=timeout)
    return proc.returncode, out, err


def _case(tmp_path, **keys) -> Path:
    cfg = tmp_path / "case.toml"
    body = "".join(f"{k} = {v!r}\n".replace("'", '"') for k, v in keys.items())
    cfg.write_text('domain = "selftest"\n' + body)
    return cfg


def _wait_for(pred, timeout=60.0) -> bool:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if pred():
            return True
        time.sleep(0.05)
    return False


def _one_line(err: str) -> str:
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    return lines[0]


def _snapshot(d: Path) -> dict:
    return {p.name: p.read_bytes() for p in sorted(d.iterdir())}


def _earlier_result(out: Path) -> dict:
    """An earlier result in ``out`` (written here: one subprocess less per test)."""
    from rotaflex.sweep._selftest_case import run_case

    run_case({"x": 1.0}).save(out, figures=False)
    return _snapshot(out)


# -- concurrent runs -------------------------------------------------------------------------
def test_a_second_run_on_the_same_out_is_refused_and_the_first_finishes(tmp_path):
    started = tmp_path / "started"
    cfg = _case(tmp_path, x=2.0, sleep=2.0, started_dir=str(started))
    out = tmp_path / "res"
    first = _cli(["selftest", "simulate", cfg, "--out", out, "-q", "--no-figures"])
    try:
        assert _wait_for(lambda: started.is_dir() and any(started.iterdir()), 60)
        code, _, err = _run(["selftest", "simulate", cfg, "--out", out, "-q", "--no-figures"])
        assert code == 2
        line = _one_line(err)
        assert f"rotaflex pid {first.pid} is writing it now" in line and line.startswith("error: --out")
        _, err1 = first.communicate(timeout=60)
    finally:
        if first.poll() is None:
            first.kill()
    assert first.returncode == 0, err1
    assert {"result.nc", "summary.json"} <= set(_snapshot(out))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["case.toml", "res", "started"]  # no lock, no tmp


# -- full disk -------------------------------------------------------------------------------
_ENOSPC = """
import errno, xarray
def full(*a, **k):
    raise OSError(errno.ENOSPC, "No space left on device")
xarray.Dataset.to_netcdf = full
"""


def test_full_disk_is_one_line_exit_1_and_the_earlier_result_is_intact(tmp_path):
    cfg = _case(tmp_path, x=1.0)
    out = tmp_path / "res"
    before = _earlier_result(out)
    code, _, err = _run(["selftest", "simulate", cfg, "--out", out, "-q", "--no-figures"], patch=_ENOSPC)
    assert code == 1
    assert _one_line(err) == (
        f"error: no space left on device while writing result.nc; the earlier result in {out} is intact"
    )
    assert _snapshot(out) == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["case.toml", "res"]


# -- signals ---------------------------------------------------------------------------------
_SLOW_WRITE = """
import io, time, h5py, xarray
real = xarray.Dataset.to_netcdf
def slow(self, *a, **k):
    with h5py.File(io.BytesIO(), "w") as f:  # an HDF5 file open while the signal arrives
        f["partial"] = [1.0, 2.0]
        print("WRITING", flush=True)
        for _ in range(600):
            time.sleep(0.05)
    return real(self, *a, **k)
xarray.Dataset.to_netcdf = slow
"""


@pytest.mark.parametrize("sig, code, word", [(signal.SIGINT, 130, "interrupted"), (signal.SIGTERM, 143, "terminated")])
def test_signal_while_an_hdf5_file_is_open_exits_cleanly(tmp_path, sig, code, word):
    cfg = _case(tmp_path, x=1.0)
    out = tmp_path / "res"
    before = _earlier_result(out)
    proc = _cli(["selftest", "simulate", cfg, "--out", out, "-q", "--no-figures"], patch=_SLOW_WRITE)
    try:
        assert proc.stdout.readline().strip() == "WRITING"
        proc.send_signal(sig)
        _, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == code, err
    assert _one_line(err).startswith(word)
    assert _snapshot(out) == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["case.toml", "res"]


_KERNEL_CASE = """
import numpy as np
import xarray as xr
from numba import njit

from rotaflex.core.result import Result


@njit(cache=False)
def spin(n):
    s = 0.0
    for i in range(n):
        s += np.sin(i * 1e-3)
    if s > -1e300:
        # raising in nopython mode calls back into Python (numba.core.serialize): a
        # KeyboardInterrupt raised there is what crashed `floating simulate` (SIGSEGV)
        raise ValueError("kernel done")
    return s


def run_case(config, *, progress=False):
    try:
        spin(10)
    except ValueError:
        pass
    print("KERNEL", flush=True)
    try:
        spin(config.get("n", 1))
    except ValueError:
        pass
    ds = xr.Dataset({"x": ("t", np.zeros(3), {"units": "m"})}, attrs={"status": "success", "message": "ok"})
    return Result(ds)
"""


def test_sigint_inside_a_compiled_kernel_is_exit_130_not_a_crash(tmp_path):
    (tmp_path / "kernel_case.py").write_text(_KERNEL_CASE)
    cfg = tmp_path / "k.toml"
    cfg.write_text('domain = "kernel"\nn = 30000000\n')
    patch = f"""
    sys.path.insert(0, {str(tmp_path)!r})
    domains.CASES.setdefault("kernel", "kernel_case")
    """
    proc = _cli(["kernel", "simulate", cfg, "--out", tmp_path / "o", "-q", "--no-figures"], patch=patch)
    try:
        assert proc.stdout.readline().strip() == "KERNEL"
        time.sleep(0.2)  # inside the loop of the kernel
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 130, err
    assert _one_line(err) == "interrupted"
    assert not (tmp_path / "o").exists()


@pytest.mark.slow  # a dask LocalCluster takes 10-20 s to start on a loaded machine
@pytest.mark.skipif(not Path("/proc").is_dir(), reason="needs /proc")
def test_ctrl_c_of_a_dask_local_sweep_is_one_line(tmp_path):
    pytest.importorskip("distributed")
    started = tmp_path / "started"
    cfg = _case(tmp_path, x=0.0, sleep=30.0, started_dir=str(started))
    proc = subprocess.Popen(
        [sys.executable, str(HELPER), "sweep", str(cfg), "--vary", "x=1,2", "-o", str(tmp_path / "s"), "-j", "2"]
        + ["-q", "--scheduler", "dask-local"],
        env=ENV,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )
    try:
        assert _wait_for(lambda: started.is_dir() and len(list(started.iterdir())) >= 2, 120)
        os.killpg(proc.pid, signal.SIGINT)  # Ctrl-C in a terminal: the whole process group
        _, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    assert proc.returncode == 130
    assert _one_line(err).startswith("interrupted: finished cases are in")


# -- unsafe --out values of the writing verbs (in-process: no computation starts) ----------------
def _main(args, capsys):
    with pytest.raises(SystemExit) as info:
        main([str(a) for a in args])
    return info.value.code, capsys.readouterr().err


@pytest.mark.parametrize("verb", [["docs", "config-reference"], ["rotor", "template"], ["floating", "template"]])
def test_text_outputs_refuse_unsafe_paths(tmp_path, capsys, verb):
    f = tmp_path / "file.md"
    f.write_text("keep")
    for bad, why in [
        (tmp_path, "not a directory"),
        ("", "empty string"),
        (f / "x.md", "under the file"),
        ("/dev/rotaflex-test-node", "system path"),
    ]:
        code, err = _main([*verb, "--out", bad], capsys)
        assert code == 2 and why in _one_line(err), (bad, err)
    assert f.read_text() == "keep"
    code, err = _main([*verb, "--out", f], capsys)
    assert code == 0, err
    assert f.read_text().startswith("#")


def test_result_verbs_refuse_the_current_directory_and_the_input_directory(tmp_path, capsys, monkeypatch):
    cfg = tmp_path / "c.toml"
    cfg.write_text("[disk]\nmass = 1.0\n[solver]\nt_end = 0.01\n")
    monkeypatch.chdir(tmp_path)
    for out in (".", "", str(tmp_path), "c.toml"):
        code, err = _main(["rotor", "simulate", cfg, "--out", out], capsys)
        assert code == 2 and _one_line(err).startswith("error: --out"), (out, err)
    code, err = _main(["sweep", cfg, "--vary", "disk.mass=1,2", "--out", "."], capsys)
    assert code == 2 and "current one" in _one_line(err)
    code, err = _main(["reproduce", "rotor", "--out", ".."], capsys)
    assert code == 2 and "current one" in _one_line(err)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["c.toml"]


def test_max_memory_option(tmp_path, capsys, monkeypatch):
    from rotaflex.core import limits

    monkeypatch.delenv("ROTAFLEX_MAX_MEMORY", raising=False)
    code, err = _main(["--max-memory", "lots", "docs", "config-reference"], capsys)
    assert code == 2 and _one_line(err).startswith("error: --max-memory = 'lots' is invalid")
    try:
        code, _ = _main(["--max-memory", "3GiB", "docs", "config-reference", "--out", tmp_path / "r.md"], capsys)
        assert code == 0 and limits.max_memory() == 3 * 1024**3
        assert os.environ["ROTAFLEX_MAX_MEMORY"] == "3GiB"  # sweep workers inherit it
        with pytest.raises(Exception, match="raise the limit with --max-memory"):
            limits.require_memory("solver.n_output", 10**9, 4 * 1024**3, "the history")
    finally:
        limits.set_max_memory(None)
        os.environ.pop("ROTAFLEX_MAX_MEMORY", None)
