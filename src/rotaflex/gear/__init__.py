"""Spur-gear dynamic contact with finite-element teeth (seed C).

Submodules: :mod:`~rotaflex.gear.geometry` (involute + rack-generated fillet),
:mod:`~rotaflex.gear.mesh` (8-node tooth mesh), :mod:`~rotaflex.gear.fe` (plane-stress element,
stiffness, HRZ mass, stable time step), :mod:`~rotaflex.gear.static` (tooth/mesh stiffness,
transmission error, root stress), :mod:`~rotaflex.gear.export` (VTU output).
Public mesh interface for machine models: :class:`GearMesh`, :func:`gear_mesh`, :class:`MeshTable`
(:mod:`~rotaflex.gear.mesh_stiffness`), :class:`PairSpec` and :func:`pair_from_mapping` (the one
``[pinion]/[wheel]`` description). Imported lazily: ``import rotaflex`` does not import this package.
"""

from rotaflex.gear.geometry import GearGeometry, contact_angles, contact_ratio, path_of_contact

#: the public interface other packages (geared rotor systems, sweeps) use; loaded on first access
_PUBLIC = {
    "GearMesh": "rotaflex.gear.mesh_stiffness",
    "MeshTable": "rotaflex.gear.mesh_stiffness",
    "gear_mesh": "rotaflex.gear.mesh_stiffness",
    "PairSpec": "rotaflex.gear.drawing",
    "pair_from_mapping": "rotaflex.gear.drawing",
}

__all__ = ["GearGeometry", "contact_angles", "contact_ratio", "path_of_contact", *_PUBLIC]


def __getattr__(name: str):
    if name in _PUBLIC:
        import importlib

        return getattr(importlib.import_module(_PUBLIC[name]), name)
    raise AttributeError(f"module 'rotaflex.gear' has no attribute {name!r}")
