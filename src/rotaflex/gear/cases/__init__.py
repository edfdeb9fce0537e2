"""The gear verbs, thin: config -> model -> solver -> result.

* :mod:`~rotaflex.gear.cases.simulate` -- ``rotaflex gear simulate`` (schema in
  :mod:`~rotaflex.gear.cases.simulate_config`);
* :mod:`~rotaflex.gear.cases.static` -- ``rotaflex gear static``;
* :mod:`~rotaflex.gear.cases.steady` -- ``rotaflex gear steady``.
"""
