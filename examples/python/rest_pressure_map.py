#!/usr/bin/env python3
# SPDX-License-Identifier: AGPL-3.0-or-later
"""Rest the bundled thigh on a flat seat and take its pressure map as numpy arrays.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/rest_pressure_map.py --out rest

Writes the rest folder (body.vtu, skin.ply, pressure maps as SVG, summary.json)
and pressures.npz (skin vertices and faces [m], pressure per vertex [Pa]) into
--out. Checks that the skin's map carries the load."""
import argparse
import json
import os

import numpy as np

import palpa

HERE = os.path.dirname(os.path.abspath(__file__))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="rest-python")
    ap.add_argument("--small", action="store_true", help="a coarse body (for tests)")
    a = ap.parse_args()
    with open(os.path.join(HERE, "..", "rest", "thigh", "scene.json")) as f:
        scene = json.load(f)
    if a.small:
        scene["body"]["edge"] = "30 mm"
    palpa.set_log_level("warning")
    r = palpa.rest(scene, out=os.path.join(a.out, "thigh"), overwrite=True)
    np.savez(os.path.join(a.out, "pressures.npz"), vertices=r.skin_vertices, faces=r.skin_faces,
             pressure=r.body_pressure)
    load = np.linalg.norm(r.summary["load_N"])
    carried = r.summary["pressure_map_force_N"]["body"]
    touching = np.count_nonzero(r.body_pressure)
    print(f"load {load:.1f} N, the skin's map carries {carried:.1f} N; peak {r.body_pressure.max() / 1e3:.2f} kPa "
          f"on {touching} of {len(r.body_pressure)} skin vertices")
    assert abs(carried / load - 1) < 0.05, (carried, load)


if __name__ == "__main__":
    main()
