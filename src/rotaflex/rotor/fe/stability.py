"""Stability as API 617 practises it: Level I screening and Level II analysis of the first forward mode.

Anticipated aerodynamic cross-coupling (API 617 8th ed. 2014, 1.8.5.x / 2.6.5; API RP 684 2nd ed.
2005, 2.9.5.5; Wachel & von Nimitz 1981). Per stage i, with its rated power P_i [W], the
speed N [rpm], its diameter D_i [m] and the flow restriction H_i [m]:

    q_A,i = B P_i C / (D_i H_i N) (rho_d / rho_s)_i

C = 9.55 = 60 / (2 pi) turns P / N into the stage torque T = P / Omega [N m], so
q_A = B T / (D H) (rho_d / rho_s) [N/m]; the standard's US form (hp, in, rpm -> klbf/in) has
C = 63. B = 3 and the density ratio for centrifugal compressors (D_c impeller diameter, H_c the
smaller of the impeller discharge width and the diffuser width); B = 1.5 and no density ratio for
axial compressors and turbines (D_t blade pitch diameter, H_t effective blade height). Q_A is the
sum over the stages.

Level I: the rotor on its bearings (seals left out), at the maximum continuous speed (MCS), with
a cross-coupled stiffness Q applied at mid-span (or split over the stages in proportion to
their q_A,i): k_xy = Q, k_yx = -Q, destabilising forward whirl. Q_0 is the Q at which the first
forward mode's log decrement is 0 (root found by Brent's method to 1e-6 relative); delta_A is
the log decrement at Q_A. The screening (API 617 8th ed.): a Level II analysis is required if
Q_0 / Q_A < 2, or delta_A < 0.1, or (centrifugal compressors) 2 <= Q_0 / Q_A < 10 and the
critical speed ratio CSR = MCS / (first critical speed on rigid supports) lies in region B of
the CSR versus mean gas density map (boundary CSR = 2.5 up to 16.53 kg/m^3, then linear to 2.0
at 60 kg/m^3; above 60 kg/m^3 every CSR is taken as region B, the map ends there).

Level II: the first forward mode at MCS with every bearing, seal and Q_A; accepted when its log
decrement is >= 0.1. Each seal's and Q_A's contribution is the change of the log decrement when
it is added to the bearings alone and when it is removed from the full model. A ``pump`` has no
Q_A and no Level I: its Level II has the bearings and seals only.

Frequency-dependent elements (magnetic bearings) are evaluated at the mode's own damped
frequency: the eigenproblem is solved again with the coefficients at the last mode's frequency
until it changes by less than WHIRL_RTOL (relative).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

import numpy as np
import scipy.linalg as sla

from rotaflex.core.config import param
from rotaflex.core.errors import InputError
from rotaflex.core.units import rad_s_to_rpm, rpm_to_rad_s
from rotaflex.rotor.fe.bearings import registry
from rotaflex.rotor.fe.model import NDOF_NODE, Rotor

#: the damped frequency of a mode iterated for frequency-dependent elements converges to this (relative)
WHIRL_RTOL = 1e-7
#: a machine's rotor owns a mode (as its first forward mode) when its nodes carry at least this
#: fraction of the mode's lateral motion sum |x|^2 + |y|^2: a rotor barely moved by a mode of
#: its neighbour does not take that mode as its own
MIN_SHARE = 0.1
#: ... and a mode is lateral when its x, y motion is at least this fraction of its whole |v|^2
#: (round-off puts ~1e-30 on the lateral DOFs of an uncoupled torsional mode)
LATERAL_MIN = 1e-6
#: API 617 acceptance / screening log decrement
LOG_DEC_MIN = 0.1
#: B of the q_A formula and whether the density ratio counts, per machine type
MACHINES = {"centrifugal_compressor": (3.0, True), "axial_compressor": (1.5, False), "turbine": (1.5, False)}
#: machines without anticipated aerodynamic cross-coupling: Level II only (seals and bearings, no Q_A)
NO_LEVEL1 = ("pump",)
#: the q_A constant C = 60 / (2 pi) ~ 9.55 (W, m, rpm -> N/m)
C_SI = 60.0 / (2 * np.pi)


@dataclass(frozen=True)
class Stage:
    """``[[stability.stage]]``: one impeller (or blade row) of the machine."""

    power: float = param(unit="W", gt=0, doc="rated power of the stage P")
    diameter: float = param(unit="m", gt=0, doc="impeller diameter D_c (blade pitch diameter D_t)")
    width: float = param(unit="m", gt=0, doc="min(impeller discharge, diffuser) width H_c (blade height H_t)")
    density_ratio: float = param(1.0, gt=0, doc="discharge / suction gas density (centrifugal compressors)")
    node: int | None = param(None, ge=0, doc="node of the stage (or give position)")
    position: float | None = param(None, unit="m")


@dataclass(frozen=True)
class StabilitySpec:
    """``[stability]``: API 617 Level I and Level II at the maximum continuous speed."""

    speed_rpm: float | None = param(None, unit="rpm", gt=0, doc="maximum continuous speed (MCS)")
    rated_speed_rpm: float | None = param(None, unit="rpm", gt=0, doc="speed N of the q_A formula (default MCS)")
    machine: Literal["centrifugal_compressor", "axial_compressor", "turbine", "pump"] = param(
        "centrifugal_compressor", doc="pump: no Q_A and no Level I; Level II with the bearings and seals"
    )
    stage: tuple[Stage, ...] = param((), doc="the stages (power, diameter, width): needed for Q_A")
    location: Literal["midspan", "stages"] = param("midspan", doc="where Q is applied in Level I (and Q_A in Level II)")
    mean_density: float | None = param(None, unit="kg/m^3", gt=0, doc="mean gas density (CSR map, compressors)")
    n_points: int = param(41, ge=3, doc="points of the Level I sweep from 0 to 2 max(Q_0, Q_A)")
    log_dec_min: float = param(LOG_DEC_MIN, doc="Level II acceptance log decrement")


@dataclass(frozen=True)
class Level1:
    """Level I outcome (SI)."""

    q_a: float  #: anticipated cross-coupling Q_A [N/m]
    q_stage: np.ndarray  #: q_A of each stage [N/m]
    q0: float  #: cross-coupling at zero log decrement [N/m] (inf: none up to the search limit)
    log_dec_a: float  #: first forward mode's log decrement at Q_A
    log_dec_0: float  #: ... at Q = 0
    frequency_a: float  #: its damped frequency at Q_A [rad/s]
    q: np.ndarray  #: sweep of Q [N/m]
    log_dec: np.ndarray  #: log decrement over the sweep
    csr: float  #: MCS / first critical speed on rigid supports
    rigid_critical: float  #: that critical speed [rad/s]
    region: str  #: "A", "B" or "" (not evaluated)
    reasons: tuple[str, ...]  #: why a Level II is required (empty: it is not)

    @property
    def ratio(self) -> float:
        return self.q0 / self.q_a

    @property
    def level2_required(self) -> bool:
        return bool(self.reasons)


@dataclass(frozen=True)
class Level2:
    """Level II outcome: log decrement of the first forward mode per element combination."""

    cases: tuple[str, ...]
    log_dec: np.ndarray
    frequency: np.ndarray  #: damped frequency [rad/s]
    full: float
    limit: float

    @property
    def passed(self) -> bool:
        return bool(self.full >= self.limit)


@dataclass
class _System:
    """A rotor's matrices at one speed, split by element so that any subset can be assembled.

    The interface :func:`first_forward`, :func:`level1_sweep` and :func:`level2_cases` take (a
    machine's counterpart is ``rotaflex.system.stability.MachineSystem``): ``speed`` [rad/s],
    ``labels`` and ``seal`` (one per element), ``matrices(include, whirl)``,
    ``cross_couple(K, q_at)``, ``frequency_dependent_in(include)`` and ``lateral`` (None: the
    eigenvectors are the rotor's own DOF vectors, which the whirl sense is judged on)."""

    rotor: Rotor
    speed: float
    labels: list[str] = field(default_factory=list)
    seal: list[bool] = field(default_factory=list)

    def __post_init__(self):
        for i, b in enumerate(self.rotor.bearing):
            self.labels.append(b.name or f"bearing[{i}]")
            self.seal.append(registry.kind_of(b) in registry.SEALS)

    def matrices(self, include, whirl=None):
        """M, K, C (C with the gyroscopic term) with the bearings whose flag in ``include`` is set
        (``Rotor.MKC``: the same assembly as every other analysis)."""
        wh = None if whirl is None else np.array([whirl])
        M, K, C = (a[0] for a in self.rotor.MKC(np.array([self.speed]), wh, include=include))
        return M, K, C + self.speed * self.rotor.G

    @property
    def frequency_dependent(self) -> bool:
        return any(el.frequency_dependent for _, _, el in self.rotor.bearings)

    def frequency_dependent_in(self, include) -> bool:
        """True when an included element depends on the whirl frequency (mode iteration needed)."""
        return any(include[i] and el.frequency_dependent for i, (_, _, el) in enumerate(self.rotor.bearings))

    def cross_couple(self, K, q_at: dict[int, float]) -> None:
        """Add k_xy = Q, k_yx = -Q at each node of ``q_at`` ({node: Q [N/m]}) to K in place."""
        for node, q in q_at.items():
            K[NDOF_NODE * node, NDOF_NODE * node + 1] += q
            K[NDOF_NODE * node + 1, NDOF_NODE * node] -= q

    #: eigenvectors are rotor DOF vectors: the whirl sense is judged on them as they are
    lateral = None


def _forward(M, K, C, n: int, lateral=None) -> tuple[complex, np.ndarray]:
    """Eigenvalue and shape of the lowest-frequency forward mode of M q'' + C q' + K q = 0.

    ``lateral``: function of the eigenvectors (m, n) giving a machine's lateral shapes, one array
    (m, 4 per node, rotor/fe order) per rotor, and the indices of the rotors judged; each judged
    rotor's first forward mode is the lowest one that whirls forward on its nodes and carries at
    least :data:`MIN_SHARE` of the mode's lateral motion, and the one of these with the smallest
    log decrement is returned. None: one rotor, the eigenvectors decide the whirl sense."""
    from rotaflex.rotor.fe.modal import Modes

    Minv = sla.inv(M)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-Minv @ K, -Minv @ C]])
    lam, vec = sla.eig(A, check_finite=False, overwrite_a=True)
    keep = lam.imag > 1e-9 * np.abs(lam).max()
    lam, vec = lam[keep], vec[:n, keep]
    order = np.argsort(lam.imag)
    lam, vec = lam[order], vec[:, order].T
    shapes, judged = ([vec], [0]) if lateral is None else lateral(vec)
    # a double eigenvalue (isotropic supports without gyroscopic splitting) has a forward and a
    # backward mode in any basis eig returns: it counts as forward
    gap = np.abs(lam[:, None] - lam[None, :])
    np.fill_diagonal(gap, np.inf)
    double = gap.min(1) < 1e-6 * np.abs(lam)
    motion = [np.sum(np.abs(s[:, 0::NDOF_NODE]) ** 2 + np.abs(s[:, 1::NDOF_NODE]) ** 2, 1) for s in shapes]
    total = sum(motion)
    # a machine's torsional (or axial) modes have no lateral motion: they are no rotor's mode
    lateral_mode = total >= LATERAL_MIN * np.sum(np.abs(vec) ** 2, 1)
    first = []
    for s, m in (z for i, z in enumerate(zip(shapes, motion, strict=True)) if i in judged):
        modes = Modes(np.zeros(1), lam[None], s[None])
        fw = (modes.whirl[0] == "forward") | (modes.forward_fraction[0] > 0.5) | double
        if lateral is not None:
            fw &= (m >= MIN_SHARE * total) & lateral_mode
        if fw.any():
            first.append(int(np.argmax(fw)))
    if not first:
        raise InputError("stability", "<model>", "a model with a forward whirling mode")
    j = min(first, key=lambda k: log_dec(lam[k]))
    return complex(lam[j]), vec[j]


