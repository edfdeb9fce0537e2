"""Result objects and figures of the gearbox analyses (xarray datasets with units)."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np

from rotaflex.core.result import Result, register_result
from rotaflex.core.units import rad_s_to_rpm

HZ = 1 / (2 * np.pi)
#: excitation-line names of the Campbell dataset: ``mesh<i> x<order>`` (see system.modal)
_MESH_LINE = re.compile(r"mesh(\d+) x(\S+)$")


def excitation_name(name: str, n_mesh: int = 1) -> str:
    """An excitation line's name as an engineer writes it: ``mesh0 x2`` -> ``2× mesh frequency``
    (``2× mesh 0 frequency`` when the gearbox has several meshes), ``input 1X`` -> ``1X input``."""
    m = _MESH_LINE.match(name)
    if m:
        return f"{m.group(2)}× mesh{f' {m.group(1)}' if n_mesh > 1 else ''} frequency"
    if name.endswith(" 1X"):
        return f"1X {name[:-3]}"
    return name


def bearing_name(name: str) -> str:
    """A bearing's dataset name ``<rotor>:<node>`` as a legend entry: ``input, node 1``."""
    rotor, _, node = name.rpartition(":")
    return f"{rotor}, node {node}" if rotor else name


def system_figure(box):
    """Plan view (gearbox plane: centres, base and pitch circles, line of action, sense of
    rotation) and side view (shafts along z side by side, disks, bearings, gear nodes)."""
    from matplotlib.patches import Circle, FancyArrowPatch, Polygon, Rectangle

    from rotaflex.core.plotting import new_figure

    fig, (ax, bx) = new_figure(1, 2, figsize=(11, 4.5))
    for m in box.meshes:
        (rd, _), (rf, _) = m.driver, m.driven
        for r, rb in ((rd, m.radius[0]), (rf, m.radius[1])):
            c = box.rotors[r].center
            ax.add_patch(Circle(c, rb, fill=False, ls="--", lw=0.8, ec="0.4"))
            rp = rb / np.cos(m.gear.pressure_angle)
            ax.add_patch(Circle(c, rp, fill=False, lw=1.2, ec="tab:blue"))
        cd, cf = box.rotors[rd].center, box.rotors[rf].center
        pitch = cd + (cf - cd) * m.radius[0] / sum(m.radius)
        half = 1.2 * np.hypot(*(cf - cd)) * np.sin(m.gear.pressure_angle) + 0.3 * min(m.radius)
        a, b = pitch - half * m.normal, pitch + half * m.normal
        ax.add_patch(FancyArrowPatch(a, b, arrowstyle="-|>", mutation_scale=12, color="tab:red", lw=1.2))
        ax.annotate("line of action (force on driven)", b, fontsize=7, color="tab:red")
    for i, pr in enumerate(box.rotors):
        c = pr.center
        ax.plot(*c, "k+", ms=8)
        same = sum(np.allclose(q.center, c) for q in box.rotors[:i])  # coupled rotors share a centre
        ax.annotate(
            f"{pr.name} ({'ccw' if pr.sense > 0 else 'cw'}, x{pr.ratio:.3g})",
            c,
            fontsize=8,
            xytext=(4, -12 - 10 * same),
            textcoords="offset points",
        )
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.set(xlabel="x [m]", ylabel="y [m]", title="gearbox plane")
    # side view: each rotor drawn at its x position, shaft along z
    order = np.argsort([pr.center[0] for pr in box.rotors])
    gear_nodes = {}
    for m in box.meshes:
        for r, n in (m.driver, m.driven):
            gear_nodes.setdefault(r, []).append(n)
    shift = {}  # coupled rotors drawn end to end: hub b at hub a's axial position
    for cp in getattr(box, "couplings", ()):
        (ra, na), (rb, nb) = cp.a, cp.b
        shift.setdefault(ra, 0.0)
        shift[rb] = shift[ra] + box.rotors[ra].rotor.nodes[na] - box.rotors[rb].rotor.nodes[nb]
    for i in order:
        pr = box.rotors[i]
        z, e = pr.rotor.nodes + shift.get(i, 0.0), pr.rotor.elements
        y0 = pr.center[0]  # each shaft drawn at its x in the gearbox plane
        for j in range(e["L"].size):
            ro = e["do_l"][j] / 2
            bx.add_patch(Rectangle((z[j], y0 - ro), z[j + 1] - z[j], 2 * ro, fc="0.75", ec="0.3", lw=0.5))
        for node, d in pr.rotor.disks:
            rd = np.sqrt(2 * d.Ip / d.mass) if d.mass > 0 and d.Ip > 0 else 0.02
            col = "tab:blue" if node in gear_nodes.get(i, []) else "tab:gray"
            bx.add_patch(Rectangle((z[node] - 0.004, y0 - rd), 0.008, 2 * rd, fc=col, alpha=0.6))
        for node, _, _ in pr.rotor.bearings:
            h = 0.01
            yb = y0 - e["do_l"][min(node, e["L"].size - 1)] / 2
            bx.add_patch(
                Polygon(
                    [[z[node], yb], [z[node] - 0.008, yb - h], [z[node] + 0.008, yb - h]],
                    fc="tab:orange",
                    ec="k",
                    lw=0.5,
                )
            )
        # the name right of the shaft's end, inside the axes (left of it, it met the tick labels)
        bx.annotate(pr.name, (z[-1], y0), fontsize=8, xytext=(10, 0), textcoords="offset points", va="center")
    bx.autoscale_view()
    lo, hi = bx.get_xlim()
    bx.set_xlim(lo, hi + 0.2 * (hi - lo))
    bx.set(xlabel="z [m]", ylabel="x of the shaft axis [m]", title="shafts, gears (blue), bearings (orange)")
    return fig


