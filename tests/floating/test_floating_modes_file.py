"""Modes and mass data from .npz files: round trip, load checks with named fields."""

import numpy as np
import pytest

from rotaflex.core.errors import InputError
from rotaflex.floating.beam import uniform_beam
from rotaflex.floating.body import integrals
from rotaflex.floating.case import run_case
from rotaflex.floating.modes_file import load_modes, save_modes


def test_round_trip_reproduces_the_body_integrals_and_motion(tmp_path):
    # section inertia of a 5 cm solid section, as nodal rotary inertias in the file
    r = 0.05
    b = uniform_beam(2.0, 1.0, 10.0, 3, section_radius=r)
    path = tmp_path / "beam.npz"
    save_modes(path, b)
    with np.load(path) as z:
        d = dict(z)
    d["rotary_inertias"] = np.outer(b.masses * r**2, [0.5, 0.25, 0.25])
    np.savez(path, **d)
    fb = load_modes(path)
    np.testing.assert_allclose(integrals(fb)["M"], integrals(b)["M"], atol=1e-12)
    cfg = {
        "body": {"type": "file", "file": {"path": str(path)}},
        "loads": [
            {
                "kind": "torque",
                "vector": [0.0, 0.0, 1.0],
                "point": b.points[40].tolist(),
                "profile": "pulse",
                "duration": 0.5,
            }
        ],
        # the file carries no geometric stiffness: compare with it off on both sides
        "solver": {"method": "full", "t_end": 1.0, "dt_out": 0.1, "geometric_stiffness": False},
    }
    r_file = run_case(cfg)
    cfg["body"] = {"type": "beam", "beam": {"length": 2.0, "rho_a": 1.0, "ei": 10.0, "n_modes": 3, "section_radius": r}}
    r_beam = run_case(cfg)
    np.testing.assert_allclose(
        r_file.dataset["modal_displacement"].values, r_beam.dataset["modal_displacement"].values, atol=1e-12
    )


@pytest.mark.parametrize(
    "change, field",
    [
        ("masses_neg", "body.file.masses[4]"),
        ("scaled", "body.file.shapes"),
        ("rigid", "body.file.shapes[0]"),
        ("zero_freq", "body.file.frequencies[0]"),
        ("bad_shape", "body.file.positions"),
    ],
)
def test_bad_files_are_refused_with_the_array_named(tmp_path, change, field):
    b = uniform_beam(2.0, 1.0, 10.0, 3)
    save_modes(tmp_path / "ok.npz", b)
    with np.load(tmp_path / "ok.npz") as z:
        d = dict(z)
    if change == "masses_neg":
        d["masses"] = d["masses"].copy()
        d["masses"][4] = -1.0
    elif change == "scaled":
        d["shapes"] = 1.1 * d["shapes"]
    elif change == "rigid":  # a mode with a rigid translation mixed in (not mass-orthogonal)
        s = d["shapes"].copy()
        s[0, :, 1] += 0.05
        d["shapes"] = s
    elif change == "zero_freq":
        d["frequencies"] = np.r_[0.0, d["frequencies"][1:]]
    else:
        d["positions"] = d["positions"][:-1]
    np.savez(tmp_path / "bad.npz", **d)
    with pytest.raises(InputError) as exc:
        load_modes(tmp_path / "bad.npz")
    assert exc.value.field == field, str(exc.value)
    with pytest.raises(InputError, match="body.file.path"):
        load_modes(tmp_path / "missing.npz")


def test_relative_file_path_is_read_from_the_case_files_directory(tmp_path, monkeypatch):
    from typer.testing import CliRunner

    from rotaflex.cli import app
    from rotaflex.floating import run

    case_dir = tmp_path / "case"
    case_dir.mkdir()
    b = uniform_beam(2.0, 1.0, 10.0, 2)
    save_modes(case_dir / "beam.npz", b)
    with np.load(case_dir / "beam.npz") as z:
        d = dict(z)
    d["rotary_inertias"] = np.outer(b.masses * 0.05**2, [0.5, 0.25, 0.25])  # a 5 cm section
    np.savez(case_dir / "beam.npz", **d)
    toml = case_dir / "file_case.toml"
    toml.write_text(
        'domain = "floating"\n[body]\ntype = "file"\n[body.file]\npath = "beam.npz"\n'
        '[solver]\nmethod = "full"\nt_end = 0.2\ndt_out = 0.1\ngeometric_stiffness = false\n'
    )
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)  # no beam.npz here: only the case file's directory has it
    assert run(toml).status == "success"
    res = CliRunner().invoke(app, ["floating", "simulate", str(toml), "--out", str(tmp_path / "o"), "--quiet"])
    assert res.exit_code == 0, res.output
    # an absolute path is kept as given
    from rotaflex.floating.case import resolve_paths

    cfg = {"body": {"type": "file", "file": {"path": str(case_dir / "beam.npz")}}}
    assert resolve_paths(cfg, elsewhere) == cfg


