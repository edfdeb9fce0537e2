"""Size of a ``rotaflex system`` run, estimated before it starts, and the limits it is held to.

Each verb's solver calls its check as soon as the numbers it depends on are known and before
the large arrays are allocated: modal and Campbell at once (DOFs from the layout, the basis
bounded by the free DOFs), the TE response after its reduced basis (``r`` columns) is built,
the steady state after its steps per mesh cycle are chosen (automatic ones follow the fastest
mode of the reduced model). Counts go through :func:`rotaflex.core.limits.require`, memory
through :func:`rotaflex.core.limits.require_memory` (``--max-memory`` / ``ROTAFLEX_MAX_MEMORY``).

The DOF count itself is bounded per rotor by its ``max_dof`` (rotor/fe); the dense system
matrices of all rotors together are sized here. The byte estimates count the float64/complex128
arrays of the largest stage (tests compare them with the peak that tracemalloc measures).
"""

from __future__ import annotations

from rotaflex.core.limits import require, require_memory

__all__ = [
    "DEFAULT_MAX_STEPS",
    "campbell_size",
    "check_assembly",
    "check_campbell",
    "check_modal",
    "check_response",
    "check_steady",
    "clamp_modes",
    "modal_size",
    "response_size",
    "steady_size",
]

#: default of ``[steady] max_steps``: RK4 steps of one steady state (~40 us a step of the
#: example's 31-column reduced model on this 2-core machine: 1e7 steps is about 7 min)
DEFAULT_MAX_STEPS = 10_000_000


def _assembly_bytes(n_dof: int, n_rotors: int) -> float:
    """Dense M, K0, C0, one G per rotor, bearing K and C, and the free-DOF M, D, K copies."""
    return 8.0 * n_dof**2 * (8 + n_rotors)


def _eig_bytes(n: int) -> float:
    """One first-order eigenproblem of n DOFs: the real state matrix (2n)^2, M^-1 [K D],
    geev's real vectors and their complex copy, the eigenvalues."""
    s = (2 * n) ** 2
    return 8.0 * s + 8.0 * 2 * n * n + 8.0 * s + 16.0 * s + 16.0 * 2 * n


def clamp_modes(n_modes: int, n_free: int, field: str) -> tuple[int, str]:
    """``n_modes`` clamped to the free DOF count (a model of n free DOFs has at most n
    oscillatory modes), and a note saying so (empty when nothing was clamped)."""
    if n_modes <= n_free:
        return n_modes, ""
    return n_free, f"{field} = {n_modes} clamped to {n_free} (the gearbox has {n_free} free DOFs)"


def modal_size(n_dof: int, n_free: int, n_rotors: int) -> dict:
    """``dofs``, ``bytes`` (peak of the assembly plus one full eigenproblem) of ``system modal``."""
    return {"dofs": n_dof, "bytes": _assembly_bytes(n_dof, n_rotors) + _eig_bytes(n_free)}


def campbell_size(n_dof: int, n_free: int, n_rotors: int, n_speeds: int, n_modes: int, basis: int) -> dict:
    """``dofs``, ``eigenproblems`` (speeds), ``output points`` (speeds x modes) and ``bytes`` of
    ``system campbell``: the assembly, one eigenproblem of ``basis`` DOFs, the tracked complex
    shapes (speeds x modes x DOFs) and the four arrays of that size the energy split makes."""
    shapes = 16.0 * n_speeds * n_modes * n_dof
    return {
        "dofs": n_dof,
        "eigenproblems": n_speeds,
        "points": n_speeds * n_modes,
        "bytes": _assembly_bytes(n_dof, n_rotors) + _eig_bytes(basis) + 5 * shapes,
    }


def response_size(n_speeds: int, harmonics: int, basis: int, n_mesh: int, n_bearings: int, n_probes: int) -> dict:
    """``solves`` (speeds x harmonics per mesh), ``points`` (outputs: meshes x speeds x
    harmonics) and ``bytes`` of ``system response`` once its basis (``basis`` columns) is known:
    the per-speed damping (and bearing damping) matrices, the complex system matrices of all
    speeds and harmonics with the real temporary that fills them, the solutions, and the
    outputs with the bearing-force temporaries."""
    ns, nh, r = n_speeds, harmonics, basis
    points = n_mesh * ns * nh
    outputs = points * (8.0 + 3 * 16.0 + 2 * 16.0 * (n_bearings + n_probes))
    temps = ns * nh * (16.0 * r + 3 * 2 * 16.0 * n_bearings)
    return {
        "solves": ns * nh,
        "points": points,
        "bytes": 8.0 * ns * r * r * (2 + 3 * nh) + temps + outputs,
    }


