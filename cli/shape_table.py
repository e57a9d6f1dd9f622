"""The shapes of a run, one row each as the scene gave them: what a trajectory's /shapes group stores.

Rows follow the bodies in order and each body's shapes in order (`World.shapes`). Points are in the
shape's own frame (its `offset` and `angle` place it on its body): a box's four corners
counter-clockwise from its lower left, a polygon's vertices as written (a concave one is one row, not
its convex pieces), a segment's two and a chain's points; circles and capsules have none (their
`radius` and `length` say it all).

/shapes/vertices is [S, V, 2], zero-padded to the longest row V. So that one long chain does not make
every row that long on disk, the dataset is chunked and only chunks holding points are written: HDF5
reads the others as their fill value, 0.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    import h5py

GROUP = "shapes"
BAND = 64  # points per column band of /shapes/vertices, and per chunk along them
CHUNK_ROWS = 8  # shapes per chunk: a long row's chunks carry little of the others' padding


@dataclass(frozen=True)
class ShapeTable:
    """Per shape: its body, type, placement on the body, size, points, material and flags."""

    body: np.ndarray  # [S] int32 row of /particles/bodies
    type: list[str]  # circle | aabb | obb | polygon | capsule | segment | chain
    offset: np.ndarray  # [S, 2] body-local position of the shape's origin
    angle: np.ndarray  # [S] body-local rotation
    radius: np.ndarray  # [S] circles and capsules, else 0
    length: np.ndarray  # [S] capsules, else 0
    points: list[np.ndarray]  # per shape [k, 2] in the shape's frame (k = 0 for circles and capsules)
    loop: np.ndarray  # [S] bool: a chain closed from its last point to its first
    material: list[str]  # the material's name ("inline" for an inline one)
    sensor: np.ndarray  # [S] bool

    @property
    def count(self) -> int:
        return len(self.type)

    @property
    def vertex_count(self) -> np.ndarray:
        """[S] int32 points of each shape."""
        return np.array([len(p) for p in self.points], dtype=np.int32)

    def body_points(self, s: int) -> np.ndarray:
        """[k, 2] the points that place shape s in its body's frame (its angle and offset applied): a
        circle's centre, the centres of a capsule's end circles, else its points."""
        if self.type[s] == "circle":
            local = np.zeros((1, 2))
        elif self.type[s] == "capsule":
            local = np.array([[-self.length[s] / 2, 0.0], [self.length[s] / 2, 0.0]])
        else:
            local = self.points[s]
        c, sin = math.cos(self.angle[s]), math.sin(self.angle[s])
        return local @ np.array([[c, sin], [-sin, c]]) + self.offset[s]


def shape_table(world: Any, materials: Sequence[str]) -> ShapeTable:
    """The table of a rustycs World's shapes; `materials` names each shape's material, in row order."""
    from rustycs.shapes import Box, Capsule, Chain, Circle, Polygon, Segment, type_name

    placed = world.shapes
    if len(materials) != len(placed):
        raise ValueError(f"{len(materials)} material names for {len(placed)} shapes")

    def points(shape: Any) -> np.ndarray:
        if isinstance(shape, Box):
            w, h = shape.width / 2, shape.height / 2
            return np.array([[-w, -h], [w, -h], [w, h], [-w, h]])
        if isinstance(shape, Polygon):
            return np.array(shape.vertices, dtype=np.float64)
        if isinstance(shape, (Segment, Chain)):
            return np.array(shape.points, dtype=np.float64)
        return np.zeros((0, 2))

    shapes = [shape for _, shape in placed]
    return ShapeTable(
        body=np.array([body for body, _ in placed], dtype=np.int32),
        type=[type_name(shape) for shape in shapes],
        offset=np.array([shape.offset for shape in shapes], dtype=np.float64).reshape(-1, 2),
        angle=np.array([shape.angle for shape in shapes], dtype=np.float64),
        radius=np.array([s.radius if isinstance(s, (Circle, Capsule)) else 0.0 for s in shapes]),
        length=np.array([s.length if isinstance(s, Capsule) else 0.0 for s in shapes]),
        points=[points(shape) for shape in shapes],
        loop=np.array([isinstance(s, Chain) and s.loop for s in shapes], dtype=bool),
        material=list(materials),
        sensor=np.array([shape.sensor for shape in shapes], dtype=bool),
    )


def write_shapes(file: h5py.File, table: ShapeTable) -> None:
    """Write /shapes (the spec's datasets, plus `loop`)."""
    import h5py

    group = file.create_group(GROUP)
    text = h5py.string_dtype()
    group.create_dataset("body", data=table.body.astype("i4"))
    group.create_dataset("type", data=np.array(table.type, dtype=object), dtype=text)
    for name, values, unit in (("offset", table.offset, "m"), ("angle", table.angle, "rad"),
                               ("radius", table.radius, "m"), ("length", table.length, "m")):
        group.create_dataset(name, data=np.asarray(values, "f8")).attrs["unit"] = unit
    counts = table.vertex_count
    group.create_dataset("vertex_count", data=counts)
    _write_vertices(group, table.points, counts)
    group.create_dataset("material", data=np.array(table.material, dtype=object), dtype=text)
    group.create_dataset("sensor", data=table.sensor.astype(bool))
    group.create_dataset("loop", data=table.loop.astype(bool))


def _bands(counts: np.ndarray, columns: int) -> list[tuple[slice, np.ndarray]]:
    """The column bands of the vertices array that hold points, each with the rows that reach into it."""
    return [(slice(start, min(start + BAND, columns)), np.flatnonzero(counts > start))
            for start in range(0, columns, BAND) if (counts > start).any()]


def _rows(rows: np.ndarray, total: int) -> slice | np.ndarray:
    """A selection of `rows`: one slice when they are all rows (h5py's fast path)."""
    return slice(None) if len(rows) == total else rows


def _write_vertices(group: h5py.Group, points: list[np.ndarray], counts: np.ndarray) -> None:
    columns = max(1, int(counts.max(initial=0)))
    chunks = (min(len(points), CHUNK_ROWS), min(columns, BAND), 2) if points else None  # no shapes, no chunks
    dataset = group.create_dataset("vertices", shape=(len(points), columns, 2), dtype="f8", fillvalue=0.0,
                                   chunks=chunks)
    dataset.attrs["unit"] = "m"
    for band, rows in _bands(counts, columns):
        block = np.zeros((len(rows), band.stop - band.start, 2))
        for k, row in enumerate(rows):
            part = points[row][band]
            block[k, :len(part)] = part
        dataset[_rows(rows, len(points)), band] = block


def read_shapes(file: h5py.File) -> ShapeTable:
    """The /shapes group of a trajectory (KeyError when the file has none)."""
    group = file[GROUP]
    counts = np.asarray(group["vertex_count"], dtype=np.int64)
    dataset = group["vertices"]
    points = [np.zeros((count, 2)) for count in counts]
    for band, rows in _bands(counts, dataset.shape[1]):
        block = dataset[_rows(rows, len(counts)), band]
        for k, row in enumerate(rows):
            used = min(counts[row] - band.start, band.stop - band.start)
            points[row][band.start:band.start + used] = block[k, :used]
    return ShapeTable(
        body=np.asarray(group["body"], dtype=np.int32),
        type=[str(t) for t in group["type"].asstr()[()]],
        offset=np.asarray(group["offset"], dtype=np.float64).reshape(-1, 2),
        angle=np.asarray(group["angle"], dtype=np.float64),
        radius=np.asarray(group["radius"], dtype=np.float64),
        length=np.asarray(group["length"], dtype=np.float64),
        points=points,
        loop=np.asarray(group["loop"], dtype=bool),
        material=[str(m) for m in group["material"].asstr()[()]],
        sensor=np.asarray(group["sensor"], dtype=bool),
    )