def test_csv_layout_round_trip_and_named_errors(tmp_path):
    b = uniform_beam(2.0, 1.0, 10.0, 3)
    save_modes(tmp_path / "b.npz", b)
    save_modes(tmp_path / "b.csv", b)
    text = (tmp_path / "b.csv").read_text()
    assert text.startswith("# frequencies: ") and "\nx,y,z,mass,phi1_x," in text
    fn, fc = load_modes(tmp_path / "b.npz", frame="attached"), load_modes(tmp_path / "b.csv", frame="attached")
    for k in ("M", "J"):
        np.testing.assert_allclose(integrals(fc)[k], integrals(fn)[k], rtol=1e-14, atol=1e-14)
    np.testing.assert_allclose(fc.stiffness, b.stiffness, rtol=1e-14)
    # a column missing, a mode not mass-normalised: errors name the field
    lines = text.splitlines()
    bad = tmp_path / "bad.csv"
    bad.write_text("\n".join([lines[0], lines[1].replace("phi2_y", "phi2_q")] + lines[2:]))
    with pytest.raises(InputError, match=r"body\.file\.shapes\[1\]"):
        load_modes(bad)
    rows = np.loadtxt(tmp_path / "b.csv", delimiter=",", skiprows=2)
    rows[:, 4:7] *= 2.0  # mode 1 twice too large
    np.savetxt(bad, rows, delimiter=",", header=lines[0] + "\n" + lines[1], comments="")
    with pytest.raises(InputError, match=r"body\.file\.shapes"):
        load_modes(bad)
    bad.write_text("\n".join(lines[1:]))
    with pytest.raises(InputError, match=r"body\.file\.frequencies"):
        load_modes(bad)


def test_hdf5_layout_round_trip_and_named_errors(tmp_path):
    import h5py

    b = uniform_beam(2.0, 1.0, 10.0, 3)
    save_modes(tmp_path / "b.npz", b)
    save_modes(tmp_path / "b.h5", b)
    with h5py.File(tmp_path / "b.h5", "r") as f, np.load(tmp_path / "b.npz") as z:
        assert sorted(f.keys()) == sorted(z.files)
        for k in z.files:
            np.testing.assert_array_equal(f[k][()], z[k])  # the same arrays, bit for bit
    fn, fh = load_modes(tmp_path / "b.npz"), load_modes(tmp_path / "b.h5")
    for k in ("M", "J"):
        np.testing.assert_array_equal(integrals(fh)[k], integrals(fn)[k])
    np.testing.assert_array_equal(fh.stiffness, fn.stiffness)
    # the load-time checks apply: a mode not mass-normalised, a group instead of a dataset
    with h5py.File(tmp_path / "bad.h5", "w") as f, np.load(tmp_path / "b.npz") as z:
        for k in z.files:
            f.create_dataset(k, data=1.1 * z[k] if k == "shapes" else z[k])
    with pytest.raises(InputError) as exc:
        load_modes(tmp_path / "bad.h5")
    assert exc.value.field == "body.file.shapes"
    with h5py.File(tmp_path / "grp.h5", "w") as f:
        f.create_group("masses")
    with pytest.raises(InputError, match=r"body\.file\.masses"):
        load_modes(tmp_path / "grp.h5")
    (tmp_path / "junk.h5").write_bytes(b"not hdf5")
    with pytest.raises(InputError, match=r"body\.file\.path"):
        load_modes(tmp_path / "junk.h5")


