"""Runners of the FE rotor verbs added to the modal set: ``static`` and ``frf``.

Each takes the parsed config (rotor tables plus its own analysis table), converts rpm to rad/s
once, calls the library function and wraps the outcome in a registered Result.
"""

from __future__ import annotations

import time

import numpy as np
import xarray as xr

from rotaflex.core.units import rpm_to_rad_s
from rotaflex.rotor.fe.case_config import parse
from rotaflex.rotor.fe.case_output import add_fluid_film_tables, summary_attrs
from rotaflex.rotor.fe.results import FRFResult, StaticResult


def run_static(config: dict, *, progress: bool = False) -> StaticResult:
    """Static analysis of ``[static]``: gravity sag, point loads, reactions, shear and moment."""
    from rotaflex.rotor.fe.static import static_analysis

    t0 = time.perf_counter()
    rotor, spec = parse(config, "static")
    loads = [(rotor.station(ld.node, ld.position, f"static.load[{i}]"), ld.fx, ld.fy) for i, ld in enumerate(spec.load)]
    speed = None if spec.speed_rpm is None else rpm_to_rad_s(spec.speed_rpm)
    s = static_analysis(rotor, gravity=spec.gravity, direction=spec.gravity_direction, loads=loads, speed=speed)
    ds, extra, msg = static_dataset(rotor, s)
    ds.attrs.update(summary_attrs(config, t0, extra, msg))
    res = StaticResult(add_fluid_film_tables(ds, rotor))
    check_static(res, s)
    return res


def static_dataset(rotor, s) -> tuple[xr.Dataset, dict, str]:
    """Dataset, summary entries and message of a rotor's static answer ``s``
    (:class:`~rotaflex.rotor.fe.static.StaticData`): deflection per node and within the
    elements, bearing reactions and loads, shear, moment and stress at the cuts. The rotor verb
    and the machine's (:mod:`rotaflex.system.static`, per rotor) both build their outputs here."""
    from rotaflex.rotor.fe.static import deflection_curve

    defl = s.deflection(rotor)
    nb = len(rotor.bearings)
    names = [b.name or f"bearing[{i}]" for i, b in enumerate(rotor.bearing)]
    ds = xr.Dataset(
        {
            "deflection": (("node", "axis"), defl, {"units": "m", "long_name": "static deflection"}),
            "z": ("node", rotor.nodes, {"units": "m"}),
            "reaction": (("bearing", "axis"), s.reactions, {"units": "N", "long_name": "force of bearing on rotor"}),
            "bearing_node": ("bearing", [n for n, _, _ in rotor.bearings]),
            "bearing_name": ("bearing", names),
            "shear": (("cut", "axis"), s.shear, {"units": "N", "long_name": "shear force"}),
            "moment": (("cut", "axis"), s.moment, {"units": "N m", "long_name": "bending moment"}),
            "stress": ("cut", s.stress, {"units": "Pa", "long_name": "largest bending stress"}),
            "z_cut": ("cut", s.z, {"units": "m"}),
            "deflection_curve": (
                ("cut", "axis"),
                deflection_curve(rotor, s.q),
                {"units": "m", "long_name": "deflection within the elements (shape functions)"},
            ),
        },
        coords={"node": np.arange(rotor.n_nodes), "axis": ["x", "y"], "bearing": np.arange(nb)},
    )
    r = np.hypot(defl[:, 0], defl[:, 1])
    mm = np.hypot(s.moment[:, 0], s.moment[:, 1])
    vv = np.hypot(s.shear[:, 0], s.shear[:, 1])
    jm, jv, jd = int(np.argmax(mm)), int(np.argmax(vv)), int(np.argmax(r))
    extra = {
        "total_mass": {"value": rotor.mass, "unit": "kg"},
        "applied_load_x": {"value": float(s.load_total[0]), "unit": "N"},
        "applied_load_y": {"value": float(s.load_total[1]), "unit": "N"},
        "max_deflection": {"value": float(r[jd]), "unit": "m", "node": jd, "z": float(rotor.nodes[jd])},
        "max_bending_moment": {"value": float(mm[jm]), "unit": "N m", "z": float(s.z[jm])},
        "max_shear_force": {"value": float(vv[jv]), "unit": "N", "z": float(s.z[jv])},
        "max_bending_stress": {"value": float(s.stress.max()), "unit": "Pa", "z": float(s.z[np.argmax(s.stress)])},
    }
    for i, nm in enumerate(names):
        extra[f"reaction_{nm}_x"] = {"value": float(s.reactions[i, 0]), "unit": "N"}
        extra[f"reaction_{nm}_y"] = {"value": float(s.reactions[i, 1]), "unit": "N"}
        extra[f"load_{nm}"] = {"value": float(s.bearing_loads[i]), "unit": "N", "node": rotor.bearings[i][0]}
    msg = (
        "bearing loads [N]: "
        + ", ".join(f"{nm} {v:.4g}" for nm, v in zip(names, s.bearing_loads, strict=True))
        + f"; max deflection {r[jd] * 1e6:.4g} um at node {jd}; max moment {mm[jm]:.4g} N m at z = {s.z[jm]:.4g} m"
    )
    return ds, extra, msg


