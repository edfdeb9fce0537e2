"""What every FE rotor verb does around its analysis: BLAS threads pinned, a progress callback,
the summary attributes of the result, and the fluid-film bearing tables added to it.
"""

from __future__ import annotations

from contextlib import contextmanager

import xarray as xr

from rotaflex.core.result import summary_attrs
from rotaflex.core.units import rad_s_to_rpm
from rotaflex.rotor.fe.model import Rotor

__all__ = ["add_fluid_film_tables", "oil_whip", "pinned", "progress_callback", "summary_attrs"]


def add_fluid_film_tables(ds: xr.Dataset, rotor: Rotor) -> xr.Dataset:
    """``ds`` with the coefficient table of every fluid-film bearing of ``rotor`` (variables ``ff_*``).

    Dimensions ``fluid_film`` (bearing names) and ``ff_speed`` (table index; a shorter table is
    padded with NaN): speed, eccentricity ratio, attitude angle, journal position, Sommerfeld
    number and the 8 coefficients with units (:meth:`FluidFilmTable.to_dataset`), plus the static
    load each bearing carries (``ff_load_x``, ``ff_load_y`` [N]) and its node.
    """
    parts, names = [], []
    for i, (b, (node, _, el)) in enumerate(zip(rotor.resolved.bearing, rotor.bearings, strict=True)):
        if el.table is None:
            continue
        t = el.table.to_dataset().drop_vars("speed").rename({"speed": "ff_speed"})
        t = t.assign_coords(ff_speed=range(t.sizes["ff_speed"]))  # an index: the outer join pads with NaN
        t = t.rename({k: f"ff_{k}" for k in t.data_vars})
        t["ff_node"] = node
        t["ff_load_x"] = xr.DataArray(b.fluid_film.load[0], attrs={"units": "N"})
        t["ff_load_y"] = xr.DataArray(b.fluid_film.load[1], attrs={"units": "N"})
        parts.append(t)
        names.append(b.name or f"bearing[{i}]")
    if not parts:
        return ds
    tables = xr.concat(parts, dim="fluid_film", join="outer", combine_attrs="override")
    tables = tables.assign_coords(fluid_film=names).drop_vars("ff_speed")
    for k in tables.data_vars:  # concat keeps the first part's attributes; make sure of the units
        tables[k].attrs = parts[0][k].attrs
    return ds.merge(tables)


def oil_whip(rotor: Rotor, unstable: list[dict]) -> dict:
    """Summary entry of the oil-whip onset (lowest speed at which a mode goes unstable) on fluid film."""
    if not unstable or not any(el.table is not None for _, _, el in rotor.bearings):
        return {}
    first = min(unstable, key=lambda u: u["speed"])
    return {"oil_whip_onset_rpm": {"value": rad_s_to_rpm(first["speed"]), "unit": "rpm", "mode": first["mode"]}}


def pinned(run):
    """Run an analysis with the BLAS/OpenMP pools pinned to one thread (``ROTAFLEX_BLAS_THREADS``
    overrides), as the CLI and the sweep workers do, so that library calls get the same speed:
    the matrices are small and idle pool threads spinning between calls cost far more than
    they gain on a shared machine (the example's Campbell with direct critical speeds: 13.2 s
    CPU unpinned, see docs/fluid-film-bearings.md)."""
    import functools

    @functools.wraps(run)
    def wrapper(config: dict, *, progress: bool = False):
        from rotaflex.core.threads import limit_blas_threads

        with limit_blas_threads():
            return run(config, progress=progress)

    return wrapper


@contextmanager
def progress_callback(enabled: bool, total: float, desc: str, unit: str):
    """``progress(done, total)`` for a solver: a :class:`~rotaflex.core.progress.Progress` bar on a
    terminal, one line per 10 % when stderr is not one; None (nothing shown) when disabled."""
    if not enabled:
        yield None
        return
    from rotaflex.core.progress import Progress

    with Progress(total, desc, unit) as bar:
        yield bar.update
