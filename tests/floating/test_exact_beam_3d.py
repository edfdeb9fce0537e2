"""Statics of the 3-D geometrically exact (Simo-Reissner) beam against independent references.

References: the planar elastica (elliptic integrals, :mod:`test_exact_beam_static`) and the
planar Reissner beam of the same mesh (a second formulation); the Bathe & Bolourchi (1979) 45-degree
bend under an out-of-plane tip load with the tip coordinates published by Simo & Vu-Quoc (1986,
Comput. Methods Appl. Mech. Eng. 58, 79-116, Table 2, 8 elements) and Bathe & Bolourchi (1979, Int. J.
Numer. Methods Eng. 14, 961-986); closed forms of pure bending (a full circle under
``M = 2 pi EI / L``) and of the helix under an end moment off the principal planes (isotropic
section: the rotation ``exp(s M~ / EI)``); rigid-motion invariance and the energy gradient.
"""

from __future__ import annotations

import copy
import dataclasses
import tomllib
from pathlib import Path

import numpy as np
import pytest
from test_exact_beam_static import elastica_tip
from typer.testing import CliRunner

from rotaflex.cli import app
from rotaflex.core.errors import InputError
from rotaflex.core.threads import limit_blas_threads
from rotaflex.floating import exact_kernels3d as ek3
from rotaflex.floating.case import prepare, run_case
from rotaflex.floating.exact_beam import LoadSteppingError, PointLoads, cantilever
from rotaflex.floating.exact_beam3d import PointLoads3D, arc3d, assemble3d, cantilever3d, solve_static, straight3d
from rotaflex.floating.exact_solve3d import simulate_exact3d
from rotaflex.rotation import quaternion_from_matrix, rotation_matrix
from rotaflex.rotation.quaternion import quaternion_product

STIFF = 1e8  # EA, GA [N] for EI = 1 N m^2, L = 1 m: the inextensible, shear-rigid limit


@pytest.fixture(autouse=True, scope="module")
def _one_blas_thread():
    # small dense solves: BLAS threads only contend on a loaded machine (10x slower), as the CLI
    with limit_blas_threads():
        yield


def tip3d(alpha, n_el, frame=None, ea=STIFF, ga=STIFF):
    """Tip position and rotation of a unit cantilever (EI = 1) under ``-alpha e2`` of its frame."""
    F = np.eye(3) if frame is None else frame
    b = cantilever3d(1.0, n_el, ea=ea, ga=ga, gj=0.7, ei2=2.0, ei3=1.0, frame=F)
    loads = PointLoads3D.build(b, [F[:, 0]], ["force"], ["inertial"], [-alpha * F[:, 1]])
    q = solve_static(b, loads).q
    return b.node_positions(q)[-1], b.node_rotations(q)[-1]


@pytest.mark.parametrize("alpha", [1.0, 2.0, 5.0, 10.0])
def test_planar_elastica_in_any_plane_equals_the_planar_beam(alpha):
    n = 16
    b2 = cantilever(1.0, n, ea=STIFF, ga=STIFF, ei=1.0, rho_a=1.0)
    q2 = solve_static(b2, PointLoads.build(b2, [(1.0, 0.0)], ["force"], ["inertial"], [(0.0, -alpha)])).q
    planar = np.array([q2[3 * n], q2[3 * n + 1], 0.0])
    x, y, th = elastica_tip(alpha)
    # an arbitrary plane: the beam along F e1, loaded along -F e2, bending about F e3
    tilted = rotation_matrix("123", (0.4, -0.7, 1.1))
    for F in (np.eye(3), tilted):
        tip, R = tip3d(alpha, n, F)
        local = F.T @ tip
        assert local == pytest.approx(planar, abs=1e-9)
        assert abs(local[2]) < 1e-12
        # tip section turned by -theta about F e3
        assert F.T @ R == pytest.approx(rotation_matrix("123", (0, 0, q2[3 * n + 2])), abs=1e-9)
        # the elastica: 16 elements leave the O(h^2) error below 3e-3 L
        assert local[:2] == pytest.approx((x, -y), abs=3e-3)
        assert -q2[3 * n + 2] == pytest.approx(th, abs=3e-3)


