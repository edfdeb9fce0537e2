"""The result of a rotor-disk or free-body simulation: summary scalars and figures."""

from __future__ import annotations

import numpy as np

from rotaflex.core.result import Result, register_result


@register_result
class RotorResult(Result):
    """Rotor-disk or free-body time history (see :func:`rotaflex.rotor.simulate`)."""

    kind = "rotor"

    def summary(self) -> dict:
        ds = self.dataset
        out = super().summary()
        K, H = ds["kinetic_energy"].values, ds["angular_momentum"].values
        Hn = np.linalg.norm(H, axis=1)
        out.update(
            {
                "end_time": {"value": float(ds["time"][-1]), "unit": "s"},
                "function_evaluations": {"value": int(ds.attrs.get("nfev", 0)), "unit": ""},
                "kinetic_energy_initial": {"value": float(K[0]), "unit": "J"},
                "kinetic_energy_max_relative_change": {
                    "value": float(np.max(np.abs(K - K[0])) / abs(K[0])) if K[0] else float("nan"),
                    "unit": "1",
                },
                "angular_momentum_norm_max_relative_change": {
                    "value": float(np.max(np.abs(Hn - Hn[0])) / Hn[0]) if Hn[0] else float("nan"),
                    "unit": "1",
                },
            }
        )
        q = np.abs(ds["generalized_coordinate"].values)
        units = ds["coordinate_units"].values if "coordinate_units" in ds.coords else None
        if units is None or len(set(units)) == 1:
            unit = str(units[0]) if units is not None else ds["generalized_coordinate"].attrs.get("units", "")
            out["max_abs_coordinate"] = {"value": float(np.max(q)), "unit": unit}
        else:  # translations and angles: one maximum per unit (CF has no mixed units)
            for u, word in (("m", "translation"), ("rad", "angle")):
                cols = units == u
                if cols.any():
                    out[f"max_abs_{word}_coordinate"] = {"value": float(np.max(q[:, cols])), "unit": u}
        if "tilt_angle" in ds:
            out["max_tilt_angle"] = {"value": float(ds["tilt_angle"].max()), "unit": "rad"}
            out["rms_tilt_angle"] = {"value": float(np.sqrt(np.mean(ds["tilt_angle"].values ** 2))), "unit": "rad"}
        return out

    def plot(self) -> dict:
        from rotaflex.core.plotting import STYLES, label, legend_outside, new_figure

        ds = self.dataset
        titles = {
            "omega_body": "Angular velocity ω* in body axes",
            "omega_inertial": "Angular velocity ω in inertial axes",
            "generalized_coordinate": "Generalized coordinates q",
        }
        figs = {}
        for name, title in titles.items():
            fig, ax = new_figure()
            other = ds[name].dims[1]
            units = ds["coordinate_units"].values if other == "coordinate" and "coordinate_units" in ds.coords else None
            for i, c in enumerate(ds[other].values):
                text = f"{c} [{units[i]}]" if units is not None else str(c)
                ax.plot(ds["time"], ds[name].sel({other: c}), ls=STYLES[i % len(STYLES)], label=text)
            ax.set_xlabel("time t [s]")
            ax.set_ylabel(label(ds[name]))
            ax.set_title(title)
            legend_outside(ax)
            ax.grid(alpha=0.3)
            figs[name] = fig
        fig, ax = new_figure()
        for i, name in enumerate(("kinetic_energy", "rotational_energy_paper")):
            ax.plot(ds["time"], ds[name], ls=STYLES[i], label=ds[name].attrs["long_name"])
        ax.set_xlabel("time t [s]")
        ax.set_ylabel("energy [J]")
        ax.set_title("Kinetic energy and the paper's energy expression")
        legend_outside(ax)
        ax.grid(alpha=0.3)
        figs["energy"] = fig
        return figs
