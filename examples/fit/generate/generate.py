#!/usr/bin/env python3
# SPDX-License-Identifier: AGPL-3.0-or-later
"""Synthetic punch-indentation datasets for `palpa fit`, computed with CalculiX.

Writes the example folders examples/fit/foam, examples/fit/silicone and
examples/fit/tissue: one force-indentation curve per punch radius
(`r<radius>mm.csv`, columns indentation_mm,force_N) and the dataset files
(`dataset.json`, for the silicone also `dataset-depth.json`). The curves come
from an independent finite-element solver (CalculiX `ccx`, tested with 2.20)
so that fitting them with palpa does not fit palpa's own simulator back to
itself.

Model (one CalculiX run per punch radius and mesh level):
  - Axisymmetric layer r in [0, R], z in [-D, 0], R = 50 mm (half the lateral
    size of the block), base z = -D bonded (u = 0), axis u_r = 0, outer rim
    and top surface free. CAX8R elements (8-node quadratic, reduced
    integration: no volumetric locking for nearly incompressible materials) on
    a structured mesh graded toward the punch rim (r = a) and the top surface;
    mesh level k halves every cell of level k - 1.
  - The punch: a meshed cylinder r in [0, a], z in [0, a/2] made a *RIGID BODY
    whose reference node is driven down by *BOUNDARY (u_z = -d, no lateral
    motion, no rotation). Its face and side wall are the master surface of a
    frictionless surface-to-surface *CONTACT PAIR with the top surface of the
    layer (penalty, PRESSURE-OVERCLOSURE=LINEAR, slope 1000 x the small-strain
    Young's modulus over the cell size at the rim), so the surface outside the
    rim may fold against the punch's side but cannot enter it.
  - Material: CalculiX *HYPERELASTIC, YEOH with C10, C20, C30, D1:
    Psi = sum_i Ci0 (I1bar - 3)^i + (J - 1)^2 / D1, palpa's `yeoh` with the
    same constants. D2 and D3 are written as 1e20 (terms (J - 1)^4 / D2 and
    (J - 1)^6 / D3 negligible): CalculiX replaces a zero Di by a default.
  - One static NLGEOM step with automatic increments of at most one depth step
    (smallest 1/64 of it) and *TIME POINTS on a uniform depth grid. Punch force
    = 180 x the total contact force on the slave surface (*CONTACT PRINT, CF):
    CalculiX expands every CAX8R into a 2-degree wedge of C3D20R and prints the
    forces of that wedge (bench/poke_bench.cpp measures the factor).
  - A curve that CalculiX cannot finish is cut at the deepest depth it
    converged to (no extrapolation); when that is less than 3/4 of the planned
    depth, the curve is recomputed with the same number of points up to it
    (kept if it has more points than the first run). A run that stops within its first two
    increments is repeated with a first increment of a quarter depth step.
  - Mesh: level 1 is written (cell size at the rim min(a, D)/16); for one radius
    per example the curve is recomputed at level 2 (cells halved) and the
    largest relative force difference over depths >= 20% of the deepest is
    reported in <example>/generated.json (with the noise-free curves).

Measurement noise (seeded per curve, reproducible): every force gets Gaussian
noise with sigma = 0.5% of the curve's largest force + 1 mN (a force gauge),
every depth except the first (0) a Gaussian jitter of sigma = 5 um; the first
force is clipped at 0; depths are checked to be strictly increasing and forces
non-negative.

Usage:
  python3 examples/fit/generate/generate.py [--examples foam,silicone,tissue]
      [--ccx /usr/bin/ccx] [--keep]          (about 15-20 min on one core)
  python3 examples/fit/generate/generate.py --palpa build/apps/palpa/palpa
      compares the stored noise-free curves with `palpa poke --contact
      frictionless --mesh-level 3` (true material, same geometry and depths) and
      adds the result to generated.json; no CalculiX runs.
CalculiX runs one at a time with OMP_NUM_THREADS=1. Python standard library
only. Deterministic: the same CalculiX binary gives the same files.
"""