def test_elastica_mesh_convergence_is_second_order():
    _, y, _ = elastica_tip(5.0)
    err = np.array([abs(-tip3d(5.0, k)[0][1] - y) for k in (4, 8, 16, 32)])
    order = np.log(err[:-1] / err[1:]) / np.log(2.0)
    assert np.all(order > 1.85) and np.all(order < 2.15), order


def bend45(load, n_el=8):
    """Bathe & Bolourchi's bend: R = 100, 45 degrees in the x-y plane from the origin along y
    towards x, E = 1e7, unit square section (A = 1, I = 1/12, J = 1/6, G = E / 2, k = 5/6)."""
    E = 1e7
    frame = np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]])  # e1 = y, turns about -z
    piece = arc3d(100.0, np.pi / 4, n_el, ea=E, ga=E / 2 * 5 / 6, gj=E / 2 / 6, ei2=E / 12, ei3=E / 12, frame=frame)
    b = assemble3d([piece], [True])
    loads = PointLoads3D.build(b, [b.nodes[-1]], ["force"], ["inertial"], [(0.0, 0.0, load)])
    return b, b.node_positions(solve_static(b, loads).q)[-1]


@pytest.mark.parametrize(
    ("load", "published"),
    [
        # (Simo & Vu-Quoc 1986, 8 elements), (Bathe & Bolourchi 1979)
        (300.0, [(22.33, 58.84, 40.08), (22.5, 59.2, 39.5)]),
        (600.0, [(15.79, 47.23, 53.37), (15.9, 47.2, 53.4)]),
    ],
)
def test_bathe_bolourchi_45_degree_bend(load, published):
    b, tip = bend45(load)
    assert b.nodes[-1] == pytest.approx((100 - 100 / np.sqrt(2), 100 / np.sqrt(2), 0.0), abs=1e-12)
    pub = np.array(published)
    # within the published scatter (the two sources differ by up to 0.6) plus 0.1
    lo, hi = pub.min(axis=0) - 0.1, pub.max(axis=0) + 0.1
    assert np.all(tip >= lo) and np.all(tip <= hi), (tip, lo, hi)
    # the same 8-element 2-node element with one-point integration as Simo & Vu-Quoc: within 0.1
    assert tip == pytest.approx(pub[0], abs=0.1)


@pytest.mark.parametrize("axis", [1, 2])
def test_end_moment_rolls_a_full_circle(axis):
    # M = 2 pi EI / L about the principal axis e2 (EI2) or e3 (EI3): a closed circle, the tip
    # back at the root with its section turned by 2 pi (the identity)
    n, L = 20, 2.0
    ei = (5.0, 3.0)[axis - 1]
    b = cantilever3d(L, n, ea=1e6, ga=1e6, gj=1.0, ei2=5.0, ei3=3.0)
    m = np.zeros(3)
    m[axis] = 2 * np.pi * ei / L
    q = solve_static(b, PointLoads3D.build(b, [(L, 0.0, 0.0)], ["torque"], ["inertial"], [m])).q
    x = b.node_positions(q)
    assert np.linalg.norm(x[-1]) < 1e-9 * L
    assert b.node_rotations(q)[-1] == pytest.approx(np.eye(3), abs=1e-9)
    # the nodes: corners of a regular n-gon of side L / n in the plane normal to the axis
    assert np.allclose(x[:, axis], 0.0, atol=1e-12)
    assert np.allclose(np.linalg.norm(np.diff(x, axis=0), axis=1), L / n, rtol=1e-10)


def rotation_about(n, angle):
    """Rodrigues: the rotation by ``angle`` about the unit axis ``n``."""
    N = np.array([[0, -n[2], n[1]], [n[2], 0, -n[0]], [-n[1], n[0], 0]])
    return np.eye(3) + np.sin(angle) * N + (1 - np.cos(angle)) * N @ N


def helix(s, kappa, n):
    """Centreline of a beam from the origin along e1 under constant curvature ``kappa n``
    (spatial, constant: ``R(s) = exp(s kappa n~)``)."""
    e1 = np.array([1.0, 0.0, 0.0])
    c, sn = np.cos(kappa * s), np.sin(kappa * s)
    return (
        np.outer(sn / kappa, e1)
        + np.outer((1 - c) / kappa, np.cross(n, e1))
        + np.outer(s - sn / kappa, np.dot(n, e1) * n)
    )


