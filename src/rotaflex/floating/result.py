"""``FloatingResult``: the xarray view of one or more floating-body solutions."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from rotaflex.core.result import Result, register_result


@register_result
class FloatingResult(Result):
    """Result of ``rotaflex floating simulate`` (kind ``"floating"``).

    Dimensions: ``solution`` (``full``, ``perturbation`` or ``prescribed``), ``time``, ``axis``
    (x, y, z), ``quat`` (e0..e3), ``mode``, ``point`` (named output points). Perturbation runs also
    carry the zero-order and first-order parts (``zero_order_*``, ``first_order_*``).
    """

    kind = "floating"
    #: deformed-shape series (:class:`rotaflex.floating.paraview.Frames`) written by
    #: :meth:`write_extra` into ``paraview/``; set by ``run_case`` for a case with ``[paraview]``
    paraview = None

    def write_extra(self, out_dir: Path) -> list[Path]:
        """The ParaView series ``paraview/<solution>_00000.vtu ...`` and ``paraview/<solution>.pvd``
        if the case asked for it (``[paraview]``); nothing otherwise."""
        if self.paraview is None:
            return []
        from rotaflex.floating.paraview import write_frames

        name, series = self.paraview
        return write_frames(series, Path(out_dir) / "paraview", name)

    def summary(self):
        ds = self.dataset
        out = super().summary()
        for s in ds["solution"].values:
            sel = ds.sel(solution=s)
            for pt in ds["point"].values:
                d = np.linalg.norm(sel["point_deflection"].sel(point=pt).values, axis=-1)
                out[f"{s}.{pt}.max_deflection"] = {"value": float(np.nanmax(d)), "unit": "m"}
            e = sel["energy"].values
            ok = np.isfinite(e)
            if ok.sum() > 1:
                out[f"{s}.energy_change"] = {"value": float(e[ok][-1] - e[ok][0]), "unit": "J"}
            out[f"{s}.final_euler_123"] = {
                "value": sel["euler_123"].values[-1].tolist(),
                "unit": "rad",
            }
            out[f"{s}.final_euler_123_deg"] = {
                "value": np.degrees(sel["euler_123"].values[-1]).tolist(),
                "unit": "deg",
            }
        out.update(deflection_measure(ds))
        if "manoeuvre" in ds.attrs:
            out.update(residual_vibration(ds))
        if {"full", "perturbation"} <= set(ds["solution"].values) and ds.sizes["point"]:
            d = ds["point_position"].sel(solution="perturbation") - ds["point_position"].sel(solution="full")
            out["max_point_difference_perturbation_vs_full"] = {
                "value": float(np.nanmax(np.linalg.norm(d.values, axis=-1))),
                "unit": "m",
            }
        return out

    def plot(self):  # noqa: C901 - one panel after the other
        from rotaflex.core.plotting import new_figure

        ds = self.dataset
        t = ds["time"].values
        figs = {}
        fig, ax = new_figure()
        eul = ds["euler_123"].values
        big = np.nanmax(np.abs(eul)) if np.isfinite(eul).any() else 0.0
        # components that stay at round-off level (e.g. the out-of-plane angles of a planar
        # manoeuvre) are not drawn as signal
        shown = [a for a in range(3) if np.nanmax(np.abs(eul[..., a]), initial=0.0) > 1e-9 * big]
        for s in ds["solution"].values:
            for a in shown:
                ax.plot(t, ds["euler_123"].sel(solution=s).values[:, a], label=f"{s} {'xyz'[a]}")
        if "zero_order_euler_123" in ds:
            ax.plot(t, ds["zero_order_euler_123"].values[:, 2], "k--", lw=1, label="zero order z")
        hidden = [n for a, n in enumerate("xyz") if a not in shown]
        if hidden:
            ax.set_title(f"{', '.join(hidden)} angle(s) zero to round-off (not drawn)", fontsize=8)
        ax.set_xlabel("time [s]")
        ax.set_ylabel("Euler 1-2-3 angles [rad]")
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=7)
        ax.grid(alpha=0.3)
        figs["attitude"] = fig
        if ds.sizes["point"]:
            fig, ax = new_figure()
            u_all = ds["point_deflection"].values
            scale, unit = _length_unit(np.nanmax(np.abs(u_all)) if np.isfinite(u_all).any() else 0.0)
            sols = list(ds["solution"].values)
            styles = {"full": "-", "prescribed": "-", "perturbation": "--"}
            notes = []
            for i_pt, pt in enumerate(ds["point"].values):
                u0 = ds["point_deflection"].sel(solution=sols[0], point=pt).values
                k = int(np.argmax(np.nan_to_num(np.abs(u0)).max(axis=0)))
                for s in sols:
                    u = ds["point_deflection"].sel(solution=s, point=pt).values[:, k]
                    # solution -> line style (dashed on top of solid), point -> colour: lines that
                    # coincide stay visible as a dashed line over a solid one
                    ax.plot(
                        t,
                        u / scale,
                        ls=styles.get(str(s), "-"),
                        lw=2.2 if styles.get(str(s), "-") == "-" and len(sols) > 1 else 1.2,
                        color=f"C{i_pt}",
                        label=f"{pt} {'xyz'[k]} ({s})",
                    )
                if len(sols) > 1:
                    d = ds["point_deflection"].sel(point=pt).values[:, :, k]
                    diff = np.nanmax(np.abs(d[1:] - d[0]))
                    notes.append(f"{pt}: max |{sols[1]} - {sols[0]}| = {diff / scale:.3g} {unit}")
            if "manoeuvre" in ds.attrs:
                ax.axvline(json.loads(ds.attrs["manoeuvre"])["end"], color="0.5", lw=0.8, ls=":")
            if notes:
                ax.set_title("; ".join(notes), fontsize=8)
            ax.set_xlabel("time [s]")
            ax.set_ylabel(f"elastic deflection (body axes) [{unit}]")
            ax.legend(fontsize=7)
            ax.grid(alpha=0.3)
            figs["deflection"] = fig
        if "modal_displacement" not in ds:  # the exact body has no modes
            return figs
        fig, ax = new_figure()
        s0 = ds["solution"].values[0]
        q = ds["modal_displacement"].sel(solution=s0).values
        for j, lab in enumerate(ds["mode"].values[: min(6, q.shape[1])]):
            ax.plot(t, q[:, j], label=str(lab))
        ax.set_xlabel("time [s]")
        ax.set_ylabel(f"modal coordinates ({s0}) [kg^0.5 m]")
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3)
        figs["modal"] = fig
        return figs


#: largest deflection / L up to which the modal body is adequate: measured tip errors <= 1e-3
#: relative for end forces, slews and spin-up (docs/floating.md "When to use which body")
MODAL_LIMIT = 0.01


def deflection_measure(ds) -> dict:
    """``<solution>.max_deflection_to_length`` (the largest deflection of the body's nodes, or of
    the output points for the modal body, over the body length) and
    ``<solution>.modal_body_adequate`` (that measure <= :data:`MODAL_LIMIT`)."""
    length = ds.attrs.get("body_length")
    if not length:
        return {}
    out = {}
    for s in ds["solution"].values:
        sel = ds.sel(solution=s)
        if "deflection_to_length" in ds:
            r = sel["deflection_to_length"].values
        elif ds.sizes["point"]:
            r = np.linalg.norm(sel["point_deflection"].values, axis=-1) / length
        else:
            continue
        r = float(np.nanmax(r)) if np.isfinite(r).any() else float("nan")
        out[f"{s}.max_deflection_to_length"] = {"value": r, "unit": "1"}
        out[f"{s}.modal_body_adequate"] = {
            "value": bool(r <= MODAL_LIMIT),
            "note": f"modal body adequate up to deflection / L = {MODAL_LIMIT:g} (tip error <= 1e-3 "
            "relative measured); beyond, use body.model = 'exact' (docs/floating.md)",
        }
    return out


def _length_unit(peak: float) -> tuple[float, str]:
    """Scale [m] and unit label for lengths whose largest magnitude is ``peak`` [m]."""
    from rotaflex.core.plotting import pretty_unit

    for scale, unit in ((1.0, "m"), (1e-3, "mm"), (1e-6, "um")):
        if peak >= scale:
            return scale, pretty_unit(unit)
    return 1e-6, pretty_unit("um")


def residual_vibration(ds) -> dict:
    """Residual vibration after a slew (``attrs["manoeuvre"]``), per solution and output point.

    ``<s>.<pt>.residual_amplitude`` [m]: largest elastic deflection after the manoeuvre;
    ``<s>.<pt>.settling_time`` [s]: time after the manoeuvre's end from which the deflection
    stays inside the band (``slew.settle_tolerance``, default 5 % of its largest value during
    the manoeuvre), null if it leaves the band at the last sample; ``<s>.slew_angle_deg``: the
    final rotation about the slew axis and ``<s>.slew_angle_error_deg`` its difference from the
    target; ``<s>.residual_angle_error_deg``: the largest difference after the manoeuvre.
    """
    man = json.loads(ds.attrs["manoeuvre"])
    t = ds["time"].values
    after = t >= man["end"] - 1e-12 * max(1.0, abs(man["end"]))
    during = ~after
    axis = np.asarray(man["axis"], dtype=float)
    out = {}
    for s in ds["solution"].values:
        sel = ds.sel(solution=s)
        e = sel["quaternion"].values
        ang = np.unwrap(2.0 * np.arctan2(e[:, 1:] @ axis, e[:, 0]))
        ok = np.isfinite(ang)
        if ok.any() and after.any():
            err = ang - man["angle"]
            final = ang[ok][-1]
            out[f"{s}.slew_angle_deg"] = {"value": float(np.degrees(final)), "unit": "deg"}
            out[f"{s}.slew_angle_error_deg"] = {"value": float(np.degrees(final - man["angle"])), "unit": "deg"}
            out[f"{s}.residual_angle_error_deg"] = {
                "value": float(np.degrees(np.nanmax(np.abs(err[after])))),
                "unit": "deg",
            }
        for pt in ds["point"].values:
            d = np.linalg.norm(sel["point_deflection"].sel(point=pt).values, axis=-1)
            if not after.any() or not np.isfinite(d[after]).any():
                continue
            amp = float(np.nanmax(d[after]))
            peak = float(np.nanmax(d[during])) if during.any() and np.isfinite(d[during]).any() else amp
            tol = man["settle_tolerance"] or 0.05 * peak
            outside = np.nonzero(after & ~(d <= tol))[0]
            if outside.size == 0:
                settle = 0.0
            elif outside[-1] == len(t) - 1:
                settle = None  # still outside the band at the end of the run
            else:
                settle = float(t[outside[-1] + 1] - man["end"])
            out[f"{s}.{pt}.residual_amplitude"] = {"value": amp, "unit": "m"}
            out[f"{s}.{pt}.settling_time"] = {
                "value": settle,
                "unit": "s",
                "note": f"after the manoeuvre's end at {man['end']:g} s, band {tol:.3g} m"
                + ("; not settled by t_end" if settle is None else ""),
            }
    return out


def build_result(body, solutions, points: dict, config: dict | None = None, wall_time: float = 0.0):
    """Assemble a :class:`FloatingResult` from :class:`~rotaflex.floating.solve.Solution` s."""
    import xarray as xr

    from rotaflex.floating.solve import invariants, point_motion, rotation_matrices

    names = list(points)
    P = np.array([points[k] for k in names], dtype=float).reshape(-1, 3)
    t = solutions[0].time
    nt, npnt = len(t), len(names)

    def stack(f):
        return np.stack([f(s) for s in solutions])

    pos_pts, defl = [], []
    for s in solutions:
        if npnt:
            a, b = point_motion(body, s, P)
        else:
            a = b = np.zeros((nt, 0, 3))
        pos_pts.append(a)
        defl.append(b)
    inv = [invariants(body, s) for s in solutions]
    ax3 = ("solution", "time", "axis")
    data = {
        "position": (ax3, stack(lambda s: s.position), "m", "origin position R_o (inertial)"),
        "quaternion": (
            ("solution", "time", "quat"),
            stack(lambda s: s.quaternion),
            "1",
            "attitude",
        ),
        "rotation_matrix": (
            ("solution", "time", "row", "col"),
            stack(lambda s: rotation_matrices(s.quaternion)),
            "1",
            "attitude matrix A (body to inertial) from the state at each output time",
        ),
        "euler_123": (
            ax3,
            stack(lambda s: s.euler_123),
            "rad",
            "Euler 1-2-3 angles, unwrapped after every integrator step (independent of dt_out)",
        ),
        "velocity": (ax3, stack(lambda s: s.velocity), "m/s", "V_o (body axes)"),
        "angular_velocity": (ax3, stack(lambda s: s.angular_velocity), "rad/s", "w (body axes)"),
        "modal_displacement": (("solution", "time", "mode"), stack(lambda s: s.q), "kg^0.5 m", "q"),
        "modal_velocity": (("solution", "time", "mode"), stack(lambda s: s.p), "kg^0.5 m/s", "p"),
        "point_position": (
            ("solution", "time", "point", "axis"),
            np.stack(pos_pts),
            "m",
            "inertial position of output points",
        ),
        "point_deflection": (
            ("solution", "time", "point", "axis"),
            np.stack(defl),
            "m",
            "elastic deflection of output points (body axes)",
        ),
        "momentum": (ax3, np.stack([i[0] for i in inv]), "kg m/s", "linear momentum (inertial)"),
        "angular_momentum": (
            ax3,
            np.stack([i[1] for i in inv]),
            "kg m^2/s",
            "angular momentum about the inertial origin",
        ),
        "energy": (
            ("solution", "time"),
            np.stack([i[2] for i in inv]),
            "J",
            "kinetic + strain energy",
        ),
        "centre_of_mass": (ax3, np.stack([i[3] for i in inv]), "m", "centre of mass (inertial)"),
        "min_effective_stiffness": (
            ("solution", "time"),
            stack(lambda s: s.min_stiffness),
            "1/s^2",
            "min eigenvalue of K_b + M~(w) (+ K_G)",
        ),
    }
    pert = [s for s in solutions if s.method == "perturbation"]
    if pert:
        pp = pert[0].parts
        data.update(
            {
                "zero_order_position": (("time", "axis"), pp["R0"], "m", "R_o0"),
                "zero_order_quaternion": (("time", "quat"), pp["e0"], "1", "zero-order attitude"),
                "zero_order_euler_123": (
                    ("time", "axis"),
                    pp["euler0"],
                    "rad",
                    "zero-order Euler 1-2-3 angles (unwrapped step by step)",
                ),
                "zero_order_velocity": (("time", "axis"), pp["V0"], "m/s", "V_o0 (body axes)"),
                "zero_order_angular_velocity": (
                    ("time", "axis"),
                    pp["w0"],
                    "rad/s",
                    "w0 (body axes)",
                ),
                "first_order_position": (("time", "axis"), pp["R1"], "m", "R_o1"),
                "first_order_rotation": (("time", "axis"), pp["th1"], "rad", "theta_1 (body axes)"),
                "first_order_velocity": (("time", "axis"), pp["V1"], "m/s", "V_o1"),
                "first_order_angular_velocity": (("time", "axis"), pp["w1"], "rad/s", "w1"),
            }
        )
    ds = xr.Dataset(
        {k: (dims, np.asarray(v, dtype=float), {"units": u, "long_name": ln}) for k, (dims, v, u, ln) in data.items()},
        coords={
            "solution": [s.method for s in solutions],
            "time": ("time", t, {"units": "s", "long_name": "time"}),
            "axis": ["x", "y", "z"],
            "quat": ["e0", "e1", "e2", "e3"],
            "row": ["x", "y", "z"],
            "col": ["x", "y", "z"],
            "mode": list(body.mode_labels),
            "point": names,
            "natural_frequency": ("mode", np.sqrt(np.diag(body.stiffness)), {"units": "rad/s"}),
        },
    )
    bad = [s for s in solutions if s.status != "success"]
    ds.attrs.update(
        {
            "status": bad[0].status if bad else "success",
            "message": " | ".join(f"{s.method}: {s.message}" for s in solutions),
            "wall_time": float(wall_time),
            "config": json.dumps(config or {}),
            "body": body.name,
            "floating_frame": body.frame,
            "geometric_stiffness": int(any(s.geometric for s in solutions)),
            "kinematics": solutions[0].kinematics,
            "solver_wall_times": json.dumps({s.method: s.wall_time for s in solutions}),
            "body_model": "modal",
            "body_length": float(body.length or 0.0),
        }
    )
    return FloatingResult(ds)
