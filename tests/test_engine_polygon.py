"""Concave polygons (rustycs.polygon): which points are a valid polygon, its convex pieces and its mass
properties, against closed forms and on a few hundred random simple polygons."""

from __future__ import annotations

import math
import time

import numpy as np
import pytest

from rustycs.polygon import (
    MAX_PIECE_VERTICES,
    MAX_POLYGON_VERTICES,
    PolygonProblem,
    convex_pieces,
    polygon_mass,
    polygon_problem,
)

# An L of two unit-width arms: the 2 x 1 box [0, 2] x [0, 1] (area 2, centroid (1, 1/2),
# I = 2 (4 + 1) / 12 = 5/6) under the 1 x 1 box [0, 1] x [1, 2] (area 1, centroid (1/2, 3/2), I = 1/6).
# Centroid (2 (1, 1/2) + (1/2, 3/2)) / 3 = (5/6, 5/6); offsets (1/6, -1/3) and (-1/3, 2/3) give by the
# parallel-axis theorem I = 5/6 + 1/6 + 2 (5/36) + 5/9 = 11/6.
L_SHAPE = [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)]
L_MASS = (3.0, (5 / 6, 5 / 6), 11 / 6)

# A U: the 3 x 1 base [0, 3] x [0, 1] (area 3, centroid (3/2, 1/2), I = 3 (9 + 1) / 12 = 5/2) and two
# unit arms [0, 1] x [1, 2] and [2, 3] x [1, 2] (area 1, centroids (1/2, 3/2) and (5/2, 3/2), I = 1/6).
# Centroid (3/2, (3/2 + 3/2 + 3/2) / 5) = (3/2, 9/10); offsets (0, -2/5) and (-+1, 3/5) give
# I = 5/2 + 3 (4/25) + 2 (1/6 + 34/25) = 181/30.
U_SHAPE = [(0, 0), (3, 0), (3, 2), (2, 2), (2, 1), (1, 1), (1, 2), (0, 2)]
U_MASS = (5.0, (1.5, 0.9), 181 / 30)


# A T upside down: the 3 x 1 base under a unit stem. The base's piece holds the stem's two corners on its
# top edge, where they are straight: dropped, the base is the rectangle of 4 vertices.
T_SHAPE = [(0, 0), (3, 0), (3, 1), (2, 1), (2, 2), (1, 2), (1, 1), (0, 1)]


def regular_polygon(n: int, radius: float, centre=(0.0, 0.0)) -> np.ndarray:
    angles = 2 * np.pi * np.arange(n) / n
    return np.c_[centre[0] + radius * np.cos(angles), centre[1] + radius * np.sin(angles)]


def pieces_mass(pieces: list[np.ndarray]) -> tuple[float, np.ndarray, float]:
    """Area, centroid and inertia about it of the pieces together (parallel-axis sum)."""
    masses = [polygon_mass(piece) for piece in pieces]
    area = sum(m[0] for m in masses)
    centroid = sum(m[0] * m[1] for m in masses) / area
    inertia = sum(m[2] + m[0] * float((m[1] - centroid) @ (m[1] - centroid)) for m in masses)
    return area, centroid, inertia


