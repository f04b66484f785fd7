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

from ._palpa import (  # noqa: F401
    InputError,
    Material,
    PokeResult,
    SolverError,
    __version__,
    models,
    poke,
    quantity,
    set_threads,
    threads,
)

__all__ = [
    "InputError",
    "Material",
    "PokeResult",
    "SolverError",
    "__version__",
    "models",
    "poke",
    "quantity",
    "set_threads",
    "threads",
]
