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
from rotaflex.rotor.fe.case_config import parse
from rotaflex.rotor.fe.case_output import summary_attrs
from rotaflex.rotor.fe.model import RPM
from rotaflex.rotor.fe.results import _FEResult, _model_fig

__all__ = ["StabilityResult", "run_stability"]


def run_stability(config: dict, *, progress: bool = False) -> StabilityResult:
    """Level I screening and Level II analysis of ``[stability]`` at its ``speed_rpm`` (the MCS)."""
    from rotaflex.rotor.fe.stability import level1, level2

    t0 = time.perf_counter()
    rotor, spec = parse(config, "stability")
    l1 = level1(rotor, spec)
    l2 = level2(rotor, spec)
    names = [b.name or f"bearing[{i}]" for i, b in enumerate(rotor.bearing)]
    ds = xr.Dataset(
        {
            "log_dec_level1": ("q", l1.log_dec, {"units": "1", "long_name": "first forward mode log dec (Level I)"}),
            "q_stage": ("stage", l1.q_stage, {"units": "N/m", "long_name": "anticipated cross-coupling per stage"}),
            "log_dec_level2": ("case", l2.log_dec, {"units": "1", "long_name": "first forward mode log dec"}),
            "frequency_level2": ("case", l2.frequency, {"units": "rad/s", "long_name": "its damped frequency"}),
            "q_a": ((), l1.q_a, {"units": "N/m", "long_name": "anticipated cross-coupling Q_A"}),
            "q_0": ((), l1.q0, {"units": "N/m", "long_name": "cross-coupling at zero log dec Q_0"}),
            "csr": ((), l1.csr, {"units": "1", "long_name": "MCS / first critical speed on rigid supports"}),
            "speed": ((), spec.speed_rpm * RPM, {"units": "rad/s", "long_name": "maximum continuous speed"}),
        },
        coords={"q": ("q", l1.q, {"units": "N/m"}), "stage": np.arange(len(spec.stage)), "case": list(l2.cases)},
    )
    for name, (_, _, el) in zip(names, rotor.bearings, strict=True):
        for key, da in el.outputs(np.array([spec.speed_rpm * RPM])).items():
            ds[f"{name}_{key}"] = da.rename({d: f"{name}_{d}" for d in da.dims})  # one cavity axis per seal
    ds.attrs.update({"machine": spec.machine, "location": spec.location, "mean_density": spec.mean_density or np.nan})
    verdict1 = "Level II required" if l1.level2_required else "Level II not required"
    verdict2 = "pass" if l2.passed else "fail"
    extra = {
        "speed": {"value": spec.speed_rpm, "unit": "rpm"},
        "Q_A": {"value": l1.q_a, "unit": "N/m"},
        "Q_0": {"value": l1.q0, "unit": "N/m"},
        "Q0_over_QA": {"value": l1.ratio, "unit": "1"},
        "log_dec_at_QA": {"value": l1.log_dec_a, "unit": "1"},
        "log_dec_at_Q0_zero": {"value": l1.log_dec_0, "unit": "1"},
        "first_forward_frequency_at_QA": {"value": l1.frequency_a / (2 * np.pi), "unit": "Hz"},
        "rigid_support_critical_speed": {"value": l1.rigid_critical / RPM, "unit": "rpm"},
        "CSR": {"value": l1.csr, "unit": "1"},
        "CSR_region": {"value": l1.region or "not evaluated", "unit": ""},
        "level1_verdict": {"value": verdict1, "unit": "", "reasons": list(l1.reasons)},
        "level2_log_dec": {"value": l2.full, "unit": "1", "limit": l2.limit},
        "level2_verdict": {"value": verdict2, "unit": ""},
    }
    for case, d in zip(l2.cases, l2.log_dec, strict=True):
        extra[f"level2_log_dec[{case}]"] = {"value": float(d), "unit": "1"}
    msg = (
        f"Level I: Q_A = {l1.q_a:.4g} N/m, Q_0 = {l1.q0:.4g} N/m, Q_0/Q_A = {l1.ratio:.3g}, "
        f"log dec at Q_A {l1.log_dec_a:.3g}, CSR {l1.csr:.3g}: {verdict1}; "
        f"Level II: log dec {l2.full:.3g} (limit {l2.limit:g}): {verdict2}"
    )
    ds.attrs["reasons"] = "; ".join(l1.reasons)
    ds.attrs.update(summary_attrs(config, t0, extra, msg))
    return StabilityResult(ds)


@register_result
class StabilityResult(_FEResult):
    """API 617 Level I and Level II results (see :func:`run_stability`)."""

    kind = "rotor_fe_stability"

    def verdict_table(self) -> str:
        """The verdicts as a Markdown table."""
        ds, s = self.dataset, self.summary()
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
        rows.append(
            ("Level II verdict", f"{s['level2_verdict']['value']} (log dec >= {s['level2_log_dec']['limit']:g})")
        )
        return "| item | value |\n|---|---|\n" + "\n".join(f"| {a} | {b} |" for a, b in rows) + "\n"

    def write_extra(self, out_dir: Path) -> list[Path]:
        return [write_text_atomic(Path(out_dir) / "verdict.md", self.verdict_table())]

    def plot(self) -> dict:
        from rotaflex.rotor.fe.figures_stability import csr_map_figure, level1_figure, level2_figure

        ds = self.dataset
        figs = _model_fig(self)
        figs["level1"] = level1_figure(ds)
        if ds.attrs.get("machine") == "centrifugal_compressor" and np.isfinite(ds.attrs.get("mean_density", np.nan)):
            figs["csr_map"] = csr_map_figure(float(ds["csr"]), float(ds.attrs["mean_density"]))
        figs["level2"] = level2_figure(ds)
        return figs
