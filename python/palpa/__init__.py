# SPDX-License-Identifier: AGPL-3.0-or-later
"""palpa: soft-tissue mechanics, from poking measurements to fitted nonlinear
materials to supports with low, even contact pressure.

Physical values are SI floats (m, N, Pa) or strings with a unit ("3 mm",
"12 kPa"); arrays come back as numpy float64 arrays in SI units.

    import palpa
    m = palpa.Material("neo-hookean", E="12 kPa", nu=0.45)
    r = palpa.poke(m, thickness="10 mm", radius="3 mm", depth="2 mm")
    r.indentation, r.force

Errors: palpa.InputError (a ValueError) names the file, field or argument and
what was expected; palpa.SolverError (a RuntimeError) a numerical failure;
Ctrl-C during a long call raises KeyboardInterrupt.
"""

import dataclasses
import json
import os
import pathlib
import tempfile
from typing import Any, Callable, Optional, Sequence

import numpy as np

from ._palpa import (  # noqa: F401
    InputError,
    Material,
    PokeResult,
    SolverError,
    __version__,
    _design,
    _fit,
    _rest,
    mesh_layer,
    models,
    poke,
    quantity,
    read_mesh,
    set_log_level,
    set_threads,
    threads,
    write_mesh,
)
from . import mesh  # noqa: E402  (palpa.mesh.layer)


def _in_folder(out, name, run):
    """run(folder) in `out`, or in a temporary folder removed afterwards."""
    if out is not None:
        return run(os.fspath(out))
    with tempfile.TemporaryDirectory(prefix=f"palpa-{name}-") as folder:
        return run(os.path.join(folder, name))


@dataclasses.dataclass
class FitResult:
    """What palpa.fit found: the fitted material, report.json as a dict (per-curve
    RMS errors, uncertainty, warnings, every layer-depth guess), the objective
    history of the chosen guess, and the output folder (None when the fit ran in
    a temporary one)."""

    material: Material
    report: dict
    history: dict
    out: Optional[str]

    @property
    def curves(self) -> list:
        """Per curve: name, role, RMS error of the stage-1 and fitted materials."""
        return self.report["curves"]


# The columns of an in-memory curve, by test: (x key, x CSV column, y key, y CSV column).
_CURVE_COLUMNS = {
    "indentation": ("indentation", "indentation_m", "force", "force_N"),
    "compression": ("indentation", "indentation_m", "force", "force_N"),
}


def _curve_csv(path, who, x_name, x, y_name, y):
    try:
        x = np.asarray(x, dtype=np.float64)
        y = np.asarray(y, dtype=np.float64)
    except (TypeError, ValueError) as e:
        raise InputError(f"{who}: its arrays are not numbers ({e})") from None
    if x.ndim != 1 or y.shape != x.shape:
        raise InputError(f"{who}: its arrays are not two 1-D arrays of one length "
                         f"(got shapes {x.shape} and {y.shape})")
    with open(path, "w") as f:
        f.write(f"{x_name},{y_name}\n")
        for a, b in zip(x, y):
            f.write(f"{a!r},{b!r}\n")


def _dataset_folder(dataset: dict, folder: str, base: str) -> str:
    """Writes a dataset given as a dict into `folder`: the same JSON as a dataset file,
    where a curve may hold its arrays instead of a "file" — indentation [m] and force [N]
    for indentation and compression, stretch (or shear) and stress [Pa] for homogeneous
    tests. Files it names are relative to `base`."""
    try:
        d = json.loads(json.dumps(dataset, default=lambda o: np.asarray(o).tolist()))
    except (TypeError, ValueError) as e:
        raise InputError(f"dataset: a value that is neither JSON nor an array ({e})") from None
    test = d.get("test", "indentation")
    for k, c in enumerate(d.get("curves", [])):
        if not isinstance(c, dict):
            continue
        if "file" in c:
            c["file"] = os.path.join(base, c["file"])
            continue
        name = c.get("name", f"curve{k}")
        path = os.path.join(folder, f"{k:03d}.csv")
        if test == "homogeneous":
            x_key = "shear" if "shear" in c else "stretch"
            x_col = x_key
            y_key, y_col = "stress", "stress_Pa"
        else:
            x_key, x_col, y_key, y_col = _CURVE_COLUMNS.get(test, _CURVE_COLUMNS["indentation"])
        if x_key not in c or y_key not in c:
            raise InputError(f"dataset curve {k} ('{name}'): neither a \"file\" nor arrays "
                             f"\"{x_key}\" and \"{y_key}\"")
        _curve_csv(pathlib.Path(path), f"dataset curve {k} ('{name}')", x_col, c.pop(x_key), y_col, c.pop(y_key))
        c["file"] = os.path.basename(path)
        c.setdefault("name", name)
    path = os.path.join(folder, "dataset.json")
    with open(path, "w") as f:
        json.dump(d, f, indent=2)
    return path


