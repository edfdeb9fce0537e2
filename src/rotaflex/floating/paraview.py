"""Deformed-shape time series for ParaView: one ``.vtu`` per output time plus a ``.pvd`` index.

Each frame holds the body's mass points at their inertial positions ``R + A (r + Phi q)`` (lines
between consecutive points for beams, vertices otherwise) with the elastic displacement
(body axes) as point data. Open ``<name>.pvd`` in ParaView and press play.
"""

from __future__ import annotations

from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

from rotaflex.floating.body import Body


def deformed_points(body: Body, dataset, solution: str):
    """Inertial positions (T, N, 3) and elastic displacements (T, N, 3) of the body's points."""
    from rotaflex.floating.solve import rotation_matrices

    sel = dataset.sel(solution=solution)
    q = sel["modal_displacement"].values
    u = np.einsum("kaj,tj->tka", body.shapes, q)
    A = rotation_matrices(sel["quaternion"].values)
    pos = sel["position"].values[:, None, :] + np.einsum("tab,tkb->tka", A, body.points[None] + u)
    return pos, u


def write_paraview(
    result, body: Body, out_dir, *, solution: str | None = None, every: int = 1, name: str = "floating"
) -> Path:
    """Write ``name_0000.vtu ...`` and ``name.pvd`` into ``out_dir``; returns the ``.pvd`` path.

    Parameters
    ----------
    result : FloatingResult
    body : Body
        The body the result was computed for.
    solution : str, optional
        ``"full"``, ``"perturbation"`` or ``"prescribed"`` (default: the first one).
    every : int
        Write every ``every``-th output time (>= 1).
    """
    import meshio

    from rotaflex.core.errors import InputError

    ds = result.dataset
    sols = [str(s) for s in ds["solution"].values]
    solution = solution or sols[0]
    if solution not in sols:
        raise InputError("solution", solution, "one of " + ", ".join(sols))
    if not (isinstance(every, int) and every >= 1):
        raise InputError("every", every, "an integer >= 1")
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    pos, u = deformed_points(body, ds, solution)
    t = ds["time"].values
    N = body.points.shape[0]
    line = body.name.startswith("uniform") and N > 1
    order = np.argsort(body.points[:, 0]) if line else np.arange(N)
    cells = [("line", np.column_stack([order[:-1], order[1:]]))] if line else [("vertex", np.arange(N)[:, None])]
    entries = []
    for i in range(0, len(t), every):
        if not np.all(np.isfinite(pos[i])):
            break  # an early stop leaves NaN rows: stop the series there
        fname = f"{name}_{i:05d}.vtu"
        meshio.write(
            out / fname,
            meshio.Mesh(pos[i], cells, point_data={"displacement": u[i]}),
            binary=True,
        )
        entries.append(f'    <DataSet timestep="{t[i]:.9g}" part="0" file={quoteattr(fname)}/>')
    pvd = out / f"{name}.pvd"
    pvd.write_text(
        '<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n  <Collection>\n'
        + "\n".join(entries)
        + "\n  </Collection>\n</VTKFile>\n"
    )
    return pvd
