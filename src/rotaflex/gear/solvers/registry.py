"""The gear methods: one registry in the manner of ``scipy.integrate.solve_ivp``'s ``METHODS``.

``METHODS`` maps a method name to a :class:`Method`; every method has one contract::

    output = METHODS[name](model, settings)        # settings: a mapping of options (or keywords)

* ``"paper_rk4"`` -- the paper's scheme on the FE pair (:mod:`~rotaflex.gear.models.fe_pair`, or
  several teeth, :mod:`~rotaflex.gear.models.multitooth`): classical RK4 with constant
  multipliers and three constraint passes per step (:func:`rotaflex.gear.kernels.rk4.run_steps`),
  iterated (eq. 19-24) or direct multiplier solve, optional restitution and smoothed contact
  surfaces (:func:`rotaflex.gear.models.fe_pair.integrate`);
* ``"reduced_hht"`` -- Craig-Bampton teeth + implicit HHT-alpha with large steps
  (:func:`rotaflex.gear.models.reduced.simulate_reduced`) of the same FE pair;
* ``"lumped"`` -- the torsional chain (:class:`~rotaflex.gear.models.chain.TorsionalSystem`) with
  a mesh spring ``k(phi), e(phi)``, run to a periodic steady state
  (:func:`rotaflex.gear.models.chain.steady_state`);
* ``"elastic_teeth"`` -- the chain with FE tooth pairs in a travelling window
  (:class:`~rotaflex.gear.models.window.WindowModel`), run to a periodic steady state
  (:func:`rotaflex.gear.solvers.window_run.steady_state`).

Outputs: the transient methods (``verbs = ("simulate",)``) return a
:class:`~rotaflex.gear.solvers.drive_loop.SolverOutput` (histories, status, counters, wall
time); the steady methods (``verbs = ("steady", ...)``) return ``(SteadyStateResult, state)``,
the state to continue the next operating point from. ``settings`` holds the method's keyword
options (``speeds``, ``torque``, ``dt``, ... for transient; ``op``, ``state``, ``tol``, ... for
steady). ``rotaflex gear methods`` prints :func:`methods_table`.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

from rotaflex.gear.solvers.drive_loop import STATUS, SolverOutput, drive, raise_status

__all__ = [
    "METHODS",
    "STATUS",
    "Method",
    "SolverOutput",
    "drive",
    "methods_table",
    "paper_rk4",
    "raise_status",
    "reduced_hht",
    "steady_elastic_teeth",
    "steady_lumped",
]


def paper_rk4(model, **kw) -> SolverOutput:
    """The paper's RK4 scheme (see :func:`rotaflex.gear.models.fe_pair.integrate`)."""
    from rotaflex.gear.models.fe_pair import integrate

    return integrate(model, **kw)


def reduced_hht(model, *, modes: int = 20, **kw) -> SolverOutput:
    """Craig-Bampton teeth (``modes`` fixed-interface modes per tooth) + HHT-alpha (see
    :func:`rotaflex.gear.models.reduced.simulate_reduced`) of the FE pair ``model``."""
    from rotaflex.gear.models.reduced import build_reduced, simulate_reduced

    return simulate_reduced(build_reduced(model, modes), **kw)


def steady_lumped(model, *, op, state=None, **kw):
    """Steady state of the torsional chain with a mesh spring (see
    :func:`rotaflex.gear.models.chain.steady_state`); ``op`` an OperatingPoint."""
    from rotaflex.gear.models.chain import steady_state

    return steady_state(model, op, state=state, **kw)


def steady_elastic_teeth(model, *, op, state=None, **kw):
    """Steady state of the travelling window of FE tooth pairs (see
    :func:`rotaflex.gear.solvers.window_run.steady_state`); ``op`` an OperatingPoint."""
    from rotaflex.gear.solvers.window_run import steady_state

    return steady_state(model, op, state=state, **kw)


@dataclass(frozen=True)
class Method:
    """One registered method: the function and what a user needs to choose it.

    Attributes
    ----------
    name : str
        The key of :data:`METHODS` and the config value (``solver.method`` of ``gear simulate``,
        ``model.method`` of ``gear steady``).
    run : callable
        ``run(model, **settings) -> output``.
    models : str
        What it models.
    verbs : tuple of str
        The ``rotaflex gear`` verbs (and sweeps of them) that use it.
    cost : str
        Typical cost, measured (docs/gear-dynamics.md, docs/gear-steady-state.md).
    """

    name: str
    run: Callable[..., Any]
    models: str
    verbs: tuple[str, ...]
    cost: str

    def __call__(self, model, settings: Mapping[str, Any] | None = None, **kw):
        """``run(model, **settings, **kw)``: the one contract of every method."""
        return self.run(model, **dict(settings or {}), **kw)


#: method name -> :class:`Method` (call it as ``METHODS[name](model, settings)``)
METHODS: dict[str, Method] = {
    m.name: m
    for m in (
        Method(
            "paper_rk4",
            paper_rk4,
            "rigid disks + plane-stress FE teeth (1-12 per gear), contact by constraint passes (the paper)",
            ("simulate",),
            "~190-400 us per step on the default mesh (29,250 steps: 5.5-11 s at 4000 rpm)",
        ),
        Method(
            "reduced_hht",
            reduced_hht,
            "the same FE pair with Craig-Bampton teeth, implicit HHT-alpha, large steps",
            ("simulate",),
            "611 steps in 0.06 s (coarse mesh, 4000 rpm, 17.5 deg)",
        ),
        Method(
            "lumped",
            steady_lumped,
            "torsional chain (motor, shafts, gears, load, bearings) with a mesh spring k(phi), e(phi)",
            ("steady", "sweep"),
            "7 ms per 50-cycle steady point; 0.85 s for an 80-point up-and-down sweep",
        ),
        Method(
            "elastic_teeth",
            steady_elastic_teeth,
            "the chain with FE tooth pairs in a travelling window (load sharing, relief, corner contact)",
            ("steady", "sweep"),
            "18 ms per 50-cycle point (massless teeth), 113 ms with 4 tooth modes; 0.4 s model build",
        ),
    )
}


def methods_table() -> str:
    """The registry as plain text: name, what it models, verbs, typical cost (one block each)."""
    lines = []
    for m in METHODS.values():
        lines += [
            f"{m.name}",
            f"  models: {m.models}",
            f"  verbs:  {', '.join('gear ' + v if v != 'sweep' else 'sweep of gear steady' for v in m.verbs)}",
            f"  cost:   {m.cost}",
        ]
    return "\n".join(lines) + "\n"
