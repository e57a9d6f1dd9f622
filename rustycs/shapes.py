"""The shapes a body is made of, as a user describes them.

Every shape sits on its body at a body-local `offset` and `angle` and may carry its own material (None:
the body's) and be a `sensor` (it detects overlaps, pushes nothing and adds no mass). Circles, boxes,
polygons and capsules have area, hence mass; segments and chains are lines: they give static and
kinematic bodies their outline (terrain, ramps, containers), or line a dynamic body beside shapes with
area. `rustycs.pieces` turns each shape into the convex pieces the kernels collide.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from rustycs.materials import Material

MAX_CHAIN_POINTS = 4096


@dataclass(frozen=True, kw_only=True)
class _Placed:
    """Where a shape sits on its body, what it is made of, and whether it only senses."""

    offset: tuple[float, float] = (0.0, 0.0)
    angle: float = 0.0
    material: Material | str | None = None
    sensor: bool = False

    def __post_init__(self) -> None:
        object.__setattr__(self, "offset", (float(self.offset[0]), float(self.offset[1])))
        object.__setattr__(self, "angle", float(self.angle))
        if not all(map(math.isfinite, (*self.offset, self.angle))):
            raise ValueError("a shape's offset and angle must be finite")

    @property
    def has_area(self) -> bool:
        """Whether the shape adds mass to its body (sensors and lines do not)."""
        return not self.sensor


def _points(points, what: str, least: int, most: int) -> tuple[tuple[float, float], ...]:
    found = tuple((float(x), float(y)) for x, y in points)
    if not least <= len(found) <= most:
        raise ValueError(f"a {what} has {least} to {most} points, this one has {len(found)}")
    if not all(math.isfinite(c) for p in found for c in p):
        raise ValueError(f"a {what}'s points must be finite")
    return found


@dataclass(frozen=True)
class Circle(_Placed):
    """A circle centred on its offset."""

    radius: float

    def __post_init__(self) -> None:
        super().__post_init__()
        if not (math.isfinite(self.radius) and self.radius > 0):
            raise ValueError("a circle's radius must be > 0")


@dataclass(frozen=True)
class Box(_Placed):
    """A width x height box centred on its offset. `rotates=False` makes it an aabb: its body never
    rotates, so the box stays axis-aligned (and its angle must be 0)."""

    width: float
    height: float
    rotates: bool = True

    def __post_init__(self) -> None:
        super().__post_init__()
        if not (self.width > 0 and self.height > 0 and math.isfinite(self.width * self.height)):
            raise ValueError("a box's width and height must be > 0")
        if not self.rotates and self.angle != 0.0:
            raise ValueError("an aabb never rotates, so its angle must be 0")


@dataclass(frozen=True)
class Polygon(_Placed):
    """A simple polygon of 3 to 256 vertices in the shape's frame, convex or not, either winding; it is
    collided as convex pieces of at most 8 vertices (`rustycs.polygon.convex_pieces`)."""

    vertices: tuple[tuple[float, float], ...]

    def __post_init__(self) -> None:
        from rustycs.polygon import polygon_problem

        super().__post_init__()
        object.__setattr__(self, "vertices", tuple((float(x), float(y)) for x, y in self.vertices))
        problem = polygon_problem(self.vertices)
        if problem is not None:
            raise ValueError(problem.message)


@dataclass(frozen=True)
class Capsule(_Placed):
    """Two half-discs of `radius` joined by a box: the end circles' centres are `length` apart on the
    shape's x axis, centred on its origin."""

    length: float
    radius: float

    def __post_init__(self) -> None:
        super().__post_init__()
        if not (math.isfinite(self.length) and self.length >= 0):
            raise ValueError("a capsule's length must be >= 0")
        if not (math.isfinite(self.radius) and self.radius > 0):
            raise ValueError("a capsule's radius must be > 0")


@dataclass(frozen=True)
class Segment(_Placed):
    """A line between two points: no area, no mass; it collides on both sides."""

    points: tuple[tuple[float, float], ...]

    def __post_init__(self) -> None:
        super().__post_init__()
        object.__setattr__(self, "points", _points(self.points, "segment", 2, 2))
        if math.dist(*self.points) <= 0.0:
            raise ValueError("a segment's two points must differ")

    @property
    def has_area(self) -> bool:
        return False


@dataclass(frozen=True)
class Chain(_Placed):
    """A polyline of 2 to 4096 points (closed with `loop`): no area, no mass. Bodies slide and roll
    along it without catching at the joints between its segments; it collides on both sides."""

    points: tuple[tuple[float, float], ...]
    loop: bool = False

    def __post_init__(self) -> None:
        super().__post_init__()
        points = _points(self.points, "chain", 3 if self.loop else 2, MAX_CHAIN_POINTS)
        object.__setattr__(self, "points", points)
        closing = ((points[-1], points[0]),) if self.loop else ()
        for k, (p, q) in enumerate((*zip(points, points[1:], strict=False), *closing)):
            if p == q:
                raise ValueError(f"chain points {k} and {(k + 1) % len(points)} coincide")

    @property
    def has_area(self) -> bool:
        return False


Shape = Circle | Box | Polygon | Capsule | Segment | Chain


def type_name(shape: Shape) -> str:
    """The shape's type as the scene format and the trajectory name it."""
    if isinstance(shape, Box):
        return "obb" if shape.rotates else "aabb"
    return type(shape).__name__.lower()
