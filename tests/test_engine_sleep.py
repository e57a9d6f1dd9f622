"""Sleeping islands (issue 17): piles at rest sleep and cost next to nothing, wake where they slept when
something reaches them, and leave the results of worlds where nothing rests unchanged."""

from __future__ import annotations

import numpy as np
import pytest

from rustycs import Box, Circle, Material, World

STICKY = Material(1.0, 0.0, 0.6)


def stack(sleep: bool, boxes: int = 6, **world) -> World:
    """A column of unit boxes on a static floor, exactly touching (bodies 1 .. boxes)."""
    w = World(tick_rate=60.0, precision=4, sleep=sleep, **world)
    w.add_force((0.0, -9.81))
    w.add_body(Box(20.0, 1.0), position=(0.0, -0.5), body_type="static", material=STICKY)
    for k in range(boxes):
        w.add_body(Box(1.0, 1.0), position=(0.0, 0.5 + k), material=STICKY)
    return w


def pyramid(sleep: bool, base: int = 10) -> World:
    w = World(tick_rate=60.0, precision=4, sleep=sleep)
    w.add_force((0.0, -9.81))
    w.add_body(Box(40.0, 1.0), position=(0.0, -0.5), body_type="static", material=STICKY)
    for row in range(base):
        n = base - row
        for i in range(n):
            w.add_body(Box(1.0, 1.0), position=(i - (n - 1) / 2.0, 0.5 + row), material=STICKY)
    return w


def test_a_pile_at_rest_falls_asleep_after_sleep_time_and_keeps_its_contacts():
    world = pyramid(sleep=True)
    world.step(20)  # resting from the start: 30 ticks of rest at 60 Hz put it to sleep
    assert not world.asleep.any()
    while not world.asleep.any():
        world.step(1)
    assert 30 <= world.tick <= 35  # 0.5 s of rest, the first ticks settling the pile
    assert world.asleep[1:].all() and not world.asleep[0]  # the static floor never sleeps
    seen = world.observables()
    contacts = world.contacts()
    assert seen["kinetic_energy"] == 0.0 and seen["max_speed"] == 0.0
    assert seen["contact_count"] == len(contacts["point"]) > 100
    before = world.centers
    world.step(200)
    # asleep, the pile's state and its observables are what they were when it fell asleep
    np.testing.assert_array_equal(world.centers, before)
    later = world.observables()
    for name, value in seen.items():
        np.testing.assert_array_equal(later[name], value, err_msg=name)
    for name, values in world.contacts().items():
        np.testing.assert_array_equal(values, contacts[name])


def test_an_island_sleeps_only_once_all_its_bodies_rested_sleep_time():
    world = stack(sleep=True, sleep_time=1.0)
    world.step(55)
    assert not world.asleep.any()
    world.step(10)
    assert world.asleep[1:].all()


def test_a_world_where_nothing_rests_steps_bitwise_as_without_sleep():
    """Balls bouncing elastically in a box never rest: sleeping changes nothing, bit for bit."""
    states = []
    for sleep in (False, True):
        world = World(tick_rate=60.0, precision=4, sleep=sleep, restitution_threshold=0.0)
        world.add_force((0.0, -9.81))
        bouncy = Material(1.0, 1.0, 0.0)
        for x, y, w, h in ((0, -0.5, 12, 1), (0, 10.5, 12, 1), (-6.5, 5, 1, 12), (6.5, 5, 1, 12)):
            world.add_body(Box(w, h), position=(x, y), body_type="static", material=bouncy)
        for k in range(12):
            world.add_body(Circle(0.3), position=(-4.5 + 0.8 * k, 2.0 + 0.5 * (k % 4)),
                           velocity=(3.0 - 0.5 * k, 1.0), material=bouncy)
        world.step(600)
        assert not world.asleep.any()
        states.append((world.centers, world.velocities, world.angular_velocities))
    for a, b in zip(*states, strict=True):
        np.testing.assert_array_equal(a, b)


def test_a_sleeping_stack_hit_by_a_ball_wakes_and_the_same_boxes_fall():
    fallen = []
    for sleep in (False, True):
        world = stack(sleep, boxes=8)
        world.step(60)
        assert world.asleep[1:].all() == sleep
        ball = world.add_body(Circle(0.4), position=(-8.0, 6.5), velocity=(16.0, 2.0),
                              material=Material(5.0, 0.2, 0.3))
        world.step(240)
        assert not world.asleep[1:9].all()  # hit: the island woke (it may have gone back to sleep)
        fallen.append(world.centers[1:9, 1] < np.arange(8) + 0.4)  # boxes well below their places
        assert world.centers[ball][0] > -8.0
    assert fallen[0].sum() >= 3  # the blow topples the upper boxes
    np.testing.assert_array_equal(fallen[0], fallen[1])


