"""Critical-speed whirl labels: the direct solve and the Campbell diagram use one rule
(:func:`critical_whirl` on the forward fraction), planar modes count as forward, and modes
that become oscillatory inside the speed range are tracked from that speed."""

import numpy as np
import pytest

from rotaflex.rotor.fe.case import run_campbell
from rotaflex.rotor.fe.critical import critical_speeds
from rotaflex.rotor.fe.modal import PLANAR_BAND, TRACK_ZETA, campbell, critical_whirl
from rotaflex.rotor.fe.model import Bearing, Disk, Pedestal, Rotor, Shaft

RPM = np.pi / 30
SPEEDS = np.linspace(0, 12000, 60) * RPM


def _rotor(k=(1e6, 8e6), c=50.0, ip=0.09):
    """A flexible shaft with a disk at a third of the span on anisotropic bearings."""
    return Rotor(
        shaft=(Shaft(outer_diameter=0.04, length=1.0, elements=8),),
        disk=(Disk(node=3, mass=10.0, Id=0.05, Ip=ip),),
        bearing=tuple(Bearing(node=n, kxx=k[0], kyy=k[1], cxx=c, cyy=c) for n in (0, 8)),
    )


def _pairs(rotor):
    data = campbell(rotor, SPEEDS, 6)
    direct = critical_speeds(rotor, SPEEDS, 6, data=data)
    assert len(direct) == len(data.critical) >= 3
    for d, i in zip(direct, data.critical, strict=True):
        assert d["mode"] == i["mode"] and d["speed"] == pytest.approx(i["speed"], rel=2e-3)
    return direct, data.critical


def test_direct_and_campbell_labels_agree_on_mixed_modes():
    """Anisotropic damped bearings: some modes whirl forward at some nodes and backward at
    others ("mixed" by the orbits), which the direct solve used to report as the label, leaving
    no forward critical speed; now both solves label by the forward fraction."""
    direct, interp = _pairs(_rotor())
    assert [d["whirl"] for d in direct] == [i["whirl"] for i in interp]
    assert any(d["shape_whirl"] == "mixed" for d in direct)  # the case of the issue
    for d in direct:
        assert d["whirl"] == ("forward" if d["forward_fraction"] >= 0.5 - PLANAR_BAND else "backward")
    assert {d["whirl"] for d in direct} == {"forward", "backward"}


def test_planar_modes_are_forward():
    """No gyroscopic disk, undamped anisotropic bearings: the modes are nearly straight lines in
    x or y (forward fraction 0.5 up to the shaft's own small polar inertia: 0.4996 .. 0.5008),
    so both solves call every crossing forward: an unbalance (a forward force) excites a line."""
    direct, interp = _pairs(_rotor(c=0.0, ip=0.0))
    assert all(abs(d["forward_fraction"] - 0.5) < 1e-3 for d in direct)  # flat: minor / major axis < 1e-3
    assert any(d["forward_fraction"] < 0.5 for d in direct)  # slightly backward, within the band
    assert [d["whirl"] for d in direct] == [i["whirl"] for i in interp] == ["forward"] * len(direct)
    assert critical_whirl(0.5) == critical_whirl(0.5 - 0.9 * PLANAR_BAND) == "forward"
    assert critical_whirl(0.5 - 1.1 * PLANAR_BAND) == "backward"


def test_campbell_summary_lists_forward_criticals_of_mixed_modes():
    cfg = {
        "shaft": [{"outer_diameter": 0.04, "length": 1.0, "elements": 8}],
        "disk": [{"node": 3, "mass": 10.0, "Id": 0.05, "Ip": 0.09}],
        "bearing": {n: {"node": i, "kxx": 1e6, "kyy": 8e6, "cxx": 50.0, "cyy": 50.0} for n, i in (("a", 0), ("b", 8))},
        "campbell": {"speed_rpm": [0, 12000], "n_speeds": 60, "n_modes": 6},
    }
    res = run_campbell(cfg)
    msg = res.dataset.attrs["message"] if "message" in res.dataset.attrs else res.message
    assert "forward 1X critical speeds [rpm]: none" not in msg and "2776" in msg


def test_mode_becoming_oscillatory_is_tracked_from_that_speed():
    """A rigid rotor (m1) on two bearings (k1, damping c1 falling with speed) on two pedestals
    (m2, k2, c2): its bounce motion is the two-mass chain of test_pedestal, whose quartic has
    one complex pair while c1 is large and two once the relative motion stops being overdamped.
    The new pair must get tracks that start at the first speed where the quartic has it with a
    damping ratio below TRACK_ZETA, and follow its root; before that speed those tracks are
    empty (NaN)."""
    k1, m2, k2, c2 = 2e7, 40.0, 5e7, 2e3
    c_tab = (100e3, 5e3)
    ped = Pedestal(mass=m2, kxx=k2, kyy=k2, cxx=c2, cyy=c2)
    tab = dict(kxx=k1, kyy=k1, cxx=c_tab, cyy=c_tab, speed_rpm=(0.0, 6000.0), pedestal=ped)
    rotor = Rotor(
        shaft=(Shaft(outer_diameter=0.1, length=0.8, elements=4, rigid=True),),
        bearing=(Bearing(node=0, **tab), Bearing(node=4, **tab)),
    )
    speeds = np.linspace(0, 6000, 61) * RPM
    wd = campbell(rotor, speeds, 4).modes.wd
    roots = []
    for w in speeds:
        c1 = c_tab[0] + (c_tab[1] - c_tab[0]) * w / speeds[-1]
        a = np.polymul([rotor.mass, 2 * c1, 2 * k1], [2 * m2, 2 * (c1 + c2), 2 * (k1 + k2)])
        q = np.roots(np.polysub(a, np.polymul([2 * c1, 2 * k1], [2 * c1, 2 * k1])))
        roots.append(np.sort(q[(q.imag > 1e-6 * abs(q)) & (-q.real / abs(q) < TRACK_ZETA)].imag))
    first = next(s for s, r in enumerate(roots) if r.size == 2)
    assert 0 < first < speeds.size - 1  # the pair appears inside the range
    new = [k for k in range(wd.shape[1]) if np.isfinite(wd[:, k]).argmax() == first]
    assert len(new) == 2  # x and y bounce
    assert np.all(np.isnan(wd[:first, new]))
    np.testing.assert_allclose(wd[first, new], roots[first][0], rtol=1e-5)  # rigid-section penalty
    for s in range(first, speeds.size):  # both roots are followed by some track from there on
        for r in roots[s]:
            assert np.nanmin(np.abs(wd[s] - r)) < 1e-5 * r