@pytest.mark.parametrize("frame", ["inertial", "material"])
def test_end_moment_off_the_principal_planes_gives_the_helix(frame):
    # isotropic section (GJ = EI2 = EI3 = EI): the end moment m = EI kappa n is the spatial
    # moment at every section, the rotation exp(s kappa n~) and the centreline a helix about n;
    # one full turn (kappa L = 2 pi) ends on the axis at (n . e1) n L. A follower moment gives
    # the same (the tip turns about n, which leaves n unchanged).
    L, ei, n_el = 1.0, 2.0, 24
    n = np.array([1.0, 2.0, 2.0]) / 3.0
    b = cantilever3d(L, n_el, ea=1e7, ga=1e7, gj=ei, ei2=ei, ei3=ei)
    kappa = 2 * np.pi / L
    loads = PointLoads3D.build(b, [(L, 0, 0)], ["torque"], [frame], [ei * kappa * n])
    q = solve_static(b, loads).q
    x = b.node_positions(q)
    assert x[-1] == pytest.approx(np.dot(n, [1, 0, 0]) * n * L, abs=1e-9)
    # no force, so Gamma = 0: each chord is h R(s_mid) e1, the midpoint rule of the helix's
    # integral (error <= L h^2 kappa^2 / 24), and exactly the sum of those chords
    h = L / n_el
    mid = helix(b.arclength[1:], kappa, n) - helix(b.arclength[:-1], kappa, n)
    t_mid = np.array([rotation_about(n, kappa * (s + h / 2)) @ [1, 0, 0] for s in b.arclength[:-1]])
    assert x[1:] == pytest.approx(np.cumsum(h * t_mid, axis=0), abs=1e-9)
    assert np.abs(x[1:] - np.cumsum(mid, axis=0)).max() <= L * h**2 * kappa**2 / 24
    w = 0.5 * (b.arclength * kappa)
    expect = np.stack([np.cos(w), *(np.sin(w)[None] * n[:, None])], axis=-1)
    got = q[: 7 * (n_el + 1)].reshape(-1, 7)[:, 3:]
    assert np.abs(np.abs(np.einsum("ij,ij->i", got, expect)) - 1.0).max() < 1e-10


def test_helix_mesh_convergence_is_second_order():
    L, ei, n = 1.0, 1.0, np.array([0.0, 0.6, 0.8])
    kappa = 3.0
    exact = helix(np.array([L]), kappa, n)[0]
    err = []
    for k in (4, 8, 16, 32):
        b = cantilever3d(L, k, ea=1e7, ga=1e7, gj=ei, ei2=ei, ei3=ei)
        loads = PointLoads3D.build(b, [(L, 0, 0)], ["torque"], ["inertial"], [ei * kappa * n])
        err.append(np.linalg.norm(b.node_positions(solve_static(b, loads).q)[-1] - exact))
    order = np.log(np.array(err[:-1]) / np.array(err[1:])) / np.log(2.0)
    assert np.all(order > 1.9) and np.all(order < 2.1), order


def random_state(b, rng, size=0.3):
    """The reference state moved by random increments of ``size`` (m and rad)."""
    q = b.reference_state()
    dx = size * rng.standard_normal(b.n_dof)
    dx[b.frame_dof :] = 0.0
    ek3.advance(q, dx)
    return q


