"""The time estimate ``reproduce`` prints at its start comes from the measured numbers."""

import pytest

from rotaflex.reproduce import (
    FAST_BEFORE_CUTS_S,
    FIRST_RUN_S,
    FULL_OVER_FAST,
    MEASURED_FAST_S,
    estimate,
    expected_seconds,
)


def test_estimate_adds_the_measured_stage_times():
    names = ["rotor", "gear", "floating", "sweep"]
    fast = sum(MEASURED_FAST_S[n] for n in names)
    # below 90 s in seconds, else in whole minutes
    said = f"about {fast:.0f} s" if fast < 90 else f"about {fast / 60:.0f} min"
    assert f"{said} on 2 cores with --fast" in estimate(names, True, load=0.0, cores=2)
    # the full settings were not cut with --fast: their estimate scales the fast times before the cuts
    before = sum(FAST_BEFORE_CUTS_S[n] for n in names)
    full = before * FULL_OVER_FAST
    assert f"about {full / 60:.0f} min on 2 cores once" in estimate(names, False, load=0.0, cores=2)
    assert sum(expected_seconds(n, False) for n in names) == pytest.approx(214.0 * before / 75.2)
    first = sum(FIRST_RUN_S.values())
    assert f"compiles them (about {first / 60:.0f} min" in estimate(names, True, load=0.0, cores=2)


def test_estimate_warns_on_a_busy_machine_only():
    assert "busy now (load average 15 on 2 cores)" in estimate(["rotor"], True, load=15.0, cores=2)
    assert "busy now" not in estimate(["rotor"], True, load=3.0, cores=2)


def test_sweep_alone_still_counts_the_kernels_it_compiles():
    assert "compiles them" in estimate(["sweep"], True, load=0.0, cores=2)
