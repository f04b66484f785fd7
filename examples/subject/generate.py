#!/usr/bin/env python3
# SPDX-License-Identifier: AGPL-3.0-or-later
"""The bundled synthetic subject: raw poke and ultrasound logs of a seated person.

Writes examples/subject/: subject.json (the seated body of examples/rest/chair,
eight poke locations under the buttocks and thighs, a chair to design), the
raw logs of every location (raw/<location>/), truth.json (the materials and
depths the logs were made from) and the smaller subjects the tests run
(subject-small.json, cohort/) and the README's walkthrough (walkthrough.json).

Truth. The tissue at every location is one material's shape, an isochoric
neo-Hookean (CalculiX *HYPERELASTIC, YEOH with C20 = C30 = 0, which is
palpa's `neo-hookean-isochoric`) with nu = 0.47, scaled to that location's
Young's modulus (25-60 kPa, stiffer toward the knees), on a layer of that
location's depth (10-24 mm, thinner toward the knees) bonded to bone.

Curves. Each location is poked with flat punches of 3 and 6 mm radius; the
force-indentation curve of each comes from an independent finite-element
solver, CalculiX (the deck, mesh and contact of examples/fit/generate/
generate.py, level 1: a 100 mm wide layer, frictionless rigid punch), so that
fitting them with palpa does not fit palpa's own simulator back to itself.
Each poke goes to half the radius or 15% of the depth (at most 4 mm; a curve
CalculiX cannot finish is cut where it stopped, if past two thirds of it).

Logs. Each curve is turned into what the devices of thesis §3.2 would log
during a rest-poke-rest protocol (2 s rest, 0.6 s in, 0.6 s out, 2 s rest,
smooth ramps): a force gauge at 200 Hz (noise 0.5% of the peak force, drift
0.5%/s of it) and a laser at 1000 Hz on its own clock (12.345 s ahead; the
force log starts 0.3 s earlier), reading volts through a nonlinear
calibration (distance = 30 mm + 8 mm/V V + 0.3 mm/V^2 V^2, a 21-row table),
with 5 um noise, a 20 um/s drift and a 9 Hz hand tremor of 30 um in the true
indentation. Six locations also have ultrasound picks of two interfaces
taken while poking with the probe (fat at 40% of the depth taking 60% of the
indentation, bone at the depth taking 90%), on a clock 0.15 s ahead; the
other two have none, and their depth is searched by the fit (on a 2 mm grid).

Pressure map. The subject also ships what a pressure mat on its chair would
have logged (raw/pressure/): palpa rests the body with the true depths and
moduli (the same pipeline steps as the fitted body: `palpa subject body` on
the truths, then `palpa rest`) on the design's initial support, and a sensor
on a 25 mm grid over the seat reads its support-side pressure: 300 samples
each, through a gain, times the subject's posture at that sensor (the
reference sensor's reading, 1 + 0.1 sin(1.3 i)), with 2% noise and a few mV
of offset noise. The workflow
turns them into a map (`palpa acquire pressure`) and compares it with the
simulated one.

Usage (about 15 min on one core; CalculiX runs one at a time):
  python3 examples/subject/generate.py [--ccx /usr/bin/ccx]
  python3 examples/subject/generate.py --subjects-only --pressure build/release/apps/palpa/palpa
      (the pressure logs only; about a minute)
Python standard library only. Deterministic: the same CalculiX binary gives the
same files.
"""

import argparse
import importlib.util
import json
import math
import os
import random
import re
import shutil
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
EXAMPLES = os.path.dirname(HERE)
SEED = 20261206

# The CalculiX deck and runner of the fit examples.
_spec = importlib.util.spec_from_file_location("fit_generate", os.path.join(EXAMPLES, "fit", "generate", "generate.py"))
fit_generate = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(fit_generate)

NU = 0.47
RADII = [3.0, 6.0]  # mm
POINTS = 21         # depths per CalculiX curve, 0 included

