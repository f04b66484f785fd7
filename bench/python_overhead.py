#!/usr/bin/env python3
# SPDX-License-Identifier: AGPL-3.0-or-later
"""Call overhead of the Python module (see BENCHMARKS.md): a poke through
palpa.poke against the same poke's C++ part timed inside the module, in one
run. Problem: a 3 mm punch, 10 mm layer, neo-Hookean E = 10 kPa, nu = 0.45,
mesh level 2; a 1-step poke to 0.2 mm (the overhead dominates) and the
20-step curve to 2 mm (overhead against a whole solve); and the fixed cost
of any call, Material.energy on one row of stretches. Figures: median wall
times, the median of the paired differences (Python minus C++) and its share
of the C++ time.
One JSON line per figure.

    PYTHONPATH=build/release/python /usr/bin/python3 bench/python_overhead.py"""
import json
import statistics
import time

import numpy as np

import palpa
from palpa import _palpa


def main():
    palpa.set_log_level("warning")
    m = palpa.Material("neo-hookean", E=10e3, nu=0.45)
    for name, depth, steps, repeats in (("one_step", 0.2e-3, 1, 61), ("curve_20_steps", 2e-3, 20, 15)):
        # Paired: each repetition times the C++ part, then the same poke through
        # Python, so that drift and other load hit both alike.
        cpp, py = [], []
        for _ in range(repeats):
            cpp.append(_palpa._poke_cpp_seconds(m, 10e-3, 3e-3, depth, steps, 2, 1)[0])
            t0 = time.perf_counter()
            palpa.poke(m, thickness=10e-3, radius=3e-3, depth=depth, steps=steps, mesh_level=2, extrapolate=False)
            py.append(time.perf_counter() - t0)
        overhead = statistics.median(p - c for p, c in zip(py, cpp))
        t_cpp = statistics.median(cpp)
        print(json.dumps({"benchmark": "python_call_overhead", "case": name, "steps": steps, "repeats": repeats,
                          "cpp_seconds": t_cpp, "python_seconds": statistics.median(py),
                          "overhead_seconds": overhead, "overhead_share_of_solve": overhead / t_cpp}))
    # The fixed cost of a call: an array in (checked, converted), an array out.
    one = np.ones((1, 3))
    calls = 20000
    t0 = time.perf_counter()
    for _ in range(calls):
        m.energy(one)
    per_call = (time.perf_counter() - t0) / calls
    print(json.dumps({"benchmark": "python_call_overhead", "case": "energy_one_row", "calls": calls,
                      "seconds_per_call": per_call}))


if __name__ == "__main__":
    main()
