"""Joints against closed forms: pendulum periods, springs, motors, limits, ropes, chains, welds, gears,
pulleys, breaking and reactions; and bitwise determinism of a jointed scene."""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest

from rustycs import Box, Circle, Material, World

G = 9.81
DENSE = Material(1000.0, 0.0, 0.5)


def gravity_world(tick_rate: float = 240.0, precision: int = 4) -> World:
    world = World(tick_rate=tick_rate, precision=precision)
    world.add_force((0.0, -G))
    return world


def crossings(values: np.ndarray, dt: float) -> np.ndarray:
    """Times where the values change sign, interpolated between samples."""
    k = np.nonzero(np.sign(values[:-1]) != np.sign(values[1:]))[0]
    return (k + values[k] / (values[k] - values[k + 1])) * dt


def test_a_small_angle_pendulum_swings_with_period_two_pi_sqrt_l_over_g():
    length, theta = 1.0, 0.05
    world = gravity_world()
    bob = world.add_body(Circle(0.02), position=(length * math.sin(theta), -length * math.cos(theta)),
                         material=DENSE)
    world.add_distance(None, bob, [(0.0, 0.0), world.positions[bob]])
    x = []
    for _ in range(240 * 8):
        world.step(1)
        x.append(world.positions[bob][0])
    period = 2.0 * np.mean(np.diff(crossings(np.array(x), world.dt)))
    # a disc, not a point: its own inertia lengthens the period by r^2 / (4 L^2), 1e-4 here
    assert period == pytest.approx(2.0 * math.pi * math.sqrt(length / G), rel=0.005)


def rod_pendulum(length: float = 2.0) -> tuple[World, int]:
    """A thin rod hinged at its left end to the world, released horizontal."""
    world = gravity_world()
    rod = world.add_body(Box(length, 0.02), position=(length / 2, 0.0), material=DENSE)
    world.add_revolute(None, rod, (0.0, 0.0))
    return world, rod


def test_a_rod_released_horizontal_swings_with_the_elliptic_period_and_keeps_its_energy():
    length = 2.0
    world, rod = rod_pendulum(length)
    elliptic_k = 1.8540746773013719  # K(sin 45 degrees), the complete elliptic integral of the first kind
    small = 2.0 * math.pi * math.sqrt(2.0 * length / (3.0 * G))  # I = m L^2 / 3 about the end, d = L / 2
    expected = small * 2.0 / math.pi * elliptic_k
    energy0 = sum(world.observables()[key] for key in ("kinetic_energy", "potential_energy"))
    angles, energies = [], []
    for _ in range(int(8.4 * expected / world.dt)):
        world.step(1)
        angles.append(world.angles[rod] + math.pi / 2)  # about the hanging position
        observed = world.observables()
        energies.append(observed["kinetic_energy"] + observed["potential_energy"])
    swings = crossings(np.array(angles), world.dt)
    assert len(swings) >= 16
    assert 2.0 * np.mean(np.diff(swings)) == pytest.approx(expected, rel=0.01)
    swing = world.masses[rod] * G * length / 2  # the energy the fall turns into motion
    assert np.max(np.abs(np.array(energies) - energy0)) < 0.02 * swing


def test_a_double_pendulum_keeps_its_energy_for_twenty_seconds():
    world = gravity_world(tick_rate=480)
    upper = world.add_body(Box(1.0, 0.05), position=(0.5, 0.0), material=DENSE)
    lower = world.add_body(Box(1.0, 0.05), position=(1.5, 0.0), material=DENSE)
    world.add_revolute(None, upper, (0.0, 0.0))
    world.add_revolute(upper, lower, (1.0, 0.0))
    observed = world.observables()
    energy0 = observed["kinetic_energy"] + observed["potential_energy"]
    hanging = -world.masses[upper] * G * 0.5 - world.masses[lower] * G * 1.5
    scale = abs(observed["potential_energy"] - hanging)
    worst = 0.0
    for _ in range(40):
        world.step(240)
        observed = world.observables()
        worst = max(worst, abs(observed["kinetic_energy"] + observed["potential_energy"] - energy0))
    assert worst < 0.02 * scale  # against the energy the swing can turn into motion
    assert abs(world.angles[lower] - world.angles[upper]) > 0.1  # it did swing chaotically


