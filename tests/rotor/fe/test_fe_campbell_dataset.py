"""The one Campbell dataset and figure (rotor/fe/results.campbell_dataset, rotor/fe/figures.
campbell_figure), FE rotor side (issue 33, "each analysis exists once"): what
``rotaflex rotor campbell`` stores and draws are the eigenvalues of the assembled matrices.

Reference: each stored eigenvalue lambda (rebuilt from the stored damped frequency and
damping ratio, and again from the damped frequency and log decrement) makes the quadratic
pencil ``P(lambda) = lambda^2 M + lambda D + K`` of ``Rotor.MKC`` and ``Rotor.G`` singular: its
normalised backward error ``sigma_min(P) / (|lambda|^2 |M| + |lambda| |D| + |K|)`` is at
round-off (no eigen-solver involved). That the tracks are the lowest modes is checked against
the generalised eigenproblem ``[[0, I], [-K, -D]] x = lambda [[I, 0], [0, M]] x`` by
``scipy.linalg.eig`` (no inverse of M, no selection, no tracking).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from eigen_checks import backward_error, lowest_oscillatory

from rotaflex.core.config import load_toml
from rotaflex.rotor.fe.case_config import parse
from rotaflex.rotor.fe.verbs_modal import run_campbell

ROOT = Path(__file__).resolve().parents[3]
EXAMPLE = ROOT / "examples" / "rotor" / "fe_friswell_5_9_1.toml"
HZ = 1 / (2 * np.pi)
#: backward error of a stored eigenvalue: measured at most 2.5e-15 on this rotor (6e-16 at the
#: critical speeds); an eigenvalue moved by 1e-9 relative gives 5e-13 to 1.5e-12, so this bound
#: fails on any error above ~2e-10 relative (a wrong variable, a mix-up of modes or speeds)
BACKWARD = 1e-13
#: the generalised solve (no balancing) is itself accurate to 3e-9 relative here (measured,
#: against the stored values); neighbouring modes are >= 1e-2 apart
PENCIL = 1e-6


def pencil(rotor, speed: float):
    """(M, D, K) at ``speed`` [rad/s]."""
    M, K, C = (x[0] for x in rotor.MKC(np.array([speed])))
    return M, C + speed * rotor.G, K


@pytest.fixture(scope="module")
def run():
    """The example's ``rotor campbell`` on 5 speeds (its 1X and 2X lines), in process."""
    cfg = load_toml(EXAMPLE)
    cfg["campbell"] = {**cfg["campbell"], "n_speeds": 5}
    return cfg, run_campbell(cfg)


def test_rotor_campbell_dataset_holds_the_eigenvalues_of_the_matrices(run):
    """Every tracked damped frequency, |lambda|, damping ratio and log decrement at every speed
    is an eigenvalue of the assembled pencil; the first speed's tracks are its lowest
    oscillatory modes; the lines are the harmonics; each critical speed lies on its line, where
    the pencil has an eigenvalue of damped frequency h x speed."""
    cfg, res = run
    ds = res.dataset
    rotor, _ = parse(cfg, "campbell")
    wd, z, ld = (ds[k].values for k in ("damped_frequency", "damping_ratio", "log_dec"))
    from_zeta = -z * ds["natural_frequency"].values + 1j * wd
    from_logdec = -ld * wd / (2 * np.pi) + 1j * wd
    worst = 0.0
    for s, w in enumerate(ds["speed"].values):
        M, D, K = pencil(rotor, w)
        worst = max(worst, backward_error(np.concatenate([from_zeta[s], from_logdec[s]]), M, D, K))
        if s == 0:
            np.testing.assert_allclose(np.sort(wd[0]), lowest_oscillatory(M, D, K, wd.shape[1]), rtol=PENCIL)
    assert worst < BACKWARD, worst
    assert list(ds["line"].values) == ["1X", "2X"]
    np.testing.assert_array_equal(ds["line_factor"].values, [1.0, 2.0])
    crit = json.loads(ds.attrs["critical_speeds"])
    assert crit
    for c in crit:
        assert c["frequency"] == c["harmonic"] * c["speed"]
        # the direct solve's root is found to 1e-12 in speed (rotor/fe/critical.py): an
        # eigenvalue of damped frequency h x speed, its real part the stored log decrement
        lam = -c["log_dec"] * c["frequency"] / (2 * np.pi) + 1j * c["frequency"]
        assert backward_error(lam, *pencil(rotor, c["speed"])) < BACKWARD


def test_rotor_campbell_figure_draws_the_dataset(run):
    """campbell.png's data: mode lines (forward and backward halves) are the damped frequencies
    [Hz], the log-decrement panel the log decrements, one line each at 1X and 2X the speed [Hz]."""
    _, res = run
    ds = res.dataset
    fig = res.plot_campbell()
    ax, al = fig.axes[:2]
    rpm = ds["speed_rpm"].values
    f = ds["damped_frequency"].values * HZ
    lines = [ln.get_xydata() for ln in ax.get_lines()]
    for k in range(ds.sizes["mode"]):
        fw, bw = lines[2 * k][:, 1], lines[2 * k + 1][:, 1]  # drawn as forward, backward pairs
        np.testing.assert_array_equal(np.where(np.isnan(fw), bw, fw), f[:, k])
        np.testing.assert_array_equal(lines[2 * k][:, 0], rpm)
        ld = [x.get_xydata()[:, 1] for x in al.get_lines()[2 * k : 2 * k + 2]]
        np.testing.assert_array_equal(np.where(np.isnan(ld[0]), ld[1], ld[0]), ds["log_dec"].values[:, k])
    for h in (1, 2):
        drawn = [x for x in lines if x.shape[0] == rpm.size and np.allclose(x[:, 1], h * ds["speed"].values * HZ)]
        assert len(drawn) == 1, h
