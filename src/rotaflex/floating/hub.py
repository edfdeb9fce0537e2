"""A rigid hub with flexible appendages as one body, its frequencies, and rest-to-rest slews.

The spacecraft engineer's first model: a hub (rigid body of mass ``m_h`` and inertia ``I_h``
about its centre, the body origin) carrying one or more appendages clamped at their roots. Each
appendage is an attached-frame body (a cantilever :func:`~rotaflex.floating.beam.uniform_beam`,
e.g. from :func:`beam_appendage` with material and section, or
:func:`~rotaflex.floating.modes_file.load_modes` with ``frame = "attached"``) placed at ``root``
with its local x axis along ``direction``. The combined body uses the hub frame: the appendage
modes are clamped modes (the constrained modes), and the floating-body equations couple them
with the hub's rigid motion, which gives the unconstrained (free-hub) frequencies
(:func:`free_frequencies`).

A rest-to-rest slew by an angle in a given time is either prescribed motion of the hub
(:class:`~rotaflex.floating.model.Prescribed` with a ``bang-bang`` or ``versine`` profile) or the
torque that would make the rigid body follow the same profile (:func:`slew_torque`).
"""

from __future__ import annotations

import numpy as np

from rotaflex.core.errors import InputError
from rotaflex.floating.beam import uniform_beam
from rotaflex.floating.body import Body, check_inertia, integrals, plain, rigid_body
from rotaflex.floating.model import Load


def beam_appendage(
    length: float,
    e: float,
    rho: float,
    n_modes: int,
    *,
    width: float | None = None,
    thickness: float | None = None,
    area: float | None = None,
    second_moment: float | None = None,
    spatial: bool = False,
    where: str = "body.hub.appendages[0]",
) -> Body:
    """A uniform cantilever appendage from material and section.

    Parameters
    ----------
    length : float
        Length [m].
    e, rho : float
        Young's modulus [Pa] and density [kg/m^3].
    n_modes : int
        Clamped bending modes per plane.
    width, thickness : float, optional
        Rectangular section [m]: ``thickness`` along the in-plane deflection (body y after
        placement along x), ``I = width thickness^3 / 12`` (out of plane, spatial beams:
        ``thickness width^3 / 12``).
    area, second_moment : float, optional
        Or the section area [m^2] and second moment [m^4] directly (spatial: the same for both
        planes).
    spatial : bool
        Bending in both planes (default: in the slew plane only).
    where : str
        Config path for error messages.

    Returns
    -------
    Body
        A cantilever beam along local x from the origin.

    Examples
    --------
    >>> b = beam_appendage(2.0, 70e9, 2700.0, 3, width=0.1, thickness=0.005)
    >>> round(float(b.mass), 3)
    2.7
    """
    for key, v in (("length", length), ("e", e), ("rho", rho)):
        if v is None or not (np.isfinite(v) and v > 0):
            raise InputError(f"{where}.{key}", v, "a number > 0")
    area, i_y, i_z = section(width, thickness, area, second_moment, where)
    b = uniform_beam(length, rho * area, e * i_y, n_modes, ei_z=e * i_z, spatial=spatial, support="cantilever")
    return b


def section(width, thickness, area, second_moment, where: str) -> tuple[float, float, float]:
    """Area [m^2] and second moments in and out of the slew plane [m^4] of an appendage section:
    rectangular (``width`` out of plane, ``thickness`` in plane) or ``area``/``second_moment``
    given (the same in both planes); errors name ``where.<key>``."""
    rect = width is not None or thickness is not None
    direct = area is not None or second_moment is not None
    if rect == direct or (rect and (width is None or thickness is None)) or (direct and None in (area, second_moment)):
        raise InputError(
            f"{where}.width",
            width,
            "either width and thickness (rectangular section) or area and second_moment, not both",
        )
    for key, v in (("width", width), ("thickness", thickness), ("area", area), ("second_moment", second_moment)):
        if v is not None and not (np.isfinite(v) and v > 0):
            raise InputError(f"{where}.{key}", v, "a number > 0")
    if rect:
        return width * thickness, width * thickness**3 / 12.0, thickness * width**3 / 12.0
    return area, second_moment, second_moment


def _frame_to(direction, where: str) -> np.ndarray:
    """Rotation whose columns are the appendage's local x, y, z in hub axes: x along
    ``direction``, z as close to hub z as possible (so a planar appendage deflects in the hub's
    x-y plane, the slew plane of a slew about z)."""
    d = np.asarray(direction, dtype=float)
    nd = float(np.linalg.norm(d))
    if d.shape != (3,) or not nd > 0 or not np.isfinite(nd):
        raise InputError(f"{where}.direction", plain(d), "a non-zero vector [x, y, z]")
    x = d / nd
    ref = np.array([0.0, 0.0, 1.0]) if abs(x[2]) < 0.9 else np.array([0.0, 1.0, 0.0])
    y = np.cross(ref, x)
    y /= np.linalg.norm(y)
    return np.column_stack([x, y, np.cross(x, y)])


