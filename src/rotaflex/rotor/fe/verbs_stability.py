"""``rotaflex rotor stability FILE --out DIR``: API 617 Level I and Level II in one report.

Writes ``result.nc`` (the Level I sweep, Q_A per stage, the Level II cases and every bearing
kind's own outputs such as seal leakage or AMB sensitivity), ``summary.json`` (the numbers and
both verdicts), ``verdict.md`` (the table engineers read) and the figures ``level1`` (log dec
versus applied cross-coupling, Q_A and Q_0 marked), ``csr_map`` (centrifugal compressors with a
mean gas density) and ``level2`` (log dec per element combination). See docs/stability.md.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import xarray as xr

from rotaflex.core.io import write_text_atomic
from rotaflex.core.result import register_result
from rotaflex.core.units import rad_s_to_rpm, rpm_to_rad_s
from rotaflex.rotor.fe.case_config import parse
from rotaflex.rotor.fe.case_output import summary_attrs
from rotaflex.rotor.fe.results import _FEResult, _model_fig

__all__ = ["StabilityResult", "run_stability", "stability_dataset", "stability_figures", "verdict_table"]


def run_stability(config: dict, *, progress: bool = False) -> StabilityResult:
    """Level I screening and Level II analysis of ``[stability]`` at its ``speed_rpm`` (the MCS)."""
    from rotaflex.rotor.fe.stability import NO_LEVEL1, check, level1, level2

    t0 = time.perf_counter()
    rotor, spec = parse(config, "stability")
    check(spec)
    l1 = None if spec.machine in NO_LEVEL1 else level1(rotor, spec)
    l2 = level2(rotor, spec)
    names = [b.name or f"bearing[{i}]" for i, b in enumerate(rotor.bearing)]
    outputs = {}
    for name, (_, _, el) in zip(names, rotor.bearings, strict=True):
        for key, da in el.outputs(np.array([rpm_to_rad_s(spec.speed_rpm)])).items():
            outputs[f"{name}_{key}"] = da.rename({d: f"{name}_{d}" for d in da.dims})  # one cavity axis per seal
    ds, extra, msg = stability_dataset(spec, l1, l2, outputs)
    ds.attrs.update(summary_attrs(config, t0, extra, msg))
    return StabilityResult(ds)


def stability_dataset(spec, l1, l2, outputs: dict) -> tuple[xr.Dataset, dict, str]:
    """Dataset, summary entries and message of a Level I (None: not applicable) and Level II
    outcome at ``spec.speed_rpm``; ``outputs``: the elements' own outputs (name -> DataArray).
    One layout for ``rotor stability`` and ``system stability``."""
    ds = xr.Dataset(
        {
            "log_dec_level2": ("case", l2.log_dec, {"units": "1", "long_name": "first forward mode log dec"}),
            "frequency_level2": ("case", l2.frequency, {"units": "rad/s", "long_name": "its damped frequency"}),
            "speed": ((), rpm_to_rad_s(spec.speed_rpm), {"units": "rad/s", "long_name": "maximum continuous speed"}),
        },
        coords={"case": list(l2.cases)},
    )
    for key, da in outputs.items():
        ds[key] = da
    ds.attrs.update({"machine": spec.machine, "location": spec.location, "mean_density": spec.mean_density or np.nan})
    verdict2 = "pass" if l2.passed else "fail"
    extra = {"speed": {"value": spec.speed_rpm, "unit": "rpm"}}
    msg = f"Level I: not applicable ({spec.machine}); "
    ds.attrs["reasons"] = ""
    if l1 is not None:
        msg = _add_level1(ds, extra, l1)
    extra["level2_log_dec"] = {"value": l2.full, "unit": "1", "limit": l2.limit}
    extra["level2_verdict"] = {"value": verdict2, "unit": ""}
    for case, d in zip(l2.cases, l2.log_dec, strict=True):
        extra[f"level2_log_dec[{case}]"] = {"value": float(d), "unit": "1"}
    msg += f"Level II: log dec {l2.full:.3g} (limit {l2.limit:g}): {verdict2}"
    return ds, extra, msg


def _add_level1(ds: xr.Dataset, extra: dict, l1) -> str:
    """Put the Level I outcome into ``ds`` and ``extra``; the message's Level I part."""
    ds["log_dec_level1"] = xr.DataArray(
        l1.log_dec, dims="q", coords={"q": ("q", l1.q, {"units": "N/m"})}, attrs={"units": "1"}
    )
    ds["log_dec_level1"].attrs["long_name"] = "first forward mode log dec (Level I)"
    ds["q_stage"] = ("stage", l1.q_stage, {"units": "N/m", "long_name": "anticipated cross-coupling per stage"})
    ds["q_a"] = ((), l1.q_a, {"units": "N/m", "long_name": "anticipated cross-coupling Q_A"})
    ds["q_0"] = ((), l1.q0, {"units": "N/m", "long_name": "cross-coupling at zero log dec Q_0"})
    ds["csr"] = ((), l1.csr, {"units": "1", "long_name": "MCS / first critical speed on rigid supports"})
    verdict1 = "Level II required" if l1.level2_required else "Level II not required"
    extra.update(
        {
            "Q_A": {"value": l1.q_a, "unit": "N/m"},
            "Q_0": {"value": l1.q0, "unit": "N/m"},
            "Q0_over_QA": {"value": l1.ratio, "unit": "1"},
            "log_dec_at_QA": {"value": l1.log_dec_a, "unit": "1"},
            "log_dec_at_Q0_zero": {"value": l1.log_dec_0, "unit": "1"},
            "first_forward_frequency_at_QA": {"value": l1.frequency_a / (2 * np.pi), "unit": "Hz"},
            "rigid_support_critical_speed": {"value": rad_s_to_rpm(l1.rigid_critical), "unit": "rpm"},
            "CSR": {"value": l1.csr, "unit": "1"},
            "CSR_region": {"value": l1.region or "not evaluated", "unit": ""},
            "level1_verdict": {"value": verdict1, "unit": "", "reasons": list(l1.reasons)},
        }
    )
    ds.attrs["reasons"] = "; ".join(l1.reasons)
    return (
        f"Level I: Q_A = {l1.q_a:.4g} N/m, Q_0 = {l1.q0:.4g} N/m, Q_0/Q_A = {l1.ratio:.3g}, "
        f"log dec at Q_A {l1.log_dec_a:.3g}, CSR {l1.csr:.3g}: {verdict1}; "
    )


