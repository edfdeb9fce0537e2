"""Helical gear meshes in geared rotors (docs/geared-rotor.md, "Helical meshes").

References: closed forms written here by hand (rigid gear bodies on axial springs, torsion),
the force laws of a helical mesh (F_n = T / (r_b cos(beta_b)), F_a = T tan(beta_w) / r_w,
e.g. ISO 21771 / Niemann-Winter), and the spur model in the limit beta -> 0.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg as sla

from rotaflex.core.errors import InputError
from rotaflex.gear import pair_from_mapping
from rotaflex.system.modal import modal
from rotaflex.system.model import Gearbox

RIGID = {"E": 2.1e17, "G": 8.1e16, "rho": 7800.0}  # shafts 1e6 x steel, steel's density
D, L = 0.05, 0.1  # shaft diameter, length [m]
DISK = {"pinion": (3.0, 2.0e-3, 4.0e-3), "wheel": (9.0, 1.0e-2, 2.0e-2)}  # mass, Id, Ip
KA = (1.0e8, 2.0e8)  # thrust stiffness of the input / output rotor [N/m]
K_MESH = 2.0e8


def _gear(teeth: int, beta: float, hand: str | None) -> dict:
    g = {"teeth": teeth, "module": 3.0e-3, "face_width": 0.02}
    if beta > 0:
        g |= {"helix_angle_deg": beta, "hand": hand}
    return g


def _pair(beta: float):
    return pair_from_mapping({"pinion": _gear(20, beta, "right"), "wheel": _gear(40, beta, "left")})


def _config(beta: float, kzz=KA, rotation: str = "ccw") -> dict:
    """Two rigid one-element rotors, laterally rigid bearings at both ends, a thrust bearing at
    node 0, the gears as disks at node 1, a constant-speed drive at the input's node 0."""
    a = _pair(beta).working_center_distance

    def rotor(name, x, gear, ka):
        m, Id, Ip = DISK[gear]
        brg = [{"node": n, "kxx": 1e14, "kyy": 1e14} for n in (0, 1)]
        if ka:
            brg[0]["kzz"] = ka
        return {
            "name": name,
            "center": [x, 0.0],
            "shaft": [{"outer_diameter": D, "length": L, "elements": 1, **RIGID}],
            "disk": [{"node": 1, "mass": m, "Id": Id, "Ip": Ip}],
            "bearing": brg,
        }

    return {
        "rotor": [rotor("in", 0.0, "pinion", kzz[0]), rotor("out", a, "wheel", kzz[1])],
        "gear_mesh": [
            {
                "pinion_rotor": "in",
                "pinion_node": 1,
                "wheel_rotor": "out",
                "wheel_node": 1,
                "source": "harmonic",
                "k_mean": K_MESH,
                "torque": 100.0,
                "damping_ratio": 0.0,
                "blanks": False,
                "pinion": _gear(20, beta, "right"),
                "wheel": _gear(40, beta, "left"),
            }
        ],
        "drive": {"rotor": "in", "node": 0, "kind": "constant_speed", "rotation": rotation},
    }


def _rigid_masses():
    """Rigid-body axial mass [kg] and polar inertia [kg m^2] of a rotor: shaft + disk."""
    area, jp = math.pi / 4 * D**2, math.pi / 32 * D**4
    rho = RIGID["rho"]
    return {g: (m + rho * area * L, Ip + rho * jp * L) for g, (m, _, Ip) in DISK.items()}


def _hand_frequencies(beta: float) -> np.ndarray:
    """The 3-DOF eigenproblem (wheel twist theta_2, axial w_1, w_2; the pinion held by the
    constant-speed drive, gear bodies rigid) written out: the mesh spring along the flank normal
    has the transverse deflection r_b2 theta_2 + tan(beta_b) (w_1 - w_2)."""
    pair = _pair(beta)
    rb2 = pair.gears[1].base_radius
    t = math.tan(pair.base_helix_angle)
    (m1, _), (m2, J2) = _rigid_masses()["pinion"], _rigid_masses()["wheel"]
    a = np.array([rb2, t, -t])
    K = K_MESH * np.outer(a, a) + np.diag([0.0, KA[0], KA[1]])
    M = np.diag([J2, m1, m2])
    return np.sqrt(sla.eigh(K, M, eigvals_only=True))


@pytest.mark.parametrize("beta", [10.0, 25.0])
def test_rigid_two_gear_frequencies_match_the_hand_derived_3dof_problem(beta):
    box = Gearbox.from_mapping(_config(beta))
    wn = np.sort(modal(box, 0.0, 3).wn[0])
    ref = _hand_frequencies(beta)
    # shafts 1e6 x steel, bearings 1e14 N/m: the rigid-body model
    np.testing.assert_allclose(wn, ref, rtol=2e-5)
    # the check discriminates: the uncoupled (spur) frequencies are > 1 % away
    (m1, _), (m2, J2) = _rigid_masses()["pinion"], _rigid_masses()["wheel"]
    rb2 = _pair(beta).gears[1].base_radius
    spur = np.sort(np.sqrt([K_MESH * rb2**2 / J2, KA[0] / m1, KA[1] / m2]))
    assert np.max(np.abs(ref / spur - 1)) > 1e-2


def test_helical_mesh_without_thrust_bearing_is_refused_naming_kzz():
    with pytest.raises(InputError, match=r"rotor\[1\]\.bearing\[\]\.kzz"):
        Gearbox.from_mapping(_config(15.0, kzz=(1e8, 0.0)))