def first_forward(system: _System, include, q_at: dict | None = None) -> complex:
    """Eigenvalue of the first forward mode with the bearings ``include`` and cross-coupling ``q_at``
    ({node: Q [N/m]}: k_xy = Q, k_yx = -Q); iterated on its own frequency for frequency-dependent
    elements. ``system``: a rotor's :class:`_System` or a machine's counterpart (same interface)."""
    whirl = None
    for _ in range(100):
        M, K, C = system.matrices(include, whirl)
        system.cross_couple(K, q_at or {})
        lam, _ = _forward(M, K, C, M.shape[0], system.lateral)
        if not system.frequency_dependent_in(include):
            return lam
        if whirl is not None and abs(lam.imag - whirl) <= WHIRL_RTOL * abs(lam.imag):
            return lam
        whirl = lam.imag
    raise InputError(
        "stability.speed_rpm", rad_s_to_rpm(system.speed), "a speed at which the mode frequency iteration converges"
    )


def log_dec(lam: complex) -> float:
    """-2 pi Re / Im."""
    return float(-2 * np.pi * lam.real / lam.imag)


def anticipated_cross_coupling(spec: StabilitySpec, speed_rpm: float) -> np.ndarray:
    """q_A of each stage [N/m] (API 617 / API 684; module docstring); none for a pump."""
    if spec.machine in NO_LEVEL1:
        return np.zeros(0)
    b, with_density = MACHINES[spec.machine]
    return np.array(
        [
            b * st.power * C_SI / (st.diameter * st.width * speed_rpm) * (st.density_ratio if with_density else 1.0)
            for st in spec.stage
        ]
    )


