"""``rotaflex system ucs``: undamped critical speed map of a machine vs the stiffness of chosen bearings.

The bearings of the rotors named in ``[ucs] rotors`` (default: all) become isotropic springs
kxx = kyy = k swept over ``[ucs] stiffness``; every other bearing keeps its direct stiffness
kxx, kyy at the drive speed ``[ucs] speed_rpm`` (each rotor at its own speed; damping,
cross-coupling and added mass dropped, as ``rotor ucs`` drops them for all bearings), flexible
couplings and the mean mesh stiffness are kept, rigid couplings and a constant-speed drive
constrain as in every machine analysis (:mod:`.assembly`). Pedestal DOFs are left out (the
bearing acts between its node and the ground), as in the rotor verb.

A critical speed is a drive speed W at which a natural frequency equals the 1X of the chosen
rotor c (``[ucs] rotor``, default the drive): with ``Omega_i = r_i W`` (signed: ``sense *
ratio``) and whirl ``omega = r_c W``, ``(K(k) - omega^2 (M - i G_r)) u = 0`` with
``G_r = sum_i (r_i / r_c) G_i``; rotor/fe's :func:`~rotaflex.rotor.fe.ucs.ucs_solve` solves
it and keeps the forward roots (whirl sense of each rotor relative to its own spin).
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla

from rotaflex.core.errors import InputError
from rotaflex.core.units import rad_s_to_rpm
from rotaflex.rotor.fe.figures import ucs_bearing_line
from rotaflex.rotor.fe.model import NDOF_NODE
from rotaflex.rotor.fe.ucs import support_stiffness, ucs_solve
from rotaflex.system.model import Gearbox

__all__ = ["UCSPencil", "machine_ucs", "ucs_pencil", "ucs_result"]


@dataclass(frozen=True)
class UCSPencil:
    """The arguments of :func:`~rotaflex.rotor.fe.ucs.ucs_solve` for a machine.

    Attributes
    ----------
    M, G, K0, K1 : ndarray (n, n) on the coordinates solved (solved machine coordinates without
        pedestal DOFs; without gear meshes also without twist and axial DOFs, which then do not
        couple to the lateral ones)
    Tx, Ty : ndarray (p, n) x and sense-signed y translations of every rotor node
    rigid : ndarray (n, r) or None, rigid-body twist (torque drive of a geared machine)
    factor : float, ``|r_c|``: whirl frequency per unit drive speed
    lines : list of (label, drive speeds [rad/s] or None, kxx, kyy) of the swept bearings
    """

    M: np.ndarray
    G: np.ndarray
    K0: np.ndarray
    K1: np.ndarray
    Tx: np.ndarray
    Ty: np.ndarray
    rigid: np.ndarray | None
    factor: float
    lines: list


def ucs_pencil(box: Gearbox, swept, chosen: int, speed: float | None) -> UCSPencil:
    """The UCS pencil of ``box``: bearings of the rotors ``swept`` (indices) per unit k,
    the others' kxx, kyy at the drive ``speed`` [rad/s] (None: no bearing needs a speed),
    whirl at the 1X of rotor ``chosen``."""
    from rotaflex.system.assembly import matrices

    mats = matrices(box)
    n = box.n_dof
    r = np.array([pr.sense * pr.ratio for pr in box.rotors], float)
    rel = r / r[chosen]
    K = mats.K0 + (mats.g.T * mats.k_mean) @ mats.g if len(mats.k_mean) else mats.K0.copy()
    unit, fixed, lines = [], [], []
    for i, pr in enumerate(box.rotors):
        off = box.layout[i][0]
        for (node, other, el), b in zip(pr.rotor.bearings, pr.rotor.bearing, strict=True):
            ends = (
                off + NDOF_NODE * node + np.arange(2),
                None if other is None else off + NDOF_NODE * other + np.arange(2),
            )
            label = f"{pr.name}:{b.name or node}"
            if i in swept:
                unit.append(ends)
                lines += [
                    (lab, None if sp is None else sp.tolist(), kx.tolist(), ky.tolist())  # JSON for the dataset
                    for lab, sp, kx, ky in ucs_bearing_line(label, el, abs(pr.ratio))
                ]
                continue
            if speed is None and not el.speed_independent:
                raise InputError(
                    "ucs.speed_rpm", "<missing>", f"a drive speed [rpm] for bearing {label}'s coefficients"
                )
            w = abs(pr.ratio * (speed or 0.0))
            pr.rotor.check_speeds([w], "ucs.speed_rpm")
            kb = el.coefficients(np.array([w]))[0][0]
            fixed.append((ends, np.diag(np.diag(kb))))  # direct terms only
    K += support_stiffness(n, [e for e, _ in fixed], [k for _, k in fixed])
    K1 = support_stiffness(n, unit, [np.eye(2)] * len(unit))
    G = sum(f * Gi for f, Gi in zip(rel, mats.G, strict=True))
    E = mats.expand(np.eye(mats.free.size))  # full DOFs of the solved coordinates
    Mr, Gr, Kr, K1r = (mats.reduce(X) for X in (mats.M, G, K, K1))
    lateral = np.zeros(n, bool)
    node = np.zeros(n, bool)  # the shaft nodes' lateral DOFs (not the pedestals')
    for i, pr in enumerate(box.rotors):
        off, nl, _ = box.layout[i]
        lateral[off : off + nl] = True
        node[off : off + pr.rotor.n_rotor_dof] = True
    keep = node[mats.free]
    lat = keep.copy()
    keep |= ~lateral[mats.free]
    if not (np.any(Mr[np.ix_(lat, ~lat & keep)]) or np.any(Kr[np.ix_(lat, ~lat & keep)])):
        keep = lat  # twist and axial motion do not couple to the lateral one (no gear mesh)
    Mr, Gr, Kr, K1r = (X[np.ix_(keep, keep)] for X in (Mr, Gr, Kr, K1r))
    E = E[:, keep]
    xs = [box.lateral_dof(i, j, 0) for i, pr in enumerate(box.rotors) for j in range(pr.rotor.n_nodes)]
    sign = np.array([np.sign(rel[i]) for i, pr in enumerate(box.rotors) for _ in range(pr.rotor.n_nodes)])
    Tx, Ty = E[xs], sign[:, None] * E[np.array(xs) + 1]
    twist = np.flatnonzero(~lateral[mats.free][keep])
    rigid = None
    if twist.size:  # motions of the twist (axial) coordinates alone that strain nothing
        Z = sla.null_space(Kr[:, twist])
        if Z.size:
            rigid = np.zeros((Kr.shape[0], Z.shape[1]))
            rigid[twist] = Z
    return UCSPencil(Mr, Gr, Kr, K1r, Tx, Ty, rigid, abs(float(r[chosen])), lines)


def machine_ucs(
    box: Gearbox,
    stiffness,
    swept,
    chosen: int,
    speed: float | None,
    n_modes: int,
    progress: Callable[[float, float], None] | None = None,
):
    """Critical drive speeds [rad/s] (s, n_modes), whirl frequencies [rad/s] and forward
    fractions of ``box`` at the support ``stiffness`` values [N/m] (see :func:`ucs_pencil`).

    Examples
    --------
    >>> # box = Gearbox.from_toml("examples/system/motor_coupling_pump.toml")
    >>> # W, w, f = machine_ucs(box, [1e8], [0, 1], 0, None, 4)
    """
    p = ucs_pencil(box, swept, chosen, speed)
    try:
        w, f = ucs_solve(p.M, p.G, p.K0, p.K1, stiffness, n_modes, p.Tx, p.Ty, p.rigid, progress)
    except np.linalg.LinAlgError as err:  # K not positive definite: a rotor left unsupported
        raise InputError(
            "ucs.rotors", [box.rotors[i].name for i in swept], "bearings that support every rotor (K is singular)"
        ) from err
    return w / p.factor, w, f, p


def ucs_result(config: dict, box: Gearbox, spec, speed: float | None, t0: float, progress=False):
    """The map of ``[ucs]`` (``spec``) as a :class:`~rotaflex.system.results.SystemUCSResult`;
    ``speed`` [rad/s] is the drive speed of the kept bearings (None: not given)."""
    import xarray as xr

    from rotaflex.core.result import summary_attrs
    from rotaflex.rotor.fe.case_output import progress_callback
    from rotaflex.system.results import SystemUCSResult

    if spec.stiffness[1] <= spec.stiffness[0]:
        raise InputError("ucs.stiffness", list(spec.stiffness), "[low, high] with high > low")
    swept = [box.rotor_index(name, f"ucs.rotors[{i}]") for i, name in enumerate(spec.rotors)]
    swept = sorted(set(swept)) if swept else list(range(len(box.rotors)))
    if spec.rotor is not None:
        chosen = box.rotor_index(spec.rotor, "ucs.rotor")
    else:  # the drive rotor (ratio 1)
        chosen = box.drive[0] if box.drive is not None else 0
    k = np.geomspace(spec.stiffness[0], spec.stiffness[1], spec.n_points)
    n_lat = sum(box.rotors[i].rotor.n_rotor_dof for i in range(len(box.rotors)))
    n_modes, note = spec.n_modes, ""
    if n_modes > n_lat // 2:  # forward roots: at most half the lateral DOFs
        n_modes, note = n_lat // 2, f"ucs.n_modes = {spec.n_modes} clamped to {n_lat // 2} (half the lateral DOFs)"
    with progress_callback(progress, k.size, "ucs", "stiffness") as report:
        W, w, f, p = machine_ucs(box, k, swept, chosen, speed, n_modes, report)
    names = [box.rotors[i].name for i in swept]
    ds = xr.Dataset(
        {
            "critical_speed": (("stiffness", "mode"), W, {"units": "rad/s", "long_name": "drive speed"}),
            "whirl_frequency": (
                ("stiffness", "mode"),
                w,
                {"units": "rad/s", "long_name": f"1X of {box.rotors[chosen].name}"},
            ),
            "forward_fraction": (("stiffness", "mode"), f, {"units": "1"}),
        },
        coords={"stiffness": ("stiffness", k, {"units": "N/m"}), "mode": np.arange(n_modes)},
    )
    extra = {
        "swept_rotors": {"value": names, "unit": ""},
        "critical_rotor": {"value": box.rotors[chosen].name, "unit": ""},
        "speed": {"value": None if speed is None else rad_s_to_rpm(speed), "unit": "rpm"},
    }
    extra |= {
        f"mode_{j}_critical_rpm_at_max_stiffness": {"value": float(rad_s_to_rpm(W[-1, j])), "unit": "rpm"}
        for j in range(n_modes)
        if np.isfinite(W[-1, j])
    }
    if note:
        extra["note"] = {"value": note, "unit": ""}
    msg = (
        f"{spec.n_points} stiffness values of the bearings of {', '.join(names)}, {n_modes} critical speeds each "
        f"(1X of {box.rotors[chosen].name}); at {k[-1]:.3g} N/m [rpm]: "
        + ", ".join(f"{v:.0f}" for v in rad_s_to_rpm(W[-1]) if np.isfinite(v))
        + (f"; {note}" if note else "")
    )
    ds.attrs.update(summary_attrs(config, t0, extra, msg))
    ds.attrs["bearing_lines"] = json.dumps(p.lines)
    return SystemUCSResult(ds)
