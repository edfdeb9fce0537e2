"""Start-up of a verb: the CLI's plain parameter coercion (``rotaflex.cli_startup.plain_coercion``) gives
what typer's own pydantic adapters give, values and error messages alike, without importing
pydantic; numpy submodules no verb uses stay unexecuted (``rotaflex.cli_startup.defer_unused_numpy``)
and still work when used."""

import os
from pathlib import Path

import pytest
import typer
from typer import _coercion
from typer import core as typer_core
from typer.models import ArgumentInfo, OptionInfo

from rotaflex import cli, cli_startup

ROOT = Path(__file__).resolve().parents[1]


class _Param:  # what a runtime parameter reads of the click parameter it coerces for
    multiple = False
    nargs = 1
    name = "value"
    human_readable_name = "VALUE"
    opts = ["--value"]

    def get_error_hint(self, ctx=None):
        return "'--value'"


def _coerce(build, annotation, info, value, tmp_path):
    descriptor = _coercion.resolve_type_descriptor(annotation, info)
    try:
        return "value", build(descriptor).coerce(value, param=_Param(), ctx=None)
    except typer.BadParameter as exc:
        return "error", exc.format_message()


VALUES = {
    str: ["plain", "", " spaced ", "ünïcode", b"bytes", 3],
    int: [150, "150", "007", "-5", "1_000", " 42", "4.0", "abc", "²", True, 2.5],
    bool: [True, False, "true", "0", "maybe"],
    Path: ["a/b.toml", "", ".", Path("x"), "{missing}", 5],
}


@pytest.mark.parametrize("annotation", list(VALUES))
def test_plain_coercion_gives_typers_values_and_errors(annotation, tmp_path):
    assert cli_startup.plain_coercion()  # installed at import; a second call leaves it as it is
    plain = typer_core.build_runtime_param
    assert plain is not _coercion.build_runtime_param
    for info in (OptionInfo(), ArgumentInfo(), OptionInfo(exists=True), OptionInfo(dir_okay=False)):
        for value in VALUES[annotation]:
            if isinstance(value, str) and "{missing}" in value:
                value = str(tmp_path / "missing.toml")
            got = _coerce(plain, annotation, info, value, tmp_path)
            want = _coerce(_coercion.build_runtime_param, annotation, info, value, tmp_path)
            assert got == want, (annotation, value)
            assert type(got[1]) is type(want[1])


def test_other_annotations_keep_typers_adapter():
    ranged = _coercion.resolve_type_descriptor(int, OptionInfo(min=0))
    assert type(typer_core.build_runtime_param(ranged)).__name__ == "AdapterRuntimeParam"
    listed = _coercion.resolve_type_descriptor(list[str], OptionInfo())
    assert type(typer_core.build_runtime_param(listed)).__name__ == "AdapterRuntimeParam"


def test_usage_errors_read_as_with_typers_adapters(monkeypatch, capsys, tmp_path):
    config = str(ROOT / "examples/rotor/fe_friswell_5_9_1.toml")
    bad = [
        ["rotor", "campbell", config, "--out", str(tmp_path / "o"), "--dpi", "abc"],
        ["rotor", "campbell", config, "--out", str(tmp_path / "o"), "--dpi", "1.5"],
        ["sweep", config, "--out", str(tmp_path / "s"), "--vary", "a=1,2", "--retries", "-1"],
    ]

    def errors():
        out = []
        for argv in bad:
            with pytest.raises(SystemExit) as exc:
                cli.main(argv)
            out.append((exc.value.code, capsys.readouterr().err))
        return out

    plain = errors()
    monkeypatch.setattr(typer_core, "build_runtime_param", _coercion.build_runtime_param)
    assert plain == errors()
    assert all(code == 2 for code, _ in plain)


