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