def test_strains_are_objective_and_forces_turn_with_a_rigid_rotation():
    rng = np.random.default_rng(3)
    b = assemble3d(
        [
            arc3d(
                2.0, 1.0, 5, ea=30.0, ga=(20.0, 10.0), gj=2.0, ei2=3.0, ei3=4.0, frame=rotation_matrix("123", (1, 2, 3))
            )
        ],
        [True],
    )
    q = random_state(b, rng)
    none = PointLoads3D.build(b, [], [], [], [])
    r, _, e = b.residual(none, q, 0.0)
    # a rigid motion: every position turned by Q and shifted, every section rotation Q R
    Q = rotation_matrix("313", (0.3, 2.5, -1.0))
    qr = q.copy().reshape(-1, 7)
    qr[:, :3] = qr[:, :3] @ Q.T + (1.0, -2.0, 0.5)
    qr[:, 3:] = quaternion_product(quaternion_from_matrix(Q), qr[:, 3:])
    r2, _, e2 = b.residual(none, qr.ravel(), 0.0)
    assert e2 == pytest.approx(e, rel=1e-12)
    assert r2.reshape(-1, 3) == pytest.approx(r.reshape(-1, 3) @ Q.T, abs=1e-10 * np.abs(r).max())
    # the reference state is stress-free (the arc's curvature is the reference strain)
    r0, _, e0 = b.residual(none, b.reference_state(), 0.0)
    assert e0 < 1e-25 and np.abs(r0).max() < 1e-12


def test_internal_force_is_the_energy_gradient_and_tangent_its_derivative():
    # the analytic internal force against central differences of the strain energy under the
    # same multiplicative perturbations (x + h, exp(h e~) R), and the tangent against the force
    rng = np.random.default_rng(7)
    b = cantilever3d(1.0, 3, ea=50.0, ga=(40.0, 30.0), gj=2.0, ei2=3.0, ei3=5.0)
    q = random_state(b, rng, 0.4)
    none = PointLoads3D.build(b, [], [], [], [])
    r, K, _ = b.residual(none, q, 0.0)
    h = 1e-6
    for j in range(b.frame_dof):
        d = np.zeros(b.n_dof)
        d[j] = h
        qp, qm = q.copy(), q.copy()
        ek3.advance(qp, d)
        ek3.advance(qm, -d)
        rp, _, ep = b.residual(none, qp, 0.0)
        rm, _, em = b.residual(none, qm, 0.0)
        assert (ep - em) / (2 * h) == pytest.approx(r[j], abs=1e-6 * np.abs(r).max())
        assert (rp - rm) / (2 * h) == pytest.approx(K[:, j], abs=1e-5 * np.abs(K).max())


def test_follower_load_stiffness_is_the_derivative_of_the_load():
    rng = np.random.default_rng(11)
    b = cantilever3d(1.0, 2, ea=50.0, ga=40.0, gj=2.0, ei2=3.0, ei3=5.0)
    loads = PointLoads3D.build(
        b, [(1.0, 0, 0), (0.5, 0, 0)], ["force", "torque"], ["material", "material"], [(1.0, 2.0, 3.0), (-1, 0.5, 2)]
    )
    q = random_state(b, rng, 0.5)
    _, K, _ = b.residual(loads, q, 1.0)
    h = 1e-6
    for j in range(b.frame_dof):
        d = np.zeros(b.n_dof)
        d[j] = h
        qp, qm = q.copy(), q.copy()
        ek3.advance(qp, d)
        ek3.advance(qm, -d)
        col = (b.residual(loads, qp, 1.0, want_k=False)[0] - b.residual(loads, qm, 1.0, want_k=False)[0]) / (2 * h)
        assert col == pytest.approx(K[:, j], abs=1e-5 * np.abs(K).max())
    # the follower force at the tip is the section-turned load: |f| kept
    tip = b.node_rotations(q)[-1]
    f = np.zeros(b.n_dof)
    ek3.external(q, np.ones(3), loads.node, loads.kind, loads.frame, loads.amp, b.n_nodes, loads.dist, f, K, False)
    assert f[12:15] == pytest.approx(tip @ np.array([1.0, 2.0, 3.0]), abs=1e-12)


def test_gravity_small_deflection_is_the_uniform_load_cantilever():
    # w L^4 / (8 EI) + w L^2 / (2 GA) in the linear limit (load 1e-7 of the bending scale)
    L, ei, ga, w = 2.0, 3.0, 200.0, 1e-7
    b = cantilever3d(L, 32, ea=1e6, ga=ga, gj=1.0, ei2=ei, ei3=10 * ei, rho_a=1.0)
    q = solve_static(b, PointLoads3D.build(b, [], [], [], [], distributed=(0.0, 0.0, -w))).q
    expected = w * L**4 / (8 * ei) + w * L**2 / (2 * ga)
    assert -b.node_positions(q)[-1, 2] == pytest.approx(expected, rel=2e-3)


