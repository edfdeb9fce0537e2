"""The one steady-state driver: procedure checked on prescribed signals, and both steady methods
run through it."""

import math
from dataclasses import dataclass, field

import numpy as np
import pytest

from rotaflex.core.errors import InputError
from rotaflex.gear.models.chain import ChainSteady, OperatingPoint, TorsionalSystem
from rotaflex.gear.models.mesh_stiffness import harmonic_mesh
from rotaflex.gear.solvers.steady_driver import run_steady

RB = 0.04177
K = 1.9e8


@dataclass
class _Prescribed:
    """A SteadyMethod whose 'integration' samples a prescribed force / DTE history, so the
    driver's bookkeeping can be checked against closed forms."""

    system: TorsionalSystem
    op: OperatingPoint
    signal: object  # t [cycles] -> (force [N], dte [m])
    spc: int = 64
    keep: tuple = ("time", "force", "dte")
    attrs: dict = field(default_factory=lambda: {"method": "prescribed"})
    runs: list = field(default_factory=list)
    chain: object = None

    def start(self, state):
        return {"t": 0.0} if state is None else state

    def steps_per_cycle(self, steps, points_per_period):
        return self.spc

    def run(self, st, n_cycles, spc):
        self.runs.append(n_cycles)
        t_mesh = 2 * math.pi / (self.op.omega * self.system.teeth[0])
        t = st["t"] + np.arange(n_cycles * spc + 1) / spc  # in mesh cycles, both ends
        st["t"] = float(t[-1])
        f, d = self.signal(t)
        return {"time": t * t_mesh, "force": f, "dte": d}

    def annotate(self, ds, buf, sl):
        ds["samples"] = ((), len(buf["time"][sl]))


def _system():
    return TorsionalSystem(mesh=harmonic_mesh(K, (), (1e-6,)), base_radius=(RB, RB))


def test_period_two_signal_found_after_its_transient_decays():
    """F = F0 (1 + 0.3 sin(pi t) + 0.5 exp(-t / 3)), t in mesh cycles: period 2. The transient's
    change over the last two cycles vs the two before, 0.5 (1 - exp(-2/3)) exp(-(n - 4) / 3)
    after n cycles, is 1.2e-3 at n = 20 and 4.2e-5 at n = 30: periodic at the check after 30
    cycles (tol 1e-4). Evaluated: cycles 20-30, whose largest force is at the sine's first
    sampled peak t = 20.5: K_v = 1.3 + 0.5 exp(-20.5 / 3)."""
    sys, op = _system(), OperatingPoint(6000.0, 50.0)
    f0 = op.torque / RB
    k_mean = sys.mesh.mean_stiffness

    def signal(t):
        f = f0 * (1.0 + 0.3 * np.sin(np.pi * t) + 0.5 * np.exp(-t / 3.0))
        return f, f / k_mean

    m = _Prescribed(sys, op, signal)
    r, st = run_steady(m, op, tol=1e-4, min_cycles=20, eval_cycles=10)
    ds = r.dataset
    assert ds.attrs["status"] == "success" and int(ds["period_cycles"]) == 2
    assert int(ds["cycles_run"]) == 30 and m.runs == [10, 10, 10]
    assert int(ds["samples"]) == 10 * m.spc == ds.sizes["time"]
    assert float(ds["dynamic_factor"]) == pytest.approx(1.3 + 0.5 * math.exp(-20.5 / 3.0), rel=1e-9)
    assert ds.attrs["method"] == "prescribed" and st["t"] == 30.0
    # the blocks join without a repeated or missing sample
    assert np.allclose(np.diff(ds["time"].values), ds["time"].values[1] - ds["time"].values[0], rtol=1e-9)


def test_quasi_periodic_signal_is_reported_not_periodic():
    """Two incommensurate frequencies (1 and sqrt 2 per cycle) never repeat: status
    not_periodic after max_cycles, with the smallest change in the message."""
    sys, op = _system(), OperatingPoint(6000.0, 50.0)
    f0 = op.torque / RB

    def signal(t):
        f = f0 * (1.0 + 0.1 * np.sin(2 * np.pi * t) + 0.1 * np.sin(2 * np.pi * math.sqrt(2) * t))
        return f, f / sys.mesh.mean_stiffness

    r, _ = run_steady(_Prescribed(sys, op, signal), op, max_cycles=60)
    assert r.dataset.attrs["status"] == "not_periodic"
    assert "not periodic after 60 mesh cycles" in r.dataset.attrs["message"]
    assert int(r.dataset["period_cycles"]) == 0


def test_fixed_cycles_runs_exactly_and_is_checked():
    sys, op = _system(), OperatingPoint(6000.0, 50.0)

    def signal(t):
        return np.full_like(t, 1e3), np.full_like(t, 1e-6)

    m = _Prescribed(sys, op, signal)
    r, _ = run_steady(m, op, fixed_cycles=25, eval_cycles=10)
    assert m.runs == [10, 10, 5] and int(r.dataset["cycles_run"]) == 25
    with pytest.raises(InputError, match="fixed_cycles"):
        run_steady(m, op, fixed_cycles=5, eval_cycles=10)


def test_lumped_method_through_the_driver_matches_its_own_histories():
    """Through the driver the chain's mean DTE is the static deflection, and a continuation
    from the returned state at the same speed is periodic at the first check and repeats the
    evaluated cycles."""
    sys, op = _system(), OperatingPoint(6000.0, 50.0)
    r, st = run_steady(ChainSteady(sys, op), op, tol=1e-6, max_cycles=400)
    assert r.dataset.attrs["status"] == "success"
    r2, _ = run_steady(ChainSteady(sys, op), op, tol=1e-6, state=st, min_cycles=10)
    assert int(r2.dataset["cycles_run"]) == 10
    static_deflection = op.torque / RB / sys.mesh.mean_stiffness
    np.testing.assert_allclose(r2.dataset["dte"].values, r.dataset["dte"].values, rtol=0, atol=1e-5 * static_deflection)
    # constant mesh stiffness, zero-mean TE: the mean DTE is the static deflection F0 / k
    assert float(r.dataset["dte_mean"]) == pytest.approx(static_deflection, rel=1e-3)
