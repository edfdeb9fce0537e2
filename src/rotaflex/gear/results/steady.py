"""Steady-state post-processing of gear dynamics, independent of the solver.

Any solver that samples its histories at a whole number of points per mesh cycle (uniform in
time at constant mean speed) can use these functions: the torsional model
(:mod:`rotaflex.gear.models.chain`) does, and the FE continuous-meshing solver can.

Conventions
-----------
* ``spc``: samples per mesh cycle (an integer); a history of ``n`` cycles has ``n spc`` samples
  (the first sample of the next cycle may be appended and is ignored).
* Periodicity: the cycle-to-cycle change of a signal ``x`` for a period of ``P`` mesh cycles
  is ``max |x(t) - x(t - P T_mesh)| / scale`` over the last ``P`` cycles; the torsional model
  uses the mesh force with ``scale`` = the static mesh force. ``P`` = 1 is tried first, then
  2 ... ``max_period`` (sub-harmonic responses near resonance with contact loss).
* Harmonic amplitudes: discrete Fourier transform of the last ``n`` (whole) mesh cycles with a
  rectangular window. For a periodic signal the mesh orders fall exactly on bins ``k n`` so
  there is no leakage and no window is needed; the amplitude is ``2 |X_{k n}| / N``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rotaflex.core.errors import InputError
from rotaflex.core.result import Result, register_result

__all__ = ["Periodicity", "SteadyStateResult", "cycle_change", "detect_period", "harmonic_amplitudes", "steady_metrics"]


def _cycles(x: np.ndarray, spc: int) -> int:
    if spc < 2 or int(spc) != spc:
        raise InputError("samples_per_cycle", spc, "an integer >= 2")
    return len(x) // spc


def cycle_change(x, spc: int, period: int = 1, scale: float | None = None) -> float:
    """Largest change of ``x`` over its last ``period`` cycles vs the ``period`` before.

    Parameters
    ----------
    x : array_like
        History sampled at ``spc`` samples per mesh cycle (oldest first).
    spc : int
        Samples per mesh cycle.
    period : int
        Period tried [mesh cycles].
    scale : float, optional
        Normalisation; default: peak-to-peak of the last ``period`` cycles (or 1 if zero).

    Returns
    -------
    float
        ``max |x(t) - x(t - period T)| / scale`` [-]; ``inf`` when fewer than ``2 period``
        cycles are available.
    """
    x = np.asarray(x, dtype=float)
    n = _cycles(x, spc)
    if n < 2 * period:
        return math.inf
    x = x[: n * spc]
    w = period * spc
    last, before = x[-w:], x[-2 * w : -w]
    if scale is None:
        scale = float(np.ptp(last)) or 1.0
    return float(np.max(np.abs(last - before)) / scale)


@dataclass(frozen=True)
class Periodicity:
    """Outcome of :func:`detect_period`.

    Attributes
    ----------
    period : int
        Detected period [mesh cycles]; 0 when none met the tolerance.
    change : float
        Cycle-to-cycle change at the detected period, or the smallest change found [-].
    changes : tuple of float
        Change for period 1, 2, ... ``max_period``.
    """

    period: int
    change: float
    changes: tuple


def detect_period(x, spc: int, tol: float, *, max_period: int = 4, scale: float | None = None) -> Periodicity:
    """Smallest period (1 ... ``max_period`` mesh cycles) with change below ``tol``.

    See :func:`cycle_change`. A quasi-periodic signal (two incommensurate frequencies) never
    meets a small tolerance at any period and yields ``period = 0``.
    """
    changes = tuple(cycle_change(x, spc, p, scale) for p in range(1, max_period + 1))
    for p, c in enumerate(changes, start=1):
        if c <= tol:
            return Periodicity(p, c, changes)
    return Periodicity(0, min(changes), changes)


def harmonic_amplitudes(x, spc: int, n_cycles: int, orders=(1, 2, 3)) -> np.ndarray:
    """Amplitudes of ``x`` at multiples of the mesh frequency over its last ``n_cycles``.

    Rectangular window over whole mesh cycles (see module notes).

    Returns
    -------
    ndarray
        One amplitude per order, in the unit of ``x``.
    """
    x = np.asarray(x, dtype=float)
    n = _cycles(x, spc)
    if n_cycles < 1 or n_cycles > n:
        raise InputError("n_cycles", n_cycles, f"1 ... {n} (cycles available)")
    seg = x[n * spc - n_cycles * spc : n * spc]
    spec = np.fft.rfft(seg)
    nn = len(seg)
    out = []
    for k in orders:
        b = int(k) * n_cycles
        out.append(2.0 * abs(spec[b]) / nn if b < len(spec) else math.nan)
    return np.array(out)


#: a force peak is an impact when contact was lost within this fraction of a mesh cycle before it
IMPACT_WINDOW = 0.25


def steady_metrics(dte, force, static_force: float, spc: int, n_cycles: int, peak_force=None) -> dict:
    """Steady-state quantities over the last ``n_cycles`` mesh cycles.

    Parameters
    ----------
    dte : array_like
        Dynamic transmission error ``rb1 theta_1 - rb2 theta_2`` (any constant offset) [m].
    force : array_like
        Dynamic mesh force [N] (0 during contact loss).
    static_force : float
        Static mesh force F_t = torque / base radius [N].
    spc, n_cycles : int
        Samples per cycle and cycles evaluated.
    peak_force : array_like, optional
        The force whose maximum is the reported peak [N] (default ``force``): the lumped model
        passes its mesh force without the damper's response to the rate of the tabulated
        unloaded TE (see docs/gear-steady-state.md, "K_v from a converged peak").

    Returns
    -------
    dict
        ``dte_pp``, ``dte_rms`` (about the mean), ``dte_mean`` [m]; ``dte_h1..h3`` [m];
        ``force_max`` (of ``peak_force``), ``force_min`` [N]; ``force_max_sampled`` (the
        largest sample of ``force``) [N]; ``force_h1..h3`` [N]; ``dynamic_factor`` =
        force_max / static_force [-]; ``contact_loss_fraction`` (share of samples with
        F <= 0, of ``peak_force``: the damper's spike at a TE step can pull the sampled force
        below 0 while the teeth stay in contact) [-]; ``peak_is_impact`` (1: contact was lost
        within :data:`IMPACT_WINDOW` of a mesh cycle before the peak, so the peak is the
        re-contact impact; 0 otherwise).
    """
    dte = np.asarray(dte, dtype=float)
    force = np.asarray(force, dtype=float)
    n = _cycles(dte, spc)
    if n_cycles > n:
        raise InputError("n_cycles", n_cycles, f"<= {n} (cycles available)")
    sl = slice(n * spc - n_cycles * spc, n * spc)
    d, f = dte[sl], force[sl]
    fp = f if peak_force is None else np.asarray(peak_force, dtype=float)[sl]
    i = int(np.argmax(fp))
    before = np.roll(fp, -i)[-max(1, int(IMPACT_WINDOW * spc)) :]  # the samples just before the peak (periodic)
    out = {
        "dte_pp": float(np.ptp(d)),
        "dte_rms": float(np.std(d)),
        "dte_mean": float(d.mean()),
        "force_max": float(fp[i]),
        "force_max_sampled": float(f.max()),
        "force_min": float(f.min()),
        "dynamic_factor": float(fp[i] / static_force),
        "contact_loss_fraction": float(np.mean(fp <= 0.0)),
        "peak_is_impact": float(np.any(before <= 0.0)),
    }
    for k, a in zip((1, 2, 3), harmonic_amplitudes(d, spc, n_cycles), strict=True):
        out[f"dte_h{k}"] = float(a)
    for k, a in zip((1, 2, 3), harmonic_amplitudes(f, spc, n_cycles), strict=True):
        out[f"force_h{k}"] = float(a)
    return out


METRIC_UNITS = {
    "dte_pp": "m",
    "dte_rms": "m",
    "dte_mean": "m",
    "dte_h1": "m",
    "dte_h2": "m",
    "dte_h3": "m",
    "force_max": "N",
    "force_max_sampled": "N",
    "force_min": "N",
    "force_h1": "N",
    "force_h2": "N",
    "force_h3": "N",
    "dynamic_factor": "1",
    "contact_loss_fraction": "1",
    "peak_is_impact": "1",
}


@register_result
class SteadyStateResult(Result):
    """One steady-state operating point.

    Dataset: ``time`` histories ``dte`` [m] and ``mesh_force`` [N] of the evaluated cycles, the
    scalars of :func:`steady_metrics`, ``change`` (cycle-to-cycle), ``period_cycles``,
    ``natural_frequency`` [Hz] (dim ``mode``), attrs ``samples_per_cycle``, ``mesh_frequency``.
    """

    kind = "gear_steady"

    def summary(self) -> dict:
        """Base scalars; ``iso_resonance_speed`` [rpm] says that it is ISO 6336-1's n_E1."""
        out = super().summary()
        if "iso_resonance_speed" in out:
            out["iso_resonance_speed"]["long_name"] = (
                "ISO 6336-1 main resonance speed n_E1 of the pinion, 30000/(pi z1) sqrt(c_gamma_alpha/m_red)"
            )
        return out

    def final_state(self) -> dict | None:
        """The model state at the end of the run (``state_*`` variables, attr ``state_time``) as
        plain data for ``initial_state`` of the next point of a continuation; None if absent."""
        ds = self.dataset
        if "state_theta" not in ds:
            return None
        out = {
            "theta": ds["state_theta"].values.tolist(),
            "omega": ds["state_omega"].values.tolist(),
            "nominal": ds["state_nominal"].values.tolist(),
            "time": float(ds.attrs["state_time"]),
        }
        if "state_modal" in ds:  # elastic-tooth window model
            out.update(modal=ds["state_modal"].values.tolist(), n_hi=int(ds.attrs["state_n_hi"]))
        return out

    def plot(self) -> dict:
        """Figures: ``time_series`` (DTE, force), ``one_cycle`` (last cycle), ``spectrum``."""
        from rotaflex.core.plotting import new_figure

        ds = self.dataset
        spc = int(ds.attrs["samples_per_cycle"])
        fm = float(ds.attrs["mesh_frequency"])
        t = ds["time"].values
        figs = {}
        fig, ax = new_figure(2, 1, sharex=True)
        ax[0].plot(t * 1e3, ds["dte"].values * 1e6)
        ax[0].set_ylabel("DTE [µm]")
        ax[1].plot(t * 1e3, ds["mesh_force"].values)
        ax[1].axhline(float(ds.attrs["static_force"]), ls="--", c="k", lw=0.8, label="static")
        ax[1].set(xlabel="time [ms]", ylabel="mesh force [N]")
        ax[1].legend()
        figs["time_series"] = fig
        fig, ax = new_figure()
        n_cyc = len(t) // spc
        for c in range(max(0, n_cyc - 3), n_cyc):
            s = slice(c * spc, (c + 1) * spc + 1)
            ph = np.arange(len(ds["mesh_force"].values[s])) / spc
            ax.plot(ph, ds["mesh_force"].values[s], label=f"cycle {c + 1}")
        ax.set(xlabel="mesh phase [cycles]", ylabel="mesh force [N]", title="last mesh cycles (overlaid)")
        ax.legend()
        figs["one_cycle"] = fig
        fig, ax = new_figure()
        x = ds["dte"].values[: n_cyc * spc]
        amp = 2 * np.abs(np.fft.rfft(x - x.mean())) / len(x)
        order = np.arange(len(amp)) / n_cyc
        sel = order <= 6
        ax.plot(order[sel], amp[sel] * 1e6, marker=".")
        ax.set(
            xlabel=f"frequency / mesh frequency ({fm:.0f} Hz)",
            ylabel="DTE amplitude [um]",
            title="spectrum over whole mesh cycles, rectangular window",
        )
        figs["spectrum"] = fig
        return figs
