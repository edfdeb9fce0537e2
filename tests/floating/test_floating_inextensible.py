"""Exact inextensible kinematics of a planar cantilever under prescribed spin (solver.kinematics)."""

import numpy as np
import pytest
from scipy.integrate import quad

from rotaflex.core.errors import InputError
from rotaflex.floating.beam import uniform_beam
from rotaflex.floating.model import Initial, Load, Prescribed, Settings
from rotaflex.floating.solve import point_motion, simulate

L, RHO_A, EI = 10.0, 1.2, 1.4e4  # Kane-Ryan-Banerjee spin-up beam


@pytest.fixture(scope="module")
def beam():
    return uniform_beam(L, RHO_A, EI, 4, support="cantilever")


def _slopes(b, s):
    pts = np.zeros((len(s), 3))
    pts[:, 0] = s
    return b.shape_fn(pts)[1][:, 2, :]  # dv/ds of each mode


def _jacobi_integral(b, q, p, omega):
    """Kinetic energy relative to the frame + exact bending energy - centrifugal potential [J],
    conserved at a constant spin rate; built here from the mode slopes with plain Gauss rules
    (not the solver's panel sums), curvature by central differences of the slopes."""
    g, gw = np.polynomial.legendre.leggauss(80)
    x = b.points[:, 0]
    out = np.empty(len(q))
    sq = 0.5 * (g + 1.0) * L
    wsq = 0.5 * gw * L
    d1 = _slopes(b, sq)
    d2 = (_slopes(b, sq + 1e-5) - _slopes(b, sq - 1e-5)) / 2e-5
    tabs = [(0.5 * (g + 1.0) * xk, 0.5 * gw * xk) for xk in x]
    slopes = [_slopes(b, s) for s, _ in tabs]
    for t in range(len(q)):
        qt, pt = q[t], p[t]
        u = np.array([w @ (np.sqrt(1.0 - (S @ qt) ** 2) - 1.0) for (_, w), S in zip(tabs, slopes, strict=True)])
        du = np.array(
            [-(w * (S @ qt) / np.sqrt(1.0 - (S @ qt) ** 2)) @ S for (_, w), S in zip(tabs, slopes, strict=True)]
        )
        vy = b.shapes[:, 1, :] @ pt
        vx = du @ pt
        kin = 0.5 * b.masses @ (vx**2 + vy**2)
        rx = x + u
        ry = b.shapes[:, 1, :] @ qt
        cen = 0.5 * omega**2 * b.masses @ (rx**2 + ry**2)
        v1, v2 = d1 @ qt, d2 @ qt
        bend = 0.5 * EI * wsq @ (v2**2 / (1.0 - v1**2))
        out[t] = kin + bend - cen
    return out


def test_jacobi_integral_is_conserved_at_constant_spin_with_large_deflection(beam):
    # spin up to 4 rad/s in 0.5 s from a first-mode deflection of 1.5 m at the tip (15 % of L),
    # then constant spin: relative energy + bending - centrifugal potential is a constant of
    # the exact equations; the linear model has no such invariant at this amplitude
    tip_phi = beam.shape_fn(np.array([[L, 0.0, 0.0]]))[0][0, 1]
    q0 = np.zeros(beam.n_modes)
    q0[0] = 1.5 / tip_phi[0]
    st = Settings(t_end=6.0, dt_out=0.25, rtol=1e-11, atol=1e-12, kinematics="inextensible")
    sol = simulate(
        beam,
        [],
        settings=st,
        method="full",
        prescribed=Prescribed(rate=4.0, spin_up_time=0.5),
        initial=Initial(modal_displacement=tuple(q0)),
    )
    assert sol.status == "success", sol.message
    after = sol.time >= 0.5
    h = _jacobi_integral(beam, sol.q[after], sol.p[after], 4.0)
    scale = 0.5 * 4.0**2 * beam.masses @ beam.points[:, 0] ** 2  # centrifugal potential of the beam
    assert np.ptp(h) / scale < 1e-9  # measured 1.5e-11
    # the motion is large: the tip shortens by centimetres and the deflection swings by metres
    _, u = point_motion(beam, sol, np.array([[L, 0.0, 0.0]]))
    assert u[:, 0, 0].min() < -0.05 and np.ptp(u[after, 0, 1]) > 1.0


def test_linear_limit_agrees_with_the_linear_model_with_geometric_stiffness(beam):
    # 0.1 rad/s: tip deflection ~1 cm (1e-3 of L); the two models differ by O((u/L)^2)
    pres = Prescribed(rate=0.1, spin_up_time=15.0)
    tips = {}
    for kin in ("linear", "inextensible"):
        st = Settings(t_end=20.0, dt_out=0.1, rtol=1e-11, atol=1e-14, kinematics=kin)
        sol = simulate(beam, [], settings=st, method="full", prescribed=pres)
        tips[kin] = point_motion(beam, sol, np.array([[L, 0.0, 0.0]]))[1][:, 0, 1]
    peak = np.abs(tips["linear"]).max()
    assert 5e-3 < peak < 2e-2
    assert np.abs(tips["inextensible"] - tips["linear"]).max() / peak < 1e-5


