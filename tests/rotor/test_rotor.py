"""Rotor/free-body dynamics against closed forms, conservation laws and each other."""

import numpy as np
import pytest
import sympy as sp
from sympy.physics.mechanics import ReferenceFrame

from rotaflex.core.errors import InputError
from rotaflex.rotor.case import model_from_config, run_case
from rotaflex.rotor.symbolic import EOMSpec, derive


def free_body(parameterisation="euler", sequence="123", t_end=100.0, **kw):
    cfg = {
        "inertia": [1.0, 1.0, 1.8],  # I3 <= I1 + I2: a rigid body (rotor.model.check_principal_inertias)
        "initial_angles": [0.1, 0.4, 0.2],
        "initial_body_rate": [0.3, -0.2, 5.0],
        **kw,
        "formulation": {"parameterisation": parameterisation, "sequence": sequence},
        "solver": {"t_end": t_end, "rtol": 1e-12, "atol": 1e-12, "n_output": 2001},
    }
    return run_case({"free_body": cfg})


PARAMETERISATIONS = [("euler", "123"), ("euler", "321"), ("quaternion", "123")]


@pytest.mark.parametrize("par, seq", PARAMETERISATIONS)
def test_torque_free_axisymmetric_body_matches_closed_form_and_conserves(par, seq):
    """20 s: 12.7 periods of the body-frame precession (lambda = 4 rad/s) and 16 spin turns, at
    the tolerances of the 100 s run below (which costs five times as much)."""
    _check_torque_free_axisymmetric(par, seq, t_end=20.0)


@pytest.mark.slow
@pytest.mark.parametrize("par, seq", PARAMETERISATIONS)
def test_torque_free_axisymmetric_body_long_run(par, seq):
    """The same over 100 s (64 precession periods): integration error that grows with time."""
    _check_torque_free_axisymmetric(par, seq, t_end=100.0)


def _check_torque_free_axisymmetric(par, seq, t_end):
    res = free_body(par, seq, t_end=t_end)
    assert res.status == "success", res.message
    ds = res.dataset
    t, w = ds["time"].values, ds["omega_body"].values
    # closed form: w3 constant, (w1 + i w2) rotates at lambda = (I3 - I1)/I1 w3
    lam = (1.8 - 1.0) / 1.0 * 5.0
    expected = (0.3 - 0.2j) * np.exp(1j * lam * t)
    np.testing.assert_allclose(w[:, 0] + 1j * w[:, 1], expected, atol=1e-8)
    np.testing.assert_allclose(w[:, 2], 5.0, atol=1e-9)
    K = ds["kinetic_energy"].values
    H = np.linalg.norm(ds["angular_momentum"].values, axis=1)
    assert np.max(np.abs(K / K[0] - 1)) < 1e-9
    assert np.max(np.abs(H / H[0] - 1)) < 1e-9
    # inertial angular momentum vector itself is constant (torque-free)
    Hv = ds["angular_momentum"].values
    assert np.max(np.abs(Hv - Hv[0])) / H[0] < 1e-9


def test_euler_and_quaternion_free_body_agree_for_asymmetric_body():
    from rotaflex.rotation import euler_from_matrix, rotation_matrix

    kw = {"inertia": [1.0, 2.0, 3.0], "initial_body_rate": [0.05, 3.0, 0.1]}  # near the unstable axis
    a123 = [0.1, 0.4, 0.2]
    a313 = euler_from_matrix("313", rotation_matrix("123", a123)).tolist()  # same attitude
    runs = [
        free_body("euler", "123", t_end=10.0, **kw),
        free_body("euler", "313", t_end=10.0, **kw, initial_angles=a313),
        free_body("quaternion", "123", t_end=10.0, **kw),
    ]
    ref = runs[2].dataset
    for r in runs[:2]:
        assert r.status == "success"
        np.testing.assert_allclose(r.dataset["omega_body"].values, ref["omega_body"].values, atol=1e-7)
        np.testing.assert_allclose(r.dataset["quaternion"].values, ref["quaternion"].values, atol=1e-7)


def test_constant_torque_spin_up_about_principal_axis():
    res = free_body("quaternion", t_end=2.0, torque=[0.0, 0.0, 0.5], initial_body_rate=[0.0, 0.0, 1.0])
    w = res.dataset["omega_body"].values
    np.testing.assert_allclose(w[:, 2], 1.0 + 0.5 / 1.8 * res.dataset["time"].values, atol=1e-10)


def test_symbolic_body_rates_match_sympy_mechanics_orientation():
    """Our derivation's body rates for 3-1-3 vs sympy.physics.mechanics orient_body_fixed."""
    t = sp.Symbol("t")
    q1, q2, q3 = (sp.Function(n)(t) for n in ("q1", "q2", "q3"))
    N, B = ReferenceFrame("N"), ReferenceFrame("B")
    B.orient_body_fixed(N, (q1, q2, q3), "313")
    w_ref = B.ang_vel_in(N).to_matrix(B)
    tt, q, qd, p, M, f, e, e_dot = derive(EOMSpec(spin_index=None, sequence="313"))
    # the free-body mass matrix is E^T J E: recover E from it with J = I
    sub = {p[1]: 1, p[2]: 1, p[3]: 1}
    vals = {q[0]: 0.3, q[1]: 0.7, q[2]: -0.4}
    M_num = np.array(M.subs(sub).subs(vals), dtype=float)
    E = np.array(w_ref.jacobian([q1.diff(t), q2.diff(t), q3.diff(t)]).subs({q1: 0.3, q2: 0.7, q3: -0.4}), dtype=float)
    np.testing.assert_allclose(M_num, E.T @ E, atol=1e-12)


