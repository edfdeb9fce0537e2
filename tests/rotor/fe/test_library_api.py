"""The FE rotor library (rotaflex.rotor.fe.study): a rotor built in Python gives the command
line's results, speeds are explicit in their names, results plot themselves with the CLI's
figures, and 0.5X crossings are labelled 0.5 (issue 37, "The library")."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from rotaflex.cli import app
from rotaflex.core.errors import InputError
from rotaflex.rotor.fe import Bearing, Disk, Rotor, Shaft, campbell, modal
from rotaflex.rotor.fe.model import PointMass
from rotaflex.rotor.fe.study import (
    campbell_diagram,
    critical_speed_map,
    frf,
    modes,
    stability,
    static_state,
    transient_response,
    unbalance_response_study,
)

ROOT = Path(__file__).resolve().parents[3]
EXAMPLE = ROOT / "examples" / "rotor" / "fe_friswell_5_9_1.toml"
RAD_PER_RPM = np.pi / 30


def friswell_rotor() -> Rotor:
    """examples/rotor/fe_friswell_5_9_1.toml, written in Python."""
    disk = dict(width=0.07, inner_diameter=0.05)
    brg = dict(kxx=1e6, kyy=1e6, cxx=3e3, cyy=3e3)
    return Rotor(
        shaft=(Shaft(outer_diameter=0.05, length=1.5, elements=6, material="steel"),),
        disk=(Disk(position=0.5, outer_diameter=0.28, **disk), Disk(position=1.0, outer_diameter=0.35, **disk)),
        bearing=(Bearing(node=0, name="left", **brg), Bearing(position=1.5, name="right", **brg)),
    )


def test_half_x_crossings_are_labelled_half(tmp_path):
    """campbell(...).critical gave int(0.5) = 0; the 0.5X crossing is where the tracked mode's
    damped frequency is half the spin speed (checked with modal() at that speed)."""
    rotor = friswell_rotor()
    speeds = np.linspace(0, 4000, 81) * RAD_PER_RPM
    c = campbell(rotor, speeds, 6, harmonics=(0.5, 1))
    half = [cr for cr in c.critical if cr["harmonic"] == 0.5]
    assert half and {cr["harmonic"] for cr in c.critical} == {0.5, 1.0}
    for cr in half:
        wd = modal(rotor, cr["speed"], 6).wd[0]
        assert np.min(np.abs(wd - 0.5 * cr["speed"])) < 5e-3 * cr["speed"]  # linear interpolation on 50 rpm
    lib = campbell_diagram(rotor, speed_rpm=(0, 4000), n_speeds=81, n_modes=6, harmonics=(0.5, 1))
    assert sorted({cr["harmonic"] for cr in lib.critical}) == [0.5, 1.0]


def test_python_rotor_gives_the_cli_results(tmp_path):
    """The same rotor from TOML through the CLI and from Python through the library: the same
    critical speeds and peaks (two routes through the one runner, equal to the last bit)."""
    r = CliRunner().invoke(app, ["rotor", "campbell", str(EXAMPLE), "--out", str(tmp_path / "c"), "-q", "--no-figures"])
    assert r.exit_code == 0, r.output
    cli = json.loads((tmp_path / "c" / "summary.json").read_text())
    lib = campbell_diagram(friswell_rotor(), speed_rpm=(0, 4000), n_speeds=50, n_modes=6, harmonics=(1, 2))
    s = lib.summary()
    keys = [k for k in cli if k.startswith("critical_") and k.endswith("_rpm")]
    assert keys and all(s[k]["value"] == cli[k]["value"] for k in keys)
    r = CliRunner().invoke(
        app, ["rotor", "unbalance", str(EXAMPLE), "--out", str(tmp_path / "u"), "-q", "--no-figures"]
    )
    cli = json.loads((tmp_path / "u" / "summary.json").read_text())
    ub = unbalance_response_study(
        friswell_rotor(),
        [{"position": 1.0, "magnitude": 1e-4, "phase_deg": 0.0}],
        speed_rpm=(0, 4000),
        n_speeds=500,
        probes=(2, 4),
    )
    assert ub.summary()["peak_0_speed_rpm"]["value"] == cli["peak_0_speed_rpm"]["value"]
    assert ub.summary()["peak_0_probe"]["value"] == cli["peak_0_probe"]["value"]


def test_speeds_are_explicit_in_their_names():
    rotor = friswell_rotor()
    a = modes(rotor, speed_rpm=3000.0, n_modes=4)
    b = modes(rotor, speed=3000.0 * RAD_PER_RPM, n_modes=4)
    np.testing.assert_allclose(a.dataset["damped_frequency"], b.dataset["damped_frequency"], rtol=1e-12)
    with pytest.raises(InputError, match="one of speed_rpm"):
        modes(rotor, speed_rpm=3000.0, speed=314.0)
    with pytest.raises(InputError, match="one of speed_rpm"):
        modes(rotor)
    with pytest.raises(TypeError):
        modes(rotor, 3000.0)  # a bare number: no unit, refused
    with pytest.raises(InputError, match="start, stop"):
        campbell_diagram(rotor, speed_rpm=3000.0)


def _overlap(a, b) -> bool:
    return a.x0 < b.x1 and b.x0 < a.x1 and a.y0 < b.y1 and b.y0 < a.y1


def test_plot_methods_are_the_cli_figures_and_legends_hide_no_data(tmp_path):
    rotor = friswell_rotor()
    c = campbell_diagram(rotor, speed_rpm=(0, 4000), n_speeds=30, n_modes=4, operating_range_rpm=(2500, 3500))
    one, cli = c.plot_campbell(), c.plot()["campbell"]
    la, lb = one.axes[0].get_lines(), cli.axes[0].get_lines()
    assert len(la) == len(lb)
    assert all(np.array_equal(x.get_xydata(), y.get_xydata(), equal_nan=True) for x, y in zip(la, lb, strict=True))
    assert c.plot_campbell(frequency_limit_hz=30).axes[0].get_ylim()[1] == pytest.approx(30)
    ub = unbalance_response_study(
        rotor,
        [{"position": 1.0, "magnitude": 1e-4}],
        speed_rpm=(0, 4000),
        n_speeds=200,
        operating_range_rpm=(2500, 3500),
    )
    m = modes(rotor, speed_rpm=3000.0, n_modes=4)
    for fig in (one, ub.plot_bode(), ub.plot_orbit(), m.plot_mode(1)):
        fig.canvas.draw()
        r = fig.canvas.get_renderer()
        for leg in fig.legends:  # figure legends sit outside every axes
            for ax in fig.axes:
                assert not _overlap(leg.get_window_extent(r), ax.get_window_extent(r))
        for ax in fig.axes:  # an axes legend covers none of its data points
            leg = ax.get_legend()
            if leg is not None:
                box = leg.get_window_extent(r)
                for line in ax.get_lines():
                    xy = line.get_xydata()
                    d = ax.transData.transform(xy[np.all(np.isfinite(xy), 1)])
                    inside = (d[:, 0] > box.x0) & (d[:, 0] < box.x1) & (d[:, 1] > box.y0) & (d[:, 1] < box.y1)
                    assert not inside.any(), (fig, line.get_label())
    assert "[\u00b5m]" in ub.plot_orbit().axes[0].get_xlabel()
    assert "mode 1" in m.plot_mode(1).axes[0].get_title()
    with pytest.raises(InputError):
        m.plot_mode(7)


def test_readme_rotor_example_runs(tmp_path, python_json):
    """examples/python/readme_rotor.py builds the README rotor and writes its Campbell and Bode plots."""
    script = ROOT / "examples" / "python" / "readme_rotor.py"
    out = python_json(
        f"""
        import json, runpy, sys
        sys.argv = ["readme_rotor.py", {str(tmp_path)!r}]
        ns = runpy.run_path({str(script)!r}, run_name="__main__")
        print(json.dumps(ns["REPORT"]))
        """
    )
    assert (tmp_path / "campbell.png").exists() and (tmp_path / "bode.png").exists()
    assert out["status"] == "success" and out["critical_rpm"]
    # the static reactions carry the weight (printed to 0.01 N)
    assert sum(out["static_reaction_y_N"]) == pytest.approx(out["mass_kg"] * 9.80665, abs=0.02)
    # stiff bearings raise the first critical above the one on the 1e6 N/m bearings
    assert out["ucs_first_critical_rpm_at_1e9_N_per_m"] > out["critical_rpm"][0]
    assert out["frf_peak_hz"] > 0 and out["level2_log_dec"] > 0 and out["transient_max_displacement_m"] > 0


# --- frf, stability, static_state, critical_speed_map, transient_response -------------------
# A Jeffcott rotor: a 10 kg point mass at midspan of a light (rho = 1 kg/m^3, 2e-5 of the mass),
# shear-stiff (G = 1e20 Pa with kappa = 1: Euler-Bernoulli; Cowper's kappa from E / 2G - 1 would
# give kappa G = 3 E) shaft on two stiff bearings, and a damper to ground at
# the mass (a bearing with only cxx = cyy): per direction m x'' + c x' + k_eq x = F with
# k_eq = (1 / k_s + 1 / (2 k_b))^-1, k_s = 48 E I / L^3 (the cubic beam element is exact at its nodes).
E, D, L, M, KB, ZETA = 2e11, 0.02, 0.6, 10.0, 1e7, 0.1
K_S = 48 * E * (np.pi * D**4 / 64) / L**3
K_EQ = 1 / (1 / K_S + 1 / (2 * KB))
W_N = np.sqrt(K_EQ / M)  # [rad/s]
C = float(2 * ZETA * np.sqrt(K_EQ * M))  # [N s/m]

JEFFCOTT_TOML = f"""
[[shaft]]
outer_diameter = {D}
length = {L}
elements = 4
E = {E}
G = 1e20
shear_coefficient = 1.0
rho = 1.0
[[point_mass]]
node = 2
mass = {M}
[[bearing]]
node = 0
kxx = {KB}
kyy = {KB}
[[bearing]]
node = 4
kxx = {KB}
kyy = {KB}
[[bearing]]
node = 2
kxx = 0.0
kyy = 0.0
cxx = {C!r}
cyy = {C!r}
"""


def jeffcott(damper: bool = True) -> Rotor:
    """JEFFCOTT_TOML in Python (without the damper: the undamped rotor of the critical speed map)."""
    brg = (Bearing(node=0, kxx=KB, kyy=KB), Bearing(node=4, kxx=KB, kyy=KB))
    return Rotor(
        shaft=(Shaft(outer_diameter=D, length=L, elements=4, E=E, G=1e20, shear_coefficient=1.0, rho=1.0),),
        point_mass=(PointMass(node=2, mass=M),),
        bearing=brg + ((Bearing(node=2, kxx=0.0, kyy=0.0, cxx=C, cyy=C),) if damper else ()),
    )


def cli_dataset(tmp_path, verb: str, table: str, toml: str = JEFFCOTT_TOML):
    """The verb's dataset from the command line on the case file ``toml`` + ``table``."""
    import xarray as xr

    case = tmp_path / f"{verb}.toml"
    case.write_text(toml + table)
    out = tmp_path / verb
    r = CliRunner().invoke(app, ["rotor", verb, str(case), "--out", str(out), "-q", "--no-figures"])
    assert r.exit_code == 0, r.output
    with xr.open_dataset(out / "result.nc") as ds:
        return ds.load()


