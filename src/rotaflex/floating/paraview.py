"""Deformed-shape time series for ParaView: one ``.vtu`` per output time plus a ``.pvd`` index.

Each frame holds the body's mass points at their inertial positions ``R + A (r + u)`` with the
elastic displacement ``u = Phi q`` (body axes; with the inextensible kinematics plus the axial
shortening) as point data: lines between consecutive points for beams, vertices otherwise.
Open ``<name>.pvd`` in ParaView and press play.

:func:`frames` computes the series from a result and its body (plain arrays, picklable, so a
result can carry them to :meth:`FloatingResult.write_extra`); :func:`write_frames` writes them;
:func:`write_paraview` does both.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

from rotaflex.floating.body import Body


@dataclass(frozen=True)
class Frames:
    """A deformed-shape series: times [s] (T,), positions [m] (T, N, 3) (inertial),
    displacements [m] (T, N, 3) (body axes) and the cells (``"line"`` or ``"vertex"``, index
    array)."""

    time: np.ndarray
    positions: np.ndarray
    displacements: np.ndarray
    cells: list


def deformed_points(body: Body, dataset, solution: str):
    """Inertial positions (T, N, 3) and elastic displacements (T, N, 3) of the body's points."""
    from rotaflex.floating.solve import rotation_matrices

    sel = dataset.sel(solution=solution)
    q = sel["modal_displacement"].values
    u = np.einsum("kaj,tj->tka", body.shapes, q)
    if dataset.attrs.get("kinematics") == "inextensible" and body.inextensible is not None:
        ok = np.isfinite(q).all(axis=1)
        u[ok, :, 0] += body.inextensible.shortening(body.points[:, 0], q[ok])
    A = rotation_matrices(sel["quaternion"].values)
    pos = sel["position"].values[:, None, :] + np.einsum("tab,tkb->tka", A, body.points[None] + u)
    return pos, u


def frames(result, body: Body, *, solution: str | None = None, every: int = 1) -> Frames:
    """The deformed-shape series of ``result`` (every ``every``-th output time, up to an early
    stop) for the body it was computed for.

    Parameters
    ----------
    result : FloatingResult
    body : Body
    solution : str, optional
        ``"full"``, ``"perturbation"`` or ``"prescribed"`` (default: the first one).
    every : int
        Keep every ``every``-th output time (>= 1).
    """
    from rotaflex.core.errors import InputError

    ds = result.dataset
    sols = [str(s) for s in ds["solution"].values]
    solution = solution or sols[0]
    if solution not in sols:
        raise InputError("solution", solution, "one of " + ", ".join(sols))
    if not (isinstance(every, int) and every >= 1):
        raise InputError("every", every, "an integer >= 1")
    pos, u = deformed_points(body, ds, solution)
    keep = np.arange(0, len(ds["time"]), every)
    finite = np.isfinite(pos[keep]).all(axis=(1, 2))
    if not finite.all():  # an early stop leaves NaN rows: stop the series there
        keep = keep[: int(np.argmin(finite))]
    N = body.points.shape[0]
    line = body.name.startswith("uniform") and N > 1
    order = np.argsort(body.points[:, 0]) if line else np.arange(N)
    cells = [("line", np.column_stack([order[:-1], order[1:]]))] if line else [("vertex", np.arange(N)[:, None])]
    return Frames(ds["time"].values[keep], pos[keep], u[keep], cells)


def write_frames(series: Frames, out_dir, name: str = "floating") -> list[Path]:
    """Write ``name_00000.vtu ...`` and ``name.pvd`` into ``out_dir``; returns the paths, the
    ``.pvd`` last."""
    import meshio

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    paths, entries = [], []
    for i, t in enumerate(series.time):
        fname = f"{name}_{i:05d}.vtu"
        mesh = meshio.Mesh(series.positions[i], series.cells, point_data={"displacement": series.displacements[i]})
        meshio.write(out / fname, mesh, binary=True)
        paths.append(out / fname)
        entries.append(f'    <DataSet timestep="{t:.9g}" part="0" file={quoteattr(fname)}/>')
    pvd = out / f"{name}.pvd"
    pvd.write_text(
        '<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n  <Collection>\n'
        + "\n".join(entries)
        + "\n  </Collection>\n</VTKFile>\n"
    )
    return paths + [pvd]


def write_paraview(
    result, body: Body, out_dir, *, solution: str | None = None, every: int = 1, name: str = "floating"
) -> Path:
    """Write ``name_00000.vtu ...`` and ``name.pvd`` into ``out_dir``; returns the ``.pvd`` path.

    Parameters
    ----------
    result : FloatingResult
    body : Body
        The body the result was computed for.
    solution : str, optional
        ``"full"``, ``"perturbation"`` or ``"prescribed"`` (default: the first one).
    every : int
        Write every ``every``-th output time (>= 1).

    From a case file: ``[paraview]`` (``rotaflex floating simulate`` writes the series into
    ``<out>/paraview/``).
    """
    return write_frames(frames(result, body, solution=solution, every=every), out_dir, name)[-1]
