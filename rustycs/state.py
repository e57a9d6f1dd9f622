"""The world's state as the kernels read it: a row per body and a row per shape piece.

Both tables are structure-of-arrays records (`typing.NamedTuple`s of numpy arrays), so a kernel takes
one argument per concern and names every column it reads. The World owns the arrays and grows them by
doubling as bodies are added; the kernels get views of the rows in use.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from rustycs.pieces import MAX_VERTICES


class Bodies(NamedTuple):
    """Per body: pose and velocities of the centre of mass, mass properties, type and flags."""

    x: np.ndarray  # (N, 2) centre of mass, m
    angle: np.ndarray  # (N,) unwrapped, rad
    v: np.ndarray  # (N, 2) centre-of-mass velocity, m/s
    w: np.ndarray  # (N,) angular velocity, rad/s
    mass: np.ndarray  # (N,) kg; inf for static and kinematic bodies
    inertia: np.ndarray  # (N,) kg m^2 about the centre of mass; inf where the body cannot rotate
    inv_mass: np.ndarray  # (N,) 0 for bodies forces and contacts do not move
    inv_inertia: np.ndarray  # (N,) 0 also for fixed rotation
    body_type: np.ndarray  # (N,) int64: body_types.STATIC, DYNAMIC or KINEMATIC
    active: np.ndarray  # (N,) bool: false once the body left the bounds
    origin: np.ndarray  # (N, 2) the body origin relative to the centre of mass, body frame
    linear_damping: np.ndarray  # (N,) 1/s
    angular_damping: np.ndarray  # (N,) 1/s
    gravity_scale: np.ndarray  # (N,) times the world force
    fixed_rotation: np.ndarray  # (N,) bool: never rotates (an aabb's body, or asked for)
    bullet: np.ndarray  # (N,) bool: continuous collision against dynamic bodies too
    extent: np.ndarray  # (N,) m: the farthest point of its shapes' cores from the centre of mass
    first_shape: np.ndarray  # (N,) int64 row of the body's first shape in Shapes
    shape_count: np.ndarray  # (N,) int64 rows of its shapes, consecutive
    asleep: np.ndarray  # (N,) bool: its island sleeps (`rustycs.sleep`): frozen, skipped, still colliding
    sleep_time: np.ndarray  # (N,) s it has rested
    island: np.ndarray  # (N,) int64 while asleep: the root row of its island


class Shapes(NamedTuple):
    """Per convex piece of a body's shapes (pieces of one body are consecutive rows)."""

    body: np.ndarray  # (S,) int64 row in Bodies
    kind: np.ndarray  # (S,) int64: pieces.CIRCLE, BOX, POLYGON, CAPSULE, SEGMENT or CHAIN_SEGMENT
    radius: np.ndarray  # (S,) m: circle, capsule
    count: np.ndarray  # (S,) int64 vertices in use (0 for a circle)
    vertices: np.ndarray  # (S, MAX_VERTICES, 2) body frame about the centre of mass, counter-clockwise
    normals: np.ndarray  # (S, MAX_VERTICES, 2) outward unit normal of edge k -> k + 1
    centroid: np.ndarray  # (S, 2) body frame about the centre of mass (a circle's centre)
    ghosts: np.ndarray  # (S, 2, 2) chain segments: the chain's points before and after
    open_ends: np.ndarray  # (S,) int64 bits: pieces.OPEN_START, OPEN_END
    friction: np.ndarray  # (S,)
    restitution: np.ndarray  # (S,)
    sensor: np.ndarray  # (S,) bool: detects overlaps, never collides
    group: np.ndarray  # (S,) int64: the same non-zero group never collides
    category: np.ndarray  # (S,) int64 bits
    mask: np.ndarray  # (S,) int64 bits: the categories it collides with


# trailing shape and dtype of every column
BODY_COLUMNS = {"x": ((2,), np.float64), "angle": ((), np.float64), "v": ((2,), np.float64),
             "w": ((), np.float64), "mass": ((), np.float64), "inertia": ((), np.float64),
             "inv_mass": ((), np.float64), "inv_inertia": ((), np.float64), "body_type": ((), np.int64),
             "active": ((), np.bool_), "origin": ((2,), np.float64), "linear_damping": ((), np.float64),
             "angular_damping": ((), np.float64), "gravity_scale": ((), np.float64),
             "fixed_rotation": ((), np.bool_), "bullet": ((), np.bool_), "extent": ((), np.float64),
             "first_shape": ((), np.int64), "shape_count": ((), np.int64), "asleep": ((), np.bool_),
             "sleep_time": ((), np.float64), "island": ((), np.int64)}
SHAPE_COLUMNS = {"body": ((), np.int64), "kind": ((), np.int64), "radius": ((), np.float64),
             "count": ((), np.int64), "vertices": ((MAX_VERTICES, 2), np.float64),
             "normals": ((MAX_VERTICES, 2), np.float64), "centroid": ((2,), np.float64),
             "ghosts": ((2, 2), np.float64), "open_ends": ((), np.int64), "friction": ((), np.float64),
             "restitution": ((), np.float64), "sensor": ((), np.bool_), "group": ((), np.int64),
             "category": ((), np.int64), "mask": ((), np.int64)}


class Table:
    """Rows of a record type, appended one by one, stored in arrays that double when full."""

    def __init__(self, record: type, columns: dict[str, tuple[tuple[int, ...], type]]):
        self.record = record
        self.rows = 0
        self.columns = {name: np.zeros((0, *shape), dtype) for name, (shape, dtype) in columns.items()}

    def append(self, **values) -> int:
        """Add a row (columns left out are zero) and return its index."""
        if self.rows == len(next(iter(self.columns.values()))):
            capacity = max(8, 2 * self.rows)
            for name, array in self.columns.items():
                grown = np.zeros((capacity, *array.shape[1:]), array.dtype)
                grown[: self.rows] = array[: self.rows]
                self.columns[name] = grown
        row = self.rows
        for name, value in values.items():
            self.columns[name][row] = value
        self.rows += 1
        return row

    def view(self):
        """The record of the rows in use (views: the kernels write the world's own arrays)."""
        return self.record(**{name: array[: self.rows] for name, array in self.columns.items()})