def rigid_support_critical(rotor: Rotor, system: _System) -> float:
    """First undamped natural frequency [rad/s] at zero speed with the support bearings' nodes pinned."""
    pinned = set()
    for keep, (node, other, _) in zip(np.logical_not(system.seal), rotor.bearings, strict=True):
        if keep and other is None:
            pinned |= {NDOF_NODE * node, NDOF_NODE * node + 1}
    free = np.array([d for d in range(rotor.n_dof) if d not in pinned])
    w2 = sla.eigh(rotor.K_shaft[np.ix_(free, free)], rotor.M[np.ix_(free, free)], eigvals_only=True)
    return float(np.sqrt(max(w2[w2 > 1e-6 * w2.max()].min(), 0.0)))


def csr_region(csr: float, density: float) -> str:
    """Region of the API 617 CSR vs mean gas density map (A: Level II by this test not required)."""
    if density > 60.0:
        return "B"
    bound = 2.5 if density <= 16.53 else 2.5 - (density - 16.53) * 0.5 / (60.0 - 16.53)
    return "B" if csr > bound else "A"


def _q_nodes(rotor: Rotor, spec: StabilitySpec, q_stage: np.ndarray, q: float) -> dict[int, float]:
    """Q [N/m] per node: all at mid-span, or split over the stages as their q_A,i."""
    if spec.location == "midspan":
        supports = [
            node
            for (node, other, _), b in zip(rotor.bearings, rotor.bearing, strict=True)
            if registry.kind_of(b) not in registry.SEALS
        ]
        z = 0.5 * (rotor.nodes[min(supports)] + rotor.nodes[max(supports)])
        return {int(np.argmin(np.abs(rotor.nodes - z))): q}
    out: dict[int, float] = {}
    for i, (st, qi) in enumerate(zip(spec.stage, q_stage, strict=True)):
        node = rotor.station(st.node, st.position, f"stability.stage[{i}]")
        out[node] = out.get(node, 0.0) + q * qi / q_stage.sum()
    return out


