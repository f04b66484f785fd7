# SPDX-License-Identifier: AGPL-3.0-or-later
"""palpa.fit and the mesh round trips: the same results as `palpa fit`, a
progress callback, Ctrl-C leaving a checkpoint to resume from, and meshes
that come back exactly."""
import json
import os
import signal
import subprocess
import sys
import threading

import numpy as np
import pytest

import palpa

SOURCE = os.environ.get("PALPA_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
PALPA = os.environ.get("PALPA_BINARY", "palpa")
ECOFLEX = os.path.join(SOURCE, "examples", "fit", "ecoflex30", "dataset-homogeneous.json")
FOAM = os.path.join(SOURCE, "examples", "fit", "foam", "dataset.json")


def test_fit_matches_the_command_line(tmp_path):
    seen = []
    r = palpa.fit(ECOFLEX, model="yeoh", out=str(tmp_path / "py"), progress=seen.append)
    subprocess.run([PALPA, "fit", ECOFLEX, "--model", "yeoh", "-o", str(tmp_path / "cli")], check=True,
                   capture_output=True)
    cli = palpa.Material.load(str(tmp_path / "cli" / "material.json"))
    assert r.material.model == "yeoh"
    for k, v in cli.parameters.items():
        assert r.material.parameters[k] == pytest.approx(v, rel=1e-12, abs=0)
    with open(tmp_path / "cli" / "report.json") as f:
        report = json.load(f)
    assert r.report["rms_error"] == report["rms_error"]
    assert [c["name"] for c in r.curves] == [c["name"] for c in report["curves"]]
    assert r.history["objective"][-1] <= r.history["objective"][0]
    assert seen and {"guess", "iteration", "objective", "layer_depth"} <= set(seen[-1])
    # Without a folder: a temporary one, the same material.
    again = palpa.fit(ECOFLEX, model="yeoh")
    assert again.out is None and again.material.parameters == r.material.parameters
    # Resuming the finished fit does nothing.
    assert palpa.fit(ECOFLEX, model="yeoh", out=str(tmp_path / "py"), resume=True) is None


def test_fit_bad_input_and_a_failing_callback(tmp_path):
    with pytest.raises(palpa.InputError, match="unknown model 'rubber'"):
        palpa.fit(ECOFLEX, model="rubber")
    with pytest.raises(palpa.InputError, match="cannot be fitted"):
        palpa.fit(ECOFLEX, model="stvk")
    with pytest.raises(palpa.InputError, match="missing.json"):
        palpa.fit(str(tmp_path / "missing.json"))
    with pytest.raises(palpa.InputError, match="nu_range"):
        palpa.fit(ECOFLEX, model="yeoh", nu_range=(0.4, 0.6))
    # The command line's ranges, NaN outside every one of them.
    for keyword, value in [("starts", -1), ("smoothing", -1.0), ("tolerance", float("nan")),
                           ("smoothing", float("inf")), ("mesh_level", 8), ("steps", 1)]:
        with pytest.raises(palpa.InputError, match=keyword):
            palpa.fit(ECOFLEX, model="yeoh", out=str(tmp_path / "ranges"), **{keyword: value})
        assert not os.path.exists(tmp_path / "ranges")
    with pytest.raises(palpa.InputError, match="0 \\(all cores\\) to 4096"):
        palpa.set_threads(10**6)
    (tmp_path / "used").mkdir()
    (tmp_path / "used" / "x.txt").write_text("x")
    with pytest.raises(palpa.InputError, match="not empty"):
        palpa.fit(ECOFLEX, model="yeoh", out=str(tmp_path / "used"))

    def boom(info):
        raise ZeroDivisionError("stop here")

    with pytest.raises(ZeroDivisionError, match="stop here"):
        palpa.fit(ECOFLEX, model="ogden", out=str(tmp_path / "boom"), progress=boom)


def test_ctrl_c_during_a_fit_keeps_a_checkpoint_to_resume(tmp_path):
    out = str(tmp_path / "foam")
    main = threading.get_ident()
    sent = threading.Event()

    def interrupt(info):
        if info["iteration"] >= 1 and not sent.is_set():
            sent.set()
            threading.Thread(target=lambda: signal.pthread_kill(main, signal.SIGINT)).start()

    with pytest.raises(KeyboardInterrupt):
        palpa.fit(FOAM, model="neo-hookean", out=out, progress=interrupt, mesh_level=1, steps=8)
    with open(os.path.join(out, "checkpoint.json")) as f:
        checkpoint = json.load(f)
    assert checkpoint["kind"] == "fit"
    assert not os.path.exists(os.path.join(out, "report.json"))
    r = palpa.fit(FOAM, model="neo-hookean", out=out, resume=True, mesh_level=1, steps=8)
    assert r is not None and r.material.small_strain()["E"] > 0


def test_meshes_round_trip(tmp_path):
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float64)
    F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]], dtype=np.int32)  # int32 faces are fine
    for name in ("t.obj", "t.ply", "t.off", "t.stl"):
        palpa.write_mesh(str(tmp_path / name), V, F)
        V2, F2 = palpa.read_mesh(str(tmp_path / name))
        assert V2.dtype == np.float64 and F2.dtype == np.int64
        assert V2.shape == (4, 3) and F2.shape == (4, 3)
    V2, F2 = palpa.read_mesh(str(tmp_path / "t.obj"))
    np.testing.assert_array_equal(V2, V)
    palpa.write_mesh(tmp_path / "path.obj", V, F)  # a pathlib.Path as well as a str
    np.testing.assert_array_equal(palpa.read_mesh(tmp_path / "path.obj")[1], F)
    np.testing.assert_array_equal(F2, F)
    T = np.array([[0, 1, 2, 3]])
    palpa.write_mesh(str(tmp_path / "t.vtu"), V.astype(np.float32), T)
    V3, T3 = palpa.read_mesh(str(tmp_path / "t.vtu"), unit="1 mm")
    np.testing.assert_array_equal(V3, V * 1e-3)
    np.testing.assert_array_equal(T3, T)
    for cells, message in [(np.array([[0, 1, 9]]), "indices from 0 to 3"), (np.array([[0, 1]]), "triangles"),
                           (np.array([[0.0, 1.0, 2.0]]), "integer")]:
        with pytest.raises((palpa.InputError, TypeError), match=message):
            palpa.write_mesh(str(tmp_path / "bad.obj"), V, cells)
    assert not os.path.exists(tmp_path / "bad.obj")
    with pytest.raises(palpa.InputError, match="nope.xyz"):
        palpa.read_mesh(str(tmp_path / "nope.xyz"))


