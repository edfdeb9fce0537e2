"""Time integrators of the gear pair: a method registry in the manner of ``scipy.integrate``.

``METHODS`` maps a method name to its integrator ``fn(model, **options) -> SolverOutput``
(like ``solve_ivp(method=...)``):

* ``"paper_rk4"`` -- the paper's scheme: classical RK4 with constant multipliers and three
  constraint passes per step (:func:`rotaflex.gear.kernels.rk4.run_steps`), any number of
  contact pairs, iterated (eq. 19-24) or direct multiplier solve, optional restitution and
  smoothed contact surfaces (:func:`rotaflex.gear.models.fe_pair.integrate`);
* ``"reduced_hht"`` -- Craig-Bampton teeth + implicit HHT-alpha with large steps
  (:func:`rotaflex.gear.models.reduced.simulate_reduced`).

All share the driver loop, the status -> error mapping and the output type of
:mod:`rotaflex.gear.solvers.drive_loop`.
"""

from __future__ import annotations

from collections.abc import Callable

from rotaflex.gear.solvers.drive_loop import STATUS, SolverOutput, drive, raise_status

__all__ = ["METHODS", "STATUS", "SolverOutput", "drive", "paper_rk4", "raise_status", "reduced_hht"]


def paper_rk4(model, **kw) -> SolverOutput:
    """The paper's RK4 scheme (see :func:`rotaflex.gear.models.fe_pair.integrate`)."""
    from rotaflex.gear.models.fe_pair import integrate

    return integrate(model, **kw)


def reduced_hht(model, *, modes: int = 20, **kw) -> SolverOutput:
    """Craig-Bampton teeth (``modes`` fixed-interface modes per tooth) + HHT-alpha (see
    :func:`rotaflex.gear.models.reduced.simulate_reduced`) of the FE pair ``model``."""
    from rotaflex.gear.models.reduced import build_reduced, simulate_reduced

    return simulate_reduced(build_reduced(model, modes), **kw)


#: method name -> integrator ``fn(model, **options) -> SolverOutput``
METHODS: dict[str, Callable[..., SolverOutput]] = {
    "paper_rk4": paper_rk4,
    "reduced_hht": reduced_hht,
}
