"""Every limit of the application in one place: what a scene, a sweep or a run may ask for.

Each limit keeps numbers inside the range the engine computes correctly (sizes, masses and rates whose
products and inverses stay finite in float64), and keeps the work, memory and disk a command can be asked
for bounded, so that hostile or mistaken input is refused before any work starts with the limit named
rather than running out of memory or disk. Messages and the JSON Schema name these constants; so does
docs/limits.md, which explains them.
"""

from __future__ import annotations

from dataclasses import dataclass

from rustycs.defaults import MAX_PRECISION
from rustycs.polygon import MAX_POLYGON_VERTICES
from rustycs.shapes import MAX_CHAIN_POINTS


@dataclass(frozen=True)
class Limit:
    """A named bound: `name` is how messages, the schema and docs/limits.md refer to it."""

    name: str
    value: float | int
    unit: str = ""

    def __str__(self) -> str:
        value = f"{self.value:g}" if isinstance(self.value, float) else str(self.value)
        return f"{value}{' ' + self.unit if self.unit else ''} ({self.name}, see docs/limits.md)"


# ---------------------------------------------------------------------------------- numbers in a scene
MIN_LENGTH = Limit("MIN_LENGTH", 1e-6, "m")  # sizes: radius, width, height, spacing, min_distance
MAX_LENGTH = Limit("MAX_LENGTH", 1e6, "m")
MAX_COORDINATE = Limit("MAX_COORDINATE", 1e9, "m")  # |x|, |y| of positions, offsets, regions, bounds
MAX_SPEED = Limit("MAX_SPEED", 1e6, "m/s")
MAX_ANGLE = Limit("MAX_ANGLE", 1e6, "rad")
MAX_ANGULAR_SPEED = Limit("MAX_ANGULAR_SPEED", 1e6, "rad/s")
MAX_ACCELERATION = Limit("MAX_ACCELERATION", 1e9, "m/s^2")
MIN_MASS = Limit("MIN_MASS", 1e-9, "kg")
MAX_MASS = Limit("MAX_MASS", 1e30, "kg")
MIN_DENSITY = Limit("MIN_DENSITY", 1e-6, "kg/m^2")
MAX_DENSITY = Limit("MAX_DENSITY", 1e6, "kg/m^2")
MAX_FRICTION = Limit("MAX_FRICTION", 1e3)
MAX_FACTOR = Limit("MAX_FACTOR", 1e6)  # gravity_scale, the gravitational constant
MAX_DAMPING = Limit("MAX_DAMPING", 1e6, "1/s")
MIN_TICK_RATE = Limit("MIN_TICK_RATE", 1e-3, "Hz")
MAX_TICK_RATE = Limit("MAX_TICK_RATE", 1e6, "Hz")
MAX_TICKS = Limit("MAX_TICKS", 10**9)  # ticks of one run, and the recording interval `every`
MAX_SLEEP_TIME = Limit("MAX_SLEEP_TIME", 1e9, "s")  # world.sleep_time (> 0): about 30 years
PRECISION = Limit("MAX_PRECISION", MAX_PRECISION)  # solver substeps per tick
MAX_SEED = Limit("MAX_SEED", 2**63 - 1)  # stored as a signed 64-bit HDF5 attribute
MAX_GROUP = Limit("MAX_GROUP", 2**31 - 1)  # collision_group, stored as int32
MAX_BITS = Limit("MAX_BITS", 2**63 - 1)  # collision category and mask, int64 in the engine

# ---------------------------------------------------------------------------------- sizes of inputs
MAX_BODIES = Limit("MAX_BODIES", 1_000_000)  # bodies of one scene, listed and generated together
MAX_SHAPES = Limit("MAX_SHAPES", 1_000_000)  # shapes of all the bodies of one scene
POLYGON_VERTICES = Limit("MAX_POLYGON_VERTICES", MAX_POLYGON_VERTICES)
CHAIN_POINTS = Limit("MAX_CHAIN_POINTS", MAX_CHAIN_POINTS)
MAX_LIST_ITEMS = Limit("MAX_LIST_ITEMS", 10_000)  # forces, attractors, materials, generators, choices
MAX_NAME_LENGTH = Limit("MAX_NAME_LENGTH", 100, "characters")
MAX_TEXT_LENGTH = Limit("MAX_TEXT_LENGTH", 100_000, "characters")  # a scene's description
MAX_SCENE_BYTES = Limit("MAX_SCENE_BYTES", 32 * 2**20, "bytes")  # a scene file
MAX_YAML_DEPTH = Limit("MAX_YAML_DEPTH", 64, "levels")  # nesting of YAML collections
MAX_YAML_VALUES = Limit("MAX_YAML_VALUES", 10_000_000, "values")  # a document with its aliases expanded
MAX_VARIANTS = Limit("MAX_VARIANTS", 10_000)  # variants of one sweep

MAX_VIEW = Limit("MAX_VIEW", 1e12, "m")  # |x|, |y| of a rendered view

# ---------------------------------------------------------------------------------- runs
DISK_MARGIN_BYTES = 64 * 2**20  # a run must leave this much free beyond its estimated output
STOP_SECONDS = 0.25  # the engine is called for about this long at most, so a stop request is quick
