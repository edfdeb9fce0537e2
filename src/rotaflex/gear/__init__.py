"""Spur-gear dynamic contact with finite-element teeth (seed C).

Submodules: :mod:`~rotaflex.gear.geometry` (involute + rack-generated fillet),
:mod:`~rotaflex.gear.mesh` (8-node tooth mesh), :mod:`~rotaflex.gear.fe` (plane-stress element,
stiffness, HRZ mass, stable time step), :mod:`~rotaflex.gear.static` (tooth/mesh stiffness,
transmission error, root stress), :mod:`~rotaflex.gear.export` (VTU output).
Imported lazily: ``import rotaflex`` does not import this package.
"""

from rotaflex.gear.geometry import GearGeometry, contact_angles, contact_ratio, path_of_contact

__all__ = ["GearGeometry", "contact_angles", "contact_ratio", "path_of_contact"]
