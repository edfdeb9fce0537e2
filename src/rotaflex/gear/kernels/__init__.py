"""Compiled kernels of the gear-contact solvers, split by concern.

* :mod:`~rotaflex.gear.kernels.contact` -- spline surfaces, contact search, sliding terms;
* :mod:`~rotaflex.gear.kernels.passes` -- the constraint operator, the iterated and the direct
  multiplier solves;
* :mod:`~rotaflex.gear.kernels.rk4` -- the paper's RK4 stage loop with three passes per step
  (any number of contact pairs), :func:`~rotaflex.gear.kernels.rk4.run_steps`;
* :mod:`~rotaflex.gear.kernels.hht` -- Craig-Bampton teeth + HHT-alpha (method ``reduced_hht``);
* :mod:`~rotaflex.gear.kernels.arrays` -- the named argument groups of ``run_steps``.
"""