def test_an_array_too_large_to_copy_raises_memory_error(tmp_path):
    # A broadcast view of 10⁹ rows takes no memory; its float64 copy would take
    # 24 GB, beyond the address space the child process is held to.
    code = """
import resource, sys
import numpy as np
import palpa
resource.setrlimit(resource.RLIMIT_AS, (4 << 30, 4 << 30))
V = np.broadcast_to(np.zeros(3), (10**9, 3))
try:
    palpa.write_mesh(sys.argv[1], V, np.array([[0, 1, 2]]))
except MemoryError:
    print("MemoryError")
"""
    r = subprocess.run([sys.executable, "-c", code, str(tmp_path / "big.obj")], capture_output=True, text=True,
                       env=os.environ, timeout=120)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == "MemoryError"
    assert not os.path.exists(tmp_path / "big.obj")


def test_mesh_layer_from_arrays():
    # An icosphere-like closed surface: a generated one from the rest example is simplest.
    t = np.linspace(0, np.pi, 13)[1:-1]
    p = np.linspace(0, 2 * np.pi, 24, endpoint=False)
    r = 0.05
    rings = [np.column_stack([r * np.sin(a) * np.cos(p), r * np.sin(a) * np.sin(p), np.full(24, r * np.cos(a))])
             for a in t]
    V = np.vstack([[0, 0, r]] + rings + [[0, 0, -r]])
    F = []
    for j in range(24):
        F.append([0, 1 + j, 1 + (j + 1) % 24])
    for i in range(len(t) - 1):
        for j in range(24):
            a, b = 1 + i * 24 + j, 1 + i * 24 + (j + 1) % 24
            F += [[a, a + 24, b], [b, a + 24, b + 24]]
    last = len(V) - 1
    for j in range(24):
        a, b = 1 + (len(t) - 1) * 24 + j, 1 + (len(t) - 1) * 24 + (j + 1) % 24
        F.append([a, last, b])
    F = np.array(F)
    layer = palpa.mesh.layer(V, F, depth="10 mm", edge="8 mm")
    assert layer["T"].shape[1] == 4 and layer["T"].max() < layer["V"].shape[0]
    assert layer["attached"].size > 0 and layer["youngs_modulus"] is None
    core_radius = np.linalg.norm(layer["core_vertices"], axis=1)
    assert core_radius.mean() == pytest.approx(0.04, rel=0.1)
    far = V[[0, len(V) - 1, 1 + 5 * 24, 1 + 5 * 24 + 12]]  # poles and two opposite equator points
    stiff = palpa.mesh_layer(V, F, depth="10 mm", edge="8 mm", stiffness_points=far, stiffness_values=[2e4] * 4)
    np.testing.assert_allclose(stiff["youngs_modulus"], 2e4)
    with pytest.raises(palpa.InputError, match="no layer depth"):
        palpa.mesh_layer(V, F)
    with pytest.raises(palpa.InputError, match="one value per point"):
        palpa.mesh_layer(V, F, depth_points=V[:3], depth_values=[0.01, 0.01])