def _box(result):
    from rotaflex.system.model import MODEL_KEYS, Gearbox

    cfg = result.config
    try:
        return Gearbox.from_mapping({k: v for k, v in cfg.items() if k in MODEL_KEYS})
    except Exception:  # noqa: BLE001 - a figure is optional (e.g. a pair file moved since the run)
        return None


class _SystemResult(Result):
    def summary(self) -> dict:
        out = super().summary()
        out.update(json.loads(self.dataset.attrs.get("summary_extra", "{}")))
        return out

    def _model(self) -> dict:
        box = _box(self)
        return {} if box is None else {"system": system_figure(box)}

    def plot_model(self):
        """Plan and side views of the machine (``system.png``); None when the model cannot be
        rebuilt from the stored config (a pair file moved since the run)."""
        return self._model().get("system")


@register_result
class SystemModalResult(_SystemResult):
    """Coupled modes at one speed with the energy split of each mode."""

    kind = "system_modal"

    def plot(self) -> dict:
        return {**self._model(), "energy_split": self.plot_energy()}

    def plot_energy(self):
        """Kinetic-energy split of each mode over the rotors and the mesh strain energy
        (``energy_split.png``)."""
        from rotaflex.core.plotting import new_figure

        ds = self.dataset
        fig, ax = new_figure()
        nm = ds.sizes["mode"]
        bottom = np.zeros(nm)
        x = np.arange(nm)
        for gi, g in enumerate(ds["group"].values):
            v = ds["energy"].values[:, gi]
            ax.bar(x, v, bottom=bottom, label=str(g))
            bottom += v
        ax.plot(x, ds["mesh_energy"].values, "k^", label="mesh strain energy")
        ax.set_xticks(x, [f"{f * HZ:.0f}" for f in ds["natural_frequency"].values], rotation=60, fontsize=7)
        ax.set(xlabel="mode frequency [Hz]", ylabel="energy fraction")
        ax.legend(fontsize=7)
        return fig


@register_result
class SystemCampbellResult(_SystemResult):
    """Campbell diagram: tracked coupled modes, mesh-order and 1X lines, crossings."""

    kind = "system_campbell"

    def plot(self) -> dict:
        return {**self._model(), "campbell": self.plot_campbell()}

    def plot_campbell(self):
        """The Campbell diagram of rotor/fe (:func:`~rotaflex.rotor.fe.figures.campbell_figure`,
        log-decrement panel below) with the tracks' points coloured by mesh strain energy, the
        mesh-order (red) and 1X lines, and the mesh-order crossings of mesh modes (``campbell.png``)."""
        from rotaflex.rotor.fe.results import campbell_lines, plot_campbell_dataset

        ds = self.dataset
        lines = campbell_lines(ds)
        n_mesh = len({m.group(1) for n, _ in lines if (m := _MESH_LINE.match(n))})
        styled = [
            (excitation_name(n, n_mesh), f, *(("tab:red", "-") if n.startswith("mesh") else ("0.3", ":")))
            for n, f in lines
        ]
        marks = [
            cr
            for cr in json.loads(ds.attrs.get("crossings", "[]"))
            if cr["line"].startswith("mesh") and cr["mesh_energy"] > 0.05
        ]
        # a train without gears has no mesh energy to colour by: no colour bar
        return plot_campbell_dataset(
            ds,
            styled,
            marks,
            colour=ds["mesh_energy"].values if n_mesh else None,
            colour_label="mesh strain-energy fraction",
            speed_label="drive speed [rpm]",
            marks_note="o: mesh-order crossing of a mode with > 5 % mesh strain energy" if n_mesh else "",
        )


