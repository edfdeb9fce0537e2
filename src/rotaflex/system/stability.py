"""``rotaflex system stability``: API 617 Level I and Level II on a machine.

The rotor verb's analysis (:mod:`rotaflex.rotor.fe.stability`) on the machine's matrices: at the
drive's maximum continuous speed W every rotor r turns at ``Omega_r = sense_r ratio_r W`` with
its bearings, seals and magnetic bearings at that speed (frequency-dependent elements at the
mode's own damped frequency), the couplings and the meshes' mean stiffness, as the Campbell
diagram takes them (:func:`rotaflex.system.assembly.system_matrices`, on the solved coordinates
``q = T p``). The anticipated cross-coupling Q_A of the rotor named by ``stability.rotor``
(k_xy = Q, k_yx = -Q at its stage or mid-span nodes) enters as ``T^T K_Q T``. The first forward
modes are rotor/fe's criterion applied per rotor: rotor r's first forward mode is the
lowest-frequency oscillatory mode whose orbits on r's nodes whirl with r's spin (y of a rotor
turning clockwise is mirrored) and in which r carries at least ``MIN_SHARE`` = 0.1 of the
lateral motion; the machine's log decrement is the smallest of these (one rotor: the rotor
verb's mode; uncoupled rotors: the smaller of their own). Level II reports it with every element
and Q_A, and each seal's and Q_A's contribution; Level I sweeps Q on the named rotor with the
bearings alone (no seals) to Q_0.
The q_A formula's speed N is the named rotor's (``rated_speed_rpm``, default its ratio times
the drive's MCS), and the CSR is that rotor's speed over its own rigid-support critical speed.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rotaflex.core.config import param
from rotaflex.core.errors import InputError
from rotaflex.core.units import rpm_to_rad_s
from rotaflex.rotor.fe.bearings import registry
from rotaflex.rotor.fe.model import NDOF_NODE
from rotaflex.rotor.fe.stability import StabilitySpec
from rotaflex.system.model import Gearbox

__all__ = ["MachineStabilitySpec", "MachineSystem", "machine_level1", "machine_level2", "stability_result"]


@dataclass(frozen=True)
class MachineStabilitySpec(StabilitySpec):
    """``[stability]`` of a machine: the rotor verb's keys; ``speed_rpm`` is the drive's MCS."""

    rotor: str | None = param(None, doc="rotor whose stages carry Q_A (default: the only rotor)")


class MachineSystem:
    """A machine's matrices at one drive speed [rad/s], any subset of its elements assembled: the
    interface of rotor/fe's ``_System`` (labels ``<rotor>.<element>``, one flag per element of
    every rotor, rotor after rotor)."""

    def __init__(self, box: Gearbox, speed: float, judged=None):
        from rotaflex.system.assembly import matrices

        self.box, self.speed, self.mats = box, speed, matrices(box)
        #: the rotors whose first forward modes count (None: all; Level I: the screened one)
        self.judged = range(len(box.rotors)) if judged is None else judged
        self.labels, self.seal, self.counts = [], [], []
        for pr in box.rotors:
            self.counts.append(len(pr.rotor.bearing))
            for i, b in enumerate(pr.rotor.bearing):
                self.labels.append(f"{pr.name}.{b.name or f'bearing[{i}]'}")
                self.seal.append(registry.kind_of(b) in registry.SEALS)
        # per rotor: lateral DOFs of the shaft's nodes (rotor/fe order, pedestals left out) and
        # the sign that mirrors y of a rotor turning clockwise
        self._lateral = []
        for r, pr in enumerate(box.rotors):
            sign = np.ones(pr.rotor.n_rotor_dof)
            sign[1::NDOF_NODE] = pr.sense
            self._lateral.append((box.layout[r][0] + np.arange(pr.rotor.n_rotor_dof), sign))

    def _split(self, include) -> list[list[bool]]:
        ends = np.cumsum([0, *self.counts])
        return [list(include[a:b]) for a, b in zip(ends[:-1], ends[1:], strict=True)]

    def matrices(self, include, whirl=None):
        """M, K, C (C with the gyroscopic terms) on the solved coordinates with the elements whose
        flag in ``include`` is set; frequency-dependent ones at ``whirl`` [rad/s]."""
        from rotaflex.system.assembly import system_matrices

        M, D, K = system_matrices(self.box, self.speed, self.mats, include=self._split(include), whirl=whirl)
        return M, K, D

    def frequency_dependent_in(self, include) -> bool:
        els = [el for pr in self.box.rotors for _, _, el in pr.rotor.bearings]
        return any(keep and el.frequency_dependent for keep, el in zip(include, els, strict=True))

    def cross_couple(self, K, q_at: dict) -> None:
        """Add ``T^T K_Q T`` to K in place; ``q_at``: {(rotor index, node): Q [N/m]}."""
        if not q_at:
            return
        KQ = np.zeros((self.box.n_dof, self.box.n_dof))
        for (r, node), q in q_at.items():
            x, y = self.box.lateral_dof(r, node, 0), self.box.lateral_dof(r, node, 1)
            KQ[x, y] += q
            KQ[y, x] -= q
        K += self.mats.reduce(KQ)

    def lateral(self, vec: np.ndarray) -> tuple[list[np.ndarray], range | list[int]]:
        """Lateral shapes (m, 4 per node), one per rotor, of eigenvectors (m, n_solved) on the
        solved coordinates; the rotors judged."""
        full = self.mats.expand(vec.T).T
        return [full[:, idx] * sign for idx, sign in self._lateral], self.judged


def _named(box: Gearbox, spec: MachineStabilitySpec) -> int | None:
    """Index of the rotor named by ``stability.rotor`` (InputError naming the key); None for a
    pump without one (no Q_A)."""
    from rotaflex.rotor.fe.stability import NO_LEVEL1

    if spec.rotor is None and spec.machine in NO_LEVEL1:
        return None
    return box.rotor_index(spec.rotor, "stability.rotor")


def _q_stage(box: Gearbox, spec: MachineStabilitySpec, r: int) -> np.ndarray:
    """q_A per stage [N/m] at the named rotor's speed N (``rated_speed_rpm`` or ratio x MCS)."""
    from rotaflex.rotor.fe.stability import anticipated_cross_coupling

    return anticipated_cross_coupling(spec, spec.rated_speed_rpm or box.rotors[r].ratio * spec.speed_rpm)


