# SPDX-License-Identifier: AGPL-3.0-or-later
# Type stubs of the compiled part of palpa. Physical values: float in SI units
# or str with a unit ("3 mm"); arrays: numpy float64 in SI units.
from typing import Any, Sequence, Union

import numpy as np
import numpy.typing as npt

Quantity = Union[float, int, str]
ArrayLike = npt.ArrayLike

__version__: str

class InputError(ValueError): ...
class SolverError(RuntimeError): ...

def quantity(text: str, dimension: str = "") -> float:
    """The SI value of a quantity with its unit: quantity('12 kPa') -> 12000.0."""

def set_threads(n: int) -> None:
    """Threads palpa's own loops may use (0: every core)."""

def set_log_level(level: str) -> None:
    """How much palpa logs: debug, info (default), warning, error or off."""

def read_mesh(path: str, unit: Quantity = "1 m") -> tuple[npt.NDArray[np.float64], npt.NDArray[np.int64]]:
    """(V, F) of a surface or (V, T) of a tet mesh; V in metres (`unit`: one file unit)."""

def write_mesh(path: str, V: ArrayLike, cells: ArrayLike) -> None:
    """Writes triangles (m, 3) or tetrahedra (m, 4) by the file's extension; V in metres."""

def mesh_layer(
    V: ArrayLike,
    F: ArrayLike,
    *,
    depth: Union[Quantity, None] = None,
    depth_points: Union[ArrayLike, None] = None,
    depth_values: Union[ArrayLike, None] = None,
    stiffness_points: Union[ArrayLike, None] = None,
    stiffness_values: Union[ArrayLike, None] = None,
    edge: Quantity = "5 mm",
    clamp_depth: bool = False,
) -> dict[str, Any]:
    """The soft tet layer on a rigid core under a closed scan (V [m], F): V, T, attached, youngs_modulus [Pa],
    outer and core surfaces, depth per outer vertex [m]."""

def _fit(*args: Any) -> bool: ...
def _rest(*args: Any) -> dict[str, Any]: ...
def _design(*args: Any) -> Union[dict[str, Any], None]: ...
def _poke_cpp_seconds(material: Material, thickness: float, radius: float, depth: float, steps: int,
                      mesh_level: int, repeats: int) -> list[float]: ...

def threads() -> int:
    """Threads palpa's own loops may use now."""

def models() -> dict[str, dict[str, Any]]:
    """The material models: name -> summary, parameters, fittable."""

class Material:
    """A hyperelastic material: a model and its parameters (SI or strings with units)."""
    def __init__(self, model: str, **parameters: Union[Quantity, Sequence[Quantity], dict[str, ArrayLike]]) -> None: ...
    @staticmethod
    def load(path: str) -> Material:
        """Reads a material file (material.json)."""
    def save(self, path: str, method: str = ...) -> None:
        """Writes a material file atomically."""
    @property
    def model(self) -> str: ...
    @property
    def description(self) -> str: ...
    @property
    def parameters(self) -> dict[str, Any]:
        """The parameters by name, SI (Pa for moduli)."""
    def to_json(self) -> str: ...
    def small_strain(self) -> dict[str, float]:
        """E, nu, shear_modulus, bulk_modulus (Pa)."""
    def energy(self, stretches: ArrayLike) -> npt.NDArray[np.float64]:
        """Energy density [Pa] at each row of an (n, 3) array of principal stretches."""
    def stress(self, stretches: ArrayLike) -> npt.NDArray[np.float64]:
        """Principal nominal stresses dPsi/dlambda [Pa], (n, 3)."""
    def curve(self, test: str, loads: ArrayLike) -> dict[str, npt.NDArray[np.float64]]:
        """Homogeneous 'uniaxial', 'equibiaxial' or 'shear' test: load, lateral, nominal [Pa], cauchy [Pa], energy [Pa]."""

class PokeResult:
    """The curve of palpa.poke, one entry per depth (depth 0 first)."""
    @property
    def indentation(self) -> npt.NDArray[np.float64]:
        """[m]"""
    @property
    def force(self) -> npt.NDArray[np.float64]:
        """[N]"""
    @property
    def iterations(self) -> npt.NDArray[np.float64]: ...
    @property
    def substeps(self) -> npt.NDArray[np.float64]: ...
    @property
    def residual(self) -> npt.NDArray[np.float64]:
        """[N]"""
    @property
    def penetration(self) -> npt.NDArray[np.float64]:
        """[m]"""
    @property
    def min_det_f(self) -> npt.NDArray[np.float64]: ...
    @property
    def contact_nodes(self) -> npt.NDArray[np.float64]: ...
    @property
    def mesh_correction(self) -> npt.NDArray[np.float64]:
        """[N]"""
    @property
    def sensitivities(self) -> Union[npt.NDArray[np.float64], None]:
        """dF/dtheta, (n_depths, n_params) [N per SI unit]."""
    @property
    def fields(self) -> Union[list[dict[str, npt.NDArray[Any]]], None]:
        """With fields=True: per depth the deformed mesh (points, quads) and its fields."""
    parameter_names: list[str]
    newton_iterations: int

def poke(
    material: Material,
    *,
    thickness: Quantity,
    radius: Quantity,
    depth: Quantity,
    steps: int = 20,
    test: str = "indentation",
    contact: str = "",
    mesh_level: int = 2,
    extrapolate: bool = True,
    element: str = "fbar",
    fillet: Quantity = 0.0,
    outer_radius: Quantity = 0.0,
    sensitivities: bool = False,
    fields: bool = False,
) -> PokeResult:
    """A flat punch pressed into a layer (lengths in m or with units); releases the GIL."""
