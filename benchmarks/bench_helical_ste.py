"""Cost of the sliced helical STE against the spur STE of the same transverse mesh.

Spur: the transverse FE data of the pair (``pair_line``) and the loaded STE over one mesh cycle
(``loaded_te``). Helical: the same FE data (computed once, as ``gear static`` does) and the STE of
20 slices over the same cycle (``sliced_te``). The issue's bound: helical <= 3 x spur.

    PYTHONPATH=src python benchmarks/bench_helical_ste.py          # default mesh, 240 angles
    PYTHONPATH=src python benchmarks/bench_helical_ste.py --tiny   # coarse mesh, 60 angles
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np


def run(tiny: bool = False, slices: int = 20, repeat: int = 3) -> dict:
    """Best-of-``repeat`` wall times [s] of the spur and the helical STE and their ratio."""
    from rotaflex.gear.cases.static import gear_meshes
    from rotaflex.gear.pair.drawing import pair_from_mapping
    from rotaflex.gear.static.helical import face_model, sliced_te
    from rotaflex.gear.static.loaded_te import loaded_te, pair_line

    c = {"module": 2e-3, "face_width": 0.02, "helix_angle_deg": 15.0}
    pair = pair_from_mapping(
        {"pinion": {"teeth": 20, "hand": "right", **c}, "wheel": {"teeth": 40, "hand": "left", **c}}
    )
    g1, g2 = pair.gears
    preset, n = ("coarse", 60) if tiny else ("default", 240)
    force = 100.0 / g1.base_radius
    face = face_model(pair, slices, 1.0, 0.0)

    def fe():
        m1, m2 = gear_meshes(pair, preset)
        return pair_line(g1, g2, m1, m2, pair.working_center_distance, force, (210e9, 0.3, 210e9, 0.3), 9)

    def cycle(line):
        return line.s_start + line.base_pitch * np.arange(n) / n

    spur, hel = [], []
    for _ in range(repeat):
        t0 = time.perf_counter()
        line = fe()
        loaded_te(line, cycle(line))
        t1 = time.perf_counter()
        line = fe()
        sliced_te(line, face, cycle(line))
        t2 = time.perf_counter()
        spur.append(t1 - t0)
        hel.append(t2 - t1)
    return {"spur_s": min(spur), "helical_s": min(hel), "ratio": min(hel) / min(spur), "slices": slices, "angles": n}


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tiny", action="store_true")
    print(json.dumps(run(ap.parse_args().tiny)))