#: largest bending slope [rad] of a linear static answer: small-rotation beam theory takes
#: sin(theta) = tan(theta) = theta, off by 0.3 % at 0.1 rad
MAX_SLOPE = 0.1
#: largest imbalance of applied loads and reactions, relative to the applied load
MAX_IMBALANCE = 1e-6


def check_static(res, s, label: str = "") -> None:
    """Mark a static answer outside linear theory or out of equilibrium as ``failed_check``
    (a 1e300 N load; a disk so heavy that the solve loses the equilibrium to round-off).

    Equilibrium: applied loads + bearing reactions (+ the forces of the other bodies of a
    machine, :attr:`~rotaflex.rotor.fe.static.StaticData.external`) = 0, relative to the applied
    load (to the larger of it and the external forces in a machine). ``label`` (a machine's
    rotor name) prefixes the check's name."""
    from rotaflex.rotor.fe.model import NDOF_NODE

    slope = np.abs(np.concatenate([s.q[2::NDOF_NODE], s.q[3::NDOF_NODE]]))
    applied = float(np.hypot(*s.load_total))
    residual = s.load_total + s.reactions.sum(0)
    if s.external is not None:
        residual = residual + s.external[:, :2].sum(0)
        applied = max(applied, float(np.abs(s.external[:, :2]).sum()))
    imbalance = float(np.hypot(*residual)) / applied if applied > 0 else 0.0
    pre = f"{label}: " if label else ""
    if not (np.all(np.isfinite(s.q)) and np.all(np.isfinite(s.reactions))):
        res.failed_check(pre + "finite answer", "non-finite deflections or reactions", "finite values")
    elif not slope.max(initial=0.0) <= MAX_SLOPE:
        res.failed_check(pre + "small slopes", f"{slope.max():.3g} rad", f"<= {MAX_SLOPE} rad for linear beam theory")
    elif not imbalance <= MAX_IMBALANCE:
        res.failed_check(pre + "equilibrium", f"{imbalance:.3g} of the applied load", f"<= {MAX_IMBALANCE:g}")


def run_frf(config: dict, *, progress: bool = False) -> FRFResult:
    """FRFs of ``[frf]`` at ``speed_rpm`` over ``frequency_hz``, with peaks and half-power damping."""
    from rotaflex.core.errors import InputError
    from rotaflex.rotor.fe.frf import dof_index, frf, frf_dataset, pair_unit

    t0 = time.perf_counter()
    rotor, spec = parse(config, "frf")
    f0, f1 = spec.frequency_hz
    if f1 <= f0:
        raise InputError("frf.frequency_hz", list(spec.frequency_hz), "[start, stop] with stop > start")
    node = rotor.disks[0][0] if rotor.disks else rotor.n_nodes // 2
    pairs = [(p.input_node, p.input_direction, p.output_node, p.output_direction) for p in spec.pair] or [
        (node, "x", None, None),
        (node, "y", None, None),
    ]
    ins, outs, labels, units = [], [], [], []
    for i, (a, da, b, db) in enumerate(pairs):
        b = a if b is None else b
        db = da if db is None else db
        ins.append(dof_index(rotor, a, da, f"frf.pair[{i}]", ("input_node", "input_direction")))
        outs.append(dof_index(rotor, b, db, f"frf.pair[{i}]", ("output_node", "output_direction")))
        labels.append(f"{db}{b}/{'F' if da in 'xy' else 'M'}{da}{a}")
        units.append(pair_unit(spec.kind, db, da))
    w = np.linspace(f0, f1, spec.n_frequencies) * 2 * np.pi
    speed = rpm_to_rad_s(spec.speed_rpm)
    uniq = sorted(set(ins))
    data = frf(rotor, w, speed, uniq, sorted(set(outs)), spec.kind)
    out_idx = {d: j for j, d in enumerate(sorted(set(outs)))}
    H = np.stack([data.H[:, out_idx[o], uniq.index(i)] for i, o in zip(ins, outs, strict=True)], 1)
    ds, extra, msg = frf_dataset(w, H, labels, spec.kind, spec.speed_rpm, units)
    ds.attrs.update(summary_attrs(config, t0, extra, msg))
    return FRFResult(add_fluid_film_tables(ds, rotor))
