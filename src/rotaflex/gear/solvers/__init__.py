"""Solvers of the gear models: the method registry, the drive loop, the steady-state runs.

* :mod:`~rotaflex.gear.solvers.registry` -- ``METHODS``: method name -> integrator;
* :mod:`~rotaflex.gear.solvers.drive_loop` -- the loop every compiled integrator runs in chunks,
  its status -> error map and its output type;
* :mod:`~rotaflex.gear.solvers.window_run` -- time integration and steady state of the window model;
* :mod:`~rotaflex.gear.solvers.steady_loop` -- the run-until-periodic loop of both steady
  methods (``run_steady``) and of the geared-rotor steady state (``until_periodic``); it imports
  no model, so every model imports it;
* :mod:`~rotaflex.gear.solvers.steady_driver` -- the continuation loop of speed sweeps
  (``sweep_steady``; the dataset in :mod:`rotaflex.gear.results.steady_sweep`).
"""
