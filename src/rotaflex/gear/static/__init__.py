"""Static analysis of a gear pair: tooth compliance, loaded transmission error, ISO 6336.

* :mod:`~rotaflex.gear.static.tooth_analysis` -- tooth compliance, single-pair mesh stiffness,
  transmission error and root stress from the FE tooth;
* :mod:`~rotaflex.gear.static.loaded_te` -- loaded TE and load sharing of a general pair;
* :mod:`~rotaflex.gear.static.iso6336_kv` -- ISO 6336-1 method B dynamic factor.
"""
