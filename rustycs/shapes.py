"""Shapes and their mass properties.

Boxes and polygons are stored as convex polygons of at most MAX_VERTICES counter-clockwise vertices
about the centre of mass; a circle is a radius. Mass properties are exact closed forms: the area
centroid is the centre of mass (not the vertex average), and the inertia is the area moment about it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

MAX_VERTICES = 8

CIRCLE, AABB, OBB, POLYGON = 0, 1, 2, 3
KIND_NAMES = ("circle", "aabb", "obb", "polygon")


@dataclass(frozen=True)
class Circle:
    radius: float


@dataclass(frozen=True)
class Box:
    """A width x height box centred on the body origin; `rotates=False` makes it an aabb."""

    width: float
    height: float
    rotates: bool = True


@dataclass(frozen=True)
class Polygon:
    """A convex polygon, vertices body-local about the body origin, either winding."""

    vertices: tuple[tuple[float, float], ...]

    def __init__(self, vertices) -> None:
        object.__setattr__(self, "vertices", tuple((float(x), float(y)) for x, y in vertices))


Shape = Circle | Box | Polygon


@dataclass(frozen=True)
class MassProperties:
    """Per unit density: area, centroid (body-local) and inertia about the centroid.

    `vertices` are counter-clockwise and relative to the centroid (empty for circles).
    """

    kind: int
    area: float
    centroid: np.ndarray
    unit_inertia: float
    radius: float
    vertices: np.ndarray


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def convex_polygon(points) -> np.ndarray:
    """Validate a convex polygon and return its vertices counter-clockwise (raises ValueError)."""
    p = np.asarray(points, dtype=np.float64)
    if p.ndim != 2 or p.shape[1] != 2 or not 3 <= len(p) <= MAX_VERTICES:
        raise ValueError(f"a polygon needs 3 to {MAX_VERTICES} vertices, got {len(p)}")
    if not np.all(np.isfinite(p)):
        raise ValueError("polygon vertices must be finite")
    edges = np.roll(p, -1, axis=0) - p
    turns = _cross(edges, np.roll(edges, -1, axis=0))
    scale = max(float(np.max(np.abs(p - p.mean(axis=0)))), 1e-300)
    tol = 1e-12 * scale * scale
    if np.all(turns > tol):
        ccw = p
    elif np.all(turns < -tol):
        ccw = p[::-1].copy()
    else:
        raise ValueError("polygon must be convex with no repeated or collinear vertices")
    centred = ccw - ccw.mean(axis=0)
    winding = np.sum(np.arctan2(_cross(centred, np.roll(centred, -1, axis=0)),
                                np.sum(centred * np.roll(centred, -1, axis=0), axis=1)))
    if abs(winding - 2 * np.pi) > 1e-6:
        raise ValueError("polygon must not intersect itself")
    return ccw


def mass_properties(shape: Shape) -> MassProperties:
    """Area, centroid and inertia of a shape at unit density."""
    if isinstance(shape, Circle):
        r = float(shape.radius)
        if not r > 0:
            raise ValueError("circle radius must be > 0")
        area = np.pi * r * r
        return MassProperties(CIRCLE, area, np.zeros(2), 0.5 * area * r * r, r, np.zeros((0, 2)))
    if isinstance(shape, Box):
        w, h = float(shape.width), float(shape.height)
        if not (w > 0 and h > 0):
            raise ValueError("box width and height must be > 0")
        corners = np.array([[-w / 2, -h / 2], [w / 2, -h / 2], [w / 2, h / 2], [-w / 2, h / 2]])
        area = w * h
        return MassProperties(OBB if shape.rotates else AABB, area, np.zeros(2),
                              area * (w * w + h * h) / 12.0, 0.0, corners)
    ccw = convex_polygon(shape.vertices)
    ref = ccw.mean(axis=0)  # integrate about an interior point to limit round-off
    p = ccw - ref
    q = np.roll(p, -1, axis=0)
    c = _cross(p, q)
    area = 0.5 * float(np.sum(c))
    centroid_rel = np.sum((p + q) * c[:, None], axis=0) / (6.0 * area)
    squares = np.sum(p * p, axis=1) + np.sum(p * q, axis=1) + np.sum(q * q, axis=1)
    inertia_ref = float(np.sum(c * squares)) / 12.0
    unit_inertia = inertia_ref - area * float(centroid_rel @ centroid_rel)
    centroid = ref + centroid_rel
    return MassProperties(POLYGON, area, centroid, unit_inertia, 0.0, ccw - centroid)