def test_linear_whirl_frequencies_match_closed_form():
    """Disk with tilt stiffness: Id w^2 -/+ Ip Omega w - k = 0 (inertial frame whirl)."""
    Ip, Id, k, Om = 2.0, 1.0, 50.0, 10.0
    wf = (Ip * Om + np.sqrt((Ip * Om) ** 2 + 4 * Id * k)) / (2 * Id)
    wb = (-Ip * Om + np.sqrt((Ip * Om) ** 2 + 4 * Id * k)) / (2 * Id)
    for seq, expansion, expect in [
        ("123", "second_order", {abs(wf - Om), wb + Om}),
        ("quaternion", "second_order", None),
    ]:
        if seq == "quaternion":
            continue  # time-varying coefficients: no constant-coefficient eigenproblem
        spec = EOMSpec(sequence=seq, expansion=expansion, spin_index=0)
        tt, q, qd, p, M, f, e, e_dot = derive(spec)
        vals = dict(zip(p, [1.0, Ip, Id, Id, 0.0, k, Om, 0.0, 0, 0, 0], strict=False))
        Mn = np.array(M.subs(vals), dtype=float)[2:, 2:]
        fq = f.subs(vals)[2:, :]
        Kn = -np.array(fq.jacobian(q[2:]), dtype=float)
        Gn = -np.array(fq.jacobian(qd[2:]), dtype=float)
        A = np.block([[np.zeros((2, 2)), np.eye(2)], [-np.linalg.solve(Mn, Kn), -np.linalg.solve(Mn, Gn)]])
        freqs = sorted(set(np.round(np.abs(np.linalg.eigvals(A).imag), 9)))
        np.testing.assert_allclose(freqs, sorted(expect), rtol=1e-9)


def test_paper_truncated_123_reproduces_eq34():
    """The paper's 1-2-3 body-frame linear EOM: I q'' - Omega G q' = 0 with G = [[0,-2I],[2I,0]]."""
    tt, q, qd, p, M, f, e, e_dot = derive(
        EOMSpec(sequence="123", convention="paper", expansion="paper_truncated", spin_index=0)
    )
    I, Om = 1.0, 10.0
    vals = dict(zip(p, [1.0, 2 * I, I, I, 0.0, 0.0, Om, 0.0, 0, 0, 0], strict=False))
    Mn = np.array(M.subs(vals), dtype=float)
    G = np.array(f.subs(vals).jacobian(qd), dtype=float) / Om
    np.testing.assert_allclose(Mn[2:, 2:], I * np.eye(2))
    np.testing.assert_allclose(G[2:, 2:], [[0, -2 * I], [2 * I, 0]], atol=1e-15)
    assert np.all(np.array(f.subs(vals).jacobian(q), dtype=float) == 0)  # K*_123 = 0


def test_spherical_quaternion_singularity_is_reported_not_integrated():
    res = run_case(
        {
            "formulation": {"parameterisation": "quaternion_spherical"},
            "motion": {"initial_spin_angle": 1.0},
            "solver": {"t_end": 2.0},
        }
    )
    assert res.status == "singular"
    t_stop = float(res.dataset["time"][-1])
    assert t_stop < (2 * np.pi - 1.0) / 10.0 + 1e-3  # phi = 2 pi at t = 0.528 s
    assert t_stop > 0.45
    at_start = run_case({"formulation": {"parameterisation": "quaternion_spherical"}})
    assert at_start.status == "singular" and "t = 0" in at_start.message


def test_bad_config_is_rejected_with_field_name():
    with pytest.raises(InputError, match="disk.mass"):
        model_from_config({"disk": {"mass": -1.0}})
    with pytest.raises(InputError, match="formulation.sequence"):
        model_from_config({"formulation": {"sequence": "112"}})
    with pytest.raises(InputError, match="solver.method"):
        model_from_config({"solver": {"method": "Euler"}})
    with pytest.raises(InputError, match="free_body.formulation.parameterisation"):
        model_from_config({"free_body": {"formulation": {"parameterisation": "quaternion_spherical"}}})


