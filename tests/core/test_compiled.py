"""The two kernel decorators: @inner kernels are linked into their entry point, which gives the
same numbers as plain numba; entry caches are keyed on every kernel module of the package."""

import importlib
import pickle
import subprocess
import sys
import textwrap

import numpy as np
import pytest

_KERNELS = {
    "leaf.py": """
        from rotaflex.core.compiled import inner

        @inner
        def poly(x):
            return 1.0 + x * (0.5 + x * (1.0 / 6.0 + x / 24.0))
    """,
    "mid.py": """
        import numpy as np
        from rotaflex.core.compiled import inner
        from kpkg.leaf import poly

        @inner
        def integrate(y, dt, n):
            for _ in range(n):
                y = y * poly(-dt) + np.sin(y) * dt
            return y
    """,
    "top.py": '''
        from rotaflex.core.compiled import entry
        from kpkg.mid import integrate

        @entry
        def run(y0, dt, n):
            return integrate(y0, dt, n)

        def plain(y, dt, n):
            """The same arithmetic in Python."""
            import math
            for _ in range(n):
                x = -dt
                y = y * (1.0 + x * (0.5 + x * (1.0 / 6.0 + x / 24.0))) + math.sin(y) * dt
            return y
    ''',
}


@pytest.fixture
def kpkg(tmp_path, monkeypatch):
    pkg = tmp_path / "kpkg"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    for name, text in _KERNELS.items():
        (pkg / name).write_text(textwrap.dedent(text))
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path / "cache"))
    yield pkg
    for mod in [m for m in sys.modules if m == "kpkg" or m.startswith("kpkg.")]:
        del sys.modules[mod]


def test_inner_tree_linked_into_its_entry_gives_the_python_result(kpkg):
    top = importlib.import_module("kpkg.top")
    got = top.run(0.3, 1e-3, 1000)
    # no fast-math: the compiled tree must round exactly as Python does
    assert got == top.plain(0.3, 1e-3, 1000)
    with pytest.raises(TypeError, match="integrate is compiled only for calls from other kernels"):
        importlib.import_module("kpkg.mid").integrate(0.3, 1e-3, 10)


def test_entry_cache_follows_an_edit_of_a_kernel_it_calls(kpkg, tmp_path):
    """numba alone keys the cache on the entry's file: an edited callee in a sibling module would
    load the old machine code. Each run is a fresh process sharing one cache directory."""
    script = "import sys; sys.path.insert(0, sys.argv[1]); from kpkg.top import run; print(repr(run(0.3, 1e-3, 100)))"

    def run_fresh():
        out = subprocess.run(
            [sys.executable, "-c", script, str(tmp_path)], capture_output=True, text=True, check=True
        ).stdout
        return float(out)

    first = run_fresh()
    leaf = kpkg / "leaf.py"
    leaf.write_text(leaf.read_text().replace("1.0 + x *", "2.0 + x *"))
    second = run_fresh()
    assert second != first
    top = importlib.import_module("kpkg.top")
    assert np.isfinite(second) and top.run(0.3, 1e-3, 100) == second


def test_entry_cache_never_loads_data_of_another_signature_or_source(kpkg, tmp_path):
    """numba saves a cache index before its data: a process reading the index in between could
    load an older data file of the same name. Data files carry the source stamp in their names,
    and an index entry whose data holds another signature is a miss (here: forged by pointing
    the float entry at the integer entry's data)."""
    script = (
        "import sys; sys.path.insert(0, sys.argv[1]); from kpkg.top import run; "
        "print(repr(run(0.3, 1e-3, 100)), repr(run(1, 0, 3)))"
    )

    def run_fresh():
        out = subprocess.run(
            [sys.executable, "-c", script, str(tmp_path)], capture_output=True, text=True, check=True
        ).stdout
        return [float(v) for v in out.split()]

    first = run_fresh()
    cached = sorted(p.name for p in (tmp_path / "cache").rglob("*.nbc"))
    assert len(cached) == 2 and len({name.split(".")[-3] for name in cached}) == 1  # one stamp
    (index_path,) = (tmp_path / "cache").rglob("*run*.nbi")
    with open(index_path, "rb") as f:  # numba's layout: pickled version, then (stamp, overloads)
        version = pickle.load(f)
        stamp, index = pickle.loads(f.read())
    assert len(index) == 2
    (key_a, name_a), (key_b, name_b) = index.items()
    with open(index_path, "wb") as f:  # each entry names the other's data
        pickle.dump(version, f, protocol=-1)
        f.write(pickle.dumps((stamp, {key_a: name_b, key_b: name_a}), protocol=-1))
    assert run_fresh() == first
    # an edited source writes data files of a new stamp beside the old ones
    leaf = kpkg / "leaf.py"
    leaf.write_text(leaf.read_text().replace("1.0 + x *", "2.0 + x *"))
    second = run_fresh()
    assert second[0] != first[0]
    stamps = {p.name.split(".")[-3] for p in (tmp_path / "cache").rglob("*.nbc")}
    assert len(stamps) == 2
