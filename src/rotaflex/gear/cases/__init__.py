"""The gear verbs, thin: config -> model -> solver -> result.

* :mod:`~rotaflex.gear.cases.simulate` -- ``rotaflex gear simulate`` (schema in
  :mod:`~rotaflex.gear.cases.simulate_config`);
* :mod:`~rotaflex.gear.cases.static` -- ``rotaflex gear static``;
* :mod:`~rotaflex.gear.cases.steady` -- ``rotaflex gear steady`` (schema and checks in
  :mod:`~rotaflex.gear.cases.steady_config`, what a point writes besides the solver's metrics in
  :mod:`~rotaflex.gear.cases.steady_output`, size limits in :mod:`~rotaflex.gear.cases.steady_size`).
"""
