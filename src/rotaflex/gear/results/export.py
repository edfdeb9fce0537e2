"""VTU export of tooth meshes and fields for ParaView (via meshio, written atomically)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from rotaflex.core.errors import InputError
from rotaflex.core.io import write_atomic

__all__ = ["write_vtu"]


def write_vtu(
    path: str | Path,
    mesh,
    displacement: np.ndarray | None = None,
    point_data: dict | None = None,
    cell_data: dict | None = None,
) -> Path:
    """Write a quad8 mesh with optional fields to a ``.vtu`` file (atomic).

    Parameters
    ----------
    path : str or Path
        Target file.
    mesh : ToothMesh
        Mesh (``nodes`` (n, 2) [m], ``elements`` (ne, 8)); written as VTK ``quad8`` cells with
        z = 0 points.
    displacement : ndarray, optional
        Interleaved DOF vector (2n,) or array (n, 2) [m], written as point vector
        ``"displacement"`` (3 components, z = 0) for ParaView's "Warp By Vector".
    point_data : dict, optional
        Extra nodal arrays, each (n,) or (n, k).
    cell_data : dict, optional
        Extra element arrays, each (ne,) or (ne, k).

    Returns
    -------
    Path
    """
    import meshio

    n, ne = mesh.nodes.shape[0], mesh.elements.shape[0]
    pts = np.column_stack([mesh.nodes, np.zeros(n)])
    pdata = {}
    if displacement is not None:
        d = np.asarray(displacement, dtype=float)
        if d.shape == (2 * n,):
            d = d.reshape(n, 2)
        if d.shape != (n, 2):
            raise InputError("displacement", d.shape, f"shape ({2 * n},) or ({n}, 2)")
        pdata["displacement"] = np.column_stack([d, np.zeros(n)])
    for k, v in (point_data or {}).items():
        v = np.asarray(v)
        if v.shape[0] != n:
            raise InputError(f"point_data.{k}", v.shape, f"first dimension {n}")
        pdata[k] = v
    cdata = {}
    for k, v in (cell_data or {}).items():
        v = np.asarray(v)
        if v.shape[0] != ne:
            raise InputError(f"cell_data.{k}", v.shape, f"first dimension {ne}")
        cdata[k] = [v]
    out = meshio.Mesh(pts, [("quad8", np.asarray(mesh.elements))], point_data=pdata, cell_data=cdata)
    return write_atomic(path, lambda p: meshio.write(p, out, file_format="vtu"))
