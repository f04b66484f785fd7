# SPDX-License-Identifier: AGPL-3.0-or-later
"""palpa.design: the numbers of `palpa design`, the designed shape as arrays,
resume of a finished run, bad options refused."""
import copy
import importlib.util
import json
import os
import subprocess

import numpy as np
import pytest

import palpa

PALPA = os.environ.get("PALPA_BINARY", "palpa")

SOURCE = os.environ.get("PALPA_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))


def example_scene():
    """The scene of examples/python/design_short.py, shortened: 2 CG iterations."""
    spec = importlib.util.spec_from_file_location(
        "design_short", os.path.join(SOURCE, "examples", "python", "design_short.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    scene = copy.deepcopy(module.SCENE)
    scene["design"].update({"method": "cg", "iterations": 2})
    return scene


SCENE = example_scene()


def without_timings(d):
    if isinstance(d, dict):
        return {k: without_timings(v) for k, v in d.items()
                if "seconds" not in k and k not in ("scene", "iteration_per_equilibrium")}
    if isinstance(d, list):
        return [without_timings(v) for v in d]
    return d


def test_design_matches_the_command_line(tmp_path):
    (tmp_path / "scene.json").write_text(json.dumps(SCENE))
    subprocess.run([PALPA, "design", "scene.json", "-o", "cli"], cwd=tmp_path, check=True, capture_output=True)
    with open(tmp_path / "cli" / "summary.json") as f:
        cli = json.load(f)
    palpa.set_log_level("warning")
    try:
        r = palpa.design(SCENE, out=str(tmp_path / "py"))
    finally:
        palpa.set_log_level("info")
    assert without_timings(r.summary) == without_timings(cli)
    assert r.summary["termination"] == "iteration_limit"
    assert r.support_vertices.shape[1] == 3 and r.support_faces.shape[1] == 3
    V, F = palpa.read_mesh(str(tmp_path / "py" / "support.obj"))
    np.testing.assert_allclose(r.support_vertices, V, rtol=0, atol=1e-12)
    # A finished run is left as it is.
    assert palpa.design(SCENE, out=str(tmp_path / "py"), resume=True) is None


def test_bad_design_options_are_refused():
    for kwargs, message in [(dict(method="newton"), "unknown method 'newton'"), (dict(iterations=-1), "iterations"),
                            (dict(threads=-2), "threads")]:
        with pytest.raises(palpa.InputError, match=message):
            palpa.design(SCENE, **kwargs)
    scene = json.loads(json.dumps(SCENE))
    scene["design"]["method"] = "simplex"
    with pytest.raises(palpa.InputError, match="simplex"):
        palpa.design(scene)


def test_a_cohort_design_gives_each_body_and_the_one_support(tmp_path):
    """Two of the bundled cohort on one seat, from a dict: the summary's bodies
    and the one support as arrays."""
    with open(os.path.join(SOURCE, "examples", "design", "cohort", "scene.json")) as f:
        scene = json.load(f)
    scene["bodies"] = scene["bodies"][:2]
    scene["cohort"] = {"objective": "quantile", "quantile": 0.5, "baseline": False}
    palpa.set_log_level("warning")
    try:
        r = palpa.design(scene, out=str(tmp_path / "cohort"), iterations=1)
    finally:
        palpa.set_log_level("info")
    s = r.summary
    assert s["cohort"] == {"objective": "quantile", "quantile": 0.5, "bodies": 2, "start": "scene"}
    assert [b["name"] for b in s["bodies"]] == ["small", "medium"]
    assert all(b["zeta_body_ratio"] < 1.0 for b in s["bodies"])
    assert "own_designs" not in s and "baseline" not in s
    assert r.support_vertices.shape[1] == 3
    V, _ = palpa.read_mesh(str(tmp_path / "cohort" / "support.obj"))
    np.testing.assert_allclose(r.support_vertices, V, rtol=0, atol=1e-12)
