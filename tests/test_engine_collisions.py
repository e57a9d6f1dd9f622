"""Collisions against textbook results: bounce heights, head-on elastic and inelastic impacts.

Restitution mixes by the mean of the two materials; the approach speeds here are above the
restitution threshold, except in the test of the threshold itself.
"""

from __future__ import annotations

import numpy as np
import pytest

from rustycs import MATERIALS, Box, Circle, Material, World


def rebound_height(ball: str, floor: str, drop: float, radius: float = 0.25) -> float:
    """Highest point of the ball's bottom after its first bounce, dropped from `drop` above the floor."""
    world = World(tick_rate=60.0, precision=10)
    world.add_force((0.0, -9.81))
    world.add_body(Box(10.0, 1.0), position=(0, -0.5), body_type="static", material=floor)
    b = world.add_body(Circle(radius), position=(0, drop + radius), material=ball)
    bounced = False
    apex = -np.inf
    for _ in range(300):
        world.step()
        vy = world.velocities[b][1]
        if vy > 0:
            bounced = True
            apex = max(apex, world.centers[b][1] - radius)
        elif bounced:
            return apex
    raise AssertionError("the ball never came back down")


@pytest.mark.parametrize("ball, floor", [("rubber", "rubber"), ("rubber", "stone"), ("default", "default"),
                                         ("stone", "stone"), ("metal", "rubber")])
def test_bounce_height_is_restitution_squared_times_drop(ball, floor):
    drop = 2.0
    e = 0.5 * (MATERIALS[ball].restitution + MATERIALS[floor].restitution)
    assert rebound_height(ball, floor, drop) == pytest.approx(e * e * drop, rel=0.10)


def head_on(m1, m2, u1, u2, restitution, threshold=0.1):
    """Two circles approaching along x in zero gravity; returns final velocities and momenta."""
    world = World(tick_rate=60.0, restitution_threshold=threshold)
    material = Material(1.0, restitution, 0.0)
    world.add_body(Circle(0.5), position=(-2.0, 0.0), velocity=(u1, 0.0), mass=m1, material=material)
    world.add_body(Circle(0.5), position=(2.0, 0.0), velocity=(u2, 0.0), mass=m2, material=material)
    before = world.observables()["linear_momentum"]
    meet = 3.0 / (u1 - u2)  # the gap is 3 m
    world.step(int(60 * (2 * meet + 0.5)))
    after = world.observables()["linear_momentum"]
    assert world.centers[1][0] - world.centers[0][0] >= 1.0 - 0.01  # they did not pass through
    return world.velocities, world.angular_velocities, before, after


def assert_momentum_conserved(before, after):
    assert np.linalg.norm(after - before) <= 1e-9 * np.linalg.norm(before)


@pytest.mark.parametrize("m1, m2, u1, u2", [(1.0, 1.0, 4.0, 0.0), (2.0, 2.0, 3.0, -1.5),
                                            (1.0, 3.0, 4.0, 0.0), (3.0, 1.0, 4.0, -1.0)])
def test_elastic_head_on(m1, m2, u1, u2):
    v, w, before, after = head_on(m1, m2, u1, u2, restitution=1.0)
    v1 = ((m1 - m2) * u1 + 2 * m2 * u2) / (m1 + m2)
    v2 = ((m2 - m1) * u2 + 2 * m1 * u1) / (m1 + m2)
    assert v[0, 0] == pytest.approx(v1, abs=0.01 * abs(u1 - u2))
    assert v[1, 0] == pytest.approx(v2, abs=0.01 * abs(u1 - u2))
    assert np.all(v[:, 1] == 0.0) and np.all(w == 0.0)
    assert_momentum_conserved(before, after)


@pytest.mark.parametrize("m1, m2, u1, u2", [(1.0, 3.0, 4.0, 0.0), (2.0, 1.0, 3.0, -3.0)])
def test_inelastic_head_on_ends_at_the_common_velocity(m1, m2, u1, u2):
    v, _, before, after = head_on(m1, m2, u1, u2, restitution=0.0)
    common = (m1 * u1 + m2 * u2) / (m1 + m2)
    assert v[:, 0] == pytest.approx([common, common], abs=0.01 * abs(u1 - u2))
    assert_momentum_conserved(before, after)


def test_partially_elastic_head_on():
    v, _, before, after = head_on(1.0, 1.0, 4.0, 0.0, restitution=0.5)
    # e = 0.5: separation speed 2 from approach speed 4, common momentum 4
    assert v[:, 0] == pytest.approx([1.0, 3.0], abs=0.04)
    assert_momentum_conserved(before, after)


def test_approach_slower_than_the_threshold_does_not_bounce():
    v, _, before, after = head_on(1.0, 1.0, 0.5, 0.0, restitution=1.0, threshold=1.0)
    assert v[:, 0] == pytest.approx([0.25, 0.25], abs=0.005)
    assert_momentum_conserved(before, after)


def test_kinematic_body_pushes_a_dynamic_body_and_keeps_its_velocity():
    world = World(tick_rate=60.0)
    material = Material(1.0, 0.0, 0.5)
    pusher = world.add_body(Box(1.0, 1.0), position=(-2.0, 0.0), velocity=(1.5, 0.0), body_type="kinematic",
                            material=material)
    crate = world.add_body(Box(1.0, 1.0), position=(0.0, 0.0), material=material)
    world.step(120)
    assert np.array_equal(world.velocities[pusher], [1.5, 0.0])
    assert world.centers[pusher] == pytest.approx([1.0, 0.0], abs=1e-9)
    # pushed ahead of it at its speed (restitution 0), touching it
    assert world.velocities[crate] == pytest.approx([1.5, 0.0], abs=0.015)
    assert world.centers[crate][0] - world.centers[pusher][0] == pytest.approx(1.0, abs=0.01)


@pytest.mark.parametrize("material", ["rubber", "default"])
def test_box_dropped_flat_rebounds_like_a_ball_without_spinning(material):
    # beyond the list: the bounce test with a box landing on its face (a two-point manifold)
    drop = 2.0
    world = World(tick_rate=60.0, precision=10)
    world.add_force((0.0, -9.81))
    world.add_body(Box(10.0, 1.0), position=(0, -0.5), body_type="static", material=material)
    box = world.add_body(Box(1.0, 0.5), position=(0, drop + 0.25), material=material)
    bounced = False
    apex = -np.inf
    spin = 0.0
    for _ in range(120):
        world.step()
        spin = max(spin, abs(world.angular_velocities[box]))
        if world.velocities[box][1] > 0:
            bounced = True
            apex = max(apex, world.centers[box][1] - 0.25)
        elif bounced:
            break
    e = MATERIALS[material].restitution
    assert apex == pytest.approx(e * e * drop, rel=0.10)
    assert spin < 0.05
