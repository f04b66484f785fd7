#!/usr/bin/env python3
# SPDX-License-Identifier: AGPL-3.0-or-later
"""Poke a tissue layer with a flat punch and plot the force-indentation curve.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/poke_and_plot.py --out poke

Writes poke.csv (and poke.png when matplotlib is installed) into --out. Checks
that the layer is stiffer than a half-space at small indentation (a thin layer
on a rigid base: Hayes' correction) and that the force grows with depth."""
import argparse
import os

import numpy as np

import palpa


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="poke-python")
    ap.add_argument("--small", action="store_true", help="a coarse mesh and few steps (for tests)")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    palpa.set_log_level("warning")
    tissue = palpa.Material("neo-hookean-volume", E="10 kPa", nu=0.45)
    radius, thickness = 3e-3, 10e-3
    r = palpa.poke(tissue, thickness=thickness, radius=radius, depth="2 mm", steps=4 if a.small else 20,
                   mesh_level=1 if a.small else 2, sensitivities=True)
    np.savetxt(os.path.join(a.out, "poke.csv"), np.column_stack([r.indentation, r.force]), delimiter=",",
               header="indentation_m,force_N", comments="")
    # Sneddon's half-space stiffness 2 a E / (1 - nu^2); a layer on a rigid base is stiffer.
    small = tissue.small_strain()
    half_space = 2 * radius * small["E"] / (1 - small["nu"] ** 2)
    ratio = (r.force[1] / r.indentation[1]) / half_space
    print(f"force at {r.indentation[-1] * 1e3:.1f} mm: {r.force[-1]:.4f} N; initial stiffness {ratio:.3f} x the "
          f"half-space's; dF/dE at the deepest point {r.sensitivities[-1, 0]:.3e} N/Pa")
    assert 1.0 < ratio < 2.0, ratio
    assert np.all(np.diff(r.force) > 0)
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib is not installed: no plot (apt-get install python3-matplotlib)")
        return
    fig, ax = plt.subplots()
    ax.plot(r.indentation * 1e3, r.force, "o-")
    ax.set_xlabel("indentation [mm]")
    ax.set_ylabel("force [N]")
    ax.set_title("3 mm punch, 10 mm layer, E = 10 kPa")
    fig.savefig(os.path.join(a.out, "poke.png"), dpi=120)


if __name__ == "__main__":
    main()