# name, position on the scan (mm, its frame), E (kPa), depth (mm), ultrasound?
LOCATIONS = [
    ("buttock-left", (-59.6, -16.9, -36.0), 25.0, 24.0, True),
    ("buttock-right", (59.6, -16.9, -36.0), 28.0, 22.0, True),
    ("thigh-back-left", (-117.1, -28.3, 85.2), 35.0, 18.0, True),
    ("thigh-back-right", (117.1, -28.3, 85.2), 32.0, 20.0, True),
    ("thigh-mid-left", (-88.7, -10.4, 195.8), 45.0, 14.0, False),
    ("thigh-mid-right", (88.7, -10.4, 195.8), 42.0, 16.0, True),
    ("knee-left", (-149.9, 0.3, 296.7), 60.0, 10.0, True),
    ("knee-right", (149.9, 0.3, 296.7), 55.0, 12.0, False),
]


def material(young_kpa):
    """Isochoric neo-Hookean (Yeoh with C20 = C30 = 0) of this E and NU."""
    c10 = young_kpa / (4.0 * (1.0 + NU))
    return fit_generate.yeoh_from_small_strain(c10=c10, c20=0.0, c30=0.0, poisson=NU)


def max_depth(depth, radius):
    # CalculiX's neo-Hookean layer gives way under the sharp rim at about
    # 0.65 of the radius, and a thin layer under a wide punch at about a fifth
    # of its depth: stay below both.
    return min(0.5 * radius, 0.15 * depth, 4.0)


# ------------------------------------------------------------------ logs

def smoothstep(x):
    x = min(1.0, max(0.0, x))
    return x * x * (3.0 - 2.0 * x)


class Protocol:
    rest_before, ramp_in, ramp_out, rest_after = 2.0, 0.6, 0.6, 2.0

    def __init__(self, depth_m):
        self.depth = depth_m

    def total(self):
        return self.rest_before + self.ramp_in + self.ramp_out + self.rest_after

    def poke(self, t):
        if t < self.rest_before + self.ramp_in:
            return self.depth * smoothstep((t - self.rest_before) / self.ramp_in)
        return self.depth * (1.0 - smoothstep((t - self.rest_before - self.ramp_in) / self.ramp_out))


def interpolate(xs, ys, x):
    """Piecewise linear, extended linearly at both ends."""
    if x <= xs[0]:
        k = 0
    elif x >= xs[-1]:
        k = len(xs) - 2
    else:
        k = max(i for i in range(len(xs) - 1) if xs[i] <= x)
    t = (x - xs[k]) / (xs[k + 1] - xs[k])
    return ys[k] + t * (ys[k + 1] - ys[k])


CAL_VOLTS = [0.5 * i for i in range(21)]
CAL_MM = [30.0 + 8.0 * v + 0.3 * v * v for v in CAL_VOLTS]


def poke_logs(depths_mm, forces_n, rng):
    """(force.csv, laser.csv) texts of one poke along the curve, to 95% of its depth."""
    p = Protocol(0.95 * depths_mm[-1] * 1e-3)
    peak = max(forces_n)
    force_noise, force_drift = 0.005 * peak, 0.005 * peak
    laser_noise, laser_drift, tremor, tremor_hz = 5e-6, 20e-6, 30e-6, 9.0
    laser_clock, force_lead, laser_rest = 12.345, 0.3, 60e-3
    xs = [d * 1e-3 for d in depths_mm]

    def delta(t):
        return p.poke(t) + tremor * math.sin(2.0 * math.pi * tremor_hz * t + 0.7)

    def force(d):
        return interpolate(xs, forces_n, d) if d > 0.0 else 0.0

    f_lines = ["# synthetic force gauge log", "time_s,force_N"]
    i = 0
    while True:
        t = -force_lead + i / 200.0
        if t > p.total():
            break
        f = force(delta(t)) + force_drift * (t + 1.0) + rng.gauss(0.0, force_noise)
        f_lines.append("%.6f,%.5f" % (t, f))
        i += 1
    l_lines = ["# synthetic laser log", "time_s,voltage_V"]
    i = 0
    while True:
        t = i / 1000.0
        if t > p.total():
            break
        distance_mm = (laser_rest - delta(t) + laser_drift * t + rng.gauss(0.0, laser_noise)) * 1e3
        l_lines.append("%.6f,%.7f" % (t + laser_clock, interpolate(CAL_MM, CAL_VOLTS, distance_mm)))
        i += 1
    return "\n".join(f_lines) + "\n", "\n".join(l_lines) + "\n"