def steady_size(max_cycles: int, check_every: int, eval_cycles: int, spc: int, basis: int, n_mesh: int, nb: int):
    """``cycles`` (at most: ``max_cycles`` rounded up to whole checks, plus the evaluated ones),
    ``steps`` (RK4 steps at most), ``points`` (evaluated samples) and ``bytes`` of one steady
    state: the run's histories (DTE, deflection, force per mesh, energy and two powers, every
    step, kept for the energy balance) with the joined copy of energy and powers, and the
    evaluated cycles' buffers (states, rates, bearing forces)."""
    run = -(-max_cycles // check_every) * check_every
    cycles = run + eval_cycles
    per_run_step = 8.0 * (3 * n_mesh + 3 + 3)  # kept histories; energy and powers joined at the end
    # each block of check_every cycles keeps five array views, their headers and list slots:
    # measured 1.3-1.8 kB (tracemalloc, 10 cycles x 32 steps)
    per_block = 2048.0
    n_eval = eval_cycles * spc + 1
    per_eval = 8.0 * (4 * basis + 3 * n_mesh + 3 + 3 * 2 * nb + 2 * n_mesh)
    return {
        "cycles": cycles,
        "steps": cycles * spc,
        "points": n_eval,
        "bytes": run * spc * per_run_step + run // check_every * per_block + n_eval * per_eval,
    }


def check_assembly(box) -> None:
    """Refuse a gearbox whose dense system matrices alone exceed the memory limit, blaming the
    rotor with the most DOFs (its shaft elements)."""
    i = max(range(len(box.rotors)), key=lambda k: box.layout[k][1] + box.layout[k][2])
    shafts = box.spec.rotor[i].shaft
    j = max(range(len(shafts)), key=lambda k: shafts[k].elements)  # the section to coarsen first
    field = f"rotor[{i}].shaft[{j}].elements"
    require_memory(
        field, shafts[j].elements, _assembly_bytes(box.n_dof, len(box.rotors)), f"the {box.n_dof}-DOF system matrices"
    )


def check_modal(n_dof: int, n_free: int, n_rotors: int, field: str, value) -> dict:
    """Refuse a modal solve beyond the memory limit; returns :func:`modal_size`."""
    size = modal_size(n_dof, n_free, n_rotors)
    require_memory(field, value, size["bytes"], f"the {n_free}-DOF eigenproblem")
    return size


def check_campbell(n_dof, n_free, n_rotors, n_speeds, n_modes, basis) -> dict:
    """Refuse a Campbell diagram beyond the memory limit, blaming the larger of the speed and
    mode counts; returns :func:`campbell_size`."""
    size = campbell_size(n_dof, n_free, n_rotors, n_speeds, n_modes, basis)
    key, value = ("campbell.n_speeds", n_speeds) if n_speeds >= n_modes else ("campbell.n_modes", n_modes)
    require_memory(key, value, size["bytes"], "the eigenproblems and the tracked mode shapes")
    return size


def check_response(n_speeds, harmonics, basis, n_mesh, n_bearings, n_probes, cutoff) -> dict:
    """Refuse a TE response beyond the memory limit (blame: ``response.n_speeds``, or
    ``response.cutoff`` when the basis is the whole model); returns :func:`response_size`."""
    size = response_size(n_speeds, harmonics, basis, n_mesh, n_bearings, n_probes)
    key, value = ("response.n_speeds", n_speeds)
    if cutoff is None and n_speeds * harmonics < basis * basis:
        key, value = "response.cutoff", "none"
    require_memory(key, value, size["bytes"], f"{n_speeds} x {harmonics} complex solves of {basis} DOFs")
    return size


def check_steady(st, spc: int, basis: int, n_mesh: int, nb: int, max_steps: int) -> dict:
    """Refuse a steady state beyond ``max_steps`` RK4 steps or the memory limit, blaming the
    larger factor (``steady.max_cycles`` or ``steady.steps_per_cycle``); returns :func:`steady_size`."""
    size = steady_size(st.max_cycles, st.check_every, st.eval_cycles, spc, basis, n_mesh, nb)
    if spc > size["cycles"]:
        key, value = "steady.steps_per_cycle", st.steps_per_cycle or f"automatic ({spc})"
    elif st.eval_cycles > st.max_cycles:
        key, value = "steady.eval_cycles", st.eval_cycles
    else:
        key, value = "steady.max_cycles", st.max_cycles
    require(
        key,
        value,
        size["steps"],
        max_steps,
        f"RK4 steps ((max_cycles + eval_cycles) x {spc} steps per cycle)",
        "raise [steady] max_steps if you mean it",
    )
    require_memory(key, value, size["bytes"], "the histories of one steady state")
    return size
