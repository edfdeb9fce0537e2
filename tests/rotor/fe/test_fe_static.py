"""Static analysis vs the statics of a beam on two supports (closed forms)."""

import json
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from rotaflex.core.errors import InputError
from rotaflex.rotor.fe.model import Bearing, Disk, Rotor, Shaft
from rotaflex.rotor.fe.static import STANDARD_GRAVITY, static_analysis

E, G, RHO = 211e9, 81.2e9, 7810.0
NU = E / (2 * G) - 1
KAPPA = 6 * (1 + NU) / (7 + 6 * NU)  # Cowper, solid circle
EXAMPLE = Path(__file__).resolve().parents[3] / "examples" / "rotor" / "fe_api684.toml"


def _beam(L=1.0, d=0.05, n=8, k=1e14, **kw):
    return Rotor(
        shaft=(Shaft(outer_diameter=d, length=L, elements=n),),
        bearing=(Bearing(node=0, kxx=k, kyy=k), Bearing(node=n, kxx=k, kyy=k)),
        **kw,
    )


def test_simply_supported_self_weight_timoshenko_exact():
    L, d, k = 1.0, 0.05, 1e14
    r = _beam(L, d, 8, k)
    s = static_analysis(r)
    A, I = np.pi * d**2 / 4, np.pi * d**4 / 64
    w = RHO * A * STANDARD_GRAVITY  # N/m, acting in -y
    assert np.allclose(s.reactions[:, 1], w * L / 2, rtol=1e-12) and np.allclose(s.reactions[:, 0], 0)
    assert np.isclose(s.moment[:, 1].max(), w * L**2 / 8, rtol=1e-12)
    # midspan sag: bending + shear (exact for the interdependent element at its nodes), minus support give
    exact = 5 * w * L**4 / (384 * E * I) + w * L**2 / (8 * KAPPA * G * A)
    sag = -(s.q[4 * 4 + 1] - s.q[1])
    assert np.isclose(sag, exact, rtol=1e-9)
    # shear: +wL/2 right of the left support, linear, -wL/2 at the right end (left limit)
    assert np.isclose(s.shear[0, 1], w * L / 2, rtol=1e-12) and np.isclose(s.shear[-1, 1], -w * L / 2, rtol=1e-12)
    assert abs(s.moment[-1, 1]) < 1e-9 * w * L**2


def test_euler_bernoulli_limit_for_slender_shafts():
    d = 0.02
    I = np.pi * d**4 / 64
    errs = []
    for L in (0.2, 0.6, 2.0):  # L/d = 10, 30, 100
        s = static_analysis(_beam(L, d, 10))
        w = RHO * np.pi * d**2 / 4 * STANDARD_GRAVITY
        errs.append(-(s.q[4 * 5 + 1] - s.q[1]) / (5 * w * L**4 / (384 * E * I)) - 1)
    # shear adds 48 E I / (5 kappa G A L^2) = 0.6 (d/L)^2 E / (kappa G) ... relative: decays as (d/L)^2
    assert errs[0] > errs[1] > errs[2] > 0 and errs[2] < 1e-3
    assert np.isclose(errs[0] / errs[1], 9.0, rtol=1e-6)


def test_point_load_reactions_moment_and_deflection():
    L, d, n, P = 1.2, 0.06, 12, 1000.0
    r = Rotor(
        shaft=(Shaft(outer_diameter=d, length=L, elements=n),),
        bearing=(Bearing(position=0.1, kxx=1e14, kyy=1e14), Bearing(position=1.1, kxx=1e14, kyy=1e14)),
    )
    s = static_analysis(r, gravity=0.0, loads=[(4, 0.0, -P)])  # load at z = 0.4, span 0.1..1.1
    a, b, span = 0.3, 0.7, 1.0
    assert np.allclose(s.reactions[:, 1], [P * b / span, P * a / span], rtol=1e-10)
    assert np.isclose(s.moment[:, 1].max(), P * a * b / span, rtol=1e-10)
    # overhangs carry nothing
    assert np.allclose(s.moment[s.z < 0.1 - 1e-9], 0, atol=1e-9) and np.allclose(s.moment[s.z > 1.1 + 1e-9], 0)
    # deflection under the load: P a^2 b^2 / (3 E I span) + P a b / (kappa G A span)
    A, I = np.pi * d**2 / 4, np.pi * d**4 / 64
    exact = P * a**2 * b**2 / (3 * E * I * span) + P * a * b / (KAPPA * G * A * span)
    assert np.isclose(-s.q[4 * 4 + 1], exact, rtol=1e-6)


