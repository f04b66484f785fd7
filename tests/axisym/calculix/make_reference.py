#!/usr/bin/env python3
# SPDX-License-Identifier: AGPL-3.0-or-later
"""Mesh-converged reference forces of the flat punch from CalculiX (CAX8).

Writes cax8_reference.csv beside this script: for each case (punch radius a,
layer thickness D, Poisson's ratio, contact under the punch, depth d) the
force of quadratic axisymmetric elements (CAX8, 3x3 Gauss points) at three
nested mesh levels and their Richardson extrapolation. The tests
(PokePhysics.MatchesCalculixQuadraticElementsExtrapolated) compare palpa's
default force against it.

The problem is palpa's: a layer on a bonded rigid base, the top-surface nodes
with r <= a pushed down by d (stick: also held radially; frictionless: free
radially), the rest of the surface free, the far rim r = R = 8 max(a, D) free.
The material is CalculiX's *HYPERELASTIC, NEO HOOKE (palpa's
neo-hookean-isochoric: C10 = mu/2, D1 = 2/K) with E = 10 kPa. The mesh is the
graded grid of palpa's make_layer_mesh (4 cells under the punch shrinking by
0.7 toward the rim, growing by 1.45 outward and 1.35 downward, the top row at
most a fifth of the layer), each level splitting every cell 2 x 2, with
mid-side nodes on straight edges.

CalculiX expands a CAX8 into a 2-degree wedge of C3D20 elements: its printed
reaction totals are those of that segment, so the full-circle force is
180 times the printed total (the same convention the poke benchmark checks).

The rim of a sharp punch is a stress singularity: quadratic elements too
converge at first order in the cell size there, so the converged force is
2 F_L - F_(L-1) over the two finest levels; the extrapolation from the two
coarser levels is written too, as an estimate of what is left.

Usage: python3 make_reference.py  (needs `ccx` on PATH: Debian calculix-ccx;
about 10 minutes on 2 cores).
"""
import csv
import math
import os
import re
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "common"))
from graded_points import geometric_points, growing_points, refine  # noqa: E402

E = 10e3  # Pa
LEVELS = (1, 2, 3)

# (name, a [m], D [m], nu, contact, depth [m], increments). Frictionless
# punches stay at 0.1 a: deeper, CalculiX's Newton stops converging on the
# finer meshes (at 0.3 a on case A, level 2), where the rim nodes slide.
CASES = [
    ("A", 2e-3, 2e-3 / 0.3, 0.45, "stick", 0.2e-3, 4),
    ("A", 2e-3, 2e-3 / 0.3, 0.45, "frictionless", 0.2e-3, 4),
    ("A", 2e-3, 2e-3 / 0.3, 0.45, "stick", 0.6e-3, 8),
    ("B", 2e-3, 2e-3, 0.3, "stick", 0.1e-3, 2),
    ("B", 2e-3, 2e-3, 0.3, "frictionless", 0.1e-3, 2),
    ("C", 3e-3, 10e-3, 0.4, "stick", 0.6e-3, 6),
    ("C", 3e-3, 10e-3, 0.4, "frictionless", 0.3e-3, 3),
]





def layer_grid(a, thickness, level):
    big_r = 8.0 * max(a, thickness)
    r = geometric_points(0.0, a, 4, 0.7)
    rim = r[-1] - r[-2]
    r += growing_points(a, big_r, rim, 1.45)[1:]
    depth = growing_points(0.0, thickness, min(rim, thickness / 5.0), 1.35)
    return refine(r, level), refine(depth, level)


