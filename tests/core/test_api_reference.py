"""The API reference (docs/api, Sphinx autodoc + autosummary + napoleon) builds from the
docstrings with warnings as errors, so a broken cross-reference or a docstring that is not valid
reStructuredText fails the suite (issue 37, "The library").

The build uses Sphinx's ``dummy`` builder: it reads every docstring and resolves every reference
as the HTML build does, without writing pages (10.8 s CPU against 12.1 s for ``-b html``, means
of four builds each on the shared 2-core machine).
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
API = ROOT / "docs" / "api"


def _build(source: Path, out: Path, *python_path: Path) -> subprocess.CompletedProcess:
    """``sphinx-build -b dummy -W --keep-going`` in a fresh interpreter, rotaflex from this checkout."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(str(p) for p in (ROOT / "src", *python_path))}
    cmd = [sys.executable, "-m", "sphinx", "-b", "dummy", "-W", "--keep-going", "-q", str(source), str(out)]
    return subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=300)


def _copy_sources(tmp_path: Path) -> Path:
    """docs/api copied, so the pages autosummary generates land in tmp_path, not in the checkout."""
    src = tmp_path / "api"
    shutil.copytree(API, src, ignore=shutil.ignore_patterns("generated", "_build"))
    return src


def test_api_reference_builds_without_warnings(tmp_path):
    src = _copy_sources(tmp_path)
    run = _build(src, tmp_path / "out")
    assert run.returncode == 0, run.stderr
    assert "WARNING" not in run.stderr and "ERROR" not in run.stderr, run.stderr
    pages = {p.stem for p in (src / "generated").glob("*.rst")}
    public = {
        "rotaflex.rotation",
        "rotaflex.rotor",
        "rotaflex.rotor.fe",
        "rotaflex.rotor.fe.study",
        "rotaflex.floating",
    }
    public |= {"rotaflex.gear", "rotaflex.system", "rotaflex.system.study", "rotaflex.sweep"}
    public |= {"rotaflex.core.units", "rotaflex.core.errors"}
    assert public <= pages, public - pages


def test_broken_references_and_markup_fail_the_build(tmp_path):
    """The gate itself: a reference to nothing and an undefined substitution (``|x|`` in prose)
    fail the build; a reference to a helper that exists but is not in the reference is shown as
    code and passes; a numpydoc type in words is prose, not a reference."""
    src = _copy_sources(tmp_path)
    pkg = tmp_path / "lib"
    pkg.mkdir()
    good = '''
        """A module whose docstrings are fine.

        Uses :func:`rotaflex.core.io.write_netcdf` (exists, not in the reference).
        """


        def f(x):
            """Square.

            Parameters
            ----------
            x : (3,) array of float, optional
                Length [m].

            Returns
            -------
            ndarray
                ``|x|^2`` [m^2].
            """
            return x * x
        '''
    bad = '''
        """A module with a broken reference: :func:`rotaflex.core.io.no_such_writer`."""


        def g(x):
            """Absolute value |x| of :class:`NoSuchClass`."""
            return abs(x)
        '''
    (pkg / "goodmod.py").write_text(textwrap.dedent(good))
    (pkg / "badmod.py").write_text(textwrap.dedent(bad))
    for name, mods in (("good", ["goodmod"]), ("bad", ["goodmod", "badmod"])):
        (src / "index.rst").write_text(
            "Test\n====\n\n.. autosummary::\n   :toctree: generated\n\n" + "".join(f"   {m}\n" for m in mods)
        )
        run = _build(src, tmp_path / f"out_{name}", pkg)
        if name == "good":
            assert run.returncode == 0, run.stderr
        else:
            assert run.returncode != 0
            assert "rotaflex.core.io.no_such_writer" in run.stderr
            assert "NoSuchClass" in run.stderr
            assert 'Undefined substitution referenced: "x"' in run.stderr
