"""Speed sweeps of the torsional gear model with continuation, and the K_v / DTE figure.

Each speed starts from the previous speed's steady state (angles and vibration velocities
kept, mean speeds moved to the new value), first upwards through ``speeds_rpm``, then
downwards from the top state. Where contact loss makes the response multi-valued (a softening
resonance), the two directions follow different branches: the hysteresis and the jumps show
as the difference between ``direction = "up"`` and ``"down"``.
"""

from __future__ import annotations

import json
import time

import numpy as np

from rotaflex.core.errors import InputError
from rotaflex.core.result import Result, register_result
from rotaflex.gear.models.chain import (
    OperatingPoint,
    TorsionalSystem,
    natural_frequencies,
    resonance_speeds_rpm,
)
from rotaflex.gear.results.steady import METRIC_UNITS
from rotaflex.gear.solvers.registry import METHODS
from rotaflex.gear.static.iso6336_kv import IsoKvInput, iso_kv, reduced_mass_per_width

__all__ = ["SpeedSweepResult", "iso_input", "speed_sweep"]

FILLET = ("fillet_stress_max_pinion", "fillet_stress_max_wheel")


def iso_input(
    sys: TorsionalSystem,
    torque: float,
    face_width: float,
    contact_ratio: float,
    *,
    c_single: float | None = None,
    c_gamma_alpha: float | None = None,
    reference_radius: float | None = None,
    f_pb_eff: float = 0.0,
    f_f_eff: float = 0.0,
    tip_relief: float = 0.0,
    application_factor: float = 1.0,
) -> IsoKvInput:
    """ISO 6336-1 method B data for the torsional model's pair.

    ``m_red`` from the gears' inertias and base radii; ``K_A F_t / b`` with ISO's nominal
    tangential load at the wheel's *reference* circle, ``F_t = T_out / r_2``
    (``reference_radius``; default ``r_b2 / cos 20 deg``). The stiffnesses [N/m^2] are ISO's own
    when given (``c_single``, ``c_gamma_alpha``, e.g. from
    :func:`rotaflex.gear.static.tooth_analysis.iso6336_stiffness`); otherwise ``c_gamma_alpha = k_mean / b``
    (the model's mean mesh stiffness) and ``c' = c_gamma_alpha / (0.75 eps_alpha + 0.25)``
    (ISO's relation between the two).
    """
    c_g = sys.mesh.mean_stiffness / face_width if c_gamma_alpha is None else c_gamma_alpha
    c1 = c_g / (0.75 * contact_ratio + 0.25) if c_single is None else c_single
    r2 = sys.base_radius[1] / np.cos(np.radians(20.0)) if reference_radius is None else reference_radius
    return IsoKvInput(
        z1=int(sys.teeth[0]),
        c_single=c1,
        c_gamma_alpha=c_g,
        m_red=reduced_mass_per_width(sys.inertia, sys.base_radius, face_width),
        load_per_width=application_factor * torque / r2 / face_width,
        eps_gamma=contact_ratio,
        f_pb_eff=f_pb_eff,
        f_f_eff=f_f_eff,
        tip_relief=tip_relief,
    )


