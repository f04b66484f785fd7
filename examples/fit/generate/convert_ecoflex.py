#!/usr/bin/env python3
# SPDX-License-Identifier: AGPL-3.0-or-later
"""Converts three Ecoflex 00-30 compression tests to palpa's curve CSVs.

Source: the tissue phantom material database of Dawood, Zhang, Osman, Suulker,
Abdulali, Angelmahr and Althoefer (Queen Mary University of London),
https://github.com/abubakardawood/tissue-phantom-material-database, data under
CC BY 4.0. Folder EF30_0T: Ecoflex 00-30 without thinner, cylinders 50 mm in
diameter and 30 mm high compressed between two plates at 10 mm/min to 20 mm.

Writes into examples/fit/ecoflex30/:
  - EF30_0T_<test>_force.csv: indentation_mm,force_N (platen displacement and
    load, the source's "Compression (mm)" and "Load (N)" columns), for the
    "compression" dataset (dataset.json);
  - EF30_0T_<test>_stress.csv: stretch,stress_kPa (stretch = 1 + the source's
    engineering strain, stress = its engineering stress, i.e. the nominal
    stress F/A0, both negative in compression), for the "homogeneous" dataset
    (dataset-homogeneous.json, uniaxial);
  - dataset.json, dataset-homogeneous.json.
Each curve is subsampled to POINTS rows: for each of POINTS platen displacements
uniformly spaced from 0 to the largest one, the source row closest to it (no
averaging or smoothing; values are copied as they are, only rounded to the
source's precision). The source files hold only the loading part of each test.

Usage: python3 examples/fit/generate/convert_ecoflex.py --source DIR
  DIR: a checkout of the database (the folder holding EF30_0T/).
Standard library only; deterministic.
"""

import argparse
import json
import os

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(os.path.dirname(HERE), "ecoflex30")
POINTS = 80
TESTS = [("A1", "train"), ("A2", "train"), ("B1", "validate")]
CREDIT = ("Dawood, Zhang, Osman, Suulker, Abdulali, Angelmahr, Althoefer, "
          "\"Hyperelastic Characterisation of Silicone Tissue Phantoms\" (2026), "
          "https://github.com/abubakardawood/tissue-phantom-material-database")


def read_source(path):
    with open(path) as f:
        lines = f.read().splitlines()
    head = next(i for i, l in enumerate(lines) if l.startswith("Time"))
    meta = [l.strip().rstrip(";") for l in lines[:head] if l.strip()]
    cols = lines[head].split(",")
    rows = []
    for l in lines[head + 1:]:
        if l.strip():
            rows.append([float(v) for v in l.split(",")])
    return meta, cols, rows


def subsample(rows, col):
    top = max(r[col] for r in rows)
    picked = []
    for k in range(POINTS):
        target = top * k / (POINTS - 1)
        best = min(range(len(rows)), key=lambda i: abs(rows[i][col] - target))
        if picked and best <= picked[-1]:
            continue
        picked.append(best)
    return [rows[i] for i in picked]


def header(name, test, meta, what, columns):
    return [
        "# Ecoflex 00-30 (no thinner), uniaxial compression test %s: %s" % (test, what),
        "# source: file EF30_0T/%s of the tissue phantom material database," % name,
        "#   " + CREDIT,
        "#   licence: CC BY 4.0 (https://creativecommons.org/licenses/by/4.0/), see DATA_LICENSE.md",
        "# source metadata: " + "; ".join(meta),
        "# changes: " + columns,
        "#   subsampled to %d rows (the source row closest to each of %d platen displacements" % (POINTS, POINTS),
        "#   uniformly spaced from 0 to the largest); loading only, as in the source",
    ]


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--source", required=True, help="folder holding EF30_0T/")
    args = p.parse_args()
    os.makedirs(OUT, exist_ok=True)
    force_curves, stress_curves = [], []
    for test, role in TESTS:
        name = "EF30_0T_%s.csv" % test
        meta, cols, rows = read_source(os.path.join(args.source, "EF30_0T", name))
        ic, il = cols.index("Compression (mm)"), cols.index("Load (N)")
        ie, isg = cols.index("Engineering Strain [-]"), cols.index("Engineering Stress (kPa)")
        rows = subsample(rows, ic)
        fname = "EF30_0T_%s_force.csv" % test
        with open(os.path.join(OUT, fname), "w") as f:
            f.write("\n".join(header(name, test, meta, "platen displacement and force",
                                     "kept the columns 'Compression (mm)' -> indentation_mm and "
                                     "'Load (N)' -> force_N (units unchanged)")) + "\n")
            f.write("indentation_mm,force_N\n")
            for r in rows:
                f.write("%.6f,%.6f\n" % (r[ic], r[il]))
        force_curves.append({"file": fname, "role": role})
        sname = "EF30_0T_%s_stress.csv" % test
        with open(os.path.join(OUT, sname), "w") as f:
            f.write("\n".join(header(name, test, meta, "nominal stress against stretch",
                                     "stretch = 1 + 'Engineering Strain [-]' (negative in compression); "
                                     "stress_kPa = 'Engineering Stress (kPa)' (load / initial area, "
                                     "unit unchanged)")) + "\n")
            f.write("stretch,stress_kPa\n")
            for r in rows:
                f.write("%.6f,%.6f\n" % (1.0 + r[ie], r[isg]))
        stress_curves.append({"file": sname, "load_case": "uniaxial", "role": role})
    sample = "Ecoflex 00-30 cylinder, 50 mm diameter, 30 mm high (measured; Dawood et al., CC BY 4.0)"
    datasets = {
        "dataset.json": {"palpa_dataset": 1, "sample": sample, "test": "compression",
                         "sample_radius": "25 mm", "sample_height": "30 mm", "contact": "frictionless",
                         "poisson": 0.49, "curves": force_curves},
        "dataset-homogeneous.json": {"palpa_dataset": 1, "sample": sample, "test": "homogeneous",
                                     "poisson": 0.49, "curves": stress_curves},
    }
    for fname, d in datasets.items():
        head = dict(d)
        curves = head.pop("curves")
        text = json.dumps(head, indent=2)[:-2] + ',\n  "curves": [\n    ' + \
            ",\n    ".join(json.dumps(c) for c in curves) + "\n  ]\n}\n"
        with open(os.path.join(OUT, fname), "w") as f:
            f.write(text)
    print("wrote", OUT)


if __name__ == "__main__":
    main()