def assert_same_arrays(lib, cli):
    """Every data variable of the library's dataset is in the CLI's, with the same values (to the bit)."""
    assert set(lib.data_vars) == set(cli.data_vars)
    for k in lib.data_vars:
        np.testing.assert_array_equal(lib[k].values, cli[k].values, err_msg=k)


def test_static_state_is_the_cli_and_a_uniform_shaft_hangs_on_half_its_weight_each(tmp_path):
    """Symmetric two-bearing shaft, statically determinate: each bearing carries half the weight
    rho A L g whatever the bearings' stiffness."""
    lib = static_state(jeffcott(damper=False), loads=[{"node": 1, "fy": -50.0}])
    cli = cli_dataset(
        tmp_path, "static", "[[static.load]]\nnode = 1\nfy = -50.0\n", JEFFCOTT_TOML.split("[[bearing]]\nnode = 2")[0]
    )
    assert_same_arrays(lib.dataset, cli)
    shaft = Rotor(
        shaft=(Shaft(outer_diameter=0.05, length=1.0, elements=6, material="steel"),),
        bearing=(Bearing(node=0, kxx=1e8, kyy=1e8), Bearing(node=6, kxx=1e8, kyy=1e8)),
    )
    weight = 7810.0 * np.pi * 0.025**2 * 1.0 * 9.80665  # [N]: steel, rho A L g
    s = static_state(shaft)
    np.testing.assert_allclose(s.dataset["reaction"].sel(axis="y"), [weight / 2, weight / 2], rtol=1e-12)
    np.testing.assert_allclose(s.dataset["reaction"].sel(axis="x"), [0, 0], atol=1e-9 * weight)
    with pytest.raises(InputError, match="static.load"):
        static_state(shaft, loads=[{"node": 99, "fy": 1.0}])
    with pytest.raises(InputError, match="static.load\\[0\\].fz"):
        static_state(shaft, loads=[{"node": 1, "fz": 1.0}])


