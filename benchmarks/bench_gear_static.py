# ruff: noqa: E501
"""Gear FE/static benchmark: mesh sizes, stable dt, tooth-compliance convergence, mesh stiffness,
ISO 6336-1 comparison, root stress and timings. Prints numbers; asserts nothing.

Run: PYTHONPATH=src python benchmarks/bench_gear_static.py [--tiny]
(``--tiny``: the coarse mesh only, one refinement level, 40 samples of the mesh cycle, the
20/40 example on the coarse mesh with 12 angles; checks the script runs.)
"""

import argparse
import math
import time

import numpy as np

from rotaflex.gear.pair import paper
from rotaflex.gear.pair.geometry import (
    center_distance_no_backlash,
    contact_angles,
    contact_ratio,
    path_of_contact,
)
from rotaflex.gear.pair.plane_stress import lumped_mass, stable_time_step, stiffness_matrix
from rotaflex.gear.pair.tooth_mesh import COARSE, DEFAULT, build_tooth_mesh, mesh_quality
from rotaflex.gear.static.loaded_te import loaded_te, pair_line
from rotaflex.gear.static.tooth_analysis import (
    iso6336_stiffness,
    mesh_stiffness,
    root_stress,
    solve_static,
    surface_load,
    tooth_compliance,
)

E, NU, RHO = paper.YOUNGS_MODULUS, paper.POISSON_RATIO, paper.DENSITY
G = paper.geometry()
F = paper.TORQUE / G.base_radius
#: --tiny: the smallest sizes (set by main)
TINY = False


def timed(fn, *a, repeat=3, **kw):
    best = math.inf
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn(*a, **kw)
        best = min(best, time.perf_counter() - t)
    return out, best


def main():
    global TINY
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tiny", action="store_true", help="coarse mesh, one level, few samples (checks it runs)")
    TINY = ap.parse_args().tiny
    analyses()
    static_command()


def analyses():
    th_s, th_2 = contact_angles(G, G)
    print(
        f"geometry: r_b={G.base_radius:.6f} m  g_alpha={path_of_contact(G, G):.5f} m  "
        f"eps={contact_ratio(G, G):.4f}  theta_s={math.degrees(th_s):.3f} deg  "
        f"theta_2={math.degrees(th_2):.3f} deg  form radius={G.form_radius:.6f} m"
    )
    print("\nmesh                 elements nodes  min_edge[mm] aspect  dt_RK4[s]  build[ms] K[ms] dt[ms]")
    meshes = (
        ("COARSE", COARSE),
        ("DEFAULT", DEFAULT),
        ("2x", {k: 2 * v for k, v in DEFAULT.items()}),
        ("4x", {k: 4 * v for k, v in DEFAULT.items()}),
    )
    for name, kw in meshes[:1] if TINY else meshes:
        m, tb = timed(build_tooth_mesh, G, **kw)
        _, tk = timed(stiffness_matrix, m, E, NU)
        dt, td = timed(stable_time_step, m, E, NU, RHO, repeat=1)
        q = mesh_quality(m)
        print(
            f"{name:20s} {m.n_elements:8d} {m.n_nodes:5d}  {q['min_edge'] * 1e3:10.3f} "
            f"{q['max_aspect_ratio']:7.2f}  {dt:.3e}  {tb * 1e3:8.1f} {tk * 1e3:5.1f} {td * 1e3:6.1f}"
        )
    m = build_tooth_mesh(G, **(COARSE if TINY else DEFAULT))
    print(f"  HRZ mass total {lumped_mass(m, RHO).sum() / 2:.6e} kg, min nodal {lumped_mass(m, RHO).min():.3e} kg")

    radii = np.array([G.form_radius * 1.001, 0.0430, G.pitch_radius, 0.0460, 0.0472])
    print("\ntooth compliance along the line of action [um/kN]: structural (centreline point) | load-point")
    print("refine  elements  " + "  ".join(f"r={r * 1e3:.2f}mm" for r in radii))
    for k in (1,) if TINY else (1, 2, 3, 4, 6):
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
    for rd in (1.0,) if TINY else (1.0, 2.0, 3.0, 4.0):
        mk = build_tooth_mesh(G, n_flank=20, n_through=10, n_fillet=4, n_rim=int(4 * rd), rim_depth_coef=rd)
        c = tooth_compliance(mk, np.array([G.pitch_radius]), E, NU, force=F)
        print(f"  {rd:.0f}: {c.structural[0] * 1e9:.5f}")

    ms, t = timed(mesh_stiffness, G, G, E, NU, torque=22.25, mesh1=m, mesh2=m, repeat=1)
    b = G.face_width * 1e3
    # ISO 6336-1: F_t at the reference circle (T / r), K_A = 1, per face width in N/mm
    iso = iso6336_stiffness(G, G, load_per_width=22.25 / G.pitch_radius / b)
    # one-cycle mean: mesh stiffness over one base pitch (uniform samples, endpoint excluded)
    line = pair_line(G, G, m, m, center_distance_no_backlash(G, G), F, (E, NU, E, NU))
    n_cyc = 40 if TINY else 4000
    cyc = loaded_te(line, line.s_start + G.base_pitch * np.arange(n_cyc) / n_cyc)
    k_cycle_mean = float(cyc["stiffness"].mean())
    single = ms.pair_stiffness[(ms.angle > ms.theta_2) & (ms.angle < ms.theta_s - ms.theta_2)]
    print(f"\npair/mesh stiffness ({'COARSE' if TINY else 'DEFAULT'} mesh, {t:.2f} s):")
    print(
        f"  single pair k: min {ms.pair_stiffness.min():.4e}  max {ms.pair_stiffness.max():.4e} N/m"
        f"  -> max per width {ms.pair_stiffness.max() / b / 1e6:.2f} N/(mm um)"
    )
    print(f"  single-pair zone k: {single.min():.4e} .. {single.max():.4e} N/m")
    print(
        f"  mesh stiffness one-cycle mean {k_cycle_mean:.4e} N/m = {k_cycle_mean / b / 1e6:.2f} N/(mm um)"
        f"  (mean over one pair's whole engagement, not a cycle mean: {ms.mesh_stiffness.mean():.4e})"
    )
    print(f"  STE one-cycle mean {cyc['te'].mean() * 1e6:.3f} um, peak-to-peak {np.ptp(cyc['te']) * 1e6:.3f} um")
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
        f"{ms.pair_stiffness.max() / iso['k_single']:.3f}; one-cycle mean / c_gamma(c'_th) = "
        f"{k_cycle_mean / iso['k_th_gamma']:.3f}, / c_gamma = {k_cycle_mean / iso['k_gamma']:.3f}"
    )

    print("\nroot stress at the 30-deg tangent points, load F at r = 47.2 mm on the right flank [MPa] (left, right)")
    for k in (1,) if TINY else (1, 2, 3, 4):
        mk = build_tooth_mesh(G, **{key: k * v for key, v in DEFAULT.items()})
        u = solve_static(mk, surface_load(mk, 0.0472, F, 8e-5), E, NU)
        print(f"  {k}x: {np.round(root_stress(mk, u, E, NU) / 1e6, 2)}")


