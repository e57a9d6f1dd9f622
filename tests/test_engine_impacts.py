"""Impacts (issue 12): restitution through touching bodies, and the friction of an impact.

60 Hz ticks at precision 4 (Box2D's 4 substeps), the settings the issue measured the peers with.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rustycs import Box, Circle, Material, World

ELASTIC = Material(1.0, 1.0, 0.0)  # restitution 1, no friction


def test_newtons_cradle_hands_the_first_balls_speed_to_the_last():
    world = World(tick_rate=60.0, precision=4, restitution_threshold=0.0)
    first = world.add_body(Circle(0.25), position=(-0.5, 0.0), velocity=(1.0, 0.0), material=ELASTIC)
    row = [world.add_body(Circle(0.25), position=(0.5 * i, 0.0), material=ELASTIC) for i in range(1, 5)]
    world.step(120)
    speeds = world.velocities[[first, *row], 0]
    assert speeds == pytest.approx([0.0, 0.0, 0.0, 0.0, 1.0], abs=0.05)
    assert np.sum(speeds) == pytest.approx(1.0, abs=1e-12)  # momentum


def test_a_touching_billiards_rack_keeps_its_energy():
    world = World(tick_rate=60.0, precision=4, restitution_threshold=0.0)
    r = 0.0286  # a pool ball, m
    for row in range(5):
        for k in range(row + 1):
            world.add_body(Circle(r), position=(row * r * math.sqrt(3), (k - row / 2) * 2 * r),
                           material=ELASTIC)
    world.add_body(Circle(r), position=(-1.0, 0.0), velocity=(5.0, 0.0), material=ELASTIC)
    energy = world.observables()["kinetic_energy"]
    world.step(120)
    assert world.observables()["kinetic_energy"] / energy >= 0.99


@pytest.mark.parametrize("order", [(0, 1, 2), (2, 1, 0), (1, 0, 2), (0, 2, 1)])
def test_three_balls_meeting_in_one_tick_keep_their_energy_in_any_order(order):
    # a fast ball meets two nearly touching ones in one tick (from the elastic gas, tick 3503): the soft
    # step pushes the two apart, the sequence of collisions never does; while that push stood they left
    # with 2.9-3.6 % more energy in three of these four orders of rows
    balls = [((-3.165, 3.8098), (7.4721, -2.3974)), ((-2.7173, 3.5647), (-0.0696, -1.4869)),
             ((-2.7424, 3.9711), (2.6552, -3.5523))]
    world = World(tick_rate=60.0, precision=4, restitution_threshold=0.0)
    for k in order:
        world.add_body(Circle(0.2), position=balls[k][0], velocity=balls[k][1], material=ELASTIC)
    energy, momentum = world.observables()["kinetic_energy"], world.velocities.sum(axis=0)
    world.step(1)
    assert world.observables()["kinetic_energy"] / energy == pytest.approx(1.0, abs=1e-6)
    assert world.velocities.sum(axis=0) == pytest.approx(momentum, abs=1e-12)
    assert np.any(world.velocities != [b[1] for b in (balls[k] for k in order)])  # they met


def test_an_elastic_gas_keeps_its_energy_for_a_minute():
    world = World(tick_rate=60.0, precision=4, restitution_threshold=0.0)
    for x, y, width, height in ((0, -5.25, 11, 0.5), (0, 5.25, 11, 0.5), (-5.25, 0, 0.5, 11),
                                (5.25, 0, 0.5, 11)):
        world.add_body(Box(width, height), position=(x, y), body_type="static", material=ELASTIC)
    rng = np.random.default_rng(1)
    for i in range(10):
        for j in range(10):
            heading = rng.uniform(0, 2 * math.pi)
            world.add_body(Circle(0.2), position=(-4.5 + i, -4.5 + j),
                           velocity=(3 * math.cos(heading), 3 * math.sin(heading)), material=ELASTIC)
    energy = world.observables()["kinetic_energy"]
    world.step(3600)
    # 0.9999998 (seeds 1-4): every impact of the gas, three balls meeting in one tick too, is a sequence
    # of elastic collisions (it drifted by up to 1.2 % while the soft step's pushes stood in them)
    assert world.observables()["kinetic_energy"] / energy == pytest.approx(1.0, abs=1e-5)


def test_a_disc_hitting_a_slope_leaves_rolling_with_two_thirds_of_its_tangential_speed():
    slope = math.radians(30)
    world = World(tick_rate=60.0, precision=4)
    world.add_force((0.0, -9.81))
    material = Material(1.0, 0.8, 0.5)
    world.add_body(Box(40, 1.0), angle=slope, body_type="static", material=material)
    r = 0.25
    normal = np.array([-math.sin(slope), math.cos(slope)])
    tangent = np.array([math.cos(slope), math.sin(slope)])
    touch = normal * (0.5 + r)  # the centre where the disc touches the slope
    disc = world.add_body(Circle(r), position=(touch[0], touch[1] + 2.0), material=material)  # 6.26 m/s
    arrival = math.sqrt(2 * 9.81 * 2.0)
    for _ in range(120):
        world.step()
        if world.velocities[disc] @ normal > 0.5:  # it left the slope
            break
    down = -world.velocities[disc] @ tangent
    slip = down - world.angular_velocities[disc] * r
    assert down == pytest.approx(2.0 / 3.0 * arrival * math.sin(slope), rel=0.02)  # 2.088 m/s
    assert abs(slip) < 0.05


def test_a_box_bouncing_flat_stays_straight():
    world = World(tick_rate=60.0, precision=4)
    world.add_force((0.0, -9.81))
    material = Material(1.0, 0.5, 0.5)
    world.add_body(Box(20, 1.0), position=(0, -0.5), body_type="static", material=material)
    box = world.add_body(Box(1.0, 0.5), position=(0, 2.0), material=material)
    sideways = 0.0
    bounced = False
    for _ in range(180):
        world.step()
        sideways = max(sideways, abs(world.velocities[box][0]))
        bounced = bounced or world.velocities[box][1] > 1.0
    assert bounced
    assert sideways < 0.02