def _q_nodes(box: Gearbox, spec: MachineStabilitySpec, r: int, q_stage: np.ndarray, q: float) -> dict:
    """{(rotor, node): Q [N/m]}: rotor/fe's placement (mid-span or over the stages) on rotor r."""
    from rotaflex.rotor.fe.stability import _q_nodes as rotor_q_nodes

    return {(r, n): v for n, v in rotor_q_nodes(box.rotors[r].rotor, spec, q_stage, q).items()}


def machine_level2(box: Gearbox, spec: MachineStabilitySpec):
    """API 617 Level II of the machine at the drive's MCS (module docstring).

    Returns
    -------
    Level2 (the smallest log dec over the rotors' first forward modes), and the log decrement
    and damped frequency [rad/s] of each rotor's own first forward mode in the full model
    (arrays over the rotors; NaN where no mode is that rotor's)."""
    from rotaflex.rotor.fe.stability import check, first_forward, level2_cases, log_dec

    speed = check(spec)
    r = _named(box, spec)
    q_stage = np.zeros(0) if r is None else _q_stage(box, spec, r)
    qa = _q_nodes(box, spec, r, q_stage, float(q_stage.sum())) if q_stage.size else {}
    system = MachineSystem(box, speed)
    l2 = level2_cases(system, qa, spec.log_dec_min)
    ld, wd = np.full(len(box.rotors), np.nan), np.full(len(box.rotors), np.nan)
    for k in range(len(box.rotors)):
        system.judged = [k]
        try:
            lam = first_forward(system, [True] * len(system.seal), qa)
        except InputError:  # no forward mode moves this rotor enough to be its own
            continue
        ld[k], wd[k] = log_dec(lam), lam.imag
    return l2, ld, wd


