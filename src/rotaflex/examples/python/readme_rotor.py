"""The README's rotor (examples/rotor/fe_friswell_5_9_1.toml) built in Python: a 1.5 m, 50 mm
steel shaft in 6 Timoshenko elements, two disks, two damped bearings; its Campbell diagram with
the 1X and 2X lines and the log-decrement panel, and the unbalance response (Bode) of 100 g mm
at the second disk, with API 684 verdicts over 2,500-3,500 rpm; then one number of each other
analysis: static bearing load, first undamped critical speed on stiff bearings, FRF peak, API 617
Level II log decrement and the largest transient displacement at 3,000 rpm.

Run (from the repository root; figures and summaries go to DIR, default out/readme_rotor):

    PYTHONPATH=src python examples/python/readme_rotor.py [DIR]

The same analyses from the command line: ``rotaflex rotor
campbell|unbalance|static|ucs|frf|stability|transient examples/rotor/fe_friswell_5_9_1.toml
--out DIR`` (with the tables below in the file). See docs/library.md.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

from rotaflex.core.plotting import save_figure
from rotaflex.core.units import rad_s_to_rpm
from rotaflex.rotor.fe import Bearing, Disk, Rotor, Shaft
from rotaflex.rotor.fe.study import (
    campbell_diagram,
    critical_speed_map,
    frf,
    stability,
    static_state,
    transient_response,
    unbalance_response_study,
)

out = Path(sys.argv[1] if len(sys.argv) > 1 else "out/readme_rotor")
out.mkdir(parents=True, exist_ok=True)

# SI units: m, kg, N/m, N s/m; the disks from their geometry and the shaft's steel
rotor = Rotor(
    shaft=(Shaft(outer_diameter=0.05, length=1.5, elements=6, material="steel"),),
    disk=(
        Disk(position=0.5, width=0.07, outer_diameter=0.28, inner_diameter=0.05),
        Disk(position=1.0, width=0.07, outer_diameter=0.35, inner_diameter=0.05),
    ),
    bearing=(
        Bearing(node=0, name="left", kxx=1e6, kyy=1e6, cxx=3e3, cyy=3e3),
        Bearing(position=1.5, name="right", kxx=1e6, kyy=1e6, cxx=3e3, cyy=3e3),
    ),
)

camp = campbell_diagram(rotor, speed_rpm=(0, 4000), n_speeds=50, n_modes=6, harmonics=(1, 2))
save_figure(camp.plot_campbell(), out / "campbell.png")

bode = unbalance_response_study(
    rotor,
    [{"position": 1.0, "magnitude": 1e-4, "phase_deg": 0.0}],  # kg m: 100 g mm
    speed_rpm=(0, 4000),
    n_speeds=500,
    probes=(2, 4),
    operating_range_rpm=(2500, 3500),
)
save_figure(bode.plot_bode(), out / "bode.png")
save_figure(bode.plot_orbit(), out / "orbit.png")

# one number of each other analysis (each returns the CLI's result object, as above)
static = static_state(rotor)  # gravity along -y
ucs = critical_speed_map(rotor, stiffness=(1e5, 1e9), n_points=20, n_modes=2)
h = frf(rotor, inputs=[{"node": 4}], speed_rpm=3000, frequency_hz=(1, 60), n_frequencies=600)
stab = stability(rotor, kind="pump", speed_rpm=3500)  # Level II only: bearings, no aerodynamic Q_A
run = transient_response(
    rotor,
    duration=0.5,
    speed_rpm=(3000, 3000),
    masses=[{"position": 1.0, "magnitude": 1e-4}],
    n_output=501,
    method="direct",
)

REPORT = {
    "status": camp.status,
    "critical_rpm": [round(c["speed_rpm"], 1) for c in camp.critical if c["harmonic"] == 1],
    "unbalance": bode.dataset.attrs["message"],
    "static_reaction_y_N": [round(float(r), 2) for r in static.dataset["reaction"].sel(axis="y")],
    "mass_kg": rotor.mass,
    "ucs_first_critical_rpm_at_1e9_N_per_m": round(rad_s_to_rpm(float(ucs.dataset["critical_speed"][-1, 0])), 1),
    "frf_peak_hz": round(h.summary()["x4/Fx4_peak_0_frequency_hz"]["value"], 2),
    "level2_log_dec": round(stab.summary()["level2_log_dec"]["value"], 3),
    "transient_max_displacement_m": run.summary()["max_radial_displacement"]["value"],
}
(out / "summary.json").write_text(json.dumps({"campbell": camp.summary(), "unbalance": bode.summary()}, indent=1))
if __name__ == "__main__":
    print(json.dumps(REPORT, indent=1))
