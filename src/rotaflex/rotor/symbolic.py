"""Symbolic derivation of rotor/rigid-body equations of motion, compiled and cached on disk.

From the Lagrangian ``L = K_t + K_r - V`` (sympy) we form, for generalized coordinates ``q``::

    M(q, t) q'' = f(q, q', t),   M = d2L/dq'dq',
    f = dL/dq - (d2L/dq'dq) q' - d2L/dq'dt + Q

and print ``M``, ``f`` and the attitude (quaternion and its rate) as one plain-Python function
with common subexpressions eliminated (``math`` functions on scalars: faster than NumPy for the
small systems here). The source is cached under ``ROTAFLEX_CACHE_DIR`` (default
``~/.cache/rotaflex``) keyed by a hash of the formulation, so a second run does not re-derive.
sympy is imported by the derivation only: a run that finds its equations in the cache never
loads it (~0.5 s of start-up).
"""

from __future__ import annotations

import functools
import hashlib
import importlib.metadata
import logging
import os
import stat
from dataclasses import dataclass
from pathlib import Path

from rotaflex.core.io import write_text_atomic

log = logging.getLogger(__name__)

#: bump when the generated code changes meaning (invalidates caches)
CODEGEN_VERSION = "4"


@functools.cache
def _sympy_version() -> str:
    """sympy's version from its package metadata: the cache key needs it, and importing sympy
    (~0.5 s) only to read it would cost every cached run what the cache saves."""
    try:
        return importlib.metadata.version("sympy")
    except importlib.metadata.PackageNotFoundError:  # pragma: no cover - e.g. a source checkout
        import sympy

        return sympy.__version__


#: parameter vector layout shared by the generated code and the simulator
PARAMETERS = ("m", "J1", "J2", "J3", "k", "k_tilt", "Omega", "phi0", "tau1", "tau2", "tau3")


@dataclass(frozen=True)
class EOMSpec:
    """What to derive (hashable; the cache key).

    parameterisation : "euler" or "quaternion_spherical"
    sequence, convention : Euler sequence and sign convention
    energy : "body" or "inertial_paper"; expansion : "nonlinear", "second_order", "paper_truncated"
    spin_index : index of the prescribed Euler angle, or None for a free body (all angles free)
    """

    parameterisation: str = "euler"
    sequence: str = "123"
    convention: str = "right-handed"
    energy: str = "body"
    expansion: str = "nonlinear"
    spin_index: int | None = 0

    @property
    def translation(self) -> bool:
        return self.spin_index is not None or self.parameterisation == "quaternion_spherical"

    def key(self) -> str:
        text = repr((CODEGEN_VERSION, _sympy_version(), self))
        return hashlib.sha256(text.encode()).hexdigest()[:20]


def _rot(axis: int, a):
    import sympy as sp

    c, s = sp.cos(a), sp.sin(a)
    R = sp.eye(3)
    i, j = (axis + 1) % 3, (axis + 2) % 3
    R[i, i], R[j, j], R[i, j], R[j, i] = c, c, -s, s
    return R