def test_equilibrium_with_disks_direction_and_cross_coupling():
    r = Rotor(
        shaft=(Shaft(outer_diameter=0.05, length=1.5, elements=6),),
        disk=(Disk(node=2, mass=30.0, Id=0.2, Ip=0.3), Disk(node=4, mass=20.0, Id=0.1, Ip=0.2)),
        bearing=(
            Bearing(node=0, kxx=2e7, kyy=5e7, kxy=1e7, kyx=-1e7),
            Bearing(node=6, kxx=2e7, kyy=5e7, kxy=1e7, kyx=-1e7),
        ),
    )
    s = static_analysis(r, direction=(-1.0, 0.0), loads=[(3, 100.0, 50.0)])
    W = r.mass * STANDARD_GRAVITY
    assert np.allclose(s.load_total, [-W + 100.0, 50.0], rtol=1e-12)
    assert np.allclose(s.reactions.sum(0), -s.load_total, rtol=1e-9)
    # moment equilibrium about z = 0: sum z_i F_i of reactions balances the loads
    z = r.nodes
    mom_loads = STANDARD_GRAVITY * -1 * (r.M @ np.tile([1.0, 0, 0, 0], r.n_nodes)).reshape(-1, 4)[:, 0] @ z
    mom_loads += 100.0 * z[3]
    assert np.isclose(s.reactions[0, 0] * z[0] + s.reactions[1, 0] * z[6], -mom_loads, rtol=1e-9)
    assert np.allclose(s.shear[-1] + s.reactions[1], 0, atol=1e-9 * W) and np.allclose(s.moment[-1], 0, atol=1e-9 * W)


def test_bad_inputs_are_refused():
    free = Rotor(shaft=(Shaft(outer_diameter=0.05, length=1.0, elements=2),), free=True)
    with pytest.raises(InputError, match="free"):
        static_analysis(free)
    with pytest.raises(InputError, match="gravity_direction"):
        static_analysis(_beam(), direction=(0.0, 0.0))


def test_cli_static_writes_reactions_and_figure(tmp_path: Path):
    from rotaflex.cli import app

    out = ["--out", str(tmp_path), "-q", "--dpi", "40"]  # low resolution: drawing dominates the run time
    res = CliRunner().invoke(app, ["rotor", "static", str(EXAMPLE), *out])
    assert res.exit_code == 0, res.output
    summ = json.loads((tmp_path / "summary.json").read_text())
    total = summ["load_drive_end"]["value"] + summ["load_non_drive_end"]["value"]
    assert np.isclose(total, summ["total_mass"]["value"] * STANDARD_GRAVITY, rtol=1e-9)
    assert (tmp_path / "static.png").exists()


def test_point_load_from_toml_by_position():
    """Overhung load: 200 N down at z = 1.2 m, bearings at 0.1 and 1.1 m -> -20 N and 220 N (lever rule)."""
    from rotaflex.core.config import load_toml
    from rotaflex.rotor.fe.verbs import run_static

    cfg = load_toml(EXAMPLE)
    cfg["static"] = {"gravity": 0.0, "load": [{"position": 1.2, "fy": -200.0}]}
    s = run_static(cfg).summary()
    assert s["reaction_drive_end_y"]["value"] == pytest.approx(-20.0, rel=1e-9)
    assert s["reaction_non_drive_end_y"]["value"] == pytest.approx(220.0, rel=1e-9)
    assert s["max_bending_moment"]["value"] == pytest.approx(200.0 * 0.1, rel=1e-9)  # at the right bearing


def test_deflection_curve_within_elements_is_the_exact_sag():
    """Between the nodes the element's shape functions give the exact Euler-Bernoulli + shear sag of a
    point-loaded span (the interdependent element is exact for nodal loads)."""
    from rotaflex.rotor.fe.static import deflection_curve

    L, d, P = 1.0, 0.05, 1000.0
    r = _beam(L, d, 2)
    s = static_analysis(r, gravity=0.0, loads=[(1, 0.0, -P)])
    curve = deflection_curve(r, s.q)[:, 1] - s.q[1]
    z = s.z
    A, I = np.pi * d**2 / 4, np.pi * d**4 / 64
    zl = np.minimum(z, L - z)  # symmetric: left half formula
    exact = -(P * zl * (3 * L**2 - 4 * zl**2) / (48 * E * I) + P * zl / (2 * KAPPA * G * A))
    assert np.allclose(curve, exact, rtol=1e-6, atol=1e-6 * np.abs(exact).max())