def campbell_dataset(c):
    """Dataset of ``rotaflex system campbell``: rotor/fe's Campbell dataset
    (:func:`rotaflex.rotor.fe.results.campbell_dataset`; crossings in the attribute
    ``crossings``) with the machine's shares on top: ``mesh_energy``, ``torsional_fraction``
    (speed, mode) and ``energy`` (speed, mode, group) [-]."""
    from rotaflex.rotor.fe.results import campbell_dataset as rotor_dataset

    m = c.modes
    ds = rotor_dataset(m, c.mac_min, c.lines, c.crossings)
    ds["mesh_energy"] = (("speed", "mode"), m.mesh_energy, {"units": "1"})
    ds["torsional_fraction"] = (("speed", "mode"), m.torsional_fraction, {"units": "1"})
    ds["energy"] = (("speed", "mode", "group"), m.energy, {"units": "1"})
    return ds.assign_coords(group=m.groups)


@register_result
class SystemResponseResult(_SystemResult):
    """TE-harmonic response vs speed."""

    kind = "system_response"

    def plot(self) -> dict:
        figs = {**self._model(), "response": self.plot_response()}
        if self.dataset.sizes.get("probe", 0):
            figs["orbits"] = self.plot_orbits()
        return figs

    def plot_response(self):
        """DTE, dynamic mesh force and bearing forces per TE harmonic vs speed (``response.png``)."""
        from rotaflex.core.plotting import STYLES, legend_outside, new_figure

        ds = self.dataset
        rpm = ds["speed_rpm"].values
        nh = ds.sizes["harmonic"]
        fig, ax = new_figure(3, 1, sharex=True, figsize=(7.6, 8))
        for h in range(nh):
            order = f"{h + 1}× mesh frequency"
            ax[0].semilogy(rpm, ds["dte"].values[0, :, h] * 1e6, ls=STYLES[h % len(STYLES)], label=order)
            ax[1].semilogy(rpm, ds["mesh_force"].values[0, :, h], ls=STYLES[h % len(STYLES)], label=order)
        for b in range(ds.sizes["bearing"]):
            name = bearing_name(str(ds["bearing"].values[b]))
            ax[2].semilogy(rpm, ds["bearing_force"].values[0, :, :, b].sum(-1), label=name)
        ax[0].set_ylabel("DTE amplitude, 0-pk [µm]")
        ax[1].set_ylabel("dynamic mesh force\namplitude, 0-pk [N]")
        ax[2].set(ylabel="bearing force,\nbound on the peak [N]", xlabel="drive speed [rpm]")
        ax[0].set_title(
            f"response to the first {nh} harmonics of the static transmission error\n"
            "DTE and mesh force: each harmonic's amplitude (0-pk); bearing force: "
            "sum over the harmonics of √(|F_x|² + |F_y|²)",
            fontsize=8,
        )
        legend_outside(ax[0], title="excitation")
        legend_outside(ax[2], title="bearing (shaft, node)")
        for a in ax:
            a.grid(alpha=0.3, which="both")
        return fig

    def plot_orbits(self):
        """Orbit semi-major axis of every probe vs speed (``orbits.png``)."""
        from rotaflex.core.plotting import legend_outside, new_figure

        ds = self.dataset
        rpm = ds["speed_rpm"].values
        nh = ds.sizes["harmonic"]
        fig2, a2 = new_figure()
        for p in range(ds.sizes["probe"]):
            a2.semilogy(
                rpm,
                ds["orbit_major"].values[0, :, :, p].sum(-1) * 1e6,
                label=bearing_name(str(ds["probe"].values[p])),
            )
        a2.set(
            xlabel="drive speed [rpm]",
            ylabel=f"orbit semi-major axis, sum of\nthe {nh} harmonics [µm]",
            title="orbit size per probe (sum of the harmonic semi-major axes, an upper bound)",
        )
        a2.title.set_fontsize(8)
        legend_outside(a2, title="probe (shaft, node)")
        return fig2


