"""Loaded static transmission error of a helical (or lead-modified) pair: the face width in slices.

Model
-----
Thin slices. The face width ``b`` is cut into ``N`` slices of width ``db = b / N`` at axial
positions ``z_j`` (slice centres, from mid-face). Each slice is the transverse section of the
pair, whose FE tooth compliance along the transverse line of action is that of the spur model
(:func:`rotaflex.gear.static.loaded_te.pair_line`, computed ONCE for the pair): slice j of tooth
pair k touches at ``s_jk = s + k p_bt + sigma z_j tan(beta_b)`` on the transverse line of action
(the contact line on the plane of action is inclined by the base helix angle beta_b; sigma = +1
for a right-hand pinion, -1 for a left-hand one) and has the stiffness ``k_jk = db / (b q(s_jk))``
with ``q`` the whole-face pair compliance of the transverse section (so N slices at one ``s``
add up to the spur pair). Umezawa et al. (1986), Cai (1995, J. Mech. Des. 117) and Kuang & Lin
(2001) build helical mesh stiffness the same way.

Coupling between slices. A slice model with independent springs (a Winkler foundation) lets a
loaded slice deflect alone; a real tooth carries part of a local load to its neighbours. The
slices of one tooth pair are tied by a shear layer (Pasternak's two-parameter foundation,
Pasternak 1954; used for wide-faced spur and helical teeth by Ajmi & Velex 2005, Mech. Mach.
Theory 40): the strain energy ``1/2 sum_j k_j w_j^2 + 1/2 sum_j G (w_j+1 - w_j)^2 / db`` with
``G = k' lambda^2``, ``k'`` the local stiffness per unit length and ``lambda`` the coupling length
(``coupling_length``; an isolated load's deflection decays as exp(-|z| / lambda)). A uniform
approach deflects every slice equally and shears nothing, so the coupling changes the load
distribution and the TE only where the flanks' gap varies along the line (lead and profile
modifications, misalignment), never the unmodified mesh stiffness.

Contact. The gears are rigid bodies: every slice sees the same approach ``delta`` along the
transverse line of action, less its unloaded gap ``e_jk`` (profile reliefs at ``s_jk`` plus the
lead modifications of both gears and the misalignment at ``z_j``). With K the stiffness matrix of
the slices inside the path of contact, the loads solve the complementarity problem
``f = K w``, separation ``e - delta + w >= 0``, ``f >= 0``, ``f (e - delta + w) = 0``, ``sum f = F`` (F = T_1 / r_b1,
the transverse force along the line of action), by an active set on the slices in contact (the
Schur complement condenses the separated ones). The mesh stiffness is the tangent
``dF / d delta = 1^T S 1`` (S the condensed stiffness of the contacting slices): for no coupling
and no modification the sum of the slices' stiffnesses, the spur definition.

Forces. Transverse force along the line of action F = T_1 / r_b1; total normal force
F / cos(beta_b); axial force ``F tan(beta_b) = T_1 tan(beta_w) / r_w1``. The load per unit length of
contact line of slice j is ``f_j / db`` (normal force f_j / cos(beta_b) over the length
db / cos(beta_b)).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from rotaflex.gear.static.loaded_te import PairLine

__all__ = ["FaceModel", "face_model", "sliced_te", "slice_positions", "MIN_SLICE_WIDTH_COEF"]

#: narrowest slice / normal module: below it the slices are thinner than the Hertz patch of
#: usual loads and a slice no longer behaves as a transverse section
MIN_SLICE_WIDTH_COEF = 0.05


@dataclasses.dataclass(frozen=True)
class FaceModel:
    """The face-width model of a pair.

    Attributes
    ----------
    face_width : float
        Common face width b [m].
    base_helix_angle : float
        beta_b [rad] (0: spur, the slices then only carry lead modifications).
    hand : int
        +1 (right-hand pinion) or -1 (left-hand pinion): sign of the stagger.
    n_slices : int
        N.
    coupling_length : float
        lambda [m] of the shear layer (0: independent slices).
    lead_gap : ndarray, shape (N,)
        Gap of both gears' lead modifications and the misalignment at each slice [m].
    """

    face_width: float
    base_helix_angle: float
    hand: int
    n_slices: int
    coupling_length: float
    lead_gap: np.ndarray


def face_model(pair, n_slices: int, coupling_length_coef: float, misalignment: float, where: str = "face"):
    """The :class:`FaceModel` of a checked :class:`~rotaflex.gear.pair.drawing.PairSpec`.

    Parameters
    ----------
    pair : PairSpec
    n_slices : int
        Slices over the face width.
    coupling_length_coef : float
        Coupling length lambda / m_n.
    misalignment : float
        Tilt of the wheel relative to the pinion in the plane of action [rad] (a gap
        ``misalignment z`` along the face).
    where : str
        Table of ``n_slices`` in the user's file (for the message of a too narrow face).
    """
    from rotaflex.core.errors import InputError

    b, m_n = pair.face_width, pair.pinion.module
    if b / n_slices < MIN_SLICE_WIDTH_COEF * m_n:
        raise InputError(
            "pinion.face_width",
            pair.pinion.face_width,
            f">= {n_slices} slices x {MIN_SLICE_WIDTH_COEF} x module = {n_slices * MIN_SLICE_WIDTH_COEF * m_n:.4g} m "
            f"(or fewer {where}.slices)",
        )
    z = slice_positions(b, n_slices)
    gap = misalignment * z
    for g in (pair.pinion, pair.wheel):
        if g.lead is not None:
            gap = gap + g.lead.depth(z, b)
    hand = -1 if pair.pinion.hand == "left" else 1
    return FaceModel(b, pair.base_helix_angle, hand, n_slices, coupling_length_coef * m_n, gap)


def slice_positions(face_width: float, n_slices: int) -> np.ndarray:
    """Slice centres z_j [m] from mid-face (midpoint rule)."""
    db = face_width / n_slices
    return -0.5 * face_width + db * (np.arange(n_slices) + 0.5)


def _pair_range(line: PairLine, face: FaceModel) -> np.ndarray:
    """Tooth-pair offsets k that can touch for a reference position in one base pitch."""
    spread = face.face_width * math.tan(face.base_helix_angle)
    n = int(math.ceil((line.s_end - line.s_start + spread) / line.base_pitch)) + 1
    return np.arange(-n, n + 1)


def sliced_te(line: PairLine, face: FaceModel, s_ref: np.ndarray, *, with_gaps: bool = True) -> dict:
    """Loaded static TE and mesh stiffness of the sliced face at reference positions ``s_ref``.

    Parameters
    ----------
    line : PairLine
        Transverse-section FE data of the pair (compliance, profile-relief gaps); its ``force``
        is the transverse force F [N] along the line of action.
    face : FaceModel
    s_ref : ndarray
        Transverse line-of-action positions [m] of the mid-face contact of the reference pair.
    with_gaps : bool
        False: no modification (profile reliefs and lead gaps off).

    Returns
    -------
    dict
        ``te`` [m] (transverse line of action), ``stiffness`` [N/m] (tangent, transverse line of
        action), ``load`` (n, pairs, N) slice forces [N] along the transverse line of action,
        ``k`` offsets of the tooth pairs, ``s`` (n, pairs, N) slice positions [m],
        ``n_contact`` slices in contact.
    """
    s_ref = np.asarray(s_ref, dtype=float)
    n_s = face.n_slices
    z = slice_positions(face.face_width, n_s)
    db = face.face_width / n_s
    ks = _pair_range(line, face)
    shift = face.hand * z * math.tan(face.base_helix_angle)
    s = s_ref[:, None, None] + ks[None, :, None] * line.base_pitch + shift[None, None, :]
    inside = (s >= line.s_start - 1e-15) & (s <= line.s_end + 1e-15)
    kk = np.zeros(s.shape)
    kk[inside] = (db / face.face_width) / line.compliance(s[inside])  # one evaluation for all slices
    gap = np.zeros(s.shape)
    if with_gaps:
        gap[inside] = line.gap(s[inside])
        gap += face.lead_gap[None, None, :]
    te = np.empty(s_ref.size)
    stiff = np.empty(s_ref.size)
    load = np.zeros(s.shape)
    lam2 = face.coupling_length**2
    for i in range(s_ref.size):
        idx = np.nonzero(inside[i].ravel())[0]
        kv = kk[i].ravel()[idx]
        # shear layer between neighbouring slices of one tooth pair, both inside the path
        pair_of, slice_of = np.divmod(idx, n_s)
        nb = np.nonzero((pair_of[1:] == pair_of[:-1]) & (slice_of[1:] == slice_of[:-1] + 1))[0]
        kc = lam2 * 0.5 * (kv[nb] + kv[nb + 1]) / db**2  # G / db with G = k' lambda^2, k' = k / db
        f, te[i], stiff[i] = _contact(kv, nb, kc, gap[i].ravel()[idx], line.force)
        load[i].ravel()[idx] = f
    return {"te": te, "stiffness": stiff, "load": load, "k": ks, "s": s, "n_contact": (load > 0).sum(axis=(1, 2))}


def _contact(kv, nb, kc, gap, force, max_iter=200):
    """Active-set solution of the slices' contact problem (module docstring).

    Returns (slice loads [N], approach delta [m], tangent stiffness [N/m]).
    """
    n = kv.size
    if np.ptp(gap) == 0.0:  # uniform gap: a uniform approach shears nothing, all in parallel
        k_tot = kv.sum()
        return kv * (force / k_tot), gap[0] + force / k_tot, k_tot
    kmat = np.diag(kv)
    if nb.size:
        kmat[nb, nb] += kc
        kmat[nb + 1, nb + 1] += kc
        kmat[nb, nb + 1] -= kc
        kmat[nb + 1, nb] -= kc
    act = np.ones(n, dtype=bool)
    seen = set()
    for it in range(max_iter):
        a, o = np.nonzero(act)[0], np.nonzero(~act)[0]
        kaa = kmat[np.ix_(a, a)]
        if o.size:
            kao = kmat[np.ix_(a, o)]
            tmat = np.linalg.solve(kmat[np.ix_(o, o)], kao.T)  # w_o = -T w_a
            schur = kaa - kao @ tmat
        else:
            schur = kaa
        s1 = schur.sum(axis=0)
        k_tan = s1.sum()
        delta = (force + s1 @ gap[a]) / k_tan
        w_a = delta - gap[a]
        f_a = schur @ w_a
        # tolerances relative to the load and the approach (1e-5 of delta: sub-nanometre): a
        # slice at the edge of the contact zone carries ~0 and must not flip between the sets;
        # an active set met again (a slice released and taken back) is that edge: accept it
        neg = f_a < -1e-7 * force
        pen = np.zeros(o.size, dtype=bool)
        if o.size:
            # separation e - delta + w of a free slice must stay >= 0
            pen = -(tmat @ w_a) < delta - gap[o] - 1e-5 * abs(delta)
        state = act.tobytes()
        if (not neg.any() and not pen.any()) or state in seen:
            f = np.zeros(n)
            f[a] = np.maximum(f_a, 0.0)
            return f, delta, k_tan
        seen.add(state)
        if neg.any():  # release the tensile slices (later one at a time, should that cycle)
            if it < max_iter // 4:
                act[a[neg]] = False
            else:
                act[a[np.argmin(f_a)]] = False
        else:
            act[o[pen]] = True
    raise RuntimeError("slice contact: active set did not settle")  # pragma: no cover
