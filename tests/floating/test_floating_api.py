"""One-call API ``rotaflex.floating.run``: config path, library objects, closed-loop controller."""

import json
from pathlib import Path

import numpy as np
import pytest

from rotaflex.core.errors import InputError
from rotaflex.floating import Settings, run, uniform_beam

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "floating"
L, RA, EI = 4.0, 2.0, 40.0
KP, KD, TARGET = 4.0, 6.0, 1.0


def pd(t, state):
    return [("torque", (0.0, 0.0, -KP * (state.euler_123[2] - TARGET) - KD * state.angular_velocity[2]))]


def rigid_zoh(J, dt, n):
    """The same loop on a rigid body, exact per hold interval (theta'' = tau_k / J)."""
    th, om, out = 0.0, 0.0, [0.0]
    for _ in range(n):
        a = (-KP * (th - TARGET) - KD * om) / J
        th, om = th + om * dt + 0.5 * a * dt * dt, om + a * dt
        out.append(th)
    return np.array(out)


def test_slew_controller_closes_the_loop_on_attitude():
    b = uniform_beam(L, RA, EI, 4)
    dt = 0.05
    res = run(
        body=b,
        controller=pd,
        control_dt=dt,
        solver=Settings(method="full", t_end=15.0, dt_out=dt),
        outputs={"tip": (2.0, 0.0, 0.0)},
    )
    ds = res.dataset
    th = ds["euler_123"].sel(solution="full").values[:, 2]
    ref = rigid_zoh(RA * L**3 / 12, dt, len(th) - 1)
    # mean axes: the rigid angle differs from the rigid body only through J(q) = J + O(q^2)
    assert np.abs(th - ref).max() < 1e-3 * TARGET
    assert abs(th[-1] - TARGET) < 0.02
    assert np.abs(ds["point_deflection"].values).max() > 1e-4  # the beam did flex
    cfg = json.loads(ds.attrs["config"])
    assert cfg["controller"] == "pd" and cfg["control_dt"] == dt
    assert ds.attrs["wall_time"] > 0


def test_run_from_a_case_file_and_bad_calls(tmp_path):
    text = (EXAMPLES / "planar_slew.toml").read_text()
    text = text.replace("t_end = 10.0", "t_end = 0.2").replace('method = "both"', 'method = "full"')
    (tmp_path / "c.toml").write_text(text)
    r0 = run(tmp_path / "c.toml")
    assert json.loads(r0.dataset.attrs["config"])["solver"]["t_end"] == 0.2
    cfg = {
        "domain": "floating",
        "body": {"type": "beam", "beam": {"length": L, "rho_a": RA, "ei": EI, "n_modes": 2}},
        "solver": {"method": "full", "t_end": 0.2, "dt_out": 0.1},
    }
    r = run(cfg)
    assert "body" in json.loads(r.dataset.attrs["config"]) and r.dataset.attrs["wall_time"] > 0
    b = uniform_beam(L, RA, EI, 2)
    with pytest.raises(InputError, match="control_dt"):
        run(body=b, controller=pd, control_dt=0.015, solver=Settings(method="full", t_end=1.0, dt_out=0.01))
    with pytest.raises(InputError, match="solver.method"):
        run(body=b, controller=pd, solver=Settings(method="both", t_end=1.0, dt_out=0.1))


def test_controller_sees_the_initial_attitude_and_modal_state_at_t0():
    # a body turned 0.8 rad about z and bent in its first mode at t = 0: the controller's first
    # state is that state (before: Euler angles and modal coordinates were zeros at t = 0 and
    # jumped to the true values at the first sampling instant)
    from rotaflex.floating import Initial

    b = uniform_beam(L, RA, EI, 2)
    a = 0.8
    ini = Initial(
        quaternion=(np.cos(a / 2), 0.0, 0.0, np.sin(a / 2)),
        angular_velocity=(0.0, 0.0, 0.3),
        modal_displacement=(0.01, 0.0),
        modal_velocity=(0.0, 0.02),
    )
    seen = []

    def record(t, state):
        seen.append((t, state))
        return []

    res = run(
        body=b, initial=ini, controller=record, control_dt=0.1, solver=Settings(method="full", t_end=0.2, dt_out=0.1)
    )
    t0, s0 = seen[0]
    assert t0 == 0.0
    np.testing.assert_allclose(s0.euler_123, [0.0, 0.0, a], atol=1e-12)
    np.testing.assert_allclose(s0.quaternion, ini.quaternion, atol=1e-15)
    np.testing.assert_allclose(s0.angular_velocity, [0.0, 0.0, 0.3])
    np.testing.assert_allclose(s0.q, [0.01, 0.0])
    np.testing.assert_allclose(s0.p, [0.0, 0.02])
    # the same values the result holds at t = 0, and continuous into the next sample
    ds = res.dataset.sel(solution="full")
    np.testing.assert_allclose(ds["euler_123"].values[0], s0.euler_123, atol=1e-12)
    t1, s1 = seen[1]
    assert t1 == 0.1 and abs(s1.euler_123[2] - (a + 0.03)) < 1e-3


def test_library_errors_name_the_load_index_and_the_body_record():
    from rotaflex.floating import Load, point_body

    b = uniform_beam(L, RA, EI, 2)
    ok = Load(kind="torque", vector=(0.0, 0.0, 1.0))
    bad = {"kind": "torque", "vector": (0.0, 0.0, 1.0), "profile": "pulse", "duration": -1.0}
    with pytest.raises(InputError, match=r"^loads\[1\]\.duration = -1.0 is invalid: expected a number >= 0"):
        run(body=b, loads=[ok, bad])
    with pytest.raises(InputError, match=r"^loads\[1\]\.duration = 0.0 .*> 0 s for a pulse"):
        run(body=b, loads=[ok, {**bad, "duration": 0.0}])
    # a Load object is checked too (its constructor checks only the cross-field rules)
    with pytest.raises(InputError, match=r"^loads\[0\]\.start = -1.0"):
        run(body=b, loads=[Load(kind="torque", vector=(0.0, 0.0, 1.0), start=-1.0)])
    with pytest.raises(InputError, match=r"^controller\(t=0\)\[0\]\.kind = 'push'"):
        run(body=b, controller=lambda t, s: [("push", (0.0, 0.0, 1.0))], solver=Settings(method="full", t_end=0.1))
    # point_body names the fields as a case file does
    with pytest.raises(InputError, match=r"^body\.points\.masses\[1\] = -2.0"):
        point_body([1.0, -2.0, 1.0], np.eye(3), np.zeros((1, 3, 3)), frequencies=[1.0])
    # the result records the body's parameters, not only its name
    res = run(body=b, loads=[ok], solver=Settings(method="full", t_end=0.1, dt_out=0.05))
    rec = json.loads(res.dataset.attrs["config"])["body"]
    assert rec["source"] == "uniform_beam" and rec["length"] == L and rec["ei"] == EI and rec["n_modes"] == 2
    assert rec["mass"] == pytest.approx(L * RA) and len(rec["frequencies"]) == 2
