#!/usr/bin/env python3
# SPDX-License-Identifier: AGPL-3.0-or-later
"""A short design run: the seat under a soft sphere shaped for low, even pressure.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/design_short.py --out design

Writes the design folder (support.obj, support_mm.stl, score.svg, summary.json,
...) into --out. Checks that the score ζ, solved from scratch, went down."""
import argparse
import os

import palpa

SCENE = {
    "palpa_design": 1,
    "body": {
        "generate": {"shape": "sphere", "length": "60 mm"},
        "edge": "7 mm", "depth": "8 mm",
        "material": {"model": "neo-hookean", "parameters": {"E": "20 kPa", "nu": 0.4}},
        "position": ["0 mm", "0 mm", "31 mm"],
    },
    "core": {"mass": "0.5 kg", "free": ["z"]},
    "support": {"box": {"size": ["150 mm", "150 mm", "20 mm"], "divisions": 30}},
    "design": {"method": "lbfgs",
               "region": {"min": ["-60 mm", "-60 mm", "-5 mm"], "max": ["60 mm", "60 mm", "5 mm"]},
               "iterations": 6},
}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="design-python")
    ap.add_argument("--small", action="store_true", help="three iterations (for tests)")
    a = ap.parse_args()
    palpa.set_log_level("warning")
    r = palpa.design(SCENE, out=os.path.join(a.out, "sphere"), overwrite=True, iterations=3 if a.small else None)
    s = r.summary
    print(f"zeta {s['initial']['zeta']:.4g} -> {s['final']['zeta']:.4g} ({s['zeta_reduction_percent']:.1f}% lower, "
          f"from scratch) in {s['iterations']} iterations; body peak {s['initial']['peak_pressure_Pa']['body'] / 1e3:.2f}"
          f" -> {s['final']['peak_pressure_Pa']['body'] / 1e3:.2f} kPa; support {r.support_vertices.shape[0]} vertices")
    assert s["final"]["zeta"] < s["initial"]["zeta"]


if __name__ == "__main__":
    main()
