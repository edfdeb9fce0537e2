"""Results of the gear verbs: datasets, post-processing, figures and export.

* :mod:`~rotaflex.gear.results.transient` -- ``gear simulate`` dataset builder and figures;
* :mod:`~rotaflex.gear.results.steady` -- periodicity, cycle metrics and the steady-state result;
* :mod:`~rotaflex.gear.results.post` -- transmission error, fillet stress, static references;
* :mod:`~rotaflex.gear.results.export` -- VTU export for ParaView;
* :mod:`~rotaflex.gear.results.sweep_figures` -- the figures of a gear sweep.
"""