def fit(
    dataset,
    *,
    model: str = "spline",
    optimizer: str = "lm",
    out: Optional[str] = None,
    resume: bool = False,
    overwrite: bool = False,
    progress: Optional[Callable[[dict], Any]] = None,
    max_iterations: int = 50,
    tolerance: float = 1e-5,
    fix: Sequence[str] = (),
    nu_range: Optional[tuple] = None,
    starts: int = 0,
    ogden_terms: int = 2,
    element: str = "fbar",
    mesh_level: int = 2,
    steps: int = 20,
    depth_from: str = "small",
    smoothing: float = 0.1,
    initial: Optional[str] = None,
) -> Optional[FitResult]:
    """Fits `model` to the curves of a dataset file, exactly as `palpa fit DATASET -o OUT`
    (same options, same outputs and checkpoint in `out`; a temporary folder when
    `out` is None). `dataset` may also be the same JSON as a dict whose curves hold
    their arrays instead of files: {"indentation": [...] (m), "force": [...] (N)}, or
    for homogeneous tests {"stretch" or "shear": [...], "stress": [...] (Pa)}; files
    it names are relative to the working folder. `progress(info)` is called after every iteration with a dict
    (guess, layer_depth [m], iteration, objective, evaluations, seconds); an
    exception it raises stops the fit. Ctrl-C raises KeyboardInterrupt with the
    checkpoint kept in `out`: call again with resume=True to go on. Returns a
    FitResult, or None when a resumed fit was already finished."""
    if isinstance(dataset, dict):
        with tempfile.TemporaryDirectory(prefix="palpa-dataset-") as scratch:
            return fit(_dataset_folder(dataset, scratch, os.getcwd()), model=model, optimizer=optimizer, out=out,
                       resume=resume, overwrite=overwrite, progress=progress, max_iterations=max_iterations,
                       tolerance=tolerance, fix=fix, nu_range=nu_range, starts=starts, ogden_terms=ogden_terms,
                       element=element, mesh_level=mesh_level, steps=steps, depth_from=depth_from,
                       smoothing=smoothing, initial=initial)

    def run(folder):
        done = _fit(os.fspath(dataset), folder, model, optimizer, resume, overwrite, progress, max_iterations,
                    tolerance, list(fix), nu_range, starts, ogden_terms, element, mesh_level, steps, depth_from,
                    smoothing, None if initial is None else os.fspath(initial))
        if not done:
            return None
        with open(os.path.join(folder, "report.json")) as f:
            report = json.load(f)
        best = next(g for g in report["guesses"] if g["layer_depth_m"] == report["layer_depth_m"])
        history = {k: np.array([h[k] for h in best["history"]], dtype=float)
                   for k in ("iteration", "objective", "evaluations", "seconds")}
        return FitResult(Material.load(os.path.join(folder, "material.json")), report, history,
                         None if out is None else os.fspath(folder))
    return _in_folder(out, "fit", run)



@dataclasses.dataclass
class RestResult:
    """A body at rest on its support: pressures per vertex [Pa] on the body's skin
    and on the support (the normal traction per deformed area, what a mat would
    read), the deformed skin and the support where it is [m],
    summary.json as a dict (forces, balance, peaks, the pressure-map figures of
    each side), and the output folder (None when it ran in a temporary one)."""

    body_pressure: np.ndarray
    support_pressure: np.ndarray
    skin_vertices: np.ndarray
    skin_faces: np.ndarray
    support_vertices: np.ndarray
    support_faces: np.ndarray
    summary: dict
    out: Optional[str]


def _scene_text(scene):
    if isinstance(scene, dict):
        return json.dumps(scene), False
    return os.fspath(scene), True


def rest(scene, *, out: Optional[str] = None, overwrite: bool = False, base: Optional[str] = None) -> RestResult:
    """Rests a body on a support, exactly as `palpa rest SCENE -o OUT`. `scene` is a
    scene file or the same JSON as a dict (its relative paths then relative to
    `base`, the working folder by default). Writes the outputs to `out` (a
    temporary folder when None). Releases the GIL; Ctrl-C raises KeyboardInterrupt."""
    text, is_file = _scene_text(scene)
    where = os.path.abspath(base if base is not None else os.getcwd())

    def run(folder):
        r = _rest(text, is_file, where, folder, overwrite)
        r["summary"] = json.loads(r["summary"])
        return RestResult(out=None if out is None else folder, **r)
    return _in_folder(out, "rest", run)


@dataclasses.dataclass
class DesignResult:
    """A designed support: its shape [m], summary.json as a dict (ζ, ζ_body and the
    peak pressures before and after, both solved from scratch; the optimizer's own
    figures; history; baselines), and the output folder (None when it ran in a
    temporary one)."""

    support_vertices: np.ndarray
    support_faces: np.ndarray
    summary: dict
    out: Optional[str]


def design(scene, *, out: Optional[str] = None, resume: bool = False, overwrite: bool = False,
           baselines: bool = True, iterations: Optional[int] = None, threads: Optional[int] = None,
           method: Optional[str] = None, base: Optional[str] = None) -> Optional[DesignResult]:
    """Optimizes a support's shape, exactly as `palpa design SCENE -o OUT`: `scene` is a
    design scene file or the same JSON as a dict (relative paths relative to `base`,
    the working folder by default); `iterations`, `threads` and `method` ('lbfgs' or
    'cg') override the scene's. Ctrl-C raises KeyboardInterrupt with the checkpoint
    kept in `out`; resume=True goes on from it. Returns None when a resumed run was
    already finished."""
    text, is_file = _scene_text(scene)
    where = os.path.abspath(base if base is not None else os.getcwd())

    def run(folder):
        r = _design(text, is_file, where, folder, resume, overwrite, baselines, iterations, threads, method)
        if r is None:
            return None
        r["summary"] = json.loads(r["summary"])
        return DesignResult(out=None if out is None else folder, **r)
    return _in_folder(out, "design", run)


__all__ = [
    "DesignResult",
    "FitResult",
    "InputError",
    "Material",
    "PokeResult",
    "RestResult",
    "SolverError",
    "__version__",
    "design",
    "fit",
    "mesh",
    "mesh_layer",
    "models",
    "poke",
    "quantity",
    "read_mesh",
    "rest",
    "set_log_level",
    "set_threads",
    "threads",
    "write_mesh",
]