@pytest.mark.parametrize("key", ["ea", "ga2", "ga3", "gj", "ei2", "ei3"])
@pytest.mark.parametrize("value", [0.0, -1.0])
def test_bad_section_data_names_the_key(key, value):
    args = {"ea": 1.0, "ga": [1.0, 1.0], "gj": 1.0, "ei2": 1.0, "ei3": 1.0}
    if key.startswith("ga"):
        args["ga"][int(key[-1]) - 2] = value
    else:
        args[key] = value
    with pytest.raises(InputError, match=rf"body\.exact\.{key} ="):
        straight3d(1.0, 4, **args)


def test_load_beyond_reach_reports_the_fraction():
    b = cantilever3d(1.0, 4, ea=STIFF, ga=STIFF, gj=1.0, ei2=1.0, ei3=1.0)
    loads = PointLoads3D.build(b, [(1.0, 0, 0)], ["force"], ["inertial"], [(0.0, -1e4, 1e4)])
    with pytest.raises(LoadSteppingError, match="load fraction"):
        solve_static(b, loads, max_iter=3, min_step=0.05)


def test_section_rotations_stay_unit_quaternions():
    _, R = tip3d(10.0, 8, rotation_matrix("123", (0.2, 0.3, 0.4)))
    assert R @ R.T == pytest.approx(np.eye(3), abs=1e-14)


# ---------------------------------------------------------------------------------------------
# the case file: body.exact.dimension = 3
# ---------------------------------------------------------------------------------------------
EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "floating" / "exact_beam_3d_bend.toml"


def bend_config() -> dict:
    cfg = tomllib.loads(EXAMPLE.read_text())
    cfg.pop("domain")
    return cfg


def test_bend_example_through_the_case_file_is_the_mirrored_literature_bend():
    # the example turns from x towards y (the literature from y towards x): the same bend
    # mirrored in the plane x = y, so its tip is the published one with x and y swapped
    cfg = bend_config()
    cfg["paraview"] = {}
    res = run_case(cfg)
    ds = res.dataset.sel(solution="static")
    # the ParaView series is the node polyline of the solution
    assert res.paraview[1].positions == pytest.approx(ds["node_position"].values)
    tip = ds["point_position"].sel(point="tip").values
    assert tip[0] == pytest.approx((100 / np.sqrt(2), 100 - 100 / np.sqrt(2), 0.0), abs=1e-12)
    for k, load in ((1, 300.0), (2, 600.0)):
        _, lit = bend45(load)
        assert tip[k] == pytest.approx(lit[[1, 0, 2]], abs=1e-8)
    assert float(ds["deflection_to_length"].max()) > 0.5
    assert res.dataset.attrs["kinematics"] == "geometrically exact (3-D Simo-Reissner beam)"


@pytest.mark.parametrize(
    ("edit", "key"),
    [
        (("body", "exact", "gj", 0.0), "body.exact.gj"),
        (("body", "exact", "ea", -1.0), "body.exact.ea"),
        (("body", "exact", "ga", 0.0), "body.exact.ga"),
        (("body", "beam", "ei", 0.0), "body.beam.ei"),
        (("body", "beam", "ei_z", -2.0), "body.beam.ei_z"),
        (("body", "exact", "dimension", 4), "body.exact.dimension"),
        (("body", "exact", "analysis", "sideways"), "body.exact.analysis"),
        (("outputs", "tip", [80.0, 0.0, 0.0]), "outputs.tip"),
    ],
)
def test_bad_3d_case_names_the_key(edit, key):
    cfg = bend_config()
    *path, last, value = edit
    node = cfg
    for p in path:
        node = node[p]
    node[last] = value
    with pytest.raises(InputError) as err:
        prepare(cfg)
    assert err.value.field == key


def test_planar_case_refuses_3d_keys():
    cfg = bend_config()
    cfg["body"]["exact"]["dimension"] = 2
    with pytest.raises(InputError) as err:
        prepare(cfg)
    assert err.value.field in ("body.exact.gj", "body.exact.bend_radius")