def test_a_mass_on_a_spring_oscillates_at_the_springs_hertz():
    hertz = 2.0
    world = World(tick_rate=240, precision=4)
    bob = world.add_body(Circle(0.1), position=(1.2, 0.0), material=DENSE)
    world.add_distance(None, bob, [(0.0, 0.0), (1.2, 0.0)], length=1.0, spring_hertz=hertz)
    x = []
    for _ in range(240 * 4):
        world.step(1)
        x.append(world.positions[bob][0] - 1.0)
    period = 2.0 * np.mean(np.diff(crossings(np.array(x), world.dt)))
    assert period == pytest.approx(1.0 / hertz, rel=0.02)
    assert max(x[-120:]) > 0.15  # undamped: it still swings by almost its start


def test_a_motor_reaches_its_speed_and_a_torque_limited_one_accelerates_at_max_torque_over_inertia():
    world = World(tick_rate=240, precision=4)
    wheel = world.add_body(Circle(0.5), material=DENSE)
    torque = 20.0
    world.add_revolute(None, wheel, (0.0, 0.0), motor_speed=10.0, max_motor_torque=torque)
    alpha = torque / world.inertias[wheel]
    world.step(24)
    assert world.angular_velocities[wheel] == pytest.approx(alpha * 0.1, rel=0.02)
    world.step(int(240 * 10.0 / alpha))
    assert world.angular_velocities[wheel] == pytest.approx(10.0, rel=1e-6)
    strong = World(tick_rate=240, precision=4)
    wheel = strong.add_body(Circle(0.5), material=DENSE)
    strong.add_revolute(None, wheel, (0.0, 0.0), motor_speed=-3.0, max_motor_torque=1e9)
    strong.step(1)
    assert strong.angular_velocities[wheel] == pytest.approx(-3.0, rel=1e-9)


def test_revolute_and_prismatic_limits_hold_under_load():
    world = gravity_world()
    arm = world.add_body(Box(1.0, 0.1), position=(0.5, 0.0), material=DENSE)
    hinge = world.add_revolute(None, arm, (0.0, 0.0), limits=(-0.5, 0.25))
    world.add_body(Box(0.4, 0.4), position=(0.8, 0.3), material=DENSE)  # a load on the arm's end
    lowest = 0.0
    for _ in range(480):
        world.step(1)
        lowest = min(lowest, world.joint_coordinates[hinge])
    assert lowest > -0.5 - 0.01
    assert world.joint_coordinates[hinge] == pytest.approx(-0.5, abs=0.01)  # resting on its lower limit
    slider_world = gravity_world()
    block = slider_world.add_body(Box(0.5, 0.5), position=(0.0, 0.0), material=DENSE)
    slide = slider_world.add_prismatic(None, block, (0.0, 0.0), (0.0, 1.0), limits=(-1.0, 1.0))
    slider_world.step(240)
    assert slider_world.joint_coordinates[slide] == pytest.approx(-1.0, abs=0.005)
    assert slider_world.positions[block][0] == pytest.approx(0.0, abs=1e-9)  # only along the axis
    assert slider_world.angles[block] == pytest.approx(0.0, abs=1e-9)


def test_a_rope_catches_a_falling_bob_at_its_length():
    world = gravity_world()
    bob = world.add_body(Circle(0.05), position=(0.3, 0.0), material=DENSE)
    rope = world.add_rope(None, bob, [(0.0, 0.0), (0.3, 0.0)], length=1.0)
    distances = []
    for _ in range(480):
        world.step(1)
        distances.append(world.joint_coordinates[rope])
    assert min(distances[:20]) < 0.5  # slack at first: it falls freely
    assert max(distances) < 1.0 * 1.01
    assert distances[-1] == pytest.approx(1.0, abs=0.01)


