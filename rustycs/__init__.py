"""rustycs: a deterministic 2D rigid-body physics engine on a numba core.

The engine does no I/O: build a World, step it, read its arrays. See API.md.
"""

from rustycs.batch import WorldBatch
from rustycs.kernel_cache import compile_needed
from rustycs.materials import MATERIALS, Material
from rustycs.scene_files import SceneError, load_scene, open_trajectory
from rustycs.shapes import Box, Capsule, Chain, Circle, Polygon, Segment
from rustycs.world import SimulationDiverged, World

__version__ = "0.1.0"

__all__ = ["World", "WorldBatch", "Circle", "Box", "Polygon", "Capsule", "Segment", "Chain", "Material",
           "MATERIALS", "SimulationDiverged", "compile_needed", "load_scene", "open_trajectory", "SceneError",
           "__version__"]
