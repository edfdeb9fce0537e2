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
