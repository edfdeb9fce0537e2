"""Result objects: an ``xarray.Dataset`` with solver status, summary scalars and figures."""

from __future__ import annotations

import gc
import importlib
import json
import time
from pathlib import Path
from typing import Any

import numpy as np

from rotaflex.core.io import defer_dask, replace_dir, write_json_atomic, write_netcdf

#: The statuses of a run that completed with a physical finding rather than a failure; the results
#: are written and count as done (exit 0, not "failed" in a sweep); the status word and the
#: message say what was found. ``not_periodic``: a steady state that did not settle within
#: its cycle budget (quasi-periodic or chaotic motion near a jump), evaluated over its last cycles.
FINDINGS = frozenset({"not_periodic"})


def completed(status: str) -> bool:
    """True for ``"success"`` and the :data:`FINDINGS` statuses (the one rule of the CLI, the
    sweep runner and the sweep table)."""
    return status == "success" or status in FINDINGS


def summary_attrs(config, t0, extra, message) -> dict:
    """Result attributes of a successful run: status, message, wall time since ``t0`` [s], the
    config and the summary entries (JSON)."""
    return {
        "status": "success",
        "message": message,
        "wall_time": time.perf_counter() - t0,
        "config": json.dumps(config, default=str),
        "summary_extra": json.dumps(extra, default=float),
    }


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
        # where the class lives: load_result imports it in a process that has not (a resumed
        # sweep's client reading a case's final state)
        self.dataset.attrs.setdefault("result_class", f"{type(self).__module__}:{type(self).__qualname__}")

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
        """Write the dataset to NetCDF atomically (:func:`rotaflex.core.io.write_netcdf`)."""
        return write_netcdf(path, self.dataset)

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

    def write_extra(self, out_dir: Path) -> list[Path]:
        """Domain-specific files written with the result set (e.g. meshes); none by default."""
        return []

    def save(
        self,
        out_dir: str | Path,
        *,
        figures: bool = True,
        fig_format: str | None = None,
        dpi: int | None = None,
        provenance: dict[str, Any] | None = None,
    ) -> list[Path]:
        """Write ``result.nc``, ``summary.json``, extra files and figures into ``out_dir`` as a set.

        Everything is written into a temporary sibling directory that then replaces
        ``out_dir`` in one step (:func:`rotaflex.core.io.replace_dir`): an interrupted save
        leaves the previous result directory complete, never a mix of old and new files.

        Parameters
        ----------
        figures : bool
            Write the figures of :meth:`plot`.
        fig_format : {"png", "svg", "pdf"}, optional
            Default: the one set with :func:`rotaflex.core.plotting.configure` (png).
        dpi : int, optional
            Resolution of raster figures (default of :func:`rotaflex.core.plotting.save_figure`).
        provenance : dict, optional
            Global attributes to add (see :func:`rotaflex.core.provenance.provenance`); the
            version, commit and time are added if missing.
        """
        from rotaflex.core.provenance import provenance as _prov

        self.dataset.attrs.update({**_prov(), **(provenance or {})})  # keeps input_file/sha256 set earlier

        def write(tmp: Path) -> list[Path]:
            paths = [self.to_netcdf(tmp / "result.nc")]
            paths.append(write_json_atomic(tmp / "summary.json", self.summary()))
            paths += self.write_extra(tmp)
            if figures:
                from rotaflex.core.plotting import chosen_format, save_figure

                fmt = fig_format or chosen_format()
                for stem, fig in self.plot().items():
                    paths.append(save_figure(fig, tmp / f"{stem}.{fmt}", dpi=dpi, fmt=fmt))
            return paths

        return replace_dir(out_dir, write)

    def failed_check(self, name: str, measured: str, criterion: str) -> None:
        """Mark the result as failing one of its own checks (``status = "failed_check"``).

        The CLI then exits 1 and prints ``message``, which names the check, the measured value
        and the criterion.
        """
        self.dataset.attrs["status"] = "failed_check"
        self.dataset.attrs["message"] = f"check {name!r} failed: {measured} (required {criterion})"
        self.dataset.attrs["failed_check"] = name


def import_xarray():
    """``xarray``, with the imports it defers to its first variable already done.

    xarray asks whether data are dask arrays when it makes its first variable and index, and
    imports dask for the answer (``dask.array``: 0.4-0.5 s); :func:`rotaflex.core.io.defer_dask`
    gives the same answer without the import while dask is not loaded. What xarray still defers
    is done here, before a solver's clock starts, so that the first run of a process does not
    count an import as solver time.
    """
    import xarray as xr

    defer_dask()
    xr.Dataset({"v": ("x", np.zeros(1))}, coords={"x": np.zeros(1)})
    return xr


def freeze_imports() -> None:
    """Take the objects that exist now (mostly what imports made) out of garbage collection.

    Called once per process (later calls do nothing) before a solver's clock starts. A full
    collection walks every tracked object, and after the imports of a rotor verb (numpy,
    scipy, xarray, pandas) there are ~87,000 of them: 38 ms a collection, and one fell inside
    the first solve of a process (rotor disk: reported 0.196 s against 0.157 s on repeat).
    :func:`gc.freeze` moves them to a generation that is never walked; cycles made later are
    collected as before. Garbage that exists at the call stays until the process ends.
    """
    global _FROZEN
    if not _FROZEN:
        gc.freeze()
        _FROZEN = True


_FROZEN = False
_KINDS: dict[str, type[Result]] = {}


def register_result(cls: type[Result]) -> type[Result]:
    """Class decorator: make ``load_result`` return ``cls`` for datasets of ``cls.kind``."""
    _KINDS[cls.kind] = cls
    return cls


def load_result(path: str | Path) -> Result:
    """Open a saved ``result.nc`` as the Result subclass that wrote it (data loaded eagerly)."""
    import xarray as xr

    defer_dask()  # numpy data: no dask import (0.1 s) to ask whether they are dask data
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        ds = ds.load()
    kind = ds.attrs.get("result_kind", "")
    module = str(ds.attrs.get("result_class", "")).partition(":")[0]
    if kind not in _KINDS and module.startswith("rotaflex."):  # registered when its module is imported
        try:
            importlib.import_module(module)
        except ImportError:  # a class of another version: the generic Result
            pass
    return _KINDS.get(kind, Result)(ds)
