"""Gear post-processing benchmarks (printed, not asserted).

1. Result size of a full 4000 rpm run (default mesh, theta_s) with the default decimation and
   with ``[output] every = 1``.
2. Dynamic mesh convergence: the 4000 rpm case on the coarse, default and fine (2x) meshes:
   peak and mean single-pair contact force, DTE, fillet stress.
3. Driver choice for the speed-mismatch cases (Fig. 10, 11): driver A and driver B, contact
   losses / regains, peak force, energy balance.
4. Quasi-static (1000 rpm) DTE and fillet stress against static FE, coarse and default meshes.

    PYTHONPATH=src python benchmarks/bench_gear_post.py [sizes] [mesh] [driver] [qs] [--tiny]

``--tiny``: every run on the coarse mesh over 0.2 deg (the quasi-static one over 0.6 deg with a
0.05 deg two-pair zone, so that it has single-pair records to compare), one mesh preset, the
driver choice at 20000/20200 rpm only; checks the script runs.
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np

from rotaflex.gear.cases import simulate

#: --tiny: overrides merged into every case (None: the cases as written)
TINY: dict | None = None


def _merged(base: dict, extra: dict) -> dict:
    """``base`` with ``extra`` merged in, table by table (``extra`` wins)."""
    out = dict(base)
    for k, v in extra.items():
        out[k] = _merged(out.get(k, {}), v) if isinstance(v, dict) else v
    return out


def run_case(config: dict):
    """:func:`rotaflex.gear.cases.simulate.run_case` of ``config`` (with the --tiny overrides)."""
    return simulate.run_case(_merged(config, TINY) if TINY else config)


def _losses(ds, frac=0.01):
    f = ds["contact_force"].values
    on = f > frac * float(ds["nominal_force"])
    if not on.any():
        return 0, 0
    first = int(np.argmax(on))
    d = np.diff(on[first:].astype(int))
    return int(np.sum(d == -1)), int(np.sum(d == 1))


def sizes() -> None:
    for every in (10, 1):
        t = time.perf_counter()
        res = run_case({"output": {"every": every}})
        with tempfile.TemporaryDirectory() as d:
            p = res.to_netcdf(Path(d) / "result.nc")
            size = p.stat().st_size
        mem = sum(v.nbytes for v in res.dataset.variables.values())
        what = "coarse mesh, 0.2 deg" if TINY else "default mesh"
        print(
            f"4000 rpm, {what}, every = {every}: {res.dataset.sizes['time']} records, "
            f"result.nc {size / 1e6:.1f} MB, in memory {mem / 1e6:.1f} MB "
            f"({time.perf_counter() - t:.1f} s)",
            flush=True,
        )


def mesh() -> None:
    for preset, dt in (("coarse", 3e-8),) if TINY else (("coarse", 3e-8), ("default", 3e-8), ("fine", 1.5e-8)):
        t = time.perf_counter()
        res = run_case({"mesh": {"preset": preset}, "solver": {"dt": dt}})
        ds = res.dataset
        s = {k: v["value"] for k, v in res.summary().items()}
        print(
            f"{preset:8s} dt {dt:.1e}: steps {s['steps']}, peak {s['peak_contact_force']:.1f} N, "
            f"mean single-pair {s['mean_single_pair_force']:.1f} N, DTE p2p "
            f"{s['dte_peak_to_peak'] * 1e6:.3f} um, mean DTE (single-pair) "
            f"{_single_mean(ds, 'transmission_error') * 1e6:.3f} um, root stress peak "
            f"{s['root_stress_peak'] / 1e6:.1f} MPa, energy {s['energy_balance_error']:.4f}, "
            f"{time.perf_counter() - t:.1f} s",
            flush=True,
        )


def _single_mean(ds, name):
    ang = ds["rotation_angle"].values[:, 0]
    th2, ths = float(ds["theta_2"]), float(ds["theta_s"])
    sel = (ang > th2) & (ang < ths - th2)
    return float(np.mean(ds[name].values[sel]))


def driver() -> None:
    for speeds in ((20000.0, 20200.0), (4000.0, 4040.0))[: 1 if TINY else 2]:
        for drv in ("A", "B"):
            res = run_case({"operation": {"speed_rpm": list(speeds), "driver": drv}})
            ds = res.dataset
            lost, regained = _losses(ds)
            s = {k: v["value"] for k, v in res.summary().items()}
            print(
                f"{speeds[0]:g}/{speeds[1]:g} rpm, driver {drv}: contact lost {lost}, regained "
                f"{regained}, impacts {s['impacts']:g}, peak {s['peak_contact_force']:.1f} N "
                f"(K_v {s['dynamic_factor']:.3f}), energy balance {s['energy_balance_error']:.4f}"
                f", D {float(ds['velocity_pass_loss'][-1]):.3e} J, DTE p2p "
                f"{s['dte_peak_to_peak'] * 1e6:.2f} um, root stress peak "
                f"{s['root_stress_peak'] / 1e6:.1f} MPa",
                flush=True,
            )


def quasi_static() -> None:
    """Quasi-static DTE / fillet stress vs static FE on the coarse and default meshes."""
    from rotaflex.reproduce.gear_post import quasi_static_entry

    for preset in ("coarse",) if TINY else ("coarse", "default"):
        cfg = {
            "operation": {"speed_rpm": [1000.0, 1000.0], "span_deg": 10.53},
            "mesh": {"preset": preset},
            "output": {"every": 20},
        }
        if TINY:
            cfg = _merged(cfg, {"operation": {"span_deg": 0.6, "theta_2_deg": 0.05}, "output": {"every": 5}})
        res = simulate.run_case(cfg)
        with tempfile.TemporaryDirectory() as d:
            entry = quasi_static_entry(res, Path(d), preset)
        for c in entry.checks:
            print(f"{preset:8s} {c.name}: {c.measured:.4f} ({c.criterion})", flush=True)


def main() -> None:
    global TINY
    parts = {"sizes": sizes, "mesh": mesh, "driver": driver, "qs": quasi_static}
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("parts", nargs="*", help="parts to run: " + ", ".join(parts) + " (default: all)")
    ap.add_argument("--tiny", action="store_true", help="coarse mesh, 0.2 deg spans (checks it runs)")
    a = ap.parse_args()
    if unknown := set(a.parts) - set(parts):
        ap.error(f"unknown part(s) {', '.join(sorted(unknown))}; choose from {', '.join(parts)}")
    if a.tiny:
        TINY = {"mesh": {"preset": "coarse"}, "operation": {"span_deg": 0.2}}
    for w in a.parts or parts:
        parts[w]()


if __name__ == "__main__":
    main()