@register_result
class SystemSteadyResult(_SystemResult):
    """One nonlinear steady-state point: DTE, mesh force, bearing forces over the last cycles."""

    kind = "system_steady"

    def final_state(self) -> dict | None:
        """Physical state at the end (plain data) for ``initial_state`` of the next point."""
        ds = self.dataset
        if "state_q" not in ds:
            return None
        return {
            "q": ds["state_q"].values.tolist(),
            "qdot": ds["state_qdot"].values.tolist(),
            "phase": ds["state_phase"].values.tolist(),
        }

    def plot(self) -> dict:
        return {**self._model(), "time_series": self.plot_time_series()}

    def plot_time_series(self):
        """DTE, mesh force and bearing forces over the last cycles (``time_series.png``)."""
        from rotaflex.core.plotting import new_figure

        ds = self.dataset
        t = ds["time"].values
        fig, ax = new_figure(3, 1, sharex=True, figsize=(7, 8))
        ax[0].plot(t * 1e3, ds["dte"].values[:, 0] * 1e6)
        ax[0].set_ylabel("DTE [µm]")
        ax[1].plot(t * 1e3, ds["mesh_force"].values[:, 0])
        ax[1].axhline(float(ds["static_force"].values[0]), ls="--", c="k", lw=0.8)
        ax[1].set_ylabel("mesh force [N]")
        for b in range(ds.sizes["bearing"]):
            f = np.hypot(*ds["bearing_force"].values[:, b].T)
            ax[2].plot(t * 1e3, f, label=str(ds["bearing"].values[b]), lw=0.8)
        ax[2].set(xlabel="time [ms]", ylabel="|bearing force| [N]")
        ax[2].legend(fontsize=6)
        return fig


def torsional_dataset(model, w, shape, lines, margin, passed, operating, speed_range, required):
    """Dataset of ``rotaflex system torsional`` (frequencies, shapes, lines, margins)."""
    import xarray as xr

    return xr.Dataset(
        {
            "natural_frequency": ("mode", w, {"units": "rad/s"}),
            "shape": (("mode", "station"), shape, {"units": "1", "long_name": "twist, largest = 1"}),
            "line_factor": ("line", [ln["factor"] for ln in lines], {"units": "1", "long_name": "omega / drive speed"}),
            "line_fixed": ("line", [ln["fixed"] for ln in lines], {"units": "rad/s"}),
            "margin": (("mode", "line"), margin, {"units": "1", "long_name": "API 684 separation margin"}),
            "passed": (("mode", "line"), passed.astype(np.int8), {"units": "1", "required_margin": required}),
            "operating_speed": ("bound", np.asarray(operating, float), {"units": "rad/s"}),
            "speed_range": ("bound", np.asarray(speed_range, float), {"units": "rad/s"}),
        },
        coords={
            "mode": np.arange(w.size),
            "station": model.labels,
            "line": [ln["name"] for ln in lines],
            "bound": ["min", "max"],
        },
    )


