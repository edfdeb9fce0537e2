"""The compiled Newton iteration of the 3-D exact beam's time step.

Independent reference: the same equations, iteration matrix and update written with numpy
block products (``simulate_exact3d(..., kernel=False)``, a second implementation), on a slew
about an oblique axis with every kind of load (follower force, frame-fixed torque, distributed
load fixed in space) and Kelvin-Voigt damping: the same iteration counts and states to
round-off.
"""

from __future__ import annotations

import numpy as np
import pytest

from rotaflex.core.errors import ConvergenceError
from rotaflex.core.threads import limit_blas_threads
from rotaflex.floating import exact_step3d
from rotaflex.floating.exact_beam3d import PointLoads3D, cantilever3d
from rotaflex.floating.exact_solve3d import HubDrive, simulate_exact3d, simulate_hub3d
from rotaflex.floating.model import Prescribed


@pytest.fixture(autouse=True, scope="module")
def _one_blas_thread():
    with limit_blas_threads():
        yield


def slew(kernel: bool, eta: float):
    """A soft 1 m cantilever (tip deflection ~ 10 % L) slewed 1 rad about an oblique axis."""
    b = cantilever3d(1.0, 4, ea=1e3, ga=(800.0, 1200.0), gj=7.0, ei2=10.0, ei3=14.0, rho_a=1.0)
    pres = Prescribed(axis=(1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0), profile="versine", angle=1.0, duration=1.0)
    loads = PointLoads3D.build(
        b,
        [(1.0, 0.0, 0.0), (0.6, 0.0, 0.0)],
        ["force", "torque"],
        ["material", "body"],
        [(0.0, 0.3, 0.1), (0.2, 0.0, 0.1)],
        distributed=(0.0, 0.0, -0.5),
    )
    kw = {"t_end": 1.2, "dt_out": 0.1, "time_step": 0.01, "eta": eta, "kernel": kernel}
    return simulate_exact3d(b, loads, prescribed=pres.packed(), breakpoints=pres.breakpoints(), **kw)


@pytest.mark.parametrize("eta", [0.0, 0.01])
def test_compiled_step_equals_the_numpy_step(eta):
    fast, ref = slew(True, eta), slew(False, eta)
    assert fast.niter == ref.niter
    # the tip moves by ~0.8 m: states to round-off (the iteration is the same; only the order
    # of the sums in the products differs)
    assert np.abs(ref.q[-1, 28:31] - ref.q[0, 28:31]).max() > 0.5
    assert np.abs(fast.q - ref.q).max() < 1e-12
    assert np.abs(fast.v - ref.v).max() < 1e-11 * np.abs(ref.v).max()
    assert np.abs(fast.energy - ref.energy).max() < 1e-12 * np.abs(ref.energy).max()


def test_compiled_hub_equations_equal_the_numpy_ones():
    # a hub of 0.02 kg m^2 turned about an oblique axis by a bang-bang torque (0.5 s each way,
    # the breakpoints at the switches), a follower tip force on a soft, unequal beam
    b = cantilever3d(1.0, 4, ea=1e3, ga=(800.0, 1200.0), gj=7.0, ei2=10.0, ei3=14.0, rho_a=1.0)
    loads = PointLoads3D.build(b, [(1.0, 0.0, 0.0)], ["force"], ["material"], [(0.0, 0.2, 0.1)])
    hub = HubDrive(np.array([1.0, 2.0, 2.0]) / 3.0, 0.02, np.array([2.0]), np.array([3]), np.array([[0.0, 1.0, 0, 0]]))
    kw = {"t_end": 1.2, "dt_out": 0.1, "time_step": 0.01, "breakpoints": (0.5, 1.0)}
    fast, ref = (simulate_hub3d(b, loads, hub, kernel=k, **kw) for k in (True, False))
    assert fast.niter == ref.niter
    assert abs(ref.hub[-1, 0]) > 0.5  # the hub turned by more than 0.5 rad
    assert np.abs(fast.q - ref.q).max() < 1e-12
    assert np.abs(fast.hub - ref.hub).max() < 1e-11 * np.abs(ref.hub).max()
    assert np.abs(fast.energy - ref.energy).max() < 1e-12 * np.abs(ref.energy).max()


def test_a_diverging_step_is_refused_not_accepted():
    # a tolerance the iteration cannot reach within 2 iterations: ConvergenceError naming the
    # time, as the numpy path; and a NaN residual never counts as converged
    b = cantilever3d(1.0, 2, ea=1e3, ga=1e3, gj=7.0, ei2=10.0, ei3=10.0, rho_a=1.0)
    loads = PointLoads3D.build(b, [(1.0, 0.0, 0.0)], ["force"], ["inertial"], [(0.0, 5.0, 0.0)])
    for kernel in (True, False):
        with pytest.raises(ConvergenceError, match="generalized-alpha step"):
            simulate_exact3d(b, loads, t_end=0.01, dt_out=0.01, time_step=0.01, tol=1e-300, max_iter=2, kernel=kernel)
    n = b.n_dof
    r, m = np.zeros(n), np.zeros((n // 6, 3))
    f = np.zeros(n)
    f[7] = np.nan
    q, M = b.reference_state(), np.eye(n)
    res = exact_step3d.dynamic_residual(
        q, np.zeros(n), np.zeros(n), M, np.ones(n), f, np.zeros(n), np.arange(6, n), r, m
    )
    assert np.isnan(res)
