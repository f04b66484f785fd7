# SPDX-License-Identifier: AGPL-3.0-or-later
"""palpa.poke: the same numbers as `palpa poke`, the GIL released during the
solve, Ctrl-C honoured, memory flat over many calls."""
import csv
import os
import resource
import signal
import subprocess
import threading
import time

import numpy as np
import pytest

import palpa

PALPA = os.environ.get("PALPA_BINARY", "palpa")


def tissue():
    return palpa.Material("neo-hookean-volume", E="10 kPa", nu=0.45)


def test_poke_matches_the_command_line_exactly(tmp_path):
    m = tissue()
    m.save(str(tmp_path / "m.json"))
    r = palpa.poke(m, thickness="10 mm", radius="3 mm", depth="2 mm", steps=4, mesh_level=1, sensitivities=True)
    subprocess.run([PALPA, "poke", "--material", "m.json", "--thickness", "10mm", "--radius", "3mm", "--depth", "2mm",
                    "--steps", "4", "--mesh-level", "1", "-o", "curve.csv", "--sensitivities", "sens.csv"],
                   cwd=tmp_path, check=True, capture_output=True)
    with open(tmp_path / "curve.csv") as f:
        rows = [row for row in csv.DictReader(line for line in f if not line.startswith("#"))]
    np.testing.assert_allclose(r.indentation, [float(row["indentation_m"]) for row in rows], rtol=1e-12, atol=0)
    np.testing.assert_allclose(r.force, [float(row["force_N"]) for row in rows], rtol=1e-12, atol=0)
    assert r.indentation.shape == (5,) and r.force[0] == 0.0 and np.all(np.diff(r.force) > 0)
    assert r.sensitivities.shape == (5, 3)
    assert r.parameter_names == ["E", "nu", "volume_share"]
    with open(tmp_path / "sens.csv") as f:
        sens = [row for row in csv.DictReader(line for line in f if not line.startswith("#"))]
    np.testing.assert_allclose(r.sensitivities[:, 0], [float(row["dF/dE"]) for row in sens], rtol=1e-12, atol=0)
    np.testing.assert_allclose(r.sensitivities[:, 2], [float(row["dF/dvolume-share"]) for row in sens], rtol=1e-12,
                               atol=0)


def test_deformed_mesh_fields_on_request():
    m = tissue()
    r = palpa.poke(m, thickness="10 mm", radius="3 mm", depth="1 mm", steps=2, mesh_level=0, fields=True)
    assert palpa.poke(m, thickness="10 mm", radius="3 mm", depth="1 mm", steps=2, mesh_level=0).fields is None
    last = r.fields[-1]
    assert last["points"].shape[1] == 3 and last["quads"].shape[1] == 4
    assert last["quads"].max() < last["points"].shape[0]
    # The punch pushed the surface under it down by the indentation.
    under = (last["points"][:, 0] < 1e-3) & (last["points"][:, 1] > 10e-3 - 1e-9)
    np.testing.assert_allclose(last["displacement_m"][under, 1], -1e-3, rtol=1e-3)
    assert last["det_F"].shape == (last["quads"].shape[0],)
    assert np.all(last["det_F"] > 0)


def test_compression_and_bad_geometry():
    m = tissue()
    c = palpa.poke(m, test="compression", thickness="30 mm", radius="15 mm", depth="3 mm", steps=3, mesh_level=0)
    assert c.force[-1] > 0
    for kwargs, message in [
        (dict(thickness="-10 mm", radius="3 mm", depth="2 mm"), "positive"),
        (dict(thickness="10 mm", radius="3 kPa", depth="2 mm"), "not a length"),
        (dict(thickness="10 mm", radius="3 mm", depth="2 mm", steps=0), "steps"),
        (dict(thickness="10 mm", radius="3 mm", depth="2 mm", contact="glued"), "glued"),
    ]:
        with pytest.raises(palpa.InputError, match=message):
            palpa.poke(m, **kwargs)
    with pytest.raises(TypeError):
        palpa.poke(None, thickness="10 mm", radius="3 mm", depth="2 mm")


def test_the_gil_is_released_during_a_poke():
    m = tissue()
    ticks = []
    done = threading.Event()

    def count():
        while not done.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    t = threading.Thread(target=count)
    t.start()
    start = time.perf_counter()
    palpa.poke(m, thickness="10 mm", radius="3 mm", depth="2 mm", steps=10, mesh_level=2)
    end = time.perf_counter()
    done.set()
    t.join()
    during = [x for x in ticks if start < x < end]
    # The other thread ran all along: ticks at least every 50 ms of the solve.
    assert end - start > 0.05
    assert len(during) >= (end - start) / 0.05, (len(during), end - start)


def test_ctrl_c_raises_keyboard_interrupt():
    m = tissue()
    main = threading.get_ident()
    timer = threading.Timer(0.2, lambda: signal.pthread_kill(main, signal.SIGINT))
    timer.start()
    start = time.perf_counter()
    with pytest.raises(KeyboardInterrupt):
        palpa.poke(m, thickness="10 mm", radius="3 mm", depth="6 mm", steps=400, mesh_level=4)
    timer.join()
    assert time.perf_counter() - start < 5.0
    # The module works on afterwards.
    r = palpa.poke(m, thickness="10 mm", radius="3 mm", depth="1 mm", steps=2, mesh_level=0)
    assert r.force[-1] > 0


def test_many_small_pokes_keep_memory_flat():
    m = tissue()

    def run(n):
        for _ in range(n):
            palpa.poke(m, thickness="10 mm", radius="3 mm", depth="0.5 mm", steps=1, mesh_level=0)

    run(100)  # warm up allocators and caches
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    run(1000)
    after = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    assert after - before < 20_000, (before, after)  # kB


def test_pokes_from_several_threads_at_once_leave_ctrl_c_to_python():
    m = tissue()
    results = []

    def run():
        results.append(palpa.poke(m, thickness="10 mm", radius="3 mm", depth="1 mm", steps=3, mesh_level=1).force[-1])

    threads = [threading.Thread(target=run) for _ in range(3)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert len(results) == 3 and len(set(results)) == 1
    # Python's own handler is back: Ctrl-C between calls raises KeyboardInterrupt at once.
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    with pytest.raises(KeyboardInterrupt):
        signal.raise_signal(signal.SIGINT)
        time.sleep(1)
