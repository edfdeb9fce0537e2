"""Shaft coupling: a two-node element joining node a of one rotor to node b of another on the same axis.

A ``[[coupling]]`` table of a system file joins two rotors in series (a motor to a pump, a turbine
to a gearbox). The element follows the element contract of docs/architecture.md: K, C and M on
the DOFs it touches, per node ``[x, y, theta_x, theta_y, theta_z]`` (the system has no axial DOF,
so the contract's axial entry is absent here). The coupling force on side a is

    f_a = -Kd (q_a - q_b) - Cd (q_a' - q_b'),   f_b = -f_a,

with ``Kd = diag(k_r, k_r, k_b, k_b, k_t)`` (lateral, angular/bending, torsional stiffness) and
``Cd`` alike: a zero-length spring-damper between the two hub nodes (a disc, gear or elastomer
coupling seen from the shafts). Its mass, polar and diametral inertia are split to the two hubs
(``split`` on side a, the rest on side b) as thin rigid disks on the rotors (the rotor's disk
element; gyroscopic included); the element's own M is zero. A rotor without twist DOFs
(``torsion = false``) takes no torsional part.

``rigid = true`` is the exact limit: node b's DOFs are made equal to node a's by a constraint
(eliminated in the assembly, :func:`rotaflex.system.assembly.constraint`), so the two rotors
are one continuous rotor (tested to 1e-9 against the rotor built in one piece). A large finite
stiffness is the penalty approximation of it and converges to the same modes as 1/k.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rotaflex.core.config import param

#: per-node DOFs of the element, in this order (lateral of rotor/fe, then the twist)
NODE_DOFS = ("x", "y", "theta_x", "theta_y", "theta_z")


@dataclass(frozen=True)
class CouplingSpec:
    """A ``[[coupling]]`` table: two hub stations, stiffness and damping, mass and inertias."""

    rotor_a: str = param(doc="rotor of hub a")
    rotor_b: str = param(doc="rotor of hub b (on the same axis: the same centre)")
    node_a: int | None = param(None, ge=0, doc="node of hub a (or position_a)")
    position_a: float | None = param(None, unit="m")
    node_b: int | None = param(None, ge=0, doc="node of hub b (or position_b)")
    position_b: float | None = param(None, unit="m")
    name: str | None = param(None, doc="label in results (default: coupling<i>)")
    rigid: bool = param(False, doc="exact constraint: node b moves with node a (no stiffness keys)")
    torsional_stiffness: float | None = param(None, unit="N m/rad", gt=0, doc="required unless rigid")
    torsional_damping: float = param(0.0, unit="N m s/rad", ge=0)
    lateral_stiffness: float = param(0.0, unit="N/m", ge=0, doc="radial (parallel offset) stiffness")
    lateral_damping: float = param(0.0, unit="N s/m", ge=0)
    angular_stiffness: float = param(0.0, unit="N m/rad", ge=0, doc="bending (angular misalignment) stiffness")
    angular_damping: float = param(0.0, unit="N m s/rad", ge=0)
    mass: float = param(0.0, unit="kg", ge=0, doc="coupling mass, split to the hubs")
    Ip: float = param(0.0, unit="kg m^2", ge=0, doc="polar moment of inertia, split to the hubs")
    Id: float = param(0.0, unit="kg m^2", ge=0, doc="diametral moment of inertia, split to the hubs")
    split: float = param(0.5, ge=0, le=1, doc="fraction of mass and inertias on hub a")


@dataclass(frozen=True)
class CouplingElement:
    """A built coupling: hubs ``a``/``b`` as (rotor index, node), stiffness ``k`` and damping
    ``c`` (5,) per :data:`NODE_DOFS` [N/m, N m/rad; N s/m, N m s/rad], ``torsion`` (both rotors
    have twist DOFs), ``rigid`` (constraint instead of springs)."""

    name: str
    a: tuple[int, int]
    b: tuple[int, int]
    k: np.ndarray
    c: np.ndarray
    torsion: bool
    rigid: bool

    @property
    def n_node_dofs(self) -> int:
        return 5 if self.torsion else 4

    def K(self) -> np.ndarray:
        """Stiffness (2n, 2n) on ``[node a DOFs, node b DOFs]`` (n = 5, or 4 without twist)."""
        return _two_node(self.k[: self.n_node_dofs])

    def C(self) -> np.ndarray:
        """Damping (2n, 2n), same DOFs as :meth:`K`."""
        return _two_node(self.c[: self.n_node_dofs])

    def M(self) -> np.ndarray:
        """Mass (2n, 2n): zero, the coupling's mass and inertias are disks on the hubs."""
        n = self.n_node_dofs
        return np.zeros((2 * n, 2 * n))

    def dofs(self, box) -> np.ndarray:
        """Global DOF indices (2n,) of the element on a :class:`~rotaflex.system.model.Gearbox`."""
        out = []
        for r, node in (self.a, self.b):
            out += [box.lateral_dof(r, node, ax) for ax in range(4)]
            if self.torsion:
                out.append(box.torsion_dof(r, node))
        return np.array(out)

    def twist(self, q: np.ndarray, box) -> np.ndarray:
        """Twist across the coupling ``theta_a - theta_b`` [rad] of full DOF vectors q (..., n_dof)."""
        return q[..., box.torsion_dof(*self.a)] - q[..., box.torsion_dof(*self.b)]


def _two_node(d: np.ndarray) -> np.ndarray:
    D = np.diag(d)
    return np.block([[D, -D], [-D, D]])


def element(spec: CouplingSpec, a, b, torsion: bool, name: str) -> CouplingElement:
    """The element of a validated spec at stations ``a``, ``b`` (rotor index, node)."""
    kt = spec.torsional_stiffness or 0.0
    k = np.array([spec.lateral_stiffness] * 2 + [spec.angular_stiffness] * 2 + [kt])
    c = np.array([spec.lateral_damping] * 2 + [spec.angular_damping] * 2 + [spec.torsional_damping])
    return CouplingElement(name, a, b, k, c, torsion, spec.rigid)


__all__ = ["NODE_DOFS", "CouplingElement", "CouplingSpec", "element"]