import argparse
import json
import math
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
FIT_DIR = os.path.dirname(HERE)

OUTER_RADIUS = 50.0  # mm, half the lateral size of the 100 mm blocks
CCX_SEGMENT = 180.0  # full circle / the 2-degree wedge CalculiX prints
SEED = 20240611


def yeoh_from_small_strain(c10, c20, c30, poisson):
    """Yeoh constants with D1 chosen for the small-strain Poisson ratio."""
    mu = 2.0 * c10  # kPa
    bulk = 2.0 * mu * (1.0 + poisson) / (3.0 * (1.0 - 2.0 * poisson))  # kPa
    return {"C10": c10, "C20": c20, "C30": c30, "D1": 2.0 / bulk, "nu": poisson,
            "E": 2.0 * mu * (1.0 + poisson), "bulk": bulk}


# The examples. Moduli in kPa, D1 in 1/kPa, lengths in mm.
EXAMPLES = {
    "foam": {
        "sample": "foam, 10x10x1 cm (synthetic: CalculiX, compressible Yeoh, see README.md)",
        "depth": 10.0,
        "radii": [1.03, 2.06, 3.01, 4.05, 5.06],
        "train": [4.05],
        "check": [5.06],
        "material": yeoh_from_small_strain(c10=8.0, c20=2.0, c30=0.5, poisson=0.25),
        "max_depth": 4.0,
        "points": 26,
        "poisson_hint": 0.25,
    },
    "silicone": {
        "sample": "silicone, 10x10x0.5 cm (synthetic: CalculiX, Yeoh, see README.md)",
        "depth": 5.0,
        "radii": [1.03, 2.06, 3.01, 4.05, 5.06],
        "train": [3.01, 5.06],
        "check": [5.06],
        "material": yeoh_from_small_strain(c10=12.0, c20=0.6, c30=0.15, poisson=0.47),
        "max_depth": 2.0,
        "points": 26,
        "poisson_hint": 0.47,
    },
    "tissue": {
        "sample": "forearm, anterior: 20 mm of soft tissue over bone "
                  "(synthetic: CalculiX, Yeoh, see README.md)",
        "depth": 20.0,
        "radii": [2.06, 4.05, 6.0],
        "train": [2.06, 6.0],
        "check": [6.0],
        "material": yeoh_from_small_strain(c10=9.0, c20=4.0, c30=1.5, poisson=0.48),
        "max_depth": 7.0,
        "points": 26,
        "poisson_hint": 0.48,
    },
}


def fmt(v):
    return "%.10g" % v


# ------------------------------------------------------------------ mesh

def graded(start, end, h0, growth, hmax):
    """Points from start to end: cells of size h0 growing by `growth` (capped
    at hmax), the last cell stretched/shrunk so the end is hit exactly."""
    pts = [start]
    h = h0
    length = abs(end - start)
    sign = 1.0 if end > start else -1.0
    pos = 0.0
    while True:
        if pos + h >= length - 0.5 * h:
            break
        pos += h
        pts.append(start + sign * pos)
        h = min(h * growth, hmax)
    pts.append(end)
    return pts


def uniform(start, end, n):
    return [start + (end - start) * k / n for k in range(n + 1)]


def layer_grid(a, depth, dmax, level):
    """Radial and vertical grid lines of the layer for punch radius a."""
    # cell size at the rim and under the punch: a/8 at level 0, halved per level,
    # but not coarser than D/8.
    h0 = min(a / 8.0, depth / 8.0) / (2 ** level)
    n_face = max(2, int(math.ceil(a / h0 - 1e-9)))
    rs = uniform(0.0, a, n_face)
    h = a / n_face
    band = a + 0.25 * a  # uniform band outside the rim, then cells growing by 12%
    n_band = max(1, int(math.ceil((band - a) / h - 1e-9)))
    rs += uniform(a, band, n_band)[1:]
    rs += graded(band, OUTER_RADIUS, h, 1.12, 4.0)[1:]
    top = min(depth, 0.25 * a)  # uniform band below the surface, then growing by 12%
    n_top = max(1, int(math.ceil(top / h - 1e-9)))
    zs = uniform(0.0, -top, n_top)
    if top < depth:
        zs += graded(-top, -depth, h, 1.12, depth)[1:]
    return rs, zs, h


