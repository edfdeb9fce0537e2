"""sweep.nc: provenance, identifier-safe dimensions, schema units; figures apart for diagnostics."""

import hashlib

import pytest
import xarray as xr

from rotaflex.cli import main


def test_sweep_nc_provenance_and_safe_dims(tmp_path, capsys, selftest_domain):
    cfg = tmp_path / "s.toml"
    cfg.write_text('domain = "selftest"\nx = 1.0\ny = 0.0\n')
    with pytest.raises(SystemExit) as exc:
        main(["sweep", str(cfg), "--vary", "x=1,2", "--vary", "y=0.5,1.5", "-o", str(tmp_path / "s"), "-j", "0", "-q"])
    assert exc.value.code == 0, capsys.readouterr().err
    with xr.open_dataset(tmp_path / "s" / "sweep.nc", engine="h5netcdf") as ds:
        attrs = dict(ds.attrs)
        assert ds["a"].dims == ("x", "y")
        assert ds["a"].values.tolist() == [[1.5, 2.5], [4.5, 5.5]]  # a = x**2 + y
    assert attrs["input_sha256"] == hashlib.sha256(cfg.read_bytes()).hexdigest()
    assert attrs["rotaflex_version"] and attrs["created_utc"].endswith("Z")
    figs = sorted(p.name for p in (tmp_path / "s" / "figures").iterdir())
    assert "summary_vs_x.png" in figs and "diagnostics_vs_x.png" in figs


def test_dim_names_are_identifiers():
    from rotaflex.sweep.combine import dim_name

    for key in ("motion.spin_speed", "loads[0].duration", "operation.speed_rpm[1]", "2d.x"):
        assert dim_name(key).isidentifier(), key
    assert dim_name("loads[0].duration") == "loads_0_duration"