def _lumped_fe_export(n_el=12, length=2.0, rho_a=1.0, ei=10.0, j_node=2e-3, n_modes=4):
    """A planar free-free Euler-Bernoulli beam as an FE program exports it: lumped nodal masses
    and rotary inertias (J = (2j, j, j)), modes normalised with the full lumped mass matrix."""
    from scipy.linalg import eigh

    nn, h = n_el + 1, length / n_el
    k = ei / h**3 * np.array([[12, 6 * h, -12, 6 * h], [6 * h, 4 * h * h, -6 * h, 2 * h * h],
                              [-12, -6 * h, 12, -6 * h], [6 * h, 2 * h * h, -6 * h, 4 * h * h]])  # fmt: skip
    K = np.zeros((2 * nn, 2 * nn))
    for e in range(n_el):
        K[2 * e : 2 * e + 4, 2 * e : 2 * e + 4] += k
    m = np.full(nn, rho_a * h)
    m[[0, -1]] *= 0.5
    jz = np.full(nn, j_node)
    w2, V = eigh(K, np.diag(np.column_stack([m, jz]).ravel()))
    V, w2 = V[:, 2 : 2 + n_modes], w2[2 : 2 + n_modes]  # drop the two planar rigid modes
    x = np.linspace(-length / 2, length / 2, nn)
    shapes = np.zeros((n_modes, nn, 3))
    rot = np.zeros((n_modes, nn, 3))
    shapes[:, :, 1] = V[0::2].T
    rot[:, :, 2] = V[1::2].T
    return {
        "positions": np.column_stack([x, 0 * x, 0 * x]),
        "masses": m,
        "shapes": shapes,
        "frequencies": np.sqrt(w2),
        "rotation_shapes": rot,
        "rotary_inertias": np.column_stack([2 * jz, jz, jz]),
    }


def test_fe_export_normalised_with_the_full_mass_matrix(tmp_path):
    """Modes normalised with m and J (as FE programs export them) load; the nodal rotary inertia
    is in the modal mass, the rigid-body inertia and the dynamics."""
    d = _lumped_fe_export()
    path = tmp_path / "fe.npz"
    np.savez(path, **d)
    b = load_modes(path)
    ig = integrals(b)
    np.testing.assert_allclose(np.einsum("k,kai,kaj->ij", b.masses, b.shapes, b.shapes), np.eye(4), atol=1e-12)
    x, m, J = d["positions"][:, 0], d["masses"], d["rotary_inertias"]
    np.testing.assert_allclose(np.diag(ig["J"]), [J[:, 0].sum(), m @ x**2 + J[:, 1].sum(), m @ x**2 + J[:, 2].sum()],
                               rtol=1e-12)  # fmt: skip
    assert ig["M"][0, 0] == pytest.approx(m.sum(), rel=1e-14)
    # a torque pulse about z: the rigid rate afterwards is the impulse over I_zz (rotary part 0.9 %)
    impulse = 0.5 * 2.0  # rectangular pulse, 0.5 N m for 2 s
    cfg = {
        "body": {"type": "file", "file": {"path": str(path)}},
        "loads": [
            {"kind": "torque", "vector": [0.0, 0.0, 0.5], "point": [0.0, 0.0, 0.0], "profile": "pulse", "duration": 2.0}
        ],  # fmt: skip
        "solver": {"method": "full", "t_end": 3.0, "dt_out": 0.01, "geometric_stiffness": False},
    }
    res = run_case(cfg).dataset
    wz = res["angular_velocity"].isel(solution=0).values[-100:, 2].mean()
    izz = m @ x**2 + J[:, 2].sum()
    assert J[:, 2].sum() / izz > 5e-3
    assert wz == pytest.approx(impulse / izz, rel=5e-4)
    # the same data normalised with the translational masses is refused: neither holds
    bad = dict(d, shapes=d["shapes"] * 1.01)
    np.savez(tmp_path / "bad.npz", **bad)
    with pytest.raises(InputError, match="body.file.shapes"):
        load_modes(tmp_path / "bad.npz")


def test_forces_on_a_file_body_are_said_not_to_stiffen_it(tmp_path):
    d = _lumped_fe_export()
    np.savez(tmp_path / "fe.npz", **d)
    force = {"kind": "force", "vector": [-1.0, 0.0, 0.0], "point": [1.0, 0.0, 0.0], "profile": "constant"}
    cfg = {
        "body": {"type": "file", "file": {"path": str(tmp_path / "fe.npz")}},
        "loads": [force],
        "solver": {"method": "full", "t_end": 0.1, "dt_out": 0.05},
    }
    res = run_case(cfg)
    assert "forces do not stiffen this body" in res.dataset.attrs["message"]
