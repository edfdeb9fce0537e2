"""core.jit: the compile timer picks numba up when a block imports it, and the first-run line
is written only while numba's disk cache of the kernels is cold (fresh processes: NUMBA_CACHE_DIR
is read when numba is imported)."""

from __future__ import annotations

from pathlib import Path

SRC = Path(__file__).resolve().parents[2] / "src"


def _run(python_json, code: str, tmp_path: Path) -> dict:
    """``code`` in a fresh process with ``tmp_path`` importable and its own numba cache."""
    return python_json(code, extra_path=[tmp_path], env={"NUMBA_CACHE_DIR": str(tmp_path / "cache")}, timeout=120)


def test_timer_starts_listening_when_the_block_imports_numba(tmp_path, python_json):
    got = _run(
        python_json,
        """
        import json, sys
        from rotaflex.core.jit import CompileTimer
        with CompileTimer() as idle:
            pass
        after_idle = "numba" in sys.modules
        said = []
        with CompileTimer(said.append) as timer:
            import numba  # first imported inside the block, as a domain's kernels module would
            @numba.njit(cache=False)
            def twice(x):
                return 2.0 * x
            twice(1.5)
            twice(2.5)
        hooks = [type(f).__name__ for f in sys.meta_path if type(f).__name__ == "_AfterImport"]
        print(json.dumps({"after_idle": after_idle, "idle": idle.count, "count": timer.count,
                          "seconds": timer.seconds, "said": said, "hooks": hooks}))
        """,
        tmp_path,
    )
    assert got["after_idle"] is False and got["idle"] == 0  # a block that compiles nothing imports nothing
    assert got["count"] == 1 and got["seconds"] > 0  # one compilation, timed although numba came late
    assert len(got["said"]) == 1 and "compiling numba kernels" in got["said"][0]
    assert got["hooks"] == []  # the import hook is gone after the block


def test_announcement_only_while_the_disk_cache_is_cold(tmp_path, python_json):
    (tmp_path / "tiny_kernels.py").write_text(
        "from numba import njit\n\n\n@njit(cache=True)\ndef plus_one(x):\n    return x + 1.0\n"
    )
    code = """
        import json
        import tiny_kernels
        from rotaflex.core.jit import CompileTimer, announce_compilation, cache_is_cold
        said = []
        with CompileTimer(said.append) as timer:
            cold = cache_is_cold([tiny_kernels])
            first = announce_compilation("tiny", [tiny_kernels], 3.0)
            again = announce_compilation("tiny", [tiny_kernels], 3.0)
            tiny_kernels.plus_one(1.0)
        print(json.dumps({"cold": cold, "first": first, "again": again, "said": said,
                          "count": timer.count, "cold_after": cache_is_cold([tiny_kernels.plus_one])}))
    """
    one = _run(python_json, code, tmp_path)
    assert one["cold"] and one["first"] and not one["again"]
    assert one["said"] == ["compiling the tiny kernels once, ~3 s; later runs load them from the cache"]
    assert one["count"] == 1 and not one["cold_after"]  # compiled and written to the cache
    two = _run(python_json, code, tmp_path)  # a new process: numba loads the kernel from the cache
    assert not two["cold"] and not two["first"] and two["said"] == [] and two["count"] == 0


class _Reached(Exception):
    """Raised by a stand-in for a verb's first kernel call."""


def _cold(monkeypatch, cold: bool) -> list:
    """Pretend numba's disk cache is cold (or warm) for every kernel; a fresh announcement state."""
    import rotaflex.core.jit as jit

    monkeypatch.setattr(jit, "cache_is_cold", lambda kernels: cold)
    monkeypatch.setattr(jit, "_ANNOUNCED", set())
    return []


def _announced_before_kernels(monkeypatch, cold: bool, run, stand_in: tuple) -> list:
    """Lines written by the verb ``run`` before ``stand_in`` (module, name: its first kernel
    call) is reached; the stand-in records them and stops the run."""
    from rotaflex.core.jit import CompileTimer

    said = _cold(monkeypatch, cold)
    before = []

    def reached(*args, **kwargs):
        before.append(list(said))
        raise _Reached

    monkeypatch.setattr(*stand_in, reached)
    with CompileTimer(said.append):
        for _ in range(2):  # twice in one process: said once
            try:
                run()
            except _Reached:
                pass
    assert len(before) == 2  # the stand-in was reached both times
    assert before[0] == before[1] == said  # said before the first kernel call, not after
    return said


def test_gear_simulate_announces_its_kernels_once_before_the_first_kernel_call(monkeypatch):
    from rotaflex.gear.cases import simulate

    cfg = {"mesh": {"preset": "coarse"}, "operation": {"span_deg": 0.05}}

    def run():
        simulate.run_case(cfg)

    # as the CLI does: validate (builds the model, whose own kernels may compile on a cold
    # cache, outside the CLI's compile timer), then run
    simulate.validate_config(cfg)
    said = _announced_before_kernels(monkeypatch, True, run, (simulate, "_preload"))
    seconds = simulate.COMPILE_SECONDS["paper_rk4"]
    assert said == [f"compiling the gear kernels once, ~{seconds:.0f} s; later runs load them from the cache"]
    assert _announced_before_kernels(monkeypatch, False, run, (simulate, "_preload")) == []


def test_gear_steady_announces_its_kernels_once_before_the_first_kernel_call(monkeypatch):
    from rotaflex.gear.cases import steady, steady_size
    from rotaflex.gear.models import chain  # the chain model calls its kernel as chain.run_rk4

    cfg = {"mesh_stiffness": {"source": "contact_pattern", "table_points": 64}, "steady": {"fixed_cycles": 12}}

    said = _announced_before_kernels(monkeypatch, True, lambda: steady.run_torsional(cfg), (chain, "run_rk4"))
    seconds = steady_size.COMPILE_SECONDS["lumped"]
    assert said == [f"compiling the gear steady kernels once, ~{seconds:.0f} s; later runs load them from the cache"]
    assert _announced_before_kernels(monkeypatch, False, lambda: steady.run_torsional(cfg), (chain, "run_rk4")) == []


def test_floating_simulate_announces_its_kernels_once_before_the_first_kernel_call(monkeypatch):
    import tomllib

    from rotaflex.floating import case, solve

    example = Path(__file__).resolve().parents[2] / "examples" / "floating" / "planar_slew.toml"
    cfg = tomllib.loads(example.read_text())
    cfg.pop("domain", None)
    said = _announced_before_kernels(monkeypatch, True, lambda: case.run_case(cfg), (solve, "simulate"))
    assert said == [
        f"compiling the floating-body kernels once, ~{case.COMPILE_SECONDS:.0f} s; later runs load them from the cache"
    ]
    assert _announced_before_kernels(monkeypatch, False, lambda: case.run_case(cfg), (solve, "simulate")) == []
