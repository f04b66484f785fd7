#!/usr/bin/env python3
# SPDX-License-Identifier: AGPL-3.0-or-later
"""Fit a Yeoh material to the bundled Ecoflex 00-30 stress-stretch curves and
compare fitted with measured stresses.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/fit_dataset.py --out fit

Writes the fit's folder (material.json, report.json, curves/) into --out, and
fit.png when matplotlib is installed. Checks the training RMS error."""
import argparse
import csv
import os

import palpa

HERE = os.path.dirname(os.path.abspath(__file__))
DATASET = os.path.join(HERE, "..", "fit", "ecoflex30", "dataset-homogeneous.json")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="fit-python")
    ap.add_argument("--small", action="store_true", help="(the fit is quick at any size)")
    a = ap.parse_args()
    palpa.set_log_level("warning")
    iterations = []
    r = palpa.fit(DATASET, model="yeoh", out=os.path.join(a.out, "yeoh"), overwrite=True,
                  progress=lambda info: iterations.append(info["objective"]))
    rms = r.report["rms_error"]
    print(f"{r.material!r}: RMS train {rms['train'] / 1e3:.2f} kPa, validate {rms['validate'] / 1e3:.2f} kPa, "
          f"{len(iterations)} iterations; E = {r.material.small_strain()['E'] / 1e3:.2f} kPa")
    for c in r.curves:
        print(f"  {c['name']} ({c['role']}): {c['rms_error_fitted'] / 1e3:.2f} kPa")
    assert rms["train"] < 2e3, rms  # Pa
    assert r.history["objective"][-1] < r.history["objective"][0]
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib is not installed: no plot (apt-get install python3-matplotlib)")
        return
    fig, ax = plt.subplots()
    for c in r.curves:
        with open(os.path.join(r.out, "curves", c["name"] + ".csv")) as f:
            rows = list(csv.reader(line for line in f if not line.startswith("#")))
        head, data = rows[0], [[float(x) for x in row] for row in rows[1:]]
        x = [d[0] for d in data]
        ax.plot(x, [d[1] for d in data], "o", ms=3, label=c["name"] + " measured")
        ax.plot(x, [d[head.index(next(h for h in head if "_fitted" in h))] for d in data], "-",
                label=c["name"] + " fitted")
    ax.set_xlabel(head[0])
    ax.set_ylabel("stress")
    ax.legend(fontsize=7)
    fig.savefig(os.path.join(a.out, "fit.png"), dpi=120)


if __name__ == "__main__":
    main()
