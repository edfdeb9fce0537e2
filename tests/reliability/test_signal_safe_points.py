"""Where an interrupt may be raised: not inside the import system's module-lock callback (a
weakref callback: an exception raised there is only printed, 'Exception ignored in
<function _get_module_lock.<locals>.cb>', with a traceback -- seen in CI), but anywhere else in
an import and in plain Python frames, so that it is not held back until the run has finished."""

import importlib
import sys

from rotaflex.cli import _at_safe_point


def _frame_named(name: str, filename: str):
    namespace = {}
    exec(compile(f"def {name}():\n    import sys\n    return sys._getframe()\n", filename, "exec"), namespace)
    return namespace[name]()


def test_the_module_lock_callback_is_not_a_safe_point():
    # the callback's frame as the signal handler receives it: function cb of importlib's bootstrap
    assert not _at_safe_point(_frame_named("cb", "<frozen importlib._bootstrap>"))
    assert _at_safe_point(_frame_named("cb", "my_module.py"))  # only the import system's callback


def test_a_frame_inside_an_import_is_a_safe_point(tmp_path, monkeypatch):
    (tmp_path / "frame_at_import.py").write_text("import sys\nFRAME = sys._getframe()\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    sys.modules.pop("frame_at_import", None)
    mod = importlib.import_module("frame_at_import")
    chain, f = [], mod.FRAME
    while f is not None:
        chain.append(f.f_code.co_filename)
        f = f.f_back
    assert any(c.startswith("<frozen importlib") for c in chain)  # the frame is inside an import
    assert _at_safe_point(mod.FRAME)


def test_a_plain_frame_is_a_safe_point():
    assert _at_safe_point(sys._getframe())