def speed_sweep(
    sys: TorsionalSystem,
    torque: float,
    speeds_rpm,
    *,
    directions=("up", "down"),
    iso: IsoKvInput | None = None,
    **steady_kw,
):
    """Steady state at each speed, with continuation, up and then down.

    Parameters
    ----------
    sys : TorsionalSystem or WindowModel
        The lumped model, or the elastic-tooth window model (:mod:`~.window`; adds
        ``fillet_stress_max_pinion`` / ``_wheel``).
    torque : float
        Output torque [N m].
    speeds_rpm : array_like
        Pinion speeds [rpm], ascending, > 0.
    directions : sequence of {"up", "down"}
    iso : IsoKvInput, optional
        Adds the ISO 6336-1 method B K_v at each speed (``iso_kv``) for the figure.
    **steady_kw
        Passed to :func:`rotaflex.gear.models.chain.steady_state` (tol, eval_cycles, ...).

    Returns
    -------
    SpeedSweepResult
        dims ``direction`` x ``speed`` [rpm]; every steady-state metric, ``change``,
        ``period_cycles``, ``converged`` (periodic within tol); ``natural_frequency`` [Hz] and
        the resonance speeds ``resonance_speed`` [rpm] (mesh orders 1-3 of the mesh modes),
        ``n_not_periodic``. Status "success" once every point ran; points that did not become
        periodic are named in the message and flagged by ``converged``.
    """
    import xarray as xr

    speeds = np.asarray(speeds_rpm, dtype=float)
    if speeds.ndim != 1 or len(speeds) < 2 or np.any(np.diff(speeds) <= 0) or speeds[0] <= 0:
        raise InputError("speeds_rpm", list(speeds), "ascending speeds > 0 (at least two)")
    for d in directions:
        if d not in ("up", "down"):
            raise InputError("directions", d, "'up' or 'down'")
    t0 = time.perf_counter()
    model, run = sys, METHODS["lumped"]
    if not isinstance(sys, TorsionalSystem):  # the elastic-tooth window model
        model, run, sys = sys, METHODS["elastic_teeth"], sys.system
    names = list(METRIC_UNITS) + ["change", "period_cycles", "cycles_run"]
    data = {k: np.full((len(directions), len(speeds)), np.nan) for k in names}

    state = None
    for di, d in enumerate(directions):
        order = range(len(speeds)) if d == "up" else range(len(speeds) - 1, -1, -1)
        for j in order:
            op = OperatingPoint(speed_rpm=float(speeds[j]), torque=torque)
            res, state = run(model, dict(steady_kw, op=op, state=state))
            for k in names:
                data[k][di, j] = res.dataset[k].item()
            for k in FILLET:
                if k in res.dataset:
                    data.setdefault(k, np.full((len(directions), len(speeds)), np.nan))[di, j] = res.dataset[k].item()
    nf = natural_frequencies(sys)
    res_speeds = resonance_speeds_rpm(sys)
    ds = xr.Dataset(
        coords={
            "direction": ("direction", list(directions)),
            "speed": ("speed", speeds, {"units": "rpm", "long_name": "pinion speed"}),
            "mode": ("mode", np.arange(len(nf["frequency"]))),
        }
    )
    units = dict(METRIC_UNITS, change="1", period_cycles="1", cycles_run="1")
    for k in names:
        ds[k] = (("direction", "speed"), data[k], {"units": units[k]})
    ds["converged"] = (("direction", "speed"), data["period_cycles"] > 0, {"units": "1"})
    for k in FILLET:
        if k in data:
            ds[k] = (("direction", "speed"), data[k], {"units": "Pa"})
    ds["natural_frequency"] = ("mode", nf["frequency"], {"units": "Hz"})
    ds["resonance_speed"] = (
        "resonance",
        np.array([r[2] for r in res_speeds]),
        {"units": "rpm", "long_name": "pinion speed: mesh order h meets f_n"},
    )
    ds["resonance_order"] = ("resonance", np.array([r[0] for r in res_speeds]), {"units": "1"})
    ds["resonance_frequency"] = ("resonance", np.array([r[1] for r in res_speeds]), {"units": "Hz"})
    if iso is not None:
        ds["iso_kv"] = ("speed", iso_kv(iso, speeds), {"units": "1", "long_name": "ISO 6336-1 method B K_v"})
        ds.attrs["iso_resonance_speed"] = iso.resonance_speed_rpm
    # a response that does not settle at some speed (quasi-periodic or chaotic motion next to a
    # jump) is a finding of the sweep, not a failure of the run: named in the message, counted
    bad = [
        f"{directions[d]} {speeds[j]:.0f} rpm (change {data['change'][d, j]:.2g})"
        for d, j in np.argwhere(~ds["converged"].values)
    ]
    ds["n_not_periodic"] = ((), len(bad), {"units": "1"})
    msg = f"{ds['converged'].size - len(bad)} of {ds['converged'].size} points periodic"
    if bad:
        msg += "; not periodic: " + ", ".join(bad)
    ds.attrs.update(
        status="success",
        message=msg,
        wall_time=time.perf_counter() - t0,
        torque=torque,
        config=json.dumps({"torque": torque, "speeds_rpm": speeds.tolist()}),
    )
    return SpeedSweepResult(ds)


