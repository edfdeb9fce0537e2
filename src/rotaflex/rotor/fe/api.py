"""API 684 / API 617 practice: operating bands, separation-margin verdicts, unbalance amounts, limits.

Rules used (API 617 8th ed. 4.8.2 / API 684 2nd ed. 2.8 as applied by rotordynamic practice):

- Amplification factor from the half-power points of a peak, ``AF = N_c / (N_2 - N_1)``
  (:func:`rotaflex.rotor.fe.response.peaks`).
- Required separation margin (:func:`rotaflex.rotor.fe.response.api684_required_margin`): none
  for AF < 2.5; otherwise min(16, 17 (1 - 1/(AF - 1.5))) % for a critical below an operating band
  (relative to its minimum speed) and min(26, 10 + 17 (1 - 1/(AF - 1.5))) % for one above
  (relative to its maximum speed). A critical with AF >= 2.5 inside a band fails.
- Unbalance per plane: ISO 21940-11 balance grade G [mm/s]: the permissible specific unbalance
  ``e_per = 1000 G / Omega`` [g mm/kg, i.e. um] at the maximum continuous speed Omega [rad/s],
  and ``U = e_per m`` [g mm] for the mass share m [kg] of the plane; or API: ``U = 6350 W / N``
  [g mm] with W [kg] the journal static load share of the plane and N [rpm] the maximum
  continuous speed (the SI form of API's 4 W/N oz in).
- Vibration limit (API 617): ``A_lim = 25.4 sqrt(12000 / N)`` um peak-to-peak, at most 25.4 um,
  N [rpm] the maximum continuous speed; compared with twice the orbit's semi-major axis.
- Stability (API 617's stability analysis: every mode's log decrement must be positive at every
  operating speed; its Level II acceptance asks for 0.1): separation margins say nothing about
  a mode whose damping turns negative, so every verdict over an operating range also checks every eigenvalue of the
  rotor-bearing system at speeds spanning the range (:func:`stability_in_bands`) and fails when
  one has a negative real part (oil whip, cross-coupled seals).
"""

from __future__ import annotations

import numpy as np

from rotaflex.core.errors import InputError
from rotaflex.rotor.fe.model import NDOF_NODE, RPM, Rotor
from rotaflex.rotor.fe.response import api684_required_margin

#: API's unbalance constant in SI: U [g mm] = API_UNBALANCE * W [kg] / N [rpm]
API_UNBALANCE = 6350.0


def vibration_limit(max_speed_rpm: float) -> float:
    """API 617 peak-to-peak vibration limit [m] at the maximum continuous speed [rpm].

    Examples
    --------
    >>> round(vibration_limit(12000.0) * 1e6, 6), round(vibration_limit(3000.0) * 1e6, 6)
    (25.4, 25.4)
    >>> round(vibration_limit(20000.0) * 1e6, 4)
    19.6749
    """
    return min(25.4, 25.4 * np.sqrt(12000.0 / max_speed_rpm)) * 1e-6


def iso_specific_unbalance(grade: float, speed: float) -> float:
    """Permissible specific unbalance e_per [g mm/kg = um] of ISO 21940 grade G [mm/s] at ``speed`` [rad/s].

    Examples
    --------
    >>> round(iso_specific_unbalance(2.5, 3000 * np.pi / 30), 4)  # G2.5 at 3000 rpm: ~8 um
    7.9577
    """
    return 1000.0 * grade / speed


def api_unbalance(journal_load_kg: float, max_speed_rpm: float) -> float:
    """API unbalance U = 6350 W / N [g mm] for a journal static load W [kg] and speed N [rpm]."""
    return API_UNBALANCE * journal_load_kg / max_speed_rpm


def plane_masses(rotor: Rotor, planes, reactions: np.ndarray) -> np.ndarray:
    """Mass share [kg] of each unbalance plane: the static load of its nearest bearing / g,
    divided among the planes that share that bearing (so the shares add up to the rotor's mass
    when every bearing has a plane near it).

    ``reactions`` are the static bearing forces under 1 g ([N] per m/s^2, i.e. kg), e.g.
    ``static_analysis(rotor, gravity=1.0).reactions``.
    """
    zb = np.array([rotor.nodes[n] for n, _, _ in rotor.bearings])
    loads = np.hypot(reactions[:, 0], reactions[:, 1])
    near = [int(np.argmin(np.abs(zb - rotor.nodes[p]))) for p in planes]
    count = np.bincount(near, minlength=zb.size)
    return np.array([loads[b] / count[b] for b in near])


