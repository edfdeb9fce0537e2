"""Quaternion (Euler-parameter) disk on the FE shaft: convergence to the rigidly attached disk as
the hub stiffens, energy and spin conservation, norm drift, passage through 90 deg tilt where the
1-2-3 disk is singular."""

import numpy as np
import pytest

from rotaflex.core.errors import InputError, SingularityError
from rotaflex.rotor.fe import Bearing, Disk, Rotor, Shaft
from rotaflex.rotor.fe.elements.quaternion_disk import QuaternionDisk, rotation_matrix
from rotaflex.rotor.fe.transient import transient

NODE = 6
TILT = slice(4 * NODE + 2, 4 * NODE + 4)
KW = dict(method="modal", n_modes=6, n_output=21, rtol=1e-9, atol=1e-12)


def _overhung():
    return Rotor(
        shaft=(Shaft(outer_diameter=0.04, length=0.6, elements=6),),
        disk=(Disk(node=NODE, mass=5.0, Id=0.05, Ip=0.09),),
        bearing=(Bearing(node=0, kxx=1e7, kyy=1e7), Bearing(node=3, kxx=1e7, kyy=1e7)),
    )


def _tilted(r, tilt):
    q0 = np.zeros(r.n_dof)
    q0[4 * NODE + 3] = tilt
    return q0


def _hub(r):
    return float(r.KC(300.0)[0][0][4 * NODE + 3, 4 * NODE + 3])  # the node's tilt stiffness


def test_quaternion_disk_tends_to_the_attached_disk_as_one_over_hub_stiffness():
    # small tilt, where the attached 1-2-3 disk and the linear disk agree: the hub-joined
    # quaternion disk converges to them as 1/k (measured 2.4e-4, 3.1e-5, 3.0e-6 at 1, 10, 100 x)
    r = _overhung()
    q0 = _tilted(r, 1e-3)
    ref = transient(r, 0.005, q0=q0, speed_start=300.0, large_rotation=[NODE], **KW)
    errs = []
    for f in (1.0, 10.0, 100.0):
        qd = transient(
            r,
            0.005,
            q0=q0,
            speed_start=300.0,
            large_rotation=[NODE],
            large_rotation_model="quaternion",
            hub_stiffness=f * _hub(r),
            **KW,
        )
        errs.append(np.max(np.abs(qd.q[:, TILT] - ref.q[:, TILT])))
    amp = np.max(np.abs(ref.q[:, TILT]))
    assert errs[2] < 1e-2 * amp
    assert errs[1] / errs[2] > 5.0 and errs[0] / errs[1] > 5.0  # first order in 1/k


def test_energy_spin_and_norm_at_large_tilt():
    r = _overhung()
    tr = transient(
        r,
        0.005,
        q0=_tilted(r, 0.4),
        speed_start=300.0,
        large_rotation=[NODE],
        large_rotation_model="quaternion",
        hub_stiffness=10 * _hub(r),
        **KW,
    )
    K = r.KC(300.0)[0][0]
    M = r.M.copy()
    M[TILT, TILT] -= 0.05 * np.eye(2)  # the disk's Id is carried by the rigid body
    e = 0.5 * np.einsum("ti,ij,tj->t", tr.v, M, tr.v) + 0.5 * np.einsum("ti,ij,tj->t", tr.q, K, tr.q)
    el = tr.disks[0]
    e += np.array([el.energy(a, w, q[TILT]) for a, w, q in zip(tr.quaternion[:, 0], tr.omega[:, 0], tr.q, strict=True)])
    assert np.max(np.abs(e - e[0])) / e[0] < 1e-6
    assert tr.quaternion_norm_drift < 1e-8
    # the joint passes no torque about the disk axis: the spin rate stays constant
    assert np.allclose(tr.omega[:, 0, 2], tr.omega[0, 0, 2], rtol=0, atol=1e-8 * 300.0)


def test_free_disk_tumbles_through_90_deg_where_euler_123_is_singular():
    # a free disk (hub 0) tilted 80 deg and tipping over about its body axis 2: its axis passes
    # the horizontal; torque-free rigid body: energy and inertial angular momentum conserved
    r = _overhung()
    e0, _ = QuaternionDisk.initial_state((0.0, np.radians(80.0)), (0.0, 0.0), 0.0)
    w0 = np.array([0.0, 400.0, 1.0])
    tr = transient(
        r,
        0.01,
        q0=_tilted(r, np.radians(80.0)),
        speed_start=300.0,
        large_rotation=[NODE],
        large_rotation_model="quaternion",
        hub_stiffness=0.0,
        disk_state0={NODE: (e0, w0)},
        **KW,
    )
    el = tr.disks[0]
    nz = np.array([rotation_matrix(a)[2, 2] for a in tr.quaternion[:, 0]])
    assert nz.min() < -0.5  # through 90 deg tilt and well beyond
    h = np.array([el.angular_momentum(a, w) for a, w in zip(tr.quaternion[:, 0], tr.omega[:, 0], strict=True)])
    assert np.max(np.abs(h - h[0])) < 1e-7 * np.linalg.norm(h[0])
    ke = 0.5 * np.sum(el.J * tr.omega[:, 0] ** 2, axis=1)
    assert np.max(np.abs(ke - ke[0])) < 1e-7 * ke[0]
    assert tr.quaternion_norm_drift < 1e-7
    # the 1-2-3 disk pushed over 90 deg tilt stops with a SingularityError that names the way out
    v0 = np.zeros(r.n_dof)
    v0[4 * NODE + 3] = 2e4
    with pytest.raises(SingularityError, match="quaternion"):
        transient(r, 0.002, q0=_tilted(r, np.radians(85.0)), v0=v0, speed_start=300.0, large_rotation=[NODE], **KW)


def test_bad_large_rotation_model_is_an_input_error():
    r = _overhung()
    with pytest.raises(InputError, match="large_rotation_model"):
        transient(r, 0.01, speed_start=300.0, large_rotation=[NODE], large_rotation_model="rodrigues", **KW)


def test_example_toml_runs_with_the_quaternion_disk():
    import tomllib
    from pathlib import Path

    from rotaflex.rotor.fe.case import run_case

    path = Path(__file__).resolve().parents[3] / "examples" / "rotor" / "fe_overhung_quaternion_disk.toml"
    cfg = tomllib.loads(path.read_text())
    cfg["transient"].update(duration=0.004, n_output=41)
    res = run_case({"analysis": "transient", **cfg})
    ds = res.dataset
    assert ds.attrs["status"] == "success"
    assert ds["disk_quaternion"].dims == ("time", "disk", "component")
    norm = np.linalg.norm(ds["disk_quaternion"].values, axis=-1)
    assert np.max(np.abs(norm - 1.0)) < 1e-8
    assert res.summary()["quaternion_norm_drift"]["value"] < 1e-8
