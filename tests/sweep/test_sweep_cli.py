import json
import re
import signal
import subprocess
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from sweep_helpers import PY, env_with_src
from typer.testing import CliRunner

from rotaflex.cli import app
from rotaflex.core.result import load_result

HELPER = str(Path(__file__).with_name("selftest_cli.py"))
runner = CliRunner()


def _config(tmp_path, **kw) -> Path:
    lines = ['domain = "selftest"', "x = 1.0", "y = 0.5", "n = 32"]
    lines += [f"{k} = {json.dumps(v)}" for k, v in kw.items()]
    path = tmp_path / "case.toml"
    path.write_text("\n".join(lines) + "\n")
    return path


def _counts(output: str) -> tuple[int, int, int]:
    m = re.search(r"(\d+) computed, (\d+) reused from an earlier run, (\d+) failed", output)
    assert m, output
    return tuple(int(g) for g in m.groups())


def test_unknown_key_exits_2_naming_it_before_running(tmp_path, selftest_domain):
    cfg = _config(tmp_path)
    out = tmp_path / "out"
    res = runner.invoke(
        app,
        [
            "sweep",
            str(cfg),
            "--vary",
            "x=0:1:3",
            "--vary",
            "drive.speed_rpm=1,2",
            "--out",
            str(out),
            "-q",
        ],
    )
    assert res.exit_code == 2
    assert "drive.speed_rpm" in res.output and "Traceback" not in res.output
    assert not out.exists()
    res = runner.invoke(app, ["sweep", str(cfg), "--vary", "x=0:1", "--out", str(out), "-q"])
    assert res.exit_code == 2 and "START:STOP:N" in res.output


def test_local_sweep_then_rerun_reuses_everything(tmp_path, selftest_domain):
    cfg = _config(tmp_path)
    args = [
        "sweep",
        str(cfg),
        "--vary",
        "x=0:2:3",
        "--param",
        "y=1,2",
        "--out",
        str(tmp_path / "out"),
        "-j",
        "2",
        "-q",
    ]
    res = runner.invoke(app, args)
    assert res.exit_code == 0, res.output
    assert _counts(res.output) == (6, 0, 0)
    ds = xr.open_dataset(tmp_path / "out" / "sweep.nc", engine="h5netcdf").load()
    assert ds["a"].dims == ("x", "y") and ds.attrs["domain"] == "selftest"
    np.testing.assert_allclose(ds["a"].values, ds["x"].values[:, None] ** 2 + ds["y"].values[None, :])
    res = runner.invoke(app, args)
    assert res.exit_code == 0 and _counts(res.output) == (0, 6, 0)


def test_failed_cases_give_exit_status_1_and_a_count(tmp_path, selftest_domain):
    cfg = _config(tmp_path, fail=False)
    res = runner.invoke(
        app,
        [
            "sweep",
            str(cfg),
            "--vary",
            "fail=false,true",
            "--vary",
            "x=1,2,3",
            "--out",
            str(tmp_path / "out"),
            "-j",
            "0",
            "-q",
        ],
    )
    assert res.exit_code == 1
    assert "3 of 6 cases failed" in res.output
    assert _counts(res.output) == (6, 0, 3)
    rows = (tmp_path / "out" / "summary.csv").read_text().splitlines()
    assert sum(",error," in r for r in rows) == 3


def _done(out: Path) -> dict[str, int]:
    stamps = {}
    for marker in (out / "cases").glob("*/case.json"):
        if json.loads(marker.read_text()).get("state") == "done":
            stamps[marker.parent.name] = (marker.parent / "result.nc").stat().st_mtime_ns
    return stamps


