"""``rotaflex system transient``: linear time response of a machine with unbalance, at a constant
drive speed or on a linear ramp.

The drive speed is W(t) = W0 + alpha t; rotor r turns at ``Omega_r = f_r W`` with
``f_r = sense_r ratio_r`` and its angle is ``f_r phi(t)``, ``phi = W0 t + alpha t^2 / 2`` (the
integral of its own speed), so an unbalance u at phase b on rotor r loads its node with

    F_x = u (Omega_r^2 cos(f_r phi + b) + f_r alpha sin(f_r phi + b)),
    F_y = u (Omega_r^2 sin(f_r phi + b) - f_r alpha cos(f_r phi + b)),

the rotor verb's force (:mod:`rotaflex.rotor.fe.transient`) at the rotor's own speed and
acceleration. The equations are the machine's on its solved coordinates (:mod:`.assembly`:
couplings, mean mesh stiffness and mesh damping), with the Campbell diagram's
``(M, D, K)`` of :func:`.modal.speed_pencil`'s :func:`~.assembly.system_matrices` at each drive
speed of a grid (the ends and every bearing table breakpoint of each rotor, divided by its ratio)
and ``D = C + W sum_r f_r G_r``; between grid speeds C and K are interpolated linearly (bearings
and seals at the instantaneous speed, as the rotor verb takes them), M is taken at the mid speed
of the run and the spin-acceleration coupling is ``alpha sum_r f_r Kst_r``. The integration
(undamped modal basis at the mid speed, or all coordinates with Newmark) is rotor/fe's one
:func:`~rotaflex.rotor.fe.transient.linear_transient`.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from rotaflex.core.limits import require, require_memory
from rotaflex.core.units import rpm_to_rad_s
from rotaflex.rotor.fe.response import unbalance_force
from rotaflex.rotor.fe.transient import Pencil, TransientData, linear_transient, speed_grid
from rotaflex.rotor.fe.verbs_response import transient_peak
from rotaflex.system.model import Gearbox

__all__ = ["machine_pencil", "machine_transient", "transient_result"]

#: largest counts accepted: the rotor verb's (rotor/fe/case_config.py MAX_POINTS x 10, MAX_STEPS)
_MAX_OUTPUT, _MAX_STEPS = 10_000_000, 100_000_000


def machine_pencil(box: Gearbox, speed_start: float, speed_end: float, unbalance=(), mats=None) -> Pencil:
    """The machine's :class:`~rotaflex.rotor.fe.transient.Pencil` on its solved coordinates for a
    run from drive speed ``speed_start`` to ``speed_end`` [rad/s].

    Parameters
    ----------
    unbalance : sequence of (rotor index, node, magnitude [kg m], phase [rad])
        Grouped by the rotors' signed speed ratio (one phasor column per distinct ratio).
    """
    from rotaflex.system.assembly import matrices, system_matrices

    mats = matrices(box) if mats is None else mats
    lo, hi = min(speed_start, speed_end), max(speed_start, speed_end)
    grid = np.unique(np.concatenate([speed_grid(pr.rotor, lo, hi, abs(pr.ratio)) for pr in box.rotors]))
    fac = [float(pr.sense * pr.ratio) for pr in box.rotors]
    n = box.n_dof
    Gs, Ks = np.zeros((n, n)), np.zeros((n, n))
    for i, pr in enumerate(box.rotors):
        off, nl, _ = box.layout[i]
        sl = slice(off, off + nl)
        Gs[sl, sl] = fac[i] * pr.rotor.G
        Ks[sl, sl] = fac[i] * pr.rotor.Kst
    G, Kst = mats.reduce(Gs), mats.reduce(Ks)
    K, C = [], []
    for w in grid:
        _, D, Kw = system_matrices(box, float(w), mats)
        K.append(Kw)
        C.append(D - w * G)  # the gyroscopic part is added back at the instantaneous speed
    mid = 0.5 * (speed_start + speed_end)
    M, _, Kmid = system_matrices(box, mid, mats)
    groups = sorted({fac[r] for r, *_ in unbalance}, key=abs)
    F = np.zeros((n, len(groups)), complex)
    for r, node, u, phase in unbalance:
        g = groups.index(fac[r])
        i = box.lateral_dof(r, node, 0)
        F[i : i + 2, g] += unbalance_force(1.0, u, phase)  # per unit spin^2: u e^{i b}, -i u e^{i b}
    return Pencil(M, grid, np.stack(K), np.stack(C), G, Kst, mats.project(F.T).T, np.array(groups), lambda: Kmid, M)


def machine_transient(
    box: Gearbox,
    t_end: float,
    *,
    speed_start: float,
    speed_end: float | None = None,
    unbalance=(),
    method: str = "modal",
    n_modes: int = 20,
    n_output: int = 2001,
    steps_per_output: int = 4,
    rtol: float = 1e-7,
    atol: float = 1e-12,
    progress=None,
) -> TransientData:
    """Time response of ``box`` from rest over ``t_end`` [s], drive speed linear from
    ``speed_start`` to ``speed_end`` [rad/s]; ``q``, ``v`` on the full DOFs of the machine
    (:class:`~rotaflex.rotor.fe.transient.TransientData`, ``speed`` the drive's).

    Parameters
    ----------
    unbalance : sequence of (rotor index, node, magnitude [kg m], phase [rad])
    method, n_modes, n_output, steps_per_output, rtol, atol, progress
        As :func:`rotaflex.rotor.fe.transient.transient` takes them.

    Examples
    --------
    >>> # box = Gearbox.from_toml("examples/system/motor_coupling_pump.toml")
    >>> # machine_transient(box, 0.5, speed_start=155.0, unbalance=[(1, 5, 1e-3, 0.0)]).q.shape
    """
    from rotaflex.system.assembly import matrices

    speed_end = speed_start if speed_end is None else speed_end
    mats = matrices(box)
    p = machine_pencil(box, speed_start, speed_end, unbalance, mats)
    tr = linear_transient(
        p,
        t_end,
        speed_start=speed_start,
        speed_end=speed_end,
        method=method,
        n_modes=n_modes,
        n_output=n_output,
        rtol=rtol,
        atol=atol,
        steps_per_output=steps_per_output,
        progress=progress,
    )
    return TransientData(
        tr.time, mats.expand(tr.q.T).T, mats.expand(tr.v.T).T, tr.speed, tr.nfev, tr.wall_time, tr.message
    )


def check_size(spec, n_dof: int) -> None:
    """Refuse a run beyond the limits before it starts: the rotor verb's counts (output points,
    integration steps) and the memory of the history (q, v and the output on ``n_dof`` DOFs)
    plus six dense matrices of the machine."""
    require("transient.n_output", spec.n_output, spec.n_output, _MAX_OUTPUT, "output points")
    steps = spec.n_output * spec.steps_per_output if spec.method == "direct" else spec.n_output
    require("transient.steps_per_output", spec.steps_per_output, steps, _MAX_STEPS, "integration steps")
    state = 8.0 * (2 * n_dof) ** 2
    require_memory("transient.n_output", spec.n_output, spec.n_output * 3 * 8.0 * n_dof + 6 * state, "the history")


def transient_result(config: dict, box: Gearbox, spec, probes, t0: float, progress=False):
    """Run ``[transient]`` (``spec``) on ``box`` and give the
    :class:`~rotaflex.system.results.SystemTransientResult`: displacements x, y at the
    ``probes`` ((rotor index, node); None: the unbalance nodes) and the drive speed over time.
    The verb ``rotaflex system transient`` is :func:`rotaflex.system.case.run_transient`."""
    from rotaflex.core.result import summary_attrs
    from rotaflex.rotor.fe.case_output import progress_callback
    from rotaflex.system.assembly import free_dofs
    from rotaflex.system.results import SystemTransientResult
    from rotaflex.system.size import clamp_modes
    from rotaflex.system.unbalance import _masses

    ub = _masses(box, spec.mass, "transient")
    if probes is None:
        probes = list(dict.fromkeys((r, n) for r, n, *_ in ub)) or [(0, box.rotors[0].rotor.n_nodes // 2)]
    check_size(spec, box.n_dof)
    n_modes, note = clamp_modes(spec.n_modes, free_dofs(box).size, "transient.n_modes")
    w0, w1 = rpm_to_rad_s(spec.speed_rpm[0]), rpm_to_rad_s(spec.speed_rpm[1])
    with progress_callback(progress, spec.duration, "transient", "s") as report:
        tr = machine_transient(
            box,
            spec.duration,
            speed_start=w0,
            speed_end=w1,
            unbalance=ub,
            method=spec.method,
            n_modes=n_modes,
            n_output=spec.n_output,
            steps_per_output=spec.steps_per_output,
            progress=report,
        )
    cols = [box.lateral_dof(r, n, 0) for r, n in probes]
    disp = np.stack([tr.q[:, cols], tr.q[:, [c + 1 for c in cols]]], -1)  # (time, probe, axis)
    names = [f"{box.rotors[r].name}:{n}" for r, n in probes]
    ds = xr.Dataset(
        {
            "displacement": (("time", "probe", "axis"), disp, {"units": "m"}),
            "speed": ("time", tr.speed, {"units": "rad/s", "long_name": "drive speed"}),
            "rotor_speed": (
                ("time", "rotor"),
                np.outer(tr.speed, box.speeds(1.0)),
                {"units": "rad/s", "long_name": "signed spin speed"},
            ),
        },
        coords={
            "time": ("time", tr.time, {"units": "s"}),
            "probe": names,
            "axis": ["x", "y"],
            "rotor": [pr.name for pr in box.rotors],
        },
    )
    extra, msg = transient_peak(tr, disp, names)
    extra["speed_at_max_rpm"]["note"] = "drive speed at the largest radial displacement"
    if note:
        extra["note"] = {"value": note, "unit": ""}
    msg += f"; {note}" if note else ""
    ds.attrs.update(summary_attrs(config, t0, extra, msg))
    ds.attrs["nfev"] = tr.nfev
    return SystemTransientResult(ds)
