"""Nonlinear steady state of a gearbox: time-varying mesh stiffness, TE, contact loss (time domain).

The equations of :mod:`.assembly` with the mesh forces of :mod:`.kernel` (one-sided contact,
back flank after the backlash, k(phi) from the mesh table or its mean) are reduced on the basis
of :func:`~.assembly.reduced_basis` (modes below ``cutoff`` x the highest mesh harmonic kept, plus
the static mesh-force shapes) and integrated by compiled RK4 with a whole number of steps per
mesh cycle of the first mesh (``phi = z_p Omega_p t / (2 pi)``, the nominal kinematic phase).
The run starts from the static state under the load (mean stiffness, mean TE) or from a given
state (continuation) and stops when the DTE of the last cycle repeats that of ``p`` = 1 ... 4
cycles before to ``tol`` x the static deflection (``period`` = p; 0: not periodic within
``max_cycles``). The last ``eval_cycles`` cycles are returned.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rotaflex.core.errors import InputError
from rotaflex.core.units import rad_s_to_rpm
from rotaflex.gear.results.steady import Periodicity, detect_period
from rotaflex.gear.solvers.steady_loop import until_periodic
from rotaflex.system.assembly import load_vector, matrices, reduced_basis, system_matrices
from rotaflex.system.helical import axial_reactions
from rotaflex.system.model import Gearbox
from rotaflex.system.size import DEFAULT_MAX_STEPS, check_assembly, check_steady


@dataclass(frozen=True)
class SteadySettings:
    """Time-domain settings (SI)."""

    steps_per_cycle: int = 0  # 0: omega_top dt <= 1.2, a multiple of the table points if linear
    min_cycles: int = 20
    max_cycles: int = 400
    eval_cycles: int = 10
    check_every: int = 10
    tol: float = 1e-5
    cutoff: float = 4.0
    harmonics: int = 3
    stiffness: str | None = None  # None: each mesh's own setting; "mean" / "varying" for all
    max_steps: int = DEFAULT_MAX_STEPS  # refuse runs that may take more RK4 steps


@dataclass(frozen=True)
class SteadyState:
    """Histories of the evaluated cycles and the run's figures of merit.

    time (n,) [s]; dte, deflection, force (n, n_mesh) [m, m, N]; bearing_force (n, n_bearing, 2)
    [N]; energy (n_all,), power (n_all, 2) of the whole run, every step [J, W] (power: limits
    from after / before the sample, equal unless a table has a kink there);
    period (cycles, 0: none), change, cycles run, steps per cycle, static force (n_mesh,) [N],
    contact_loss (n_mesh,) fraction of evaluated samples without contact; final (q, qdot, phase);
    phase_shift (n, n_mesh) [cycles]: the pinion's twist as mesh phase, z_p s_p theta_p / (2 pi),
    which the nominal phase of the run leaves out (its peak-to-peak bounds the difference to a
    phase that follows the actual pinion angle).
    """

    time: np.ndarray
    dte: np.ndarray
    deflection: np.ndarray
    force: np.ndarray
    bearing_force: np.ndarray
    bearings: list
    energy: np.ndarray
    power: np.ndarray
    dt: float
    period: int
    change: float
    cycles: int
    steps_per_cycle: int
    static_force: np.ndarray
    mesh_frequency: float
    final_q: np.ndarray
    final_qdot: np.ndarray
    final_phase: np.ndarray
    basis_size: int
    phase_shift: np.ndarray
    axial_force: np.ndarray | None = None  # (n, n_thrust) [N]: thrust bearings (helical meshes)

    @property
    def contact_loss(self) -> np.ndarray:
        return np.mean(self.force == 0.0, axis=0)

    @property
    def energy_error(self) -> float:
        """|E(t) - E(0) - int P dt| max over the run, relative to the largest of |E - E(0)| and
        int |P| dt (trapezoidal integral of the recorded power over each step, from the power's
        limit at the step's start to its limit at the step's end: piecewise-linear tables have a
        kink at every grid point, where the steps fall)."""
        p = self.power
        w = np.concatenate([[0.0], np.cumsum(0.5 * (p[:-1, 0] + p[1:, 1]) * self.dt)])
        res = self.energy - self.energy[0] - w
        ref = max(np.max(np.abs(self.energy - self.energy[0])), np.sum(np.abs(p[:, 0])) * self.dt, 1e-300)
        return float(np.max(np.abs(res)) / ref)


def _periodicity(dte: np.ndarray, spc: int, scale: float, tol: float) -> Periodicity:
    """Period and change of the DTE history (whole cycles, oldest first) by the cycle comparison
    of gear steady (:func:`rotaflex.gear.results.steady.detect_period`, periods 1 ... 4, the last
    p cycles against the p before, relative to ``scale``); only the last 8 cycles are read."""
    return detect_period(dte[-8 * spc :], spc, tol, max_period=4, scale=scale)


def steady_state(box: Gearbox, speed: float, settings: SteadySettings | None = None, state=None) -> SteadyState:
    """Steady state at drive ``speed`` [rad/s] (see the module docstring).

    ``state``: dict with ``q``, ``qdot`` (full DOFs) and ``phase`` (per mesh, cycles) to start from.
    """
    from rotaflex.system.kernel import Meshes, Reduced, run_rk4

    st = settings or SteadySettings()
    if not len(box.meshes):
        raise InputError("gear_mesh", [], "at least one [[gear_mesh]] for a steady state")
    if not speed > 0:
        raise InputError("steady.speed_rpm", rad_s_to_rpm(speed), "a drive speed > 0 rpm")
    check_assembly(box)
    mats = matrices(box)
    free = mats.free
    nm = len(box.meshes)
    wm = np.array([box.mesh_frequency(j, speed) for j in range(nm)])
    P = reduced_basis(box, mats, speed, st.harmonics * float(wm.max()), st.cutoff, extra=False)
    M, D, K = system_matrices(box, speed, mats, mesh=False)
    Kr, Dr = P.T @ K @ P, P.T @ D @ P
    # diagonalise the reduced stiffness (P^T M P = I): the time step follows its top frequency
    Ks = 0.5 * (Kr + Kr.T)
    gf = mats.project(mats.g)
    w2, V = np.linalg.eigh(Ks + (P.T @ (gf.T * mats.k_mean) @ gf @ P))
    P = P @ V
    Kr, Dr = V.T @ Kr @ V, V.T @ Dr @ V
    w_top = float(np.sqrt(max(w2.max(), 0.0)))
    f_full = load_vector(box)
    fr = P.T @ mats.project(f_full)
    gr = mats.project(mats.g) @ P
    r = P.shape[1]
    tors = np.zeros_like(mats.g)
    for j, m in enumerate(box.meshes):
        idx = [box.torsion_dof(*m.driver), box.torsion_dof(*m.driven)]
        tors[j, idx] = mats.g[j, idx]
    tr = mats.project(tors) @ P
    Kss, Dss = 0.5 * (Kr + Kr.T), 0.5 * (Dr + Dr.T)
    Ka = Kr - Kss
    if np.max(np.abs(Ka)) <= 1e-14 * np.max(np.abs(Kr)):  # symmetric up to round-off: no skew power
        Ka = np.zeros((0, 0))
    rd = Reduced(Kr, Dr, Kss, Ka, Dss, fr, gr, tr)
    varying = np.array([(st.stiffness or m.spec.stiffness) == "varying" for m in box.meshes], dtype=np.int64)
    tabs = [m.gear.table for m in box.meshes]
    n_tab = max(len(t.stiffness) for t in tabs)
    ck = np.zeros((nm, 4, n_tab))
    ce = np.zeros((nm, 4, n_tab))
    for j, t in enumerate(tabs):
        if len(t.stiffness) != n_tab:
            raise InputError(f"gear_mesh[{j}].table_points", len(t.stiffness), f"{n_tab} (the same for every mesh)")
        ck[j], ce[j] = t.coefficients(t.stiffness), t.coefficients(t.unloaded_te)
    # the step: |lambda| dt <= 1.2 for every eigenvalue of the linearised reduced system in contact
    # (mesh damping can make |lambda| exceed the undamped omega); RK4 is stable to |lambda dt| ~ 2.6
    A = np.zeros((2 * r, 2 * r))
    A[:r, r:] = np.eye(r)
    A[r:, :r] = -(Kr + (gr.T * mats.k_mean * (1 + varying)) @ gr)
    A[r:, r:] = -(Dr + (gr.T * mats.c_mesh) @ gr)
    w_top = max(w_top, float(np.max(np.abs(np.linalg.eigvals(A)))))
    T = 2 * np.pi / wm[0]
    spc = st.steps_per_cycle or max(16, int(np.ceil(w_top * T / 1.2)))
    if not st.steps_per_cycle and any(t.interpolation == "linear" for t in tabs):
        spc = int(np.ceil(spc / n_tab)) * n_tab  # steps on the table's points: its jumps resolved
    dt = T / spc
    n_brg = sum(len(pr.rotor.bearings) for pr in box.rotors)
    check_steady(st, spc, r, nm, n_brg, st.max_steps)
    kmean = mats.k_mean.copy()
    # initial state: static under the load with the mean stiffness and mean TE, or the given one
    if state is None:
        Kst = Kr + (gr.T * kmean) @ gr
        rhs = fr + gr.T @ (kmean * np.array([t.unloaded_te.mean() for t in tabs]))
        x = np.linalg.lstsq(Kst, rhs, rcond=1e-12)[0]
        v = np.zeros_like(x)
        phase0 = np.zeros(nm)
    else:
        try:
            q, qd = np.asarray(state["q"], float), np.asarray(state["qdot"], float)
            phase0 = np.asarray(state["phase"], float).reshape(nm)
        except (KeyError, TypeError, ValueError) as exc:
            raise InputError(
                "initial_state", type(state).__name__, f"a final_state() of system steady ({exc})"
            ) from None
        if q.shape != (box.n_dof,) or qd.shape != (box.n_dof,):
            raise InputError("initial_state.q", q.shape, f"{box.n_dof} DOFs (the same gearbox)")
        MP = M @ P
        x, v = MP.T @ q[free], MP.T @ qd[free]
    nu = wm / (2 * np.pi)
    ms = Meshes(ck, ce, nu, phase0, mats.c_mesh.copy(), np.array([m.backlash for m in box.meshes]), kmean, varying)
    static_force = np.array([m.gear.torque / m.gear.base_radius[0] for m in box.meshes])
    scale = float(np.max(static_force / kmean))  # the largest static deflection
    hist = {k: [] for k in ("dte", "d", "F", "E", "P")}
    clock = [0.0]  # time at the end of the blocks run [s]

    def advance(n_cycles):
        n = n_cycles * spc
        bufs = _buffers(n, r, nm)
        run_rk4(rd, ms, x, v, clock[0], dt, n, *bufs)
        for key, b in zip(("dte", "d", "F", "E", "P"), bufs[2:], strict=True):
            hist[key].append(b[:-1])  # the last sample starts the next block
        clock[0] += n * dt
        if not np.all(np.isfinite(x)):
            raise InputError("steady.steps_per_cycle", spc, "more steps per cycle (the integration diverged)")

    def last_dte():
        return np.concatenate(hist["dte"][-(8 // st.check_every + 2) :])[:, 0]  # >= the 8 cycles the test reads

    # gear steady's loop (whole blocks of check_every cycles, checked from min_cycles on)
    cycles, per = until_periodic(
        advance,
        lambda: _periodicity(last_dte(), spc, scale, st.tol),
        block=st.check_every,
        min_cycles=st.min_cycles,
        max_cycles=st.max_cycles,
        whole_blocks=True,
    )
    t0, period, change, dte = clock[0], per.period, per.change, last_dte()
    # evaluation cycles with full histories
    n = st.eval_cycles * spc
    bufs = _buffers(n, r, nm)
    run_rk4(rd, ms, x, v, t0, dt, n, *bufs)
    xs, vs, dte_e, d_e, F_e, E_e, P_e = bufs
    energy = np.concatenate([*hist["E"], E_e])
    power = np.concatenate([*hist["P"], P_e])
    if period == 0:  # the evaluated cycles may show a period the last block did not
        # dte_e[0] is the state the last block ended in (not in ``dte``): whole cycles, no gap
        per = _periodicity(np.concatenate([dte, dte_e[:-1, 0]]), spc, scale, st.tol)
        period, change = per.period, per.change
    # bearing forces from the physical displacements of the evaluated cycles
    Tfull = mats.expand(P)
    from rotaflex.system.assembly import bearing_matrices

    Kb, Cb = bearing_matrices(box, speed)
    brg, bf = [], []
    for ri, pr in enumerate(box.rotors):
        for node, other, _ in pr.rotor.bearings:
            rows = [box.lateral_dof(ri, node, 0), box.lateral_dof(ri, node, 1)]
            Tb = Tfull[rows]
            if other is not None:
                Tb = Tb - Tfull[[box.lateral_dof(ri, other, 0), box.lateral_dof(ri, other, 1)]]
            u, ud = xs @ Tb.T, vs @ Tb.T
            bf.append(-(u @ Kb[np.ix_(rows, rows)].T + ud @ Cb[np.ix_(rows, rows)].T))
            brg.append((pr.name, node))
    bf = np.stack(bf, 1) if bf else np.zeros((n + 1, 0, 2))
    # what the nominal mesh phase leaves out: the pinion's own twist in mesh cycles,
    # z_p s_p theta_p / (2 pi) (gear steady's phase follows the actual pinion angle)
    shift = np.zeros((n + 1, nm))
    for j, m in enumerate(box.meshes):
        rp, node = m.driver if m.pinion_is_driver else m.driven
        shift[:, j] = m.gear.teeth[0] * box.rotors[rp].sense * (xs @ Tfull[box.torsion_dof(rp, node)]) / (2 * np.pi)
    t_eval = t0 + dt * np.arange(n + 1)
    axial = axial_reactions(box, xs, vs, Tfull) if box.axial else None
    q_end = Tfull @ x
    qd_end = Tfull @ v
    return SteadyState(
        t_eval,
        dte_e,
        d_e,
        F_e,
        bf,
        brg,
        energy,
        power,
        dt,
        period,
        change,
        cycles + st.eval_cycles,
        spc,
        static_force,
        float(wm[0] / (2 * np.pi)),
        q_end,
        qd_end,
        (phase0 + nu * (t0 + n * dt)) % 1.0,
        r,
        shift,
        axial,
    )


def _buffers(n: int, r: int, nm: int):
    return (
        np.empty((n + 1, r)),
        np.empty((n + 1, r)),
        np.empty((n + 1, nm)),
        np.empty((n + 1, nm)),
        np.empty((n + 1, nm)),
        np.empty(n + 1),
        np.empty((n + 1, 2)),
    )