def machine_level1(box: Gearbox, spec: MachineStabilitySpec):
    """API 617 Level I of the named rotor in the machine: Q on its stage (mid-span) nodes, every
    rotor on its bearings without seals; CSR of that rotor alone on rigid supports."""
    from rotaflex.rotor.fe.stability import _System, check, level1_sweep, rigid_support_critical

    speed = check(spec)
    r = _named(box, spec)
    pr = box.rotors[r]
    q_stage = _q_stage(box, spec, r)
    own = abs(pr.ratio * speed)
    wcr = rigid_support_critical(pr.rotor, _System(pr.rotor, own))
    system = MachineSystem(box, speed, judged=[r])
    return level1_sweep(system, spec, q_stage, lambda q: _q_nodes(box, spec, r, q_stage, q), wcr, own)


def stability_result(config: dict, box: Gearbox, spec: MachineStabilitySpec, t0: float):
    """Level I (of ``stability.rotor``; not for a pump) and Level II of ``[stability]``, the rotor
    verb's dataset, summary and figures; every element's own outputs (seal leakage, AMB
    sensitivity) at its rotor's speed as ``<rotor>_<element>_<output>``. ``config`` and ``t0``
    (``time.perf_counter`` at the start) go into the summary. The verb is
    :func:`rotaflex.system.case.run_stability`, which reads the case and calls this."""
    from rotaflex.core.result import summary_attrs
    from rotaflex.rotor.fe.stability import NO_LEVEL1, check
    from rotaflex.rotor.fe.verbs_stability import stability_dataset
    from rotaflex.system.results import SystemStabilityResult

    check(spec)
    _named(box, spec)
    l1 = None if spec.machine in NO_LEVEL1 else machine_level1(box, spec)
    l2, ld_rotor, wd_rotor = machine_level2(box, spec)
    outputs = {}
    for pr in box.rotors:
        w = np.array([abs(pr.ratio) * rpm_to_rad_s(spec.speed_rpm)])
        for i, (b, (_, _, el)) in enumerate(zip(pr.rotor.bearing, pr.rotor.bearings, strict=True)):
            name = f"{pr.name}_{b.name or f'bearing[{i}]'}"
            for key, da in el.outputs(w).items():
                outputs[f"{name}_{key}"] = da.rename({d: f"{name}_{d}" for d in da.dims})
    ds, extra, msg = stability_dataset(spec, l1, l2, outputs)
    names = [pr.name for pr in box.rotors]
    ds = ds.assign_coords(rotor=names)
    ds["log_dec_rotor"] = ("rotor", ld_rotor, {"units": "1", "long_name": "each rotor's first forward mode log dec"})
    ds["frequency_rotor"] = ("rotor", wd_rotor, {"units": "rad/s", "long_name": "its damped frequency"})
    for name, d, w in zip(names, ld_rotor, wd_rotor, strict=True):
        extra[f"level2_log_dec[{name}]"] = {"value": float(d), "unit": "1", "frequency_hz": float(w / (2 * np.pi))}
    weakest = names[int(np.nanargmin(ld_rotor))]
    msg = msg.replace(" (limit", f" ({weakest}'s first forward mode; limit", 1)
    r = _named(box, spec)
    ds.attrs["q_rotor"] = "" if r is None else box.rotors[r].name
    if r is not None and l1 is not None:
        msg = f"rotor {ds.attrs['q_rotor']!r}: {msg}"
    ds.attrs.update(summary_attrs(config, t0, extra, msg))
    return SystemStabilityResult(ds)
