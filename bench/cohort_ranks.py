#!/usr/bin/env python3
# SPDX-License-Identifier: AGPL-3.0-or-later
"""cohort_ranks: one support for a cohort, as `palpa design` runs it on one
process and spread over MPI ranks (mpirun -np 2): per cohort size and number
of ranks, the wall time of the whole run, the seconds per design iteration,
and whether the shape to make is the one process's to the last bit.

    bench/cohort_ranks.py [--palpa build/release/apps/palpa/palpa] [--bodies 2 3 6] [--iterations 3]

The cohorts are the bundled three spheres (examples/design/cohort) and, for
six, three more of other sizes, stiffnesses and places. Prints one JSON line
per run."""
import argparse
import copy
import json
import os
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.path.dirname(HERE)


def cohort(n):
    with open(os.path.join(SOURCE, "examples", "design", "cohort", "scene.json")) as f:
        scene = json.load(f)
    bodies = scene["bodies"]
    extra = []
    for k, (size, modulus, mass, x, y) in enumerate([(60, 16, 0.45, -20, -14), (68, 30, 0.65, 18, 16),
                                                     (56, 20, 0.35, -4, 20)]):
        b = copy.deepcopy(bodies[k % len(bodies)])
        b["name"] = f"extra-{k + 1}"
        b["body"]["generate"]["length"] = f"{size} mm"
        b["body"]["material"]["parameters"]["E"] = f"{modulus} kPa"
        b["body"]["position"] = [f"{x} mm", f"{y} mm", f"{size / 2 + 1} mm"]
        b["core"]["mass"] = f"{mass} kg"
        extra.append(b)
    scene["bodies"] = (bodies + extra)[:n]
    return scene


def run(palpa, scene_file, out, ranks, iterations):
    cmd = [palpa, "-q", "design", scene_file, "-o", out, "--iterations", str(iterations)]
    env = dict(os.environ)
    if ranks > 1:
        cmd = ["mpirun", "--oversubscribe", "-np", str(ranks)] + cmd
        env.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    t0 = time.monotonic()
    subprocess.run(cmd, check=True, env=env, stdout=subprocess.DEVNULL)
    wall = time.monotonic() - t0
    with open(os.path.join(out, "summary.json")) as f:
        return wall, json.load(f)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--palpa", default=os.path.join(SOURCE, "build", "release", "apps", "palpa", "palpa"))
    ap.add_argument("--bodies", type=int, nargs="+", default=[2, 3, 6])
    ap.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--iterations", type=int, default=3)
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        for n in a.bodies:
            scene_file = os.path.join(tmp, f"cohort{n}.json")
            with open(scene_file, "w") as f:
                json.dump(cohort(n), f)
            first_shape = None
            for r in a.ranks:
                if r > n:
                    continue
                out = os.path.join(tmp, f"cohort{n}-ranks{r}")
                wall, s = run(a.palpa, scene_file, out, r, a.iterations)
                with open(os.path.join(out, "support.obj")) as f:
                    shape = f.read()
                first_shape = first_shape if first_shape is not None else shape
                print(json.dumps({"bench": "cohort_ranks", "bodies": n, "ranks": r, "iterations": s["iterations"],
                                  "wall_seconds": round(wall, 2), "seconds_per_iteration": s["seconds_per_iteration"],
                                  "initial_equilibrium_seconds": s["initial_equilibrium_seconds"],
                                  "equilibrium_solves": s["equilibrium_solves"],
                                  "mean_zeta_body_ratio": s["mean_zeta_body_ratio"],
                                  "same_shape_as_one_process": shape == first_shape}), flush=True)


if __name__ == "__main__":
    sys.exit(main())