class Deck:
    def __init__(self):
        self.nodes = []  # (x, y)
        self.lines = []

    def node(self, x, y):
        self.nodes.append((x, y))
        return len(self.nodes)


def quad8_grid(deck, rs, zs, first_elem):
    """8-node quads on the grid rs x zs (zs from top to bottom). Returns
    (elements, node id of grid point (i, j) in the doubled grid, ...)."""
    nr, nz = len(rs) - 1, len(zs) - 1
    ids = {}
    for j in range(2 * nz + 1):
        z = zs[j // 2] if j % 2 == 0 else 0.5 * (zs[j // 2] + zs[j // 2 + 1])
        for i in range(2 * nr + 1):
            if i % 2 == 1 and j % 2 == 1:
                continue
            r = rs[i // 2] if i % 2 == 0 else 0.5 * (rs[i // 2] + rs[i // 2 + 1])
            ids[(i, j)] = deck.node(r, z)
    elems = {}
    e = first_elem
    for jj in range(nz):  # row jj: between zs[jj] (top) and zs[jj+1]
        for ii in range(nr):
            i0, i1 = 2 * ii, 2 * ii + 2
            jt, jb = 2 * jj, 2 * jj + 2  # top, bottom rows of the doubled grid
            # counter-clockwise in (x = r, y = z): bottom-left, bottom-right, top-right, top-left
            n = [ids[(i0, jb)], ids[(i1, jb)], ids[(i1, jt)], ids[(i0, jt)],
                 ids[(i0 + 1, jb)], ids[(i1, jb - 1)], ids[(i0 + 1, jt)], ids[(i0, jb - 1)]]
            elems[(ii, jj)] = (e, n)
            e += 1
    return elems, ids


def build_deck(ex, a, level, dmax, steps, first=1.0):
    """The CalculiX input deck of one punch curve; returns (text, info)."""
    mat = ex["material"]
    depth = ex["depth"]
    rs, zs, h = layer_grid(a, depth, dmax, level)
    deck = Deck()
    layer, ids = quad8_grid(deck, rs, zs, 1)
    nr, nz = len(rs) - 1, len(zs) - 1
    base = [ids[(i, 2 * nz)] for i in range(2 * nr + 1)]
    axis = [ids[(0, j)] for j in range(2 * nz + 1)]
    # the punch: r in [0, a], z in [0, a/2], cells about twice the layer's
    n_pr = max(2, (len(rs) and int(round(a / h / 2.0))))
    prs = uniform(0.0, a, n_pr)
    pzs = uniform(0.5 * a, 0.0, 2)
    punch, pids = quad8_grid(deck, prs, pzs, len(layer) + 1)
    punch_nodes = list(pids.values())
    ref = deck.node(0.0, 0.5 * a)
    rot = deck.node(0.0, 0.5 * a + 1.0)
    # contact surfaces: layer top faces out to r = a + 0.75 dmax + 4 h (S3: nodes 3-4;
    # the surface beyond cannot reach the punch), punch face (S1: nodes 1-2,
    # bottom row) and side wall (S2: nodes 2-3)
    slave_r = min(OUTER_RADIUS, a + 0.75 * dmax + 4.0 * h)
    slave = [layer[(ii, 0)][0] for ii in range(nr) if rs[ii] < slave_r]
    master_face = [punch[(ii, 1)][0] for ii in range(n_pr)]
    master_side = [punch[(n_pr - 1, jj)][0] for jj in range(2)]
    # penalty: pressure per overclosure, 1000 x the small-strain Young's modulus
    # over the cell size at the rim (MPa/mm)
    young_mpa = mat["E"] * 1e-3
    penalty = 1000.0 * young_mpa / h
    out = []
    w = out.append
    w("** palpa example data: rigid flat punch (radius %g mm) on a %g mm layer" % (a, depth))
    w("** units: mm, N, MPa; x = r, y = z (top surface y = 0); generated by generate.py")
    w("*NODE, NSET=NALL")
    for k, (x, y) in enumerate(deck.nodes, start=1):
        w("%d, %s, %s" % (k, fmt(x), fmt(y)))
    w("*ELEMENT, TYPE=CAX8R, ELSET=LAYER")
    for (e, n) in layer.values():
        w("%d, %s" % (e, ", ".join(str(v) for v in n)))
    w("*ELEMENT, TYPE=CAX8R, ELSET=PUNCH")
    for (e, n) in punch.values():
        w("%d, %s" % (e, ", ".join(str(v) for v in n)))

    def nset(name, nodes):
        w("*NSET, NSET=%s" % name)
        for k in range(0, len(nodes), 12):
            w(", ".join(str(v) for v in nodes[k:k + 12]))

    nset("BASE", base)
    nset("AXIS", axis)
    nset("PUNCHN", punch_nodes)
    nset("REFN", [ref])
    nset("ROTN", [rot])
    w("*SURFACE, NAME=TOP, TYPE=ELEMENT")
    for e in slave:
        w("%d, S3" % e)
    w("*SURFACE, NAME=PFACE, TYPE=ELEMENT")
    for e in master_face:
        w("%d, S1" % e)
    for e in master_side:
        w("%d, S2" % e)
    w("*MATERIAL, NAME=LAYERMAT")
    w("*HYPERELASTIC, YEOH")
    w("%s, %s, %s, %s, 1e20, 1e20" % (fmt(mat["C10"] * 1e-3), fmt(mat["C20"] * 1e-3),
                                  fmt(mat["C30"] * 1e-3), fmt(mat["D1"] * 1e3)))
    w("*MATERIAL, NAME=PUNCHMAT")
    w("*ELASTIC")
    w("%s, 0.3" % fmt(1000.0 * young_mpa))
    w("*SOLID SECTION, ELSET=LAYER, MATERIAL=LAYERMAT")
    w("*SOLID SECTION, ELSET=PUNCH, MATERIAL=PUNCHMAT")
    w("*RIGID BODY, NSET=PUNCHN, REF NODE=%d, ROT NODE=%d" % (ref, rot))
    w("*SURFACE INTERACTION, NAME=SMOOTH")
    w("*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR")
    w("%s, %s" % (fmt(penalty), fmt(1e-3 * young_mpa)))
    w("*CONTACT PAIR, INTERACTION=SMOOTH, TYPE=SURFACE TO SURFACE")
    w("TOP, PFACE")
    w("*BOUNDARY")
    w("BASE, 1, 2")
    w("AXIS, 1, 1")
    w("REFN, 1, 1")
    w("REFN, 3, 3")
    w("ROTN, 1, 3")
    w("*TIME POINTS, NAME=SCHEDULE")
    tp = [fmt(k / steps) for k in range(1, steps + 1)]
    for k in range(0, len(tp), 8):
        w(", ".join(tp[k:k + 8]))
    inc = 1.0 / steps
    w("*STEP, NLGEOM, INC=100000")
    w("*STATIC")
    w("%s, 1., %s, %s" % (fmt(inc * first), fmt(inc / 64.0), fmt(inc)))
    w("*BOUNDARY")
    w("REFN, 2, 2, %s" % fmt(-dmax))
    w("*CONTACT PRINT, SLAVE=TOP, MASTER=PFACE, TIME POINTS=SCHEDULE")
    w("CF")
    w("*END STEP")
    info = {"elements_layer": len(layer), "nodes": len(deck.nodes), "rim_cell_mm": h,
            "cells_r": nr, "cells_z": nz, "penalty_MPa_per_mm": penalty}
    return "\n".join(out) + "\n", info


# ------------------------------------------------------------------ running

def run_ccx(ccx, deck, keep, tag):
    folder = tempfile.mkdtemp(prefix="palpa_fit_example_%s_" % tag)
    with open(os.path.join(folder, "poke.inp"), "w") as f:
        f.write(deck)
    env = dict(os.environ, OMP_NUM_THREADS="1")
    t0 = time.time()
    with open(os.path.join(folder, "ccx.log"), "w") as log:
        rc = subprocess.call([ccx, "-i", "poke"], cwd=folder, stdout=log, stderr=subprocess.STDOUT, env=env)
    seconds = time.time() - t0
    times, forces = [], []
    dat = os.path.join(folder, "poke.dat")
    if os.path.exists(dat):
        with open(dat) as f:
            lines = f.read().splitlines()
        k = 0
        while k < len(lines):
            line = lines[k]
            if "statistics for slave set" in line:
                t = float(line[line.rfind("time") + 4:])
                while k < len(lines) and "total surface force" not in lines[k]:
                    k += 1
                k += 1
                while k < len(lines) and not lines[k].strip():
                    k += 1
                vals = lines[k].split()
                times.append(t)
                forces.append(-CCX_SEGMENT * float(vals[1]))
            k += 1
    with open(os.path.join(folder, "ccx.log")) as f:
        log_text = f.read()
    finished = "Job finished" in log_text and rc == 0
    error = ""
    m = re.search(r"\*ERROR.*", log_text)
    if m:
        error = m.group(0).strip()
    if not keep:
        shutil.rmtree(folder)
    return {"times": times, "forces": forces, "finished": finished, "seconds": seconds,
            "error": error, "folder": folder if keep else None}


def simulate(ccx, ex, a, level, dmax, steps, keep, tag, first=1.0):
    deck, info = build_deck(ex, a, level, dmax, steps, first)
    run = run_ccx(ccx, deck, keep, tag)
    depths = [0.0]
    forces = [0.0]
    for t, f in zip(run["times"], run["forces"]):
        k = int(round(t * steps))
        if abs(t * steps - k) > 1e-3 or k != len(depths):
            continue
        depths.append(dmax * k / steps)
        forces.append(f)
    run.update(info)
    run["depths"] = depths
    run["curve"] = forces
    return run


# ------------------------------------------------------------------ output

def radius_label(a):
    return ("%.2f" % a).rstrip("0").rstrip(".") if a != int(a) else "%d" % a


def noisy_curve(depths, forces, rng):
    fmax = max(forces)
    sigma_f = 0.005 * fmax + 0.001
    out = []
    for k, (d, f) in enumerate(zip(depths, forces)):
        dn = d if k == 0 else d + rng.gauss(0.0, 0.005)
        fn = f + rng.gauss(0.0, sigma_f)
        if k == 0:
            fn = max(0.0, fn)
        out.append((dn, fn))
    for k in range(1, len(out)):
        if not out[k][0] > out[k - 1][0]:
            raise RuntimeError("depth jitter made the indentation non-increasing")
        if out[k][1] < 0.0:
            raise RuntimeError("noise made a force negative")
    return out, sigma_f


def write_curve_csv(path, name, ex, a, points, sigma_f, deepest, stop_reason):
    with open(path, "w") as f:
        f.write("# %s: punch radius %s mm, layer depth %g mm, frictionless\n" % (name, radius_label(a), ex["depth"]))
        f.write("# synthetic measurement: CalculiX (ccx) curve + Gaussian noise "
                "(force sigma %.4f N, depth sigma 0.005 mm); see README.md\n" % sigma_f)
        f.write("# deepest depth CalculiX converged to: %.4g mm (%s)\n" % (deepest, stop_reason))
        f.write("indentation_mm,force_N\n")
        for d, fo in points:
            f.write("%.4f,%.5f\n" % (d, fo))


def dataset_json(ex, name, radii_files, train, layer_depth):
    curves = []
    order = sorted(radii_files, key=lambda a: (a not in train, -a))
    for a in order:
        curves.append({"file": radii_files[a], "radius": "%s mm" % radius_label(a),
                       "role": "train" if a in train else "validate"})
    return {
        "palpa_dataset": 1,
        "sample": ex["sample"],
        "test": "indentation",
        "layer_depth": layer_depth,
        "lateral_size": "100 mm",
        "contact": "frictionless",
        "poisson": ex["poisson_hint"],
        "curves": curves,
    }


def dump_json(path, obj):
    with open(path, "w") as f:
        f.write(json_text(obj))


def json_text(obj):
    """JSON with one curve per line (readable, stable)."""
    if isinstance(obj, dict) and "curves" in obj:
        head = dict(obj)
        curves = head.pop("curves")
        body = json.dumps(head, indent=2)[:-2]
        lines = ",\n    ".join(json.dumps(c) for c in curves)
        return body + ',\n  "curves": [\n    ' + lines + "\n  ]\n}\n"
    return json.dumps(obj, indent=2) + "\n"


def true_material_json(mat, note):
    return {
        "palpa_material": 1,
        "model": "yeoh",
        "parameters": {"C10": "%g kPa" % mat["C10"], "C20": "%g kPa" % mat["C20"],
                       "C30": "%g kPa" % mat["C30"], "D1": "%.6g 1/Pa" % (mat["D1"] * 1e-3)},
        "provenance": {"created_by": "palpa example", "method": note, "objective": None},
    }


# ------------------------------------------------------------------ palpa cross-check

def palpa_curve(palpa, material_path, ex, a, dmax, steps, level):
    folder = tempfile.mkdtemp(prefix="palpa_fit_example_poke_")
    out = os.path.join(folder, "curve.csv")
    cmd = [palpa, "poke", "--material", material_path, "--thickness", "%gmm" % ex["depth"],
           "--radius", "%gmm" % a, "--depth", "%gmm" % dmax, "--steps", str(steps),
           "--contact", "frictionless", "--outer-radius", "%gmm" % OUTER_RADIUS,
           "--mesh-level", str(level), "-o", out]
    t0 = time.time()
    rc = subprocess.call(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    seconds = time.time() - t0
    depths, forces = [0.0], [0.0]
    if os.path.exists(out):
        with open(out) as f:
            rows = [l for l in f.read().splitlines() if l and not l.startswith("#")]
        head = rows[0].split(",")
        di, fi = head.index("indentation_m"), head.index("force_N")
        for r in rows[1:]:
            v = r.split(",")
            d = float(v[di]) * 1e3
            if d > 0:
                depths.append(d)
                forces.append(float(v[fi]))
    shutil.rmtree(folder)
    return {"rc": rc, "depths": depths, "forces": forces, "seconds": seconds, "cmd": " ".join(cmd[1:])}


# ------------------------------------------------------------------ main

def compare(d1, f1, d2, f2, dmin):
    """Largest relative difference of f2 against f1 at the common depths >= dmin."""
    worst = 0.0
    at = None
    for d, fa in zip(d1, f1):
        if d < dmin or fa <= 0:
            continue
        for dd, fb in zip(d2, f2):
            if abs(dd - d) < 1e-9:
                rel = (fb - fa) / fa
                if abs(rel) > abs(worst):
                    worst, at = rel, d
    return worst, at


def compare_with_palpa(args):
    """palpa poke --contact frictionless with the true material on every stored
    noise-free curve's geometry and depth grid; results into generated.json."""
    for name in args.examples.split(","):
        ex = EXAMPLES[name]
        folder = os.path.join(FIT_DIR, name)
        path = os.path.join(folder, "generated.json")
        with open(path) as f:
            report = json.load(f)
        for entry in report["curves"]:
            a = entry["radius_mm"]
            if args.radii and not any(abs(a - float(v)) < 1e-9 for v in args.radii.split(",")):
                continue
            depths = [d for d, _ in entry["noise_free"]]
            forces = [f for _, f in entry["noise_free"]]
            pc = palpa_curve(args.palpa, os.path.join(folder, "true-material.json"), ex, a, depths[-1],
                             len(depths) - 1, args.palpa_level)
            rel, at = compare(depths, forces, pc["depths"], pc["forces"], 0.2 * depths[-1])
            rel_end, _ = compare(depths, forces, pc["depths"], pc["forces"], depths[-1] - 1e-9)
            command = "palpa " + pc["cmd"].replace(folder + os.sep, "")
            command = command[:command.rindex(" -o ")] + " -o curve.csv"
            entry["palpa"] = {"command": command, "rc": pc["rc"],
                              "deepest_mm": pc["depths"][-1], "seconds": pc["seconds"],
                              "max_rel_diff_beyond_20pct": rel, "at_mm": at, "rel_diff_deepest": rel_end,
                              "noise_free": [[round(d, 6), round(f, 7)] for d, f in zip(pc["depths"], pc["forces"])]}
            print("%s a=%g: palpa (rc %d, %.1f s, to %.3g mm) vs CalculiX: largest %+.2f%% (at %.3g mm), "
                  "%+.2f%% at the deepest depth" % (name, a, pc["rc"], pc["seconds"], pc["depths"][-1],
                                                    100 * rel, at or 0, 100 * rel_end), flush=True)
        with open(path, "w") as f:
            json.dump(report, f, indent=1)
            f.write("\n")
    return 0


def log_run(name, a, level, r, steps):
    print("%s a=%g level %d: %d elements, rim cell %.3f mm, %d/%d depths to %.3g mm, %.1f s%s %s" % (
        name, a, level, r["elements_layer"], r["rim_cell_mm"], len(r["depths"]) - 1, steps, r["depths"][-1],
        r["seconds"], "" if r["finished"] else " (stopped)", r["error"]), flush=True)
    if r["folder"]:
        print("  kept", r["folder"])


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter,
                                epilog="See the top of this file for the model and the noise.")
    p.add_argument("--examples", default="foam,silicone,tissue", help="comma-separated subset")
    p.add_argument("--radii", default="", help="only these radii (mm, comma-separated; for testing)")
    p.add_argument("--ccx", default=shutil.which("ccx") or "/usr/bin/ccx")
    p.add_argument("--level", type=int, default=1, help="mesh level of the written curves")
    p.add_argument("--no-check", action="store_true", help="skip the mesh refinement check")
    p.add_argument("--palpa", default="", help="palpa binary: only compare the stored noise-free "
                   "curves (generated.json) with palpa poke, no CalculiX runs")
    p.add_argument("--palpa-level", type=int, default=3, help="palpa poke --mesh-level for the comparison")
    p.add_argument("--keep", action="store_true", help="keep the CalculiX folders")
    p.add_argument("--dry", action="store_true", help="run, print, write nothing")
    args = p.parse_args()
    if args.palpa:
        return compare_with_palpa(args)
    t_start = time.time()
    for name in args.examples.split(","):
        ex = EXAMPLES[name]
        folder = os.path.join(FIT_DIR, name)
        os.makedirs(folder, exist_ok=True)
        radii = ex["radii"]
        if args.radii:
            radii = [a for a in radii if any(abs(a - float(v)) < 1e-9 for v in args.radii.split(","))]
        report = {"example": name, "material": ex["material"], "curves": []}
        files = {}
        mat_path = os.path.join(folder, "true-material.json")
        if not args.dry:
            dump_json(mat_path, true_material_json(
                ex["material"], "the material the synthetic curves were computed with (CalculiX YEOH, same constants)"))
        for a in ex["radii"]:
            if a not in radii:
                continue
            dmax, steps = ex["max_depth"], ex["points"] - 1
            tag = "%s_%s" % (name, radius_label(a))
            run = simulate(args.ccx, ex, a, args.level, dmax, steps, args.keep, tag)
            log_run(name, a, args.level, run, steps)
            if len(run["depths"]) <= 3:
                # stopped in the first increments: start with a quarter of a depth step
                run = simulate(args.ccx, ex, a, args.level, dmax, steps, args.keep, tag, first=0.25)
                log_run(name, a, args.level, run, steps)
            if len(run["depths"]) - 1 < 0.75 * steps and len(run["depths"]) > 3:
                # stopped early: the same number of points up to the deepest depth reached
                # (convergence near the limit depends on the increments: keep
                # the run with more points)
                dmax = run["depths"][-1]
                again = simulate(args.ccx, ex, a, args.level, dmax, steps, args.keep, tag)
                log_run(name, a, args.level, again, steps)
                if len(again["depths"]) > len(run["depths"]):
                    run = again
                else:
                    dmax = ex["max_depth"]
            deepest = run["depths"][-1]
            stop = "reached the planned depth" if deepest >= ex["max_depth"] - 1e-9 else \
                "CalculiX did not converge beyond it"
            entry = {"radius_mm": a, "deepest_mm": deepest, "planned_mm": ex["max_depth"],
                     "points": len(run["depths"]), "stop": stop, "level": args.level,
                     "seconds": run["seconds"], "elements": run["elements_layer"],
                     "rim_cell_mm": run["rim_cell_mm"], "force_N": run["curve"][-1],
                     "noise_free": [[round(d, 6), round(f, 7)] for d, f in zip(run["depths"], run["curve"])]}
            if a in ex["check"] and not args.no_check:
                fine = simulate(args.ccx, ex, a, args.level + 1, dmax, steps, args.keep, tag + "_fine")
                log_run(name, a, args.level + 1, fine, steps)
                rel, at = compare(fine["depths"], fine["curve"], run["depths"], run["curve"], 0.2 * deepest)
                rel_end, _ = compare(fine["depths"], fine["curve"], run["depths"], run["curve"], deepest - 1e-9)
                entry["refinement"] = {"level": args.level + 1, "elements": fine["elements_layer"],
                                       "rim_cell_mm": fine["rim_cell_mm"], "seconds": fine["seconds"],
                                       "deepest_mm": fine["depths"][-1],
                                       "max_rel_diff_beyond_20pct": rel, "at_mm": at,
                                       "rel_diff_deepest": rel_end,
                                       "noise_free": [[round(d, 6), round(f, 7)]
                                                      for d, f in zip(fine["depths"], fine["curve"])]}
                print("  level %d vs %d: largest %.2f%% (at %.3g mm), %.2f%% at the deepest depth" % (
                    args.level, args.level + 1, 100 * rel, at or 0, 100 * rel_end), flush=True)
            fine = run
            rng = random.Random("%s-%s-%d" % (name, radius_label(a), SEED))
            points, sigma_f = noisy_curve(fine["depths"], fine["curve"], rng)
            entry["sigma_force_N"] = sigma_f
            fname = "r%smm.csv" % radius_label(a)
            files[a] = fname
            if not args.dry:
                write_curve_csv(os.path.join(folder, fname), name, ex, a, points, sigma_f, deepest, stop)
            report["curves"].append(entry)
        if args.dry:
            continue
        files = {a: "r%smm.csv" % radius_label(a) for a in ex["radii"]}
        gen_path = os.path.join(folder, "generated.json")
        if args.radii and os.path.exists(gen_path):  # merge with the stored curves
            with open(gen_path) as f:
                old = json.load(f)
            done = {c["radius_mm"] for c in report["curves"]}
            report["curves"] = sorted([c for c in old["curves"] if c["radius_mm"] not in done] + report["curves"],
                                      key=lambda c: c["radius_mm"])
        dump_json(os.path.join(folder, "dataset.json"),
                  dataset_json(ex, name, files, ex["train"], "%g mm" % ex["depth"]))
        if name == "silicone":
            dump_json(os.path.join(folder, "dataset-depth.json"),
                      dataset_json(ex, name, files, ex["radii"], {"from": "3 mm", "to": "9 mm", "count": 7}))
        report["seconds"] = time.time() - t_start
        with open(gen_path, "w") as f:
            json.dump(report, f, indent=1)
            f.write("\n")
    print("total %.0f s" % (time.time() - t_start))


if __name__ == "__main__":
    sys.exit(main())
