"""The shipped examples: one folder inside the package, listed and copied by ``rotaflex examples``."""

import subprocess
import sys
from pathlib import Path

import pytest

from rotaflex.core.errors import InputError
from rotaflex.core.examples import IncompleteInstall, copy_examples, example_path, examples_dir, list_examples

ROOT = Path(__file__).resolve().parents[2]


def test_checkout_examples_are_the_shipped_ones():
    # the top-level folder of the checkout is a link to the package data, not a second copy
    assert (ROOT / "examples").resolve() == examples_dir().resolve()
    on_disk = sorted(p.relative_to(examples_dir()).as_posix() for p in examples_dir().rglob("*.toml"))
    assert on_disk and set(on_disk) <= set(list_examples())


def test_every_shipped_file_is_package_data():
    # pyproject's package-data globs must cover every file in the folder, or the wheel lacks it
    import tomllib

    globs = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["package-data"]["rotaflex"]
    suffixes = {g.rsplit("*", 1)[-1] for g in globs}
    files = [p for p in examples_dir().rglob("*") if p.is_file() and "__pycache__" not in p.parts]
    assert files and all(p.suffix in suffixes for p in files), [p for p in files if p.suffix not in suffixes]


def test_missing_example_names_the_full_path():
    with pytest.raises(IncompleteInstall, match=str(examples_dir() / "system" / "nosuch.toml").replace("\\", "\\\\")):
        example_path("system/nosuch.toml")


def test_copy_never_overwrites(tmp_path):
    written = copy_examples(tmp_path, "system/*")
    assert sorted(p.relative_to(tmp_path).as_posix() for p in written) == [
        r for r in list_examples() if r.startswith("system/")
    ]
    assert written[0].read_bytes() == (examples_dir() / written[0].relative_to(tmp_path)).read_bytes()
    with pytest.raises(InputError, match="never overwritten"):
        copy_examples(tmp_path, "system/*")


def test_cli_lists_and_refuses_an_unmatched_pattern(tmp_path):
    ok = subprocess.run([sys.executable, "-m", "rotaflex", "examples", "gear/steady"], capture_output=True, text=True)
    assert ok.returncode == 0 and "gear/steady/torsional_dynamic_factor.toml" in ok.stdout
    bad = subprocess.run([sys.executable, "-m", "rotaflex", "examples", "nope/*"], capture_output=True, text=True)
    assert bad.returncode == 2
    (line,) = bad.stderr.strip().splitlines()
    assert line.startswith("error: pattern = 'nope/*' is invalid: expected a glob matching shipped examples")
