"""``rotaflex system frf``: receptance, mobility or accelerance between DOFs of a machine.

At a drive speed W every rotor r turns at ``Omega_r = sense_r ratio_r W``. A harmonic force (or
moment) ``e^{i w t}`` at an input DOF gives the response ``X e^{i w t}`` with

    [K(W) - w^2 M + i w D(W)] X = T^T e_in,    D(W) = C(W) + sum_r Omega_r G_r (+ c_m g g^T)

on the machine's solved coordinates ``q = T p`` (:mod:`.assembly`), with the matrices the
Campbell diagram takes (:mod:`.modal`: every rotor's bearings at that rotor's speed, mean mesh
stiffness, couplings). The solve is rotor/fe's one FRF solve
(:func:`~rotaflex.rotor.fe.frf.dynamic_solve`); the receptance is the output DOF of ``T X``.
Mobility is ``i w X`` and accelerance ``-w^2 X``; the dataset, peaks and half-power damping
are the rotor verb's (:func:`~rotaflex.rotor.fe.frf.frf_dataset`).
"""

from __future__ import annotations

import numpy as np

from rotaflex.core.errors import InputError
from rotaflex.rotor.fe.frf import DIRECTIONS, KINDS, FRFData, dynamic_solve, in_kind
from rotaflex.system.model import Gearbox

__all__ = ["MACHINE_DIRECTIONS", "machine_frf", "frf_result"]

#: a machine's DOFs per node: the rotor's four lateral ones and the twist (rotors with torsion)
MACHINE_DIRECTIONS = (*DIRECTIONS, "twist")


def machine_frf(box: Gearbox, frequencies, speed: float, inputs, outputs=None, kind="receptance") -> FRFData:
    """FRF matrix of ``box`` between full DOF numbers at drive ``speed`` [rad/s].

    Parameters
    ----------
    frequencies : array (f,) [rad/s]
    inputs, outputs : sequences of global DOF numbers (``box.lateral_dof``, ``box.torsion_dof``);
        outputs default to inputs. A DOF the machine does not solve for (the twist of a
        constant-speed drive node) takes no force and does not move.
    kind : {"receptance", "mobility", "accelerance"}

    Returns
    -------
    FRFData with ``H`` (f, n_out, n_in)

    Examples
    --------
    >>> # box = Gearbox.from_toml("examples/system/motor_coupling_pump.toml")
    >>> # machine_frf(box, [100.0, 200.0], 150.0, [box.lateral_dof(1, 5, 0)]).H.shape  # (2, 1, 1)
    """
    from rotaflex.system.assembly import matrices
    from rotaflex.system.modal import speed_pencil

    if kind not in KINDS:
        raise InputError("frf.kind", kind, "one of " + ", ".join(KINDS))
    w = np.atleast_1d(np.asarray(frequencies, float))
    inputs = list(inputs)
    outputs = inputs if outputs is None else list(outputs)
    mats = matrices(box)
    M, D, K = speed_pencil(box, mats, None)(speed)
    E = np.zeros((len(inputs), box.n_dof))
    E[np.arange(len(inputs)), inputs] = 1.0
    B = mats.project(E).T  # T^T e_in (n_solved, n_in)
    X = dynamic_solve(M, D, K, w, B)  # (f, n_solved, n_in)
    n = X.shape[1]
    full = mats.expand(X.transpose(1, 0, 2).reshape(n, -1)).reshape(box.n_dof, w.size, len(inputs))
    return FRFData(w, in_kind(full[outputs].transpose(1, 0, 2), w, kind), kind)


def _dofs(box: Gearbox, rows, key: str) -> tuple[list[int], list[str]]:
    """Global DOF numbers and labels (``"<rotor>:<node> <direction>"``) of ``[[frf.<key>]]``;
    errors name ``frf.<key>[i].rotor`` / ``.node`` / ``.direction`` as typed."""
    names = [pr.name for pr in box.rotors]
    dofs, labels = [], []
    for i, d in enumerate(rows):
        where = f"frf.{key}[{i}]"
        r = box.rotor_index(d.rotor, f"{where}.rotor")
        name = names[r]
        nn = box.rotors[r].rotor.n_nodes
        if not 0 <= d.node < nn:
            raise InputError(f"{where}.node", d.node, f"an existing node 0..{nn - 1} of rotor {name!r}")
        if d.direction not in MACHINE_DIRECTIONS:
            raise InputError(f"{where}.direction", d.direction, "one of " + ", ".join(MACHINE_DIRECTIONS))
        if d.direction == "twist":
            if not box.layout[r][2]:
                raise InputError(
                    f"{where}.direction", d.direction, f"x, y, theta_x or theta_y (rotor {name!r} has no torsion)"
                )
            dofs.append(box.torsion_dof(r, d.node))
        else:
            dofs.append(box.lateral_dof(r, d.node, DIRECTIONS.index(d.direction)))
        labels.append(f"{name}:{d.node} {d.direction}")
    return dofs, labels


def frf_result(config: dict, box: Gearbox, spec, t0: float):
    """FRFs of ``[frf]``: every output of ``[[frf.outputs]]`` per unit force (moment) at every
    input of ``[[frf.inputs]]``, at the drive ``speed_rpm`` over ``frequency_hz``; peaks with
    half-power damping as the rotor verb reports them. ``config`` and ``t0`` (start of the run,
    ``time.perf_counter``) go into the summary. The verb ``rotaflex system frf`` is
    :func:`rotaflex.system.case.run_frf`, which reads the case and calls this."""
    from rotaflex.core.result import summary_attrs
    from rotaflex.core.units import rpm_to_rad_s
    from rotaflex.rotor.fe.frf import frf_dataset, pair_unit
    from rotaflex.system.results import SystemFRFResult

    f0, f1 = spec.frequency_hz
    if f1 <= f0:
        raise InputError("frf.frequency_hz", list(spec.frequency_hz), "[start, stop] with stop > start")
    if spec.pair:
        raise InputError("frf.pair", "[[frf.pair]]", "absent on a machine: [[frf.inputs]] and [[frf.outputs]]")
    if not spec.inputs:
        raise InputError("frf.inputs", "<missing>", "at least one [[frf.inputs]] table (rotor, node, direction)")
    ins, in_labels = _dofs(box, spec.inputs, "inputs")
    outs, out_labels = _dofs(box, spec.outputs, "outputs") if spec.outputs else (ins, in_labels)
    w = np.linspace(f0, f1, spec.n_frequencies) * 2 * np.pi
    data = machine_frf(box, w, rpm_to_rad_s(spec.speed_rpm), ins, outs, spec.kind)
    # one pair per (output, input), output fastest: the rotor verb's dataset and figures
    H = data.H.transpose(0, 2, 1).reshape(w.size, -1)
    force = {"x": "Fx", "y": "Fy", "theta_x": "Mtheta_x", "theta_y": "Mtheta_y", "twist": "Mtwist"}
    labels = [f"{o} / {lab.split(' ')[0]} {force[lab.split(' ')[1]]}" for lab in in_labels for o in out_labels]
    units = [pair_unit(spec.kind, o.split(" ")[1], i.split(" ")[1]) for i in in_labels for o in out_labels]
    if len(set(labels)) != len(labels):
        raise InputError("frf.inputs", [*in_labels, *out_labels], "distinct inputs and distinct outputs")
    ds, extra, msg = frf_dataset(w, H, labels, spec.kind, spec.speed_rpm, units)
    ds.attrs.update(summary_attrs(config, t0, extra, msg.replace(" rpm;", " rpm drive speed;", 1)))
    return SystemFRFResult(ds)
