"""Ray casts, point and box queries against hand-computed hits on every shape kind."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rustycs import Box, Capsule, Chain, Circle, Polygon, Segment, World


@pytest.fixture(scope="module")
def world() -> World:
    """One body of each shape kind along the x axis (rays are cast along y, from below)."""
    world = World()
    world.add_body(Circle(1.0), position=(0.0, 5.0), name="circle")
    world.add_body(Box(2.0, 1.0), position=(4.0, 5.0), angle=math.pi / 4, name="box")  # a diamond
    world.add_body(Capsule(2.0, 0.5), position=(8.0, 5.0), angle=math.pi / 2, name="capsule")  # upright
    world.add_body(Polygon([(-1, 0), (1, 0), (0, 2)]), position=(12.0, 4.0), name="triangle")
    world.add_body(Segment([(-1, 0), (1, 0)]), position=(16.0, 5.0), body_type="static", name="segment")
    world.add_body(Chain([(-1, 0), (0, 1), (1, 0)]), position=(20.0, 4.0), body_type="static", name="chain")
    world.add_body(Circle(0.5, sensor=True), position=(24.0, 5.0), body_type="static", name="sensor")
    world.add_body(Polygon([(0, 0), (2, 0), (2, 2), (1, 2), (1, 1), (0, 1)]), position=(27.0, 4.0),
                   name="ell")  # concave: two pieces
    return world


def _up(x: float, offset: float = 0.0):
    """A ray straight up at x, from y = 0 to y = 10."""
    return (x + offset, 0.0), (x + offset, 10.0)


@pytest.mark.parametrize("name, x, offset, distance, normal", [
    ("circle", 0.0, 0.6, 5.0 - math.sqrt(1 - 0.36), (0.6, -0.8)),  # off-centre chord: closed form
    ("box", 4.0, 0.0, 5.0 - 1.0 / math.sqrt(2), (math.sqrt(0.5), -math.sqrt(0.5))),  # its lower right face
    ("capsule", 8.0, 0.3, 4.0 - math.sqrt(0.25 - 0.09), (0.6, -0.8)),  # lower end cap
    ("triangle", 12.0, 0.5, 4.0, (0.0, -1.0)),  # base
    ("segment", 16.0, 0.25, 5.0, (0.0, -1.0)),
    ("chain", 20.0, 0.5, 4.5, (-math.sqrt(0.5), -math.sqrt(0.5))),  # the right-hand link, from below
])
def test_closest_hit_of_a_ray_on_every_shape_kind(world, name, x, offset, distance, normal):
    start, end = _up(x, offset)
    hit = world.ray_cast(start, end)
    assert world.body_names[hit.body] == name
    assert hit.distance == pytest.approx(distance, abs=1e-12)
    assert hit.fraction == pytest.approx(distance / 10.0, abs=1e-13)
    assert hit.point == pytest.approx([x + offset, distance], abs=1e-12)
    assert hit.normal == pytest.approx(normal, abs=1e-12)


def test_the_diamond_is_hit_at_its_lower_corner(world):
    # a 2 x 1 box turned 45 degrees: its lowest corner is (-1, -0.5) turned, at y = 5 - 1.5 / sqrt(2)
    hit = world.ray_cast(*_up(4.0 + (-1.0 + 0.5) / math.sqrt(2)))
    assert hit.distance == pytest.approx(5.0 - 1.5 / math.sqrt(2), abs=1e-12)


def test_misses_sensors_and_rays_that_stop_short(world):
    for start, end in [((2.0, 0.0), (2.0, 10.0)),  # between the circle and the diamond
                       ((0.0, 0.0), (0.0, 3.9)),  # stops 0.1 below the circle
                       ((24.0, 0.0), (24.0, 10.0)),  # a sensor is passed through
                       ((-5.0, 5.0), (-5.0, 5.0))]:  # a ray of no length outside every shape
        hit = world.ray_cast(start, end)
        assert hit.body == -1 and hit.shape == -1 and hit.fraction == math.inf
        assert np.isnan(hit.point).all()
    assert world.body_names[world.ray_cast((24.0, 0.0), (24.0, 10.0), sensors=True).body] == "sensor"


def test_a_ray_starting_inside_a_shape_hits_it_at_its_start(world):
    hit = world.ray_cast((0.2, 5.0), (0.2, 10.0))
    assert (hit.body, hit.fraction, hit.distance) == (0, 0.0, 0.0)
    assert hit.normal == pytest.approx([0.0, -1.0])


def test_all_hits_along_a_ray_sorted_by_distance():
    world = World()
    for k in range(10):  # discs of radius 0.5 at x = 2, 4, ..., 20 on the x axis
        world.add_body(Circle(0.5), position=(2.0 * (k + 1), 0.0))
    # more hits than the first guess of room (4 per ray): the call makes room and asks again
    ray, hits = world.ray_cast_all([(0.0, 0.0), (0.0, 1.0)], [(21.0, 0.0), (21.0, 1.0)])
    assert ray.tolist() == [0] * 10
    assert hits.body.tolist() == list(range(10))
    assert hits.distance == pytest.approx(2.0 * np.arange(10) + 1.5, abs=1e-12)
    assert hits.normal == pytest.approx(np.tile([-1.0, 0.0], (10, 1)), abs=1e-12)


def test_a_fan_of_rays_in_one_call_matches_single_casts(world):
    angles = np.linspace(0.05, math.pi - 0.05, 301)
    starts = np.tile([13.0, -2.0], (len(angles), 1))
    ends = starts + 40.0 * np.stack([np.cos(angles), np.sin(angles)], axis=1)
    batch = world.ray_cast(starts, ends)
    assert (batch.body >= 0).sum() > 50  # the fan sweeps over the row of shapes
    for k in range(0, len(angles), 10):
        one = world.ray_cast(starts[k], ends[k])
        assert (one.body, one.fraction) == (batch.body[k], batch.fraction[k])
    # brute force over every body: the nearest of the single-body worlds' hits
    for k in range(0, len(angles), 30):
        best = min(world.ray_cast_all(starts[k], ends[k])[1].fraction.tolist() or [math.inf])
        assert batch.fraction[k] == best


def test_point_query_finds_the_shape_holding_each_point(world):
    points = [(0.5, 5.5), (4.0, 5.0), (8.0, 6.2), (8.0, 6.6), (12.0, 5.9), (16.0, 5.0), (28.5, 5.5),
              (27.5, 5.5), (-3.0, 0.0)]
    bodies = world.point_query(points)
    names = [world.body_names[b] if b >= 0 else None for b in bodies]
    # the capsule's upper cap ends at 5 + 1 + 0.5; the segment holds no point; the L's notch is empty
    assert names == ["circle", "box", "capsule", None, "triangle", None, "ell", None, None]
    assert world.point_query((24.0, 5.0)) == -1
    assert world.body_names[world.point_query((24.0, 5.0), sensors=True)] == "sensor"


def test_aabb_query_finds_bodies_whose_boxes_overlap(world):
    found = world.aabb_query((3.0, 4.0), (9.0, 4.5))
    assert world.body_names[found].tolist() == ["box", "capsule"]
    assert world.aabb_query((100, 100), (101, 101)).tolist() == []


def test_removed_bodies_are_not_found():
    world = World()
    world.add_body(Circle(1.0), position=(0.0, 5.0))
    world.add_body(Circle(1.0), position=(0.0, 8.0))
    world.remove_body(0)
    assert world.ray_cast((0.0, 0.0), (0.0, 10.0)).body == 1
    assert world.point_query((0.0, 5.0)) == -1


def test_the_mask_keeps_the_shapes_of_its_categories():
    world = World()
    world.add_body(Circle(1.0), position=(0.0, 5.0), collision_category=0b10)
    world.add_body(Circle(1.0), position=(0.0, 8.0), collision_category=0b01)
    assert world.ray_cast((0.0, 0.0), (0.0, 10.0)).body == 0
    assert world.ray_cast((0.0, 0.0), (0.0, 10.0), mask=0b01).body == 1
    assert world.aabb_query((-1, 0), (1, 10), mask=0b10).tolist() == [0]