def _skew(v):
    import sympy as sp

    return sp.Matrix([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


def _euler_attitude(spec: EOMSpec, angles, rates):
    """R, body and inertial angular velocity of an Euler sequence (sympy)."""
    import sympy as sp

    a, b, c = (int(ch) - 1 for ch in spec.sequence)
    ang = list(angles)
    if spec.convention == "paper":
        ang[1] = -ang[1]  # the paper's maps: matrices evaluated with the second angle negated
    Ra, Rb, Rc = _rot(a, ang[0]), _rot(b, ang[1]), _rot(c, ang[2])
    ea, eb, ec = (sp.eye(3)[:, i] for i in (a, b, c))
    w_body = (Rb * Rc).T * ea * rates[0] + Rc.T * eb * rates[1] + ec * rates[2]
    w_inertial = ea * rates[0] + Ra * eb * rates[1] + Ra * Rb * ec * rates[2]
    R = Ra * Rb * Rc
    # quaternion of the attitude for output (product of axis quaternions, scalar first)
    e = sp.Matrix([1, 0, 0, 0])
    for axis, angle in zip((a, b, c), ang, strict=False):
        qk = sp.Matrix([sp.cos(angle / 2), 0, 0, 0])
        qk[1 + axis] = sp.sin(angle / 2)
        e = _qmul(e, qk)
    return R, w_body, w_inertial, e


def _qmul(p, q):
    import sympy as sp

    p0, pv, q0, qv = p[0], p[1:, 0], q[0], q[1:, 0]
    s = p0 * q0 - (pv.T * qv)[0]
    v = p0 * qv + q0 * pv + pv.cross(qv)
    return sp.Matrix([s, *v])


def _quaternion_rates(e, e_dot):
    import sympy as sp

    e0, v = e[0], e[1:, 0]
    S = _skew(v)
    L = sp.Matrix.hstack(-v, e0 * sp.eye(3) - S)  # w*  = 2 L e'
    G = sp.Matrix.hstack(-v, e0 * sp.eye(3) + S)  # w   = 2 G e'
    return 2 * L * e_dot, 2 * G * e_dot


def derive(spec: EOMSpec):
    """Symbolic ``(t, q, qd, p, M, f, e, e_dot)`` for ``spec`` (see module docstring)."""
    import sympy as sp

    t = sp.Symbol("t")
    p = sp.symbols(PARAMETERS)
    m, J1, J2, J3, k, k_tilt, Omega, phi0, *tau = p
    J = sp.diag(J1, J2, J3)

    if spec.parameterisation == "quaternion_spherical":
        names = ["eps_theta", "eps_psi"]
    elif spec.spin_index is None:
        names = [f"a{i}" for i in range(3)]
    else:
        names = [f"a{i}" for i in range(3) if i != spec.spin_index]
    rot_q = sp.symbols(names)
    rot_qd = sp.symbols([n + "_d" for n in names])
    trans_q = sp.symbols("U V") if spec.translation else ()
    trans_qd = sp.symbols("U_d V_d") if spec.translation else ()
    q, qd = (*trans_q, *rot_q), (*trans_qd, *rot_qd)

    spin = Omega * t + phi0
    if spec.parameterisation == "quaternion_spherical":
        # eq. 21-22 with the + signs: theta = pi/2 + eps_theta, psi = pi + eps_psi
        th, ps = sp.pi / 2 + rot_q[0], sp.pi + rot_q[1]
        half = spin / 2
        e = sp.Matrix(
            [
                sp.cos(half),
                sp.sin(half) * sp.sin(th) * sp.cos(ps),
                sp.sin(half) * sp.sin(th) * sp.sin(ps),
                sp.sin(half) * sp.cos(th),
            ]
        )
        e_dot = e.diff(t) + sum((e.diff(qi) * qdi for qi, qdi in zip(rot_q, rot_qd, strict=False)), sp.zeros(4, 1))
        w_body, w_inertial = _quaternion_rates(e, e_dot)
        S = _skew(e[1:, 0])
        R = sp.eye(3) + 2 * e[0] * S + 2 * S * S
        polar = 0
    else:
        if spec.spin_index is None:
            angles, rates = list(rot_q), list(rot_qd)
        else:
            it, itd = iter(rot_q), iter(rot_qd)
            angles = [spin if i == spec.spin_index else next(it) for i in range(3)]
            rates = [Omega if i == spec.spin_index else next(itd) for i in range(3)]
        R, w_body, w_inertial, e = _euler_attitude(spec, angles, rates)
        e_dot = e.diff(t) + sum((e.diff(qi) * qdi for qi, qdi in zip(rot_q, rot_qd, strict=False)), sp.zeros(4, 1))
        polar = int(spec.sequence[spec.spin_index or 0]) - 1

    w = w_body if spec.energy == "body" else w_inertial
    K_rot = (w.T * J * w)[0] / 2
    V_rot = 0
    if spec.spin_index is not None or spec.parameterisation == "quaternion_spherical":
        # tilt potential k_tilt (1 - n . n0), n the polar axis in inertial components
        V_rot = k_tilt * (1 - R[polar, polar])
    K_rot, V_rot = _expand(spec.expansion, K_rot, V_rot, rot_q, rot_qd)

    K_t = m * sum(v**2 for v in trans_qd) / 2
    V_t = k * sum(u**2 for u in trans_q) / 2
    L = K_t + K_rot - V_t - V_rot

    Q = sp.zeros(len(q), 1)
    if spec.spin_index is None and spec.parameterisation == "euler":
        # free body: generalized forces of a body-frame torque (virtual work tau . E_body dq)
        Q = sp.Matrix(w_body).jacobian(rot_qd).T * sp.Matrix(tau)

    L_qd = sp.Matrix([L.diff(v) for v in qd])
    M = L_qd.jacobian(qd)
    f = sp.Matrix([L.diff(v) for v in q]) - L_qd.jacobian(q) * sp.Matrix(qd) - L_qd.diff(t)
    f += Q
    return t, q, qd, p, M, f, e, e_dot


def _expand(expansion: str, K, V, q, qd):
    """Second-order Taylor expansion in the small coordinates and rates (exact or as printed)."""
    import sympy as sp

    if expansion == "nonlinear":
        return K, V
    eps = sp.Symbol("eps")
    small = {v: eps * v for v in (*q, *qd)}

    def taylor2(expr):
        s = expr.subs(small, simultaneous=True)
        d1 = s.diff(eps)
        return s.subs(eps, 0) + d1.subs(eps, 0) + d1.diff(eps).subs(eps, 0) / 2

    K2, V2 = taylor2(K), taylor2(V)
    if expansion == "paper_truncated":
        # drop the quadratic kinetic terms that contain no rate (eq. 27 omits -Omega^2 (th^2+ps^2))
        coords_only = K2.subs({v: 0 for v in qd}) - K2.subs({v: 0 for v in (*q, *qd)})
        quadratic = sp.expand(coords_only)
        linear = sum((quadratic.coeff(v, 1).subs({u: 0 for u in q}) * v for v in q), sp.S(0))
        K2 = K2 - (quadratic - linear)
    return K2, V2


def generate_source(spec: EOMSpec) -> str:
    """Python source of ``_all(t, y, p)`` (M, f and the attitude e, e_dot) and ``_mass_rhs(t, y, p)``
    (M and f only) for ``spec``."""
    import sympy as sp
    from sympy.printing.pycode import PythonCodePrinter

    t, q, qd, p, M, f, e, e_dot = derive(spec)
    n = len(q)
    exprs = list(M) + list(f) + list(e) + list(e_dot)
    replacements, reduced = sp.cse(exprs, symbols=sp.numbered_symbols("x"), optimizations="basic")
    printer = PythonCodePrinter({"fully_qualified_modules": False, "standard": "python3"})
    body = [f"    {printer.doprint(s)} = {printer.doprint(v)}" for s, v in replacements]
    M_r, f_r = reduced[: n * n], reduced[n * n : n * n + n]
    e_r, ed_r = reduced[n * n + n : n * n + n + 4], reduced[n * n + n + 4 :]
    unpack = [
        f"    ({', '.join(map(str, (*q, *qd)))},) = y",
        f"    ({', '.join(map(str, p))},) = p",
    ]

    def tup(xs):
        return "(" + ", ".join(printer.doprint(x) for x in xs) + ",)"

    # the right-hand side needs M and f only: its function keeps the subexpressions they use
    # (the same lines, so the same values to the bit) and skips the attitude outputs
    needed = set().union(*(x.free_symbols for x in (*M_r, *f_r)))
    for sym, value in reversed(replacements):
        if sym in needed:
            needed |= value.free_symbols
    body_mf = [line for (sym, _), line in zip(replacements, body, strict=True) if sym in needed]
    lines = [
        f"# generated by rotaflex.rotor.symbolic (codegen {CODEGEN_VERSION}) for {spec!r}",
        "from math import *  # noqa: F401,F403",
        f"N_DOF = {n}",
        f"COORDINATES = {tuple(map(str, q))!r}",
        f"MASS_DIAGONAL = {all(M_r[i * n + j] == 0 for i in range(n) for j in range(n) if i != j)!r}",
        "",
        "",
        "def _all(t, y, p):",
        *unpack,
        *body,
        f"    return {tup(M_r)}, {tup(f_r)}, {tup(e_r)}, {tup(ed_r)}",
        "",
        "",
        "def _mass_rhs(t, y, p):",
        *unpack,
        *body_mf,
        f"    return {tup(M_r)}, {tup(f_r)}",
        "",
    ]
    return "\n".join(lines)


def cache_dir() -> Path:
    """Directory of cached generated code (``ROTAFLEX_CACHE_DIR`` or ``~/.cache/rotaflex``)."""
    root = os.environ.get("ROTAFLEX_CACHE_DIR") or Path.home() / ".cache" / "rotaflex"
    return Path(root) / "eom"


_LOADED: dict[str, dict] = {}


def _trusted_dir(path: Path) -> bool:
    """The cache directory exists, is ours and nobody else can write into it.

    Cached source is executed, so a directory others can write to would let them run code as
    us; such a cache is ignored (the equations are derived again, in memory).
    """
    try:
        st = path.stat()
    except OSError:
        return False
    return stat.S_ISDIR(st.st_mode) and st.st_uid == os.getuid() and not (st.st_mode & 0o022)


def _digest(source: str) -> str:
    return hashlib.sha256(source.encode("utf-8")).hexdigest()


def _read_cached(path: Path) -> str | None:
    """Cached source whose stored SHA-256 matches it, in a trusted directory; else None."""
    sums = path.with_suffix(".sha256")
    if not (path.exists() and sums.exists() and _trusted_dir(path.parent)):
        return None
    try:
        source = path.read_text(encoding="utf-8")
        expected = sums.read_text(encoding="utf-8").strip()
    except (OSError, UnicodeDecodeError):
        return None
    if _digest(source) != expected:
        log.warning("cached rotor equations %s do not match their checksum; deriving again", path)
        return None
    return source


def _write_cached(path: Path, source: str) -> None:
    path.parent.mkdir(parents=True, exist_ok=True, mode=0o700)
    if not _trusted_dir(path.parent):
        log.warning("not caching rotor equations: %s is not owned by this user or writable by others", path.parent)
        return
    write_text_atomic(path, source)
    write_text_atomic(path.with_suffix(".sha256"), _digest(source) + "\n")


def compiled(spec: EOMSpec, *, use_cache: bool = True) -> dict:
    """Namespace with ``_all``, ``_mass_rhs``, ``N_DOF``, ``COORDINATES``, ``MASS_DIAGONAL`` (the
    mass matrix has no off-diagonal terms, structurally) for ``spec`` (derived at most once).

    Looks in memory, then on disk, then derives with sympy and writes the source atomically.
    Cached source is executed only if its directory belongs to the user, is not writable by
    others, and the source matches the SHA-256 stored beside it.
    """
    key = spec.key()
    if use_cache and key in _LOADED:
        return _LOADED[key]
    path = cache_dir() / f"eom_{key}.py"
    source = _read_cached(path) if use_cache else None
    if source is not None:
        log.debug("rotor EOM %s loaded from cache %s", spec, path)
    else:
        log.info("deriving rotor EOM for %s", spec)
        source = generate_source(spec)
        try:
            _write_cached(path, source)
        except OSError as exc:  # a read-only home must not stop a simulation
            log.warning("could not cache derived equations at %s: %s", path, exc)
    namespace: dict = {}
    exec(compile(source, str(path), "exec"), namespace)
    _LOADED[key] = namespace
    return namespace