def read_curve(path):
    with open(path) as f:
        rows = [line.strip().split(",") for line in f if not line.startswith("#")]
    head, data = rows[0], np.array([[float(x) for x in row] for row in rows[1:]])
    scale = {"stress_Pa": 1.0, "stress_kPa": 1e3, "stress_MPa": 1e6}[head[1]]
    return data[:, 0], data[:, 1] * scale


def test_fit_in_memory_curves_matches_the_files():
    folder = os.path.dirname(ECOFLEX)
    curves = []
    for name, role in (("EF30_0T_A1_stress", "train"), ("EF30_0T_A2_stress", "train"),
                       ("EF30_0T_B1_stress", "validate")):
        stretch, stress = read_curve(os.path.join(folder, name + ".csv"))
        curves.append({"name": name, "stretch": stretch, "stress": stress, "load_case": "uniaxial", "role": role})
    dataset = {"palpa_dataset": 1, "test": "homogeneous", "poisson": 0.49, "curves": curves}
    memory = palpa.fit(dataset, model="yeoh")
    files = palpa.fit(ECOFLEX, model="yeoh")
    for k, v in files.material.parameters.items():
        assert memory.material.parameters[k] == pytest.approx(v, rel=1e-9), k
    assert [c["name"] for c in memory.curves] == [c["name"] for c in files.curves]
    bad = {"palpa_dataset": 1, "test": "homogeneous", "curves": [{"stretch": [1.0, 1.1], "role": "train"}]}
    with pytest.raises(palpa.InputError, match="neither a \"file\" nor arrays"):
        palpa.fit(bad, model="yeoh")
    bad["curves"][0]["stress"] = [0.0, 1.0, 2.0]
    with pytest.raises(palpa.InputError, match="curve 0 .* one length"):
        palpa.fit(bad, model="yeoh")
    # Values that are no numbers, and no JSON at all: named by curve or dataset.
    bad["curves"][0]["stress"] = ["zero", "one"]
    with pytest.raises(palpa.InputError, match="dataset curve 0 \\('curve0'\\): its arrays are not numbers"):
        palpa.fit(bad, model="yeoh")
    bad["curves"][0]["stress"] = [0.0, 1.0]
    bad["notes"] = object()
    with pytest.raises(palpa.InputError, match="dataset: a value that is neither JSON nor an array"):
        palpa.fit(bad, model="yeoh")
