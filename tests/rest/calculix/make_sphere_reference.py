#!/usr/bin/env python3
# SPDX-License-Identifier: AGPL-3.0-or-later
"""Contact pressure of a soft sphere on a rigid core pressed onto a plate (CalculiX CAX8).

Writes sphere_reference.csv and sphere_profile.csv beside this script: the
approach, contact force, contact radius, centre pressure and penetration of a
body resting on a support, at three nested mesh levels of quadratic
axisymmetric elements (CAX8, 3x3 Gauss points, NLGEOM), and the pressure
profile p(r) of the finest level.

The problem: a sphere of outer radius 70 mm whose outer 20 mm is a soft layer
on a rigid spherical core of radius 50 mm, pushed by a downward force of 25,
50 and 100 N on the core (full circle, no gravity) onto a rigid, fixed,
frictionless flat plate that touches its south pole. The layer is CalculiX's
*HYPERELASTIC, NEO HOOKE with C10 = 5170 Pa, D1 = 2e-5 1/Pa (shear modulus
10.34 kPa, bulk modulus 100 kPa: E = 30 kPa, Poisson's ratio 0.45). The core
is rigid: every node on the inner boundary is held radially and its vertical
displacement is tied (*EQUATION) to one of them, which carries the force.
The contact is CalculiX's surface-to-surface penalty contact (slave: the
sphere's outer surface up to 60 degrees from the south pole; master: the
plate's top face), frictionless, with a linear pressure-overclosure law of
slope 1e10 Pa/m: the penetration stays under 5 micrometres, 0.04% of the
approach.

The mesh is structured in (polar angle from the south pole, radius), with
mid-side nodes on the arcs: 14 equal cells from the pole to 45 degrees, then
cells growing by 2 to the north pole; 2 cells through the layer, the inner
one twice the outer. Each level splits every cell 2 x 2: level 1 has 160
elements and 2 mm surface elements near the contact, level 3 has 2560 and
0.49 mm. The plate is a row of CAX8 elements whose nodes are all fixed.

Load path. For each load, one step pushes the core down to the approach
expected at that load (a level-1 run's, within 0.1% of every level's) under
displacement control, and the next releases it under the load (applied at
once) and holds the load for two increments. Force control all the way
fails: the contact stiffens as it grows, so the first Newton iteration of a
force increment overshoots, and the overlap of the ring it pushes into the
plate blows the iteration up. The second increment at the held load matters
too: CalculiX's face-to-face contact pairs the slave integration points with
the master at the start of an increment, so a ring that comes into contact
within an increment carries no pressure until the next one (after a 25 N
increment, the penalty pressure integrated 6.6% above the load and the
centre pressure 13% above its converged value, at level 1). The results do
not depend on the path (the material is hyperelastic, the contact
frictionless): with increments less than half as large, level 2 agrees to
all printed digits.

Conventions. CalculiX expands a CAX8 into a 2-degree wedge of C3D20 elements:
its printed reaction totals are those of that segment, so the full-circle
contact force is 180 times the plate's printed total. A *CLOAD on a CAX node
is the full-circle force, on the other hand (on one element, a *CLOAD of 1
strains an annulus as 1 N over the whole circle, and its printed reaction
total is 1/180): the core's *CLOAD is the load itself, and the script checks
that 180 times the plate's reaction total equals it. The nodes on the
symmetry axis, the plate's included, sit 1 micrometre off it (held
radially): with faces that touch the axis, whose 3D expansion is
degenerate, CalculiX's face-to-face contact misses the pole, which sank 2 mm
through the plate. Convergence allows the count of contact elements to
change by 2% between iterations (*CONTROLS, PARAMETERS=CONTACT; at the
default 0.1% the contact edge chatters through many more iterations); the
residual keeps CalculiX's default tolerance, and the pressure integrates to
the load (sphere_profile.csv).

The pressure is the penalty law at the slave nodes, p = K x (the node's
overlap with the plate), from the nodal displacements. CalculiX's CSTR
output equals it at the pole (checked to 1%), but it is extrapolated from
the integration points and spills past the contact edge: at level 1, 2 pi
int CSTR r dr exceeds the load by up to 16%.

Outputs, per level and load (SI units):
  approach_m          how far the core moved toward the plate;
  force_N             the total contact force (180 x the plate's reaction);
  contact_radius_m    the deformed radius where the pressure falls to zero:
                      where the overlap, linearly interpolated between the
                      outermost slave node with a positive pressure and the
                      next one (out of contact, its overlap is negative),
                      crosses zero;
  centre_pressure_Pa  the pressure at the pole node;
  max_penetration_m   the largest overlap of a slave node with the plate.
sphere_profile.csv holds the finest level's p(r) against the deformed radius,
linearly interpolated between the slave nodes onto a 0.5 mm grid from the
axis to just past the contact radius. Its comment lines give 2 pi int p r dr
of that profile and of the overlap interpolated quadratically along the
slave faces (the pressure CalculiX integrates) against the load.

Convergence: from level 2 to 3 the approach changes by less than 0.01%, the
centre pressure and the penetration by 0.2-0.3%, and the contact radius by
up to 1.9% (at 50 N; less than 0.1% at 25 and 100 N): the pressure falls
steeply at the edge, so the radius is good to about a node spacing (0.25 mm
at level 3).

Usage: python3 make_sphere_reference.py  (needs `ccx` on PATH: Debian
calculix-ccx, CalculiX 2.20; one thread, about 10 minutes, 8 of them for
level 3).
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

# The deck is in mm, N and MPa.
R_OUT = 70.0
R_CORE = 50.0
C10 = 5170e-6  # 5170 Pa
D1 = 2e-5 * 1e6  # 2e-5 1/Pa
K_CONTACT = 1e10 * 1e-6 / 1e3  # 1e10 Pa/m
LOADS = (25.0, 50.0, 100.0)  # [N]
LEVELS = (1, 2, 3)
FINE_DEG, FINE_CELLS, COARSE_GROWTH = 45.0, 14, 2.0
LAYER_CELLS, LAYER_GROWTH = 2, 2.0
SLAVE_DEG = 60.0
PLATE_RADIUS, PLATE_CELLS, PLATE_THICKNESS = 80.0, 16, 2.0
AXIS_OFFSET = 1e-3  # radius of the nodes on the symmetry axis
APPROACH_GUESS = {25.0: 6.39, 50.0: 8.74, 100.0: 11.76}  # from a level-1 run
FIRST_TRAVEL = 0.5  # core travel of the first increment
MAX_TRAVEL = 0.75  # largest core travel of an increment
CONTACT_CONTROLS = ("*CONTROLS, PARAMETERS=CONTACT", "0.02")
PROFILE_STEP = 0.5
SAMPLES = 32  # points per slave face where the overlap is interpolated





def with_midpoints(x):
    out = []
    for k in range(len(x) - 1):
        out += [x[k], 0.5 * (x[k] + x[k + 1])]
    return out + [x[-1]]


def sphere_grid(level):
    """Polar angles [deg] from the south pole, and radii from the surface inward."""
    angle = geometric_points(0.0, FINE_DEG, FINE_CELLS, 1.0)
    angle += growing_points(FINE_DEG, 180.0, FINE_DEG / FINE_CELLS, COARSE_GROWTH)[1:]
    depth = geometric_points(0.0, R_OUT - R_CORE, LAYER_CELLS, LAYER_GROWTH)
    return refine(angle, level), [R_OUT - d for d in refine(depth, level)]


class Model:
    """The deck of one level, with what reading its results needs."""

    def __init__(self, level):
        angle, radius = sphere_grid(level)
        # Doubled grid: corners at even (i, j), mid-side nodes where one index
        # is odd; (odd, odd) is no node. i runs from the south pole (i = 0) to
        # the north pole, j from the outer surface (j = 0) to the core.
        tt, rr = with_midpoints(angle), with_midpoints(radius)
        nt, nr = len(tt), len(rr)
        nid = lambda i, j: j * nt + i + 1
        self.coords = {}
        lines = ["** palpa reference: soft sphere on a rigid core pressed onto a plate, CAX8",
                 "*NODE, NSET=SPHERE_NODES"]
        for j in range(nr):
            for i in range(nt):
                if i % 2 == 1 and j % 2 == 1:
                    continue
                t = math.radians(tt[i])
                x = AXIS_OFFSET if i in (0, nt - 1) else rr[j] * math.sin(t)
                y = -rr[j] * math.cos(t)
                self.coords[nid(i, j)] = (x, y)
                lines.append(f"{nid(i, j)}, {x:.12g}, {y:.12g}")
        # The plate: one row of elements, its top face at the south pole.
        pr = [PLATE_RADIUS * k / (2 * PLATE_CELLS) for k in range(2 * PLATE_CELLS + 1)]
        pr[0] = AXIS_OFFSET
        py = [-R_OUT, -R_OUT - PLATE_THICKNESS / 2, -R_OUT - PLATE_THICKNESS]
        pid = lambda i, j: nt * nr + j * len(pr) + i + 1
        self.plate_top = -R_OUT
        lines.append("*NODE, NSET=PLATE_NODES")
        for j in range(3):
            for i in range(len(pr)):
                if i % 2 == 1 and j % 2 == 1:
                    continue
                lines.append(f"{pid(i, j)}, {pr[i]:.12g}, {py[j]:.12g}")
        lines.append("*ELEMENT, TYPE=CAX8, ELSET=SPHERE")
        element, slave = 0, []
        for j in range(0, nr - 1, 2):
            for i in range(0, nt - 1, 2):
                element += 1
                # Counter-clockwise in (r, z): along the surface, then inward;
                # face S1 (nodes 1-2) lies on the outer surface when j = 0.
                c = [nid(i, j), nid(i + 2, j), nid(i + 2, j + 2), nid(i, j + 2)]
                m = [nid(i + 1, j), nid(i + 2, j + 1), nid(i + 1, j + 2), nid(i, j + 1)]
                assert self.signed_area(c) > 0.0
                lines.append(f"{element}, " + ", ".join(str(v) for v in c + m))
                if j == 0 and tt[i + 2] <= SLAVE_DEG + 1e-9:
                    slave.append(element)
        self.elements = element
        lines.append("*ELEMENT, TYPE=CAX8, ELSET=PLATE")
        plate = []
        for i in range(0, len(pr) - 1, 2):
            plate.append(element + len(plate) + 1)
            c = [pid(i, 2), pid(i + 2, 2), pid(i + 2, 0), pid(i, 0)]
            m = [pid(i + 1, 2), pid(i + 2, 1), pid(i + 1, 0), pid(i, 1)]
            lines.append(f"{plate[-1]}, " + ", ".join(str(v) for v in c + m))
        self.slave_nodes = [nid(i, 0) for i in range(nt) if tt[i] <= SLAVE_DEG + 1e-9]  # from the pole
        inner = [nid(i, nr - 1) for i in range(nt)]
        self.core = nid(2 * (nt // 4), nr - 1)  # a corner node of the core's boundary

        def nset(name, ids):
            lines.append(f"*NSET, NSET={name}")
            for k in range(0, len(ids), 12):
                lines.append(", ".join(str(v) for v in ids[k:k + 12]))

        nset("AXIS", [nid(0, j) for j in range(nr)] + [nid(nt - 1, j) for j in range(nr)])
        nset("INNER", inner)
        nset("CORE", [self.core])
        nset("SLAVE_NODES", self.slave_nodes)
        lines.append("*SURFACE, NAME=SLAVE, TYPE=ELEMENT")
        lines += [f"{e}, S1" for e in slave]
        lines.append("*SURFACE, NAME=MASTER, TYPE=ELEMENT")
        lines += [f"{e}, S3" for e in plate]
        lines += ["*MATERIAL, NAME=LAYER", "*HYPERELASTIC, NEO HOOKE", f"{C10:.12g}, {D1:.12g}",
                  "*SOLID SECTION, ELSET=SPHERE, MATERIAL=LAYER",
                  "*MATERIAL, NAME=STEEL", "*ELASTIC", "210000, 0.3",
                  "*SOLID SECTION, ELSET=PLATE, MATERIAL=STEEL",
                  "*SURFACE INTERACTION, NAME=FRICTIONLESS",
                  "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR", f"{K_CONTACT:.12g}",
                  "*CONTACT PAIR, INTERACTION=FRICTIONLESS, TYPE=SURFACE TO SURFACE", "SLAVE, MASTER",
                  "*EQUATION"]
        for n in inner:
            if n != self.core:
                lines += ["2", f"{n}, 2, 1.0, {self.core}, 2, -1.0"]
        fixed = ["PLATE_NODES, 1, 2", "AXIS, 1, 1", "INNER, 1, 1"]
        lines += ["*BOUNDARY"] + fixed + ["*AMPLITUDE, NAME=HOLD", "0, 1, 1, 1"]
        # Per load, two steps of unit time (see the docstring); the output
        # requests of the first step hold for all, at the end of each step.
        self.times = {}
        previous = 0.0
        for k, load in enumerate(LOADS):
            travel = APPROACH_GUESS[load] - previous
            largest = min(1.0, MAX_TRAVEL / travel)
            first = min(largest, FIRST_TRAVEL / travel)
            previous = APPROACH_GUESS[load]
            lines += ["*STEP, NLGEOM, INC=1000", *CONTACT_CONTROLS,
                      "*STATIC", f"{first:.6g}, 1, 1e-6, {largest:.6g}",
                      "*CLOAD, OP=NEW", "*BOUNDARY", f"{self.core}, 2, 2, {-APPROACH_GUESS[load]:.12g}"]
            if k == 0:
                lines += ["*NODE PRINT, NSET=CORE, FREQUENCY=1000", "U",
                          "*NODE PRINT, NSET=PLATE_NODES, TOTALS=ONLY, FREQUENCY=1000", "RF",
                          "*NODE PRINT, NSET=SLAVE_NODES, FREQUENCY=1000", "U",
                          "*CONTACT FILE, FREQUENCY=1000", "CSTR"]
            lines += ["*END STEP",
                      "*STEP, NLGEOM, INC=1000", *CONTACT_CONTROLS, "*STATIC", "0.5, 1, 1e-6, 0.5",
                      "*BOUNDARY, OP=NEW", *fixed,
                      "*CLOAD, AMPLITUDE=HOLD", f"{self.core}, 2, {-load:.12g}",
                      "*END STEP"]
            self.times[load] = 2.0 * (k + 1)
        self.deck = "\n".join(lines) + "\n"

    def signed_area(self, corners):
        a = 0.0
        for k in range(4):
            x0, y0 = self.coords[corners[k]]
            x1, y1 = self.coords[corners[(k + 1) % 4]]
            a += x0 * y1 - x1 * y0
        return a


def dat_blocks(dat, title):
    """{time: rows of numbers} of the .dat blocks whose header starts with title."""
    out = {}
    pattern = re.escape(title) + r" and time\s+([0-9.Ee+-]+)\s*\n\s*\n((?:[ \t]*[-0-9].*\n)+)"
    for m in re.finditer(pattern, dat):
        out[float(m.group(1))] = [[float(v) for v in line.split()] for line in m.group(2).splitlines()]
    return out


def frd_contact_pressure(frd):
    """{time: {node: CPRESS}} from the CONTACT blocks of an ASCII .frd."""
    out = {}
    lines = frd.splitlines()
    for k, line in enumerate(lines):
        if not line.startswith(" -4  CONTACT"):
            continue
        names = [row.split()[1] for row in lines[k + 1:k + 7]]
        column = names.index("CPRESS")
        values = {}
        for row in lines[k + 7:]:
            if not row.startswith(" -1"):
                break
            values[int(row[3:13])] = float(row[13 + 12 * column:25 + 12 * column])
        out[float(lines[k - 1].split()[2])] = values
    return out


def solve(model):
    """Runs CalculiX on the model's deck; returns the .dat and .frd texts and the seconds taken."""
    with tempfile.TemporaryDirectory() as work:
        with open(os.path.join(work, "sphere.inp"), "w") as f:
            f.write(model.deck)
        t0 = time.time()
        done = subprocess.run(["ccx", "-i", "sphere"], cwd=work, stdout=subprocess.DEVNULL,
                              stderr=subprocess.DEVNULL, env=dict(os.environ, OMP_NUM_THREADS="1"))
        seconds = time.time() - t0
        if done.returncode != 0:
            raise RuntimeError(f"CalculiX exited with {done.returncode}")
        with open(os.path.join(work, "sphere.dat")) as f:
            dat = f.read()
        with open(os.path.join(work, "sphere.frd")) as f:
            frd = f.read()
    return dat, frd, seconds