@register_result
class SpeedSweepResult(Result):
    """Dynamic factor and DTE vs speed, up and down."""

    kind = "gear_speed_sweep"

    def hysteresis(self, name: str = "dynamic_factor") -> float:
        """Largest |up - down| of ``name`` over the speeds (0 when only one direction)."""
        ds = self.dataset
        if ds.sizes["direction"] < 2:
            return 0.0
        v = ds[name].values
        return float(np.nanmax(np.abs(v[0] - v[1])))

    def summary(self) -> dict:
        """Base scalars plus the peak K_v and DTE per direction, the hysteresis and the resonances."""
        out = super().summary()
        ds = self.dataset
        sp = ds["speed"].values
        for di, d in enumerate(ds["direction"].values):
            kv = ds["dynamic_factor"].values[di]
            if np.all(np.isnan(kv)):
                continue
            i = int(np.nanargmax(kv))
            out[f"max_dynamic_factor_{d}"] = {"value": float(kv[i]), "unit": "1"}
            out[f"speed_at_max_dynamic_factor_{d}"] = {"value": float(sp[i]), "unit": "rpm"}
            out[f"max_dte_pp_{d}"] = {"value": float(np.nanmax(ds["dte_pp"].values[di])), "unit": "m"}
        out["dynamic_factor_hysteresis"] = {"value": self.hysteresis(), "unit": "1"}
        res = ds["resonance_speed"].values[ds["resonance_order"].values == 1]
        if res.size:
            out["resonance_speed"] = {"value": float(res[0]), "unit": "rpm"}
        return out

    def plot(self) -> dict:
        """Figure ``speed_sweep``: K_v (with ISO method B) and DTE p-p vs speed."""
        from rotaflex.core.plotting import new_figure

        ds = self.dataset
        sp = ds["speed"].values
        fig, ax = new_figure(2, 1, sharex=True)
        for di, d in enumerate(ds["direction"].values):
            mk = "^-" if d == "up" else "v--"
            ax[0].plot(sp, ds["dynamic_factor"].values[di], mk, ms=3, label=f"model, {d}")
            ax[1].plot(sp, ds["dte_pp"].values[di] * 1e6, mk, ms=3, label=f"model, {d}")
        if "iso_kv" in ds:
            ax[0].plot(sp, ds["iso_kv"].values, "k-", lw=1.0, label="ISO 6336-1 method B")
        freqs = ds["resonance_frequency"].values if "resonance_frequency" in ds else np.zeros(ds.sizes["resonance"])
        several = len(np.unique(freqs)) > 1
        for r, h, f in zip(ds["resonance_speed"].values, ds["resonance_order"].values, freqs, strict=True):
            if sp[0] <= r <= sp[-1]:
                for a in ax:
                    a.axvline(r, c="gray", lw=0.8, ls=":")
                label = f"{int(h)}x {f / 1e3:.1f} kHz" if several else f"{int(h)}x f_n"
                ax[0].annotate(label, (r, 1.0), fontsize=7, rotation=90)
        ax[0].set(ylabel="K_v = F_max / F_static [-]")
        ax[1].set(xlabel="pinion speed [rpm]", ylabel="DTE peak-to-peak [µm]")
        ax[0].legend(fontsize=7)
        ax[1].legend(fontsize=7)
        return {"speed_sweep": fig}