def check(spec: StabilitySpec) -> float:
    """The MCS [rad/s]; InputError naming the key when Level I lacks the speed or the stages' power."""
    if spec.speed_rpm is None:
        raise InputError("stability.speed_rpm", "<missing>", "the maximum continuous speed [rpm] > 0")
    if spec.machine in NO_LEVEL1:
        if spec.stage:
            raise InputError("stability.stage", "<tables>", f"no stages for machine = {spec.machine!r} (no Q_A)")
        return rpm_to_rad_s(spec.speed_rpm)
    if not spec.stage:
        raise InputError("stability.stage", "<missing>", "[[stability.stage]] tables with power, diameter, width")
    return rpm_to_rad_s(spec.speed_rpm)


def level1(rotor: Rotor, spec: StabilitySpec) -> Level1:
    """API 617 Level I screening at the MCS (module docstring)."""
    speed = check(spec)
    system = _System(rotor, speed)
    q_stage = anticipated_cross_coupling(spec, spec.rated_speed_rpm or spec.speed_rpm)
    return level1_sweep(
        system, spec, q_stage, lambda q: _q_nodes(rotor, spec, q_stage, q), rigid_support_critical(rotor, system), speed
    )


def level1_sweep(system, spec: StabilitySpec, q_stage: np.ndarray, q_nodes, wcr: float, speed: float) -> Level1:
    """Level I on ``system`` (a rotor's :class:`_System` or a machine's counterpart): its
    bearings (seals left out), Q placed by ``q_nodes(Q)`` ({node: Q [N/m]}), q_A per stage
    ``q_stage`` [N/m]; ``wcr`` the rigid-support critical speed and ``speed`` [rad/s] the
    screened rotor's MCS for the CSR."""
    from scipy.optimize import brentq

    bearings = [not s for s in system.seal]
    q_a = float(q_stage.sum())

    def ld(q):
        return log_dec(first_forward(system, bearings, q_nodes(q)))

    d0, da = ld(0.0), ld(q_a)
    q0, hi = np.inf, max(q_a, 1.0)
    if d0 > 0:
        for _ in range(60):  # bracket the root by doubling
            if ld(hi) < 0:
                q0 = brentq(ld, hi / 2 if hi > q_a else 0.0, hi, xtol=1e-12, rtol=1e-6)
                break
            hi *= 2
    else:
        q0 = 0.0
    qmax = 2 * max(q_a, q0) if np.isfinite(q0) else 10 * q_a
    q = np.linspace(0.0, qmax, spec.n_points)
    lds = np.array([ld(x) for x in q])
    csr = speed / wcr
    region = ""
    if spec.machine == "centrifugal_compressor" and spec.mean_density is not None:
        region = csr_region(csr, spec.mean_density)
    ratio = q0 / q_a
    reasons = []
    if ratio < 2.0:
        reasons.append(f"Q_0/Q_A = {ratio:.3g} < 2")
    if da < LOG_DEC_MIN:
        reasons.append(f"log dec at Q_A = {da:.3g} < {LOG_DEC_MIN}")
    if spec.machine == "centrifugal_compressor" and 2.0 <= ratio < 10.0:
        if region == "B":
            reasons.append(f"2 <= Q_0/Q_A = {ratio:.3g} < 10 and CSR = {csr:.3g} in region B")
        elif region == "":
            reasons.append(f"2 <= Q_0/Q_A = {ratio:.3g} < 10 and no mean_density for the CSR map")
    lam_a = first_forward(system, bearings, q_nodes(q_a))
    return Level1(q_a, q_stage, float(q0), da, d0, lam_a.imag, q, lds, csr, wcr, region, tuple(reasons))


