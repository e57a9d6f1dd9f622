"""Rotation: an aabb never turns, an obb hit off-centre does, a polygon turns about its centroid."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rustycs import Box, Circle, Material, Polygon, World


def off_centre_hit(rotates: bool, ball_velocity=(5.0, 0.0), friction=0.5):
    """A ball (moving +x) hits a free unit box 0.4 above its centre, in zero gravity.
    Returns the world, the box's angles and angular velocities per tick, and the angular momentum
    before and after."""
    material = Material(1.0, 0.5, friction)
    world = World(tick_rate=60.0)
    box = world.add_body(Box(1.0, 1.0, rotates=rotates), position=(0, 0), material=material)
    world.add_body(Circle(0.2), position=(-3.0, 0.4), velocity=ball_velocity, material=material)
    before = world.observables()["angular_momentum"]
    angles, spins = [], []
    for _ in range(90):
        world.step()
        angles.append(world.angles[box])
        spins.append(world.angular_velocities[box])
    return world, np.array(angles), np.array(spins), before, world.observables()["angular_momentum"]


@pytest.mark.parametrize("ball_velocity", [(5.0, 0.0), (5.0, -1.0)])
def test_aabb_hit_off_centre_never_rotates(ball_velocity):
    world, angles, spins, _, _ = off_centre_hit(rotates=False, ball_velocity=ball_velocity)
    assert np.all(angles == 0.0) and np.all(spins == 0.0)
    assert world.velocities[0][0] > 0.5  # it was hit: pushed along +x


@pytest.mark.parametrize("friction", [0.0, 0.5])
def test_obb_hit_off_centre_rotates(friction):
    world, angles, spins, before, after = off_centre_hit(rotates=True, friction=friction)
    assert world.velocities[0][0] > 0.5
    # the push above the centre turns it clockwise
    assert spins[-1] < -0.5
    assert angles[-1] < -0.3
    # the normal impulse acts at one point on both bodies: angular momentum about the origin is kept;
    # the friction impulse acts at anchors fixed for the tick while the bodies move (an O(dt) drift)
    assert after == pytest.approx(before, rel=1e-9 if friction == 0.0 else 0.01)


def test_polygon_rotates_about_its_centroid_and_its_origin_follows():
    # the off-centroid "house" (centroid (1, 19/15) from its origin), spinning freely
    house = Polygon([(0, 0), (2, 0), (2, 2), (1, 3), (0, 2)])
    world = World(tick_rate=60.0, precision=4)
    world.add_body(house, position=(5.0, 5.0), angular_velocity=1.5)
    centre = world.centers[0]
    world.step(60)
    assert world.centers[0] == pytest.approx(centre, abs=1e-12)
    assert world.angles[0] == pytest.approx(1.5, rel=1e-12)
    c, s = math.cos(1.5), math.sin(1.5)
    offset = -np.array([1.0, 19.0 / 15.0])  # from the centroid to the origin, unrotated
    expected_origin = centre + np.array([c * offset[0] - s * offset[1], s * offset[0] + c * offset[1]])
    assert world.positions[0] == pytest.approx(expected_origin, abs=1e-12)
