"""Narrow phase against hand-computed manifolds: normal (from body a to body b), depth, contact points
(midway between the two surfaces) and feature ids, for every shape pair.

Bodies are placed with `pose` (shape, body origin, angle) and collided through `manifold.narrow_phase`,
as the step does, so circle-first pairs check the flipped normal too.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rustycs import Box, Circle, Polygon, debug
from rustycs.manifold import collide_circles, new_collision

MARGIN = 0.02
S2 = math.sqrt(2.0)


def collide_pair(a, b, margin=MARGIN):
    """Manifold of two posed shapes (shape, origin, angle): normal, points (k, 2), depths (k,), ids."""
    found = debug.collide(a, b, margin)
    if not found:
        return np.zeros(2), np.zeros((0, 2)), np.zeros(0), np.zeros(0, np.int64)
    (manifold,) = found
    return manifold.normal, manifold.points, manifold.depths, manifold.ids


def by_x(points, depths):
    order = np.argsort(points[:, 0])
    return points[order], depths[order]


# ---------------------------------------------------------------------------- circle-circle

def test_circles_separated_beyond_margin_give_nothing():
    normal, points, depths, _ = collide_pair((Circle(1.0), (0, 0), 0.0), (Circle(0.5), (1.6, 0), 0.0),
                                             margin=0.05)
    assert len(points) == 0  # gap 0.1 > margin 0.05


def test_circles_within_margin_give_a_speculative_point():
    normal, points, depths, _ = collide_pair((Circle(1.0), (0, 0), 0.0), (Circle(0.5), (1.6, 0), 0.0),
                                             margin=0.2)
    assert normal == pytest.approx([1, 0], abs=1e-12)
    assert depths == pytest.approx([-0.1], abs=1e-12)  # negative depth: a gap
    assert points[0] == pytest.approx([1.05, 0.0], abs=1e-12)  # midway between x = 1 and x = 1.1


def test_circles_touching():
    normal, points, depths, _ = collide_pair((Circle(1.0), (0, 0), 0.0), (Circle(1.0), (0, 2), 0.0))
    assert normal == pytest.approx([0, 1], abs=1e-12)
    assert depths == pytest.approx([0.0], abs=1e-12)
    assert points[0] == pytest.approx([0, 1], abs=1e-12)


def test_circles_overlapping_on_a_diagonal():
    # centres 1.0 apart along (0.6, 0.8); radii 1 and 0.5: depth 0.5
    normal, points, depths, _ = collide_pair((Circle(1.0), (1, 1), 0.0), (Circle(0.5), (1.6, 1.8), 0.0))
    assert normal == pytest.approx([0.6, 0.8], abs=1e-12)
    assert depths == pytest.approx([0.5], abs=1e-12)
    # a's surface at (1.6, 1.8), b's at (1.3, 1.4): midway (1.45, 1.6)
    assert points[0] == pytest.approx([1.45, 1.6], abs=1e-12)


def test_circles_with_coincident_centres():
    normal, points, depths, _ = collide_pair((Circle(1.0), (2, 3), 0.0), (Circle(0.5), (2, 3), 0.0))
    assert np.hypot(*normal) == pytest.approx(1.0, abs=1e-12)
    assert depths == pytest.approx([1.5], abs=1e-12)
    # a's surface at c + n, b's at c - 0.5 n: midway c + 0.25 n
    assert points[0] == pytest.approx(np.array([2, 3]) + 0.25 * normal, abs=1e-12)


def test_collide_circles_kernel_directly():
    out = new_collision()
    assert collide_circles(0.0, 0.0, 1.0, 0.0, -1.5, 1.0, 0.0, out) == 1
    assert out.normal == pytest.approx([0, -1], abs=1e-12)
    assert out.separations[0] == pytest.approx(-0.5, abs=1e-12)
    assert out.points[0] == pytest.approx([0, -0.75], abs=1e-12)


# ---------------------------------------------------------------------------- circle-box

BOX = (Box(2.0, 2.0), (0, 0), 0.0)  # faces at x, y = +-1


def test_circle_box_separated_beyond_margin():
    _, points, _, _ = collide_pair(BOX, (Circle(0.5), (0, 1.6), 0.0))
    assert len(points) == 0


def test_circle_box_face():
    normal, points, depths, _ = collide_pair(BOX, (Circle(0.5), (0.3, 1.3), 0.0))
    assert normal == pytest.approx([0, 1], abs=1e-12)
    assert depths == pytest.approx([0.2], abs=1e-12)
    assert points[0] == pytest.approx([0.3, 0.9], abs=1e-12)  # between y = 1 and y = 0.8


def test_circle_box_touching_face():
    normal, points, depths, _ = collide_pair(BOX, (Circle(0.5), (-1.5, 0.25), 0.0))
    assert normal == pytest.approx([-1, 0], abs=1e-12)
    assert depths == pytest.approx([0.0], abs=1e-12)
    assert points[0] == pytest.approx([-1.0, 0.25], abs=1e-12)


def test_circle_box_corner_region():
    # centre (1.3, 1.4) is 0.5 from the corner (1, 1) along (0.6, 0.8); radius 0.6: depth 0.1
    normal, points, depths, _ = collide_pair(BOX, (Circle(0.6), (1.3, 1.4), 0.0))
    assert normal == pytest.approx([0.6, 0.8], abs=1e-12)
    assert depths == pytest.approx([0.1], abs=1e-12)
    # the circle's surface at (0.94, 0.92): midway to the corner (0.97, 0.96)
    assert points[0] == pytest.approx([0.97, 0.96], abs=1e-12)


def test_circle_centre_inside_box_is_pushed_out_through_the_nearest_face():
    # centre 0.4 from the face x = 1 (0.8 from y = 1): normal +x, depth r + 0.4
    normal, points, depths, _ = collide_pair(BOX, (Circle(0.5), (0.6, 0.2), 0.0))
    assert normal == pytest.approx([1, 0], abs=1e-12)
    assert depths == pytest.approx([0.9], abs=1e-12)
    # box surface (1, 0.2), circle surface (0.1, 0.2)
    assert points[0] == pytest.approx([0.55, 0.2], abs=1e-12)


def test_circle_centre_inside_box_near_the_bottom_face():
    normal, points, depths, _ = collide_pair(BOX, (Circle(0.25), (-0.2, -0.9), 0.0))
    assert normal == pytest.approx([0, -1], abs=1e-12)
    assert depths == pytest.approx([0.35], abs=1e-12)
    assert points[0] == pytest.approx([-0.2, -0.825], abs=1e-12)  # between y = -1 and y = -0.65


def test_circle_first_flips_the_normal():
    normal, points, depths, _ = collide_pair((Circle(0.5), (0.3, 1.3), 0.0), BOX)
    assert normal == pytest.approx([0, -1], abs=1e-12)  # from the circle (a) to the box (b)
    assert depths == pytest.approx([0.2], abs=1e-12)
    assert points[0] == pytest.approx([0.3, 0.9], abs=1e-12)


def test_circle_rotated_box_face():
    # a box turned 45 degrees: its face normal (1, 1)/sqrt2 passes 1 from the centre
    box = (Box(2.0, 2.0), (0, 0), math.pi / 4)
    centre = np.array([1.0, 1.0]) * (1.3 / S2)  # 1.3 from the box centre along the face normal
    normal, points, depths, _ = collide_pair(box, (Circle(0.5), centre, 0.0))
    assert normal == pytest.approx([1 / S2, 1 / S2], abs=1e-12)
    assert depths == pytest.approx([0.2], abs=1e-12)
    assert points[0] == pytest.approx(np.array([1.0, 1.0]) * (0.9 / S2), abs=1e-12)


# ---------------------------------------------------------------------------- circle-polygon

# a right triangle with its origin at the right angle (centroid (2/3, 2/3)); hypotenuse x + y = 2
TRIANGLE = Polygon([(0, 0), (2, 0), (0, 2)])


def test_circle_polygon_face():
    normal, points, depths, _ = collide_pair((TRIANGLE, (0, 0), 0.0), (Circle(1.0), (1.5, 1.5), 0.0))
    # the centre is 1/sqrt2 from the hypotenuse
    assert normal == pytest.approx([1 / S2, 1 / S2], abs=1e-12)
    assert depths == pytest.approx([1 - 1 / S2], abs=1e-12)
    surface_circle = 1.5 - 1 / S2
    mid = 0.5 * (1.0 + surface_circle)
    assert points[0] == pytest.approx([mid, mid], abs=1e-12)


def test_circle_polygon_vertex_region():
    # centre (-0.3, -0.4) is 0.5 from the vertex (0, 0); radius 0.6
    normal, points, depths, _ = collide_pair((TRIANGLE, (0, 0), 0.0), (Circle(0.6), (-0.3, -0.4), 0.0))
    assert normal == pytest.approx([-0.6, -0.8], abs=1e-12)
    assert depths == pytest.approx([0.1], abs=1e-12)
    assert points[0] == pytest.approx([0.03, 0.04], abs=1e-12)


def test_circle_polygon_with_an_offset_origin_and_rotation():
    # the same triangle, origin moved to (5, 1) and turned 90 degrees: the hypotenuse is now -x + y = 2
    # (relative to the origin), normal (-1, 1)/sqrt2
    centre = np.array([5.0, 1.0]) + np.array([-1.5, 1.5])
    normal, points, depths, _ = collide_pair((TRIANGLE, (5, 1), math.pi / 2), (Circle(1.0), centre, 0.0))
    assert normal == pytest.approx([-1 / S2, 1 / S2], abs=1e-12)
    assert depths == pytest.approx([1 - 1 / S2], abs=1e-12)
    mid = 0.5 * (1.0 + 1.5 - 1 / S2)
    assert points[0] == pytest.approx([5 - mid, 1 + mid], abs=1e-12)


def test_circle_centre_inside_polygon():
    # centre (0.3, 0.5): distances to the legs 0.3 (x = 0) and 0.5 (y = 0), to the hypotenuse 1.2/sqrt2
    normal, points, depths, _ = collide_pair((TRIANGLE, (0, 0), 0.0), (Circle(0.2), (0.3, 0.5), 0.0))
    assert normal == pytest.approx([-1, 0], abs=1e-12)
    assert depths == pytest.approx([0.5], abs=1e-12)
    assert points[0] == pytest.approx([0.25, 0.5], abs=1e-12)  # between x = 0 and x = 0.5


# ---------------------------------------------------------------------------- box-box

FLOOR = (Box(2.0, 1.0), (0, 0), 0.0)  # top face y = 0.5, x in [-1, 1]


def test_boxes_separated_beyond_margin():
    _, points, _, _ = collide_pair(FLOOR, (Box(1.0, 1.0), (0, 1.05), 0.0))
    assert len(points) == 0


def test_box_resting_on_a_box_clipped_at_the_corner():
    # upper box bottom face y = 0.49 (overlap 0.01), spanning x in [0.3, 1.3]: clipped at x = 1
    normal, points, depths, ids = collide_pair(FLOOR, (Box(1.0, 1.0), (0.8, 0.99), 0.0))
    assert normal == pytest.approx([0, 1], abs=1e-12)
    points, depths = by_x(points, depths)
    assert depths == pytest.approx([0.01, 0.01], abs=1e-12)
    assert points == pytest.approx(np.array([[0.3, 0.495], [1.0, 0.495]]), abs=1e-12)
    assert len(set(ids)) == 2


def test_boxes_touching():
    normal, points, depths, _ = collide_pair(FLOOR, (Box(1.0, 1.0), (-0.25, 1.0), 0.0))
    assert normal == pytest.approx([0, 1], abs=1e-12)
    points, depths = by_x(points, depths)
    assert depths == pytest.approx([0.0, 0.0], abs=1e-12)
    assert points == pytest.approx(np.array([[-0.75, 0.5], [0.25, 0.5]]), abs=1e-12)


def test_boxes_deep_overlap_from_above():
    wide = (Box(4.0, 1.0), (0, 0), 0.0)
    normal, points, depths, _ = collide_pair(wide, (Box(1.0, 1.0), (0, 0.6), 0.0))
    assert normal == pytest.approx([0, 1], abs=1e-12)
    points, depths = by_x(points, depths)
    assert depths == pytest.approx([0.4, 0.4], abs=1e-12)
    assert points == pytest.approx(np.array([[-0.5, 0.3], [0.5, 0.3]]), abs=1e-12)


def test_boxes_deep_overlap_takes_the_axis_of_least_penetration():
    # overlap 0.5 along x, 1.8 along y: pushed apart along x
    normal, points, depths, _ = collide_pair((Box(2.0, 2.0), (0, 0), 0.0), (Box(2.0, 2.0), (1.5, 0.2), 0.0))
    assert normal == pytest.approx([1, 0], abs=1e-12)
    order = np.argsort(points[:, 1])
    assert depths[order] == pytest.approx([0.5, 0.5], abs=1e-12)
    # b's left face x = 0.5, y in [-0.8, 1.2], clipped to a's right face y in [-1, 1]; midway x = 0.75
    assert points[order] == pytest.approx(np.array([[0.75, -0.8], [0.75, 1.0]]), abs=1e-12)


def test_rotated_box_on_a_corner_gives_one_point():
    theta = math.radians(30)
    c, s = math.cos(theta), math.sin(theta)
    # the lowest corner of a unit box turned 30 degrees is the local (-0.5, -0.5)
    corner = np.array([-0.5 * c + 0.5 * s, -0.5 * s - 0.5 * c])
    centre = np.array([0.2, 0.49]) - corner  # that corner at (0.2, 0.49): overlap 0.01
    normal, points, depths, _ = collide_pair(FLOOR, (Box(1.0, 1.0), centre, theta))
    assert normal == pytest.approx([0, 1], abs=1e-12)
    assert depths == pytest.approx([0.01], abs=1e-12)
    assert points == pytest.approx(np.array([[0.2, 0.495]]), abs=1e-12)


def test_box_corner_up_into_the_box_above_uses_the_second_box_as_reference():
    # a (below) is turned 30 degrees, its highest corner (local (0.5, 0.5)) 0.01 into b's bottom face
    # y = -0.5: b's face is the reference, the normal still points from a to b
    theta = math.radians(30)
    c, s = math.cos(theta), math.sin(theta)
    corner = np.array([0.5 * c - 0.5 * s, 0.5 * s + 0.5 * c])
    centre = np.array([0.2, -0.49]) - corner
    normal, points, depths, _ = collide_pair((Box(1.0, 1.0), centre, theta), FLOOR)
    assert normal == pytest.approx([0, 1], abs=1e-12)
    assert depths == pytest.approx([0.01], abs=1e-12)
    assert points == pytest.approx(np.array([[0.2, -0.495]]), abs=1e-12)


def test_feature_ids_are_stable_when_a_box_slides_slightly():
    ids = []
    for dx, dy in ((0.0, 0.0), (0.003, 0.0), (0.006, 0.001), (-0.004, -0.002)):
        _, points, _, found = collide_pair(FLOOR, (Box(1.0, 1.0), (0.2 + dx, 0.99 + dy), 0.0))
        assert len(points) == 2
        ids.append(tuple(sorted(found)))
    assert len(set(ids)) == 1
    # the slide keeps each id on the same corner
    _, p0, _, i0 = collide_pair(FLOOR, (Box(1.0, 1.0), (0.2, 0.99), 0.0))
    _, p1, _, i1 = collide_pair(FLOOR, (Box(1.0, 1.0), (0.205, 0.99), 0.0))
    left0 = i0[np.argmin(p0[:, 0])]
    left1 = i1[np.argmin(p1[:, 0])]
    assert left0 == left1


def test_feature_ids_stay_when_the_reference_face_passes_to_the_other_box():
    """A box resting on another, turned by a few milliradians either way: past -0.0015 rad its bottom face
    becomes the reference instead of the lower box's top face. The points are the same corners, so their
    ids stay (with the reference in the id, the swap dropped their impulses: S5's pile jittered)."""
    seen = set()
    lower = (Box(1.0, 1.0), (0, 0), 0.0)
    for theta in np.linspace(-0.003, 0.003, 13):
        _, points, depths, ids = collide_pair(lower, (Box(1.0, 1.0), (0.3, 0.9995), theta))
        order = np.argsort(points[:, 0])
        assert depths[order] == pytest.approx([0.0005 + 0.5 * theta, 0.0005 - 0.2 * theta], abs=1e-5)
        seen.add(tuple(ids[order]))
    assert len(seen) == 1


# ---------------------------------------------------------------------------- box-polygon

def test_box_polygon_tip_into_a_face():
    # a downward triangle, origin at its top edge's middle; tip at (0.2, 0.9) inside a box whose
    # top face is y = 1: one point, depth 0.1
    wedge = Polygon([(-1, 0), (0, -1), (1, 0)])
    normal, points, depths, _ = collide_pair(BOX, (wedge, (0.2, 1.9), 0.0))
    assert normal == pytest.approx([0, 1], abs=1e-12)
    assert depths == pytest.approx([0.1], abs=1e-12)
    assert points == pytest.approx(np.array([[0.2, 0.95]]), abs=1e-12)


def test_polygon_tip_up_into_a_box_above():
    # the polygon is body a, its tip (0.2, 0.9) 0.1 into the bottom face y = 0.8 of the box (b):
    # the box's face is the reference, the normal points from a to b
    wedge = Polygon([(-1, 0), (1, 0), (0, 1)])
    normal, points, depths, _ = collide_pair((wedge, (0.2, -0.1), 0.0), (Box(2.0, 2.0), (0, 1.8), 0.0))
    assert normal == pytest.approx([0, 1], abs=1e-12)
    assert depths == pytest.approx([0.1], abs=1e-12)
    assert points == pytest.approx(np.array([[0.2, 0.85]]), abs=1e-12)


def test_polygon_face_resting_on_a_box():
    # a pentagon ("house") with its floor y = 0 in its own frame, origin at its floor's left end
    house = Polygon([(0, 0), (2, 0), (2, 1), (1, 2), (0, 1)])
    normal, points, depths, _ = collide_pair((house, (-0.5, 0.98), 0.0), BOX)
    # house (a) above the box (b): the normal points down, from a to b
    assert normal == pytest.approx([0, -1], abs=1e-12)
    points, depths = by_x(points, depths)
    assert depths == pytest.approx([0.02, 0.02], abs=1e-12)
    # the house floor x in [-0.5, 1.5] clipped to the box top x in [-1, 1]
    assert points == pytest.approx(np.array([[-0.5, 0.99], [1.0, 0.99]]), abs=1e-12)


# ---------------------------------------------------------------------------- polygon-polygon

def test_polygons_face_contact_clipped():
    # a trapezoid with top face y = 0, x in [-1.5, 1.5]; a pentagon whose floor spans x in [0, 2] at
    # y = -0.05: two points, at x = 0 and at the clip x = 1.5, depth 0.05
    trapezoid = Polygon([(-2, -1), (2, -1), (1.5, 0), (-1.5, 0)])
    house = Polygon([(-1, 0), (1, 0), (1, 1), (0, 2), (-1, 1)])
    normal, points, depths, _ = collide_pair((trapezoid, (0, 0), 0.0), (house, (1, -0.05), 0.0))
    assert normal == pytest.approx([0, 1], abs=1e-12)
    points, depths = by_x(points, depths)
    assert depths == pytest.approx([0.05, 0.05], abs=1e-12)
    assert points == pytest.approx(np.array([[0.0, -0.025], [1.5, -0.025]]), abs=1e-12)


def test_polygons_vertex_into_slanted_face():
    # a hexagon's vertex (circumradius 1, vertex pointing along -x) pokes 0.1 into a triangle's
    # slanted face x + y = 2 (normal (1, 1)/sqrt2)
    hexagon = Polygon([(math.cos(k * math.pi / 3 + math.pi / 4), math.sin(k * math.pi / 3 + math.pi / 4))
                       for k in range(6)])
    # the hexagon's vertex at angle 225 degrees points along -(1, 1)/sqrt2
    tip_local = np.array([math.cos(math.radians(225)), math.sin(math.radians(225))])
    tip = np.array([1.0, 1.0]) - 0.1 * np.array([1, 1]) / S2
    normal, points, depths, _ = collide_pair((TRIANGLE, (0, 0), 0.0), (hexagon, tip - tip_local, 0.0))
    assert normal == pytest.approx([1 / S2, 1 / S2], abs=1e-12)
    assert depths == pytest.approx([0.1], abs=1e-12)
    assert points == pytest.approx(np.array([[1.0, 1.0]]) - 0.05 / S2, abs=1e-12)


def test_polygons_separated_beyond_margin():
    trapezoid = Polygon([(-2, -1), (2, -1), (1.5, 0), (-1.5, 0)])
    _, points, _, _ = collide_pair((trapezoid, (0, 0), 0.0), (TRIANGLE, (0, 0.1), 0.0))
    assert len(points) == 0


def test_boxes_collide_like_the_same_rectangles_as_polygons():
    """Box pairs take a shorter separating axis test: it finds the manifolds polygons would."""
    rng = np.random.default_rng(11)

    def rectangle(w, h):
        return Polygon([(-w / 2, -h / 2), (w / 2, -h / 2), (w / 2, h / 2), (-w / 2, h / 2)])

    found = 0
    for _ in range(300):
        (wa, ha), (wb, hb) = rng.uniform(0.2, 2.0, (2, 2))
        angle_a, angle_b = rng.uniform(-math.pi, math.pi, 2)
        offset = rng.uniform(-1.5, 1.5, 2)
        as_boxes = collide_pair((Box(wa, ha), (0, 0), angle_a), (Box(wb, hb), offset, angle_b), margin=0.05)
        as_polygons = collide_pair((rectangle(wa, ha), (0, 0), angle_a), (rectangle(wb, hb), offset, angle_b),
                                   margin=0.05)
        assert len(as_boxes[1]) == len(as_polygons[1])
        if len(as_boxes[1]):
            found += 1
            np.testing.assert_allclose(as_boxes[0], as_polygons[0], atol=1e-9)
            for got, want in zip(by_x(*as_boxes[1:3]), by_x(*as_polygons[1:3]), strict=True):
                np.testing.assert_allclose(got, want, atol=1e-9)
    assert found > 100  # most of the random pairs touch