@register_result
class TorsionalResult(_SystemResult):
    """Torsional modes, interference diagram (natural frequencies vs excitation lines), margins."""

    kind = "system_torsional"

    def plot(self) -> dict:
        return {**self._model(), "interference": self.plot_interference(), "torsional_modes": self.plot_modes()}

    def plot_interference(self):
        """Natural frequencies with their +-10 % bands against the excitation lines, the
        operating range and the crossings (``interference.png``)."""
        from rotaflex.core.plotting import new_figure

        ds = self.dataset
        fig, ax = new_figure(figsize=(7, 5))
        lo, hi = ds["speed_range"].values
        op = ds["operating_speed"].values
        sp = np.linspace(lo, hi, 200)
        fn = ds["natural_frequency"].values * HZ
        top = (ds["line_factor"].values * hi + ds["line_fixed"].values) * HZ
        ymax = 1.3 * max(float(top.max()) if top.size else 0.0, float(fn[0]))  # modes far above: off the chart
        ax.axvspan(
            rad_s_to_rpm(op[0]), rad_s_to_rpm(op[1]), color="tab:green", alpha=0.15, lw=0, label="operating range"
        )
        for k, f in enumerate(fn):
            ax.axhline(f, color="tab:blue", lw=0.9)
            ax.axhspan(f * 0.9, f * 1.1, color="tab:blue", alpha=0.07, lw=0)
            ax.annotate(f"mode {k}: {f:.4g} Hz", (rad_s_to_rpm(sp[0]), f), fontsize=7, va="bottom")
        for name, a, b in zip(ds["line"].values, ds["line_factor"].values, ds["line_fixed"].values, strict=True):
            y = (a * sp + b) * HZ
            ax.plot(rad_s_to_rpm(sp), y, "--" if a == 0 else "-", c="tab:red", lw=0.8)
            j = np.flatnonzero(y <= ymax)
            if j.size:
                ax.annotate(str(name), (rad_s_to_rpm(sp[j[-1]]), y[j[-1]]), fontsize=6, color="tab:red")
        for c in json.loads(ds.attrs.get("crossings", "[]")):
            ax.plot(rad_s_to_rpm(c["speed"]), c["frequency"] * HZ, "ko", mfc="none", ms=6)
        ax.set_ylim(0, ymax)
        ax.set(
            xlabel="drive speed [rpm]", ylabel="frequency [Hz]", title="torsional interference diagram (±10 % bands)"
        )
        ax.legend(fontsize=7, loc="upper left")
        return fig

    def plot_modes(self):
        """Torsional mode shapes, twist per station (``torsional_modes.png``)."""
        from rotaflex.core.plotting import new_figure

        ds = self.dataset
        fn = ds["natural_frequency"].values * HZ
        fig2, bx = new_figure(figsize=(8, 4))
        for k in range(ds.sizes["mode"]):
            bx.plot(ds["shape"].values[k], "o-", ms=3, label=f"{fn[k]:.4g} Hz")
        bx.set_xticks(np.arange(ds.sizes["station"]), ds["station"].values, rotation=90, fontsize=6)
        bx.set(ylabel="twist (largest = 1)", title="torsional mode shapes")
        bx.legend(fontsize=7)
        return fig2


def _element_torques(box, model, theta):
    """Shaft element torques [N m] (nt, n_elements) from the twists: k_e (theta_j - theta_{j+1})."""
    from rotaflex.system.assembly import torsion_matrices

    out, names = [], []
    for r, pr in enumerate(box.rotors):
        if not pr.torsion:
            continue
        kt = -np.diag(torsion_matrices(pr.rotor)[0], 1)
        idx = [model.index(box, r, j) for j in range(pr.rotor.n_nodes)]
        th = theta[:, idx]
        out.append((th[:, :-1] - th[:, 1:]) * kt * pr.sense)
        names += [f"{pr.name}:{e}" for e in range(kt.size)]
    return np.concatenate(out, 1), names


