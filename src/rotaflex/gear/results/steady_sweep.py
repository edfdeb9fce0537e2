"""Speed sweeps of the steady gear models: the dataset of a continuation and its figure.

:func:`sweep_dataset` turns the steady states of a continuation
(:func:`rotaflex.gear.solvers.steady_driver.continuation`: up through the speeds, then down from
the top state) into one dataset, dims ``direction`` x ``speed`` [rpm]: every steady-state metric,
``change``, ``period_cycles``, ``converged`` (periodic within tol), the natural frequencies
``natural_frequency`` [Hz], the resonance speeds ``resonance_speed`` [rpm] (mesh orders 1-3 of
the mesh modes), ``n_not_periodic``, and with an ISO input the ISO 6336-1 method B ``iso_kv``.
Where contact loss makes the response multi-valued (a softening resonance) the two directions
follow different branches: the hysteresis and the jumps show as the difference between ``up``
and ``down``.
"""

from __future__ import annotations

import json
import time

import numpy as np

from rotaflex.core.result import Result, register_result
from rotaflex.core.units import rpm_to_rad_s
from rotaflex.gear.results.steady import METRIC_UNITS

__all__ = ["SpeedSweepResult", "sweep_dataset"]

#: per-point scalars of the elastic-teeth model kept in a sweep [Pa]
FILLET = ("fillet_stress_max_pinion", "fillet_stress_max_wheel")


def sweep_dataset(points, speeds, directions, system, torque: float, *, iso=None, started: float | None = None):
    """The :class:`SpeedSweepResult` of a continuation's steady states.

    Parameters
    ----------
    points : iterable of (int, int, SteadyStateResult)
        ``(direction index, speed index, result)`` as
        :func:`~rotaflex.gear.solvers.steady_driver.continuation` yields them.
    speeds : ndarray
        Pinion speeds [rpm], ascending.
    directions : sequence of {"up", "down"}
    system : TorsionalSystem
        The chain (natural frequencies and resonance speeds).
    torque : float
        Output torque [N m].
    iso : IsoKvInput, optional
        Adds the ISO 6336-1 method B K_v at each speed (``iso_kv``) for the figure.
    started : float, optional
        ``time.perf_counter()`` at the start of the sweep (``wall_time`` attribute; else 0).

    Returns
    -------
    SpeedSweepResult
        Status "success" once every point ran; points that did not become periodic are named
        in the message and flagged by ``converged``.
    """
    import xarray as xr

    from rotaflex.gear.models.chain import natural_frequencies, resonance_speeds_rpm
    from rotaflex.gear.static.iso6336_kv import iso_kv

    shape = (len(directions), len(speeds))
    names = list(METRIC_UNITS) + ["change", "period_cycles", "cycles_run"]
    data = {k: np.full(shape, np.nan) for k in names}
    for di, j, res in points:
        for k in names:
            data[k][di, j] = res.dataset[k].item()
        for k in FILLET:
            if k in res.dataset:
                data.setdefault(k, np.full(shape, np.nan))[di, j] = res.dataset[k].item()
    nf = natural_frequencies(system)
    res_speeds = resonance_speeds_rpm(system)
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
        kv = iso_kv(iso, rpm_to_rad_s(speeds))
        ds["iso_kv"] = ("speed", kv, {"units": "1", "long_name": "ISO 6336-1 method B K_v"})
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
        wall_time=0.0 if started is None else time.perf_counter() - started,
        torque=torque,
        config=json.dumps({"torque": torque, "speeds_rpm": np.asarray(speeds).tolist()}),
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
        if "iso_resonance_speed" in ds.attrs:
            out["iso_resonance_speed"] = {
                "value": float(ds.attrs["iso_resonance_speed"]),
                "unit": "rpm",
                "long_name": "ISO 6336-1 main resonance speed n_E1 of the pinion",
            }
        return out

    def plot(self) -> dict:
        """Figure ``speed_sweep``: K_v (with ISO method B) and DTE p-p vs speed."""
        from rotaflex.core.plotting import new_figure

        ds = self.dataset
        sp = ds["speed"].values
        fig, ax = new_figure(2, 1, sharex=True, figsize=(9.0, 7.2))
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
                for i, a in enumerate(ax):
                    a.axvline(
                        r,
                        c="gray",
                        lw=0.8,
                        ls=":",
                        label=f"{int(h)}x mesh order at f_n: {r:,.0f} rpm" if i == 0 else None,
                    )
                # short tags above the panel (never across the curves), values in the legend
                tag = f"{int(h)}x" + (f" {f / 1e3:.1f} kHz" if several else "")
                ax[0].text(r, 1.01, tag, transform=ax[0].get_xaxis_transform(), fontsize=7, ha="center", va="bottom")
        n_e1 = ds.attrs.get("iso_resonance_speed")
        if n_e1 is not None and sp[0] <= n_e1 <= sp[-1]:
            for i, a in enumerate(ax):
                a.axvline(n_e1, c="k", lw=0.9, ls="-.", label=f"ISO 6336-1 n_E1 = {n_e1:,.0f} rpm" if i == 0 else None)
            ax[0].text(n_e1, 1.01, "n_E1", transform=ax[0].get_xaxis_transform(), fontsize=7, ha="center", va="bottom")
        ax[0].set(ylabel="K_v = F_max / F_static [-]")
        ax[1].set(xlabel="pinion speed [rpm]", ylabel="DTE peak-to-peak [µm]")
        # one legend right of the panels (the lower panel's entries are the upper one's):
        # inside either panel it covered points wherever the curves went
        fig.legend(*ax[0].get_legend_handles_labels(), loc="outside right upper", fontsize=7)
        return {"speed_sweep": fig}
