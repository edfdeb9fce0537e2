"""User structures from files: nodes, masses and mass-normalised modes in a NumPy ``.npz`` or
HDF5 file (``.h5``/``.hdf5``: the same arrays as root-level datasets of the same names).

Layout (SI units, arrays stored under these names; ``N`` nodes, ``n`` elastic modes)::

    positions        (N, 3)     node coordinates in the body frame [m]
    masses           (N,)       nodal masses [kg], > 0
    shapes           (n, N, 3)  mode j translation at node k [1/sqrt(kg)], mass-normalised:
                                sum_k m_k shapes[i, k] . shapes[j, k] = delta_ij
    frequencies      (n,)       natural frequencies [rad/s], > 0 (rigid-body modes left out)
    rotation_shapes  (n, N, 3)  optional: mode j rotation at node k [rad/sqrt(kg)] (needed for
                                torques at nodes)
    rotary_inertias  (N, 3)     optional: principal rotary inertias of the nodes [kg m^2]

The same data as one CSV file (``.csv``): a comment line ``# frequencies: w1, w2, ...`` [rad/s],
then a header row and one row per node, comma-separated, columns by name (any order)::

    x, y, z, mass                 node coordinates [m] and nodal mass [kg]
    jx, jy, jz                    optional: principal rotary inertias [kg m^2]
    phi1_x, phi1_y, phi1_z, ...   mode j translations (j = 1 .. n) [1/sqrt(kg)]
    psi1_x, psi1_y, psi1_z, ...   optional: mode j rotations [rad/sqrt(kg)] (all modes or none)

Mass normalisation: either with the translational masses alone (``sum_k m_k phi_ik . phi_jk =
delta_ij``; rotary inertias then count only in the rigid-body inertia) or, when the file has
``rotation_shapes`` and ``rotary_inertias``, with the full lumped mass matrix of an FE export
(``sum_k m_k phi_ik . phi_jk + psi_ik . J_k psi_jk = delta_ij``). The loader detects which one
holds. In the second case each node's rotary inertia is carried by six satellite point masses at
``+-d e_a`` moving rigidly with the node (``u + psi x s``), which reproduce ``J_k`` exactly in the
modal mass and in every inertia integral of the floating-body equations (the FE frame's section
points work the same way).

Checks on load (each one :class:`~rotaflex.core.errors.InputError` naming ``body.file.<array>``):
shapes and sizes, finite values, masses and frequencies > 0, mass-orthonormality (deviation
<= 1e-6), and for ``frame = "mean-axes"`` no rigid-body content (free-free modes must satisfy
``sum m phi = 0`` and ``sum m r x phi = 0`` to 1e-6 relative: a rigid mode left in the file, or
modes of a constrained model, fail here).
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from rotaflex.core.errors import InputError
from rotaflex.floating.body import Body, point_body

REQUIRED = ("positions", "masses", "shapes", "frequencies")
OPTIONAL = ("rotation_shapes", "rotary_inertias")
RIGID_TOL = 1e-6
HDF5 = (".h5", ".hdf5")


def load_modes(path, frame: str = "mean-axes", where: str = "body.file") -> Body:
    """A :class:`Body` from an ``.npz`` file with the layout of the module docstring.

    Parameters
    ----------
    path : str or Path
        The file.
    frame : {"mean-axes", "attached"}
        "mean-axes": free-free modes, checked for rigid-body content. "attached": modes of a
        structure clamped to the body frame (no rigid-body check).
    where : str
        Config path used in error messages.
    """
    p = Path(path)
    if p.suffix.lower() not in (".npz", ".csv", *HDF5):
        raise InputError(f"{where}.path", str(path), "a NumPy .npz, an HDF5 .h5/.hdf5 or a .csv file")
    if not p.is_file():
        raise InputError(f"{where}.path", str(path), f"an existing {p.suffix.lower()} file")
    if frame not in ("mean-axes", "attached"):
        raise InputError(f"{where}.frame", frame, "'mean-axes' or 'attached'")
    if p.suffix.lower() == ".csv":
        data, extra = _read_csv(p, where), []
    elif p.suffix.lower() in HDF5:
        data, extra = _read_hdf5(p, where)
    else:
        data, extra = _read_npz(p, where)
    body = _checked_body(data, extra, frame, where, p.name)
    return dataclasses.replace(body, params={"source": "load_modes", "path": str(p), "frame": frame})


def _read_npz(p: Path, where: str):
    import zipfile
    import zlib

    if p.is_file() and p.stat().st_size == 0:
        raise InputError(f"{where}.path", str(p), "a readable .npz file (this one is empty)")
    try:
        z = np.load(p, allow_pickle=False)
        if not hasattr(z, "files"):  # a bare .npy saved under an .npz name
            raise ValueError("a single array, not an archive of named arrays")
        with z:
            data = {k: np.asarray(z[k], dtype=float) for k in z.files if k in REQUIRED + OPTIONAL}
            extra = [k for k in z.files if k not in REQUIRED + OPTIONAL]
    # a truncated archive fails in zipfile (BadZipFile), zlib or with EOFError, depending on where it ends
    except (OSError, ValueError, EOFError, zipfile.BadZipFile, zlib.error) as exc:
        why = (str(exc).splitlines() or [""])[0] or type(exc).__name__
        if isinstance(exc, (EOFError, zipfile.BadZipFile, zlib.error)):
            why = f"truncated or not a zip archive: {why}"
        raise InputError(f"{where}.path", str(p), f"a readable .npz file ({why})") from None
    return data, extra


def _read_hdf5(p: Path, where: str):
    import h5py  # installed with h5netcdf, the NetCDF writer

    try:
        with h5py.File(p, "r") as f:
            names = list(f.keys())
            data = {}
            for k in names:
                if k not in REQUIRED + OPTIONAL:
                    continue
                if not isinstance(f[k], h5py.Dataset):
                    raise InputError(f"{where}.{k}", str(p), "a dataset at the file's root (found a group)")
                data[k] = np.asarray(f[k][()], dtype=float)
    except (OSError, ValueError, TypeError) as exc:
        raise InputError(f"{where}.path", str(p), f"a readable HDF5 file ({exc})") from None
    return data, [k for k in names if k not in REQUIRED + OPTIONAL]


def _read_csv(p: Path, where: str) -> dict:
    """The arrays of the CSV layout (module docstring)."""
    try:
        lines = p.read_text(encoding="utf-8").splitlines()
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"{where}.path", str(p), f"a readable UTF-8 .csv file ({exc})") from None
    freq = [ln for ln in lines if ln.lstrip().startswith("#") and "frequencies" in ln]
    rows = [ln for ln in lines if ln.strip() and not ln.lstrip().startswith("#")]
    if not freq:
        raise InputError(f"{where}.frequencies", "<missing>", "a line '# frequencies: w1, w2, ...' [rad/s]")
    if len(rows) < 2:
        raise InputError(f"{where}.path", str(p), "a header row and one row per node")
    head = [h.strip() for h in rows[0].split(",")]
    try:
        f = np.array([float(v) for v in freq[0].split(":", 1)[1].split(",") if v.strip()])
        table = np.array([[float(v) for v in r.split(",")] for r in rows[1:]])
    except (ValueError, IndexError) as exc:
        raise InputError(f"{where}.path", str(p), f"numbers in every row and the frequencies line ({exc})") from None
    if table.shape[1] != len(head):
        raise InputError(f"{where}.path", f"{table.shape[1]} values per row", f"{len(head)} (one per header column)")
    col = {h: table[:, i] for i, h in enumerate(head)}

    def block(names, field):
        missing = [c for c in names if c not in col]
        if missing:
            raise InputError(f"{where}.{field}", "<missing>", f"columns {', '.join(missing)}")
        return np.column_stack([col[c] for c in names])

    n = len(f)
    data = {
        "positions": block(["x", "y", "z"], "positions"),
        "masses": block(["mass"], "masses")[:, 0],
        "frequencies": f,
        "shapes": np.array([block([f"phi{j}_{a}" for a in "xyz"], f"shapes[{j - 1}]") for j in range(1, n + 1)]),
    }
    if any(c.startswith("j") for c in col):
        data["rotary_inertias"] = block(["jx", "jy", "jz"], "rotary_inertias")
    if any(c.startswith("psi") for c in col):
        data["rotation_shapes"] = np.array(
            [block([f"psi{j}_{a}" for a in "xyz"], f"rotation_shapes[{j - 1}]") for j in range(1, n + 1)]
        )
    known = {"x", "y", "z", "mass", "jx", "jy", "jz"} | {
        f"{c}{j}_{a}" for c in ("phi", "psi") for j in range(1, n + 1) for a in "xyz"
    }
    unknown = [h for h in head if h not in known]
    if unknown:
        raise InputError(
            f"{where}.{unknown[0]}", "unknown column", f"x, y, z, mass, jx.., phi1_x.. psi{n}_z for {n} frequencies"
        )
    return data


def _checked_body(data: dict, extra: list, frame: str, where: str, name: str) -> Body:
    if extra:
        raise InputError(f"{where}.{extra[0]}", "unknown array", "only " + ", ".join(REQUIRED + OPTIONAL))
    for k in REQUIRED:
        if k not in data:
            raise InputError(f"{where}.{k}", "<missing>", f"an array '{k}' in the file")
    for k, a in data.items():
        if not np.all(np.isfinite(a)):
            raise InputError(f"{where}.{k}", "non-finite values", "finite numbers")
    X, m, S, f = data["positions"], data["masses"], data["shapes"], data["frequencies"]
    N = m.size
    if m.ndim != 1 or X.shape != (N, 3):
        raise InputError(f"{where}.positions", f"shape {X.shape}", f"shape ({N}, 3) for {N} masses")
    if S.ndim != 3 or S.shape[1:] != (N, 3):
        raise InputError(f"{where}.shapes", f"shape {S.shape}", f"shape (n_modes, {N}, 3)")
    if np.any(m <= 0):
        k = int(np.argmin(m))
        raise InputError(f"{where}.masses[{k}]", float(m[k]), "a nodal mass > 0 [kg]")
    n = S.shape[0]
    if f.shape != (n,):
        raise InputError(f"{where}.frequencies", f"shape {f.shape}", f"shape ({n},)")
    if np.any(f <= 0):
        k = int(np.argmin(f))
        raise InputError(
            f"{where}.frequencies[{k}]",
            float(f[k]),
            "a frequency > 0 [rad/s] (leave the rigid-body modes out of the file)",
        )
    if _full_mass_normalised(data):
        data = _with_rotary_satellites(data, where)
        X, m, S = data["positions"], data["masses"], data["shapes"]
    if frame == "mean-axes" and n:
        # rigid-body content of each mode relative to its own mass-weighted size
        lin = np.einsum("k,jka->ja", m, S)
        ang = np.einsum("k,jka->ja", m, np.cross(X[None] - (m @ X / m.sum())[None, None], S))
        scale_l = np.sqrt(m.sum())
        scale_a = np.sqrt(m @ np.sum((X - m @ X / m.sum()) ** 2, axis=1)) + 1e-300
        rel = np.maximum(np.linalg.norm(lin, axis=1) / scale_l, np.linalg.norm(ang, axis=1) / scale_a)
        if rel.max() > RIGID_TOL:
            j = int(np.argmax(rel))
            raise InputError(
                f"{where}.shapes[{j}]",
                f"rigid-body content {rel[j]:.3g}",
                f"free-free elastic modes in mean axes (rigid content <= {RIGID_TOL:g}; "
                "use frame = 'attached' for modes of a clamped structure)",
            )
    try:
        return point_body(
            m,
            X,
            S,
            frequencies=f,
            rotation_shapes=data.get("rotation_shapes"),
            rotary_inertias=data.get("rotary_inertias"),
            name=f"modes from {name}",
        )
    except InputError as exc:  # point_body names body.points.<array>, the file's own array names
        fld = exc.field
        if fld.startswith("body.points."):
            fld = f"{where}." + fld[len("body.points.") :]
        raise InputError(fld, exc.value, exc.allowed) from None


def _full_mass_normalised(data: dict) -> bool:
    """True when the modes are orthonormal with translational *and* rotary mass, but not with
    the translational masses alone."""
    if "rotation_shapes" not in data or "rotary_inertias" not in data:
        return False
    m, S, R, J = data["masses"], data["shapes"], data["rotation_shapes"], data["rotary_inertias"]
    if R.shape != S.shape or J.shape != (m.size, 3):
        return False  # the shape checks of point_body report it
    eye = np.eye(S.shape[0])
    trans = np.einsum("k,ika,jka->ij", m, S, S)
    full = trans + np.einsum("ka,ika,jka->ij", J, R, R)
    return np.abs(full - eye).max() < np.abs(trans - eye).max()


def _with_rotary_satellites(data: dict, where: str) -> dict:
    """Nodes plus six satellite masses each (``m_a / 2`` at ``+-d e_a``) that carry the nodal
    principal rotary inertia J: ``m_x = (J_y + J_z - J_x) / (2 d^2)`` and cyclic (>= 0 by the
    triangle inequality), ``d^2 = (J_x + J_y + J_z) / m`` so that half the nodal mass stays on
    the node."""
    X, m, S, R, J = (data[k] for k in ("positions", "masses", "shapes", "rotation_shapes", "rotary_inertias"))
    tr = J.sum(axis=1)
    d = np.sqrt(np.where(tr > 0, tr / m, 0.0))
    ma = np.stack([J[:, 1] + J[:, 2] - J[:, 0], J[:, 0] + J[:, 2] - J[:, 1], J[:, 0] + J[:, 1] - J[:, 2]], axis=1)
    ma = np.where(tr[:, None] > 0, ma / (2.0 * np.where(d > 0, d, 1.0)[:, None] ** 2), 0.0)
    if np.any(ma < -1e-12 * tr[:, None]):
        k = int(np.argmin(ma.min(axis=1)))
        raise InputError(f"{where}.rotary_inertias[{k}]", J[k].tolist(), "principal inertias with J_a <= J_b + J_c")
    ma = np.maximum(ma, 0.0)
    pts, mass, shp, rot = [X], [m - ma.sum(axis=1)], [S], [R]
    for a in range(3):
        for sign in (1.0, -1.0):
            off = np.zeros(3)
            off[a] = sign
            o = d[:, None] * off[None]  # (N, 3)
            pts.append(X + o)
            mass.append(0.5 * ma[:, a])
            shp.append(S + np.cross(R, o[None]))  # u + psi x s
            rot.append(R)
    keep = np.concatenate([np.ones(len(m), bool)] + [0.5 * ma[:, a] > 0 for a in range(3) for _ in (0, 1)])
    out = dict(data)
    out.pop("rotary_inertias")
    out["positions"] = np.concatenate(pts)[keep]
    out["masses"] = np.concatenate(mass)[keep]
    out["shapes"] = np.concatenate(shp, axis=1)[:, keep]
    out["rotation_shapes"] = np.concatenate(rot, axis=1)[:, keep]
    return out


def save_modes(path, body: Body, rotation_shapes: bool = True) -> None:
    """Write ``body`` (its mass points and modes) in the ``.npz`` layout, as HDF5 datasets if
    ``path`` ends in ``.h5``/``.hdf5``, or the CSV layout if it ends in ``.csv`` (for
    exchange/tests). Rotation shapes are written only where the
    body defines them at its points; rotary inertias are not written."""
    arrays = {
        "positions": body.points,
        "masses": body.masses,
        "shapes": np.transpose(body.shapes, (2, 0, 1)),
        "frequencies": np.sqrt(np.diag(body.stiffness)),
    }
    if rotation_shapes:
        _, Psi = body.shape_fn(body.points)
        if np.all(np.isfinite(Psi)):
            arrays["rotation_shapes"] = np.transpose(Psi, (2, 0, 1))
    if str(path).lower().endswith(".csv"):
        n = arrays["shapes"].shape[0]
        cols = {"x": arrays["positions"][:, 0], "y": arrays["positions"][:, 1], "z": arrays["positions"][:, 2]}
        cols["mass"] = arrays["masses"]
        for key, pre in (("shapes", "phi"), ("rotation_shapes", "psi")):
            for j in range(n if key in arrays else 0):
                for i, a in enumerate("xyz"):
                    cols[f"{pre}{j + 1}_{a}"] = arrays[key][j, :, i]
        table = np.column_stack(list(cols.values()))
        head = "# frequencies: " + ", ".join(f"{w:.17g}" for w in arrays["frequencies"])
        np.savetxt(path, table, delimiter=",", header=",".join(cols), comments="", fmt="%.17g")
        text = Path(path).read_text(encoding="utf-8")
        Path(path).write_text(head + "\n" + text, encoding="utf-8")
        return
    if str(path).lower().endswith(HDF5):
        import h5py

        with h5py.File(path, "w") as f:
            for k, a in arrays.items():
                f.create_dataset(k, data=a)
        return
    np.savez(path, **arrays)