def hub_body(
    mass: float,
    inertia,
    appendages=(),
    *,
    radius: float = 0.0,
    name: str = "hub",
) -> Body:
    """A rigid hub with flexible appendages as one body (hub frame, clamped appendage modes).

    Parameters
    ----------
    mass : float
        Hub mass [kg] (> 0), at the hub centre (the body origin).
    inertia : float, array (3,) or (3, 3)
        Hub inertia about its centre [kg m^2]: one number (the same about every axis), principal
        moments about x, y, z, or the tensor.
    appendages : sequence of (Body, root, direction)
        Each an attached-frame body along its local x from its origin, clamped at ``root`` [m]
        (hub axes) with local x along ``direction``.
    radius : float
        Hub radius [m]: load and output points with ``|r| <= radius`` are on the rigid hub.
    name : str

    Returns
    -------
    Body
        Modes ``app<i>_<label>`` of every appendage (mass-orthonormal, block-diagonal
        stiffness: the constrained modes). Without appendages, a rigid body.

    Examples
    --------
    >>> b = hub_body(50.0, 5.0, [(beam_appendage(2.0, 70e9, 2700.0, 2, width=0.1, thickness=0.005),
    ...                          (0.5, 0.0, 0.0), (1.0, 0.0, 0.0))], radius=0.5)
    >>> b.n_modes, round(float(b.mass), 2)
    (2, 52.7)
    """
    if not (np.isfinite(mass) and mass > 0):
        raise InputError("body.hub.mass", mass, "a mass > 0 [kg]")
    J = np.asarray(inertia, dtype=float)
    J = J * np.eye(3) if J.ndim == 0 else (np.diag(J) if J.shape == (3,) else J)
    if J.shape != (3, 3):
        raise InputError("body.hub.inertia", plain(inertia), "one number, three principal moments or a 3 x 3 tensor")
    check_inertia(J, "body.hub.inertia")
    if not (np.isfinite(radius) and radius >= 0):
        raise InputError("body.hub.radius", radius, "a radius >= 0 [m]")
    if len(appendages) == 0:
        return rigid_body(mass, J, name=name)
    masses, points, blocks, labels, frames, extra = [np.array([float(mass)])], [np.zeros((1, 3))], [], [], [], J.copy()
    size = radius
    for i, (app, root, direction) in enumerate(appendages):
        where = f"body.hub.appendages[{i}]"
        if app.frame.startswith("mean axes"):
            raise InputError(
                f"{where}", app.name, "an attached-frame appendage (cantilever beam or frame = 'attached')"
            )
        R = _frame_to(direction, where)
        r0 = np.asarray(root, dtype=float)
        if r0.shape != (3,) or not np.all(np.isfinite(r0)):
            raise InputError(f"{where}.root", plain(root), "a point [x, y, z] in hub axes [m]")
        masses.append(app.masses)
        points.append(r0 + app.points @ R.T)
        blocks.append(np.einsum("ab,kbj->kaj", R, app.shapes))
        labels += [f"app{i + 1}_{lab}" for lab in (app.mode_labels or [f"mode{j + 1}" for j in range(app.n_modes)])]
        extra = extra + R @ app.extra_inertia @ R.T
        frames.append((app, R, r0))
        size = max(size, float(np.linalg.norm(points[-1], axis=1).max()))
    n_tot = sum(b.shape[2] for b in blocks)
    N = sum(len(m) for m in masses)
    shapes = np.zeros((N, 3, n_tot))
    K = np.zeros((n_tot, n_tot))
    k0, j0 = 1, 0
    offsets = []
    for (app, _R, _r0), blk in zip(frames, blocks, strict=True):
        nk, nj = blk.shape[0], blk.shape[2]
        shapes[k0 : k0 + nk, :, j0 : j0 + nj] = blk
        K[j0 : j0 + nj, j0 : j0 + nj] = app.stiffness
        offsets.append(j0)
        k0, j0 = k0 + nk, j0 + nj

    def shape_fn(pts):
        pts = np.atleast_2d(np.asarray(pts, dtype=float))
        Phi = np.zeros((len(pts), 3, n_tot))
        Psi = np.zeros((len(pts), 3, n_tot))
        for p_i, p in enumerate(pts):
            if np.linalg.norm(p) <= radius * (1 + 1e-12) + 1e-12:
                continue  # on the rigid hub
            for (app, R, r0), j0 in zip(frames, offsets, strict=True):
                try:
                    ph, ps = app.shape_fn((R.T @ (p - r0))[None])
                except InputError:
                    continue
                nj = app.n_modes
                Phi[p_i, :, j0 : j0 + nj] = R @ ph[0]
                Psi[p_i, :, j0 : j0 + nj] = R @ ps[0]
                break
            else:
                raise InputError(
                    "point",
                    p.tolist(),
                    f"a point on the hub (|r| <= {radius:g} m) or on an appendage (hub axes)",
                )
        return Phi, Psi

    return Body(
        name=f"{name} with {len(appendages)} appendage{'s' if len(appendages) > 1 else ''}",
        masses=np.concatenate(masses),
        points=np.concatenate(points),
        shapes=shapes,
        stiffness=K,
        shape_fn=shape_fn,
        geometric=None,
        frame="hub frame (origin at the hub centre; appendage modes clamped at their roots)",
        length=size,
        mode_labels=tuple(labels),
        extra_inertia=extra,
        params={
            "source": "hub_body",
            "hub_mass": float(mass),
            "hub_inertia": plain(J),
            "hub_radius": float(radius),
            "appendages": [
                {"body": app.name, **app.params, "root": plain(r0), "direction": plain(R[:, 0])}
                for app, R, r0 in frames
            ],
        },
    )