def calibration_csv():
    rows = ["# synthetic laser calibration", "voltage_V,distance_mm"]
    rows += ["%g,%.6f" % (v, d) for v, d in zip(CAL_VOLTS, CAL_MM)]
    return "\n".join(rows) + "\n"


def ultrasound_logs(depths_mm, forces_n, depth_mm, rng):
    """(force.csv, fat.csv, bone.csv): a poke with the probe and the picks of two interfaces."""
    p = Protocol(0.95 * depths_mm[-1] * 1e-3)
    xs = [d * 1e-3 for d in depths_mm]
    peak = max(forces_n)
    f_lines = ["# synthetic force gauge log (ultrasound probe)", "time_s,force_N"]
    i = 0
    while True:
        t = -0.3 + i / 100.0
        if t > p.total():
            break
        d = p.poke(t)
        f = (interpolate(xs, forces_n, d) if d > 0.0 else 0.0) + rng.gauss(0.0, 0.005 * peak)
        f_lines.append("%.6f,%.5f" % (t, f))
        i += 1
    clock = 0.15
    times = [0.5, 1.0, 1.5, 1.9] + [2.0 + 0.1 * k for k in range(13)] + [3.5, 4.0, 4.5]
    picks = []
    for rest, share, name in ((0.4 * depth_mm, 0.6, "fat"), (depth_mm, 0.9, "bone")):
        rows = ["# synthetic ultrasound picks (%s)" % name, "time_s,depth_mm"]
        for t in times:
            rows.append("%.4f,%.5f" % (t + clock, rest - share * p.poke(t) * 1e3 + rng.gauss(0.0, 0.02)))
        picks.append("\n".join(rows) + "\n")
    return "\n".join(f_lines) + "\n", picks[0], picks[1]


# ------------------------------------------------------------------ files

def write(path, text):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(text)


def dump(path, obj):
    write(path, json.dumps(obj, indent=2) + "\n")


def mm(v):
    return "%g mm" % v


def location_json(name, pos, ultrasound, depth):
    loc = {"name": name, "position": [mm(c) for c in pos],
           "pokes": [{"radius": mm(a), "force": "raw/%s/r%gmm-force.csv" % (name, a),
                      "laser": "raw/%s/r%gmm-laser.csv" % (name, a), "calibration": "raw/laser-calibration.csv"} for a in RADII]}
    if ultrasound:
        loc["ultrasound"] = {"force": "raw/%s/us-force.csv" % name,
                             "interfaces": [{"name": "fat", "picks": "raw/%s/us-fat.csv" % name},
                                            {"name": "bone", "picks": "raw/%s/us-bone.csv" % name}]}
    else:
        lo = max(6.0, 2.0 * round((depth - 4.0) / 2.0))
        loc["depth_search"] = {"from": mm(lo), "to": mm(lo + 8.0), "count": 5}
    return loc


def subject_json(name, locations, edge_mm, design):
    return {
        "palpa_subject": 1,
        "name": name,
        "body": {"surface": "../rest/chair/base_seated.obj", "unit": "m", "remove_self_intersections": True,
                 "clip": {"min": ["-250 mm", "-100 mm", "-150 mm"], "max": ["250 mm", "75 mm", "360 mm"]},
                 "core_offset": "distance", "edge": mm(edge_mm),
                 "density": "1000 kg/m^3", "rotation": {"axis": [1, 0, 0], "angle": "90 deg"},
                 "position": ["0 mm", "0 mm", "40 mm"]},
        "locations": [location_json(n, p, us, d) for (n, p, _, d, us) in locations],
        "fit": {"model": "neo-hookean-isochoric", "poisson": NU, "lateral_size": "100 mm",
                "contact": "frictionless", "mesh_level": 2, "steps": 10, "depth_from": "whole",
                "fix": ["nu"]},
        "design": design,
    }


def design_json(iterations):
    return {
        "palpa_design": 1,
        "core": {"mass": "45 kg", "free": ["z", "rx", "ry"], "centre": ["0 mm", "-30 mm", "100 mm"]},
        "support": {"box": {"size": ["500 mm", "500 mm", "200 mm"], "divisions": 40},
                    "position": ["0 mm", "-80 mm", "0 mm"]},
        "contact": {"max_penetration": "0.3 mm"},
        "design": {"method": "lbfgs",
                   "region": {"min": ["-240 mm", "-320 mm", "-10 mm"], "max": ["240 mm", "160 mm", "10 mm"]},
                   "direction": "normal", "smoothing": {"exponent": -2, "iterations": 5},
                   "iterations": iterations},
    }


