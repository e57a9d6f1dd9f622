"""Shapes as the convex pieces the kernels collide, and a body's mass properties from them.

Every piece is a convex polygon of at most MAX_VERTICES vertices with a radius: a circle is one vertex
(its centre) with its radius, a capsule two vertices with its radius, a segment two vertices with none,
a box or polygon piece its corners. A chain is one piece per segment, each knowing the chain's points
before and after it (its ghosts), so that bodies meet no bump at the joints. Mass properties are exact
closed forms at unit density: area, area centroid, and the area moment about that centroid; a body sums
its pieces' with the parallel-axis theorem.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rustycs.shapes import Box, Capsule, Chain, Circle, Polygon, Segment, Shape

MAX_VERTICES = 8
CIRCLE, BOX, POLYGON, CAPSULE, SEGMENT, CHAIN_SEGMENT = range(6)
# a chain segment's ends with no neighbour: bit 0 its first point, bit 1 its second
OPEN_START, OPEN_END = 1, 2


@dataclass(frozen=True)
class Piece:
    """One convex piece in its body's frame (about the body origin): vertices counter-clockwise; for
    a chain segment, the chain's points before and after it (`ghosts`), which are the segment's other
    end where the chain ends there (`open_ends`)."""

    kind: int
    vertices: np.ndarray  # (k, 2)
    radius: float
    area: float
    centroid: np.ndarray  # (2,)
    unit_inertia: float  # about the centroid, at unit density
    ghosts: np.ndarray  # (2, 2)
    open_ends: int


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def polygon_piece_mass(ccw: np.ndarray) -> tuple[float, np.ndarray, float]:
    """Area, centroid and unit inertia about the centroid of a convex counter-clockwise polygon,
    integrated about the vertex mean to limit round-off."""
    ref = ccw.mean(axis=0)
    p = ccw - ref
    q = np.roll(p, -1, axis=0)
    c = _cross(p, q)
    area = 0.5 * float(np.sum(c))
    centroid_rel = np.sum((p + q) * c[:, None], axis=0) / (6.0 * area)
    squares = np.sum(p * p, axis=1) + np.sum(p * q, axis=1) + np.sum(q * q, axis=1)
    inertia_ref = float(np.sum(c * squares)) / 12.0
    return area, ref + centroid_rel, inertia_ref - area * float(centroid_rel @ centroid_rel)


def capsule_mass(length: float, radius: float) -> tuple[float, float]:
    """Area and unit inertia about the centre of a capsule: a length x 2 radius box and two half-discs,
    each half-disc moved from its own centroid (4 r / 3 pi from its flat side) to the capsule's centre."""
    box_area = 2.0 * radius * length
    disc_area = math.pi * radius * radius
    box = box_area * (length * length + 4.0 * radius * radius) / 12.0
    lever = 0.5 * length + 4.0 * radius / (3.0 * math.pi)
    half_disc_about_flat = 0.25 * disc_area * radius * radius  # half of the disc's polar moment
    half_disc_about_centroid = half_disc_about_flat - 0.5 * disc_area * (4.0 * radius / (3.0 * math.pi)) ** 2
    discs = 2.0 * (half_disc_about_centroid + 0.5 * disc_area * lever * lever)
    return box_area + disc_area, box + discs


_NO_GHOSTS = np.zeros((2, 2))


def _piece(kind: int, vertices, radius: float = 0.0, area: float = 0.0, centroid=None,
           unit_inertia: float = 0.0, ghosts: np.ndarray = _NO_GHOSTS, open_ends: int = 0) -> Piece:
    vertices = np.asarray(vertices, dtype=np.float64).reshape(-1, 2)
    centroid = vertices.mean(axis=0) if centroid is None else np.asarray(centroid, dtype=np.float64)
    return Piece(kind, vertices, float(radius), float(area), centroid, float(unit_inertia), ghosts, open_ends)