@pytest.mark.parametrize("expansion", ["nonlinear", "second_order"])
def test_generated_equations_give_the_same_bits_on_python_floats_as_on_numpy_scalars(expansion):
    """The simulation evaluates the generated equations on Python floats (3x cheaper per call
    than the numpy scalars that unpacking arrays gives); both are IEEE doubles through the same
    math functions, so every output must be bit for bit what numpy scalars give."""
    from rotaflex.rotor.symbolic import compiled

    all_fn = compiled(EOMSpec(sequence="123", expansion=expansion, spin_index=0))["_all"]
    rng = np.random.default_rng(7)
    for _ in range(200):
        y = rng.normal(scale=3.0, size=8)
        p = np.abs(rng.normal(size=11)) + 0.1
        t = float(rng.uniform(0, 100))
        on_floats = all_fn(t, y.tolist(), p.tolist())
        on_numpy = all_fn(np.float64(t), y, p)
        for a, b in zip(on_floats, on_numpy, strict=True):
            assert np.array(a, float).tobytes() == np.array(b, float).tobytes()


@pytest.mark.parametrize("sequence", ["123", "313"])
def test_mass_rhs_is_all_without_the_attitude(sequence):
    """The right-hand side evaluates ``_mass_rhs``, the generated equations' M and f without
    the attitude outputs: the same bits as ``_all``'s M and f; ``MASS_DIAGONAL`` holds exactly
    when every off-diagonal term of M is zero at random states."""
    from rotaflex.rotor.symbolic import compiled

    ns = compiled(EOMSpec(sequence=sequence, expansion="nonlinear", spin_index=0))
    n = ns["N_DOF"]
    rng = np.random.default_rng(3)
    off_diagonal = 0.0
    for _ in range(100):
        y = rng.normal(scale=2.0, size=2 * n).tolist()
        p = (np.abs(rng.normal(size=11)) + 0.1).tolist()
        t = float(rng.uniform(0, 50))
        M, f, _, _ = ns["_all"](t, y, p)
        M2, f2 = ns["_mass_rhs"](t, y, p)
        assert np.array(M2, float).tobytes() == np.array(M, float).tobytes()
        assert np.array(f2, float).tobytes() == np.array(f, float).tobytes()
        Ma = np.array(M, float).reshape(n, n)
        off_diagonal = max(off_diagonal, np.abs(Ma - np.diag(np.diag(Ma))).max())
    assert ns["MASS_DIAGONAL"] == (off_diagonal == 0.0)


def test_diagonal_mass_matrix_solve_is_lapacks(monkeypatch):
    """With a structurally diagonal mass matrix the right-hand side divides f by M's diagonal
    instead of calling LAPACK's dgesv: the run must be bit for bit what dgesv gives."""
    import sys

    from rotaflex.rotor.symbolic import compiled

    sim = sys.modules["rotaflex.rotor.simulate"]
    cfg = {
        "disk": {"mass": 1.0, "polar_inertia": 2.0, "diametral_inertia": 1.0},
        "support": {"stiffness": 4.0, "tilt_stiffness": 3.0},
        "motion": {"spin_speed": 10.0, "initial_tilt": [0.01, 0.02], "initial_tilt_rate": [1.0, 1.0]},
        "solver": {"t_end": 1.0, "n_output": 101},
    }
    assert compiled(sim.spec_of(model_from_config(cfg)))["MASS_DIAGONAL"]
    divided = run_case(cfg).dataset

    def general(spec, **kw):
        return {**compiled(spec, **kw), "MASS_DIAGONAL": False}

    monkeypatch.setattr(sim, "compiled", general)
    solved = run_case(cfg).dataset
    for name in ("generalized_coordinate", "generalized_velocity", "generalized_acceleration", "quaternion"):
        np.testing.assert_array_equal(divided[name].values, solved[name].values)
    assert divided.attrs["nfev"] == solved.attrs["nfev"]


def test_overflow_on_python_floats_falls_back_to_numpy_scalars(monkeypatch):
    """Where a float power overflows (OverflowError on Python floats; numpy scalars give inf),
    the right-hand side falls back to numpy scalars: the run must give what it gives when the
    equations are evaluated on numpy scalars throughout."""
    import sys

    from rotaflex.rotor.symbolic import compiled

    sim = sys.modules["rotaflex.rotor.simulate"]  # the package re-exports a function of that name
    cfg = {
        "disk": {"mass": 1.0, "polar_inertia": 2.0, "diametral_inertia": 1.0},
        "support": {"stiffness": 0.0, "tilt_stiffness": 3.0},
        "motion": {"spin_speed": 10.0, "initial_tilt": [0.01, 0.02], "initial_tilt_rate": [1.0, 1.0]},
        "solver": {"t_end": 0.5, "n_output": 51},
    }
    plain = run_case(cfg).dataset

    def numpy_only(spec, **kw):
        ns = dict(compiled(spec, **kw))

        def on_numpy(real):
            def fn(t, y, p):
                if isinstance(y, list):
                    raise OverflowError("(34, 'Numerical result out of range')")
                return real(t, y, p)

            return fn

        ns["_all"], ns["_mass_rhs"] = on_numpy(ns["_all"]), on_numpy(ns["_mass_rhs"])
        return ns

    monkeypatch.setattr(sim, "compiled", numpy_only)
    fallback = run_case(cfg).dataset
    for name in ("generalized_coordinate", "generalized_velocity", "generalized_acceleration", "quaternion"):
        np.testing.assert_array_equal(fallback[name].values, plain[name].values)
    assert fallback.attrs["nfev"] == plain.attrs["nfev"]