def test_cli_one_line_errors(tmp_path):
    text = EXAMPLE.read_text()
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace("gj = 833333.3333333334", "gj = 0.0"))
    res = CliRunner().invoke(app, ["floating", "simulate", str(bad), "--out", str(tmp_path / "o"), "--no-figures"])
    assert res.exit_code == 2
    assert "body.exact.gj" in res.output and len(res.output.strip().splitlines()) == 1
    # a load far past what 8 elements and the step budget can follow: exit 1, the fraction named
    far = tmp_path / "far.toml"
    far.write_text(text.replace("vector = [0.0, 0.0, 600.0]", "vector = [0.0, 0.0, 6.0e9]"))
    res = CliRunner().invoke(app, ["floating", "simulate", str(far), "--out", str(tmp_path / "p"), "--no-figures"])
    assert res.exit_code == 1, res.output
    assert "load fraction" in res.output and len(res.output.strip().splitlines()) == 1


# ---------------------------------------------------------------------------------------------
# dynamics: Lie-group generalized-alpha
# ---------------------------------------------------------------------------------------------
def tumbling(h, t_end=1.0, rho_inf=1.0, ea=1e4):
    """A free beam thrown spinning about an axis off its principal axes (no loads): 4 elements,
    the section's own frequencies resolved by the steps."""
    n = 4
    piece = straight3d(1.0, n, ea=ea, ga=ea, gj=1.0, ei2=2.0, ei3=1.0, rho_a=1.0, start=(-0.5, 0, 0))
    b = dataclasses.replace(assemble3d([piece], [False]), rho_i=np.tile([0.02, 0.01, 0.01], (n, 1)))
    w = np.array([0.3, 2.0, 0.5])
    v0 = np.zeros(b.n_dof)
    blocks = v0.reshape(-1, 6)
    blocks[:-1, :3] = np.cross(w, b.nodes) + (0.5, 0, 0)
    blocks[:-1, 3:] = w  # material = inertial components at the start (sections along the axes)
    none = PointLoads3D.build(b, [], [], [], [])
    # outputs every 0.1 s: the steps h = 0.02 / 2^k divide them (equal steps)
    return b, simulate_exact3d(b, none, t_end=t_end, dt_out=0.1, time_step=h, rho_inf=rho_inf, v0=v0)


def momenta(b, q, v):
    """Linear and angular momentum (about the origin) of a state."""
    M = b.mass_matrix()
    nb = b.n_nodes
    x = b.node_positions(q)
    p = (M @ v).reshape(-1, 6)[:nb]
    R = b.node_rotations(q)
    spin = np.einsum("bij,bj->bi", R, p[:, 3:])  # R J W: the sections' own angular momentum
    return p[:, :3].sum(axis=0), (np.cross(x, p[:, :3]) + spin).sum(axis=0)


def test_free_beam_keeps_energy_and_momenta():
    # rho_inf = 1 (no numerical damping), every mode resolved (EA L^2 / EI = 100): the energy
    # error is the method's O(h^2)
    errs = []
    for h in (0.02, 0.01):
        b, sol = tumbling(h, t_end=0.3, ea=100.0)
        e = sol.energy[:, 0] + sol.energy[:, 1]
        errs.append(np.abs(e - e[0]).max() / e[0])
        assert np.all(sol.energy[:, 2] == 0.0)
    assert errs[0] < 1e-3 and errs[0] / errs[1] > 3.0, errs
    p0, h0 = momenta(b, sol.q[0], sol.v[0])
    for q, v in zip(sol.q[1:], sol.v[1:], strict=True):
        p, hh = momenta(b, q, v)
        # linear momentum: exactly (the internal forces of an element sum to zero)
        assert p == pytest.approx(p0, abs=1e-12 * np.linalg.norm(p0))
        assert hh == pytest.approx(h0, abs=1e-3 * np.linalg.norm(h0))
    # the motion is large: the beam turned by more than half a radian
    x = b.node_positions(sol.q[-1])
    assert np.linalg.norm(x[-1] - x[0] - (1, 0, 0)) > 0.5