def deck(a, thickness, nu, contact, d, increments, level):
    """CAX8 deck in mm, N, MPa; returns (text, punch node count)."""
    r, depth = layer_grid(a, thickness, level)
    # Doubled grid: corners at even (i, j), mid-side nodes where one index is
    # odd; (odd, odd) is no node. Row j = 0 is the top surface.
    rr = []
    for k in range(len(r) - 1):
        rr += [r[k], 0.5 * (r[k] + r[k + 1])]
    rr.append(r[-1])
    zz = []
    for k in range(len(depth) - 1):
        zz += [-depth[k], -0.5 * (depth[k] + depth[k + 1])]
    zz.append(-depth[-1])
    nc, nr = len(rr), len(zz)
    nid = lambda i, j: j * nc + i + 1
    lines = ["** palpa reference: flat punch on a bonded layer, CAX8", "*NODE, NSET=NALL"]
    for j in range(nr):
        for i in range(nc):
            if i % 2 == 1 and j % 2 == 1:
                continue
            lines.append(f"{nid(i, j)}, {rr[i] * 1e3:.12g}, {zz[j] * 1e3:.12g}")
    lines.append("*ELEMENT, TYPE=CAX8, ELSET=EALL")
    e = 0
    for j in range(0, nr - 1, 2):
        for i in range(0, nc - 1, 2):
            e += 1
            # counter-clockwise in (r, z): (i, j+2) bottom-left, (i+2, j+2),
            # (i+2, j), (i, j) top-left; then the mid-sides 1-2, 2-3, 3-4, 4-1.
            c = [nid(i, j + 2), nid(i + 2, j + 2), nid(i + 2, j), nid(i, j)]
            m = [nid(i + 1, j + 2), nid(i + 2, j + 1), nid(i + 1, j), nid(i, j + 1)]
            lines.append(f"{e}, " + ", ".join(str(v) for v in c + m))
    def nset(name, ids):
        lines.append(f"*NSET, NSET={name}")
        for k in range(0, len(ids), 12):
            lines.append(", ".join(str(v) for v in ids[k:k + 12]))
    nset("BASE", [nid(i, nr - 1) for i in range(nc)])
    nset("AXIS", [nid(0, j) for j in range(nr)])
    punch = [nid(i, 0) for i in range(nc) if rr[i] <= a * (1 + 1e-12)]
    nset("PUNCH", punch)
    mu = E / (2 * (1 + nu))
    bulk = E / (3 * (1 - 2 * nu))
    lines += ["*MATERIAL, NAME=TISSUE", "*HYPERELASTIC, NEO HOOKE",
              f"{mu / 2 * 1e-6:.12g}, {2 / bulk * 1e6:.12g}",
              "*SOLID SECTION, ELSET=EALL, MATERIAL=TISSUE",
              "*BOUNDARY", "BASE, 1, 2", "AXIS, 1, 1"]
    if contact == "stick":
        lines.append("PUNCH, 1, 1")
    inc = 1.0 / increments
    lines += ["*STEP, NLGEOM, INC=10000", "*STATIC", f"{inc:.12g}, 1, {inc * 1e-5:.12g}, {inc:.12g}",
              "*BOUNDARY", f"PUNCH, 2, 2, {-d * 1e3:.12g}",
              "*NODE PRINT, NSET=PUNCH, TOTALS=ONLY", "RF", "*END STEP"]
    return "\n".join(lines) + "\n", e


def run(case, level):
    name, a, thickness, nu, contact, d, increments = case
    text, elements = deck(a, thickness, nu, contact, d, increments, level)
    with tempfile.TemporaryDirectory() as work:
        with open(os.path.join(work, "poke.inp"), "w") as f:
            f.write(text)
        t0 = time.time()
        done = subprocess.run(["ccx", "-i", "poke"], cwd=work, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                              env=dict(os.environ, OMP_NUM_THREADS="2"))
        if done.returncode != 0:
            raise RuntimeError(f"case {case}: CalculiX exited with {done.returncode} at level {level}")
        seconds = time.time() - t0
        dat = open(os.path.join(work, "poke.dat")).read()
    blocks = re.findall(r"total force \(fx,fy,fz\) for set PUNCH and time\s+([0-9.Ee+-]+)\s*\n\s*"
                        r"([0-9.Ee+-]+)\s+([0-9.Ee+-]+)", dat)
    if not blocks or abs(float(blocks[-1][0]) - 1.0) > 1e-9:
        raise RuntimeError(f"case {case}: CalculiX did not reach the full depth at level {level}")
    force = -180.0 * float(blocks[-1][2])  # full circle, downward [N]
    return force, elements, seconds


def main():
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "cax8_reference.csv")
    rows = []
    for case in CASES:
        forces = []
        for level in LEVELS:
            f, elements, seconds = run(case, level)
            forces.append(f)
            print(f"{case[0]} {case[4]} d={case[5] * 1e3:g} mm level {level}: {f:.8g} N "
                  f"({elements} CAX8, {seconds:.1f} s)", file=sys.stderr, flush=True)
        fine = 2 * forces[2] - forces[1]
        coarse = 2 * forces[1] - forces[0]
        rows.append([case[0], case[1], case[2], case[3], case[4], case[5]] + forces + [fine, fine / coarse - 1])
    with open(out, "w", newline="") as f:
        f.write("# Flat punch on a bonded layer: CalculiX CAX8 forces at mesh levels 1-3 and their\n"
                "# Richardson extrapolation 2 F_3 - F_2 (make_reference.py; E = 10 kPa, neo-Hookean\n"
                "# with C10 = mu/2, D1 = 2/K). change: the extrapolation from levels 2-3 over that\n"
                "# from levels 1-2, minus 1.\n")
        w = csv.writer(f)
        w.writerow(["case", "punch_radius_m", "thickness_m", "nu", "contact", "depth_m",
                    "force_level1_N", "force_level2_N", "force_level3_N", "force_N", "change"])
        for row in rows:
            w.writerow([f"{v:.10g}" if isinstance(v, float) else v for v in row])
    print(f"wrote {out}", file=sys.stderr)


if __name__ == "__main__":
    main()
