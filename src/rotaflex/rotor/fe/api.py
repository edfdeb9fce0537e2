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
  [g mm] (the SI form of API's 4 W/N oz in) with N [rpm] the maximum continuous speed and W
  [kg] distributed over the planes of a mode by :func:`api_plane_unbalance`.
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
from rotaflex.core.units import rad_s_to_rpm, rpm_to_rad_s
from rotaflex.rotor.fe.model import NDOF_NODE, Rotor
from rotaflex.rotor.fe.response import api684_required_margin

#: API's unbalance constant in SI: U [g mm] = API_UNBALANCE * W [kg] / N [rpm]
API_UNBALANCE = 6350.0


def vibration_limit(max_speed_rpm: float) -> float:
    """API 617 peak-to-peak vibration limit [m] at the maximum continuous speed [rpm].

    Examples
    --------
    >>> round(vibration_limit(12000.0) * 1e6, 6), round(vibration_limit(3000.0) * 1e6, 6)
    (25.4, 25.4)
    >>> round(float(vibration_limit(20000.0)) * 1e6, 4)
    19.6748
    """
    return min(25.4, 25.4 * np.sqrt(12000.0 / max_speed_rpm)) * 1e-6


def iso_specific_unbalance(grade: float, speed: float) -> float:
    """Permissible specific unbalance e_per [g mm/kg = um] of ISO 21940 grade G [mm/s] at ``speed`` [rad/s].

    Examples
    --------
    >>> round(iso_specific_unbalance(2.5, rpm_to_rad_s(3000)), 4)  # G2.5 at 3000 rpm: ~8 um
    7.9577
    """
    return 1000.0 * grade / speed


def api_unbalance(journal_load_kg: float, max_speed_rpm: float) -> float:
    """API unbalance U = 6350 W / N [g mm] for a journal static load W [kg] and speed N [rpm]
    (N capped at 25,000 rpm: 254 W above it, API 617)."""
    return API_UNBALANCE * journal_load_kg / min(max_speed_rpm, 25000.0)


def plane_masses(rotor: Rotor, planes) -> np.ndarray:
    """Mass share [kg] of each unbalance plane: the rotor's mass lumped to its nearest plane.

    Each node's translational mass (the x row sums of the consistent mass matrix, which add
    up to the rotor's mass exactly) goes to the plane nearest to it along z; a node halfway
    between two planes is split equally between them. So the shares add up to the rotor's
    mass, and a symmetric rotor gets symmetric shares (a middle plane is not counted with
    either bearing).
    """
    t = np.zeros(rotor.n_dof)
    t[0::NDOF_NODE] = 1.0
    node_mass = (rotor.M @ t)[0::NDOF_NODE]
    zp = np.array([rotor.nodes[p] for p in planes])
    d = np.abs(rotor.nodes[:, None] - zp[None, :])  # (node, plane)
    near = np.isclose(d, d.min(1, keepdims=True), rtol=0, atol=1e-12 * (np.ptp(rotor.nodes) + 1.0))
    return node_mass @ (near / near.sum(1, keepdims=True))


def api_plane_unbalance(rotor: Rotor, planes, max_speed_rpm: float, shape: np.ndarray | None = None) -> np.ndarray:
    """API unbalance [g mm] of each plane: U = 6350 W / N over the planes of a mode.

    API 617 (8th ed. 4.8.2.7; quoted in API 684 2nd ed. as SP6.8.2.7) sets the unbalance
    U = 6350 W / N [g mm] (W [kg], N [rpm] the maximum continuous speed; 254 W above 25,000
    rpm) and places it to excite the mode: for a first (one-lobe) mode at the point of largest
    displacement with W the rotor's weight on both journals; for a second or conical mode two
    unbalances 180 deg apart, each with the load of its own half. Over several planes:

    - without ``shape`` (in phase): W = the rotor mass, spread over the planes in proportion to
      their mass shares (:func:`plane_masses`);
    - with a mode ``shape`` (n_dof complex): the planes are grouped into the mode's lobes by
      the sign of their displacement relative to the largest; each lobe gets U = 6350 W_lobe / N
      with W_lobe the mass shares of its planes, spread over them in proportion to
      m_i |phi_i|. A plane within 1 % of the largest displacement of zero (on a node line)
      gives its mass share to the lobes equally and receives nothing. A one-plane lobe at the
      mode's maximum is API's single unbalance; two lobes on a symmetric rotor give each half
      its half of the weight, API's journal-load rule.
    """
    share = plane_masses(rotor, planes)
    per_kg = api_unbalance(1.0, max_speed_rpm)
    if shape is None:
        return per_kg * share
    phi = np.array([shape[NDOF_NODE * p] for p in planes])
    ref = phi[np.argmax(np.abs(phi))]
    proj = (phi * np.conj(ref)).real / abs(ref)  # displacement along the largest one's direction
    on_node = np.abs(phi) < 0.01 * np.abs(ref)
    lobes = [(proj > 0) & ~on_node, (proj < 0) & ~on_node]
    lobes = [lobe for lobe in lobes if lobe.any()]
    U = np.zeros(len(planes))
    for lobe in lobes:
        w = share[lobe].sum() + share[on_node].sum() / len(lobes)
        weight = share[lobe] * np.abs(phi[lobe])
        U[lobe] = per_kg * w * weight / weight.sum()
    return U


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


def _least_damping(rotor: Rotor, speeds, f_max: float = np.inf) -> tuple[np.ndarray, np.ndarray]:
    """Smallest damping ratio of the eigenvalues at each speed [rad/s], and that eigenvalue.

    Every eigenvalue of the first-order system counts (not only the lowest modes a Campbell
    tracks; a real positive eigenvalue is a divergence, damping ratio -1) whose modulus is
    below ``f_max`` [rad/s]; eigenvalues below 1e-9 of the largest modulus (rigid-body zeros,
    round-off) do not.
    """
    from rotaflex.rotor.fe.modal import _state_matrices

    lam = np.linalg.eigvals(_state_matrices(rotor, np.atleast_1d(np.asarray(speeds, float))))
    mod = np.abs(lam)
    use = (mod > 1e-9 * mod.max(-1, keepdims=True)) & (mod <= f_max)
    zeta = np.where(use, -lam.real / np.where(mod > 0, mod, 1.0), np.inf)
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
        checked), ``min_log_dec`` (the smallest log decrement, -2 pi sigma / omega_d, of the
        modes below 3 times the band's top speed -- an undamped shaft mode at tens of kHz
        would otherwise be the one named; -inf for a divergence), ``speed_min`` [rad/s] where
        it occurs, ``frequency`` [rad/s] (its damped frequency), and when unstable ``onset``
        [rad/s] (the lowest unstable speed in the bands: the band's lower end when the mode is
        already unstable there) and ``band`` (lo, hi).

    Examples
    --------
    >>> from rotaflex.rotor.fe.model import Rotor, Shaft, Bearing
    >>> r = Rotor(shaft=(Shaft(outer_diameter=0.05, length=1.0, elements=4),),
    ...           bearing=(Bearing(node=0, kxx=1e7, kyy=1e7, cxx=1e3, cyy=1e3),
    ...                    Bearing(node=4, kxx=1e7, kyy=1e7, cxx=1e3, cyy=1e3)))
    >>> stability_in_bands(r, [(300.0, 400.0)])["stable"]
    True
    """
    from rotaflex.rotor.fe.critical import brent_root
    from rotaflex.rotor.fe.modal import STABILITY_TOL

    out = {"stable": True, "min_log_dec": np.inf, "speed_min": np.nan, "frequency": np.nan}
    for lo, hi in bands:
        sp = np.linspace(lo, hi, n_speeds if hi > lo else 1)
        zeta, lam = _least_damping(rotor, sp)
        if zeta.min() >= -STABILITY_TOL:  # stable: name the least damped mode of interest
            zeta, lam = _least_damping(rotor, sp, 3 * hi)
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
            onset = brent_root(
                lambda w: _least_damping(rotor, [w])[0][0] + STABILITY_TOL, sp[b - 1], sp[b], xtol=2e-12, rtol=1e-6
            )
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
        f"UNSTABLE {where} {rad_s_to_rpm(st['onset']):.0f} rpm "
        f"inside {rad_s_to_rpm(lo):.0f}-{rad_s_to_rpm(hi):.0f} rpm "
        f"(log dec {st['min_log_dec']:.3g} at {rad_s_to_rpm(st['speed_min']):.0f} rpm, "
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
        "speed_rpm": rad_s_to_rpm(st["speed_min"]),
        "frequency_hz": st["frequency"] / (2 * np.pi),
    }
    if not st["stable"]:
        extra["instability_onset_in_operating_range_rpm"] = {"value": rad_s_to_rpm(st["onset"]), "unit": "rpm"}
    return stability_verdict(st)


def rate_peaks(pk: list[dict], bands) -> list[dict]:
    """Add API verdicts to resonance peaks against operating ``bands`` [(lo, hi) rad/s].

    Each peak gains ``position`` ("below", "above", "inside" or "between"), ``sm_percent``
    (the smallest margin to any band, relative to that band's limit; negative inside a band),
    ``sm_required_percent`` (for that band) and ``sm_ok`` (1.0/0.0). A maximum whose AF the
    speed range does not resolve (``af`` nan: its half-power band runs past a range end, or the
    curve still rises there) is rated as if its AF were large, i.e. with the largest margins
    (16 % below, 26 % above): an unknown AF cannot claim API's exemption below 2.5.
    """
    out = []
    for p in pk:
        nc, af = p["speed"], p["af"] if np.isfinite(p["af"]) else np.inf
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


def merge_probe_peaks(per_probe: dict) -> list[dict]:
    """One entry per critical from the peaks of every probe (``{probe: peaks(...)}``).

    Peaks of different probes belong to the same critical when one's speed lies inside the
    other's half-power band (or within 3 % of it when a band is not resolved). The probe with
    the largest amplitude at that critical governs: its speed, AF and margin are the
    critical's, and ``probe`` names it; ``af_by_probe`` keeps every probe's AF (nan: not
    resolved there) and ``probes`` the probes that show the peak.
    """
    flat = sorted(({**p, "probe": int(k)} for k, pk in per_probe.items() for p in pk), key=lambda p: -p["amplitude"])
    groups: list[list[dict]] = []
    for p in flat:  # largest first: each group is led by its governing peak
        for g in groups:
            lead = g[0]
            lo = lead["n1"] if np.isfinite(lead["n1"]) else lead["speed"] * 0.97
            hi = lead["n2"] if np.isfinite(lead["n2"]) else lead["speed"] * 1.03
            if lo <= p["speed"] <= hi and p["probe"] not in {q["probe"] for q in g}:
                g.append(p)
                break
        else:
            groups.append([p])
    out = [
        {**g[0], "probes": sorted(q["probe"] for q in g), "af_by_probe": {str(q["probe"]): q["af"] for q in g}}
        for g in groups
    ]
    return sorted(out, key=lambda p: p["speed"])


def check_bands(bands, field: str) -> list[tuple[float, float]]:
    """Validated operating bands [rpm] -> [(lo, hi)] [rad/s]."""
    out = []
    for i, b in enumerate(bands):
        lo, hi = b
        if not (0 < lo < hi):
            raise InputError(
                f"{field}[{i}]" if len(bands) > 1 else field, list(b), "[min, max] speeds with 0 < min < max"
            )
        out.append((rpm_to_rad_s(lo), rpm_to_rad_s(hi)))
    return out