def test_a_chain_of_twenty_links_holding_ten_times_a_links_mass_stretches_less_than_one_percent():
    world = gravity_world(tick_rate=60, precision=4)
    link_length = 0.5
    links = []
    previous = None
    for k in range(20):
        link = world.add_body(Box(link_length, 0.1), position=(0.0, -(k + 0.5) * link_length),
                              angle=math.pi / 2, material=DENSE, collision_group=1)
        world.add_revolute(previous, link, (0.0, -k * link_length))
        links.append(link)
        previous = link
    bob_mass = 10.0 * world.masses[links[0]]
    bob = world.add_body(Circle(0.2), position=(0.0, -20 * link_length), mass=bob_mass, collision_group=1)
    world.add_revolute(previous, bob, (0.0, -20 * link_length))
    world.step(300)
    stretch = -world.positions[bob][1] / (20 * link_length) - 1.0
    assert 0.0 <= stretch < 0.01
    assert np.hypot(*world.velocities[bob]) < 1e-2


def test_a_welded_pair_turns_as_one_body_while_it_swings():
    world = gravity_world()
    first = world.add_body(Box(1.0, 0.1), position=(0.5, 0.0), material=DENSE)
    second = world.add_body(Box(0.1, 0.6), position=(1.0, -0.3), material=DENSE)
    world.add_weld(first, second, (1.0, 0.0))
    world.add_revolute(None, first, (0.0, 0.0))
    offset = world.centers[second] - world.centers[first]
    distance = np.hypot(*offset)
    widest = 0.0
    for _ in range(480):
        world.step(1)
        assert world.angles[second] - world.angles[first] == pytest.approx(0.0, abs=2e-3)
        gap = world.centers[second] - world.centers[first]
        assert np.hypot(*gap) == pytest.approx(distance, abs=2e-3)
        widest = max(widest, abs(world.angles[first]))
    assert widest > 1.0  # it swung


def test_a_gear_keeps_angle_1_plus_ratio_times_angle_2_constant():
    world = World(tick_rate=240, precision=4)
    big = world.add_body(Circle(1.0), position=(0.0, 0.0), material=DENSE, collision_group=1)
    small = world.add_body(Circle(0.5), position=(1.5, 0.0), material=DENSE, collision_group=1)
    drive = world.add_revolute(None, big, (0.0, 0.0), motor_speed=2.0, max_motor_torque=1e5)
    follower = world.add_revolute(None, small, (1.5, 0.0))
    world.add_gear(drive, follower, ratio=0.5)
    for _ in range(240):
        world.step(1)
        angles = world.joint_coordinates
        assert angles[drive] + 0.5 * angles[follower] == pytest.approx(0.0, abs=1e-3)
    assert world.angular_velocities[small] == pytest.approx(-4.0, rel=1e-3)  # twice as fast, the other way


def test_a_pulley_keeps_length_a_plus_ratio_times_length_b_and_the_heavier_side_descends():
    world = gravity_world()
    heavy = world.add_body(Box(0.3, 0.3), position=(-1.0, -2.0), mass=3.0)
    light = world.add_body(Box(0.3, 0.3), position=(1.0, -2.0), mass=1.0)
    pulley = world.add_pulley(heavy, light, [(-1.0, -2.0), (1.0, -2.0)], [(-1.0, 0.0), (1.0, 0.0)])
    total = world.joint_coordinates[pulley]
    world.step(120)
    assert world.joint_coordinates[pulley] == pytest.approx(total, abs=1e-3)
    t = 0.5
    expected_drop = 0.5 * G * (3.0 - 1.0) / (3.0 + 1.0) * t * t  # Atwood's machine
    assert -2.0 - world.positions[heavy][1] == pytest.approx(expected_drop, rel=0.02)
    assert world.positions[light][1] + 2.0 == pytest.approx(expected_drop, rel=0.02)


def test_a_hanging_bobs_reaction_is_its_weight():
    world = gravity_world()
    bob = world.add_body(Circle(0.1), position=(0.0, -1.0), material=DENSE)
    hinge = world.add_revolute(None, bob, (0.0, 0.0))
    world.step(240)
    force = world.joint_reaction_forces[hinge]
    assert force[1] == pytest.approx(world.masses[bob] * G, rel=0.01)  # the joint holds the bob up
    assert abs(force[0]) < 1e-6 * world.masses[bob] * G


