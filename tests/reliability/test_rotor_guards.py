"""Rotor run guards: step budget (estimate and at run time), failure before the first output
sample, and the verified cache of generated equation code."""

import os
import warnings

import numpy as np
import pytest

from rotaflex.core.errors import InputError
from rotaflex.rotor import symbolic
from rotaflex.rotor.case import model_from_config, run_case, validate_config
from rotaflex.rotor.simulate import EVALS_PER_STEP, estimated_steps, fastest_rate


def test_estimate_scales_with_t_end_and_spin():
    base = model_from_config({})
    # default disk: J = (2, 1, 1), spin 10 rad/s: fastest rate = (J_max / J_min) * 10 = 20 rad/s
    assert fastest_rate(base) == pytest.approx(20.0)
    long = model_from_config({"solver": {"t_end": 100.0}})
    fast = model_from_config({"motion": {"spin_speed": 100.0}})
    assert estimated_steps(long) == pytest.approx(10 * estimated_steps(base))
    assert estimated_steps(fast) == pytest.approx(10 * estimated_steps(base))


@pytest.mark.parametrize(
    ("config", "field"),
    [({"solver": {"t_end": 1e9}}, "solver.t_end"), ({"motion": {"spin_speed": 1e6}}, "motion.spin_speed")],
)
def test_hanging_runs_refused_up_front(config, field):
    with pytest.raises(InputError) as exc:
        validate_config(config)
    assert exc.value.field == field and "would take" in str(exc.value)


def test_run_time_budget_stops_a_run_the_estimate_let_through():
    # RK45 at rtol 1e-13 needs far more steps than the estimate assumes
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = run_case({"solver": {"t_end": 10.0, "max_steps": 1300, "method": "RK45", "rtol": 1e-13, "atol": 1e-16}})
    assert res.status == "failed"
    assert "step budget exceeded" in res.message
    evals = int(res.message.split("step budget exceeded: ")[1].split()[0])
    assert evals > 4 * EVALS_PER_STEP * 1300
    # nothing integrated is lost: the samples up to the stop are kept, ending at the stop time
    t = res.dataset["time"].values
    t_stop = float(res.message.split("reached t = ")[1].split()[0])
    assert t.size > 2 and 0.0 < t[-1] < 10.0 and t[-1] == pytest.approx(t_stop, rel=1e-5)
    # and they are the samples of the same run with room to finish (same steps up to the stop)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        full = run_case({"solver": {"t_end": 10.0, "max_steps": 10**6, "method": "RK45", "rtol": 1e-13, "atol": 1e-16}})
    kept = res.dataset["generalized_coordinate"].values[:-1]
    assert np.allclose(kept, full.dataset["generalized_coordinate"].values[: kept.shape[0]], rtol=0, atol=1e-12)


def test_failure_before_the_first_output_sample_is_reported():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = run_case({"solver": {"t_end": 1.0, "rtol": 1e-16, "atol": 1e-300}})
    assert res.status == "failed" and "failed after t = 0 s" in res.message
    assert res.dataset.sizes["time"] == 1 and float(res.dataset["time"][0]) == 0.0
    assert res.summary()["end_time"]["value"] == 0.0


def test_tampered_cache_is_not_executed(tmp_path, monkeypatch):
    monkeypatch.setenv("ROTAFLEX_CACHE_DIR", str(tmp_path))
    spec = symbolic.EOMSpec("euler", "123", "right-handed", "body", "second_order", 0)
    monkeypatch.setattr(symbolic, "_LOADED", {})
    ns = symbolic.compiled(spec)
    path = symbolic.cache_dir() / f"eom_{spec.key()}.py"
    assert path.exists() and path.with_suffix(".sha256").exists()
    assert (path.parent.stat().st_mode & 0o022) == 0
    # someone rewrites the cached code: it must not run (a marker file would appear if it did)
    marker = tmp_path / "ran"
    path.write_text(f"open({str(marker)!r}, 'w').close()\n" + path.read_text())
    monkeypatch.setattr(symbolic, "_LOADED", {})
    ns2 = symbolic.compiled(spec)
    assert not marker.exists()
    assert ns2["COORDINATES"] == ns["COORDINATES"]
    # a cache directory others can write to is not trusted either
    path.parent.chmod(0o777)
    try:
        assert symbolic._read_cached(path) is None
    finally:
        path.parent.chmod(0o700)
    assert os.stat(path.parent).st_uid == os.getuid()