def level2(rotor: Rotor, spec: StabilitySpec) -> Level2:
    """API 617 Level II at the MCS: every element and Q_A, with each seal's and Q_A's contribution."""
    speed = check(spec)
    system = _System(rotor, speed)
    q_stage = anticipated_cross_coupling(spec, spec.rated_speed_rpm or spec.speed_rpm)
    qa = _q_nodes(rotor, spec, q_stage, float(q_stage.sum())) if q_stage.size else {}
    return level2_cases(system, qa, spec.log_dec_min)


def level2_cases(system, qa: dict, limit: float) -> Level2:
    """Level II on ``system`` (a rotor's :class:`_System` or a machine's counterpart): the first
    forward mode with the bearings alone, each seal and Q_A (``qa``, {node: Q [N/m]}) added to
    them, each removed from the full model, and the full model; accepted at log dec >= ``limit``."""
    base = [not s for s in system.seal]
    seals = [i for i, s in enumerate(system.seal) if s]
    every = [True] * len(base)
    cases: list[tuple[str, list[bool], dict]] = [("bearings", base, {})]
    for i in seals:
        cases.append((f"bearings + {system.labels[i]}", [b or j == i for j, b in enumerate(base)], {}))
    if qa:
        cases.append(("bearings + Q_A", base, qa))
    for i in seals:
        cases.append((f"all - {system.labels[i]}", [j != i for j in range(len(base))], qa))
    if seals and qa:
        cases.append(("all - Q_A", every, {}))
    cases.append(("all", every, qa))
    lam = np.array([first_forward(system, inc, q) for _, inc, q in cases])
    ld = -2 * np.pi * lam.real / lam.imag
    return Level2(tuple(c[0] for c in cases), ld, lam.imag, float(ld[-1]), limit)
