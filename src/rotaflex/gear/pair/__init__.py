"""The gear pair as data: involute geometry, the drawing description, tooth meshes, plane-stress FE.

* :mod:`~rotaflex.gear.pair.geometry` -- involute flank, rack-generated fillet, contact-ratio quantities;
* :mod:`~rotaflex.gear.pair.drawing` -- gears and pairs as on a drawing (the one ``[pinion]/[wheel]``
  description, :class:`~rotaflex.gear.pair.drawing.PairSpec`);
* :mod:`~rotaflex.gear.pair.tooth_mesh` -- the structured 8-node mesh of one tooth and its rim sector;
* :mod:`~rotaflex.gear.pair.plane_stress` -- the plane-stress 8-node element (stiffness, HRZ mass, stresses);
* :mod:`~rotaflex.gear.pair.contact_geometry` -- contact between two spline tooth surfaces;
* :mod:`~rotaflex.gear.pair.paper` -- the paper's pair (Lee & Jang), the one definition of its data.
"""