def test_interrupted_sweep_resumes_with_only_the_missing_cases(tmp_path):
    cfg = _config(tmp_path, sleep=0.2)
    out = tmp_path / "out"
    cmd = [PY, HELPER, "sweep", str(cfg), "--vary", "x=0:3:16", "--out", str(out), "-j", "2", "-q"]
    proc = subprocess.Popen(cmd, env=env_with_src(), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 60
        while len(_done(out)) < 2 if out.exists() else True:
            assert time.monotonic() < deadline and proc.poll() is None
            time.sleep(0.05)
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 130, (proc.returncode, err)
    assert "interrupted" in err
    before = _done(out)
    assert 2 <= len(before) < 16, len(before)
    res = subprocess.run(cmd, env=env_with_src(), capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr
    assert _counts(res.stdout) == (16 - len(before), len(before), 0), (res.stdout, sorted(before))
    after = _done(out)
    assert len(after) == 16
    assert all(after[k] == v for k, v in before.items())  # finished cases were not rewritten


def _sweep_values(out: Path):
    ds = xr.open_dataset(out / "sweep.nc", engine="h5netcdf").load()
    series = {
        cid: load_result(out / "cases" / cid / "result.nc").dataset["signal"].values
        for cid in ds["case_id"].values.ravel()
    }
    return ds, series


def test_dask_scheduler_results_identical_to_serial(tmp_path, selftest_domain, dask_cluster):
    cfg = _config(tmp_path)
    common = ["sweep", str(cfg), "--vary", "x=0.5:2:4", "--vary", "y=1,3", "-q", "--no-figures"]
    res = runner.invoke(app, [*common, "--out", str(tmp_path / "serial"), "-j", "0"])
    assert res.exit_code == 0, res.output
    res = runner.invoke(app, [*common, "--out", str(tmp_path / "dask"), "--scheduler", dask_cluster])
    assert res.exit_code == 0, res.output
    assert _counts(res.output) == (8, 0, 0)
    a, sa = _sweep_values(tmp_path / "serial")
    b, sb = _sweep_values(tmp_path / "dask")
    for name in ("a", "b", "signal_max", "case_id", "status"):
        np.testing.assert_array_equal(a[name].values, b[name].values)
    assert sa.keys() == sb.keys()
    for cid in sa:
        np.testing.assert_array_equal(sa[cid], sb[cid])
    workers = {json.loads(p.read_text())["worker"] for p in (tmp_path / "dask" / "cases").glob("*/case.json")}
    assert len(workers) >= 1


def test_dask_worker_killed_mid_case_sweep_completes(tmp_path, selftest_domain, dask_cluster):
    marker = tmp_path / "killed"
    cfg = _config(tmp_path, sleep=0.1, kill_once=str(marker))
    out = tmp_path / "out"
    res = runner.invoke(
        app,
        [
            "sweep",
            str(cfg),
            "--vary",
            "x=1:6:6",
            "--out",
            str(out),
            "--scheduler",
            dask_cluster,
            "-q",
            "--no-figures",
        ],
    )
    assert res.exit_code == 0, res.output
    assert marker.exists()  # a worker really was killed
    assert _counts(res.output) == (6, 0, 0)
    ds = xr.open_dataset(out / "sweep.nc", engine="h5netcdf").load()
    np.testing.assert_allclose(ds["a"].values, ds["x"].values ** 2 + 0.5)
    assert ds["attempts"].values.max() >= 2  # KilledWorker came back and the case was resubmitted


# a hang here (seen once in CI, in a client-side writer thread since removed) fails loudly after
# 180 s (~5 s on a loaded machine) with every thread's stack printed, instead of blocking the run
# until the global timeout; "thread": a hang inside C code never returns to a signal handler
@pytest.mark.timeout(180, method="thread")
def test_dask_case_that_always_kills_its_worker_fails_alone(tmp_path, selftest_domain, dask_cluster):
    cfg = _config(tmp_path, kill_always=False)
    out = tmp_path / "out"
    res = runner.invoke(
        app,
        [
            "sweep",
            str(cfg),
            "--vary",
            "kill_always=false,true",
            "--out",
            str(out),
            "--scheduler",
            dask_cluster,
            "--retries",
            "1",
            "-q",
            "--no-figures",
        ],
    )
    assert res.exit_code == 1, res.output
    assert "1 of 2 cases failed" in res.output
    ds = xr.open_dataset(out / "sweep.nc", engine="h5netcdf").load()
    bad, good = ds.sel({"kill_always": True}), ds.sel({"kill_always": False})
    assert str(good["status"].values) == "success" and float(good["a"]) == 1.5
    assert str(bad["status"].values) == "error" and "KilledWorker" in str(bad["error"].values)
    # two deaths while running alone (retries = 1); a first run beside the good case that died
    # with it counts for neither (a worker's death fails every case queued on it)
    assert int(bad["attempts"]) in (2, 3)
    assert "died while running this case 2 time(s)" in str(bad["error"].values)


def test_dask_unreachable_scheduler_is_one_line(tmp_path, selftest_domain, monkeypatch):
    monkeypatch.setattr("rotaflex.sweep.backends.CONNECT_TIMEOUT", 2.0)
    cfg = _config(tmp_path)
    res = runner.invoke(
        app,
        [
            "sweep",
            str(cfg),
            "--vary",
            "x=1,2",
            "--out",
            str(tmp_path / "o"),
            "--scheduler",
            "tcp://127.0.0.1:9",
            "-q",
        ],
    )
    assert res.exit_code == 2 and "scheduler" in res.output and "Traceback" not in res.output


def test_dask_local_cluster_from_the_cli(tmp_path, selftest_domain):
    cfg = _config(tmp_path)
    out = tmp_path / "out"
    res = runner.invoke(
        app,
        [
            "sweep",
            str(cfg),
            "--vary",
            "x=1,2,3",
            "--out",
            str(out),
            "--scheduler",
            "dask-local",
            "-j",
            "1",
            "-q",
            "--no-figures",
        ],
    )
    assert res.exit_code == 0, res.output
    assert _counts(res.output) == (3, 0, 0)
    ds = xr.open_dataset(out / "sweep.nc", engine="h5netcdf").load()
    np.testing.assert_allclose(ds["a"].values, ds["x"].values ** 2 + 0.5)
    workers = {json.loads(p.read_text())["worker"] for p in (out / "cases").glob("*/case.json")}
    assert len(workers) == 1  # -j 1: one single-threaded worker process


def test_domain_validate_hook_rejects_a_bad_case_before_running(tmp_path, selftest_domain):
    # the selftest module's validate_config rejects n < 2 (as its run_case would)
    cfg = _config(tmp_path)
    out = tmp_path / "out"
    res = runner.invoke(app, ["sweep", str(cfg), "--vary", "n=1:5:5", "--out", str(out), "-q"])
    assert res.exit_code == 2 and "(case n=1)" in res.output and "n = 1" in res.output
    assert not out.exists()
