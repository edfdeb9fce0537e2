"""Linear forced response of a gearbox to the transmission-error harmonics (frequency domain).

About the static state under the load, with the mean mesh stiffness k_m and damping c_m, the
excitation of mesh m is its static transmission error under load ``ste(phi) = e(phi) +
F_0 / k(phi)`` (``"loaded_te"``: the time-varying stiffness' effect at the static load, the usual
linear time-invariant model) or the unloaded TE alone (``"unloaded_te"``). With
``ste = sum_h Re(E_h exp(i h omega_m t))`` each harmonic h gives, at omega = h omega_m,

    (K + k_m g g^T + i omega (D + c_m g g^T) - omega^2 M) Q = g (k_m + i omega c_m) E_h,

DTE ``g_tors^T Q`` (the twist part of the mesh deflection, ``r_b1 theta_1 - r_b2 theta_2`` in
gear steady's signs), dynamic mesh force ``(k_m + i omega c_m)(g^T Q - E_h)``, bearing forces
``-(K_b + i omega C_b) [X, Y]`` and orbits at chosen nodes. By default the solve is in the
undamped modes below 3 x the highest excitation frequency plus the static mesh-force shapes
``K^-1 g`` (exact at low frequency); ``cutoff = None``: all DOFs.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rotaflex.core.errors import InputError
from rotaflex.system.assembly import bearing_matrices, matrices, reduced_basis
from rotaflex.system.helical import thrust_operator
from rotaflex.system.model import Gearbox
from rotaflex.system.size import check_assembly, check_response


def te_harmonics(box: Gearbox, mesh: int, n_harmonics: int, excitation: str = "loaded_te") -> np.ndarray:
    """Complex amplitudes E_h [m], h = 1 ... n, of the mesh's excitation over one mesh cycle."""
    m = box.meshes[mesh]
    t = m.gear.table
    if excitation == "loaded_te":
        f0 = m.gear.torque / m.gear.base_radius[0]  # static mesh force [N]
        x = t.unloaded_te + f0 / t.stiffness
    elif excitation == "unloaded_te":
        x = t.unloaded_te
    else:
        raise InputError("response.excitation", excitation, "'loaded_te' or 'unloaded_te'")
    c = np.fft.fft(x) / x.size
    h = np.arange(1, n_harmonics + 1)
    if n_harmonics >= x.size // 2:
        raise InputError("response.harmonics", n_harmonics, f"< {x.size // 2} (half the table points)")
    return 2.0 * c[h]


#: TE harmonics below this fraction of the static mesh deflection are round-off of a constant
NO_EXCITATION = 1e-9


def refuse_no_excitation(box: Gearbox, E: np.ndarray, excitation: str) -> None:
    """InputError when no mesh has an excitation harmonic (a response would be zeros).

    ``E`` (mesh, h) [m]. A mesh excites when one harmonic exceeds :data:`NO_EXCITATION` times
    its static deflection F_0 / k_min (the FFT of a constant table leaves ~1e-16 of it). The
    key named is the one that would give an excitation: ``gear_mesh[i].source`` for the
    constant-stiffness ISO 6336 table, ``gear_mesh[i].te_harmonics`` for a harmonic table
    without harmonics, ``response.excitation`` when only the unloaded TE (zero) was asked for.
    """
    for j, m in enumerate(box.meshes):
        t = m.gear.table
        scale = max(
            float(np.max(np.abs(t.unloaded_te))), m.gear.torque / m.gear.base_radius[0] / float(np.min(t.stiffness))
        )
        if np.max(np.abs(E[j])) > NO_EXCITATION * scale:
            return
    m = box.meshes[0].gear
    if excitation == "unloaded_te" and m.source != "iso6336":
        raise InputError(
            "response.excitation",
            excitation,
            "'loaded_te': the meshes' unloaded TE is zero, only the loaded one varies",
        )
    if m.source == "harmonic":
        raise InputError(
            "gear_mesh[0].te_harmonics",
            [],
            "TE sine amplitudes [m] or k_harmonics: without them the mesh does not excite",
        )
    raise InputError(
        "gear_mesh[0].source",
        m.source,
        "a source with a TE or stiffness variation to excite the response: 'loaded_te' (FE teeth), 'static_fe', "
        "'contact_pattern' or 'harmonic' ('iso6336' is a constant stiffness: no excitation, every amplitude 0)",
    )


