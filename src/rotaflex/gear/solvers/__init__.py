"""Solvers of the gear models: the method registry, the drive loop, the steady-state runs.

* :mod:`~rotaflex.gear.solvers.registry` -- ``METHODS``: method name -> integrator;
* :mod:`~rotaflex.gear.solvers.drive_loop` -- the loop every compiled integrator runs in chunks,
  its status -> error map and its output type;
* :mod:`~rotaflex.gear.solvers.window_run` -- time integration and steady state of the window model;
* :mod:`~rotaflex.gear.solvers.steady_driver` -- the steady-state driver of both steady methods and
  the continuation loop of speed sweeps (``sweep_steady``; the dataset in
  :mod:`rotaflex.gear.results.steady_sweep`).
"""
