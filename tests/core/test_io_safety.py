"""Checked output paths, the per-run claim on an output directory, and writes that fail (full disk)."""

import errno
import os
import stat
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from rotaflex.core import io
from rotaflex.core.errors import InputError
from rotaflex.core.io import WriteFailed, check_out_dir, check_out_file, claim_out_dir, recover_dir
from rotaflex.core.result import Result


def _result(value: float) -> Result:
    ds = xr.Dataset(
        {"x": ("time", np.full(5, value), {"units": "m"})},
        coords={"time": ("time", np.arange(5.0), {"units": "s"})},
        attrs={"status": "success", "message": "test"},
    )
    return Result(ds)


def _refused(fn, *args, **kw) -> InputError:
    with pytest.raises(InputError) as info:
        fn(*args, **kw)
    assert "\n" not in str(info.value)
    return info.value


# -- checked paths ------------------------------------------------------------------------------
def test_out_dir_refuses_empty_file_under_file_cwd_and_parents(tmp_path, monkeypatch):
    f = tmp_path / "a.txt"
    f.write_text("x")
    assert "empty string" in str(_refused(check_out_dir, ""))
    assert "not an existing file" in str(_refused(check_out_dir, f))
    assert "under the file" in str(_refused(check_out_dir, f / "sub"))
    work = tmp_path / "w" / "x"
    work.mkdir(parents=True)
    monkeypatch.chdir(work)
    for p in (".", "..", str(tmp_path), "./"):
        assert "current one or one above" in str(_refused(check_out_dir, p)), p
    assert check_out_dir("new") == Path("new")  # a new directory below the current one is fine


def test_out_dir_refuses_a_directory_holding_the_input(tmp_path):
    cfg = tmp_path / "cases" / "c.toml"
    cfg.parent.mkdir()
    cfg.write_text("x = 1\n")
    for p in (cfg.parent, tmp_path):
        assert "does not hold the input" in str(_refused(check_out_dir, p, inputs=(cfg,)))
    assert "other than the input file" in str(_refused(check_out_dir, cfg, inputs=(cfg,)))
    assert check_out_dir(tmp_path / "out", inputs=(cfg,)) == tmp_path / "out"


def test_device_nodes_are_refused_without_touching_one(tmp_path, monkeypatch):
    """A path whose stat says 'character device' (stat faked: no real device is opened)."""
    target = tmp_path / "looks_like_a_device"
    real_stat = os.stat

    def fake_stat(p, *a, **kw):
        if Path(p) == target:
            return os.stat_result((stat.S_IFCHR | 0o666, 0, 0, 1, 0, 0, 0, 0, 0, 0))
        return real_stat(p, *a, **kw)

    monkeypatch.setattr(io.os, "stat", fake_stat)
    assert "not a device" in str(_refused(check_out_file, target))
    assert "not a device" in str(_refused(check_out_dir, target))
    # anything under /dev, /proc or /sys: refused from the path alone
    for p in ("/dev/rotaflex-test-node", "/dev/shm/x", "/proc/self/x"):
        assert "system path" in str(_refused(check_out_file, p)) or "not a device" in str(_refused(check_out_file, p))


def test_pipes_are_refused(tmp_path):
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    assert "not a pipe" in str(_refused(check_out_file, fifo))


def test_out_file_refuses_directories_and_paths_under_files(tmp_path):
    f = tmp_path / "a.md"
    f.write_text("x")
    assert "not a directory" in str(_refused(check_out_file, tmp_path))
    assert "not a directory" in str(_refused(check_out_file, str(tmp_path / "new") + "/"))
    assert "under the file" in str(_refused(check_out_file, f / "b.md"))
    assert "empty string" in str(_refused(check_out_file, ""))
    assert "parent exists" in str(_refused(check_out_file, tmp_path / "no" / "b.md"))
    assert check_out_file(f) == f  # an existing regular file is replaced (atomically)


# -- one run per output directory ------------------------------------------------------------
_HOLD = """
import sys, time
from rotaflex.core.io import claim_out_dir
with claim_out_dir(sys.argv[1]):
    print("HELD", flush=True)
    time.sleep(60)
"""


def test_a_second_run_on_a_claimed_directory_is_refused_naming_the_owner(tmp_path):
    out = tmp_path / "res"
    env = {**os.environ, "PYTHONPATH": str(Path(io.__file__).parents[2])}
    proc = subprocess.Popen([sys.executable, "-c", _HOLD, str(out)], env=env, stdout=subprocess.PIPE, text=True)
    try:
        assert proc.stdout.readline().strip() == "HELD"
        err = _refused(lambda: claim_out_dir(out).__enter__())
        assert f"pid {proc.pid}" in str(err) and err.field == "--out"
        (tmp_path / "link").symlink_to(out)
        for other in (str(out) + "/", tmp_path / "sub" / ".." / "res", tmp_path / "link"):
            (tmp_path / "sub").mkdir(exist_ok=True)
            assert f"pid {proc.pid}" in str(_refused(lambda o=other: claim_out_dir(o).__enter__()))
    finally:
        proc.kill()
        proc.wait()
    # the owner died (SIGKILL, no cleanup): the kernel dropped its lock, the next run proceeds
    with claim_out_dir(out):
        pass
    assert not list(tmp_path.glob(".res.rotaflex-lock*"))


