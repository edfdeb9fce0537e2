"""ParaView export: the VTU frames hold the same inertial point positions as the result."""

import xml.etree.ElementTree as ET

import meshio
import numpy as np

from rotaflex.floating import Initial, Load, Settings, run, uniform_beam
from rotaflex.floating.paraview import write_paraview


def test_vtu_series_matches_the_point_motion(tmp_path):
    b = uniform_beam(2.0, 1.0, 10.0, 2)
    res = run(
        body=b,
        loads=[Load(kind="torque", vector=(0.0, 0.0, 1.0), profile="pulse", duration=0.3)],
        initial=Initial(velocity=(0.1, 0.0, 0.0)),
        solver=Settings(method="full", t_end=1.0, dt_out=0.1),
        outputs={"tip": (1.0, 0.0, 0.0)},
    )
    pvd = write_paraview(res, b, tmp_path, every=2)
    files = [d.attrib for d in ET.parse(pvd).getroot().iter("DataSet")]
    assert [float(f["timestep"]) for f in files] == [0.0, 0.2, 0.4, 0.6, 0.8, 1.0]
    last = meshio.read(tmp_path / files[-1]["file"])
    tip = res.dataset["point_position"].sel(solution="full", point="tip").values[-1]
    k = int(np.argmax(b.points[:, 0]))  # the Gauss point nearest the tip
    Phi, _ = b.shape_fn(b.points[k : k + 1])
    # the outermost Gauss point sits just inside the tip; compare with the body-frame offset
    rel = last.points[k] - tip
    A = res.dataset["rotation_matrix"].sel(solution="full").values[-1]
    q = res.dataset["modal_displacement"].sel(solution="full").values[-1]
    Phi_tip, _ = b.shape_fn([[1.0, 0.0, 0.0]])
    expect = A @ (b.points[k] + Phi[0] @ q - np.array([1.0, 0.0, 0.0]) - Phi_tip[0] @ q)
    np.testing.assert_allclose(rel, expect, atol=1e-12)
    assert last.cells[0].type == "line" and "displacement" in last.point_data


CASE = """
domain = "floating"
[body]
type = "beam"
[body.beam]
length = 2.0
rho_a = 1.0
ei = 10.0
n_modes = 2
[[loads]]
kind = "torque"
vector = [0.0, 0.0, 1.0]
profile = "pulse"
duration = 0.3
[solver]
method = "both"
t_end = 0.5
dt_out = 0.1
[paraview]
every = 2
"""


def test_cli_writes_the_paraview_series_into_the_result_directory(tmp_path):
    # [paraview] in the case file: rotaflex floating simulate writes <out>/paraview/full.pvd and
    # one .vtu per kept output time (0, 0.2, 0.4 s) next to result.nc, readable by meshio, the
    # points equal to the library's write_paraview
    from typer.testing import CliRunner

    from rotaflex.cli import app
    from rotaflex.core.config import load_toml
    from rotaflex.core.result import load_result
    from rotaflex.floating.case import build_body, prepare

    (tmp_path / "c.toml").write_text(CASE)
    out = tmp_path / "out"
    proc = CliRunner().invoke(
        app, ["floating", "simulate", str(tmp_path / "c.toml"), "--out", str(out), "--no-figures"]
    )
    assert proc.exit_code == 0, proc.output
    pvd = out / "paraview" / "full.pvd"
    files = [d.attrib for d in ET.parse(pvd).getroot().iter("DataSet")]
    assert [float(f["timestep"]) for f in files] == [0.0, 0.2, 0.4]
    assert (out / "result.nc").is_file() and len(list((out / "paraview").glob("*.vtu"))) == 3
    last = meshio.read(out / "paraview" / files[-1]["file"])
    assert last.cells[0].type == "line" and last.point_data["displacement"].shape == last.points.shape
    cfg = load_toml(tmp_path / "c.toml")
    cfg.pop("domain")
    body = build_body(prepare(cfg)[0].body)
    lib = write_paraview(load_result(out / "result.nc"), body, tmp_path / "lib", every=2)
    ref = meshio.read(lib.parent / [d.attrib for d in ET.parse(lib).getroot().iter("DataSet")][-1]["file"])
    np.testing.assert_allclose(last.points, ref.points, atol=1e-12)
    # a solution that is not computed is refused before anything runs
    (tmp_path / "p.toml").write_text(CASE.replace("every = 2", 'solution = "prescribed"'))
    proc = CliRunner().invoke(app, ["floating", "simulate", str(tmp_path / "p.toml"), "--out", str(tmp_path / "o2")])
    assert proc.exit_code == 2 and "paraview.solution = 'prescribed'" in proc.output