@register_result
class StabilityResult(_FEResult):
    """API 617 Level I and Level II results (see :func:`run_stability`)."""

    kind = "rotor_fe_stability"

    def verdict_table(self) -> str:
        """The verdicts as a Markdown table."""
        return verdict_table(self.dataset, self.summary())

    def write_extra(self, out_dir: Path) -> list[Path]:
        return [write_text_atomic(Path(out_dir) / "verdict.md", self.verdict_table())]

    def plot(self) -> dict:
        return {**_model_fig(self), **stability_figures(self.dataset)}


def verdict_table(ds: xr.Dataset, s: dict) -> str:
    """The verdicts of a stability dataset ``ds`` with its summary ``s`` as a Markdown table."""
    rows = [("Level I", f"not applicable ({ds.attrs['machine']})")]
    if "q_a" in ds:
        rows = [
            ("Anticipated cross-coupling Q_A", f"{float(ds['q_a']):.4g} N/m"),
            ("Q at zero log dec Q_0", f"{float(ds['q_0']):.4g} N/m"),
            ("Q_0 / Q_A", f"{s['Q0_over_QA']['value']:.3g}"),
            ("Log dec at Q_A (Level I)", f"{s['log_dec_at_QA']['value']:.3g}"),
            ("CSR (MCS / rigid-support critical)", f"{float(ds['csr']):.3g}, region {s['CSR_region']['value']}"),
            (
                "Level I verdict",
                s["level1_verdict"]["value"] + (f" ({ds.attrs['reasons']})" if ds.attrs["reasons"] else ""),
            ),
        ]
    rows += [
        (f"Level II log dec: {c}", f"{d:.3g}")
        for c, d in zip(ds["case"].values, ds["log_dec_level2"].values, strict=True)
    ]
    rows.append(("Level II verdict", f"{s['level2_verdict']['value']} (log dec >= {s['level2_log_dec']['limit']:g})"))
    return "| item | value |\n|---|---|\n" + "\n".join(f"| {a} | {b} |" for a, b in rows) + "\n"


def stability_figures(ds: xr.Dataset) -> dict:
    """The figures of a stability dataset: ``level1`` (when it has one), ``csr_map``
    (centrifugal compressors with a mean gas density) and ``level2``."""
    from rotaflex.rotor.fe.figures_stability import csr_map_figure, level1_figure, level2_figure

    figs = {}
    if "q_a" in ds:
        figs["level1"] = level1_figure(ds)
    if "csr" in ds and ds.attrs.get("machine") == "centrifugal_compressor" and np.isfinite(ds.attrs["mean_density"]):
        figs["csr_map"] = csr_map_figure(float(ds["csr"]), float(ds.attrs["mean_density"]))
    figs["level2"] = level2_figure(ds)
    return figs
