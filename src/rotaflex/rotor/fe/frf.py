"""Frequency response functions: receptance, mobility and accelerance between node DOFs.

At a fixed spin speed Omega, a harmonic force F e^{i w t} on the input DOF gives the steady
response X e^{i w t} with

    [K(Omega) - w^2 M + i w (C(Omega) + Omega G)] X = F,

so the receptance is H(w) = X / F = column of the inverse dynamic stiffness [m/N, rad/N, m/(N m)
...]; mobility is i w H [m/(N s)] and accelerance -w^2 H [m/(N s^2)]. All frequencies are solved
in one batched LAPACK call. The bearings' coefficients are taken at the spin speed (not at the
excitation frequency), as for any linear rotor analysis here.

For a non-rotating rotor with symmetric K and C the dynamic stiffness is symmetric, so
H_ij = H_ji (Maxwell-Betti reciprocity); the gyroscopic term and cross-coupled bearings break it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rotaflex.core.errors import InputError
from rotaflex.rotor.fe.model import NDOF_NODE, Rotor
from rotaflex.rotor.fe.response import dynamic_stiffness

DIRECTIONS = ("x", "y", "theta_x", "theta_y")
KINDS = {"receptance": 0, "mobility": 1, "accelerance": 2}


def dof_index(
    rotor: Rotor, node: int, direction: str, where: str = "frf", keys: tuple[str, str] = ("node", "direction")
) -> int:
    """Global DOF number of ``direction`` (x, y, theta_x, theta_y) at ``node``; errors name
    ``where`` + the key of the node / the direction (``keys``) as the config spells them."""
    if not 0 <= node < rotor.n_nodes:
        raise InputError(f"{where}.{keys[0]}", node, f"an existing node 0..{rotor.n_nodes - 1}")
    if direction not in DIRECTIONS:
        raise InputError(f"{where}.{keys[1]}", direction, "one of " + ", ".join(DIRECTIONS))
    return NDOF_NODE * node + DIRECTIONS.index(direction)


@dataclass(frozen=True)
class FRFData:
    """FRFs at ``frequency`` [rad/s]: ``H`` (n_freq, n_out, n_in) complex, in the units of ``kind``."""

    frequency: np.ndarray
    H: np.ndarray
    kind: str


def frf(rotor: Rotor, frequencies, speed: float = 0.0, inputs=(0,), outputs=None, kind="receptance") -> FRFData:
    """FRF matrix between input and output DOFs at spin ``speed`` [rad/s].

    Parameters
    ----------
    frequencies : array (f,) [rad/s]
    inputs, outputs : sequences of global DOF numbers (:func:`dof_index`); outputs default to inputs
    kind : {"receptance", "mobility", "accelerance"}

    Examples
    --------
    >>> from rotaflex.rotor.fe.model import Rotor, Shaft, Bearing
    >>> r = Rotor(shaft=(Shaft(outer_diameter=0.05, length=1.0, elements=4),),
    ...           bearing=(Bearing(node=0, kxx=1e7, kyy=1e7), Bearing(node=4, kxx=1e7, kyy=1e7)))
    >>> frf(r, [10.0, 20.0], 0.0, [8], [8, 9]).H.shape
    (2, 2, 1)
    """
    if kind not in KINDS:
        raise InputError("frf.kind", kind, "one of " + ", ".join(KINDS))
    w = np.atleast_1d(np.asarray(frequencies, float))
    inputs = list(inputs)
    outputs = inputs if outputs is None else list(outputs)
    M, K, C = rotor.MKC(speed)
    E = np.zeros((rotor.n_dof, len(inputs)))
    E[inputs, np.arange(len(inputs))] = 1.0
    X = dynamic_solve(M[0], C[0] + speed * rotor.G, K[0], w, E)
    return FRFData(w, in_kind(X[:, outputs, :], w, kind), kind)


def dynamic_solve(M: np.ndarray, D: np.ndarray, K: np.ndarray, w: np.ndarray, B: np.ndarray) -> np.ndarray:
    """Receptances ``X`` (f, n, r) of ``[K - w^2 M + i w D] X = B`` at each frequency of ``w``.

    One batched LAPACK solve over the frequencies, with the matrices at one spin speed: the
    rotor's ``D = C(Omega) + Omega G`` (:func:`frf`) or a machine's (:mod:`rotaflex.system.frf`,
    every rotor at its own speed, on the solved coordinates).

    Parameters
    ----------
    M, D, K : ndarray (n, n) [kg, N s/m, N/m]
    w : ndarray (f,) excitation frequencies [rad/s]
    B : ndarray (n, r) unit force patterns, one column per input

    Returns
    -------
    ndarray (f, n, r) complex [m/N, rad/N, ...]
    """
    return np.linalg.solve(dynamic_stiffness(M, D, K, w), np.broadcast_to(B, (w.size, *B.shape)))


def in_kind(X: np.ndarray, w: np.ndarray, kind: str) -> np.ndarray:
    """Receptances ``X`` (f, ...) at ``w`` [rad/s] as ``kind``: X, i w X or -w^2 X."""
    return X * ((1j * w) ** KINDS[kind]).reshape(-1, *(1,) * (X.ndim - 1))


UNITS = {"receptance": "m/N", "mobility": "m/(N s)", "accelerance": "m/(N s^2)"}


def pair_unit(kind: str, output_direction: str, input_direction: str) -> str:
    """Unit of an FRF between DOF directions (x, y: m and N; theta_x, theta_y, twist: rad and
    N m): ``m/N`` for a force to a displacement, ``rad/(N m)`` for a moment to a rotation, ...,
    with ``/s`` (mobility) or ``/s^2`` (accelerance)."""
    out = "m" if output_direction in ("x", "y") else "rad"
    load = "N" if input_direction in ("x", "y") else "N m"
    per = {"receptance": "", "mobility": " s", "accelerance": " s^2"}[kind]
    den = load + per
    return f"{out}/{den}" if den == "N" else f"{out}/({den})"


def frf_dataset(w: np.ndarray, H: np.ndarray, labels: list, kind: str, speed_rpm: float, units: list | None = None):
    """The FRF dataset, its summary values and message (rotor and machine verbs alike).

    Parameters
    ----------
    w : ndarray (f,) [rad/s]
    H : ndarray (f, p) complex, one column per pair ``labels[j]`` (output / input), in ``kind``
    speed_rpm : float, the (drive) speed [rpm] the matrices are taken at
    units : list of str, the unit of each pair (:func:`pair_unit`); None: all translations per
        force (``UNITS[kind]``). Where the pairs differ the arrays' ``units`` attribute says
        "see pair_unit" and the coordinate ``pair_unit`` holds each one.

    Returns
    -------
    (xarray.Dataset, dict of summary values, message): real and imaginary parts, amplitude and
    phase per pair; each pair's resonance peaks with half-power damping (:func:`half_power`).
    """
    import xarray as xr

    units = [UNITS[kind]] * len(labels) if units is None else list(units)
    unit = units[0] if len(set(units)) == 1 else "see pair_unit"
    ds = xr.Dataset(
        {
            "H_real": (("frequency", "pair"), H.real, {"units": unit}),
            "H_imag": (("frequency", "pair"), H.imag, {"units": unit}),
            "amplitude": (("frequency", "pair"), np.abs(H), {"units": unit, "long_name": f"|{kind}|"}),
            "phase": (("frequency", "pair"), np.angle(H), {"units": "rad"}),
            "frequency_hz": ("frequency", w / (2 * np.pi), {"units": "Hz"}),
        },
        coords={"frequency": ("frequency", w, {"units": "rad/s"}), "pair": labels},
    )
    if len(set(units)) > 1:
        ds = ds.assign_coords(pair_unit=("pair", units))
    ds.attrs["kind"] = kind
    ds.attrs["speed_rpm"] = speed_rpm
    extra = {"speed": {"value": speed_rpm, "unit": "rpm"}, "kind": {"value": kind, "unit": unit}}
    shown = []
    for j, lab in enumerate(labels):
        for k, p in enumerate(half_power(w, np.abs(H[:, j]))):
            extra[f"{lab}_peak_{k}_frequency_hz"] = {"value": p["frequency"] / (2 * np.pi), "unit": "Hz"}
            extra[f"{lab}_peak_{k}_amplitude"] = {"value": p["amplitude"], "unit": units[j]}
            extra[f"{lab}_peak_{k}_half_power_damping_ratio"] = {"value": p["zeta"], "unit": "1"}
            if j == 0:
                shown.append(f"{p['frequency'] / (2 * np.pi):.4g} Hz")
    msg = f"{len(labels)} FRFs at {speed_rpm:g} rpm; peaks of {labels[0]}: " + (", ".join(shown) or "none")
    return ds, extra, msg


def half_power(frequency: np.ndarray, amplitude: np.ndarray) -> list[dict]:
    """Resonance peaks of |H| with half-power frequencies and the damping ratio (w2 - w1) / (2 w_peak).

    The peak frequency is refined by a parabola through the three highest samples; peaks whose
    half-power band is not inside the frequency range are skipped.
    """
    from rotaflex.rotor.fe.response import peaks

    return [
        {"frequency": p["speed"], "amplitude": p["amplitude"], "w1": p["n1"], "w2": p["n2"], "zeta": 0.5 / p["af"]}
        for p in peaks(frequency, amplitude)
    ]
