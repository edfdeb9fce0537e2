"""Compiled kernels of the gear-contact solvers, split by concern.

* :mod:`~rotaflex.gear.kernels.contact` -- spline surfaces, contact search, sliding terms;
* :mod:`~rotaflex.gear.kernels.passes` -- the constraint operator, the iterated and the direct
  multiplier solves;
* :mod:`~rotaflex.gear.kernels.forces` -- elastic force (2 x 2 node blocks of K), torques and the
  accelerations of a stage;
* :mod:`~rotaflex.gear.kernels.rk4` -- the paper's step in named pieces (RK4 stages, contact
  update, the three passes, record) and its loop :func:`~rotaflex.gear.kernels.rk4.run_steps`
  (any number of contact pairs);
* :mod:`~rotaflex.gear.kernels.hht` -- Craig-Bampton teeth + HHT-alpha (method ``reduced_hht``);
* :mod:`~rotaflex.gear.kernels.arrays` -- the named argument groups of ``run_steps``.
"""