def surface_samples(nodes):
    """(radius, overlap) along the slave faces, interpolated quadratically between
    each face's corner, mid-side and corner nodes."""
    out = [nodes[0]]
    for a, m, b in zip(nodes[0:-2:2], nodes[1:-1:2], nodes[2::2]):
        for k in range(1, SAMPLES + 1):
            x = -1.0 + 2.0 * k / SAMPLES
            w = (0.5 * x * (x - 1.0), 1.0 - x * x, 0.5 * x * (x + 1.0))
            out.append(tuple(w[0] * a[c] + w[1] * m[c] + w[2] * b[c] for c in range(2)))
    return out


def integral(curve):
    """2 pi int p r dr [N] of p = K max(overlap, 0) along (radius, overlap) points, trapezoidal."""
    f = lambda point: K_CONTACT * max(point[1], 0.0) * point[0]
    return 2 * math.pi * sum(0.5 * (f(a) + f(b)) * (b[0] - a[0]) for a, b in zip(curve, curve[1:]))


def measure(model, dat, frd):
    """The figures at each load, with the (radius, overlap) [mm] of the slave nodes in contact."""
    core = dat_blocks(dat, "displacements (vx,vy,vz) for set CORE")
    plate = dat_blocks(dat, "total force (fx,fy,fz) for set PLATE_NODES")
    surface = dat_blocks(dat, "displacements (vx,vy,vz) for set SLAVE_NODES")
    cstr = frd_contact_pressure(frd)
    results = []
    for load in LOADS:

        def at(blocks):
            found = [t for t in blocks if abs(t - model.times[load]) < 1e-9]
            if not found:
                raise RuntimeError(f"no output at {load:g} N")
            return blocks[found[0]]

        force = 180.0 * at(plate)[0][1]
        if abs(force - load) > 1e-3 * load:
            raise RuntimeError(f"contact force {force} N under a load of {load:g} N")
        u = {int(row[0]): row[1:3] for row in at(surface)}
        nodes = []  # (deformed radius, overlap with the plate) from the pole along the surface
        for n in model.slave_nodes:
            x, y = model.coords[n]
            nodes.append((x + u[n][0], model.plate_top - (y + u[n][1])))
        last = max(k for k, node in enumerate(nodes) if node[1] > 0.0)
        (r0, g0), (r1, g1) = nodes[last], nodes[last + 1]
        radius = r0 + (r1 - r0) * g0 / (g0 - g1)
        contact = nodes[:last + 1] + [(radius, 0.0)]
        if any(b[0] <= a[0] for a, b in zip(contact, contact[1:])):
            raise RuntimeError(f"the slave surface folds over at {load:g} N")
        centre = K_CONTACT * nodes[0][1]
        pole_cstr = at(cstr)[model.slave_nodes[0]]
        if abs(pole_cstr - centre) > 0.01 * centre:
            raise RuntimeError(f"CSTR {pole_cstr} MPa at the pole against K x overlap {centre} MPa")
        results.append({
            "load": load,
            "approach": -at(core)[0][2] * 1e-3,
            "force": force,
            "radius": radius * 1e-3,
            "centre": centre * 1e6,
            "penetration": max(g for _, g in nodes) * 1e-3,
            "profile_force": integral(contact),
            "face_force": integral(surface_samples(nodes)),
            "contact": contact,
        })
    return results


