"""A machine of one rotor with liquid seals has the rotor's own modes: the seals' added mass
enters the system assembly as it enters every rotor verb (rotor/fe Rotor.MKC)."""

import numpy as np

from rotaflex.core.examples import example_path
from rotaflex.rotor.fe.modal import modal
from rotaflex.rotor.fe.model import Rotor
from rotaflex.system.model import DriveSpec
from rotaflex.system.study import Machine, MachineRotor, modes


def test_one_rotor_machine_with_neck_ring_seals_has_the_rotor_verbs_modes():
    rotor = Rotor.from_toml(example_path("rotor/pump_neck_ring_seals.toml"))
    seal_mass = sum(float(el.mass(376.99)[0, 0, 0]) for _, _, el in rotor.bearings)
    assert seal_mass > 1.0  # the seals do carry added mass (kg), so the check below can fail
    machine = Machine({"pump": MachineRotor(rotor)}, drive=DriveSpec(rotor="pump", node=0, kind="torque"))
    ds = modes(machine, speed_rpm=3600.0, n_modes=6).dataset
    ref = modal(rotor, 3600.0 * np.pi / 30.0, 6)
    np.testing.assert_allclose(ds["damped_frequency"].values[:6], ref.wd[0, :6], rtol=1e-9)
    np.testing.assert_allclose(ds["damping_ratio"].values[:6], ref.damping_ratio[0, :6], rtol=1e-7)