def test_a_joint_breaks_in_the_tick_its_reaction_passes_its_break_force():
    """A bob on a rod released horizontal pulls on the rod with 3 m g sin(phi) at phi below the
    horizontal: a rod that breaks at 2 m g breaks on the way down."""
    world = gravity_world()
    bob = world.add_body(Circle(0.05), position=(1.0, 0.0), material=DENSE)
    weight = world.masses[bob] * G
    rod = world.add_distance(None, bob, [(0.0, 0.0), (1.0, 0.0)], break_force=2.0 * weight)
    forces = []
    while world.joint_active[rod]:
        world.step(1)
        forces.append(float(np.hypot(*world.joint_reaction_forces[rod])))
        assert world.tick < 240
    events = world.events()
    assert list(events["kind"]) == ["joint_break"]
    assert events["a"][0] == rod and events["tick"][0] == world.tick
    assert forces[-1] > 2.0 * weight and forces[-2] <= 2.0 * weight
    phi = math.asin(forces[-1] / (3.0 * weight))
    assert math.atan2(-world.positions[bob][1], world.positions[bob][0]) == pytest.approx(phi, abs=0.05)
    world.step(10)
    assert world.velocities[bob][1] < 0 and np.hypot(*world.positions[bob]) > 1.0  # flies free


def test_joined_bodies_do_not_collide_unless_asked():
    for connected, apart in ((False, False), (True, True)):
        world = World(tick_rate=60, precision=4)
        a = world.add_body(Box(1.0, 1.0), position=(0.0, 0.0))
        b = world.add_body(Box(1.0, 1.0), position=(0.5, 0.0))  # overlapping
        world.add_revolute(a, b, (0.25, 0.3), collide_connected=connected)  # off the overlap's centre line
        world.step(10)
        pushed = abs(world.angular_velocities[a]) + abs(world.angular_velocities[b]) > 1e-3
        assert pushed == apart
        assert (world.contacts()["normal_impulse"].sum() > 0.0) == apart


CRADLE = """
import numpy as np
from rustycs import Box, Circle, Material, World

def columns():
    world = World(tick_rate=60, precision=4)
    world.add_force((0.0, -10.0))
    world.add_body(Box(40.0, 1.0), position=(0.0, -0.5), body_type="static")
    for column in range(4):
        previous = world.add_body(Box(0.5, 0.5), position=(3.0 * column - 4.5, 0.25), body_type="static")
        for k in range(10):
            box = world.add_body(Box(0.4, 0.4), position=(3.0 * column - 4.5 + 0.5 * (k + 1), 0.25 + 0.1 * k),
                                 material=Material(1.0, 0.0, 0.6))
            world.add_revolute(previous, box, (3.0 * column - 4.5 + 0.5 * (k + 1) - 0.25, 0.25 + 0.1 * k),
                               limits=(-0.1 * (k + 1), 0.2), spring_hertz=1.0, spring_damping_ratio=0.5)
            previous = box
    world.step(300)
    return np.concatenate([world.positions.ravel(), world.angles, world.velocities.ravel()])
"""


def test_four_columns_of_hinged_boxes_with_limits_and_springs_are_bitwise_the_same_everywhere():
    namespace: dict = {}
    exec(CRADLE, namespace)
    first, second = namespace["columns"](), namespace["columns"]()
    assert np.array_equal(first, second)
    code = CRADLE + "\nimport sys\nsys.stdout.buffer.write(columns().tobytes())\n"
    other = np.frombuffer(subprocess.run([sys.executable, "-c", code], capture_output=True,
                                         check=True).stdout)
    assert np.array_equal(first, other)
    assert np.all(np.isfinite(first))


def test_a_breaking_joint_records_its_anchor_as_the_events_point():
    """A box hinged at its left edge, at (2, 3), to a hinge far too weak to hold it breaks in the first
    tick; its event is placed at the hinge, not at the origin or the box's centre."""
    world = gravity_world()
    box = world.add_body(Box(1.0, 0.2), position=(2.5, 3.0), material=DENSE)
    world.add_revolute(None, box, (2.0, 3.0), break_force=1e-3)
    world.step(1)
    events = world.events()
    assert list(events["kind"]) == ["joint_break"]
    assert events["point"][0] == pytest.approx((2.0, 3.0), abs=1e-3)  # it fell g dt^2 = 1.7e-4 m
