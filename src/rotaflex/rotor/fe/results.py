"""Result objects of the FE rotor analyses (xarray datasets with units; registered for loading)."""

from __future__ import annotations

import json

import numpy as np

from rotaflex.core.result import Result, register_result
from rotaflex.core.units import rad_s_to_rpm


def _model_fig(result):
    from rotaflex.rotor.fe.figures import model_figure
    from rotaflex.rotor.fe.model import ROTOR_KEYS, Rotor

    cfg = result.config
    if "shaft" not in cfg:
        return {}
    figs = {}
    if "ff_kxx" in result.dataset:  # fluid-film bearings: their coefficient tables vs speed
        from rotaflex.rotor.fe.figures import fluid_film_figure

        figs["bearing_coefficients"] = fluid_film_figure(result.dataset)
    rotor = Rotor.from_mapping({k: v for k, v in cfg.items() if k in ROTOR_KEYS})
    return {"model": model_figure(rotor), **figs}


def json_safe(obj):
    """``obj`` with every non-finite float replaced by None (strict JSON has no NaN/Infinity)."""
    if isinstance(obj, dict):
        return {k: json_safe(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [json_safe(v) for v in obj]
    if isinstance(obj, (float, np.floating)):
        return float(obj) if np.isfinite(obj) else None
    if isinstance(obj, np.integer):
        return int(obj)
    return obj


def campbell_dataset(modes, mac_min, lines, crossings=None, crossings_attr: str = "crossings"):
    """The Campbell dataset of an FE rotor or a machine (``rotaflex rotor campbell``,
    ``rotaflex system campbell``): the one place its variables are named.

    Parameters
    ----------
    modes : Modes or SystemModes
        Tracked modes: ``speed`` (s,) [rad/s] and ``eigenvalue`` (s, t) [1/s] (an
        :class:`~rotaflex.rotor.fe.modal.EigenvalueView`); a ``forward_fraction`` (the FE
        rotor's whirl sense) is stored when the modes have one.
    mac_min : ndarray (s,)
        Smallest MAC of each tracking step [-].
    lines : list of dict
        Excitation lines ``{"name", "factor"}``: omega = factor x speed.
    crossings : list of dict, optional
        Line crossings (or critical speeds), stored as JSON in the attribute ``crossings_attr``.

    Returns
    -------
    xarray.Dataset
        ``damped_frequency``, ``natural_frequency`` [rad/s], ``log_dec``, ``damping_ratio``,
        (``forward_fraction``), ``mac_min`` (speed, mode), ``line_factor`` (line),
        ``speed_rpm`` (speed); coordinates ``speed`` [rad/s], ``mode``, ``line``. A machine adds
        its energy shares on top (:func:`rotaflex.system.results.campbell_dataset`).
    """
    import xarray as xr

    speeds = modes.speed
    data = {
        "damped_frequency": (("speed", "mode"), modes.wd, {"units": "rad/s"}),
        "natural_frequency": (("speed", "mode"), modes.wn, {"units": "rad/s"}),
        "log_dec": (("speed", "mode"), modes.log_dec, {"units": "1"}),
        "damping_ratio": (("speed", "mode"), modes.damping_ratio, {"units": "1"}),
    }
    if hasattr(modes, "forward_fraction"):
        data["forward_fraction"] = (("speed", "mode"), modes.forward_fraction, {"units": "1"})
    data["mac_min"] = ("speed", mac_min, {"units": "1", "long_name": "smallest MAC of the tracking step"})
    data["line_factor"] = ("line", [ln["factor"] for ln in lines], {"units": "1", "long_name": "omega / Omega"})
    data["speed_rpm"] = ("speed", rad_s_to_rpm(speeds), {"units": "rpm"})
    ds = xr.Dataset(
        data,
        coords={
            "speed": ("speed", speeds, {"units": "rad/s"}),
            "mode": np.arange(modes.eigenvalue.shape[1]),
            "line": [ln["name"] for ln in lines],
        },
    )
    if crossings is not None:
        ds.attrs[crossings_attr] = json.dumps(crossings)
    return ds


def campbell_lines(ds, default=()) -> list:
    """The excitation lines ``(name, factor)`` of a Campbell dataset; ``default`` for a file
    written before the datasets carried them (``line_factor``)."""
    if "line_factor" not in ds:
        return list(default)
    return [(str(n), float(f)) for n, f in zip(ds["line"].values, ds["line_factor"].values, strict=True)]


def plot_campbell_dataset(ds, lines, marks=(), **kwargs):
    """:func:`~rotaflex.rotor.fe.figures.campbell_figure` of a Campbell dataset
    (:func:`campbell_dataset`); ``kwargs`` go to it (colour, labels, frequency limit)."""
    from rotaflex.rotor.fe.figures import campbell_figure

    if "log_dec" in ds:
        logdec = ds["log_dec"].values
    else:  # a machine's file written before it stored the log decrement: 2 pi zeta / sqrt(1 - zeta^2)
        z = ds["damping_ratio"].values
        logdec = 2 * np.pi * z / np.sqrt(1 - z**2)
    return campbell_figure(
        ds["speed"].values,
        ds["damped_frequency"].values,
        logdec,
        forward=ds["forward_fraction"].values if "forward_fraction" in ds else None,
        lines=lines,
        marks=marks,
        bands=json.loads(ds.attrs.get("bands", "[]")),
        **kwargs,
    )


class _FEResult(Result):
    def summary(self) -> dict:
        out = super().summary()
        extra = json.loads(self.dataset.attrs.get("summary_extra", "{}"))
        out.update(extra)
        return json_safe(out)


@register_result
class ModalResult(_FEResult):
    """Modes at one speed: frequencies, damping, whirl, mode shapes (see :func:`modal`)."""

    kind = "rotor_fe_modal"

    def plot(self) -> dict:
        figs = _model_fig(self)
        if "speed" in self.dataset.dims:  # several speeds: the figures of each, suffixed _speed<i>
            for i in range(self.dataset.sizes["speed"]):
                one = self.dataset.isel(speed=i)
                figs |= {f"{k}_speed{i}": v for k, v in self._mode_figures(one).items()}
            return figs
        return figs | self._mode_figures(self.dataset)

    @classmethod
    def _mode_figures(cls, ds) -> dict:
        from rotaflex.rotor.fe.figures import mode_shapes_figure

        return {"mode_shapes": mode_shapes_figure(ds), "mode_orbits": cls._orbits(ds)}

    def plot_mode(self, k: int):
        """Mode ``k``'s shape in both bending planes with its orbit envelope (the CLI's
        ``mode_shapes.png`` panel of that mode)."""
        from rotaflex.core.errors import InputError
        from rotaflex.rotor.fe.figures import mode_shapes_figure

        n = self.dataset.sizes["mode"]
        if not 0 <= k < n:
            raise InputError("k", k, f"a mode index 0..{n - 1}")
        return mode_shapes_figure(self.dataset.isel(mode=[k]))

    def plot_orbits(self):
        """Each mode's whirl orbit at every node over one period, scaled to 1 (``mode_orbits.png``)."""
        return self._orbits(self.dataset)

    @staticmethod
    def _orbits(ds):
        from rotaflex.core.plotting import new_figure

        # orbits: each mode's whirl at every node (x + i y over one period), scaled to 1
        nm = ds.sizes["mode"]
        ncol = min(nm, 4)
        fig2, axes = new_figure((nm + ncol - 1) // ncol, ncol, squeeze=False)
        th = np.linspace(0, 2 * np.pi, 121)
        for k in range(nm):
            ax = axes.flat[k]
            sh = ds["shape_real"].isel(mode=k).values + 1j * ds["shape_imag"].isel(mode=k).values
            for j in range(sh.shape[0]):
                x = (sh[j, 0] * np.exp(1j * th)).real
                y = (sh[j, 1] * np.exp(1j * th)).real
                ax.plot(x, y, lw=0.6)
                ax.plot(x[0], y[0], "k.", ms=3)  # start: the orbit runs from here in time
            ax.set_aspect("equal")
            ax.set_title(f"{k}: {ds['whirl'].values[k]}", fontsize=8)
            ax.tick_params(labelsize=6)
        for ax in list(axes.flat)[nm:]:
            ax.set_visible(False)
        return fig2


@register_result
class CampbellResult(_FEResult):
    """Campbell diagram with tracked modes, critical speeds and instability onsets."""

    kind = "rotor_fe_campbell"

    def plot(self) -> dict:
        return {**_model_fig(self), "campbell": self.plot_campbell()}

    def plot_campbell(self, frequency_limit_hz: float | None = None):
        """Campbell diagram over its log-decrement panel (the CLI's ``campbell.png``);
        ``frequency_limit_hz`` [Hz] overrides the run's ``frequency_limit_hz``."""
        ds = self.dataset
        lines = campbell_lines(ds, [(f"{h:g}X", h) for h in json.loads(ds.attrs.get("harmonics", "[1]"))])
        marks = [
            {**c, "labelled": c.get("harmonic", 1) == 1} for c in json.loads(ds.attrs.get("critical_speeds", "[]"))
        ]
        limit = frequency_limit_hz if frequency_limit_hz is not None else ds.attrs.get("frequency_limit_hz")
        return plot_campbell_dataset(ds, lines, marks, frequency_limit_hz=limit)

    @property
    def critical(self) -> list[dict]:
        """Critical speeds: ``speed_rpm``, ``frequency_hz``, ``harmonic`` (0.5 for 0.5X),
        ``whirl``, ``mode``."""
        crit = json.loads(self.dataset.attrs.get("critical_speeds", "[]"))
        return [
            {
                "speed_rpm": rad_s_to_rpm(c["speed"]),
                "frequency_hz": c["frequency"] / (2 * np.pi),
                "harmonic": c["harmonic"],
                "whirl": c["whirl"],
                "mode": c["mode"],
            }
            for c in crit
        ]


@register_result
class UCSResult(_FEResult):
    """Undamped critical speed map: critical speeds vs bearing stiffness."""

    kind = "rotor_fe_ucs"

    def plot(self) -> dict:

        from rotaflex.rotor.fe.figures import ucs_bearing_line, ucs_figure

        cfg = self.config
        bearings = []
        if "shaft" in cfg:
            from rotaflex.rotor.fe.model import ROTOR_KEYS, Rotor

            rotor = Rotor.from_mapping({k: v for k, v in cfg.items() if k in ROTOR_KEYS})
            for i, ((_, _, el), b) in enumerate(zip(rotor.bearings, rotor.bearing, strict=True)):
                bearings += ucs_bearing_line(b.name or f"bearing[{i}]", el)
        fig = ucs_figure(self.dataset, bearings)
        return {**_model_fig(self), "ucs_map": fig}


@register_result
class UnbalanceResult(_FEResult):
    """Unbalance response at probe nodes vs speed (Bode), peaks with AF and SM."""

    kind = "rotor_fe_unbalance"

    def plot(self) -> dict:
        return {**_model_fig(self), "bode": self.plot_bode(), "orbit": self.plot_orbit()}

    def plot_bode(self):
        """Peak-to-peak amplitude [um] and phase of every probe vs speed, the peaks tagged
        with their governing probe and AF, the operating range and API limit (``bode.png``)."""
        from rotaflex.rotor.fe.figures import unbalance_bode_figure

        ds = self.dataset
        return unbalance_bode_figure(
            ds,
            json.loads(ds.attrs.get("peaks", "[]")),
            json.loads(ds.attrs.get("bands", "[]")),
            ds.attrs.get("vibration_limit"),
        )

    def plot_orbit(self):
        """Orbits [um] of every probe at each response peak (``orbit.png``)."""
        from rotaflex.rotor.fe.figures import orbit_figure

        return orbit_figure(self.dataset, json.loads(self.dataset.attrs.get("peaks", "[]")))


@register_result
class TransientResult(_FEResult):
    """Time response at probe nodes (constant speed or run-up)."""

    kind = "rotor_fe_transient"

    def plot(self) -> dict:
        from rotaflex.rotor.fe.figures import transient_figures

        fig, fig2 = transient_figures(self.dataset)
        return {**_model_fig(self), "time_response": fig, "orbit": fig2}


@register_result
class StaticResult(_FEResult):
    """Static deflection, bearing reactions, shear force and bending moment."""

    kind = "rotor_fe_static"

    def plot(self) -> dict:
        from rotaflex.rotor.fe.figures import static_figure

        return {**_model_fig(self), "static": static_figure(self.dataset)}


@register_result
class FRFResult(_FEResult):
    """Frequency response functions at one spin speed: Bode and Nyquist."""

    kind = "rotor_fe_frf"

    def plot(self) -> dict:
        from rotaflex.rotor.fe.figures import frf_figures

        return {**_model_fig(self), **frf_figures(self.dataset)}
