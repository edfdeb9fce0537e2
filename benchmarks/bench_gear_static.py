# ruff: noqa: E501
"""Gear FE/static benchmark: mesh sizes, stable dt, tooth-compliance convergence, mesh stiffness,
ISO 6336-1 comparison, root stress and timings. Prints numbers; asserts nothing.

Run: PYTHONPATH=src python benchmarks/bench_gear_static.py
"""

import math
import time

import numpy as np

from rotaflex.gear.fe import lumped_mass, stable_time_step, stiffness_matrix
from rotaflex.gear.geometry import GearGeometry, contact_angles, contact_ratio, path_of_contact
from rotaflex.gear.mesh import COARSE, DEFAULT, build_tooth_mesh, mesh_quality
from rotaflex.gear.static import (
    iso6336_stiffness,
    mesh_stiffness,
    root_stress,
    solve_static,
    surface_load,
    tooth_compliance,
)

E, NU, RHO = 210e9, 0.3, 7800.0
G = GearGeometry(module=3.175e-3, teeth=28, face_width=6.35e-3, tip_radius=0.047625, root_radius=0.04048)
F = 22.25 / G.base_radius


def timed(fn, *a, repeat=3, **kw):
    best = math.inf
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn(*a, **kw)
        best = min(best, time.perf_counter() - t)
    return out, best


def main():
    th_s, th_2 = contact_angles(G, G)
    print(
        f"geometry: r_b={G.base_radius:.6f} m  g_alpha={path_of_contact(G, G):.5f} m  "
        f"eps={contact_ratio(G, G):.4f}  theta_s={math.degrees(th_s):.3f} deg  "
        f"theta_2={math.degrees(th_2):.3f} deg  form radius={G.form_radius:.6f} m"
    )
    print("\nmesh                 elements nodes  min_edge[mm] aspect  dt_RK4[s]  build[ms] K[ms] dt[ms]")
    for name, kw in (
        ("COARSE", COARSE),
        ("DEFAULT", DEFAULT),
        ("2x", {k: 2 * v for k, v in DEFAULT.items()}),
        ("4x", {k: 4 * v for k, v in DEFAULT.items()}),
    ):
        m, tb = timed(build_tooth_mesh, G, **kw)
        _, tk = timed(stiffness_matrix, m, E, NU)
        dt, td = timed(stable_time_step, m, E, NU, RHO, repeat=1)
        q = mesh_quality(m)
        print(
            f"{name:20s} {m.n_elements:8d} {m.n_nodes:5d}  {q['min_edge'] * 1e3:10.3f} "
            f"{q['max_aspect_ratio']:7.2f}  {dt:.3e}  {tb * 1e3:8.1f} {tk * 1e3:5.1f} {td * 1e3:6.1f}"
        )
    m = build_tooth_mesh(G, **DEFAULT)
    print(f"  HRZ mass total {lumped_mass(m, RHO).sum() / 2:.6e} kg, min nodal {lumped_mass(m, RHO).min():.3e} kg")

    radii = np.array([G.form_radius * 1.001, 0.0430, G.pitch_radius, 0.0460, 0.0472])
    print("\ntooth compliance along the line of action [um/kN]: structural (centreline point) | load-point")
    print("refine  elements  " + "  ".join(f"r={r * 1e3:.2f}mm" for r in radii))
    for k in (1, 2, 3, 4, 6):
        mk = build_tooth_mesh(G, **{key: k * v for key, v in DEFAULT.items()})
        c, t = timed(tooth_compliance, mk, radii, E, NU, force=F, repeat=1)
        print(
            f"{k:5d}x {mk.n_elements:8d}  "
            + "  ".join(f"{v * 1e9:9.5f}" for v in c.structural)
            + "   |  "
            + "  ".join(f"{v * 1e9:7.4f}" for v in c.load_point)
            + f"   ({t:.2f} s)"
        )

    print("\nrim depth (modules) vs structural compliance at the pitch radius [um/kN] (sides tied)")
    for rd in (1.0, 2.0, 3.0, 4.0):
        mk = build_tooth_mesh(G, n_flank=20, n_through=10, n_fillet=4, n_rim=int(4 * rd), rim_depth_coef=rd)
        c = tooth_compliance(mk, np.array([G.pitch_radius]), E, NU, force=F)
        print(f"  {rd:.0f}: {c.structural[0] * 1e9:.5f}")

    ms, t = timed(mesh_stiffness, G, G, E, NU, torque=22.25, mesh1=m, mesh2=m, repeat=1)
    b = G.face_width * 1e3
    iso = iso6336_stiffness(G, G, load_per_width=F / b)
    single = ms.pair_stiffness[(ms.angle > ms.theta_2) & (ms.angle < ms.theta_s - ms.theta_2)]
    print(f"\npair/mesh stiffness (DEFAULT mesh, {t:.2f} s):")
    print(
        f"  single pair k: min {ms.pair_stiffness.min():.4e}  max {ms.pair_stiffness.max():.4e} N/m"
        f"  -> max per width {ms.pair_stiffness.max() / b / 1e6:.2f} N/(mm um)"
    )
    print(f"  single-pair zone k: {single.min():.4e} .. {single.max():.4e} N/m")
    print(
        f"  mesh stiffness mean {ms.mesh_stiffness.mean():.4e} N/m = {ms.mesh_stiffness.mean() / b / 1e6:.2f} N/(mm um)"
    )
    print(
        f"  static TE along LOA: {ms.transmission_error.min() * 1e6:.3f} .. {ms.transmission_error.max() * 1e6:.3f} um"
        f" (peak-to-peak {np.ptp(ms.transmission_error) * 1e6:.3f} um) at F = {ms.force:.1f} N"
    )
    print(
        f"  ISO 6336-1: c'_th = {iso['c_th']:.2f}, c' = {iso['c_single']:.2f} (C_M={iso['C_M']}, "
        f"C_B={iso['C_B']:.4f}, load factor={iso['load_factor']:.4f}), c_gamma_alpha = {iso['c_gamma']:.2f} N/(mm um);"
        f" c'_th-based c_gamma = {iso['k_th_gamma'] / b / 1e6:.2f}"
    )
    print(
        f"  FE/ISO: single max / c'_th = {ms.pair_stiffness.max() / iso['k_th']:.3f}, / c' = "
        f"{ms.pair_stiffness.max() / iso['k_single']:.3f}; mean mesh / c_gamma(c'_th) = "
        f"{ms.mesh_stiffness.mean() / iso['k_th_gamma']:.3f}, / c_gamma = {ms.mesh_stiffness.mean() / iso['k_gamma']:.3f}"
    )

    print("\nroot stress at the 30-deg tangent points, load F at r = 47.2 mm on the right flank [MPa] (left, right)")
    for k in (1, 2, 3, 4):
        mk = build_tooth_mesh(G, **{key: k * v for key, v in DEFAULT.items()})
        u = solve_static(mk, surface_load(mk, 0.0472, F, 8e-5), E, NU)
        print(f"  {k}x: {np.round(root_stress(mk, u, E, NU) / 1e6, 2)}")


if __name__ == "__main__":
    main()