def test_working_directories_of_live_runs_are_kept(tmp_path):
    target = tmp_path / "res"
    _result(1.0).save(target, figures=False)
    sleeper = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    try:
        live = tmp_path / f".res.rotaflex-tmp-{sleeper.pid}-abcd"
        live.mkdir()
        (live / "result.nc").write_text("being written")
        dead_pid = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True)
        dead = tmp_path / f".res.rotaflex-tmp-{int(dead_pid.stdout)}-efgh"
        dead.mkdir()
        recover_dir(target)
        _result(2.0).save(target, figures=False)  # replace_dir recovers too
        assert live.is_dir() and (live / "result.nc").read_text() == "being written"
        assert not dead.exists()
    finally:
        sleeper.kill()
        sleeper.wait()


# -- full disk --------------------------------------------------------------------------------
def _enospc(*_a, **_kw):
    raise OSError(errno.ENOSPC, "No space left on device")


def test_injected_enospc_keeps_the_earlier_result_and_says_so(tmp_path, monkeypatch):
    out = tmp_path / "res"
    _result(1.0).save(out, figures=False)
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    monkeypatch.setattr(xr.Dataset, "to_netcdf", _enospc)
    with pytest.raises(WriteFailed) as info:
        _result(2.0).save(out, figures=False)
    assert str(info.value) == f"no space left on device while writing result.nc; the earlier result in {out} is intact"
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["res"]  # no working directory, no partial set


def test_injected_enospc_without_an_earlier_result(tmp_path, monkeypatch):
    monkeypatch.setattr(xr.Dataset, "to_netcdf", _enospc)
    with pytest.raises(WriteFailed, match=r"while writing result\.nc; nothing was written to "):
        _result(2.0).save(tmp_path / "res", figures=False)
    assert list(tmp_path.iterdir()) == []


def test_enospc_in_a_single_file_write(tmp_path):
    target = tmp_path / "sweep.nc"
    target.write_text("old")

    def writer(p):
        Path(p).write_text("partial")
        raise OSError(errno.ENOSPC, "No space left on device")

    with pytest.raises(WriteFailed, match=rf"while writing sweep\.nc; the earlier sweep\.nc in {tmp_path} is intact"):
        io.write_atomic(target, writer)
    assert target.read_text() == "old" and [p.name for p in tmp_path.iterdir()] == ["sweep.nc"]


def test_other_io_errors_name_the_file_too(tmp_path, monkeypatch):
    monkeypatch.setattr(xr.Dataset, "to_netcdf", lambda *a, **k: (_ for _ in ()).throw(OSError(errno.EIO, "I/O")))
    with pytest.raises(WriteFailed, match=r"^could not write \(I/O\) while writing result\.nc"):
        _result(1.0).save(tmp_path / "res", figures=False)


@pytest.fixture
def small_fs(tmp_path):
    """A 1 MiB tmpfs (needs root and mount permission; skipped with the reason otherwise)."""
    mnt = tmp_path / "small"
    mnt.mkdir()
    try:
        r = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=1m", "tmpfs", str(mnt)], capture_output=True, text=True)
    except FileNotFoundError:
        pytest.skip("no mount command here: the injected-ENOSPC tests cover the same path")
    if r.returncode != 0:
        pytest.skip(f"cannot mount a small tmpfs here ({r.stderr.strip()}): the injected-ENOSPC tests cover it")
    try:
        yield mnt
    finally:
        for _ in range(20):
            if subprocess.run(["umount", str(mnt)], capture_output=True).returncode == 0:
                break
            time.sleep(0.1)


def test_full_small_filesystem_keeps_the_earlier_result(small_fs):
    out = small_fs / "res"
    _result(1.0).save(out, figures=False)
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    big = xr.Dataset({"x": ("time", np.random.default_rng(0).random(400_000), {"units": "m"})})  # 3.2 MB
    with pytest.raises(WriteFailed) as info:
        Result(big).save(out, figures=False)
    assert str(info.value) == f"no space left on device while writing result.nc; the earlier result in {out} is intact"
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before
    assert sorted(p.name for p in small_fs.iterdir()) == ["res"]
    _result(3.0).save(out, figures=False)  # the space was given back: the next save works


def test_full_small_filesystem_past_the_free_space_check(small_fs, monkeypatch):
    """The disk fills while writing (the free-space check saw room): still one clean WriteFailed."""
    import shutil

    out = small_fs / "res"
    _result(1.0).save(out, figures=False)
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    monkeypatch.setattr(shutil, "disk_usage", lambda p: shutil._ntuple_diskusage(2**40, 0, 2**40))
    big = xr.Dataset({"x": ("time", np.random.default_rng(1).random(400_000), {"units": "m"})})
    with pytest.raises(WriteFailed, match=r"^no space left on device while writing result\.nc; the earlier result"):
        Result(big).save(out, figures=False)
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before
    assert sorted(p.name for p in small_fs.iterdir()) == ["res"]


def test_free_space_is_checked_before_hdf5_starts(tmp_path, monkeypatch):
    import shutil

    calls = []
    monkeypatch.setattr(shutil, "disk_usage", lambda p: shutil._ntuple_diskusage(2**30, 2**30 - 1000, 1000))
    monkeypatch.setattr(xr.Dataset, "to_netcdf", lambda *a, **k: calls.append(a))
    with pytest.raises(WriteFailed, match=r"no space left on device while writing result\.nc"):
        _result(1.0).save(tmp_path / "res", figures=False)
    assert calls == [] and list(tmp_path.iterdir()) == []
