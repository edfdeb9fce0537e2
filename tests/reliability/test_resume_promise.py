"""Issue 32, part 4: resume keeps its promise.

A continuation sweep run again in its output reuses every finished case: after completion
(a ``system steady`` chain was "40 computed, 0 reused": its result.nc loaded as a plain Result
without ``final_state``), and after a client killed while one case's files were being written
(later cases of the chain, written meanwhile by the writer pool, are reused; the unfinished one
runs again from its predecessor's saved state). A sweep killed with SIGKILL leaves no
multiprocessing ``pymp-*`` directory in the system's temporary directory.
"""

import contextlib
import io
import json
import os
import shutil
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from _cli import dump, edited, run

from rotaflex.cli import main

SRC = Path(__file__).resolve().parents[2] / "src"


def _small_gearbox(d):
    """The example gearbox on 4 elements per shaft, 2 evaluation cycles (a chain in seconds)."""
    d["domain"], d["verb"] = "system", "steady"
    d["steady"]["eval_cycles"] = 2
    for r in d["rotor"]:
        r["shaft"][0]["elements"] = 4
        for b in r["bearing"]:
            b["node"] = min(b["node"], 4)
    d["gear_mesh"][0]["pinion_node"] = d["gear_mesh"][0]["wheel_node"] = 2
    d["load"]["node"] = 4


def _sweep_args(cfg, out, *extra):
    args = ["sweep", cfg, "--out", out, "--vary", "steady.speed_rpm=2000:3000:3"]
    return [*args, "--continuation", "steady.speed_rpm", "-j", "0", "-q", "--no-figures", *extra]


def _sweep(capsys, cfg, out, *extra):
    return run(capsys, *_sweep_args(cfg, out, *extra))


@pytest.fixture(scope="module")
def chain(tmp_path_factory):
    """The small gearbox's chain swept once (shared: each test reruns a copy of its output):
    config path, output folder, exit status and stdout of the first run."""
    tmp = tmp_path_factory.mktemp("chain")
    cfg = tmp / "gearbox.toml"
    cfg.write_text(dump(edited("system/gearbox.toml", _small_gearbox)))
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
        with pytest.raises(SystemExit) as exc:
            main([str(a) for a in _sweep_args(cfg, tmp / "o")])
    return cfg, tmp / "o", exc.value.code, out.getvalue()


def _copy_of_chain(chain, tmp_path):
    """The config and a private copy of the swept output (the tests rerun and edit it)."""
    cfg, done, code, out = chain
    assert code == 0 and "6 computed, 0 reused" in out, out
    shutil.copytree(done, tmp_path / "o")
    return cfg, tmp_path / "o"


def test_system_steady_chain_rerun_reuses_every_case(capsys, chain, tmp_path):
    cfg, o = _copy_of_chain(chain, tmp_path)
    with xr.open_dataset(o / "sweep.nc") as ds:
        before = {k: ds[k].values.copy() for k in ds.data_vars if ds[k].dtype.kind == "f"}
    code, out, _ = _sweep(capsys, cfg, o)
    assert code == 0 and "0 computed, 6 reused" in out, out
    with xr.open_dataset(o / "sweep.nc") as ds:
        for k, v in before.items():
            np.testing.assert_array_equal(ds[k].values, v)


def test_chain_resumes_after_the_case_being_written(capsys, chain, tmp_path):
    """Case 0000 left half written (no summary.json, marker not done) while later cases of its
    chain were written: only 0000 runs again; the rest are reused, and every number is the
    same as the uninterrupted run's (0000 starts the chain, so it reruns from the verb's start)."""
    cfg, _ = _copy_of_chain(chain, tmp_path)
    with xr.open_dataset(tmp_path / "o" / "sweep.nc") as ds:
        before = ds["dynamic_factor"].values.copy() if "dynamic_factor" in ds else None
        first = str(ds["case_id"].values.ravel()[0])
    assert first.startswith("0000-")
    case = tmp_path / "o" / "cases" / first
    (case / "summary.json").unlink()
    marker = json.loads((case / "case.json").read_text())
    (case / "case.json").write_text(json.dumps({**marker, "state": "running"}))
    code, out, _ = _sweep(capsys, cfg, tmp_path / "o")
    assert code == 0 and "1 computed, 5 reused" in out, out
    if before is not None:
        with xr.open_dataset(tmp_path / "o" / "sweep.nc") as ds:
            np.testing.assert_array_equal(ds["dynamic_factor"].values, before)


@pytest.mark.skipif(sys.platform != "linux", reason="fork server and SIGKILL semantics of Linux")
def test_killed_sweep_leaves_no_pymp_directory(tmp_path):
    """A client killed with SIGKILL while its pool runs: multiprocessing's directory (the fork
    server's socket) was in the output, none in the system's temporary directory; the next
    sweep in that output removes it."""
    tmp = tmp_path / "tmp"
    tmp.mkdir()
    out = tmp_path / "o"
    code = textwrap.dedent(
        f"""
        import os, signal
        from rotaflex.sweep.backends import mp_temp_dir, process_pool
        d = mp_temp_dir({str(out)!r})
        pool = process_pool(1)
        assert pool.submit(abs, -1).result() == 1
        print(sorted(os.listdir(d)), flush=True)
        os.kill(os.getpid(), signal.SIGKILL)
        """
    )
    env = {**os.environ, "PYTHONPATH": str(SRC), "TMPDIR": str(tmp)}
    log = tmp_path / "log.txt"
    with log.open("w") as fh:  # a file, not a pipe: the pool's processes outlive the client a while
        proc = subprocess.Popen([sys.executable, "-c", code], env=env, stdout=fh, stderr=subprocess.STDOUT)
        assert proc.wait(timeout=120) == -signal.SIGKILL, log.read_text()
    assert "listener-" in log.read_text()  # the fork server's socket was in the output
    assert not [p for p in tmp.iterdir() if p.name.startswith("pymp-")]
    assert (out / ".mp").exists()  # left by the killed run, inside its output
    from rotaflex.sweep.backends import mp_temp_dir

    config = __import__("multiprocessing").process.current_process()._config
    had = config.get("tempdir")
    try:
        mp_temp_dir(out)  # the next run in this output
        assert had is not None or config.get("tempdir") == str((out / ".mp").resolve())
        assert not any((out / ".mp").iterdir()) if (out / ".mp").exists() else True
    finally:
        if had is None and config.get("tempdir") == str((out / ".mp").resolve()):
            del config["tempdir"]
            os.environ.pop("TMPDIR", None)
        shutil.rmtree(out / ".mp", ignore_errors=True)
