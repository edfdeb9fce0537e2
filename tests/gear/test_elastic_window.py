"""Travelling-window elastic-tooth model: geometry, statics, lumped limit, energy, convergence."""

import dataclasses
import math

import numpy as np
import pytest

from rotaflex.gear.models import chain as tor
from rotaflex.gear.models.mesh_stiffness import loaded_mesh_table, mesh_table_from_static
from rotaflex.gear.models.window import build_window_model, corner_gap
from rotaflex.gear.pair.geometry import GearGeometry, ProfileRelief, center_distance_no_backlash
from rotaflex.gear.pair.tooth_mesh import build_tooth_mesh
from rotaflex.gear.solvers import window_run as wr
from rotaflex.gear.static.loaded_te import loaded_te, pair_line
from rotaflex.gear.static.tooth_analysis import mesh_stiffness

E, NU, RHO = 210e9, 0.3, 7800.0
G0 = GearGeometry(module=3.175e-3, teeth=28, face_width=6.35e-3)
A = center_distance_no_backlash(G0, G0)
L = A * math.sin(math.acos(2 * G0.base_radius / A))
S_E = math.sqrt(G0.tip_radius_**2 - G0.base_radius**2)
S_A = L - S_E


def _system(table, zeta=0.07, **kw):
    kw.setdefault("drive", "motor")
    kw.setdefault("motor_slope", 0.5)
    return tor.TorsionalSystem(
        mesh=table,
        teeth=(28, 28),
        base_radius=(G0.base_radius,) * 2,
        inertia=(2.965e-4,) * 2,
        mesh_damping_ratio=zeta,
        **kw,
    )


@pytest.fixture(scope="module")
def plain():
    mesh = build_tooth_mesh(G0)
    return mesh, {t: pair_line(G0, G0, mesh, mesh, A, t / G0.base_radius, (E, NU, E, NU)) for t in (5.0, 22.25)}


@pytest.fixture(scope="module")
def relieved():
    r_start = math.sqrt(G0.base_radius**2 + (S_A + G0.base_pitch) ** 2)  # end of single contact
    g = dataclasses.replace(G0, tip_relief=ProfileRelief(6e-6, r_start))
    mesh = build_tooth_mesh(g)
    return g, mesh, pair_line(g, g, mesh, mesh, A, 22.25 / g.base_radius, (E, NU, E, NU))


# ------------------------------------------------------------------------ corner contact
def test_corner_gap_touches_at_the_path_start_and_opens_quadratically():
    rb, ra = G0.base_radius, G0.tip_radius_
    d = corner_gap(rb, rb, ra, L, S_A - np.array([0.0, 1e-4, 2e-4, 4e-4]))
    assert d[0] < 1e-15
    order = np.log2(d[2:] / d[1:-1])
    assert np.all(np.abs(order - 2.0) < 0.05), order


def test_corner_gap_is_zero_for_any_conjugate_contact_point():
    """The formula's distance to the involute vanishes for every point of the mate's involute
    that is on the line of action (conjugate action), whatever its radius."""
    rb = G0.base_radius
    for s in np.linspace(S_A, S_E, 5):
        r_mate = math.sqrt(rb**2 + (L - s) ** 2)
        assert corner_gap(rb, rb, r_mate, L, np.array([s]))[0] < 1e-14


# ------------------------------------------------------------------------------- statics
@pytest.mark.parametrize("n_modes", [0, 2])
def test_slow_roll_reproduces_the_loaded_static_te_of_gear_static(relieved, n_modes):
    """At 100 rpm (mesh 47 Hz, mesh mode 7 kHz) the window model's DTE is the relieved pair's
    loaded static TE over a whole mesh cycle, with one pair, two pairs and the relief zones."""
    g, mesh, line = relieved
    force = 22.25 / g.base_radius
    table = loaded_mesh_table(line, force)
    model = build_window_model(
        _system(table, drive="constant_speed"), line, (mesh, mesh), (RHO, RHO), n_modes=n_modes, corner_contact=False
    )
    op = tor.OperatingPoint(100.0, 22.25)
    h = wr.simulate(model, op, 3)
    spc = h["spc"]
    last = slice(2 * spc, 3 * spc)
    phase = np.arange(spc) / spc
    static = loaded_te(line, S_A + phase * g.base_pitch, force)["te"]
    err = np.abs(h["dte"][last] - static)
    assert err.max() < 5e-3 * static.mean(), err.max() / static.mean()
    assert abs(h["dte"][last].mean() / static.mean() - 1) < 1e-3


# ------------------------------------------------------------------------ lumped limit
def _curve(model_or_sys, speeds, torque, window):
    """K_v, DTE first-harmonic amplitude and contact-loss fraction, continued up in speed."""
    st, out = None, []
    for rpm in speeds:
        op = tor.OperatingPoint(float(rpm), torque)
        run = wr.steady_state if window else tor.steady_state
        r, st = run(model_or_sys, op, state=st)
        out.append((float(r.dataset.dynamic_factor), float(r.dataset.dte_h1), float(r.dataset.contact_loss_fraction)))
    return np.array(out)


def _peak(speeds, y):
    i = int(np.argmax(y))
    a, b, c = y[i - 1 : i + 2]
    return speeds[i] + 0.5 * (a - c) / (a - 2 * b + c) * (speeds[1] - speeds[0])