@dataclass(frozen=True)
class ForcedResponse:
    """Response amplitudes (complex, per speed s and harmonic h) of each mesh's excitation.

    Attributes (leading dims: (mesh, speed, harmonic))
    ------------------------------------------------
    speed : (s,) drive speeds [rad/s];  frequency : (mesh, s, h) [rad/s]
    excitation : (mesh, h) E_h [m]
    dte, deflection : [m];  mesh_force : [N] (dynamic part)
    bearing_force : (mesh, s, h, n_bearing, 2) [N];  orbit : (mesh, s, h, n_probe, 2) [m]
    bearings : list of (rotor name, node);  probes : list of (rotor name, node)
    static_force : (mesh,) [N]
    axial_bearing_force : (mesh, s, h, n_thrust) [N] thrust bearing forces on the rotors
        (boxes with helical meshes; None otherwise)
    """

    speed: np.ndarray
    frequency: np.ndarray
    excitation: np.ndarray
    dte: np.ndarray
    deflection: np.ndarray
    mesh_force: np.ndarray
    bearing_force: np.ndarray
    orbit: np.ndarray
    bearings: list
    probes: list
    static_force: np.ndarray
    axial_bearing_force: np.ndarray | None = None


def forced_response(
    box: Gearbox,
    speeds,
    *,
    harmonics: int = 3,
    probes=(),
    excitation: str = "loaded_te",
    cutoff: float | None = 2.0,
) -> ForcedResponse:
    """TE-harmonic response over drive speeds [rad/s] (see the module docstring).

    ``probes``: (rotor index, node) pairs whose lateral orbits are returned. ``cutoff``: keep
    the undamped modes below ``cutoff`` x the highest excitation frequency (plus the static
    mesh-force shapes); None: all DOFs.
    """
    speeds = np.atleast_1d(np.asarray(speeds, float))
    if not len(box.meshes):
        raise InputError("gear_mesh", [], "at least one [[gear_mesh]] for a TE response")
    check_assembly(box)
    mats = matrices(box)
    nf = mats.free.size
    ns, nm, nh = speeds.size, len(box.meshes), harmonics
    w_max = nh * max(box.mesh_frequency(j, float(np.max(np.abs(speeds)))) for j in range(nm))
    P = np.eye(nf) if cutoff is None else reduced_basis(box, mats, float(np.median(speeds)), w_max, cutoff)
    n_brg = sum(len(pr.rotor.bearings) for pr in box.rotors)
    check_response(ns, nh, P.shape[1], nm, n_brg, len(probes), cutoff)
    Tfull = mats.expand(P)
    M = P.T @ mats.reduce(mats.M) @ P
    K0 = P.T @ mats.reduce(mats.K0) @ P
    Gr = [P.T @ mats.reduce(G) @ P for G in mats.G]
    g = mats.project(mats.g) @ P  # (n_mesh, r)
    constant = all(el.speed_independent for pr in box.rotors for _, _, el in pr.rotor.bearings)
    brg = [(i, node, other) for i, pr in enumerate(box.rotors) for node, other, _ in pr.rotor.bearings]
    rows = [[box.lateral_dof(i, n, 0), box.lateral_dof(i, n, 1)] for i, n, _ in brg]
    # displacement across each bearing (relative to its second node, or ground)
    Tb = np.zeros((len(brg), 2, P.shape[1]))
    for b, (i, _, other) in enumerate(brg):
        Tb[b] = Tfull[rows[b]]
        if other is not None:
            Tb[b] -= Tfull[[box.lateral_dof(i, other, 0), box.lateral_dof(i, other, 1)]]
    if box.axial:  # thrust bearings (helical meshes): axial displacement across each
        Ta, ka, ca = thrust_operator(box, Tfull)
        fa = np.zeros((nm, ns, nh, ka.size), complex)
    Tp = np.zeros((len(probes), 2, P.shape[1]))
    for p, (r, n) in enumerate(probes):
        Tp[p] = Tfull[[box.lateral_dof(r, n, 0), box.lateral_dof(r, n, 1)]]
    # bearing matrices per speed (once if constant)
    sel = [0] if constant else range(ns)
    Kb, Cb, Mb, kbn, cbn = [], [], [], [], []
    for s in sel:
        Kf, Cf, Mf = bearing_matrices(box, speeds[s], with_mass=True)
        Mb.append(P.T @ mats.reduce(Mf) @ P)
        Kb.append(P.T @ mats.reduce(Kf) @ P)
        Cb.append(P.T @ mats.reduce(Cf + mats.C0) @ P)
        kbn.append(np.array([Kf[np.ix_(r, r)] for r in rows]).reshape(len(rows), 2, 2))
        cbn.append(np.array([Cf[np.ix_(r, r)] for r in rows]).reshape(len(rows), 2, 2))
    Kb, Cb, Mb, kbn, cbn = (np.array(x) for x in (Kb, Cb, Mb, kbn, cbn))  # (1 or ns, ...)
    M = M[None] + Mb  # seals' added mass (zero for every other element)
    K = K0[None] + Kb + ((g.T * mats.k_mean) @ g)[None]
    Gsum = sum(pr.sense * pr.ratio * G for pr, G in zip(box.rotors, Gr, strict=True))
    D = Cb + ((g.T * mats.c_mesh) @ g)[None] + speeds[:, None, None] * Gsum[None]  # (ns, r, r)
    K = np.broadcast_to(K, D.shape)
    E = np.array([te_harmonics(box, j, nh, excitation) for j in range(nm)])
    refuse_no_excitation(box, E, excitation)
    tors = np.zeros((nm, box.n_dof))
    for j in range(nm):
        idx = [box.torsion_dof(*box.meshes[j].driver), box.torsion_dof(*box.meshes[j].driven)]
        tors[j, idx] = mats.g[j, idx]
    tors_r = tors @ Tfull
    shape = (nm, ns, nh)
    freq = np.zeros(shape)
    out = {k: np.zeros(shape, complex) for k in ("dte", "deflection", "mesh_force")}
    bf = np.zeros((*shape, len(brg), 2), complex)
    orb = np.zeros((*shape, len(probes), 2), complex)
    hs = np.arange(1, nh + 1)
    for j in range(nm):
        wm = hs[None, :] * np.array([box.mesh_frequency(j, w0) for w0 in speeds])[:, None]  # (ns, nh)
        freq[j] = wm
        H = np.empty((ns, nh, *M.shape[-2:]), complex)  # K + i w D - w^2 M, written in place
        H.real[...] = K[:, None]
        H.real[...] -= wm[..., None, None] ** 2 * M[:, None]
        np.multiply(wm[..., None, None], D[:, None], out=H.imag)
        zk = mats.k_mean[j] + 1j * wm * mats.c_mesh[j]  # (ns, nh)
        rhs = g[j][None, None, :] * (zk * E[j][None, :])[..., None]
        Q = np.linalg.solve(H, rhs[..., None])[..., 0]  # (ns, nh, r)
        gq = Q @ g[j]
        out["dte"][j] = Q @ tors_r[j]
        out["deflection"][j] = gq - E[j][None, :]
        out["mesh_force"][j] = zk * (gq - E[j][None, :])
        if len(brg):
            u = np.einsum("bar,shr->shba", Tb, Q)  # (ns, nh, nb, 2)
            fk = np.einsum("sbij,shbj->shbi", kbn, u)  # kbn, cbn: (1 or ns, nb, 2, 2)
            fc = np.einsum("sbij,shbj->shbi", cbn, u)
            bf[j] = -(fk + 1j * wm[..., None, None] * fc)
        if len(probes):
            orb[j] = np.einsum("par,shr->shpa", Tp, Q)
        if box.axial:
            fa[j] = -(ka + 1j * wm[..., None] * ca) * (Q @ Ta.T)
    names = [(box.rotors[i].name, node) for i, node, _ in brg]
    pnames = [(box.rotors[r].name, n) for r, n in probes]
    f0 = np.array([m.gear.torque / m.gear.base_radius[0] for m in box.meshes])
    fa = fa if box.axial else None
    return ForcedResponse(
        speeds, freq, E, out["dte"], out["deflection"], out["mesh_force"], bf, orb, names, pnames, f0, fa
    )


def orbit_semi_axes(X: np.ndarray, Y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Semi-major and semi-minor axes [m] of the ellipse x = Re(X e^{iwt}), y = Re(Y e^{iwt})."""
    fwd = np.abs(X + 1j * Y) / 2  # forward and backward circle radii
    bwd = np.abs(X - 1j * Y) / 2
    return fwd + bwd, np.abs(fwd - bwd)