def profile(contact):
    """(r [m], p [Pa]) on a uniform grid of deformed radii to just past the contact radius."""
    rows = []
    for k in range(math.floor(contact[-1][0] / PROFILE_STEP) + 2):
        r = k * PROFILE_STEP
        g = contact[0][1] if r < contact[0][0] else 0.0  # the pole node sits AXIS_OFFSET off the axis
        for a, b in zip(contact, contact[1:]):
            if a[0] <= r <= b[0]:
                g = a[1] + (b[1] - a[1]) * (r - a[0]) / (b[0] - a[0])
                break
        rows.append((r * 1e-3, K_CONTACT * max(g, 0.0) * 1e6))
    return rows


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    table, total = [], 0.0
    for level in LEVELS:
        model = Model(level)
        dat, frd, seconds = solve(model)
        results = measure(model, dat, frd)
        total += seconds
        print(f"level {level}: {model.elements} CAX8, {seconds:.0f} s", file=sys.stderr, flush=True)
        for r in results:
            print(f"  {r['load']:g} N: approach {r['approach'] * 1e3:.4f} mm, contact radius "
                  f"{r['radius'] * 1e3:.3f} mm, centre {r['centre']:.1f} Pa, penetration "
                  f"{r['penetration'] * 1e6:.2f} um, 2 pi int p r dr {r['profile_force']:.3f} N "
                  f"(quadratic along the faces {r['face_force']:.3f} N)", file=sys.stderr, flush=True)
            table.append([level, r["load"], r["approach"], r["force"], r["radius"], r["centre"],
                          r["penetration"]])
    with open(os.path.join(here, "sphere_reference.csv"), "w", newline="") as f:
        f.write("# Soft sphere on a rigid core pressed onto a rigid frictionless plate by a force on the\n"
                "# core: R = 70 mm, a 20 mm layer of CalculiX's NEO HOOKE with C10 = 5170 Pa, D1 = 2e-5 1/Pa\n"
                "# on a 50 mm core; CalculiX CAX8, NLGEOM, surface-to-surface penalty contact of slope\n"
                "# 1e10 Pa/m, at mesh levels 1-3 (make_sphere_reference.py). approach: the core's\n"
                "# displacement toward the plate; force: the total contact force; contact_radius: the\n"
                "# deformed radius where the pressure (slope x overlap of the slave nodes) falls to zero;\n"
                "# centre_pressure: the pressure at the pole; max_penetration: the largest overlap.\n")
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["level", "load_N", "approach_m", "force_N", "contact_radius_m", "centre_pressure_Pa",
                    "max_penetration_m"])
        for row in table:
            w.writerow([f"{v:.8g}" if isinstance(v, float) else v for v in row])
    with open(os.path.join(here, "sphere_profile.csv"), "w", newline="") as f:
        f.write(f"# Contact pressure against the deformed radius at mesh level {LEVELS[-1]} of\n"
                "# sphere_reference.csv (make_sphere_reference.py): slope x overlap of the slave nodes,\n"
                f"# linearly interpolated onto a {PROFILE_STEP:g} mm grid to just past the contact radius.\n"
                "# 2 pi int p r dr of these profiles: "
                + ", ".join(f"{r['profile_force']:.3f} N at {r['load']:g} N" for r in results) + ";\n"
                "# with the overlap interpolated quadratically along the slave faces: "
                + ", ".join(f"{r['face_force']:.3f} N" for r in results) + ".\n")
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["load_N", "r_m", "pressure_Pa"])
        for r in results:
            for radius, p in profile(r["contact"]):
                w.writerow([f"{r['load']:g}", f"{radius:.6g}", f"{p:.6g}"])
    print(f"CalculiX took {total:.0f} s; wrote sphere_reference.csv and sphere_profile.csv", file=sys.stderr)


if __name__ == "__main__":
    main()
