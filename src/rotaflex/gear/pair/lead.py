"""Lead (face-width) modifications of a gear flank, as on a drawing: crowning, end relief and
helix slope deviation.

Every modification is a depth of material removed from the flank, a function of the axial
position ``z`` [m] measured from mid-face along the gear axis (``-b/2 <= z <= b/2``), given, as
ISO 1328-1 gives helix deviations, in the transverse plane along the base-circle tangent, i.e.
along the transverse line of action: it opens a gap of exactly that depth between the flanks
of a slice at ``z`` (:func:`rotaflex.gear.static.helical.sliced_te`).

* crowning ``C_b``: ``c(z) = C_b (2 z / b)^2`` (parabolic, ``C_b`` at both face ends);
* end relief ``C_I`` over ``L_I`` from each end: ``c(z) = C_I t^p`` with
  ``t = (|z| - (b/2 - L_I)) / L_I`` on ``|z| > b/2 - L_I`` (p = 1 linear, 2 parabolic);
* helix slope deviation ``f_Hb``: ``c(z) = f_Hb z / b`` (more material removed towards
  ``+z``; a negative value the other way); a tilt of one gear in the plane of action by
  ``gamma`` [rad] (``[face] misalignment`` of ``gear static``) adds ``gamma z`` the same way.
"""

from __future__ import annotations

import dataclasses
from typing import Literal

import numpy as np

from rotaflex.core.config import param
from rotaflex.core.errors import InputError

__all__ = ["LeadSpec", "FaceConfig"]


@dataclasses.dataclass(frozen=True)
class LeadSpec:
    """Lead modifications of one gear (``[pinion.lead]``, ``[wheel.lead]``), depths in m."""

    crowning: float = param(0.0, unit="m", ge=0.0, le=1e-3, doc="crowning depth C_b at each face end")
    end_relief: float = param(0.0, unit="m", ge=0.0, le=1e-3, doc="end relief depth C_I at each face end")
    end_relief_length: float | None = param(None, unit="m", gt=0.0, doc="axial length L_I of each end relief")
    end_relief_shape: Literal["linear", "parabolic"] = param("linear", doc="depth ~ t or t^2")
    slope_deviation: float = param(0.0, unit="m", ge=-1e-3, le=1e-3, doc="helix slope deviation f_Hb over b")

    def check(self, face_width: float, where: str) -> LeadSpec:
        """Refuse an end relief without a length in (0, b/2]; return self."""
        if self.end_relief > 0.0:
            length = self.end_relief_length
            if length is None or length > 0.5 * face_width:
                raise InputError(
                    f"{where}.end_relief_length",
                    length,
                    f"a length in (0, {0.5 * face_width:.6g}] m (half the face width) with end_relief > 0",
                )
        return self

    @property
    def active(self) -> bool:
        """True if any modification is non-zero."""
        return self.crowning > 0.0 or self.end_relief > 0.0 or self.slope_deviation != 0.0

    def depth(self, z: np.ndarray, face_width: float) -> np.ndarray:
        """Material removed [m] at axial positions ``z`` [m] from mid-face."""
        z = np.asarray(z, dtype=float)
        b = face_width
        c = self.crowning * (2.0 * z / b) ** 2 + self.slope_deviation * z / b
        if self.end_relief > 0.0:
            length = self.end_relief_length
            t = np.clip((np.abs(z) - (0.5 * b - length)) / length, 0.0, 1.0)
            c = c + self.end_relief * (t if self.end_relief_shape == "linear" else t**2)
        return c


@dataclasses.dataclass(frozen=True)
class FaceConfig:
    """``[face]`` of gear static and gear steady: the face width in slices (helical or
    lead-modified pairs; docs/gear-helical.md)."""

    slices: int = param(20, ge=1, le=400, doc="slices over the face width")
    coupling_length_coef: float = param(
        1.0, ge=0.0, le=20.0, doc="shear-layer coupling length between slices / normal module"
    )
    misalignment: float = param(
        0.0, unit="rad", ge=-0.01, le=0.01, doc="tilt of the wheel relative to the pinion in the plane of action"
    )
