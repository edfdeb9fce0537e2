"""examples/system/motor_coupling_pump.toml built in Python: a 75 kW, 4-pole, 50 Hz induction
motor (1480 rpm) driving an overhung centrifugal pump through an elastomer coupling. Its
torsional modes with the API 684 interference diagram over 1440-1500 rpm, the coupled
(lateral + torsional) modes at 1480 rpm, the Campbell diagram over 0-3000 rpm, the unbalance
response of the impeller over 300-4500 rpm, the impeller's FRF at 1480 rpm, the API 617
Level II stability at 1480 rpm, the static bearing loads under gravity, the undamped critical
speed map over the pump's bearing stiffness and a 0.5 s run-up through the pump's critical;
the same numbers as the TOML file through the command line (tests/system/test_library_machine.py).

Run (from the repository root; figures and summaries go to DIR, default out/coupled_train):

    PYTHONPATH=src python examples/python/coupled_train.py [DIR]

The same analyses from the command line: ``rotaflex system
torsional|modal|campbell|unbalance|frf|stability|static|ucs|transient
examples/system/motor_coupling_pump.toml --out DIR`` (with the settings below in its [unbalance],
[frf], [stability], [ucs] and [transient] tables). See docs/library.md.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

from rotaflex.core.plotting import save_figure
from rotaflex.core.units import rad_s_to_rpm
from rotaflex.rotor.fe import Bearing, Disk, Rotor, Shaft
from rotaflex.system.study import (
    CouplingSpec,
    DriveSpec,
    ExcitationSpec,
    LoadSpec,
    Machine,
    MachineDOF,
    MachineRotor,
    MachineUnbalanceMass,
    campbell_diagram,
    critical_speed_map,
    frf,
    modes,
    stability,
    static_state,
    torsional_analysis,
    transient_response,
    unbalance_response_study,
)

out = Path(sys.argv[1] if len(sys.argv) > 1 else "out/coupled_train")
out.mkdir(parents=True, exist_ok=True)

# SI units: m, kg, kg m^2, N/m, N s/m, N m/rad; speeds in rpm where the name says so
motor = Rotor(
    shaft=(Shaft(outer_diameter=0.075, length=0.9, elements=6),),
    disk=(Disk(node=3, mass=120.0, Id=4.0, Ip=1.2),),  # rotor core
    bearing=(  # rolling-element bearings
        Bearing(node=1, kxx=1.5e8, kyy=1.5e8, cxx=1.0e3, cyy=1.0e3),
        Bearing(node=5, kxx=1.5e8, kyy=1.5e8, cxx=1.0e3, cyy=1.0e3),
    ),
)
pump = Rotor(
    shaft=(Shaft(outer_diameter=0.06, length=0.8, elements=5),),
    disk=(Disk(node=5, mass=25.0, Id=0.2, Ip=0.35),),  # impeller, overhung
    bearing=(
        Bearing(node=1, kxx=1.0e8, kyy=1.0e8, cxx=8.0e2, cyy=8.0e2),
        Bearing(node=3, kxx=1.0e8, kyy=1.0e8, cxx=8.0e2, cyy=8.0e2),
    ),
)
machine = Machine(
    rotors={"motor": MachineRotor(motor, speed_rpm=1480.0), "pump": pump},  # coaxial, at (0, 0)
    couplings=(  # elastomer (jaw) coupling: soft in torsion, its mass split to the hubs
        CouplingSpec(
            name="elastomer",
            rotor_a="motor",
            node_a=6,
            rotor_b="pump",
            node_b=0,
            torsional_stiffness=1.2e4,
            torsional_damping=12.0,
            lateral_stiffness=5.0e6,
            angular_stiffness=2.0e3,
            mass=8.0,
            Ip=0.05,
            Id=0.04,
        ),
    ),
    drive=DriveSpec(
        rotor="motor",
        node=3,
        kind="torque",
        # NEMA design B shape: locked rotor 2.2x, pull-up 1.9x, breakdown 2.8x of the rated 484 N m
        curve_speed_rpm=(0.0, 300.0, 600.0, 900.0, 1200.0, 1350.0, 1440.0, 1480.0, 1500.0),
        curve_torque=(1065.0, 980.0, 920.0, 1000.0, 1200.0, 1355.0, 1000.0, 484.0, 0.0),
        line_frequency_hz=50.0,
        poles=4,
    ),
    load=LoadSpec(rotor="pump", node=5, torque=20.0, quadratic=0.0196),  # breakaway + affinity law
)

torsion = torsional_analysis(
    machine,
    operating_speed_rpm=(1440.0, 1500.0),
    n_modes=4,
    excitation=(
        ExcitationSpec(kind="shaft", rotor="motor", order=1),
        ExcitationSpec(kind="shaft", rotor="motor", order=2),
        ExcitationSpec(kind="shaft", rotor="pump", order=6, name="vane passing"),
        ExcitationSpec(kind="fixed", frequency_hz=50.0, order=2, name="2x line"),
    ),
)
save_figure(torsion.plot_interference(), out / "interference.png")
coupled = modes(machine, speed_rpm=1480.0, n_modes=12)
camp = campbell_diagram(machine, speed_rpm=(0.0, 3000.0), n_speeds=31, n_modes=10)
save_figure(camp.plot_campbell(), out / "campbell.png")
# impeller unbalance: 1e-4 kg m (G2.5-class for a 25 kg impeller at 1480 rpm is 4e-4 kg m)
unbalance = unbalance_response_study(
    machine,
    [MachineUnbalanceMass(rotor="pump", node=5, magnitude=1e-4)],
    speed_rpm=(300.0, 4500.0),
    n_speeds=85,
    operating_range_rpm=(1440.0, 1500.0),
)
impeller = MachineDOF(rotor="pump", node=5, direction="x")
receptance = frf(machine, inputs=[impeller], speed_rpm=1480.0, frequency_hz=(5.0, 150.0), n_frequencies=300)
# pump: no Q_A, Level II of the bearings alone; rolling-element bearings of 800-1000 N s/m damp
# the lateral modes little, so API 617's 0.1 (written for fluid-film machines) is not met
stab = stability(machine, rotor="pump", kind="pump", speed_rpm=1480.0)
# gravity along -y, bearings at the motor's nominal 1480 rpm; the pump's inboard (coupling-side)
# bearing at node 1 is pulled down by the overhung impeller
static = static_state(machine)
# the pump's bearings swept 1e6-1e10 N/m (5 points: 1e8, their value, is the middle one)
ucs = critical_speed_map(machine, rotors=("pump",), stiffness=(1e6, 1e10), n_points=5, n_modes=4)
# a 2000 rpm/s run-up of the motor through the pump's 4062 rpm critical with the impeller's 1e-4 kg m
runup = transient_response(
    machine,
    speed_rpm=(3500.0, 4500.0),
    duration=0.5,
    n_output=1001,
    masses=[MachineUnbalanceMass(rotor="pump", node=5, magnitude=1e-4)],
)

REPORT = {
    "torsional_hz": [round(s["value"], 3) for k, s in torsion.summary().items() if k.endswith("_frequency_hz")],
    "api684": torsion.summary()["api684_verdict"]["value"],
    "lowest_coupled_hz": round(coupled.summary()["mode_0_frequency_hz"]["value"], 3),
    "campbell": camp.dataset.attrs["message"],
    "unbalance_peak_rpm": round(unbalance.summary()["peak_0_speed_rpm"]["value"], 1),
    "unbalance_peak_um": round(unbalance.summary()["peak_0_amplitude"]["value"] * 1e6, 3),
    "frf_peak_hz": round(receptance.summary()["pump:5 x / pump:5 Fx_peak_0_frequency_hz"]["value"], 2),
    "level2_log_dec": round(stab.summary()["level2_log_dec"]["value"], 4),
    "level2_verdict": stab.summary()["level2_verdict"]["value"],
    "pump_inboard_bearing_load_n": round(static.summary()["pump_load_bearing[0]"]["value"], 1),
    "first_critical_rpm_at_1e8": round(float(rad_s_to_rpm(ucs.dataset["critical_speed"][2, 0])), 1),
    "runup_peak_um": round(runup.summary()["max_radial_displacement"]["value"] * 1e6, 2),
    "runup_peak_rpm": round(runup.summary()["speed_at_max_rpm"]["value"], 1),
}
(out / "summary.json").write_text(
    json.dumps(
        {
            "torsional": torsion.summary(),
            "modal": coupled.summary(),
            "campbell": camp.summary(),
            "unbalance": unbalance.summary(),
            "frf": receptance.summary(),
            "stability": stab.summary(),
            "static": static.summary(),
            "ucs": ucs.summary(),
            "transient": runup.summary(),
        },
        indent=1,
        default=str,
    )
)
if __name__ == "__main__":
    print(json.dumps(REPORT, indent=1))