def startup_dataset(box, model, run, n_steady):
    """Dataset and summary entries of ``rotaflex system startup``."""
    import xarray as xr

    d = model.index(box, *box.drive)
    speed = run.rate * model.sense  # each twist's speed in its rotor's sense
    shaft, names = _element_torques(box, model, run.theta)
    ctq, cnames = [], []
    for cp in box.couplings:
        if cp.torsion and not cp.rigid:
            ia, ib = model.index(box, *cp.a), model.index(box, *cp.b)
            tw = run.theta[:, ia] - run.theta[:, ib]
            rt = run.rate[:, ia] - run.rate[:, ib]
            ctq.append((cp.k[4] * tw + cp.c[4] * rt) * model.sense[ia])
            cnames.append(cp.name)
    first = [model.index(box, r, 0) for r, pr in enumerate(box.rotors) if pr.torsion]
    ds = xr.Dataset(
        {
            "rotor_speed": (("time", "rotor"), speed[:, first], {"units": "rad/s", "long_name": "speed of node 0"}),
            "drive_speed_rpm": ("time", rad_s_to_rpm(speed[:, d]), {"units": "rpm"}),
            "motor_torque": ("time", run.motor_torque, {"units": "N m"}),
            "load_torque": ("time", run.load_torque, {"units": "N m"}),
            "shaft_torque": (("time", "element"), shaft, {"units": "N m", "long_name": "torque transmitted"}),
            "coupling_torque": (("time", "coupling"), np.array(ctq).T.reshape(run.time.size, -1), {"units": "N m"}),
            "work": (("time", "term"), run.work, {"units": "J"}),
            "energy": (("time", "kind"), run.energy, {"units": "J"}),
            "twist": (
                ("time", "station"),
                run.theta - run.theta[:, [d]] * model.ratio * model.sense * model.sense[d],
                {"units": "rad", "long_name": "twist relative to the rigid rotation of the drive node"},
            ),
        },
        coords={
            "time": ("time", run.time, {"units": "s"}),
            "rotor": [pr.name for pr in box.rotors if pr.torsion],
            "element": names,
            "coupling": cnames,
            "term": ["motor", "load", "damping"],
            "kind": ["kinetic", "potential"],
            "station": model.labels,
        },
    )
    final = float(rad_s_to_rpm(speed[-1, d]))
    target = 0.99 * n_steady
    reach = np.flatnonzero(speed[:, d] >= target)
    err = float(np.max(np.abs(run.balance)) / max(float(np.max(np.abs(run.work[:, 0]))), 1e-300))
    extra = {
        "final_speed_rpm": {"value": final, "unit": "rpm"},
        "steady_speed_rpm": {"value": rad_s_to_rpm(n_steady), "unit": "rpm", "long_name": "motor = load torque"},
        "time_to_99_percent": {"value": float(run.time[reach[0]]) if reach.size else None, "unit": "s"},
        "energy_balance_error": {"value": err, "unit": "1", "long_name": "max |E - W| / max W_motor"},
        "modes_kept": {"value": run.n_modes, "unit": ""},
        "nfev": {"value": run.nfev, "unit": ""},
    }
    for j, name in enumerate(names):
        extra[f"peak_shaft_torque_{name}"] = {"value": float(np.abs(shaft[:, j]).max()), "unit": "N m"}
    for j, name in enumerate(cnames):
        extra[f"peak_coupling_torque_{name}"] = {"value": float(np.abs(ctq[j]).max()), "unit": "N m"}
    return ds, extra


@register_result
class StartupResult(_SystemResult):
    """Run-up histories: speeds, motor and load torque, shaft and coupling torques."""

    kind = "system_startup"

    def plot(self) -> dict:
        return {**self._model(), "startup": self.plot_startup()}

    def plot_startup(self):
        """Rotor speeds, motor and load torque, and the transmitted torque vs time (``startup.png``)."""
        from rotaflex.core.plotting import new_figure

        ds = self.dataset
        t = ds["time"].values
        fig, ax = new_figure(3, 1, sharex=True, figsize=(7, 8))
        for i, name in enumerate(ds["rotor"].values):
            ax[0].plot(t, rad_s_to_rpm(ds["rotor_speed"].values[:, i]), label=str(name))
        ax[0].set_ylabel("speed [rpm]")
        ax[0].legend(fontsize=7)
        ax[1].plot(t, ds["motor_torque"].values, label="motor")
        ax[1].plot(t, ds["load_torque"].values, label="load")
        ax[1].set_ylabel("torque [N m]")
        ax[1].legend(fontsize=7)
        for j, name in enumerate(ds["coupling"].values):
            ax[2].plot(t, ds["coupling_torque"].values[:, j], label=str(name), lw=0.8)
        if not ds.sizes["coupling"]:
            j = int(np.argmax(np.abs(ds["shaft_torque"].values).max(0)))
            ax[2].plot(t, ds["shaft_torque"].values[:, j], label=f"shaft {ds['element'].values[j]}", lw=0.8)
        ax[2].set(xlabel="time [s]", ylabel="transmitted torque [N m]")
        ax[2].legend(fontsize=7)
        return fig