def test_critical_speed_map_is_the_cli_and_the_jeffcott_closed_form(tmp_path):
    """Critical speed of the Jeffcott rotor = sqrt(k_eq / m), k_eq of the shaft in series with the
    two bearings, at every stiffness of the map."""
    rotor = jeffcott(damper=False)
    lib = critical_speed_map(rotor, stiffness=(1e5, 1e9), n_points=5, n_modes=1)
    toml = JEFFCOTT_TOML.split("[[bearing]]\nnode = 2")[0]
    cli = cli_dataset(tmp_path, "ucs", "[ucs]\nstiffness = [1e5, 1e9]\nn_points = 5\nn_modes = 1\n", toml)
    assert_same_arrays(lib.dataset, cli)
    k = np.logspace(5, 9, 5)
    closed = np.sqrt(1 / (1 / K_S + 1 / (2 * k)) / M)
    np.testing.assert_allclose(lib.dataset["critical_speed"][:, 0], closed, rtol=2e-5)


def test_frf_is_the_cli_and_peaks_at_the_jeffcott_natural_frequency(tmp_path):
    """Receptance at the mass = 1 / (k_eq - m w^2 + i c w) (1 DOF per direction); its peak at
    w_n sqrt(1 - 2 zeta^2)."""
    rotor = jeffcott()
    kw = dict(inputs=[{"node": 2, "direction": "y"}], frequency_hz=(1.0, 80.0), n_frequencies=800)
    lib = frf(rotor, speed_rpm=1000.0, **kw)
    table = "[frf]\nspeed_rpm = 1000.0\nfrequency_hz = [1.0, 80.0]\nn_frequencies = 800\n"
    table += "[[frf.pair]]\ninput_node = 2\ninput_direction = 'y'\n"
    assert_same_arrays(lib.dataset, cli_dataset(tmp_path, "frf", table))
    w = lib.dataset["frequency"].values
    H = lib.dataset["H_real"].values[:, 0] + 1j * lib.dataset["H_imag"].values[:, 0]
    np.testing.assert_allclose(H, 1 / (K_EQ - M * w**2 + 1j * C * w), rtol=1e-4)
    peak = lib.summary()["y2/Fy2_peak_0_frequency_hz"]["value"] * 2 * np.pi
    assert abs(peak - W_N * np.sqrt(1 - 2 * ZETA**2)) < (w[1] - w[0])  # within one frequency step
    both = frf(rotor, inputs=[{"node": 2}, {"node": 2, "direction": "y"}], n_frequencies=10)
    assert list(both.dataset["pair"].values) == ["x2/Fx2", "y2/Fx2", "x2/Fy2", "y2/Fy2"]  # output fastest
    with pytest.raises(InputError, match="frf.inputs\\[0\\].rotor"):
        frf(rotor, inputs=[{"rotor": "r", "node": 2}])
    with pytest.raises(InputError, match="frf.pair\\[0\\]"):
        frf(rotor, inputs=[{"node": 9}])


