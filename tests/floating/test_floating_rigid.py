"""A body with the elastic part switched off reproduces the rotor domain's free rigid body."""

import numpy as np
import pytest

from rotaflex.core.errors import InputError
from rotaflex.floating.body import point_body, rigid_body
from rotaflex.floating.model import Initial, Load, Settings
from rotaflex.floating.solve import simulate
from rotaflex.rotation.quaternion import quaternion_from_euler
from rotaflex.rotor.model import Formulation, FreeBody, Solver
from rotaflex.rotor.simulate import simulate as rotor_simulate

J = (1.0, 2.5, 3.2)  # asymmetric: tumbling, the hardest case for attitude agreement
ANGLES = (0.1, 0.4, 0.2)
RATE = (0.3, 1.1, 2.0)


@pytest.mark.parametrize("frame", ["body", "inertial"])
@pytest.mark.parametrize("method", ["full", "perturbation"])
def test_rigid_body_matches_rotor_free_body(frame, method):
    torque = (0.2, -0.1, 0.3)
    ref = rotor_simulate(
        FreeBody(
            inertia=J,
            initial_angles=ANGLES,
            initial_body_rate=RATE,
            torque=torque,
            torque_frame=frame,
            formulation=Formulation(parameterisation="quaternion", sequence="123"),
            solver=Solver(t_end=5.0, n_output=501, rtol=1e-11, atol=1e-13),
        )
    ).dataset
    e0 = quaternion_from_euler("123", ANGLES)
    s = simulate(
        rigid_body(3.0, J),
        [Load(kind="torque", vector=torque, frame=frame)],
        Initial(quaternion=tuple(e0), angular_velocity=RATE),
        Settings(t_end=5.0, dt_out=0.01, rtol=1e-11, atol=1e-13),
        method,
    )
    assert np.allclose(s.time, ref["time"].values)
    dq = np.abs(s.quaternion - ref["quaternion"].values).max()
    dw = np.abs(s.angular_velocity - ref["omega_body"].values).max()
    print(f"rigid {method} {frame}: |de| {dq:.2e}, |dw| {dw:.2e} rad/s")
    assert dq < 1e-8 and dw < 1e-8, (dq, dw)
    # the attitude really changes (tumbling, several rad)
    assert np.abs(s.quaternion - s.quaternion[0]).max() > 0.5


def test_rigid_flag_only_through_rigid_body():
    # normal bodies still need elastic modes; rigid_body validates its inertia
    with pytest.raises(InputError, match="at least one elastic mode"):
        point_body([1.0], [[0.0, 0.0, 0.0]], np.zeros((0, 1, 3)), frequencies=[])
    with pytest.raises(InputError, match="principal moments > 0"):
        rigid_body(1.0, (1.0, -1.0, 1.0))
    with pytest.raises(InputError, match="mass > 0"):
        rigid_body(0.0, J)


def test_rigid_inertia_must_satisfy_the_triangle_inequality():
    with pytest.raises(InputError, match="triangle inequality") as exc:
        rigid_body(1.0, [10.0, 1.0, 1.0])
    assert exc.value.field == "body.inertia"
    rigid_body(1.0, [2.0, 1.0, 1.0])  # the limiting case (a flat plate) is physical