def free_frequencies(body: Body) -> np.ndarray:
    """Unconstrained natural frequencies [rad/s] of the free-floating body at rest: the elastic
    eigenvalues of ``K x = omega^2 M x`` with the full (6 + n) mass matrix (rigid and modal
    coordinates coupled), the six rigid-body zeros left out. For a hub body these are the
    free-hub frequencies; ``body.frequencies`` are the constrained (clamped-hub) ones."""
    from scipy.linalg import eigh

    n = body.n_modes
    if n == 0:
        return np.zeros(0)
    M = integrals(body)["M"]
    ev = np.linalg.eigvalsh(M[:6, :6])
    keep = np.nonzero(ev > 1e-12 * ev.max())[0]  # a planar line beam has no inertia about its axis
    V = np.linalg.eigh(M[:6, :6])[1][:, keep]
    T = np.zeros((6 + n, len(keep) + n))
    T[:6, : len(keep)] = V
    T[6:, len(keep) :] = np.eye(n)
    Mr = T.T @ M @ T
    Kr = np.zeros_like(Mr)
    Kr[len(keep) :, len(keep) :] = body.stiffness
    w2 = eigh(0.5 * (Kr + Kr.T), 0.5 * (Mr + Mr.T), eigvals_only=True)
    return np.sqrt(np.clip(np.sort(w2)[len(keep) :], 0.0, None))


def slew_inertia(body: Body, axis) -> float:
    """Rigid inertia [kg m^2] of the undeformed body about ``axis`` through its centre of mass
    (a pure torque turns a free body about its centre of mass)."""
    a = np.asarray(axis, dtype=float)
    a = a / np.linalg.norm(a)
    I0 = integrals(body)
    c = I0["S"] / I0["m"]
    Jc = I0["J"] - I0["m"] * (np.dot(c, c) * np.eye(3) - np.outer(c, c))
    return float(a @ Jc @ a)


def slew_torque(body: Body, angle: float, duration: float, profile: str, *, axis=(0.0, 0.0, 1.0), start=0.0) -> Load:
    """The body-axis torque on the hub centre that slews the rigid body rest-to-rest by
    ``angle`` [rad] in ``duration`` [s] about ``axis`` (a principal axis through the centre of
    mass for an exact rigid slew): ``tau(t) = J theta_ref''(t)`` with ``J`` from
    :func:`slew_inertia` and the reference of :func:`rotaflex.floating.kernels.motion_profile`:
    bang-bang ``+-4 angle / duration^2``, versine ``2 pi angle / duration^2 sin(2 pi s)``."""
    a = np.asarray(axis, dtype=float)
    a = a / np.linalg.norm(a)
    J = slew_inertia(body, a)
    if profile == "bang-bang":
        amp = 4.0 * angle / duration**2
        return Load(kind="torque", vector=tuple(J * amp * a), profile="bang-bang", start=start, duration=duration)
    if profile == "versine":
        amp = 2.0 * np.pi * angle / duration**2
        return Load(
            kind="torque",
            vector=tuple(J * amp * a),
            profile="sinusoid",
            frequency=1.0 / duration,
            start=start,
            duration=duration,
        )
    raise InputError("slew.profile", profile, "'bang-bang' or 'versine'")
