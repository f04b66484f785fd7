# SPDX-License-Identifier: AGPL-3.0-or-later
"""palpa.rest: a scene file or the same scene as a dict, the numbers of
`palpa rest`, pressure maps that carry the load, bad scenes refused."""
import json
import os
import subprocess

import numpy as np
import pytest

import palpa

SOURCE = os.environ.get("PALPA_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
PALPA = os.environ.get("PALPA_BINARY", "palpa")


def thigh():
    with open(os.path.join(SOURCE, "examples", "rest", "thigh", "scene.json")) as f:
        scene = json.load(f)
    scene["body"]["edge"] = "30 mm"  # coarse: a quick test
    return scene


def without_timings(d):
    if isinstance(d, dict):
        return {k: without_timings(v) for k, v in d.items() if "seconds" not in k and k != "scene"}
    if isinstance(d, list):
        return [without_timings(v) for v in d]
    return d


def test_rest_matches_the_command_line(tmp_path):
    scene = thigh()
    (tmp_path / "thigh.json").write_text(json.dumps(scene))
    subprocess.run([PALPA, "rest", "thigh.json", "-o", "cli"], cwd=tmp_path, check=True, capture_output=True)
    with open(tmp_path / "cli" / "summary.json") as f:
        cli = json.load(f)
    palpa.set_log_level("warning")
    r = palpa.rest(scene, out=str(tmp_path / "py"))
    f = palpa.rest(str(tmp_path / "thigh.json"))
    palpa.set_log_level("info")
    assert without_timings(r.summary) == without_timings(cli)
    np.testing.assert_array_equal(f.body_pressure, r.body_pressure)
    assert r.out == str(tmp_path / "py") and f.out is None
    # Per-vertex maps on the deformed skin and the support; each carries the load.
    assert r.body_pressure.shape == (r.skin_vertices.shape[0],)
    assert r.support_pressure.shape == (r.support_vertices.shape[0],)
    assert r.skin_faces.dtype == np.int64 and r.skin_faces.max() < r.skin_vertices.shape[0]
    load = np.linalg.norm(r.summary["load_N"])
    assert r.summary["pressure_map_force_N"]["body"] == pytest.approx(load, rel=0.05)
    assert r.body_pressure.max() == pytest.approx(r.summary["peak_pressure_Pa"]["body"], rel=1e-12)


def test_bad_scenes_are_refused_naming_the_field(tmp_path):
    scene = thigh()
    scene["body"]["edge"] = "30 kPa"
    with pytest.raises(palpa.InputError, match="edge"):
        palpa.rest(scene)
    scene = thigh()
    scene["support"] = {"pyramid": {}}
    with pytest.raises(palpa.InputError, match="pyramid"):
        palpa.rest(scene)
    with pytest.raises(palpa.InputError, match="missing.json"):
        palpa.rest(str(tmp_path / "missing.json"))
    scene = thigh()
    scene["body"]["surface"] = "nowhere.obj"
    del scene["body"]["generate"]
    with pytest.raises(palpa.InputError, match="nowhere.obj"):
        palpa.rest(scene, base=str(tmp_path))
    (tmp_path / "used").mkdir()
    (tmp_path / "used" / "x").write_text("x")
    with pytest.raises(palpa.InputError, match="not empty"):
        palpa.rest(thigh(), out=str(tmp_path / "used"))