def _shape_frame_pieces(shape: Shape) -> list[Piece]:
    """The shape's pieces in its own frame."""
    if isinstance(shape, Circle):
        r = shape.radius
        area = math.pi * r * r
        return [_piece(CIRCLE, [[0.0, 0.0]], r, area, None, 0.5 * area * r * r)]
    if isinstance(shape, Box):
        w, h = shape.width, shape.height
        corners = [[-w / 2, -h / 2], [w / 2, -h / 2], [w / 2, h / 2], [-w / 2, h / 2]]  # face k+2 opposite k
        area = w * h
        return [_piece(BOX, corners, 0.0, area, np.zeros(2), area * (w * w + h * h) / 12.0)]
    if isinstance(shape, Polygon):
        from rustycs.polygon import convex_pieces

        pieces = []
        for ccw in convex_pieces(shape.vertices):
            area, centroid, inertia = polygon_piece_mass(ccw)
            pieces.append(_piece(POLYGON, ccw, 0.0, area, centroid, inertia))
        return pieces
    if isinstance(shape, Capsule):
        if shape.length == 0.0:
            return _shape_frame_pieces(Circle(shape.radius))
        area, inertia = capsule_mass(shape.length, shape.radius)
        half = 0.5 * shape.length
        return [_piece(CAPSULE, [[-half, 0.0], [half, 0.0]], shape.radius, area, np.zeros(2), inertia)]
    if isinstance(shape, Segment):
        return [_piece(SEGMENT, shape.points)]
    assert isinstance(shape, Chain)
    return _chain_pieces(np.asarray(shape.points, dtype=np.float64), shape.loop)


def _chain_pieces(points: np.ndarray, loop: bool) -> list[Piece]:
    """One piece per segment of the chain; an open end's ghost is the segment's other end (the
    chain turns back on itself there, so every direction beyond the end is a free one)."""
    n = len(points)
    count = n if loop else n - 1
    pieces = []
    for k in range(count):
        p1, p2 = points[k], points[(k + 1) % n]
        open_ends = 0
        if loop or k > 0:
            before = points[(k - 1) % n]
        else:
            before, open_ends = p2, open_ends | OPEN_START
        if loop or k + 2 < n:
            after = points[(k + 2) % n]
        else:
            after, open_ends = p1, open_ends | OPEN_END
        pieces.append(_piece(CHAIN_SEGMENT, [p1, p2], ghosts=np.array([before, after]), open_ends=open_ends))
    return pieces


def shape_pieces(shape: Shape) -> list[Piece]:
    """The shape's pieces in its body's frame (its offset and angle applied)."""
    c, s = math.cos(shape.angle), math.sin(shape.angle)
    rotation = np.array([[c, -s], [s, c]])
    offset = np.asarray(shape.offset, dtype=np.float64)

    def place(points: np.ndarray) -> np.ndarray:
        return points @ rotation.T + offset

    return [Piece(p.kind, place(p.vertices), p.radius, p.area, place(p.centroid), p.unit_inertia,
                  place(p.ghosts), p.open_ends) for p in _shape_frame_pieces(shape)]


@dataclass(frozen=True)
class BodyMass:
    """A body's mass, centre of mass (body frame, about the origin) and inertia about it, from the
    pieces with area."""

    mass: float
    center: np.ndarray
    inertia: float


def body_mass(pieces: list[Piece], densities: list[float], massive: list[bool],
              mass: float | None = None) -> BodyMass:
    """Sum the massive pieces (`massive`: not sensors, with area): their masses are area x density,
    scaled to `mass` when it is given; the centre of mass is their mass-weighted centroid; the
    inertia, their inertias moved to that centre (parallel axes). A body with no massive piece has
    mass 0 and its origin as centre."""
    counted = [(p, d) for p, d, m in zip(pieces, densities, massive, strict=True) if m and p.area > 0.0]
    masses = [p.area * d for p, d in counted]
    total = float(sum(masses))
    if not counted:
        return BodyMass(0.0, np.zeros(2), 0.0)
    if mass is not None:
        # each piece's share times the given mass (exactly the given mass for a body of one piece)
        masses = [mass * (m / total) for m in masses]
        total = float(mass)
    first = counted[0][0].centroid
    center = first + sum((m * (p.centroid - first) for (p, _), m in zip(counted, masses, strict=True)),
                         np.zeros(2)) / total
    inertia = 0.0
    for (p, _), m in zip(counted, masses, strict=True):
        d = p.centroid - center
        inertia += (p.unit_inertia + p.area * float(d @ d)) * m / p.area
    return BodyMass(total, center, inertia)


def edge_normals(vertices: np.ndarray) -> np.ndarray:
    """Outward unit normals of a counter-clockwise polygon's edges (k to k + 1); a two-vertex piece
    (capsule, segment) has its two sides' normals."""
    edges = np.roll(vertices, -1, axis=0) - vertices
    normals = np.stack([edges[:, 1], -edges[:, 0]], axis=1)
    return normals / np.linalg.norm(normals, axis=1)[:, None]