def test_stability_is_the_cli_and_the_jeffcott_log_dec(tmp_path):
    """Level II log decrement of the Jeffcott rotor = 2 pi zeta / sqrt(1 - zeta^2), zeta = c / (2 sqrt(k_eq m))."""
    rotor = jeffcott()
    lib = stability(rotor, kind="pump", speed_rpm=1000.0)
    cli = cli_dataset(tmp_path, "stability", "[stability]\nmachine = 'pump'\nspeed_rpm = 1000.0\n")
    assert_same_arrays(lib.dataset, cli)
    log_dec = lib.summary()["level2_log_dec"]["value"]
    assert log_dec == pytest.approx(2 * np.pi * ZETA / np.sqrt(1 - ZETA**2), rel=2e-5)
    assert lib.summary()["level2_verdict"]["value"] == "pass"  # 0.63 > API 617's 0.1
    with pytest.raises(InputError, match="stability.speed_rpm"):
        stability(rotor, kind="pump")
    with pytest.raises(InputError, match="stability.machine"):
        stability(rotor, kind="fan", speed_rpm=1000.0)


def test_transient_response_is_the_cli_and_ends_on_the_unbalance_orbit(tmp_path):
    """At constant speed the free vibration decays (exp(-zeta w_n t) < 2e-5 after 0.6 s) and the
    orbit left is the steady unbalance response at that speed (frequency domain, a second
    formulation); Newmark's average acceleration is second order: halving the step quarters the gap."""
    rotor = jeffcott()
    mass = [{"node": 2, "magnitude": 1e-4, "phase_deg": 30.0}]
    kw = dict(speed_rpm=(1500.0, 1500.0), masses=mass, method="direct")
    lib = transient_response(rotor, duration=0.05, n_output=51, steps_per_output=2, **kw)
    table = "[transient]\nspeed_rpm = [1500.0, 1500.0]\nduration = 0.05\nn_output = 51\nmethod = 'direct'\n"
    table += "steps_per_output = 2\n[[transient.mass]]\nnode = 2\nmagnitude = 1e-4\nphase_deg = 30.0\n"
    assert_same_arrays(lib.dataset, cli_dataset(tmp_path, "transient", table))
    ub = unbalance_response_study(rotor, mass, speed_rpm=(1500.0, 1600.0), n_speeds=2).dataset
    X = complex(ub["x_real"][0, 0], ub["x_imag"][0, 0])  # x(t) = Re(X exp(i Omega t)) [m]
    Y = complex(ub["y_real"][0, 0], ub["y_imag"][0, 0])
    gaps = []
    for steps in (2, 4):  # time step 0.7 s / 1400 / steps
        t = transient_response(rotor, duration=0.7, n_output=1401, steps_per_output=steps, **kw).dataset
        late = t["time"].values > 0.6
        z = np.exp(1j * 1500.0 * RAD_PER_RPM * t["time"].values[late])
        q = t["displacement"].values[late, 0, :]
        gaps.append(max(np.abs(q[:, 0] - np.real(X * z)).max(), np.abs(q[:, 1] - np.real(Y * z)).max()) / abs(X))
    assert gaps[1] < 2e-4
    assert 3.5 < gaps[0] / gaps[1] < 4.5
    with pytest.raises(InputError, match="transient.mass\\[0\\].nod"):
        transient_response(rotor, speed_rpm=(1500.0, 1500.0), masses=[{"nod": 2, "magnitude": 1e-4}])
    with pytest.raises(InputError, match="one of speed_rpm"):
        transient_response(rotor, speed_rpm=(1500.0, 1500.0), speed=(157.0, 157.0))