def test_massless_teeth_without_corner_contact_are_the_lumped_model_from_gear_static(plain):
    """Same physics by two routes: the lumped torsional model driven by gear static's
    k(phi) (static.mesh_stiffness) vs the window model's per-pair tables and bookkeeping."""
    mesh, lines = plain
    torque = 5.0
    ms = mesh_stiffness(G0, G0, E, NU, torque=torque)
    lumped = _system(mesh_table_from_static(ms, 28), zeta=0.2)
    model = build_window_model(
        _system(loaded_mesh_table(lines[5.0], torque / G0.base_radius), zeta=0.2),
        lines[5.0],
        (mesh, mesh),
        (RHO, RHO),
        n_modes=0,
        corner_contact=False,
    )
    speeds = np.arange(12000.0, 17001.0, 500.0)
    cl, cw = _curve(lumped, speeds, torque, False), _curve(model, speeds, torque, True)
    assert cl[:, 2].max() == 0 and cw[:, 2].max() == 0  # light load: no contact loss
    np.testing.assert_allclose(cw[:, 0], cl[:, 0], rtol=5e-3)
    np.testing.assert_allclose(cw[:, 1], cl[:, 1], rtol=5e-3)
    assert abs(_peak(speeds, cw[:, 1]) / _peak(speeds, cl[:, 1]) - 1) < 0.01


def test_default_window_model_agrees_with_the_lumped_model_in_the_linear_limit(plain):
    """Issue criterion: light load, no contact loss; resonance within 3 %, K_v within 5 % away
    from the resonance peak. The window model adds premature corner contact (lumped: a
    stiffness step), which is why K_v differs most at low speed (documented)."""
    mesh, lines = plain
    torque = 5.0
    ms = mesh_stiffness(G0, G0, E, NU, torque=torque)
    lumped = _system(mesh_table_from_static(ms, 28), zeta=0.25)
    model = build_window_model(
        _system(loaded_mesh_table(lines[5.0], torque / G0.base_radius), zeta=0.25), lines[5.0], (mesh, mesh), (RHO, RHO)
    )
    speeds = np.arange(11000.0, 20001.0, 500.0)
    cl, cw = _curve(lumped, speeds, torque, False), _curve(model, speeds, torque, True)
    assert cl[:, 2].max() == 0 and cw[:, 2].max() == 0
    peak_l, peak_w = _peak(speeds, cl[:, 1]), _peak(speeds, cw[:, 1])
    assert abs(peak_w / peak_l - 1) < 0.03, (peak_w, peak_l)
    away = np.abs(speeds - peak_l) > 0.1 * peak_l
    dev = np.abs(cw[away, 0] / cl[away, 0] - 1)
    assert dev.max() < 0.05, dict(zip(speeds[away], dev, strict=True))


# ---------------------------------------------------------------------- energy, convergence
@pytest.fixture(scope="module")
def toothed(plain):
    mesh, lines = plain
    line = lines[22.25]
    model = build_window_model(_system(loaded_mesh_table(line, line.force)), line, (mesh, mesh), (RHO, RHO), n_modes=2)
    op = tor.OperatingPoint(10000.0, 22.25)
    res, st = wr.steady_state(model, op)
    return model, op, res, st


def test_energy_balance_with_damping_tooth_modes_and_corner_contact(toothed):
    model, op, _, st = toothed
    res = []
    for spc in (400, 1600):
        h = wr.simulate(model, op, 10, steps_per_cycle=spc, state=st)
        eb = wr.energy_balance(model, op, h)
        assert eb["dissipated"] > 0 and eb["dropped"] < 1e-3 * eb["dissipated"]
        res.append(abs(eb["residual"]) / eb["dissipated"])
    assert res[1] < 0.01 and res[1] < res[0] / 2, res


def test_time_step_and_window_size_converge(toothed):
    model, op, ref, st = toothed
    fine, _ = wr.steady_state(model, op, steps_per_cycle=2 * ref.dataset.attrs["samples_per_cycle"], state=st)
    assert abs(float(fine.dataset.dynamic_factor) / float(ref.dataset.dynamic_factor) - 1) < 5e-3
    assert abs(float(fine.dataset.dte_pp) / float(ref.dataset.dte_pp) - 1) < 5e-3
    wide = dataclasses.replace(model, window=model.window + 2)
    more, _ = wr.steady_state(wide, op, state=None)
    assert abs(float(more.dataset.dynamic_factor) / float(ref.dataset.dynamic_factor) - 1) < 1e-3


def test_tooth_modes_converge(plain):
    """K_v converges in the tooth modes kept (the corner-entry impact excites the first three);
    the DTE hardly depends on them."""
    mesh, lines = plain
    line = lines[22.25]
    sys = _system(loaded_mesh_table(line, line.force))
    op = tor.OperatingPoint(19000.0, 22.25)
    kv, dte = [], []
    for n in (2, 3, 4):
        r, _ = wr.steady_state(build_window_model(sys, line, (mesh, mesh), (RHO, RHO), n_modes=n), op)
        kv.append(float(r.dataset.dynamic_factor))
        dte.append(float(r.dataset.dte_pp))
    assert abs(kv[2] - kv[1]) < 0.2 * abs(kv[1] - kv[0]) and abs(kv[2] / kv[1] - 1) < 0.01, kv
    assert abs(dte[2] / dte[1] - 1) < 5e-3 and abs(dte[1] / dte[0] - 1) < 5e-3, dte


def test_contact_loss_and_reimpact_at_resonance_run_through(plain):
    mesh, lines = plain
    line = lines[22.25]
    model = build_window_model(_system(loaded_mesh_table(line, line.force)), line, (mesh, mesh), (RHO, RHO))
    r, _ = wr.steady_state(model, tor.OperatingPoint(15000.0, 22.25))
    ds = r.dataset
    assert float(ds.contact_loss_fraction) > 0.1
    assert np.all(np.isfinite(ds["mesh_force"].values)) and float(ds.force_min) <= 0.0
    assert ds.attrs["status"] in ("success", "not_periodic") and "periodic" in ds.attrs["message"]
    assert float(ds.fillet_stress_max_pinion) > 0 and float(ds.fillet_stress_max_wheel) > 0
