"""Mass, centre of mass and inertia of every shape against closed forms, read through the World."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rustycs import Box, Circle, Material, Polygon, World


def one_body(shape, density=1.0, **kwargs):
    world = World()
    world.add_body(shape, material=Material(density, 0.5, 0.5), **kwargs)
    return world


def test_circle():
    world = one_body(Circle(0.5), density=2.0)
    m = 2.0 * math.pi * 0.25
    assert world.masses[0] == pytest.approx(m, rel=1e-12)
    assert world.inertias[0] == pytest.approx(m * 0.25 / 2, rel=1e-12)


def test_box():
    world = one_body(Box(2.0, 1.0), density=3.0)
    assert world.masses[0] == pytest.approx(6.0, rel=1e-12)
    assert world.inertias[0] == pytest.approx(6.0 * (4 + 1) / 12, rel=1e-12)


def test_right_triangle():
    # legs 3 and 3 from the origin: area 4.5, centroid (1, 1), inertia about it m (a^2 + b^2) / 18
    world = one_body(Polygon([(0, 0), (3, 0), (0, 3)]), density=2.0)
    m = 9.0
    assert world.masses[0] == pytest.approx(m, rel=1e-12)
    assert world.inertias[0] == pytest.approx(m * 18 / 18, rel=1e-12)
    assert world.centers[0] == pytest.approx([1.0, 1.0], abs=1e-12)
    assert world.positions[0] == pytest.approx([0.0, 0.0], abs=1e-12)


def test_clockwise_vertices_give_the_same_body():
    ccw = one_body(Polygon([(0, 0), (3, 0), (0, 3)]))
    cw = one_body(Polygon([(0, 3), (3, 0), (0, 0)]))
    assert cw.masses[0] == pytest.approx(ccw.masses[0], rel=1e-12)
    assert cw.inertias[0] == pytest.approx(ccw.inertias[0], rel=1e-12)
    assert cw.centers[0] == pytest.approx(ccw.centers[0], abs=1e-12)


# The "house": the square [0, 2] x [0, 2] (area 4, centroid (1, 1), I = 4 (4 + 4) / 12 = 8/3) under
# the triangle (0, 2), (2, 2), (1, 3) (area 1, centroid (1, 7/3), I = b h^3/36 + h b^3/48 = 1/18 + 1/6).
# Composite centroid y = (4 * 1 + 1 * 7/3) / 5 = 19/15 (not the vertex average 1.6); by the parallel
# axis theorem I = 8/3 + 4 (4/15)^2 + 2/9 + (16/15)^2 = 194/45 at unit density.
HOUSE = [(0, 0), (2, 0), (2, 2), (1, 3), (0, 2)]
HOUSE_CENTROID = np.array([1.0, 19.0 / 15.0])
HOUSE_INERTIA = 194.0 / 45.0


def test_off_centroid_polygon():
    offset = np.array([3.0, -1.0])  # the body origin lies outside the polygon
    shape = Polygon([(x + offset[0], y + offset[1]) for x, y in HOUSE])
    world = one_body(shape, density=0.5, position=(10.0, 20.0))
    assert world.masses[0] == pytest.approx(2.5, rel=1e-12)
    assert world.inertias[0] == pytest.approx(0.5 * HOUSE_INERTIA, rel=1e-12)
    assert world.centers[0] == pytest.approx(np.array([10.0, 20.0]) + offset + HOUSE_CENTROID, abs=1e-12)
    assert world.positions[0] == pytest.approx([10.0, 20.0], abs=1e-12)
    assert world.local_centers[0] == pytest.approx(offset + HOUSE_CENTROID, abs=1e-12)  # about the origin


def test_off_centroid_polygon_placed_at_an_angle():
    theta = 0.7
    world = one_body(Polygon(HOUSE), position=(1.0, 2.0), angle=theta)
    c, s = math.cos(theta), math.sin(theta)
    centroid = np.array([c * HOUSE_CENTROID[0] - s * HOUSE_CENTROID[1],
                         s * HOUSE_CENTROID[0] + c * HOUSE_CENTROID[1]])
    assert world.centers[0] == pytest.approx(np.array([1.0, 2.0]) + centroid, abs=1e-12)
    assert world.positions[0] == pytest.approx([1.0, 2.0], abs=1e-12)
    assert world.inertias[0] == pytest.approx(HOUSE_INERTIA, rel=1e-12)


def test_explicit_mass_scales_the_inertia():
    world = one_body(Box(2.0, 1.0), density=3.0, mass=10.0)
    assert world.masses[0] == 10.0
    assert world.inertias[0] == pytest.approx(10.0 * 5 / 12, rel=1e-12)
    world = one_body(Polygon(HOUSE), density=3.0, mass=7.0)
    assert world.inertias[0] == pytest.approx(7.0 * HOUSE_INERTIA / 5.0, rel=1e-12)
    world = one_body(Circle(2.0), mass=3.0)
    assert world.inertias[0] == pytest.approx(3.0 * 4.0 / 2, rel=1e-12)


def test_aabb_has_infinite_inertia_and_finite_mass():
    world = one_body(Box(2.0, 1.0, rotates=False), density=3.0)
    assert world.masses[0] == pytest.approx(6.0, rel=1e-12)
    assert world.inertias[0] == math.inf
    assert world.shape_kinds[0] == "aabb"


@pytest.mark.parametrize("body_type", ["static", "kinematic"])
def test_static_and_kinematic_bodies_are_immovable(body_type):
    world = World()
    for shape in (Circle(1.0), Box(1.0, 2.0), Polygon(HOUSE)):
        world.add_body(shape, body_type=body_type)
    assert np.all(world.masses == math.inf)
    assert np.all(world.inertias == math.inf)
    assert list(world.body_types) == [body_type] * 3
