"""rotaflex as a user installs it: the wheel, in a fresh virtual environment, run away from the checkout.

The suite itself runs on an editable install, which reads the source tree; this test is what
catches a file the package reads at run time but the wheel does not ship. It builds the wheel,
installs it (without dependencies: those of the running environment are put on the new
environment's path, so the test needs no download beyond the build backend), copies the shipped
examples out with ``rotaflex examples --to``, runs one verb of every domain on the copies and
every ``reproduce`` section in its fastest setting, all from a folder that is not the checkout.

Marked ``install`` (deselected by default: it compiles every kernel family in the new
environment, about 3-4 min); ``.ci/run`` runs it after the suite.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import sysconfig
from pathlib import Path

import pytest

pytestmark = pytest.mark.install

REPO = Path(__file__).resolve().parents[2]


def _run(cmd: list[str], cwd: Path, env: dict, timeout: float = 900) -> subprocess.CompletedProcess:
    proc = subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True, timeout=timeout)
    assert proc.returncode == 0, f"{' '.join(map(str, cmd))} exited {proc.returncode}:\n{proc.stderr[-3000:]}"
    return proc


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    """(rotaflex executable, environment, work folder) of a wheel installed in a fresh venv."""
    tmp = tmp_path_factory.mktemp("wheel")
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    _run([sys.executable, "-m", "pip", "wheel", "-q", "--no-deps", "-w", str(tmp / "dist"), str(REPO)], tmp, env)
    (wheel,) = (tmp / "dist").glob("rotaflex-*.whl")
    _run([sys.executable, "-m", "venv", str(tmp / "venv")], tmp, env)
    py = tmp / "venv" / "bin" / "python"
    site = Path(
        _run([str(py), "-c", "import sysconfig; print(sysconfig.get_path('purelib'))"], tmp, env).stdout.strip()
    )
    # the dependencies of the running environment as plain path entries: their .pth files (and so an
    # editable rotaflex there) are not processed, and the venv's own site-packages comes first
    deps = {sysconfig.get_path("purelib"), sysconfig.get_path("platlib")}
    (site / "zz_test_dependencies.pth").write_text("\n".join(sorted(deps)) + "\n")
    _run([str(py), "-m", "pip", "install", "-q", "--no-deps", str(wheel)], tmp, env)
    work = tmp / "user"
    work.mkdir()
    return tmp / "venv" / "bin" / "rotaflex", env, work


def test_the_package_is_the_wheel(installed):
    exe, env, work = installed
    py = exe.parent / "python"
    where = _run([str(py), "-c", "import rotaflex; print(rotaflex.__file__)"], work, env).stdout.strip()
    assert str(exe.parents[1]) in where, where  # not the checkout's src/
    assert not str(work).startswith(str(REPO))


def test_one_verb_of_every_domain_on_copied_examples(installed):
    exe, env, work = installed
    _run([str(exe), "examples", "--to", "ex"], work, env)
    assert (work / "ex" / "system" / "gearbox.toml").is_file()
    runs = {
        "rotor": ["rotor", "simulate", "ex/rotor/disk_whirl_linear.toml"],
        "rotor_fe": ["rotor", "campbell", "ex/rotor/fe_friswell_5_9_1.toml"],
        "gear": ["gear", "steady", "ex/gear/steady/torsional_dynamic_factor.toml"],
        "floating": ["floating", "simulate", "ex/floating/planar_slew.toml"],
        "system": ["system", "modal", "ex/system/gearbox.toml"],
    }
    for name, cmd in runs.items():
        _run([str(exe), *cmd, "--out", f"out_{name}", "--quiet"], work, env)
        summary = json.loads((work / f"out_{name}" / "summary.json").read_text())
        assert summary, name
        assert (work / f"out_{name}" / "result.nc").is_file(), name


def test_every_reproduce_section_fast(installed):
    exe, env, work = installed
    proc = _run([str(exe), "reproduce", "all", "--fast", "--out", "rep"], work, env, timeout=1200)
    passed, total = proc.stdout.split(" checks passed")[0].split()[-1].split("/")
    assert int(total) >= 118 and passed == total, proc.stdout
    assert (work / "rep" / "index.html").is_file()