def test_campbell_imports_neither_pydantic_nor_scipy_optimize_and_defers_unused_numpy(tmp_path, python_json):
    # from 100 rpm, not 0: at rest each forward/backward pair is degenerate, LAPACK may return any
    # basis of its plane (numpy 2.4 / scipy 1.17 do), and the first tracking step then rightly
    # needs the assignment solver; past rest the diagram is well tracked, which is what is tested
    text = (ROOT / "examples/rotor/fe_friswell_5_9_1.toml").read_text()
    head, tail = text.split("[campbell]", 1)
    case = tmp_path / "case.toml"
    case.write_text(head + "[campbell]" + tail.replace("speed_rpm = [0, 4000]", "speed_rpm = [100, 4000]", 1))
    code = f"""
        import json, sys
        from rotaflex.cli import main
        try:
            main(["rotor", "campbell", {str(case)!r},
                  "--out", {str(tmp_path / "out")!r}, "--no-figures", "--quiet", "--dpi", "120"])
        except SystemExit as exc:
            assert exc.code == 0, exc.code
        loaded = sorted(m for m in ("pydantic", "scipy.optimize", "matplotlib") if m in sys.modules)
        lazy = sorted(m for m in ("numpy.f2py", "numpy.testing") if type(sys.modules[m]).__name__ == "_LazyModule")
        import numpy as np
        from numpy.testing import assert_array_equal  # a use runs the module as an import would

        assert_array_equal(np.arange(3), [0, 1, 2])
        assert callable(np.f2py.get_include) and type(sys.modules["numpy.f2py"]).__name__ == "module"
        print(json.dumps({{"loaded": loaded, "lazy": lazy}}))
    """
    got = python_json(code)
    assert got == {"loaded": [], "lazy": ["numpy.f2py", "numpy.testing"]}
    assert (tmp_path / "out" / "result.nc").exists()


@pytest.mark.parametrize(
    ("rotaflex", "openblas", "want"),
    [(None, None, "1"), ("3", None, "3"), ("2", "4", "4"), ("0", None, None), ("x", None, None)],
)
def test_openblas_starts_with_the_verbs_thread_count(monkeypatch, rotaflex, openblas, want):
    for name, value in (("ROTAFLEX_BLAS_THREADS", rotaflex), ("OPENBLAS_NUM_THREADS", openblas)):
        if value is None:
            monkeypatch.delenv(name, raising=False)
        else:
            monkeypatch.setenv(name, value)
    cli_startup.blas_threads_at_load()
    assert os.environ.get("OPENBLAS_NUM_THREADS") == want  # a user's own setting is kept


def test_garbage_collection_is_on_again_after_a_verb(tmp_path, capsys):
    """Collection is paused while a verb imports its modules and draws its figures; after the
    command, finished or failed inside, it is on as before (and left off if it was off)."""
    import gc

    config = str(ROOT / "examples/rotor/fe_friswell_5_9_1.toml")
    assert gc.isenabled()
    for argv, code in (
        (["rotor", "campbell", config, "--out", str(tmp_path / "a"), "-q", "--no-figures"], 0),
        (["rotor", "campbell", config, "--out", str(tmp_path / "b"), "--dpi", "5"], 2),  # fails inside
    ):
        with pytest.raises(SystemExit) as exc:
            cli.main(argv)
        assert exc.value.code == code
        assert gc.isenabled()
    gc.disable()
    try:
        with pytest.raises(SystemExit):
            cli.main(["rotor", "campbell", config, "--out", str(tmp_path / "c"), "-q", "--no-figures"])
        assert not gc.isenabled()
    finally:
        gc.enable()
    capsys.readouterr()


@pytest.mark.parametrize("value", ["abc", "-1", "0", "1.5"])
def test_bad_blas_thread_count_is_one_line_exit_2(value, monkeypatch, tmp_path):
    from typer.testing import CliRunner

    from rotaflex.cli import app

    monkeypatch.setenv("ROTAFLEX_BLAS_THREADS", value)
    res = CliRunner().invoke(
        app, ["rotor", "campbell", str(ROOT / "examples/rotor/fe_friswell_5_9_1.toml"), "--out", str(tmp_path / "o")]
    )
    assert res.exit_code == 2
    assert f"ROTAFLEX_BLAS_THREADS = '{value}' is invalid" in res.output
    assert "Traceback" not in res.output
