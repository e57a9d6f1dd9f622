"""Free motion: forces and attractors against exact solutions of the integrator.

The engine runs `precision` substeps of h = dt / precision per tick, each a semi-implicit Euler step
v += h a; x += h v. After k substeps of a constant acceleration g from (x0, v0) that is exactly
v_k = v0 + k h g and x_k = x0 + k h v0 + h^2 g k (k + 1) / 2.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rustycs import Circle, World


@pytest.mark.parametrize("tick_rate, precision", [(60.0, 10), (240.0, 1), (30.0, 3)])
def test_free_fall_matches_the_discrete_solution(tick_rate, precision):
    world = World(tick_rate=tick_rate, precision=precision)
    world.add_force((0.0, -9.81))
    world.add_force((0.5, 0.0))  # forces add up into one world force
    g = np.array([0.5, -9.81])
    x0, v0 = np.array([1.0, 100.0]), np.array([1.0, 3.0])
    world.add_body(Circle(0.5), position=x0, velocity=v0)
    h = 1.0 / (tick_rate * precision)
    for tick in range(1, 91):
        world.step()
        k = tick * precision
        assert world.velocities[0] == pytest.approx(v0 + k * h * g, rel=1e-12, abs=1e-12)
        assert world.centers[0] == pytest.approx(x0 + k * h * v0 + h * h * g * k * (k + 1) / 2,
                                                 rel=1e-12, abs=1e-12)
    assert world.tick == 90
    assert world.angles[0] == 0.0


def test_static_and_kinematic_bodies_ignore_forces():
    world = World()
    world.add_force((0.0, -9.81))
    world.add_attractor((0.0, 0.0), mass=100.0)
    world.add_body(Circle(0.5), position=(5, 5), body_type="static")
    world.add_body(Circle(0.5), position=(-5, 5), velocity=(0.5, -0.25), angular_velocity=2.0,
                   body_type="kinematic")
    world.step(60)
    assert world.centers[0] == pytest.approx([5, 5], abs=0)
    assert world.velocities[1] == pytest.approx([0.5, -0.25], abs=0)
    assert world.centers[1] == pytest.approx([-4.5, 4.75], abs=1e-12)
    assert world.angles[1] == pytest.approx(2.0, abs=1e-12)


GM = 4.0 * math.pi ** 2  # a circular orbit of radius 1 then takes exactly 1 s


@pytest.mark.parametrize("mass", [1e-3, 1.0, 1e3])
def test_circular_orbit_keeps_its_radius_for_ten_orbits(mass):
    world = World(tick_rate=240.0, gravitational_constant=2.0)
    world.add_attractor((3.0, -2.0), mass=GM / 2.0)
    world.add_body(Circle(0.05), position=(3.0, -1.0), velocity=(-math.sqrt(GM), 0.0), mass=mass)
    radii = []
    angles = []
    for _ in range(100):  # 10 orbits, sampled 10 times each
        world.step(24)
        d = world.centers[0] - np.array([3.0, -2.0])
        radii.append(np.hypot(*d))
        angles.append(math.atan2(d[1], d[0]))
    assert np.max(np.abs(np.array(radii) - 1.0)) < 0.01
    # and it went round 10 times: one full turn per second, back near the start after 10
    turns = np.unwrap(np.array([math.pi / 2] + angles))
    assert (turns[-1] - turns[0]) / (2 * math.pi) == pytest.approx(10.0, abs=0.05)


def test_orbit_does_not_depend_on_the_body_mass():
    # two bodies on the same orbit, never colliding (same collision group): identical trajectories
    world = World(tick_rate=240.0)
    world.add_attractor((0.0, 0.0), mass=GM)
    light = world.add_body(Circle(0.05), position=(1.0, 0.0), velocity=(0.0, math.sqrt(GM)), mass=1e-3,
                           collision_group=1)
    heavy = world.add_body(Circle(0.5), position=(1.0, 0.0), velocity=(0.0, math.sqrt(GM)), mass=1e4,
                           collision_group=1)
    world.step(240)
    assert np.array_equal(world.centers[light], world.centers[heavy])
    assert np.array_equal(world.velocities[light], world.velocities[heavy])
    assert np.hypot(*world.centers[light]) == pytest.approx(1.0, abs=0.01)


def test_attractor_acceleration_is_gm_over_d_squared_within_range_only():
    # one substep per tick: after one tick v = h G M / d^2 towards the attractor
    dt = 1.0 / 100.0
    world = World(tick_rate=100.0, precision=1, gravitational_constant=2.0)
    world.add_attractor((0.0, 0.0), mass=50.0, range=2.0, min_distance=0.1)  # G M = 100
    inside = world.add_body(Circle(0.01), position=(1.5, 0.0), collision_group=1)
    heavy = world.add_body(Circle(0.01), position=(0.0, -1.5), mass=1e6, collision_group=1)
    core = world.add_body(Circle(0.01), position=(0.0, 0.05), collision_group=1)
    outside = world.add_body(Circle(0.01), position=(-2.5, 0.0), collision_group=1)
    world.step()
    v = world.velocities
    assert v[inside] == pytest.approx([-dt * 100.0 / 1.5 ** 2, 0.0], rel=1e-12, abs=1e-15)
    assert v[heavy] == pytest.approx([0.0, dt * 100.0 / 1.5 ** 2], rel=1e-12, abs=1e-15)
    # closer than min_distance: the acceleration is G M / min_distance^2
    assert v[core] == pytest.approx([0.0, -dt * 100.0 / 0.1 ** 2], rel=1e-12, abs=1e-15)
    # beyond the range: nothing at all
    assert np.array_equal(v[outside], [0.0, 0.0])
    world.step(99)
    assert np.array_equal(world.centers[outside], [-2.5, 0.0])
    assert np.array_equal(world.velocities[outside], [0.0, 0.0])


def test_attractors_add_up():
    world = World(tick_rate=100.0, precision=1)
    world.add_attractor((-1.0, 0.0), mass=4.0)
    world.add_attractor((0.0, 2.0), mass=8.0, range=5.0)
    world.add_force((0.0, -1.0))
    world.add_body(Circle(0.01), position=(0.0, 0.0))
    world.step()
    expected = np.array([-4.0 / 1.0, 8.0 / 4.0 - 1.0]) / 100.0
    assert world.velocities[0] == pytest.approx(expected, rel=1e-12)


def test_leaving_the_bounds_deactivates_and_freezes_a_body():
    world = World(tick_rate=60.0, bounds=((-10.0, -1.0), (10.0, 10.0)))
    world.add_force((0.0, -9.81))
    falling = world.add_body(Circle(0.1), position=(0.0, 0.0))
    flying = world.add_body(Circle(0.1), position=(5.0, 5.0), velocity=(30.0, 0.0))
    world.add_body(Circle(0.1), position=(-50.0, 0.0), body_type="static")  # static: never counted
    world.step(60)
    assert list(world.active) == [False, False, True]
    assert world.escaped_count == 2
    frozen = world.centers
    # the fall crosses y = -1 after sqrt(2/9.81) s, within tick 28: it stopped just beyond the bound
    assert -1.0 - 30 * 9.81 / 60 / 60 < frozen[falling][1] < -1.0
    assert frozen[flying][0] > 10.0
    world.step(10)
    assert np.array_equal(world.centers, frozen)
    assert np.all(world.velocities[:2] == 0.0)
