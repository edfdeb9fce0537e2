"""``rotaflex system unbalance``: steady unbalance response of a machine vs drive speed.

Rotor r turns at the signed speed ``Omega_r = sense_r ratio_r W`` of the drive speed W, so its
unbalances excite the machine at ``w_r = Omega_r``. Unbalances of rotors with the same signed
speed act at one frequency and add as complex amplitudes; rotors at other speeds (a gearbox)
give responses at other frequencies, kept apart along the ``excitation`` dimension. Each is
rotor/fe's one solve (:func:`~rotaflex.rotor.fe.response.harmonic_solve`)

    [K(W) - w_r^2 M + i w_r D(W)] Q = F_r,    D(W) = C(W) + sum_s Omega_s G_s (+ c_m g g^T)

with the machine's matrices on its solved coordinates taken as the Campbell diagram takes
them (:mod:`.modal`: every rotor's own spin in its G and in its bearings' speed-dependent
coefficients, mean mesh stiffness) and F_r the rotor verb's unbalance force
(:func:`~rotaflex.rotor.fe.response.unbalance_force`) at the rotor's nodes.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import xarray as xr

from rotaflex.core.errors import InputError
from rotaflex.core.units import rad_s_to_rpm
from rotaflex.rotor.fe.response import harmonic_solve, unbalance_force
from rotaflex.system.model import Gearbox

__all__ = ["MachineUnbalance", "machine_unbalance", "unbalance_result"]


@dataclass(frozen=True)
class MachineUnbalance:
    """Complex response amplitudes of a machine per excitation (one per distinct rotor speed).

    Attributes
    ----------
    speed : ndarray (s,) drive speed [rad/s]
    factor : ndarray (g,) excitation frequency per unit drive speed (signed: ``sense ratio``)
    label : list of str, ``"<rotor>[+<rotor>] 1X"`` per excitation
    Q : ndarray (g, s, n_dof) complex, full DOF vector [m, rad], relative to ``e^{i factor W t}``
    """

    speed: np.ndarray
    factor: np.ndarray
    label: list
    Q: np.ndarray


def machine_unbalance(
    box: Gearbox, speeds, unbalance, progress: Callable[[float, float], None] | None = None
) -> MachineUnbalance:
    """Steady response of ``box`` to ``unbalance`` at drive ``speeds`` [rad/s].

    Parameters
    ----------
    unbalance : sequence of (rotor index, node, magnitude [kg m], phase [rad])
    progress : callable ``progress(done, total)``, optional

    Examples
    --------
    >>> # box = Gearbox.from_toml("examples/system/motor_coupling_pump.toml")
    >>> # machine_unbalance(box, [100.0, 150.0], [(1, 5, 1e-4, 0.0)]).Q.shape  # (1, 2, n_dof)
    """
    from rotaflex.system.assembly import matrices
    from rotaflex.system.modal import speed_pencil

    speeds = np.atleast_1d(np.asarray(speeds, float))
    mats = matrices(box)
    at = speed_pencil(box, mats, None)  # the Campbell diagram's (M, D, K) at a drive speed

    def pencil(sp):
        M, D, K = zip(*(at(w) for w in sp), strict=True)
        return np.stack(M), np.stack(D), np.stack(K)

    factors = sorted({float(box.rotors[r].sense * box.rotors[r].ratio) for r, *_ in unbalance}, key=abs)
    labels, Qs = [], []
    for k, fac in enumerate(factors):
        rows = [u for u in unbalance if float(box.rotors[u[0]].sense * box.rotors[u[0]].ratio) == fac]
        names = dict.fromkeys(box.rotors[r].name for r, *_ in rows)
        labels.append("+".join(names) + " 1X")
        w = fac * speeds
        F = np.zeros((speeds.size, box.n_dof), complex)
        for r, node, u, phase in rows:
            i = box.lateral_dof(r, node, 0)
            F[:, i : i + 2] += unbalance_force(w, u, phase)

        def report(done, total, k=k):
            progress(k * total + done, len(factors) * total)

        Q = harmonic_solve(pencil, speeds, mats.project(F), w, report if progress else None)
        Qs.append(mats.expand(Q.T).T)
    return MachineUnbalance(speeds, np.array(factors), labels, np.stack(Qs))


def _masses(box: Gearbox, masses, table: str = "unbalance") -> list[tuple[int, int, float, float]]:
    """``(rotor index, node, magnitude [kg m], phase [rad])`` of the ``[[<table>.mass]]`` tables."""
    out = []
    for i, m in enumerate(masses):
        where = f"{table}.mass[{i}]"
        r = box.rotor_index(m.rotor, f"{where}.rotor")
        node = box.rotors[r].rotor.station(m.node, m.position, where)
        out.append((r, node, m.magnitude, np.radians(m.phase_deg)))
    return out


def unbalance_result(config: dict, box: Gearbox, spec, probes, speeds: np.ndarray, t0: float, progress=False):
    """Unbalance response (Bode) at the ``probes`` ((rotor index, node) pairs; None: the
    unbalance nodes) over the drive ``speeds`` [rad/s]; peaks with AF and API 684 separation
    margins, per probe, as the rotor verb rates them. ``config`` and ``t0`` (start of the run,
    ``time.perf_counter``) go into the summary. The verb ``rotaflex system unbalance`` is
    :func:`rotaflex.system.case.run_unbalance`, which reads the case and calls this."""
    from rotaflex.rotor.fe.api import merge_probe_peaks, rate_peaks
    from rotaflex.rotor.fe.case_output import progress_callback
    from rotaflex.rotor.fe.response import peaks
    from rotaflex.rotor.fe.verbs_response import PEAK_FLOOR, _bands, margin_verdict, peak_entries
    from rotaflex.system.results import SystemUnbalanceResult

    ub = _masses(box, spec.mass)
    if not ub:
        raise InputError(
            "unbalance.mass", "<missing>", "at least one [[unbalance.mass]] table (rotor, node, magnitude)"
        )
    bands, _ = _bands(spec)
    if probes is None:
        probes = list(dict.fromkeys((r, n) for r, n, *_ in ub))
    with progress_callback(progress, speeds.size, "unbalance", "speed") as report:
        res = machine_unbalance(box, speeds, ub, progress=report)
    X = np.stack([res.Q[:, :, box.lateral_dof(r, n, 0)] for r, n in probes], -1)  # (g, s, p)
    Y = np.stack([res.Q[:, :, box.lateral_dof(r, n, 1)] for r, n in probes], -1)
    major = 0.5 * (np.abs(X + 1j * Y) + np.abs(X - 1j * Y))
    names = [f"{box.rotors[r].name}:{n}" for r, n in probes]
    floor = PEAK_FLOOR * major.max()
    pk = []
    for g, label in enumerate(res.label):
        per = {
            j: [q for q in peaks(speeds, major[g, :, j], range_end=True) if q["amplitude"] >= floor]
            for j in range(len(probes))
        }
        found = merge_probe_peaks(per)
        if bands:
            found = rate_peaks(found, bands)
        for p in found:
            p["probe"] = names[p["probe"]]
            p["probes"] = [names[j] for j in p["probes"]]
            p["af_by_probe"] = {names[int(j)]: v for j, v in p["af_by_probe"].items()}
            p["excitation"] = label
        pk += found
    u = {"units": "m"}
    dims = ("excitation", "speed", "probe")
    ds = xr.Dataset(
        {
            "x_real": (dims, X.real, u),
            "x_imag": (dims, X.imag, u),
            "y_real": (dims, Y.real, u),
            "y_imag": (dims, Y.imag, u),
            "x_amplitude": (dims, np.abs(X), u),
            "y_amplitude": (dims, np.abs(Y), u),
            "x_phase": (dims, np.angle(X), {"units": "rad", "long_name": "phase of x (lag < 0)"}),
            "y_phase": (dims, np.angle(Y), {"units": "rad", "long_name": "phase of y (lag < 0)"}),
            "major_axis": (dims, major, {**u, "long_name": "orbit semi-major axis"}),
            "frequency_factor": ("excitation", res.factor, {"units": "1", "long_name": "excitation / drive speed"}),
            "speed_rpm": ("speed", rad_s_to_rpm(speeds), {"units": "rpm"}),
        },
        coords={"speed": ("speed", speeds, {"units": "rad/s"}), "probe": names, "excitation": res.label},
    )
    extra = peak_entries(pk)
    for i, p in enumerate(pk):
        extra[f"peak_{i}_speed_rpm"].update(excitation=p["excitation"], note="drive speed")
    rated = [p for p in pk if p["kind"] == "resonance"]
    msg = f"{spec.n_speeds} drive speeds, {len(probes)} probes, {len(res.label)} excitation(s); peaks [rpm]: " + (
        ", ".join(f"{rad_s_to_rpm(p['speed']):.0f} (AF {p['af']:.1f}, {p['probe']})" for p in rated) or "none"
    )
    msg += margin_verdict(pk, bands)
    from rotaflex.core.result import summary_attrs

    ds.attrs.update(summary_attrs(config, t0, extra, msg))
    ds.attrs["peaks"] = json.dumps(pk)
    ds.attrs["bands"] = json.dumps(bands)
    return SystemUnbalanceResult(ds)
