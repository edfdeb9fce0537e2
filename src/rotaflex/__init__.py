"""rotaflex: dynamics of rotating and flexible machine elements.

Domains
-------
rotation  finite rotations: Euler sequences, quaternions, angular-velocity maps (Yun & Ren 2008)
rotor     rotor-disk equations of motion, derived symbolically and simulated (Yun & Ren 2008)
floating  floating flexible bodies in quasi-coordinates, perturbation method (Kwak & Seong 2005)
gear      spur-gear dynamic contact with finite-element teeth (Lee & Jang)

``import rotaflex`` loads numpy and scipy only; domains are imported on use.
"""

from rotaflex.core.errors import ConvergenceError, InputError, SingularityError

__version__ = "0.1.0"
__all__ = ["ConvergenceError", "InputError", "SingularityError", "__version__"]