def test_time_step_convergence_is_second_order():
    # rho_inf = 0.5: the unresolved axial and shear modes (EA L^2 / EI = 1e4) damped out; the
    # resolved motion converges at second order
    tips = [tumbling(h, t_end=0.3, rho_inf=0.5)[1].q[-1][28:35] for h in (0.02, 0.01, 0.005)]
    d1, d2 = np.linalg.norm(tips[0] - tips[1]), np.linalg.norm(tips[1] - tips[2])
    assert 1.85 < np.log2(d1 / d2) < 2.2, (d1, d2)


DYNAMIC_CASE = {
    "body": {
        "type": "beam",
        "model": "exact",
        "beam": {"length": 1.0, "rho_a": 1.0, "ei": 1.0, "ei_z": 2.0, "support": "cantilever"},
        "exact": {"dimension": 3, "elements": 4, "analysis": "dynamic", "rho_inf": 1.0},
    },
    "loads": [
        {
            "kind": "force",
            "vector": [0.0, -1.5, 2.0],
            "point": [1.0, 0.0, 0.0],
            "frame": "material",
            "profile": "ramp",
            "duration": 0.5,
        }
    ],
    "solver": {"t_end": 0.5, "dt_out": 0.1},
    "outputs": {"tip": [1.0, 0.0, 0.0]},
}


def test_dynamic_case_balances_the_work_of_a_follower_load():
    # kinetic + strain energy = work of the (non-conservative) follower load, to the O(h^2) of
    # the integrator and of the trapezoidal work (measured 1e-4 of the work at h = 0.05 s)
    cfg = copy.deepcopy(DYNAMIC_CASE)
    cfg["body"]["exact"]["time_step"] = 0.05
    ds = run_case(cfg).dataset.sel(solution="exact")
    work = float(ds["work_of_loads"][-1])
    assert work > 0.1
    assert float(np.abs(ds["energy_balance"]).max()) < 1e-3 * work
    # out of the plane and large: the tip left the x-y plane by 5 % of L or more
    assert abs(float(ds["point_position"].sel(point="tip")[-1, 2])) > 0.05


def test_bend_is_path_independent():
    # the same load reached by other load steps: the interpolation depends on the current
    # rotations only, so the equilibrium is the same (Crisfield & Jelenic 1999)
    b, tip = bend45(600.0)
    loads = PointLoads3D.build(b, [b.nodes[-1]], ["force"], ["inertial"], [(0.0, 0.0, 600.0)])
    other = b.node_positions(solve_static(b, loads, first_step=0.37).q)[-1]
    assert other == pytest.approx(tip, abs=1e-8)


def test_small_loads_follow_linear_theory_for_each_stiffness():
    # torsion T L / GJ; bending out of the plane P L^3 / 3 EI2 + P L / GA3 and in it with EI3,
    # GA2; extension P L / EA (loads 1e-7 of the bending scale: the linear limit)
    L, n = 2.0, 32
    ea, ga2, ga3, gj, ei2, ei3 = 300.0, 40.0, 60.0, 0.7, 2.0, 5.0
    b = cantilever3d(L, n, ea=ea, ga=(ga2, ga3), gj=gj, ei2=ei2, ei3=ei3)
    P = 1e-7

    def tip(kind, vec):
        loads = PointLoads3D.build(b, [(L, 0, 0)], [kind], ["inertial"], [vec])
        q = solve_static(b, loads).q
        return b.node_positions(q)[-1] - (L, 0, 0), q[7 * n + 3 : 7 * n + 7]

    _, e = tip("torque", (P, 0, 0))
    assert 2 * e[1] == pytest.approx(P * L / gj, rel=1e-6)
    u, _ = tip("force", (0, 0, P))
    # the one-point element's bending is P L^3 / 3 EI (1 + 1 / (4 n^2)) (planar test)
    assert u[2] == pytest.approx(P * L**3 / (3 * ei2) + P * L / ga3, rel=5e-4)
    u, _ = tip("force", (0, P, 0))
    assert u[1] == pytest.approx(P * L**3 / (3 * ei3) + P * L / ga2, rel=5e-4)
    u, _ = tip("force", (P, 0, 0))
    assert u[0] == pytest.approx(P * L / ea, rel=1e-6)
