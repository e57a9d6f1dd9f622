"""Friction on an incline: a static obb turned by theta, a body released on it from rest.

The acceleration along the slope is fitted (a quadratic in time) to the positions over a window
that starts after the first half second, so the settling of the first contact does not count.
Friction mixes by the mean of the two materials; both use the same mu here.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rustycs import Box, Circle, Material, World

G = 9.81
TICK_RATE = 60.0


def release_on_incline(shape, theta, mu, seconds=2.0, size=1.0):
    """Release `shape` (of height `size`) on an incline; return (times, distance down the slope,
    speed down the slope, angular velocities)."""
    world = World(tick_rate=TICK_RATE, precision=10)
    world.add_force((0.0, -G))
    material = Material(1.0, 0.0, mu)
    c, s = math.cos(theta), math.sin(theta)
    down = np.array([-c, -s])  # the slope rises towards +x
    up_normal = np.array([-s, c])
    world.add_body(Box(40.0, 1.0), position=(0, 0), angle=theta, body_type="static", material=material)
    start = up_normal * (0.5 + size / 2) - 15.0 * down  # resting on the top face, 15 m up the slope
    body = world.add_body(shape, position=start, angle=theta if isinstance(shape, Box) else 0.0,
                          material=material)
    times, distance, speed, spin = [], [], [], []
    for k in range(int(seconds * TICK_RATE)):
        world.step()
        times.append((k + 1) / TICK_RATE)
        distance.append((world.centers[body] - start) @ down)
        speed.append(world.velocities[body] @ down)
        spin.append(world.angular_velocities[body])
    return np.array(times), np.array(distance), np.array(speed), np.array(spin)


def fitted_acceleration(times, distance, after=0.5):
    window = times >= after
    return 2.0 * np.polyfit(times[window], distance[window], 2)[0]


@pytest.mark.parametrize("degrees, mu", [(20.0, 0.6), (30.0, 0.6), (10.0, 0.2)])
def test_box_sticks_when_tan_theta_is_below_mu(degrees, mu):
    theta = math.radians(degrees)
    assert math.tan(theta) < mu
    _, distance, speed, spin = release_on_incline(Box(1.0, 1.0), theta, mu)
    assert np.max(np.abs(distance)) < 1e-3
    assert abs(speed[-1]) < 1e-3
    assert np.max(np.abs(spin)) < 1e-3


@pytest.mark.parametrize("degrees, mu", [(30.0, 0.2), (30.0, 0.5), (10.0, 0.1), (40.0, 0.3)])
def test_box_slides_with_a_equal_g_sin_minus_mu_cos(degrees, mu):
    theta = math.radians(degrees)
    times, distance, _, spin = release_on_incline(Box(1.0, 1.0), theta, mu)
    expected = G * (math.sin(theta) - mu * math.cos(theta))
    assert fitted_acceleration(times, distance) == pytest.approx(expected, rel=0.05)
    assert np.max(np.abs(spin)) < 1e-3  # it slides flat, it does not tumble


@pytest.mark.parametrize("degrees, mu", [(20.0, 0.8), (30.0, 0.6), (10.0, 0.5)])
def test_disc_rolls_without_slipping(degrees, mu):
    theta = math.radians(degrees)
    radius = 0.5
    times, distance, speed, spin = release_on_incline(Circle(radius), theta, mu, size=2 * radius)
    assert fitted_acceleration(times, distance) == pytest.approx(2.0 / 3.0 * G * math.sin(theta), rel=0.05)
    # rolling: the contact point is at rest, v = omega r (turning counter-clockwise while moving to -x)
    assert spin[-1] * radius == pytest.approx(speed[-1], rel=0.02)


def test_disc_slips_when_friction_is_too_low_to_roll():
    # rolling needs mu >= tan(theta) / 3; below that the disc slides with a = g (sin - mu cos)
    theta = math.radians(30.0)
    mu = 0.1
    radius = 0.5
    times, distance, speed, spin = release_on_incline(Circle(radius), theta, mu, size=2 * radius)
    assert fitted_acceleration(times, distance) == pytest.approx(
        G * (math.sin(theta) - mu * math.cos(theta)), rel=0.05)
    # friction spins it up at 2 mu g cos / r
    assert spin[-1] == pytest.approx(2 * mu * G * math.cos(theta) / radius * times[-1], rel=0.05)