@pytest.mark.parametrize(
    "call",
    [
        lambda r: frf(r, speed_rpm=1000.0, speed=104.7, n_frequencies=10),
        lambda r: stability(r, kind="pump", speed_rpm=1000.0, speed=104.7),
        lambda r: static_state(r, speed_rpm=1000.0, speed=104.7),
        lambda r: transient_response(r, speed_rpm=(0.0, 1.0), speed=(0.0, 0.1)),
    ],
    ids=["frf", "stability", "static_state", "transient_response"],
)
def test_speed_rpm_and_speed_together_are_refused(call):
    """One speed, one unit: both names given is an input error naming the table's speed_rpm key."""
    with pytest.raises(InputError, match=r"\.speed_rpm.*<both>.*one of speed_rpm"):
        call(jeffcott())


@pytest.mark.parametrize("name", ["frf", "stability", "static_state", "critical_speed_map", "transient_response"])
def test_docstring_examples_run(name):
    """The Examples of the five functions run as written (the weight split, the bounce ratio,
    the machine's numbers for the same one-rotor machine)."""
    import doctest

    from rotaflex.rotor.fe import study

    finder, runner = doctest.DocTestFinder(), doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
    (test,) = finder.find(getattr(study, name), f"rotaflex.rotor.fe.study.{name}", globs=vars(study).copy())
    assert test.examples
    assert runner.run(test).failed == 0