def strictly_inside(piece: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Points strictly inside a counter-clockwise convex piece."""
    a, b = piece, np.roll(piece, -1, axis=0)
    cross = ((b[:, 0] - a[:, 0]) * (points[:, None, 1] - a[:, 1])
             - (b[:, 1] - a[:, 1]) * (points[:, None, 0] - a[:, 0]))
    return np.all(cross > 0, axis=1)


def inside_or_on(piece: np.ndarray, points: np.ndarray) -> np.ndarray:
    a, b = piece, np.roll(piece, -1, axis=0)
    cross = ((b[:, 0] - a[:, 0]) * (points[:, None, 1] - a[:, 1])
             - (b[:, 1] - a[:, 1]) * (points[:, None, 0] - a[:, 0]))
    return np.all(cross >= 0, axis=1)


def inside_polygon(polygon: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Even-odd rule: a horizontal ray from each point crosses the boundary an odd number of times."""
    a, b = polygon, np.roll(polygon, -1, axis=0)
    y = points[:, None, 1]
    straddles = (a[:, 1] > y) != (b[:, 1] > y)
    with np.errstate(divide="ignore", invalid="ignore"):
        x_crossing = a[:, 0] + (y - a[:, 1]) * (b[:, 0] - a[:, 0]) / (b[:, 1] - a[:, 1])
    return np.sum(straddles & (points[:, None, 0] < x_crossing), axis=1) % 2 == 1


def sample_points(polygon: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Random points and a jittered grid over the polygon's bounding box (off its vertex lattice)."""
    lo, hi = polygon.min(axis=0), polygon.max(axis=0)
    grid = (np.stack(np.meshgrid(np.arange(24), np.arange(24)), axis=-1).reshape(-1, 2) + 0.5137) / 24
    return np.vstack([lo + rng.random((400, 2)) * (hi - lo), lo + grid * (hi - lo)])


def check_pieces(polygon: np.ndarray, rng: np.random.Generator) -> list[np.ndarray]:
    """Every property a split must have; returns the pieces."""
    polygon = np.asarray(polygon, dtype=np.float64)
    assert polygon_problem(polygon) is None
    pieces = convex_pieces(polygon)
    for piece in pieces:
        assert piece.dtype == np.float64 and piece.ndim == 2 and piece.shape[1] == 2
        assert 3 <= len(piece) <= MAX_PIECE_VERTICES
        # convex and counter-clockwise, with no repeated or collinear vertex: every turn strictly left
        edges = np.roll(piece, -1, axis=0) - piece
        following = np.roll(edges, -1, axis=0)
        turns = edges[:, 0] * following[:, 1] - edges[:, 1] * following[:, 0]
        scale = float(np.max(np.abs(piece - piece.mean(axis=0))))
        assert np.all(turns > 1e-12 * scale * scale)
        assert np.all((piece[:, None, :] == polygon[None, :, :]).all(axis=2).any(axis=1))
    area, centroid, inertia = polygon_mass(polygon)
    size = float(np.max(polygon.max(axis=0) - polygon.min(axis=0)))
    piece_area, piece_centroid, piece_inertia = pieces_mass(pieces)
    assert piece_area == pytest.approx(area, rel=1e-9)
    assert np.max(np.abs(piece_centroid - centroid)) <= 1e-9 * size
    assert piece_inertia == pytest.approx(inertia, rel=1e-9)
    centroids = np.array([polygon_mass(piece)[1] for piece in pieces])
    assert np.all(inside_polygon(polygon, centroids))
    points = sample_points(polygon, rng)
    assert np.all(sum(strictly_inside(piece, points).astype(int) for piece in pieces) <= 1)
    covered = sum(inside_or_on(piece, points).astype(int) for piece in pieces)
    assert np.all(covered[inside_polygon(polygon, points)] >= 1)
    assert np.all(covered[~inside_polygon(polygon, points)] == 0)
    return pieces


# ---------------------------------------------------------------------------------------------------
# Known shapes


@pytest.mark.parametrize(("shape", "expected", "count"), [(L_SHAPE, L_MASS, 2), (U_SHAPE, U_MASS, 3)])
def test_l_and_u_against_their_boxes(shape, expected, count):
    area, centroid, inertia = expected
    for mass in (polygon_mass(shape), pieces_mass(convex_pieces(shape))):
        assert mass[0] == pytest.approx(area, rel=1e-9)
        assert mass[1] == pytest.approx(centroid, abs=1e-9)
        assert mass[2] == pytest.approx(inertia, rel=1e-9)
    assert len(check_pieces(shape, np.random.default_rng(0))) == count


def test_straight_vertices_of_merged_pieces_are_dropped():
    pieces = check_pieces(T_SHAPE, np.random.default_rng(0))
    assert sorted(map(len, pieces)) == [4, 4]
    assert sorted(polygon_mass(piece)[0] for piece in pieces) == pytest.approx([1.0, 3.0], rel=1e-12)


def test_regular_40_gon_against_the_closed_forms():
    # n triangles from the centre, each with two sides r at the angle t = 2 pi / n: area n r^2 sin(t) / 2,
    # and from sum cross (a.a + a.b + b.b) / 12 the polar moment n r^2 sin(t) (r^2 + r^2 cos(t) + r^2) / 12.
    n, r, centre = 40, 1.5, (3.0, -2.0)
    t = 2 * math.pi / n
    polygon = regular_polygon(n, r, centre)
    pieces = check_pieces(polygon, np.random.default_rng(0))
    assert len(pieces) <= math.ceil((n - 2) / (MAX_PIECE_VERTICES - 2)) == 7
    for area, centroid, inertia in (polygon_mass(polygon), pieces_mass(pieces)):
        assert area == pytest.approx(n / 2 * r * r * math.sin(t), rel=1e-9)
        assert centroid == pytest.approx(centre, abs=1e-9)
        assert inertia == pytest.approx(n * r**4 / 12 * math.sin(t) * (2 + math.cos(t)), rel=1e-9)


def test_mass_does_not_depend_on_the_start_vertex_or_the_winding():
    area, centroid, inertia = L_MASS
    for start in range(len(L_SHAPE)):
        for shape in (L_SHAPE[start:] + L_SHAPE[:start], (L_SHAPE[start:] + L_SHAPE[:start])[::-1]):
            a, c, i = polygon_mass(shape)
            assert a == pytest.approx(area, rel=1e-12)
            assert c == pytest.approx(centroid, abs=1e-12)
            assert i == pytest.approx(inertia, rel=1e-12)


# ---------------------------------------------------------------------------------------------------
# Random simple polygons


def star_polygon(rng: np.random.Generator) -> np.ndarray:
    """Random radii at sorted random angles about a random centre: simple while no angular gap reaches pi."""
    n = int(rng.integers(3, MAX_POLYGON_VERTICES + 1))
    while True:
        gaps = rng.uniform(0.05, 1.0, n)
        if gaps.max() < 0.45 * gaps.sum():
            break
    angles = rng.uniform(0, 2 * np.pi) + 2 * np.pi * np.cumsum(gaps) / gaps.sum()
    radii = 10 ** rng.uniform(-1, 1.5) * rng.uniform(0.2, 1.0, n)
    return rng.uniform(-50, 50, 2) + np.c_[radii * np.cos(angles), radii * np.sin(angles)]


def staircase_polygon(rng: np.random.Generator) -> np.ndarray:
    """An orthogonal histogram: bars of random heights (neighbours differ) on random widths, on integer or
    random coordinates; integers put many vertices exactly on the lines of candidate diagonals."""
    steps = int(rng.integers(1, (MAX_POLYGON_VERTICES - 2) // 2 + 1))
    integer = bool(rng.integers(2))
    widths = rng.integers(1, 4, steps) if integer else rng.uniform(0.1, 1.0, steps)
    xs = np.concatenate([[0], np.cumsum(widths)])
    heights = [int(rng.integers(1, 10)) if integer else float(rng.uniform(0.1, 2.0))]
    while len(heights) < steps:
        height = int(rng.integers(1, 10)) if integer else float(rng.uniform(0.1, 2.0))
        if height != heights[-1]:
            heights.append(height)
    top = [(xs[k + dx], heights[k]) for k in range(steps - 1, -1, -1) for dx in (1, 0)]
    return np.array([(0.0, 0.0), (xs[-1], 0.0), *top], dtype=np.float64)


def random_polygon(kind: str, seed: int) -> tuple[np.ndarray, np.random.Generator]:
    rng = np.random.default_rng([0 if kind == "star" else 1, seed])
    polygon = star_polygon(rng) if kind == "star" else staircase_polygon(rng)
    polygon = np.roll(polygon, -int(rng.integers(len(polygon))), axis=0)
    return (polygon[::-1].copy() if rng.integers(2) else polygon), rng


@pytest.mark.parametrize("seed", range(150))
@pytest.mark.parametrize("kind", ["star", "staircase"])
def test_random_simple_polygons_split_into_valid_pieces(kind, seed):
    check_pieces(*random_polygon(kind, seed))


# ---------------------------------------------------------------------------------------------------
# Validity, rule by rule


@pytest.mark.parametrize(("vertices", "message", "vertex"), [
    ("abc", "the vertices are not a list of [x, y] pairs", None),
    (5, "the vertices are not a list of [x, y] pairs", None),
    ([(0, 0), (1,), (0, 1)], "vertex 1 is not an [x, y] pair of numbers", 1),
    ([(0, 0), (1, 0), ("0", "1")], "vertex 2 is not an [x, y] pair of numbers", 2),
    ([(0, 0), (1, 0)], "a polygon has 3 to 256 vertices, this one has 2", None),
    (regular_polygon(257, 1.0), "a polygon has 3 to 256 vertices, this one has 257", None),
    ([(0, 0), (1, math.nan), (0, 1)], "vertex 1 is not finite", 1),
    ([(0, 0), (1, 0), (0, -math.inf)], "vertex 2 is not finite", 2),
    ([(0, 0), (1, 0), (1, 0), (0, 1)], "vertex 2 repeats vertex 1: the polygon is degenerate", 2),
    # a pinch: vertex 5 is 1e-10 m from vertex 2, which is not its neighbour
    ([(0, 0), (2, 0), (1, 1), (2, 2), (0, 2), (1 + 1e-10, 1)],
     "vertex 5 repeats vertex 2: the polygon is degenerate", 5),
    ([(0, 0), (1, 1), (1, 0), (0, 1)], "edges 0-1 and 2-3 cross: the polygon intersects itself", 2),
    ([(0, 0), (1, 0), (0, 1), (1, 1)], "edges 1-2 and 3-0 cross: the polygon intersects itself", 3),
    # vertex 3 lies on edge 0-1: the edges 0-1 and 2-3 touch
    ([(0, 0), (4, 0), (4, 3), (2, 0), (0, 3)], "edges 0-1 and 2-3 cross: the polygon intersects itself", 2),
    # vertex 3 is the exact midpoint of edge 0-1, where rounded arithmetic puts it 2e-16 m^2 to its left
    ([(0.822, 0.067), (2.7560000000000002, 2.9680000000000004), (1, 3.5),
      (1.7890000000000001, 1.5175000000000003), (0, 1.5)],
     "edges 0-1 and 2-3 cross: the polygon intersects itself", 2),
    # edge 3-4 runs along edge 0-1
    ([(0, 0), (4, 0), (4, 2), (3, 0), (1, 0), (0, 2)],
     "edges 0-1 and 2-3 cross: the polygon intersects itself", 2),
    ([(0, 0), (1, 0), (2, 0), (2, 2), (0, 2)],
     "vertex 1 lies on the line through its neighbours: the polygon is degenerate", 1),
    ([(0, 0), (1, 1e-10), (2, 0), (2, 2), (0, 2)],  # a turn of sine 2e-10
     "vertex 1 lies on the line through its neighbours: the polygon is degenerate", 1),
    ([(0, 0), (1e-5, 0), (0, 1e-5)], "the polygon's area 5e-11 m^2 is too small: it is degenerate", None),
    # the first problem wins: non-finite before repeated, crossing before collinear
    ([(0, 0), (0, 0), (math.nan, 1), (0, 1)], "vertex 2 is not finite", 2),
    ([(0, 0), (1, 1), (2, 2), (2, 0), (0, 2)], "edges 0-1 and 3-4 cross: the polygon intersects itself", 3),
])
def test_each_rule_names_its_problem(vertices, message, vertex):
    assert polygon_problem(vertices) == PolygonProblem(message, vertex)


def test_invalid_polygons_are_not_split():
    with pytest.raises(ValueError, match="edges 0-1 and 2-3 cross"):
        convex_pieces([(0, 0), (1, 1), (1, 0), (0, 1)])


def test_a_million_vertices_are_rejected_at_once():
    vertices = [(float(k), 0.0) for k in range(10**6)]
    start = time.perf_counter()
    problem = polygon_problem(vertices)
    elapsed = time.perf_counter() - start
    assert problem == PolygonProblem("a polygon has 3 to 256 vertices, this one has 1000000", None)
    assert elapsed < 0.5


@pytest.mark.parametrize("vertices", [
    L_SHAPE, U_SHAPE, [(0, 0), (3, 0), (0, 3)], [(0, 0), (2, 0), (2, 2), (1, 3), (0, 2)],
    regular_polygon(8, 1.0), regular_polygon(9, 1.0), regular_polygon(MAX_POLYGON_VERTICES, 1.0),
    [(0, 0), (4, 0), (4, 3), (2, 1e-9), (0, 3)],  # close to edge 0-1, but not on it
])
def test_valid_polygons_have_no_problem(vertices):
    assert polygon_problem(vertices) is None
    assert polygon_problem(np.asarray(vertices, dtype=np.float64)[::-1]) is None


# ---------------------------------------------------------------------------------------------------
# Determinism and convex polygons


def test_the_same_polygon_gives_bitwise_the_same_pieces():
    for polygon in (U_SHAPE, random_polygon("star", 7)[0], random_polygon("staircase", 3)[0]):
        first, second = convex_pieces(polygon), convex_pieces(polygon)
        assert len(first) == len(second) > 1
        assert all(a.tobytes() == b.tobytes() for a, b in zip(first, second, strict=True))


def test_a_convex_polygon_of_up_to_8_vertices_is_one_piece_counter_clockwise():
    octagon = regular_polygon(8, 2.0, (5.0, 1.0))
    pentagon = [(1, 0), (2, 2), (1, 3), (0, 2), (0, 1)]
    for polygon in ([(0, 0), (3, 0), (0, 3)], pentagon, np.roll(octagon, 3, axis=0)):
        counter_clockwise = np.asarray(polygon, dtype=np.float64)
        (piece,) = convex_pieces(counter_clockwise)
        assert piece.tobytes() == counter_clockwise.tobytes()  # same order, same start
        clockwise = counter_clockwise[::-1]
        (piece,) = convex_pieces(clockwise)
        assert piece.tobytes() == clockwise[::-1].tobytes()