def test_tip_shortening_is_the_arc_length_deficit_of_the_deflected_curve(beam):
    q = np.zeros((1, beam.n_modes))
    q[0, :2] = [3.0, -0.7]
    u = beam.inextensible.shortening(np.array([L, 0.4 * L]), q)

    def deficit(x):
        return quad(lambda s: np.sqrt(1.0 - (_slopes(beam, np.array([s]))[0] @ q[0]) ** 2) - 1.0, 0.0, x, epsabs=1e-13)[
            0
        ]

    assert abs(u[0, 0] - deficit(L)) < 1e-10
    assert abs(u[0, 1] - deficit(0.4 * L)) < 1e-10
    with pytest.raises(ValueError, match="inextensible"):
        beam.inextensible.shortening(np.array([L]), 50.0 * q)


def test_a_folded_beam_stops_with_a_failure_that_says_why(beam):
    # a first-mode tip deflection of 9 m on a 10 m beam needs slopes > 1 near the tip
    tip_phi = beam.shape_fn(np.array([[L, 0.0, 0.0]]))[0][0, 1]
    q0 = np.zeros(beam.n_modes)
    q0[0] = 9.0 / tip_phi[0]
    st = Settings(t_end=1.0, dt_out=0.1, kinematics="inextensible")
    sol = simulate(beam, [], settings=st, prescribed=Prescribed(), initial=Initial(modal_displacement=tuple(q0)))
    assert sol.status == "failed"
    assert "t = 0 s" in sol.message and "|v'| >= 1" in sol.message
    assert np.isnan(sol.q[-1]).all()


@pytest.mark.parametrize(
    ("change", "field"),
    [
        ({"support": "free-free"}, "solver.kinematics"),
        ({"prescribed": None}, "solver.kinematics"),
        ({"geometric_stiffness": True}, "solver.geometric_stiffness"),
        ({"loads": [Load(kind="force", vector=(0.0, 1.0, 0.0), point=(L, 0.0, 0.0))]}, "loads"),
    ],
)
def test_bad_input_names_the_field(change, field):
    b = uniform_beam(L, RHO_A, EI, 3, support=change.get("support", "cantilever"))
    st = Settings(
        t_end=1.0, dt_out=0.1, kinematics="inextensible", geometric_stiffness=change.get("geometric_stiffness")
    )
    pres = change.get("prescribed", Prescribed())
    with pytest.raises(InputError) as exc:
        simulate(b, change.get("loads", []), settings=st, method="full", prescribed=pres)
    assert exc.value.field == field


def test_a_soft_beam_that_folds_during_spin_up_keeps_its_samples_and_says_why():
    # EI 300 instead of 1.4e4: the beam curls over (|v'| -> 1) during the spin-up; trial states
    # of rejected steps are far out of range, which must not raise from inside the kernel
    b = uniform_beam(L, RHO_A, 3e2, 6, support="cantilever")
    st = Settings(t_end=8.0, dt_out=0.05, kinematics="inextensible")
    sol = simulate(b, [], settings=st, prescribed=Prescribed(rate=6.0, spin_up_time=15.0))
    assert sol.status == "failed"
    assert "|v'| >= 1" in sol.message and "slope |v'| reached" in sol.message
    kept = np.isfinite(sol.q).all(axis=1)
    assert 2.0 < sol.time[kept][-1] < 8.0 and kept[: int(2.0 / 0.05)].all()


def test_the_linear_model_flags_deflections_beyond_its_range():
    # EI 140: the linear model (with geometric stiffness) deflects by more than the beam's length
    b = uniform_beam(L, RHO_A, 1.4e2, 6, support="cantilever")
    sol = simulate(b, [], settings=Settings(t_end=20.0, dt_out=0.1), prescribed=Prescribed(rate=6.0, spin_up_time=15.0))
    assert sol.status == "diverged"
    assert "of the body size 10 m" in sol.message and "not a small-deflection solution" in sol.message
    # the spin-up beam itself (5.7 % of L) stays in range without a note
    ok = simulate(
        uniform_beam(L, RHO_A, EI, 6, support="cantilever"),
        [],
        settings=Settings(t_end=20.0, dt_out=0.1),
        prescribed=Prescribed(rate=6.0, spin_up_time=15.0),
    )
    assert ok.status == "success" and "body size" not in ok.message


def test_perturbation_method_with_prescribed_motion_is_refused_by_name():
    from rotaflex.floating.case import run_case

    cfg = {
        "body": {
            "type": "beam",
            "beam": {"length": L, "rho_a": RHO_A, "ei": EI, "n_modes": 3, "support": "cantilever"},
        },
        "prescribed": {"rate": 1.0, "spin_up_time": 5.0},
        "solver": {"method": "perturbation", "t_end": 1.0, "dt_out": 0.1},
    }
    with pytest.raises(InputError) as exc:
        run_case(cfg)
    assert exc.value.field == "solver.method" and "prescribed" in exc.value.allowed