@register_result
class SystemUnbalanceResult(_SystemResult):
    """Unbalance response of a machine at its probes vs drive speed, peaks with AF and SM."""

    kind = "system_unbalance"

    def plot(self) -> dict:
        ds = self.dataset
        figs = {**self._model()}
        for k in range(ds.sizes["excitation"]):
            figs["bode" if k == 0 else f"bode_{k}"] = self.plot_bode(k)
        return figs

    def plot_bode(self, excitation: int = 0):
        """The rotor verb's Bode figure (:func:`~rotaflex.rotor.fe.figures.unbalance_bode_figure`)
        of one excitation (``bode.png``, ``bode_<k>.png`` for the k-th rotor speed)."""
        from rotaflex.rotor.fe.figures import unbalance_bode_figure

        ds = self.dataset
        label = str(ds["excitation"].values[excitation])
        pk = [p for p in json.loads(ds.attrs.get("peaks", "[]")) if p["excitation"] == label]
        fig = unbalance_bode_figure(ds.isel(excitation=excitation), pk, json.loads(ds.attrs.get("bands", "[]")))
        fig.axes[1].set_xlabel(f"drive speed [rpm] (excitation: {label})")
        return fig


@register_result
class SystemFRFResult(_SystemResult):
    """FRFs of a machine at one drive speed: the rotor verb's Bode and Nyquist figures."""

    kind = "system_frf"

    def plot(self) -> dict:
        from rotaflex.rotor.fe.figures import frf_figures

        return {**self._model(), **frf_figures(self.dataset)}


@register_result
class SystemStabilityResult(_SystemResult):
    """API 617 Level I and II of a machine: the rotor verb's verdict table and figures."""

    kind = "system_stability"

    def verdict_table(self) -> str:
        """The verdicts as a Markdown table."""
        from rotaflex.rotor.fe.verbs_stability import verdict_table

        return verdict_table(self.dataset, self.summary())

    def write_extra(self, out_dir: Path) -> list[Path]:
        from rotaflex.core.io import write_text_atomic

        return [write_text_atomic(Path(out_dir) / "verdict.md", self.verdict_table())]

    def plot(self) -> dict:
        from rotaflex.rotor.fe.verbs_stability import stability_figures

        return {**self._model(), **stability_figures(self.dataset)}


@register_result
class SystemStaticResult(_SystemResult):
    """Static state of a machine: per rotor deflection, reactions, shear, moment; mesh forces."""

    kind = "system_static"

    def plot(self) -> dict:
        figs = {**self._model()}
        for name in dict.fromkeys(self.dataset["node_rotor"].values):
            figs[f"static_{name}"] = self.plot_static(str(name))
        return figs

    def rotor_dataset(self, name: str):
        """The part of the dataset on rotor ``name``, in the rotor verb's layout (what
        :func:`~rotaflex.rotor.fe.figures.static_figure` draws)."""
        ds = self.dataset
        sel = {d: np.flatnonzero(ds[f"{d}_rotor"].values == name) for d in ("node", "cut", "bearing")}
        sub = ds.isel(sel)
        return sub.assign_coords(node=sub["node_index"].values, bearing=np.arange(sub.sizes["bearing"]))

    def plot_static(self, rotor: str):
        """The rotor verb's static figure (:func:`~rotaflex.rotor.fe.figures.static_figure`) of
        one rotor, the mesh and coupling forces on it included (``static_<rotor>.png``)."""
        from rotaflex.rotor.fe.figures import static_figure

        fig = static_figure(self.rotor_dataset(rotor))
        ax = fig.axes[0]
        ax.set_title(f"{rotor}: {ax.get_title()}", fontsize=9)
        return fig


@register_result
class SystemUCSResult(_SystemResult):
    """Undamped critical speed map of a machine: critical drive speeds vs the swept bearings' stiffness."""

    kind = "system_ucs"

    def plot(self) -> dict:
        """The machine's views and the rotor verb's UCS figure (``ucs_map.png``) with the swept
        bearings' kxx, kyy against the drive speed."""
        from rotaflex.rotor.fe.figures import ucs_figure

        lines = json.loads(self.dataset.attrs.get("bearing_lines", "[]"))
        return {**self._model(), "ucs_map": ucs_figure(self.dataset, lines)}


@register_result
class SystemTransientResult(_SystemResult):
    """Time response of a machine at its probes (constant drive speed or ramp)."""

    kind = "system_transient"

    def plot(self) -> dict:
        """The rotor verb's figures (:func:`~rotaflex.rotor.fe.figures.transient_figures`):
        ``time_response.png`` (speed panel: the drive's) and ``orbit.png``."""
        from rotaflex.rotor.fe.figures import transient_figures

        fig, fig2 = transient_figures(self.dataset)
        return {**self._model(), "time_response": fig, "orbit": fig2}