def arrangement_phases(rotor: Rotor, planes, shape: np.ndarray | None) -> np.ndarray:
    """Unbalance phases [rad] per plane: 0 (in phase) or the phase of the mode's x at the plane.

    With ``shape`` (a mode shape, n_dof complex) each plane's unbalance points where that mode
    displaces the plane, which excites the mode most (its "worst" arrangement): e.g. in phase
    for a first bending mode, opposed for a conical or second mode.
    """
    if shape is None:
        return np.zeros(len(planes))
    ph = np.array([np.angle(shape[NDOF_NODE * p]) for p in planes])
    return np.angle(np.exp(1j * (ph - ph[0])))  # relative to the first plane, in (-pi, pi]


#: speeds per operating band at which the eigenvalues are checked (the onset is then refined by Brent's method)
STABILITY_SPEEDS = 21


def _least_damping(rotor: Rotor, speeds: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Smallest damping ratio of all eigenvalues at each speed [rad/s], and that eigenvalue.

    Every eigenvalue of the first-order system counts (not only the lowest modes a Campbell
    tracks; a real positive eigenvalue is a divergence, damping ratio -1); eigenvalues below
    1e-9 of the largest modulus (rigid-body zeros, round-off) do not.
    """
    from rotaflex.rotor.fe.modal import _state_matrices

    lam = np.linalg.eigvals(_state_matrices(rotor, np.atleast_1d(np.asarray(speeds, float))))
    mod = np.abs(lam)
    zeta = np.where(mod > 1e-9 * mod.max(-1, keepdims=True), -lam.real / np.where(mod > 0, mod, 1.0), np.inf)
    j = np.argmin(zeta, -1)
    i = np.arange(lam.shape[0])
    return zeta[i, j], lam[i, j]


def stability_in_bands(rotor: Rotor, bands, n_speeds: int = STABILITY_SPEEDS) -> dict:
    """Stability of every mode over operating ``bands`` [(lo, hi) rad/s].

    The eigenvalues are computed at ``n_speeds`` speeds spanning each band (one for a single
    operating speed); where the least damped one crosses to negative damping between two of
    them the onset is located by Brent's method to 1e-6 relative.

    Returns
    -------
    dict
        ``stable`` (bool: every eigenvalue has damping ratio >= -STABILITY_TOL at every speed
        checked), ``min_log_dec`` (the smallest log decrement found, -2 pi sigma / omega_d; -inf
        for a divergence), ``speed_min`` [rad/s] where it occurs, ``frequency`` [rad/s] (its damped
        frequency), and when unstable ``onset`` [rad/s] (the lowest unstable speed in the bands:
        the band's lower end when the mode is already unstable there) and ``band`` (lo, hi).

    Examples
    --------
    >>> from rotaflex.rotor.fe.model import Rotor, Shaft, Bearing
    >>> r = Rotor(shaft=(Shaft(outer_diameter=0.05, length=1.0, elements=4),),
    ...           bearing=(Bearing(node=0, kxx=1e7, kyy=1e7, cxx=1e3, cyy=1e3),
    ...                    Bearing(node=4, kxx=1e7, kyy=1e7, cxx=1e3, cyy=1e3)))
    >>> stability_in_bands(r, [(300.0, 400.0)])["stable"]
    True
    """
    from scipy.optimize import brentq

    from rotaflex.rotor.fe.modal import STABILITY_TOL

    out = {"stable": True, "min_log_dec": np.inf, "speed_min": np.nan, "frequency": np.nan}
    for lo, hi in bands:
        sp = np.linspace(lo, hi, n_speeds if hi > lo else 1)
        zeta, lam = _least_damping(rotor, sp)
        ld = np.where(np.abs(lam.imag) > 0, -2 * np.pi * lam.real / np.abs(lam.imag), -np.inf)
        k = int(np.argmin(ld))
        if ld[k] < out["min_log_dec"]:
            out.update(min_log_dec=float(ld[k]), speed_min=float(sp[k]), frequency=float(abs(lam[k].imag)))
        bad = np.flatnonzero(zeta < -STABILITY_TOL)
        if bad.size == 0:
            continue
        b = bad[0]
        onset = float(sp[0])
        if b > 0:
            onset = brentq(lambda w: _least_damping(rotor, [w])[0][0] + STABILITY_TOL, sp[b - 1], sp[b], rtol=1e-6)
        if out["stable"] or onset < out["onset"]:
            out.update(stable=False, onset=float(onset), band=(float(lo), float(hi)))
    return out


def stability_verdict(st: dict) -> str:
    """One phrase of a :func:`stability_in_bands` result for a summary line."""
    if st["stable"]:
        return (
            f"stable in the operating range (smallest log dec {st['min_log_dec']:.3g}, "
            f"{st['frequency'] / (2 * np.pi):.4g} Hz mode)"
        )
    lo, hi = st["band"]
    where = "already at" if st["onset"] <= lo else "from"
    return (
        f"UNSTABLE {where} {st['onset'] / RPM:.0f} rpm inside {lo / RPM:.0f}-{hi / RPM:.0f} rpm "
        f"(log dec {st['min_log_dec']:.3g} at {st['speed_min'] / RPM:.0f} rpm, "
        f"whirl {st['frequency'] / (2 * np.pi):.1f} Hz)"
    )


def stability_summary(rotor, bands, extra: dict) -> str:
    """Stability over the operating ``bands`` into the summary ``extra``; the verdict phrase.

    A verdict over an operating range fails when any mode is unstable in it, whatever its
    separation margins (:func:`stability_in_bands`)."""
    st = stability_in_bands(rotor, bands)
    extra["stable_in_operating_range"] = {
        "value": st["stable"],
        "unit": "",
        "note": f"every eigenvalue checked at {STABILITY_SPEEDS} speeds per band (onset by root finding)",
    }
    extra["min_log_dec_in_operating_range"] = {
        "value": st["min_log_dec"],
        "unit": "1",
        "speed_rpm": st["speed_min"] / RPM,
        "frequency_hz": st["frequency"] / (2 * np.pi),
    }
    if not st["stable"]:
        extra["instability_onset_in_operating_range_rpm"] = {"value": st["onset"] / RPM, "unit": "rpm"}
    return stability_verdict(st)


def rate_peaks(pk: list[dict], bands) -> list[dict]:
    """Add API verdicts to resonance peaks against operating ``bands`` [(lo, hi) rad/s].

    Each peak gains ``position`` ("below", "above", "inside" or "between"), ``sm_percent``
    (the smallest margin to any band, relative to that band's limit; negative inside a band),
    ``sm_required_percent`` (for that band) and ``sm_ok`` (1.0/0.0).
    """
    out = []
    for p in pk:
        nc, af = p["speed"], p["af"]
        worst = None  # (ok, margin - required, sm, req, position)
        for lo, hi in bands:
            if nc < lo:
                sm, req, pos = (lo - nc) / lo * 100, api684_required_margin(af, True), "below"
            elif nc > hi:
                sm, req, pos = (nc - hi) / hi * 100, api684_required_margin(af, False), "above"
            else:
                sm = -min(nc - lo, hi - nc) / hi * 100
                req, pos = api684_required_margin(af, True), "inside"
            ok = sm >= req or af < 2.5
            cand = (ok, sm - req, sm, req, pos)
            if worst is None or (cand[0], cand[1]) < (worst[0], worst[1]):
                worst = cand
        ok, _, sm, req, pos = worst
        below_any = any(nc < lo for lo, _ in bands)
        above_any = any(nc > hi for _, hi in bands)
        if pos != "inside" and below_any and above_any:
            pos = "between"
        out.append(
            {**p, "position": pos, "sm_percent": float(sm), "sm_required_percent": float(req), "sm_ok": float(ok)}
        )
    return out


def check_bands(bands, field: str) -> list[tuple[float, float]]:
    """Validated operating bands [rpm] -> [(lo, hi)] [rad/s]."""
    out = []
    for i, b in enumerate(bands):
        lo, hi = b
        if not (0 < lo < hi):
            raise InputError(
                f"{field}[{i}]" if len(bands) > 1 else field, list(b), "[min, max] speeds with 0 < min < max"
            )
        out.append((lo * RPM, hi * RPM))
    return out
