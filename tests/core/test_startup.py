"""A verb imports only what it uses (issue 25): checked as a property of sys.modules in a fresh
process, not as a time (times are in benchmarks/bench_startup.py)."""

from __future__ import annotations

from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_help_and_campbell_import_neither_numba_nor_sympy_nor_scipy_integrate(tmp_path, python_json):
    code = f"""
        import json, sys
        from rotaflex.cli import main

        def run(argv):
            try:
                main(argv)
            except SystemExit as exc:
                assert exc.code == 0, (argv, exc.code)
            return sorted(m for m in ("numba", "sympy", "scipy.integrate", "distributed", "matplotlib",
                                      "xarray", "dask", "dask.array") if m in sys.modules)

        helped = run(["--help"])
        campbell = run(["rotor", "campbell", {str(ROOT / "examples/rotor/fe_friswell_5_9_1.toml")!r},
                        "--out", {str(tmp_path / "out")!r}, "--no-figures", "--quiet"])
        print(json.dumps({{"help": helped, "campbell": campbell}}))
    """
    got = python_json(code)
    assert got["help"] == []  # --help loads none of the heavy libraries
    # campbell computes eigenvalues and writes NetCDF: xarray only; no compiler, no symbolic
    # algebra, no ODE integrator, no dask (xarray would load dask.array and dask.base to ask
    # whether numpy data are dask data, 0.5 s), no Dask cluster client, no plotting with --no-figures
    assert got["campbell"] == ["xarray"]
    assert (tmp_path / "out" / "result.nc").exists()


def test_xarray_without_dask_loaded_still_tells_dask_data_apart(tmp_path, python_json):
    # rotaflex.core.io.defer_dask answers xarray's "is this dask data?" without importing dask
    # while none is loaded; once dask.array is imported, dask data must behave as dask data
    # again (chunks kept, written and read back), and the file written must be the same
    code = f"""
        import json, sys
        import numpy as np
        from rotaflex.core.io import write_netcdf
        from rotaflex.core.result import import_xarray

        xr = import_xarray()
        ds = xr.Dataset({{"a": (("x", "y"), np.arange(12.0).reshape(4, 3), {{"units": "m"}})}},
                        coords={{"x": np.arange(4)}})
        write_netcdf({str(tmp_path / "numpy.nc")!r}, ds)
        before = sorted(m for m in sys.modules if m.split(".")[0] in ("dask", "distributed"))
        left = sorted(m for m, v in sys.modules.items() if v is None and m.split(".")[0] in ("dask", "distributed"))

        import dask.array as da
        lazy = xr.DataArray(da.from_array(ds["a"].values, chunks=2), dims=("x", "y"))
        write_netcdf({str(tmp_path / "dask.nc")!r}, xr.Dataset({{"a": lazy}}, coords={{"x": np.arange(4)}}))
        back = {{k: xr.open_dataset(str(p), engine="h5netcdf").load() for k, p in
                (("numpy", {str(tmp_path / "numpy.nc")!r}), ("dask", {str(tmp_path / "dask.nc")!r}))}}
        print(json.dumps({{
            "before": before, "left": left,
            "chunks": [list(c) for c in lazy.chunks],
            "numpy_has_chunks": ds["a"].chunks is not None,
            "numpy_back": back["numpy"].identical(ds),
            "dask_back": bool((back["dask"]["a"].values == ds["a"].values).all()),
        }}))
    """
    got = python_json(code)
    assert got["before"] == []  # a dataset made and written: dask never imported
    assert got["left"] == []  # and no import blocked after the write
    assert got["chunks"] == [[2, 2], [2, 1]]  # dask data stay lazy, in their chunks
    assert not got["numpy_has_chunks"]
    assert got["numpy_back"] and got["dask_back"]
