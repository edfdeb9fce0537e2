"""Result objects: an ``xarray.Dataset`` with solver status, summary scalars and figures."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np

from rotaflex.core.io import write_atomic, write_json_atomic


class Result:
    """Outcome of one simulation.

    Parameters
    ----------
    dataset : xarray.Dataset
        Named dimensions (``time``, ``axis``, ...), SI values, a ``units`` attribute on every
        variable. Global attributes carry ``status``, ``message``, ``wall_time`` [s] and
        ``config`` (the resolved configuration as JSON) for provenance.

    Notes
    -----
    Domains subclass this to add summary scalars (:meth:`summary`) and figures (:meth:`plot`).
    """

    #: name stored in the dataset's ``result_kind`` attribute, used by :func:`load_result`
    kind = "generic"

    def __init__(self, dataset):
        self.dataset = dataset
        self.dataset.attrs.setdefault("result_kind", self.kind)

    # -- provenance ---------------------------------------------------------------------
    @property
    def status(self) -> str:
        return str(self.dataset.attrs.get("status", "unknown"))

    @property
    def message(self) -> str:
        return str(self.dataset.attrs.get("message", ""))

    @property
    def config(self) -> dict[str, Any]:
        return json.loads(self.dataset.attrs.get("config", "{}"))

    def to_xarray(self):
        """The underlying ``xarray.Dataset``."""
        return self.dataset

    # -- output -------------------------------------------------------------------------
    def to_netcdf(self, path: str | Path) -> Path:
        """Write the dataset to NetCDF atomically (temporary file, then rename)."""
        return write_atomic(path, lambda p: self.dataset.to_netcdf(p, engine="h5netcdf"))

    def summary(self) -> dict[str, dict[str, Any]]:
        """Key scalars as ``{name: {"value": v, "unit": u}}``.

        The base version lists solver status, wall time and every 0-d data variable.
        """
        out: dict[str, dict[str, Any]] = {
            "status": {"value": self.status, "unit": ""},
            "wall_time": {"value": float(self.dataset.attrs.get("wall_time", np.nan)), "unit": "s"},
        }
        for name, var in self.dataset.data_vars.items():
            if var.ndim == 0:
                out[name] = {"value": var.item(), "unit": var.attrs.get("units", "")}
        return out

    def plot(self) -> dict[str, Any]:
        """Matplotlib figures keyed by file stem. The base version plots every time series."""
        from rotaflex.core.plotting import time_series_figures

        return time_series_figures(self.dataset)

    def save(self, out_dir: str | Path, *, figures: bool = True) -> list[Path]:
        """Write ``result.nc``, ``summary.json`` and (optionally) PNG figures into ``out_dir``."""
        out_dir = Path(out_dir)
        out_dir.mkdir(parents=True, exist_ok=True)
        paths = [self.to_netcdf(out_dir / "result.nc")]
        paths.append(write_json_atomic(out_dir / "summary.json", self.summary()))
        if figures:
            from rotaflex.core.plotting import save_figure

            for stem, fig in self.plot().items():
                paths.append(save_figure(fig, out_dir / f"{stem}.png"))
        return paths


_KINDS: dict[str, type[Result]] = {}


def register_result(cls: type[Result]) -> type[Result]:
    """Class decorator: make ``load_result`` return ``cls`` for datasets of ``cls.kind``."""
    _KINDS[cls.kind] = cls
    return cls


def load_result(path: str | Path) -> Result:
    """Open a saved ``result.nc`` as the Result subclass that wrote it (data loaded eagerly)."""
    import xarray as xr

    with xr.open_dataset(path, engine="h5netcdf") as ds:
        ds = ds.load()
    return _KINDS.get(ds.attrs.get("result_kind", ""), Result)(ds)