def test_it_wakes_where_it_slept_with_the_impulses_it_slept_with():
    world = stack(sleep=True)
    world.step(59)
    before = world.contacts()
    world.step(1)
    assert world.asleep[1:].all()
    np.testing.assert_array_equal(world.contacts()["normal_impulse"], before["normal_impulse"])
    rest = world.centers
    world.wake()
    world.step(1)
    after = world.contacts()
    assert not world.asleep.any()
    # warm-started with what it slept with, the stack carries its weight at once: nothing sags
    np.testing.assert_allclose(after["normal_impulse"], before["normal_impulse"], rtol=0.02)
    assert np.abs(world.centers - rest).max() < 1e-5


def test_a_body_on_a_kinematic_platform_that_starts_moving_wakes():
    world = World(tick_rate=60.0, precision=4, sleep=True)
    world.add_force((0.0, -9.81))
    platform = world.add_body(Box(4.0, 0.5), position=(0.0, -0.25), body_type="kinematic", material=STICKY)
    crate = world.add_body(Box(1.0, 1.0), position=(0.0, 0.5), material=STICKY)
    world.step(60)
    assert world.asleep[crate]
    world.set_velocity(platform, (1.0, 0.0))
    assert world.asleep[crate]  # the kinematic body is not the crate: it wakes when the platform reaches it
    world.step(1)
    assert not world.asleep[crate]
    world.step(59)
    # carried along by friction: it slips while friction (0.6 g) brings it up to speed, then rides
    assert world.velocities[crate][0] == pytest.approx(1.0, abs=0.01)
    assert world.centers[crate][0] == pytest.approx(1.0 - 1.0 ** 2 / (2 * 0.6 * 9.81), abs=0.02)


def test_a_pendulum_at_rest_sleeps_and_wakes_when_its_kinematic_pivot_moves():
    world = World(tick_rate=60.0, precision=4, sleep=True)
    world.add_force((0.0, -9.81))
    pivot = world.add_body(Circle(0.1), position=(0.0, 2.0), body_type="kinematic")
    bob = world.add_body(Circle(0.2), position=(0.0, 1.0))
    world.add_revolute(pivot, bob, (0.0, 2.0))
    world.step(60)
    assert world.asleep[bob]
    world.set_velocity(pivot, (2.0, 0.0))
    world.step(1)
    assert not world.asleep[bob]
    world.step(30)
    assert world.centers[bob][0] > 0.3  # dragged along by the joint (it would stay at 0 asleep)


def test_pushing_moving_or_removing_a_body_and_changing_the_forces_wake_its_island():
    world = stack(sleep=True)
    world.step(60)
    world.apply_impulse(3, (1.0, 0.0))
    assert not world.asleep[1:].any()
    world.step(200)
    assert world.asleep[1:].all()
    world.remove_body(1)  # the bottom box: the others must fall
    assert not world.asleep[2:].any()
    world.step(30)
    assert world.centers[2][1] < 1.2
    world.step(200)
    assert world.asleep[2:].all()
    world.add_force((1.0, 0.0))
    assert not world.asleep.any()


def test_a_body_removed_by_its_lifetime_wakes_the_island_it_slept_in():
    world = stack(sleep=True, boxes=0)
    world.add_body(Box(1.0, 1.0), position=(0.0, 0.5), material=STICKY, remove_tick=90)
    top = world.add_body(Box(1.0, 1.0), position=(0.0, 1.5), material=STICKY)
    world.step(80)
    assert world.asleep[top]
    world.step(30)
    assert not world.active[1] and world.centers[top][1] < 1.2


def test_sleeping_is_deterministic():
    runs = []
    for _ in range(2):
        world = pyramid(sleep=True, base=8)
        ball = world.add_body(Circle(0.3), position=(-9.0, 3.0), velocity=(12.0, 0.0))
        world.step(400)
        runs.append((world.centers, world.asleep, world.velocities[ball]))
    for a, b in zip(*runs, strict=True):
        np.testing.assert_array_equal(a, b)


def test_ticks_in_which_nothing_moves_change_nothing():
    """A sleeping world in which nothing moves skips the stages of its ticks: pushed after 100 such ticks,
    it goes on bitwise as pushed after one."""
    early, late = stack(sleep=True), stack(sleep=True)
    for world, rest in ((early, 1), (late, 100)):
        world.step(60)
        assert world.asleep[1:].all()
        world.step(rest)
        world.set_velocity(6, (3.0, 0.0))  # the top box, pushed: its island wakes
        world.step(60)
    assert early.tick + 99 == late.tick
    assert not early.asleep.any()
    np.testing.assert_array_equal(early.centers, late.centers)
    np.testing.assert_array_equal(early.velocities, late.velocities)
    np.testing.assert_array_equal(early.angles, late.angles)
    assert early.centers[6][0] > 0.5  # the push moved the top box