def read_ply_pressure(path):
    """Vertices and pressure_Pa of a binary PLY written by palpa (x, y, z, pressure_Pa doubles)."""
    import struct
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode()
    n = int(re.search(r"element vertex (\d+)", header).group(1))
    props = re.findall(r"property double (\w+)", header.split("element face")[0])
    rows = struct.unpack_from("<%dd" % (n * len(props)), data, end)
    k = props.index("pressure_Pa")
    return [(rows[i * len(props)], rows[i * len(props) + 1], rows[i * len(props) + 2], rows[i * len(props) + k])
            for i in range(n)]


def pressure_logs(palpa, seated, truth):
    """raw/pressure/: a pressure mat's logs of the body with the true fields on the initial chair."""
    import subprocess
    import tempfile
    palpa = os.path.abspath(palpa)
    work = tempfile.mkdtemp(prefix="palpa_subject_pressure_")
    subject = json.loads(json.dumps(seated))  # a copy: the subject file keeps its locations
    subject["name"] = "truth"
    subject["body"] = dict(seated["body"], surface=os.path.join(EXAMPLES, "rest", "chair", "base_seated.obj"))
    subject["design"] = os.path.join(HERE, "chair-design.json")
    for loc in subject["locations"]:
        loc["pokes"] = [{"radius": "3 mm", "curve": os.path.join(work, "unused.csv")}]
        loc.pop("ultrasound", None)
        loc["depth_search"] = {"from": "5 mm", "to": "10 mm", "count": 2}
    write(os.path.join(work, "unused.csv"), "indentation_m,force_N\n")
    dump(os.path.join(work, "subject.json"), subject)
    for l in truth["locations"]:
        e_kpa = l["youngs_modulus_Pa"] * 1e-3
        dump(os.path.join(work, "fits", l["name"], "material.json"),
             {"palpa_material": 1, "model": "neo-hookean-isochoric",
              "parameters": {"E": "%.17g kPa" % e_kpa, "nu": NU},
              "provenance": {"created_by": "examples/subject/generate.py", "method": "the truth", "objective": None}})
        dump(os.path.join(work, "fits", l["name"], "report.json"),
             {"layer_depth_m": l["depth_m"], "depth_search": False, "termination": "converged",
              "curves": [{"role": "train", "rms_error_fitted": 0.0, "largest_measured": 1.0}]})
    for cmd in (["subject", "body", "subject.json", "--fits", "fits", "-o", "body"],
                ["-q", "rest", "body/rest.json", "-o", "rest"]):
        subprocess.run([palpa] + cmd, cwd=work, check=True)
    with open(os.path.join(work, "rest", "summary.json")) as f:
        load = json.load(f)["pressure_map_force_N"]["load"]
    verts = read_ply_pressure(os.path.join(work, "rest", "support.ply"))
    top = max(v[2] for v in verts)
    seat = [v for v in verts if v[2] > top - 1e-6]
    touched = [v for v in seat if v[3] > 0.0]
    lo = [min(v[k] for v in touched) - 0.03 for k in (0, 1)]
    hi = [max(v[k] for v in touched) + 0.03 for k in (0, 1)]
    sensors = []
    x = lo[0]
    while x <= hi[0]:
        y = lo[1]
        while y <= hi[1]:
            v = min(seat, key=lambda q: (q[0] - x) ** 2 + (q[1] - y) ** 2)
            if (v[0] - x) ** 2 + (v[1] - y) ** 2 < 0.01 ** 2:
                sensors.append(v)
            y += 0.025
        x += 0.025
    rng = random.Random("pressure-%d" % SEED)
    peak = max(v[3] for v in sensors)
    loc_rows = ["# synthetic pressure-mat sensor locations (on the chair's seat, world frame)",
                "location,x_mm,y_mm,z_mm"]
    sample_rows = ["# synthetic pressure-mat samples, 300 per sensor", "location,reading_V,reference_V"]
    for i, v in enumerate(sensors, start=1):
        loc_rows.append("%d,%.3f,%.3f,%.3f" % (i, v[0] * 1e3, v[1] * 1e3, v[2] * 1e3))
        posture = 1.0 + 0.1 * math.sin(1.3 * i)
        for _ in range(300):
            # 2% noise on the reading, and a sensor's own few mV above 0 (an unloaded
            # sensor does not read exactly 0, which would look like a clipped one).
            reading = 2.0 * v[3] / peak * posture * (1.0 + rng.gauss(0.0, 0.02)) + abs(rng.gauss(0.0, 0.002))
            sample_rows.append("%d,%.5f,%.5f" % (i, reading, posture * (1.0 + rng.gauss(0.0, 0.005))))
    write(os.path.join(HERE, "raw", "pressure", "locations.csv"), "\n".join(loc_rows) + "\n")
    write(os.path.join(HERE, "raw", "pressure", "samples.csv"), "\n".join(sample_rows) + "\n")
    write(os.path.join(HERE, "raw", "pressure", "load.txt"), "%.6g N\n" % load)
    print("pressure mat: %d sensors, load %.1f N, peak %.1f kPa" % (len(sensors), load, peak * 1e-3))
    shutil.rmtree(work)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--ccx", default=shutil.which("ccx") or "/usr/bin/ccx")
    ap.add_argument("--keep", action="store_true", help="keep the CalculiX folders")
    ap.add_argument("--only", default="", help="these locations only (comma-separated; for testing)")
    ap.add_argument("--subjects-only", action="store_true", help="rewrite the subject files only, no CalculiX runs")
    ap.add_argument("--pressure", default="", help="palpa binary: (re)make the pressure-mat logs with it")
    args = ap.parse_args()
    t0 = time.time()
    truth = {"palpa_subject_truth": 1, "material": "neo-hookean-isochoric (CalculiX YEOH, C20 = C30 = 0)",
             "poisson": NU, "locations": []}
    truth_path = os.path.join(HERE, "truth.json")
    if os.path.exists(truth_path):
        with open(truth_path) as f:
            truth = json.load(f)
    write(os.path.join(HERE, "raw", "laser-calibration.csv"), calibration_csv())
    for name, pos, young, depth, ultrasound in LOCATIONS:
        if args.subjects_only or (args.only and name not in args.only.split(",")):
            continue
        ex = {"material": material(young), "depth": depth}
        rng = random.Random("%s-%d" % (name, SEED))
        curves = []
        for a in RADII:
            dmax = max_depth(depth, a)
            tag = "%s_r%g" % (name, a)
            run = fit_generate.simulate(args.ccx, ex, a, 1, dmax, POINTS - 1, args.keep, tag)
            fit_generate.log_run(name, a, 1, run, POINTS - 1)
            if len(run["depths"]) < POINTS:
                # stopped early: again from a quarter of a depth step (as the fit examples do)
                again = fit_generate.simulate(args.ccx, ex, a, 1, dmax, POINTS - 1, args.keep, tag, first=0.25)
                fit_generate.log_run(name, a, 1, again, POINTS - 1)
                if len(again["depths"]) > len(run["depths"]):
                    run = again
            if len(run["depths"]) < (2 * POINTS) // 3:
                sys.exit("CalculiX stopped at %.3g of %.3g mm for %s, radius %g mm" % (
                    run["depths"][-1], dmax, name, a))
            force, laser = poke_logs(run["depths"], run["curve"], rng)
            write(os.path.join(HERE, "raw", name, "r%gmm-force.csv" % a), force)
            write(os.path.join(HERE, "raw", name, "r%gmm-laser.csv" % a), laser)
            curves.append({"radius_mm": a, "noise_free": [[round(d, 6), round(f, 7)]
                                                          for d, f in zip(run["depths"], run["curve"])],
                           "seconds": run["seconds"]})
            if ultrasound and a == RADII[-1]:
                us_force, fat, bone = ultrasound_logs(run["depths"], run["curve"], depth, rng)
                write(os.path.join(HERE, "raw", name, "us-force.csv"), us_force)
                write(os.path.join(HERE, "raw", name, "us-fat.csv"), fat)
                write(os.path.join(HERE, "raw", name, "us-bone.csv"), bone)
        truth["locations"] = [l for l in truth["locations"] if l["name"] != name] + [{
            "name": name, "position_mm": list(pos), "youngs_modulus_Pa": young * 1e3, "depth_m": depth * 1e-3,
            "ultrasound": ultrasound, "curves": curves}]
        dump(truth_path, truth)
    order = [n for (n, _, _, _, _) in LOCATIONS]
    truth["locations"].sort(key=lambda l: order.index(l["name"]))
    dump(truth_path, truth)
    # The subject, a smaller one for the tests (four locations, a coarser
    # body), and a cohort of three tiny subjects.
    dump(os.path.join(HERE, "chair-design.json"), design_json(12))
    seated = subject_json("seated", LOCATIONS, 12.0, "chair-design.json")
    if args.pressure:
        pressure_logs(args.pressure, seated, truth)
    if os.path.exists(os.path.join(HERE, "raw", "pressure", "samples.csv")):
        with open(os.path.join(HERE, "raw", "pressure", "load.txt")) as f:
            seated["pressure"] = {"locations": "raw/pressure/locations.csv", "samples": "raw/pressure/samples.csv",
                                  "load": f.read().strip()}
    dump(os.path.join(HERE, "subject.json"), seated)
    small = [LOCATIONS[i] for i in (0, 3, 4, 7)]
    dump(os.path.join(HERE, "subject-small.json"), subject_json("seated-small", small, 16.0, "chair-design.json"))
    # The README's walkthrough: two locations (one with ultrasound, one whose
    # depth is searched), the coarser body, the pressure mat.
    walk = subject_json("seated-walkthrough", [LOCATIONS[0], LOCATIONS[7]], 16.0, "chair-design.json")
    if "pressure" in seated:
        walk["pressure"] = seated["pressure"]
    dump(os.path.join(HERE, "walkthrough.json"), walk)
    # A cohort of three tiny subjects for the workflow's bookkeeping tests: a
    # generated thigh each, one location with the logs of one of the seated
    # subject's, a two-iteration design of a flat block.
    cohort = os.path.join(HERE, "cohort")
    dump(os.path.join(cohort, "thigh-design.json"), {
        "palpa_design": 1,
        "core": {"mass": "5 kg", "free": ["z"]},
        "support": {"box": {"size": ["500 mm", "240 mm", "40 mm"], "divisions": 30}},
        "contact": {"max_penetration": "0.3 mm"},
        "design": {"region": {"min": ["-240 mm", "-110 mm", "-10 mm"], "max": ["240 mm", "110 mm", "10 mm"]},
                   "direction": "normal", "iterations": 2}})
    names = []
    for tiny, source in (("tiny-a", "knee-left"), ("tiny-b", "thigh-mid-right"), ("tiny-c", "thigh-back-left")):
        loc = location_json(source, (0.0, 0.0, -69.0), True, 0.0)
        loc["name"] = "underside"
        for p in loc["pokes"]:
            for k in ("force", "laser", "calibration"):
                p[k] = "../../" + p[k]
        for k, v in list(loc["ultrasound"].items()):
            if k == "force":
                loc["ultrasound"][k] = "../../" + v
        for i in loc["ultrasound"]["interfaces"]:
            i["picks"] = "../../" + i["picks"]
        dump(os.path.join(cohort, tiny, "subject.json"), {
            "palpa_subject": 1,
            "name": tiny,
            "body": {"generate": {"shape": "thigh", "length": "400 mm", "width": "160 mm", "height": "140 mm"},
                     "edge": "20 mm", "position": ["0 mm", "0 mm", "72 mm"]},
            "locations": [loc],
            "fit": {"model": "neo-hookean-isochoric", "poisson": NU, "lateral_size": "100 mm",
                    "contact": "frictionless", "mesh_level": 1, "steps": 6, "fix": ["nu"]},
            "design": "../thigh-design.json"})
        names.append("%s/subject.json" % tiny)
    dump(os.path.join(cohort, "cohort.json"), {"palpa_cohort": 1, "subjects": names})
    print("total %.0f s" % (time.time() - t0))


if __name__ == "__main__":
    sys.exit(main())
