"""The time estimate ``reproduce`` prints at its start comes from the measured numbers."""

import pytest

from rotaflex.reproduce import (
    FIRST_RUN_S,
    MEASURED_FAST_S,
    MEASURED_FULL_S,
    estimate,
    expected_seconds,
)


def test_estimate_adds_the_measured_stage_times():
    names = ["rotor", "gear", "floating", "sweep"]
    fast = sum(MEASURED_FAST_S[n] for n in names)
    # below 90 s in seconds, else in whole minutes
    said = f"about {fast:.0f} s" if fast < 90 else f"about {fast / 60:.0f} min"
    assert f"{said} on 2 cores with --fast" in estimate(names, True, load=0.0, cores=2)
    # the full settings: each section's own measured time, one after the other on one worker
    full = sum(MEASURED_FULL_S[n] for n in names)
    said = f"about {full:.0f} s" if full < 90 else f"about {full / 60:.0f} min"
    assert f"{said} on 2 cores once" in estimate(names, False, load=0.0, cores=2)
    assert sum(expected_seconds(n, False) for n in names) == pytest.approx(full)
    first = sum(FIRST_RUN_S.values())
    assert f"compiles them (about {first / 60:.0f} min" in estimate(names, True, load=0.0, cores=2)


def test_estimate_warns_on_a_busy_machine_only():
    assert "busy now (load average 15 on 2 cores)" in estimate(["rotor"], True, load=15.0, cores=2)
    assert "busy now" not in estimate(["rotor"], True, load=3.0, cores=2)


def test_sweep_alone_still_counts_the_kernels_it_compiles():
    assert "compiles them" in estimate(["sweep"], True, load=0.0, cores=2)
