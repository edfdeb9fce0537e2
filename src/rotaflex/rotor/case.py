"""``rotaflex rotor simulate``: TOML case -> model -> simulation -> RotorResult."""

from __future__ import annotations

import numpy as np

from rotaflex.core.config import from_mapping
from rotaflex.core.result import Result, register_result
from rotaflex.rotor.model import FreeBody, RotorModel


def model_from_config(config: dict) -> RotorModel | FreeBody:
    """A ``[free_body]`` table gives a FreeBody; otherwise the tables form a RotorModel."""
    if "free_body" in config:
        extra = [k for k in config if k != "free_body"]
        if extra:
            from rotaflex.core.errors import InputError

            raise InputError(extra[0], config[extra[0]], "nothing beside [free_body] in a free-body case")
        return from_mapping(FreeBody, config["free_body"], "free_body")
    return from_mapping(RotorModel, config)


def run_case(config: dict, *, progress: bool = False) -> RotorResult:
    """Validate a parsed rotor config and simulate it."""
    from rotaflex.rotor.simulate import simulate

    return simulate(model_from_config(config), progress=progress)


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
                    "unit": "",
                },
                "angular_momentum_norm_max_relative_change": {
                    "value": float(np.max(np.abs(Hn - Hn[0])) / Hn[0]) if Hn[0] else float("nan"),
                    "unit": "",
                },
                "max_abs_coordinate": {
                    "value": float(np.max(np.abs(ds["generalized_coordinate"].values))),
                    "unit": "SI",
                },
            }
        )
        if "tilt_angle" in ds:
            out["max_tilt_angle"] = {"value": float(ds["tilt_angle"].max()), "unit": "rad"}
            out["rms_tilt_angle"] = {"value": float(np.sqrt(np.mean(ds["tilt_angle"].values ** 2))), "unit": "rad"}
        return out

    def plot(self) -> dict:
        from rotaflex.core.plotting import label, new_figure

        ds = self.dataset
        figs = {}
        for name in ("omega_body", "omega_inertial", "generalized_coordinate"):
            fig, ax = new_figure()
            other = ds[name].dims[1]
            for c in ds[other].values:
                ax.plot(ds["time"], ds[name].sel({other: c}), label=str(c))
            ax.set_xlabel("time [s]")
            ax.set_ylabel(label(ds[name]))
            ax.legend(fontsize=8)
            ax.grid(alpha=0.3)
            figs[name] = fig
        fig, ax = new_figure()
        for name in ("kinetic_energy", "rotational_energy_paper"):
            ax.plot(ds["time"], ds[name], label=ds[name].attrs["long_name"])
        ax.set_xlabel("time [s]")
        ax.set_ylabel("energy [J]")
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
        figs["energy"] = fig
        return figs
