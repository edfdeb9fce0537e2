"""Floating flexible bodies: quasi-coordinate hybrid equations and the perturbation method.

Kwak & Seong (2005), "Dynamic analysis of space structure by using perturbation method". A body
is quadrature data (:mod:`~rotaflex.floating.body`, :mod:`~rotaflex.floating.fe`); the solvers
(:func:`~rotaflex.floating.solve.simulate`) integrate the full nonlinear hybrid equations or the
zero-order rigid + first-order linear time-varying perturbation equations. Heavy modules (numba
kernels, xarray) are imported only when a solver runs.
"""

from rotaflex.floating.api import State, run
from rotaflex.floating.beam import uniform_beam
from rotaflex.floating.body import Body, integrals, point_body
from rotaflex.floating.model import Initial, Load, Prescribed, Settings
from rotaflex.floating.modes_file import load_modes

__all__ = [
    "Body",
    "Initial",
    "Load",
    "Prescribed",
    "Settings",
    "State",
    "integrals",
    "load_modes",
    "point_body",
    "run",
    "uniform_beam",
]
