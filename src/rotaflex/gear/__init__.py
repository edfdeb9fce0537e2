"""Spur-gear dynamics (seed C): one package, laid out by concern.

Data runs one way: TOML -> ``cases`` (config read, units converted to SI once) -> ``pair``
(what the gears are) -> ``models`` (frozen model, built once) -> ``solvers`` (a method from the
registry) -> ``results`` (xarray dataset, figures, files)::

    ``pair/``      the gears as data: ``geometry`` (involute, fillet, contact ratio), ``drawing`` (the one
                   ``[pinion]/[wheel]`` description, PairSpec), ``paper`` (the Lee & Jang pair preset),
                   ``tooth_mesh`` (8-node tooth mesh), ``plane_stress`` (element K, M, stresses),
                   ``contact_geometry`` (spline surfaces, contact search front end)
    ``static/``    ``tooth_analysis`` (tooth compliance, single-pair stiffness, TE, root stress),
                   ``loaded_te`` (loaded TE and load sharing of a general pair), ``iso6336_kv``
    ``models/``    ``fe_pair`` (rigid disks + FE teeth), ``multitooth``, ``reduced`` (Craig-Bampton),
                   ``chain`` (motor-shafts-gears-load torsional chain), ``window`` (elastic teeth in a
                   travelling window), ``lumped``, ``mesh_stiffness`` (k(phi)/TE tables from named
                   sources: the public interface for machine models)
    ``kernels/``   compiled (numba) kernels: ``contact``, ``passes``, ``rk4`` (paper scheme), ``hht``
                   (reduced), ``chain`` and ``window`` (steady models), ``arrays`` (named tuples)
    ``solvers/``   ``registry`` (METHODS: name -> integrator; ``rotaflex gear methods`` lists it),
                   ``drive_loop`` (chunked loop, status -> error, SolverOutput), ``steady_driver``
                   (the run-until-periodic loop of both steady methods, the continuation loop of
                   speed sweeps), ``window_run``
    ``results/``   ``transient`` (gear simulate dataset + figures), ``steady`` (periodicity, cycle
                   metrics), ``steady_sweep`` (speed-sweep dataset and figure), ``post`` (TE, fillet
                   stress), ``export`` (VTU), ``sweep_figures``
    ``cases/``     thin verbs: ``simulate`` (+ ``simulate_config``), ``static``, ``steady``

Public names (lazy; ``import rotaflex`` does not import this package): :class:`GearMesh`,
:func:`gear_mesh`, :class:`MeshTable` (``models.mesh_stiffness``), :class:`PairSpec`,
:func:`pair_from_mapping` (``pair.drawing``), and the geometry helpers below.
"""

from rotaflex.gear.pair.geometry import GearGeometry, contact_angles, contact_ratio, path_of_contact

#: the public interface other packages (geared rotor systems, sweeps) use; loaded on first access
_PUBLIC = {
    "GearMesh": "rotaflex.gear.models.mesh_stiffness",
    "MeshTable": "rotaflex.gear.models.mesh_stiffness",
    "gear_mesh": "rotaflex.gear.models.mesh_stiffness",
    "PairSpec": "rotaflex.gear.pair.drawing",
    "pair_from_mapping": "rotaflex.gear.pair.drawing",
}

__all__ = ["GearGeometry", "contact_angles", "contact_ratio", "path_of_contact", *_PUBLIC]


def __getattr__(name: str):
    if name in _PUBLIC:
        import importlib

        return getattr(importlib.import_module(_PUBLIC[name]), name)
    raise AttributeError(f"module 'rotaflex.gear' has no attribute {name!r}")
