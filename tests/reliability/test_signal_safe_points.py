"""Where an interrupt may be raised: never inside the import system (its module-lock callback
only prints an exception raised there, 'Exception ignored in ... _get_module_lock', and the
interrupt would be lost to the run), nor in weakref callbacks; a plain Python frame is safe."""

import importlib
import sys

from rotaflex.cli import _at_safe_point


def test_a_frame_inside_an_import_is_not_a_safe_point(tmp_path, monkeypatch):
    (tmp_path / "frame_at_import.py").write_text("import sys\nFRAME = sys._getframe()\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    sys.modules.pop("frame_at_import", None)
    mod = importlib.import_module("frame_at_import")
    chain, f = [], mod.FRAME
    while f is not None:
        chain.append(f.f_code.co_filename)
        f = f.f_back
    assert any(c.startswith("<frozen importlib") for c in chain)  # the frame is inside an import
    assert not _at_safe_point(mod.FRAME)


def test_a_plain_frame_is_a_safe_point():
    assert _at_safe_point(sys._getframe())
