# SPDX-License-Identifier: AGPL-3.0-or-later
"""palpa.mesh: meshing, as `palpa mesh` does it.

    layer = palpa.mesh.layer(V, F, depth="10 mm")   # the soft tet layer on a rigid core
"""
from ._palpa import mesh_layer as layer

__all__ = ["layer"]
