"""Small gearbox configs for the system tests (built as plain TOML-like dicts)."""

from __future__ import annotations

import copy
import math

import pytest


def pair(z1=20, z2=40, module=3e-3, width=0.025, **kw):
    """A 20/40 pair with a small backlash and solid blanks."""
    return {
        "pinion": {
            "teeth": z1,
            "module": module,
            "face_width": width,
            "blank": {"kind": "solid", "bore_diameter": 0.03},
        },
        "wheel": {
            "teeth": z2,
            "module": module,
            "face_width": width,
            "blank": {"kind": "solid", "bore_diameter": 0.04},
        },
        **kw,
    }


def bearing(node, k=2e8, c=0.0, **kw):
    return {"node": node, "kxx": k, "kyy": k, "cxx": c, "cyy": c, **kw}


def config(
    a=None, angle=0.0, elements=6, k_mesh=4e8, te=(), rotation="ccw", drive="torque", damping_ratio=0.07, **mesh
):
    """Two shafts (6 elements, gear at node 3), 20/40 pair, harmonic mesh source by default."""
    p = pair(center_distance=0.0901)
    a = 0.0901 if a is None else a
    cfg = {
        "rotor": [
            {
                "name": "in",
                "center": [0.0, 0.0],
                "shaft": [{"outer_diameter": 0.035, "length": 0.24, "elements": elements}],
                "bearing": [bearing(1, c=500.0), bearing(elements - 1, c=500.0)],
                "disk": [{"node": 0, "mass": 1.0, "Id": 1e-3, "Ip": 1.5e-3}],
            },
            {
                "name": "out",
                "center": [a * math.cos(angle), a * math.sin(angle)],
                "shaft": [{"outer_diameter": 0.045, "length": 0.24, "elements": elements}],
                "bearing": [bearing(1, 3e8, c=500.0), bearing(elements - 1, 3e8, c=500.0)],
            },
        ],
        "gear_mesh": [
            {
                "pinion_rotor": "in",
                "pinion_node": elements // 2,
                "wheel_rotor": "out",
                "wheel_node": elements // 2,
                "source": "harmonic",
                "k_mean": k_mesh,
                "te_harmonics": list(te),
                "damping_ratio": damping_ratio,
                **mesh,
                **p,
            }
        ],
        "drive": {"rotor": "in", "node": 0, "kind": drive, "rotation": rotation},
        "load": {"rotor": "out", "node": elements, "torque": 100.0, "inertia": 0.02},
    }
    return cfg


@pytest.fixture
def make():
    def _make(**kw):
        return copy.deepcopy(config(**kw))

    return _make
