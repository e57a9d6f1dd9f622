"""Names, poses, forces, impulses and removal of bodies between steps, against their physics."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rustycs import Box, Circle, Material, Polygon, World


def _free_world() -> tuple[World, int]:
    """A world without forces and one off-centre body (its origin is not its centre of mass)."""
    world = World(tick_rate=60.0, precision=4)
    body = world.add_body(Polygon([(0, 0), (2, 0), (0, 1)]), position=(1.0, 2.0), name="wedge")
    return world, body


def test_bodies_have_unique_names_given_or_by_shape():
    world = World()
    world.add_body(Circle(0.5), name="ball")
    world.add_body(Box(1, 1))
    world.add_body([Circle(0.2), Circle(0.2, offset=(1, 0))])
    assert world.body_names.tolist() == ["ball", "obb-1", "compound-2"]
    assert world.body_index("obb-1") == 1
    with pytest.raises(ValueError, match="'ball' exists already"):
        world.add_body(Circle(0.5), name="ball")
    with pytest.raises(KeyError, match="did you mean 'ball'"):
        world.body_index("bal")
    assert world.body_count == 3


def test_an_impulse_changes_momentum_by_exactly_its_value():
    world, body = _free_world()
    mass, inertia = world.masses[body], world.inertias[body]
    center = world.centers[body]
    world.apply_impulse("wedge", (3.0, -1.5))  # at the centre of mass: no turn
    assert mass * world.velocities[body] == pytest.approx([3.0, -1.5], rel=1e-15)
    assert world.angular_velocities[body] == 0.0
    point = center + np.array([0.0, 0.5])  # r = (0, 0.5): r x J = -0.5 * 2
    world.apply_impulse(body, (2.0, 0.0), point=point)
    assert mass * world.velocities[body] == pytest.approx([5.0, -1.5], rel=1e-15)
    assert inertia * world.angular_velocities[body] == pytest.approx(-1.0, rel=1e-15)
    world.apply_angular_impulse(body, 1.0)
    assert inertia * world.angular_velocities[body] == pytest.approx(0.0, abs=1e-15)


def test_a_force_over_a_tick_changes_momentum_by_force_times_dt():
    world, body = _free_world()
    mass, inertia = world.masses[body], world.inertias[body]
    world.apply_force(body, (6.0, 12.0))
    world.apply_torque(body, 3.0)
    world.step()
    assert mass * world.velocities[body] == pytest.approx([6.0 / 60, 12.0 / 60], rel=1e-14)
    assert inertia * world.angular_velocities[body] == pytest.approx(3.0 / 60, rel=1e-14)
    world.step()  # the force acted for one tick: the momentum is kept after it
    assert mass * world.velocities[body] == pytest.approx([6.0 / 60, 12.0 / 60], rel=1e-14)


def test_static_and_kinematic_bodies_are_not_pushed():
    world = World()
    wall = world.add_body(Box(1, 1), body_type="static")
    lift = world.add_body(Box(1, 1), position=(3, 0), body_type="kinematic", velocity=(0, 1))
    world.apply_impulse(wall, (5.0, 0.0))
    world.apply_force(lift, (5.0, 0.0))
    world.apply_torque(lift, 5.0)
    assert world.velocities.tolist() == [[0.0, 0.0], [0.0, 1.0]]
    assert world.angular_velocities.tolist() == [0.0, 0.0]


def test_set_position_and_angle_keep_the_origin_and_the_velocities():
    world, body = _free_world()
    world.set_velocity(body, (1.0, 0.0), angular_velocity=0.5)
    local = world.local_centers[body]
    world.set_position("wedge", (-3.0, 4.0))
    assert world.positions[body] == pytest.approx([-3.0, 4.0], abs=1e-15)
    assert world.centers[body] == pytest.approx(np.array([-3.0, 4.0]) + local, abs=1e-15)
    world.set_angle(body, math.pi / 2)
    assert world.positions[body] == pytest.approx([-3.0, 4.0], abs=1e-15)
    assert world.centers[body] == pytest.approx([-3.0 - local[1], 4.0 + local[0]], abs=1e-15)
    assert world.velocities[body].tolist() == [1.0, 0.0]
    assert world.angular_velocities[body] == 0.5
    aabb = world.add_body(Box(1, 1, rotates=False))
    with pytest.raises(ValueError, match="fixed rotation"):
        world.set_angle(aabb, 0.3)


def _ball_over_floor() -> tuple[World, int, int]:
    """A ball 0.5 m over a floor, both of a material that does not bounce."""
    world = World(tick_rate=60.0, precision=4)
    world.add_force((0.0, -9.81))
    dull = Material(density=1.0, restitution=0.0, friction=0.5)
    floor = world.add_body(Box(10, 1), position=(0, -0.5), body_type="static", name="floor", material=dull)
    ball = world.add_body(Circle(0.5), position=(0, 1.0), name="ball", material=dull)
    return world, floor, ball


def test_a_moved_static_body_collides_where_it_was_moved():
    world, floor, ball = _ball_over_floor()
    world.step(60)
    assert world.positions[ball][1] == pytest.approx(0.5, abs=0.01)  # resting on the floor
    world.set_position(floor, (0.0, -2.5))  # the floor drops 2 m: the ball falls onto it again
    world.step(90)
    assert world.positions[ball][1] == pytest.approx(-1.5, abs=0.01)


def test_a_removed_body_stops_colliding_and_moving():
    world, floor, ball = _ball_over_floor()
    world.step(60)
    world.remove_body("floor")
    assert not world.active[floor]
    world.step(30)  # free fall from rest for half a second, no floor: y drops by about g t^2 / 2
    assert world.positions[ball][1] == pytest.approx(0.5 - 9.81 * 0.25 / 2, abs=0.02)
    world.remove_body(ball)
    frozen = world.positions[ball]
    world.step(10)
    assert world.positions[ball].tolist() == frozen.tolist()
    assert world.escaped_count == 0
