"""Solvers of the gear models: the method registry, the drive loop, the steady-state runs.

* :mod:`~rotaflex.gear.solvers.registry` -- ``METHODS``: method name -> integrator;
* :mod:`~rotaflex.gear.solvers.drive_loop` -- the loop every compiled integrator runs in chunks,
  its status -> error map and its output type;
* :mod:`~rotaflex.gear.solvers.window_run` -- time integration and steady state of the window model;
* :mod:`~rotaflex.gear.solvers.speed_sweep` -- speed sweeps of the chain model with continuation.
"""