def static_command():
    """`gear static` on the 20/40 example: timings per mesh preset, root clamp vs rim."""
    from pathlib import Path

    from rotaflex.core.config import load_toml
    from rotaflex.gear.cases.static import run_static

    cfg = load_toml(Path(__file__).resolve().parents[1] / "examples/gear/unequal_shifted_relief.toml")
    print("\ngear static, examples/gear/unequal_shifted_relief.toml (20/40, x 0.25/0.1, tip relief)")
    print("preset   refinement  wall[s]  STE mean[um]  p-p[um]  p-p no relief[um]  k mean[N/um]  c'[N/(mm um)]")
    runs = (("coarse", [1, 2]),) if TINY else (("coarse", [1]), ("default", [1]), ("default", [1, 2]), ("fine", [1]))
    for preset, refine in runs:
        n_angles = 20 if TINY else 240
        c = dict(cfg, mesh={"preset": preset, "n_radii": 9}, analysis={"n_angles": n_angles, "refinement": refine})
        t = time.perf_counter()
        ds = run_static(c).dataset
        wall = time.perf_counter() - t
        print(
            f"{preset:8s} {str(refine):11s} {wall:7.2f}  {ds['ste_mean'].item() * 1e6:12.3f}"
            f"  {ds['ste_ptp'].item() * 1e6:7.3f}  {ds['ste_ptp_unrelieved'].item() * 1e6:17.3f}"
            f"  {ds['mesh_stiffness_mean'].item() * 1e-6:12.1f}  {ds['iso_c_prime'].item():.2f}"
            f" (C_R {ds['iso_C_R'].item():.3f})"
        )
        if refine == [1, 2]:
            for gname in ("pinion", "wheel"):
                print(
                    f"    refinement change {gname}: "
                    + ", ".join(
                        f"{mname} {ds[f'refinement_change_{gname}_{mname}'].item() * 100:.2f} %"
                        for mname in ("structural", "load_point", "with_contact")
                    )
                )
            print(
                f"    fillet stress max: pinion {ds['fillet_stress_max_pinion'].item() / 1e6:.1f} MPa,"
                f" wheel {ds['fillet_stress_max_wheel'].item() / 1e6:.1f} MPa;"
                f" FE mean/width (no relief) {ds['fe_mesh_stiffness_mean_per_width'].item():.2f},"
                f" ISO c_gamma_alpha {ds['iso_c_gamma_alpha'].item():.2f} N/(mm um)"
            )
    print(
        "\ntooth support: structural compliance [um/kN] of the paper's tooth, rim (2 m, sides tied) vs"
        " root clamp (all nodes inside the root circle tied)"
    )
    radii = np.array([0.0425, G.pitch_radius, 0.0470])
    for k in (1,) if TINY else (1, 2):
        kw = {key: k * v for key, v in DEFAULT.items()}
        rim = tooth_compliance(build_tooth_mesh(G, **kw), radii, E, NU, force=F).structural
        clamp = tooth_compliance(build_tooth_mesh(G, **kw, support="root_circle"), radii, E, NU, force=F).structural
        print(
            f"  {k}x  rim {np.round(rim * 1e9, 4)}  clamp {np.round(clamp * 1e9, 4)}  "
            f"rim/clamp {np.round(rim / clamp, 3)}"
        )


if __name__ == "__main__":
    main()
