"""Dynamic models of a gear pair (frozen data plus their builders).

* :mod:`~rotaflex.gear.models.fe_pair` -- rigid disks + elastic FE teeth (the paper's model);
* :mod:`~rotaflex.gear.models.multitooth` -- several elastic teeth per gear;
* :mod:`~rotaflex.gear.models.reduced` -- Craig-Bampton reduced teeth;
* :mod:`~rotaflex.gear.models.chain` -- torsional chain motor-shafts-gears-load with a mesh table;
* :mod:`~rotaflex.gear.models.window` -- reduced elastic teeth in a window travelling with the mesh;
* :mod:`~rotaflex.gear.models.lumped` -- lumped single-tooth-pair cross-check;
* :mod:`~rotaflex.gear.models.mesh_stiffness` -- mesh stiffness / TE tables from named sources (the
  public interface other packages use).
"""
