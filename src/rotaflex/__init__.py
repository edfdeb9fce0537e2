"""rotaflex: dynamics of rotating and flexible machine elements.

Domains
-------
rotation  finite rotations: Euler sequences, quaternions, angular-velocity maps (seed A)
rotor     rotor-disk equations of motion, derived symbolically and simulated (seed A)
floating  floating flexible bodies in quasi-coordinates, perturbation method (seed B)
gear      spur-gear dynamic contact with finite-element teeth (seed C)

``import rotaflex`` loads numpy and scipy only; domains are imported on use.
"""

from rotaflex.core.errors import ConvergenceError, InputError, SingularityError

__version__ = "0.1.0"
__all__ = ["ConvergenceError", "InputError", "SingularityError", "__version__"]
